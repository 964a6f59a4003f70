// Cvar resolution as UE 5.5's C++ does it (docs/spec/ue55.md §5.4, §6.2, §7).
#include "reference/ue/cpp/resolve.h"

#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <vector>

namespace {

hdrc::Case make(std::initializer_list<std::pair<const char*, double>> cvars,
                const char* stage = "tonemap") {
  hdrc::Case c;
  c.stage = hdrc::find_stage(stage);
  for (const auto& [k, v] : cvars) EXPECT_TRUE(c.cvars.set(k, v).ok()) << k;
  return c;
}

// HDRSettingChangedSinkCallback: HDR on with MaxLuminance 0 naively falls back to 1000 nits.
TEST(Resolve, MaxLuminanceZeroBecomes1000WithHdrOn) {
  auto r = *hdrc::ref::resolve(
      make({{"r.HDR.EnableHDROutput", 1}, {"r.HDR.Display.OutputDevice", 3}}), 1, 1);
  EXPECT_EQ(r.params.output_max_luminance, 1000.0);
  EXPECT_TRUE(r.degenerate.empty());
  // UE's default float parameters for 1000 nits (HDRHelper.h FACESTonemapParams()).
  EXPECT_EQ(static_cast<float>(r.params.aces_min_max[2]), 692.651123f);
  r = *hdrc::ref::resolve(
      make({{"r.HDR.EnableHDROutput", 1}, {"r.HDR.Display.MaxLuminance", 2000}}), 1, 1);
  EXPECT_EQ(r.params.output_max_luminance, 2000.0);
}

// HDR off leaves MaxLuminance 0: an ACES device then gets degenerate parameters (flagged, for the
// stages that encode with them), an SDR device does not care.
TEST(Resolve, AcesDeviceWithHdrOffIsDegenerate) {
  auto r = *hdrc::ref::resolve(make({{"r.HDR.Display.OutputDevice", 4}}), 1, 1);
  EXPECT_NE(r.degenerate.find("MaxLuminance resolves to 0"), std::string::npos) << r.degenerate;
  EXPECT_TRUE(hdrc::ref::resolve(make({{"r.HDR.Display.OutputDevice", 4}}, "shaper"), 1, 1)
                  ->degenerate.empty());
  EXPECT_TRUE(
      hdrc::ref::resolve(make({{"r.HDR.Display.OutputDevice", 0}}), 1, 1)->degenerate.empty());
}

// GetTonemapperOutputDeviceParameters: r.TonemapperGamma > 0 turns devices 0/1 into device 2 with
// InverseGamma.z = 1/Gamma; device 2 with Gamma 0 uses 2.2.
TEST(Resolve, TonemapperGammaForcesExplicitGammaDevice) {
  auto p = hdrc::ref::resolve(make({{"r.TonemapperGamma", 2.4}}), 1, 1)->params;
  EXPECT_EQ(p.output_device, 2);
  EXPECT_FLOAT_EQ(p.inverse_gamma[2], 1.0f / 2.4f);
  p = hdrc::ref::resolve(make({{"r.HDR.Display.OutputDevice", 1}, {"r.TonemapperGamma", 2.0}}), 1,
                         1)
          ->params;
  EXPECT_EQ(p.output_device, 2);
  p = hdrc::ref::resolve(make({{"r.HDR.Display.OutputDevice", 2}}), 1, 1)->params;
  EXPECT_FLOAT_EQ(p.inverse_gamma[2], 1.0f / 2.2f);
  p = hdrc::ref::resolve(make({{"r.HDR.Display.OutputDevice", 3}, {"r.TonemapperGamma", 2.4}}), 1,
                         1)
          ->params;
  EXPECT_EQ(p.output_device, 3);              // HDR devices are not remapped
  EXPECT_FLOAT_EQ(p.inverse_gamma[1], 1.0f);  // 2.2 / DisplayGamma 2.2
}

// Dither amount (docs/spec/ue55.md §6.1 step 10, 5.5 AddTonemapPass): none for 8/9, override bits,
// else 1/1023 unless the SDR back buffer is 8-bit: r.DefaultBackBufferPixelFormat defaults to 4
// (A2B10G10R10, 5.5 SceneTextures.cpp), so the default SDR amount is 1/1023; format 0 is 1/255.
TEST(Resolve, DitherAmountPerDevice) {
  EXPECT_DOUBLE_EQ(hdrc::ref::resolve(make({}), 1, 1)->params.dither_amount, 1.0 / 1023.0);
  EXPECT_DOUBLE_EQ(
      hdrc::ref::resolve(make({{"r.DefaultBackBufferPixelFormat", 0}}), 1, 1)->params.dither_amount,
      1.0 / 255.0);
  for (int format = 1; format <= 4; ++format)
    EXPECT_DOUBLE_EQ(hdrc::ref::resolve(make({{"r.DefaultBackBufferPixelFormat", format}}), 1, 1)
                         ->params.dither_amount,
                     1.0 / 1023.0)
        << format;
  // An HDR swap chain is never 8-bit, whatever the SDR default says.
  EXPECT_DOUBLE_EQ(hdrc::ref::resolve(make({{"r.HDR.EnableHDROutput", 1},
                                            {"r.HDR.Display.OutputDevice", 3},
                                            {"r.DefaultBackBufferPixelFormat", 0}}),
                                      1, 1)
                       ->params.dither_amount,
                   1.0 / 1023.0);
  EXPECT_DOUBLE_EQ(
      hdrc::ref::resolve(make({{"r.HDR.EnableHDROutput", 1}, {"r.HDR.Display.OutputDevice", 5}}), 1,
                         1)
          ->params.dither_amount,
      1.0 / 1023.0);
  EXPECT_EQ(
      hdrc::ref::resolve(make({{"r.HDR.Display.OutputDevice", 9}}), 1, 1)->params.dither_amount,
      0.0);
  EXPECT_DOUBLE_EQ(
      hdrc::ref::resolve(make({{"r.BackbufferQuantizationDitheringOverride", 12}}), 1, 1)
          ->params.dither_amount,
      1.0 / 4095.0);
}

// GetMappingPolynomial: c = Min, b = 4·Mid − 3·Min − Max, a = Max − Min − b; defaults identity.
TEST(Resolve, ColorRemapPolynomial) {
  auto p = hdrc::ref::resolve(make({}), 1, 1)->params;
  EXPECT_FLOAT_EQ(p.mapping_polynomial[0], 0.0f);
  EXPECT_FLOAT_EQ(p.mapping_polynomial[1], 1.0f);
  EXPECT_FLOAT_EQ(p.mapping_polynomial[2], 0.0f);
  p = hdrc::ref::resolve(make({{"r.Color.Min", 0.1}, {"r.Color.Mid", 0.4}, {"r.Color.Max", 0.9}}),
                         1, 1)
          ->params;
  EXPECT_NEAR(p.mapping_polynomial[2], 0.1, 1e-7);
  EXPECT_NEAR(p.mapping_polynomial[1], 4 * 0.4 - 0.3 - 0.9, 1e-6);
  EXPECT_NEAR(p.mapping_polynomial[0], 0.9 - 0.1 - (4 * 0.4 - 0.3 - 0.9), 1e-6);
}

}  // namespace

