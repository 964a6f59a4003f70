// UE 5.8's HDR UI composite (pipeline ue58, stage ue58_ui_composite) against values computed by
// hand from UE 5.8's formulas (CompositeUIPixelShader.usf: ComputeHDRUIColor, LinearizeColor,
// ComposeUIAndScene; SlateRHIRenderer.cpp: the cvar defaults and UILuminance), each written out
// here with its arithmetic; docs/ue58-differences.md U1-U5.
#include <gtest/gtest.h>

#include <cmath>

#include "core/pipeline.h"
#include "reference/ue/ue58/ue58_pipeline.h"
#include "reference/ue/ue58/ue58_ui_composite.h"

namespace {

namespace ue58 = hdrc::ref::ue58;
namespace ui = hdrc::ref::ui;
using hdrc::ref::Vec3;

const hdrc::Pipeline& pipeline() {
  return ue58::ue58_pipeline();
}

// A ue58_ui_composite case on an HDR device with `settings` and `cvars` set, resolved.
hdrc::ParamBlock resolved(std::initializer_list<std::pair<const char*, double>> settings,
                          std::initializer_list<std::pair<const char*, double>> cvars = {},
                          int device = 3) {
  hdrc::Case c;
  c.stage = hdrc::find_stage(pipeline(), "ue58_ui_composite");
  EXPECT_NE(c.stage, nullptr);
  c.settings = pipeline().new_settings();
  for (const auto& [k, v] : settings) {
    const auto st = c.settings.set(k, {v, 0, 0, 0}, 1);
    EXPECT_TRUE(st.ok()) << k << ": " << st.error().to_string();
  }
  EXPECT_TRUE(c.cvars.set("r.HDR.EnableHDROutput", 1).ok());
  EXPECT_TRUE(c.cvars.set("r.HDR.Display.OutputDevice", device).ok());
  for (const auto& [k, v] : cvars) {
    const auto st = c.cvars.set(k, v);
    EXPECT_TRUE(st.ok()) << k << ": " << st.error().to_string();
  }
  auto r = pipeline().resolve(c, 32, 32);
  EXPECT_TRUE(r.ok()) << r.error().to_string();
  return r->params;
}

// The parameters of the 5.8 defaults on device `device` (paper white 203).
ue58::UiComposite58Params defaults(int device = 3) {
  return ue58::ui_composite58_params(resolved({}, {}, device));
}

// Grey in, grey out: the sRGB -> Rec.2020 rows sum to 1 within the literal matrices' rounding.
constexpr double kGreyTolerance = 1e-5;

// SlateRHIRenderer.cpp: r.HDR.UI.Luminance 203 (5.8), Luminance.Mode 0 (paper white),
// CompositeEOTF 0 / Gamma 2.4, CompositeBlend 0 / Gamma 2.4, InvGamma = 1.f / 2.4f.
TEST(Ue58UiComposite, HostDefaultsAndUiLuminance) {
  const hdrc::ParamBlock p = resolved({});
  EXPECT_EQ(p.ui_luminance, 203.0);  // HDRPaperWhiteInNits: r.HDR.PaperWhite 203
  EXPECT_EQ(p.ue58_ui_eotf, 0);
  EXPECT_EQ(p.ue58_ui_eotf_gamma, static_cast<double>(2.4f));
  EXPECT_EQ(p.ue58_ui_blend, 0);
  EXPECT_EQ(p.ue58_ui_blend_gamma, static_cast<double>(2.4f));
  EXPECT_EQ(p.ue58_ui_blend_inv_gamma, static_cast<double>(1.f / 2.4f));
  EXPECT_EQ(p.ui_level, 1.0);
  EXPECT_EQ(p.ui_composite_mode, 1);
  // Mode 0 follows the paper white and ignores r.HDR.UI.Luminance.
  EXPECT_EQ(resolved({{"r.HDR.PaperWhite", 300}}).ui_luminance, 300.0);
  EXPECT_EQ(resolved({}, {{"r.HDR.UI.Luminance", 1000}}).ui_luminance, 203.0);
  // Mode 1: r.HDR.UI.Luminance, whose 5.8 default is 203 (5.5's 300 does not leak in).
  EXPECT_EQ(resolved({{"r.HDR.UI.Luminance.Mode", 1}}).ui_luminance, 203.0);
  EXPECT_EQ(resolved({{"r.HDR.UI.Luminance.Mode", 1}, {"r.HDR.PaperWhite", 300}},
                     {{"r.HDR.UI.Luminance", 1000}})
                .ui_luminance,
            1000.0);
}

// Opaque UI replaces the scene: grey 0.5 through pow(0.5, 2.4) = 0.18946457 x 203 nits
// = 38.4613079 nits, whatever the scene.
TEST(Ue58UiComposite, OpaqueGreyAtPaperWhite) {
  const auto p = defaults();
  const ui::Vec4 u = ue58::compute_hdr_ui_color58({0.5, 0.5, 0.5, 1.0}, p);
  const Vec3 out = ue58::compose_ui_and_scene58({5000.0, 1.0, 0.0}, u, p);
  for (double c : out) EXPECT_NEAR(c, 38.461307875201356, 38.46 * kGreyTolerance);
}

// The UI is un-premultiplied before its EOTF: (0.25, 0.25, 0.25, a 0.5) is grey 0.5, the same
// 38.4613079 nits as above (5.5 linearised the premultiplied 0.25).
TEST(Ue58UiComposite, PremultipliedUiIsUndoneBeforeTheEotf) {
  const auto p = defaults();
  const ui::Vec4 u = ue58::compute_hdr_ui_color58({0.25, 0.25, 0.25, 0.5}, p);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(u[c], 38.461307875201356, 38.46 * kGreyTolerance);
  EXPECT_EQ(u[3], 0.5);
}

// Translucent white UI (1 at a = 0.5 after un-premultiplying: 203 nits) over a 100-nit grey scene.
// Gamma space (default): s = (100 / 10000)^(1/2.4) = 0.1467799, u = (203 / 10000)^(1/2.4)
// = 0.1971450, lerp 0.1719625, ^2.4 x 10000 = 146.2334156 nits. Linear: Reinhard L = 100,
// scene x lerp(1, 1/101, 0.5) = 50.4950495, lerp(50.4950495, 203, 0.5) = 126.7475248 nits.
TEST(Ue58UiComposite, TranslucentWhiteInGammaAndLinearBlendSpace) {
  auto p = defaults();
  const ui::Vec4 u = ue58::compute_hdr_ui_color58({0.5, 0.5, 0.5, 0.5}, p);
  const Vec3 gamma = ue58::compose_ui_and_scene58({100.0, 100.0, 100.0}, u, p);
  for (double c : gamma) EXPECT_NEAR(c, 146.23341560076582, 146.2 * kGreyTolerance);
  p.blend = 1;
  const Vec3 linear = ue58::compose_ui_and_scene58({100.0, 100.0, 100.0}, u, p);
  for (double c : linear) EXPECT_NEAR(c, 126.74752475247524, 126.7 * kGreyTolerance);
}

// r.HDR.UI.CompositeBlend.Gamma 2.2, a = 0.25, UI 300 nits over a 1000-nit scene:
// s = 0.1^(1/2.2) = 0.3511192, u = 0.03^(1/2.2) = 0.2031510, s + 0.25 (u - s) = 0.3141272,
// ^2.2 x 10000 = 782.7426 nits (linear light would give 825).
TEST(Ue58UiComposite, BlendGammaFromTheCvar) {
  const auto p = ue58::ui_composite58_params(resolved({{"r.HDR.UI.CompositeBlend.Gamma", 2.2},
                                                       {"r.HDR.UI.Luminance.Mode", 1},
                                                       {"r.HDR.UI.CompositeEOTF", 1}},
                                                      {{"r.HDR.UI.Luminance", 300}}));
  EXPECT_EQ(p.blend_inv_gamma, static_cast<double>(1.f / 2.2f));
  // sRGB white is 1: 300 nits.
  const ui::Vec4 u = ue58::compute_hdr_ui_color58({0.25, 0.25, 0.25, 0.25}, p);
  const Vec3 out = ue58::compose_ui_and_scene58({1000.0, 1000.0, 1000.0}, u, p);
  // The host's gamma is float: 2.2f, 1.f / 2.2f (relative 2e-8 in the result).
  for (double c : out) EXPECT_NEAR(c, 782.7426044195654, 782.7 * kGreyTolerance);
}

// Alpha 0 with colour: ComputeHDRUIColor zeroes the colour, ComposeUIAndScene leaves the scene
// as it was (bit for bit), and the pass writes the UI's alpha (0), not 1.
TEST(Ue58UiComposite, ZeroAlphaWithColourLeavesTheScene) {
  const auto p = defaults();
  const ui::Vec4 u = ue58::compute_hdr_ui_color58({0.7, 0.2, 0.1, 0.0}, p);
  EXPECT_EQ(u[0], 0.0);
  EXPECT_EQ(u[1], 0.0);
  EXPECT_EQ(u[2], 0.0);
  const Vec3 scene{123.0, 4.5, 6789.0};
  const Vec3 out = ue58::compose_ui_and_scene58(scene, u, p);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(out[c], scene[c]);
  const ui::Vec4 px = ue58::composite_pixel58({0.5, 0.25, 0.75, 1.0}, {0.7, 0.2, 0.1, 0.0}, p);
  EXPECT_NEAR(px[0], 0.5, 1e-12);
  EXPECT_NEAR(px[1], 0.25, 1e-12);
  EXPECT_NEAR(px[2], 0.75, 1e-12);
  EXPECT_EQ(px[3], 0.0);
}

// r.HDR.UI.CompositeEOTF 1: 5.8's sRGBToLinear has no min-normal clamp (L16), so black UI is
// exactly 0 nits (5.5: 6.10352e-5 / 12.92 x luminance); sRGB 0.5 = ((0.5 + 0.055) / 1.055)^2.4
// = 0.2140411 x 203 = 43.4503 nits.
TEST(Ue58UiComposite, SrgbEotfWithoutTheClamp) {
  auto p = defaults();
  p.eotf = 1;
  const ui::Vec4 black = ue58::compute_hdr_ui_color58({0.0, 0.0, 0.0, 1.0}, p);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(black[c], 0.0);
  const ui::Vec4 grey = ue58::compute_hdr_ui_color58({0.5, 0.5, 0.5, 1.0}, p);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(grey[c], 0.21404114048223255 * 203, 43.45 * kGreyTolerance);
}

// scRGB (device 5): opaque white UI at paper white 100 is 100 nits = scRGB 100 / 80 = 1.25 per
// channel (UE_SCRGB_WHITE_NITS 80); the pass writes the UI's alpha.
TEST(Ue58UiComposite, ScRgbOpaqueWhite) {
  const auto p = ue58::ui_composite58_params(resolved({{"r.HDR.PaperWhite", 100}}, {}, 5));
  const ui::Vec4 px = ue58::composite_pixel58({0.3, 0.3, 0.3, 1.0}, {1.0, 1.0, 1.0, 1.0}, p);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(px[c], 1.25, 1.25 * kGreyTolerance);
  EXPECT_EQ(px[3], 1.0);
}

// r.HDR.UI.CompositeMode 0: Slate's premultiplied blend in the back buffer's code values,
// unchanged from 5.5: 0.25 + (1 - 0.5) x 0.5 = 0.5 on a PQ back buffer.
TEST(Ue58UiComposite, Mode0IsSlatesBlend) {
  const auto p = ue58::ui_composite58_params(resolved({}, {{"r.HDR.UI.CompositeMode", 0}}));
  const ui::Vec4 px = ue58::composite_pixel58({0.5, 0.5, 0.5, 1.0}, {0.25, 0.25, 0.25, 0.5}, p);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(px[c], 0.5);
  EXPECT_EQ(px[3], 1.0);  // 0.5 + 0.5 x 1
}

// A gamma of 0 is refused, naming the cvar.
TEST(Ue58UiComposite, ValidateNamesTheCvar) {
  auto p = defaults();
  p.blend_gamma = 0.0;
  const auto st = ue58::validate(p);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().to_string().find("r.HDR.UI.CompositeBlend.Gamma"), std::string::npos);
}

}  // namespace
