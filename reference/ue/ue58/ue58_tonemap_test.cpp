// UE 5.8's Tonemap pass (stage ue58_tonemap) against UE 5.8's formulas evaluated by hand: the host
// rules of PostProcessTonemap.cpp (LUTMax = GetTonemappingMax, VignetteParams0-2 and their
// defaults), PostProcessCommon.ush ComputeVignetteMask / VignetteSpace (cosine-fourth law with
// centre and colour, Oval, Texture without its permutation), ColorLookupTable's clamped PQ
// address (SMPTE ST 2084 constants), device 7's ST2084ToLinear and the scRGB devices' unchanged
// write (docs/ue58-differences.md T1-T3).
#include "reference/ue/ue58/ue58_tonemap.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/pipeline.h"
#include "reference/color/ue_log_shaper.h"
#include "reference/ue/tonemap.h"
#include "reference/ue/ue58/ue58_pipeline.h"

namespace {

using hdrc::ref::Vec3;
using hdrc::ref::Vignette;
namespace ue58 = hdrc::ref::ue58;
namespace ue_log = hdrc::ref::ue_log;

// A ue58_tonemap case with `settings` and `cvars` (values by name; VignetteColor as {r, g, b, a}).
hdrc::ParamBlock resolved(
    std::initializer_list<std::pair<const char*, std::array<double, 4>>> settings,
    std::initializer_list<std::pair<const char*, double>> cvars = {}) {
  const hdrc::Pipeline& pl = ue58::ue58_pipeline();
  hdrc::Case c;
  c.stage = hdrc::find_stage(pl, "ue58_tonemap");
  c.settings = pl.new_settings();
  for (const auto& [k, v] : settings) {
    int components = 1;
    for (const hdrc::SettingInfo& i : ue58::ue58_setting_table())
      if (i.name == k) components = i.components;
    const auto st = c.settings.set(k, {v[0], v[1], v[2], v[3]}, components);
    EXPECT_TRUE(st.ok()) << k << ": " << st.error().to_string();
  }
  for (const auto& [k, v] : cvars) {
    const auto st = c.cvars.set(k, v);
    EXPECT_TRUE(st.ok()) << k << ": " << st.error().to_string();
  }
  auto r = pl.resolve(c, 8, 4);
  EXPECT_TRUE(r.ok()) << r.error().to_string();
  return r->params;
}

std::array<double, 4> v1(double x) {
  return {x, 0, 0, 0};
}

// SMPTE ST 2084 by hand.
double nits_to_pq(double y) {
  const double m1 = 2610.0 / 16384, m2 = 2523.0 / 4096 * 128, c1 = 3424.0 / 4096,
               c2 = 2413.0 / 4096 * 32, c3 = 2392.0 / 4096 * 32;
  const double l = std::pow(y / 10000, m1);
  return std::pow((c1 + c2 * l) / (1 + c3 * l), m2);
}

// GetTonemappingMax (PostProcessCombineLUTs.cpp): 1.05f for Filmic on devices 0, 1 and 9, else 1;
// the Tonemap pass multiplies by it, CombineLUTs stored 1 / it.
TEST(Ue58Tonemap, LutMaxIsGetTonemappingMax) {
  for (int method : {0, 1})
    for (int device = 0; device <= 9; ++device) {
      const auto p =
          resolved({{"TonemappingMethod", v1(method)}}, {{"r.HDR.Display.OutputDevice", device}});
      const bool filmic_105 = method == 0 && (device == 0 || device == 1 || device == 9);
      EXPECT_EQ(p.ue58_lut_max, filmic_105 ? static_cast<double>(1.05f) : 1.0)
          << method << " " << device;
      EXPECT_NEAR(p.ue58_lut_max * p.ue58_lut_inv_max, 1.0, 1e-7);
    }
}

// Scene.cpp defaults: CosineFourthLaw, intensity 0.4, centre (0.5, 0.5), size 1, softness 5,
// black; AddTonemapPass packs them. At the defaults 5.8's mask is UE 5.5's to the bit, and both
// are the cosine-fourth law by hand: at the corner (1, 1) of a 2:1 viewport (aspect 0.5),
// V = (1, 0.5) * sqrt(2 / 1.25), |V * 0.4|^2 = 0.32, mask = 1 / 1.32^2.
TEST(Ue58Tonemap, DefaultVignetteIsUe55s) {
  const auto p = resolved({});
  EXPECT_EQ(p.ue58_vignette_type, 0);
  EXPECT_EQ(p.ue58_vignette_params0[0], static_cast<double>(0.4f));
  for (int c = 1; c < 4; ++c) EXPECT_EQ(p.ue58_vignette_params0[c], 0.0);
  EXPECT_EQ(p.ue58_vignette_params1[0], 0.5);
  EXPECT_EQ(p.ue58_vignette_params1[1], 0.5);
  EXPECT_EQ(p.ue58_vignette_params1[2], 1.0);
  EXPECT_EQ(p.ue58_vignette_params1[3], 1.0);
  EXPECT_EQ(p.ue58_vignette_params2, 5.0);
  hdrc::ParamBlock p55;
  p55.vignette_intensity = p.ue58_vignette_params0[0];
  const Vignette v58 = ue58::tonemap_vignette(p), v55 = hdrc::ref::ue55_vignette(p55);
  for (double x : {-1.0, -0.3, 0.0, 0.55, 1.0})
    for (double y : {-1.0, 0.2, 1.0})
      for (double aspect : {0.5, 9.0 / 16, 1.0}) {
        const Vec3 a = hdrc::ref::vignette_mask(v58, x, y, aspect);
        const Vec3 b = hdrc::ref::vignette_mask(v55, x, y, aspect);
        for (int c = 0; c < 3; ++c) EXPECT_EQ(a[c], b[c]);
      }
  const Vec3 corner = hdrc::ref::vignette_mask(v58, 1.0, 1.0, 0.5);
  EXPECT_NEAR(corner[0], 1.0 / (1.32 * 1.32), 2e-7);  // float(0.4) as the intensity
}

// Cosine-fourth law with centre (0.3, 0.65) and colour (0.25, 0.1, 0.5), intensity 1, square
// viewport: at screen position (0.5, 0), V - (centre - 0.5) = (0.7, -0.15), tan^2 = 0.5125,
// weight = 1 / 1.5125^2, mask = colour + weight * (1 - colour).
TEST(Ue58Tonemap, CosineFourthLawWithCentreAndColour) {
  const auto p = resolved({{"VignetteIntensity", v1(1)},
                           {"VignetteCenterX", v1(0.3)},
                           {"VignetteCenterY", v1(0.65)},
                           {"VignetteColor", {0.25, 0.1, 0.5, 1}}});
  const Vec3 m = hdrc::ref::vignette_mask(ue58::tonemap_vignette(p), 0.5, 0.0, 1.0);
  const double w = 1.0 / (1.5125 * 1.5125);
  const double colour[3] = {0.25, 0.1, 0.5};
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(m[c], colour[c] + w * (1 - colour[c]), 1e-7) << c;
  // Intensity 0: no vignette whatever the colour.
  const auto off = resolved({{"VignetteIntensity", v1(0)}, {"VignetteColor", {0.25, 0.1, 0.5, 1}}});
  const Vec3 one = hdrc::ref::vignette_mask(ue58::tonemap_vignette(off), 0.9, -0.7, 1.0);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(one[c], 1.0);
}

// Oval (USE_ADVANCED_VIGNETTE): size (0.5, 1) -> InvSize (2, 1); at (0.25, 0.5) of a square
// viewport Position = (0.5, 0.5), Distance = |(0.5, 0.5)|^2 = 0.5, softness 2: 0.5^2 = 0.25,
// intensity 0.8: lerp(1, 0.25, 0.8) = 0.4. Texture without USE_VIGNETTE_TEXTURE (feature level
// SM5): Distance 0, weight 1, no vignette.
TEST(Ue58Tonemap, OvalAndTextureAtSm5) {
  const auto p = resolved({{"VignetteType", v1(2)},
                           {"VignetteIntensity", v1(0.8)},
                           {"VignetteSizeX", v1(0.5)},
                           {"VignetteSoftness", v1(2)}});
  const Vec3 m = hdrc::ref::vignette_mask(ue58::tonemap_vignette(p), 0.25, 0.5, 1.0);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(m[c], 0.4, 1e-7);
  const auto t = resolved({{"VignetteType", v1(1)}, {"VignetteIntensity", v1(1)}});
  const Vec3 one = hdrc::ref::vignette_mask(ue58::tonemap_vignette(t), 0.9, 0.9, 1.0);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(one[c], 1.0);
}

// ColorLookupTable (5.8): PQ of clamp(x * 100, 0, 10000) with r.LUT.Shaper 1, for every device;
// 5.5's unclamped PQ makes a negative NaN.
TEST(Ue58Tonemap, ClampedPqAddressAndTheLogShaper) {
  const auto pq = ue58::tonemap_lut_shaper(resolved({{"r.LUT.Shaper", v1(1)}}));
  EXPECT_TRUE(pq.pq && pq.clamp_nits);
  EXPECT_NEAR(hdrc::ref::lut_encode(pq, -1.0), nits_to_pq(0.0), 1e-12);
  EXPECT_NEAR(hdrc::ref::lut_encode(pq, std::numeric_limits<double>::quiet_NaN()), nits_to_pq(0.0),
              1e-12);
  EXPECT_NEAR(hdrc::ref::lut_encode(pq, 200.0), 1.0, 1e-12);  // 20000 nits -> 10000
  EXPECT_NEAR(hdrc::ref::lut_encode(pq, 1.0), nits_to_pq(100.0), 1e-12);
  EXPECT_TRUE(std::isnan(hdrc::ref::lut_encode(hdrc::ref::LutShaper{true, false}, -1.0)));
  // r.LUT.Shaper 0 is the log shaper even on an HDR device: LinToLog(0.18 + LogToLin(0)) with
  // LogToLin(x) = exp2((x - 444/1023) * 14) * 0.18.
  const auto log = ue58::tonemap_lut_shaper(resolved({}, {{"r.HDR.Display.OutputDevice", 3}}));
  EXPECT_FALSE(log.pq);
  const double black = std::exp2((0 - 444.0 / 1023) * 14) * 0.18;
  const double e = hdrc::ref::lut_encode(log, 0.18);
  EXPECT_NEAR(std::exp2((e - 444.0 / 1023) * 14) * 0.18 - black, 0.18, 1e-12);
}

// Step 9 (T1): device 7 decodes PQ to nits; the scRGB devices write the LUT's value unchanged
// (5.5 converted PQ(AP1) to scRGB here).
TEST(Ue58Tonemap, PostConversionOnlyForLinearExr) {
  auto p = resolved({}, {{"r.HDR.Display.OutputDevice", 7}});
  const Vec3 nits = hdrc::ref::post_convert(p, {nits_to_pq(100), nits_to_pq(1000), 0.5}, false);
  EXPECT_NEAR(nits[0], 100, 1e-9);
  EXPECT_NEAR(nits[1], 1000, 1e-8);
  for (int device : {5, 6}) {
    p = resolved({}, {{"r.HDR.Display.OutputDevice", device}});
    const Vec3 in{0.3, 1.25, 12.5};
    const Vec3 out = hdrc::ref::post_convert(p, in, false);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(out[c], in[c]);
    EXPECT_EQ(p.lut_format, 1);  // RGBA16F (AddCombineLUTPass: bUseFloatOutput)
  }
}

// Device allowances (docs/ue58-decisions.md G9): a grey scene at LogToLin(8/15) − LogToLin(0)
// reads the outer LUT's texel (8, 8, 8) (the log shaper's coordinate 8/15 of a 16³ LUT, UVW on the
// texel centre). A conformant device may store either neighbouring 10-bit code of that texel's
// value (Vulkan, Fixed-Point Data Conversions) and the pass multiplies the sample by LUTMax: every
// pixel's range holds floor(v · 1023) / 1023 · LUTMax and ceil(v · 1023) / 1023 · LUTMax, v the
// unrounded texel (CombineLUTsCommon), and the tight output. LUTMax 1.05 for Filmic on device 0,
// 1 for StandardACES (GetTonemappingMax).
TEST(Ue58Tonemap, DeviceRangesHoldBothCodesTimesLutMax) {
  for (const int method : {0, 1}) {
    SCOPED_TRACE(method);
    const auto p = resolved({{"TonemappingMethod", v1(method)},
                             {"r.LUT.Inner.Size", v1(10)},
                             {"VignetteIntensity", v1(0)}},
                            {{"r.HDR.Display.OutputDevice", 0}, {"r.LUT.Size", 16}});
    ASSERT_EQ(p.lut_format, 0);
    const double lut_max = method == 0 ? static_cast<double>(1.05f) : 1.0;
    hdrc::DevicePrecision device;
    device.sub_texel_bits = 4;
    const ue58::CombineLuts58 luts(p);
    const hdrc::ref::BakedLut dev = ue58::baked_outer_lut_device(luts, p, device);
    hdrc::Image grey(8, 4);
    const double x = ue_log::lin_from_log(8.0 / 15) - ue_log::lin_from_log(0);
    for (int i = 0; i < 32; ++i)
      for (int c = 0; c < 3; ++c) grey.data[i * 4 + c] = x;
    const hdrc::Image tight = ue58::tonemap_image(p, grey, nullptr, nullptr, dev);
    const hdrc::Image out =
        ue58::tonemap_image(p, grey, nullptr, nullptr, dev, &dev, device.sub_texel_bits);
    ASSERT_EQ(out.device_admissible.size(), 32u);
    const Vec3 v = luts.outer_texel({8.0 / 15, 8.0 / 15, 8.0 / 15});
    for (const hdrc::AdmissibleRange& a : out.device_admissible) {
      const double* t = tight.px(static_cast<int>(a.pixel % 8), static_cast<int>(a.pixel / 8));
      for (int c = 0; c < 3; ++c) {
        const double code = std::clamp(v[c], 0.0, 1.0) * 1023;
        EXPECT_LE(a.lo[c], std::floor(code) / 1023 * lut_max + 1e-12) << a.pixel << " " << c;
        EXPECT_GE(a.hi[c], std::ceil(code) / 1023 * lut_max - 1e-12) << a.pixel << " " << c;
        EXPECT_LE(a.lo[c], t[c]);
        EXPECT_GE(a.hi[c], t[c]);
      }
    }
  }
}

// The Texture vignette at feature level SM6 (USE_VIGNETTE_TEXTURE, RemapPermutation), by hand from
// PostProcessCommon.ush: VignetteSpace's Texture variant V = Pos · (saturate(1/AspectRatio),
// saturate(AspectRatio)), the sample at (InvSize · V − (Centre − 0.5)) · 0.5 + 0.5, bilinear with
// clamp (TStaticSamplerState<SF_Bilinear>), Weight = lerp(1, sample.r, Intensity), mask =
// lerp(Colour, 1, Weight). The Ramp stimulus (16 x 8) holds round(255 · (0.1 + 0.9 · cx · (0.25 +
// 0.75 · cy))) / 255 at texel centre (cx, cy) = ((x + 0.5) / 16, (y + 0.5) / 8).
//  * Square viewport, Pos (0.25, −0.5): UV (0.625, 0.25), texel coordinate (9.5, 1.5): the four
//    texels (9, 1) (10, 1) (9, 2) (10, 2) = 79, 84, 92, 98 (of 255) at weight 1/4 each: 88.25/255;
//    intensity 0.6, colour (0.25, 0.1, 0.5).
//  * 2:1 viewport (AspectRatio 0.5), Pos (−0.5, 1): V = (−0.5, 0.5) (the other types' space would
//    scale by sqrt(2/1.25)), UV (0.25, 0.75), texel coordinate (3.5, 5.5): 64, 75, 69, 81 →
//    72.25/255 at intensity 1, black.
// At SM5 the same settings give no vignette, and at SM6 without a texture (the white dummy) too.
TEST(Ue58Tonemap, TextureVignetteAtSm6ByHand) {
  const auto p = resolved({{"FeatureLevel", v1(4)},
                           {"VignetteType", v1(1)},
                           {"VignetteTexture", v1(2)},
                           {"VignetteIntensity", v1(0.6)},
                           {"VignetteColor", {0.25, 0.1, 0.5, 1}}});
  EXPECT_EQ(p.ue58_vignette_texture, 1);
  EXPECT_EQ(p.ue58_vignette_tex_width, 16);
  EXPECT_EQ(p.ue58_vignette_tex_height, 8);
  const Vec3 m = hdrc::ref::vignette_mask(ue58::tonemap_vignette(p), 0.25, -0.5, 1.0);
  const double w = 1 + 0.6 * (88.25 / 255 - 1);
  const double colour[3] = {0.25, 0.1, 0.5};
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(m[c], colour[c] + w * (1 - colour[c]), 1e-7) << c;

  const auto wide = resolved({{"FeatureLevel", v1(4)},
                              {"VignetteType", v1(1)},
                              {"VignetteTexture", v1(2)},
                              {"VignetteIntensity", v1(1)}});
  const Vec3 n = hdrc::ref::vignette_mask(ue58::tonemap_vignette(wide), -0.5, 1.0, 0.5);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(n[c], 72.25 / 255, 1e-12) << c;

  const auto sm5 =
      resolved({{"VignetteType", v1(1)}, {"VignetteTexture", v1(2)}, {"VignetteIntensity", v1(1)}});
  EXPECT_EQ(sm5.ue58_vignette_texture, 0);
  const auto dummy =
      resolved({{"FeatureLevel", v1(4)}, {"VignetteType", v1(1)}, {"VignetteIntensity", v1(1)}});
  EXPECT_EQ(dummy.ue58_vignette_tex_width, 1);
  for (const auto& q : {sm5, dummy}) {
    const Vec3 one = hdrc::ref::vignette_mask(ue58::tonemap_vignette(q), -0.5, 1.0, 0.5);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(one[c], 1.0);
  }
}

// The Texture vignette on a conformant device: at the first case above the weights are exactly
// 1/2 (on every sub-texel grid, up to the coordinate noise), so the range is mostly the UNORM8
// filter arithmetic's rounding; at
// a fraction off the grid (Pos (0.3, −0.5): texel x 9.9, 0.4 of a 2^-4 step away) 4 sub-texel bits
// admit the neighbouring grid weights 14/16 and 15/16 along x, whose samples by hand bound the
// range's mask. Both ranges hold the exact mask.
TEST(Ue58Tonemap, TextureVignetteDeviceRange) {
  const auto p = resolved({{"FeatureLevel", v1(4)},
                           {"VignetteType", v1(1)},
                           {"VignetteTexture", v1(2)},
                           {"VignetteIntensity", v1(1)}});
  const Vignette v = ue58::tonemap_vignette(p);
  Vec3 lo, hi;
  ASSERT_TRUE(ue58::vignette_texture_device_range(v, 0.25, -0.5, 1.0, 8, &lo, &hi));
  for (int c = 0; c < 3; ++c) {
    EXPECT_LE(lo[c], 88.25 / 255);
    EXPECT_GE(hi[c], 88.25 / 255);
    // The filter arithmetic in UNORM8 precision (FilterArithmetic::unorm(8)): each weight and each
    // of the four partial sums rounded outward on the 1/255 grid, the weights within 2^-8 of 1/2.
    EXPECT_LT(hi[c] - lo[c], 12.0 / 255);
  }
  // Pos x 0.3: u = 0.65, texel 9.9; y as above (1.5, weight 1/2). Rows 1 and 2 averaged: texel
  // 9 → (79 + 92) / 2, texel 10 → (84 + 98) / 2.
  const double a9 = (79 + 92) / 2.0 / 255, a10 = (84 + 98) / 2.0 / 255;
  ASSERT_TRUE(ue58::vignette_texture_device_range(v, 0.3, -0.5, 1.0, 4, &lo, &hi));
  const Vec3 exact = hdrc::ref::vignette_mask(v, 0.3, -0.5, 1.0);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(exact[c], a9 + (a10 - a9) * 0.9, 1e-7);
    EXPECT_LE(lo[c], a9 + (a10 - a9) * 14 / 16);
    EXPECT_GE(hi[c], a9 + (a10 - a9) * 15 / 16);
    EXPECT_LE(lo[c], exact[c]);
    EXPECT_GE(hi[c], exact[c]);
  }
  // Not the Texture branch (SM5): no range.
  const auto sm5 = resolved({{"VignetteType", v1(1)}, {"VignetteIntensity", v1(1)}});
  EXPECT_FALSE(ue58::vignette_texture_device_range(ue58::tonemap_vignette(sm5), 0.3, -0.5, 1.0, 4,
                                                   &lo, &hi));
}

}  // namespace