namespace {

// The project's Working Color Space reaches the parameter block as UE's CPU builds it
// (RendererSettings.cpp: UpdateWorkingColorSpaceAndChromaticities → SceneManagement.cpp:
// FDefaultWorkingColorSpaceUniformBuffer::Update).
TEST(Resolve, WorkingColorSpacePresetsAndCustom) {
  using hdrc::ref::WorkingColorSpacePreset;
  for (int preset = 1; preset <= 6; ++preset) {
    hdrc::Case c = make({});
    ASSERT_TRUE(c.settings.set("WorkingColorSpace", {double(preset), 0, 0, 0}, 1).ok());
    const auto r = hdrc::ref::resolve(c, 1, 1);
    ASSERT_TRUE(r) << r.error().to_string();
    const auto w =
        hdrc::ref::make_working_color_space(static_cast<WorkingColorSpacePreset>(preset));
    EXPECT_EQ(r->params.wcs_is_srgb, preset == 1 ? 1 : 0);
    EXPECT_EQ(hdrc::ref::max_abs_diff(r->params.wcs_to_ap1, w.to_ap1), 0.0);
    EXPECT_EQ(hdrc::ref::max_abs_diff(r->params.wcs_from_ap1, w.from_ap1), 0.0);
    EXPECT_EQ(hdrc::ref::max_abs_diff(r->params.wcs_to_ap0, w.to_ap0), 0.0);
    EXPECT_EQ(hdrc::ref::max_abs_diff(r->params.wcs_to_xyz, w.to_xyz), 0.0);
  }
  // Custom Rec.2020 chromaticities give the Rec2020 preset's matrices (bIsSRGB false).
  hdrc::Case c = make({});
  ASSERT_TRUE(c.settings.set_choice("WorkingColorSpace", "Custom").ok());
  ASSERT_TRUE(c.settings.set("WorkingColorSpaceRedGreen", {0.708, 0.292, 0.170, 0.797}, 4).ok());
  ASSERT_TRUE(c.settings.set("WorkingColorSpaceBlueWhite", {0.131, 0.046, 0.3127, 0.3290}, 4).ok());
  const auto r = hdrc::ref::resolve(c, 1, 1);
  ASSERT_TRUE(r) << r.error().to_string();
  EXPECT_EQ(hdrc::ref::max_abs_diff(
                r->params.wcs_to_ap1,
                hdrc::ref::make_working_color_space(WorkingColorSpacePreset::kRec2020).to_ap1),
            0.0);
  EXPECT_EQ(r->params.wcs_is_srgb, 0);
  // Custom with the defaults is sRGB, and bIsSRGB (IsSRGBChromaticities).
  hdrc::Case d = make({});
  ASSERT_TRUE(d.settings.set_choice("WorkingColorSpace", "Custom").ok());
  EXPECT_EQ(hdrc::ref::resolve(d, 1, 1)->params.wcs_is_srgb, 1);
}

TEST(Resolve, WorkingColorSpaceErrors) {
  hdrc::Case c = make({});
  auto st = c.settings.set_choice("WorkingColorSpace", "Rec709");
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().message, "unknown WorkingColorSpace 'Rec709' (did you mean Rec2020?)");
  EXPECT_EQ(st.error().choices,
            "sRGB (1), Rec2020 (2), ACESAP0 (3), ACESAP1 (4), P3DCI (5), P3D65 (6), Custom (7)");
  EXPECT_FALSE(c.settings.set("WorkingColorSpace", {2.5, 0, 0, 0}, 1).ok());
  EXPECT_FALSE(c.settings.set("WorkingColorSpace", {0, 0, 0, 0}, 1).ok());
  EXPECT_FALSE(c.settings.set_choice("WhiteTemp", "D65").ok());
  // Chromaticities with a preset: an error naming both.
  ASSERT_TRUE(c.settings.set_choice("WorkingColorSpace", "Rec2020").ok());
  ASSERT_TRUE(c.settings.set("WorkingColorSpaceRedGreen", {0.7, 0.3, 0.2, 0.7}, 4).ok());
  auto r = hdrc::ref::resolve(c, 1, 1);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("applies only when WorkingColorSpace is Custom (7); it is "
                                   "Rec2020"),
            std::string::npos)
      << r.error().message;
  // Degenerate custom chromaticities: the values and the problem.
  ASSERT_TRUE(c.settings.set_choice("WorkingColorSpace", "Custom").ok());
  ASSERT_TRUE(c.settings.set("WorkingColorSpaceBlueWhite", {0.15, 0.06, 0.3, 0.0}, 4).ok());
  r = hdrc::ref::resolve(c, 1, 1);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("W (0.3, 0): the white's y must be above 0"), std::string::npos)
      << r.error().message;
}

