// UE 5.8's VisualizeHDR (stage ue58_visualize_hdr): UE 5.5's pass (PostProcessVisualizeHDR.usf
// MainPS; 5.8's differs only in the mobile histogram accessors, docs/ue58-differences.md §1c′) over
// UE 5.8's tonemapped scene. The printed numbers and the debug view are derived here by hand from
// UE's formulas (GetEyeAdaptationScalarParameters, LuminanceMaxFromLensAttenuation, MainPS); the
// scene it shows is 5.8's Tonemap pass (ue58_tonemap), not 5.5's.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "core/pipeline.h"
#include "reference/reference_engine.h"
#include "reference/ue/cpp/resolve.h"
#include "reference/ue/ue58/ue58_pipeline.h"
#include "reference/ue/ue58/ue58_tonemap.h"

namespace {

namespace ue58 = hdrc::ref::ue58;

constexpr int kWidth = 192, kHeight = 168;  // about the smallest view that holds UE's panel

hdrc::Image grey(double v) {
  hdrc::Image img(kWidth, kHeight);
  for (size_t i = 0; i < img.pixel_count(); ++i)
    for (int c = 0; c < 4; ++c) img.data[i * 4 + c] = c < 3 ? v : 1.0;
  return img;
}

// A resolved ue58 case of `stage` over a grey scene of `value` (pre-exposed).
hdrc::ResolvedCase resolved(const char* stage, std::map<std::string, double> settings,
                            std::map<std::string, double> cvars, double value) {
  const hdrc::Pipeline& pl = ue58::ue58_pipeline();
  hdrc::Case c;
  c.stage = hdrc::find_stage(pl, stage);
  c.settings = pl.new_settings();
  c.settings.set("r.LUT.Inner.Size", {16, 0, 0, 0}, 1);
  for (const auto& [k, v] : settings) {
    const auto st = c.settings.set(k, {v, 0, 0, 0}, 1);
    EXPECT_TRUE(st.ok()) << k << ": " << st.error().to_string();
  }
  for (const auto& [k, v] : cvars) {
    const auto st = c.cvars.set(k, v);
    EXPECT_TRUE(st.ok()) << k << ": " << st.error().to_string();
  }
  EXPECT_TRUE(c.cvars.set("r.HDR.EnableHDROutput", 1).ok());
  EXPECT_TRUE(c.cvars.set("r.LUT.Size", 16).ok());
  hdrc::ResolvedCase rc;
  rc.spec = c;
  auto r = pl.resolve(c, kWidth, kHeight);
  EXPECT_TRUE(r.ok()) << r.error().to_string();
  if (r.ok()) rc.params = r->params;
  rc.input = grey(value);
  return rc;
}

hdrc::Image run(const hdrc::ResolvedCase& rc) {
  auto img = ue58::ue58_pipeline().reference(rc, false);
  EXPECT_TRUE(img.ok()) << img.error().to_string();
  return img.ok() ? *img : hdrc::Image();
}

// By hand, UE defaults with the extended luminance range: LuminanceMax = 0.78 / max(0.78, 0.01)
// = 1 (LuminanceMaxFromLensAttenuation). Exposure E = 2: "without bias" EV = log2(1/E) = -1,
// EV100 = log2((1/E) / LuminanceMax) = -1; the histogram maps log2 luminance by scale 1/30, bias
// 1/3 (HistogramLogMin/Max -10/20 EV100), so the white line sits at (-1/30 + 10/30) * 64 = 19.2 px
// of the 192 - 2 * 64 = 64 px panel. The meters divide the pre-exposed scene by PreExposure
// (View.OneOverPreExposure): a 0.18 grey reads Luminance 0.18 "NIT", log2((0.18 / 0.18) / 1) = 0
// EV100, illuminance pi * 0.18 "LUX". None of it moves with PreExposure, the method or the ACES
// version: 5.8 carries PreExposure and the debug type into its block as 5.5 does.
TEST(Ue58Visualize, PrintedNumbersAreUeFormulasAtAnyPreExposure) {
  for (double method : {0.0, 1.0})
    for (double version : {1.0, 2.0})
      for (double pre : {1.0, 2.5}) {
        const auto rc = resolved("ue58_visualize_hdr",
                                 {{"TonemappingMethod", method},
                                  {"r.HDR.Aces.Version", version},
                                  {"Exposure", 2.0},
                                  {"PreExposure", pre}},
                                 {{"r.HDR.Display.OutputDevice", 3}}, 0.18 * pre);
        EXPECT_EQ(rc.params.pre_exposure, pre);
        const auto v = run(rc).values;
        ASSERT_TRUE(v.count("exposure_ev100")) << method << " " << version << " " << pre;
        EXPECT_NEAR(v.at("exposure_without_bias_ev"), -1.0, 1e-12) << pre;
        EXPECT_NEAR(v.at("exposure_ev100"), -1.0, 1e-12) << pre;
        EXPECT_NEAR(v.at("exposure_px"), 19.2, 1e-9) << pre;
        EXPECT_NEAR(v.at("meter_luminance"), 0.18, 1e-9) << pre;
        EXPECT_NEAR(v.at("meter_ev100"), 0.0, 1e-9) << pre;
        EXPECT_NEAR(v.at("illuminance_lux"), M_PI * 0.18, 1e-9) << pre;
      }
}

// r.EyeAdaptation.VisualizeDebugType 2 (MainPS): Luminance = CalculateEyeAdaptationLuminance(scene
// / PreExposure) = max(dot(rgb, LuminanceWeights), LuminanceMin) with LuminanceWeights 1/3 each
// (r.AutoExposure.LuminanceMethod 0: GetEyeAdaptationScalarParameters) and LuminanceMin =
// 2^HistogramLogMin (about 1e-3 at the default -10 EV100), times LuminanceScale 1
// (r.EyeAdaptation.VisualizeLuminanceScale). At pixel (0, 0), outside the meters and the panel, a
// 0.3 grey pre-exposed by 2 (0.6 in the scene colour) shows 0.3 in every channel.
TEST(Ue58Visualize, LuminanceDebugViewIsTheMeteredLuminance) {
  const auto rc =
      resolved("ue58_visualize_hdr", {{"PreExposure", 2.0}},
               {{"r.HDR.Display.OutputDevice", 5}, {"r.EyeAdaptation.VisualizeDebugType", 2}}, 0.6);
  EXPECT_EQ(rc.params.visualize_debug_type, 2);
  const hdrc::Image img = run(rc);
  ASSERT_FALSE(img.data.empty());
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(img.data[c], 0.3, 1e-12) << c;
}

// Debug type 0 shows the tonemapped scene: UE 5.8's Tonemap pass (the ue58_tonemap stage's pixel,
// sampled bilinearly at its centre: equal to 1e-12), which for the scRGB device 5 writes the LUT's
// value unchanged where UE 5.5's pass converts PQ to scRGB (docs/ue58-differences.md T1): 5.5's
// VisualizeHDR of the same scene differs.
TEST(Ue58Visualize, SceneIsUe58sTonemapPass) {
  for (double method : {0.0, 1.0}) {
    const std::map<std::string, double> settings = {{"TonemappingMethod", method}};
    const std::map<std::string, double> cvars = {{"r.HDR.Display.OutputDevice", 5}};
    const hdrc::Image vis = run(resolved("ue58_visualize_hdr", settings, cvars, 0.18));
    const hdrc::Image tm = run(resolved("ue58_tonemap", settings, cvars, 0.18));
    ASSERT_FALSE(vis.data.empty());
    ASSERT_FALSE(tm.data.empty());
    for (int c = 0; c < 4; ++c)
      EXPECT_NEAR(vis.data[c], tm.data[c], 1e-12 * std::fabs(tm.data[c])) << method << " " << c;
  }
  // UE 5.5's stage over the same scene and device shows 5.5's pass (scRGB from its PQ LUT).
  hdrc::Case c55;
  c55.stage = hdrc::find_stage("visualize_hdr");
  ASSERT_TRUE(c55.cvars.set("r.HDR.EnableHDROutput", 1).ok());
  ASSERT_TRUE(c55.cvars.set("r.HDR.Display.OutputDevice", 5).ok());
  hdrc::ResolvedCase rc55;
  rc55.spec = c55;
  rc55.params = *hdrc::ref::resolve_params(c55, kWidth, kHeight);
  rc55.input = grey(0.18);
  auto v55 = hdrc::ref::ReferenceEngine().run(rc55);
  ASSERT_TRUE(v55.ok());
  const hdrc::Image vis58 =
      run(resolved("ue58_visualize_hdr", {}, {{"r.HDR.Display.OutputDevice", 5}}, 0.18));
  ASSERT_FALSE(vis58.data.empty());
  EXPECT_GT(std::fabs(v55->data[0] - vis58.data[0]), 1e-3 * std::fabs(vis58.data[0]));
}

}  // namespace
