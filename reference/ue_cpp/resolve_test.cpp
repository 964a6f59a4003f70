// Cvar resolution as UE 5.5's C++ does it (spec §5.4, §6.2, §7).
#include "reference/ue_cpp/resolve.h"

#include <gtest/gtest.h>

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

// Dither amount (spec §6.1 step 10, 5.5 AddTonemapPass): none for 8/9, override bits, else
// 1/1023 unless the SDR back buffer is 8-bit: r.DefaultBackBufferPixelFormat defaults to 4
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