// The user colour-grading LUTs (docs/ue55-lut-blend-spec.md §2.7, §2.8): the case's "lut" at
// ColorGradingIntensity, then its "lut_blend" steps, reduced by GenerateFinalTable into BLENDCOUNT,
// LUTWeights and the texture slots (Textures_1..4), as the spec's tables give them.
std::shared_ptr<const hdrc::UserLut> lut_named(const char* name) {
  auto l = std::make_shared<hdrc::UserLut>();
  l->name = name;
  l->size = 16;
  return l;
}

TEST(Resolve, UserLutIntensityAndBlendFillTheTable) {
  const auto a = lut_named("a.cube"), b = lut_named("b.cube");
  struct Row {
    double intensity;
    std::vector<hdrc::LutBlendStep> steps;
    int count;
    std::array<double, 5> w;
    std::vector<std::shared_ptr<const hdrc::UserLut>> slots;
  };
  const Row rows[] = {
      {0.0, {}, 1, {1, 0, 0, 0, 0}, {}},                      // S2
      {0.5, {}, 2, {0.5, 0.5, 0, 0, 0}, {a}},                 // S3
      {1.0, {}, 2, {0, 1, 0, 0, 0}, {a}},                     // S4
      {0.5, {{b, 0.5}}, 3, {0.25, 0.5, 0.25, 0, 0}, {b, a}},  // S5
      {1.0, {{b, 0.5}}, 3, {0, 0.5, 0.5, 0, 0}, {b, a}},      // S9: the tie
      {0.5, {{a, 0.5}}, 2, {0.25, 0.75, 0, 0, 0}, {a}},       // S10
  };
  for (const Row& r : rows) {
    hdrc::Case c = make({}, "combine_luts");
    c.lut = a;
    c.lut_blend = r.steps;
    ASSERT_TRUE(c.settings.set("ColorGradingIntensity", {r.intensity, 0, 0, 0}, 1).ok());
    const auto res = *hdrc::ref::resolve(c, 16, 16);
    SCOPED_TRACE(testing::Message()
                 << "intensity " << r.intensity << ", " << r.steps.size() << " steps");
    EXPECT_EQ(res.params.lut_blend_count, r.count);
    const std::array<double, 5> w = {res.params.lut_weights[0], res.params.lut_weights[1],
                                     res.params.lut_weights[2], res.params.lut_weights[3],
                                     res.params.lut_weight_4};
    EXPECT_EQ(w, r.w);
    for (size_t i = 0; i < res.user_luts.size(); ++i)
      EXPECT_EQ(res.user_luts[i], i < r.slots.size() ? r.slots[i] : nullptr) << "slot " << i;
  }
  // Without a LUT: BLENDCOUNT 1, neutral weight 1, on every stage.
  const auto plain = *hdrc::ref::resolve(make({}, "tonemap"), 1, 1);
  EXPECT_EQ(plain.params.lut_blend_count, 1);
  EXPECT_EQ(plain.params.lut_weights[0], 1.0);
}

}  // namespace
