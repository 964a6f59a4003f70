// VisualizeHDR's exposure at PreExposure != 1 (issue 11 §4): the stage reads
// EyeAdaptationBuffer[0].x, the plain exposure (PostProcessVisualizeHDR.usf MainPS), not the
// Tonemap pass's Exposure / PreExposure. The printed numbers are derived here by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "core/stage.h"
#include "reference/reference_engine.h"
#include "reference/ue/cpp/resolve.h"

namespace {

hdrc::Image grey(int w, int h, double v) {
  hdrc::Image img(w, h);
  for (size_t i = 0; i < img.pixel_count(); ++i)
    for (int c = 0; c < 4; ++c) img.data[i * 4 + c] = c < 3 ? v : 1.0;
  return img;
}

std::map<std::string, double> printed(double exposure, double pre_exposure) {
  hdrc::Case c;
  c.stage = hdrc::find_stage("visualize_hdr");
  c.settings.set("Exposure", {exposure, 0, 0, 0}, 1);
  c.settings.set("PreExposure", {pre_exposure, 0, 0, 0}, 1);
  hdrc::ResolvedCase rc;
  rc.spec = c;
  rc.params = *hdrc::ref::resolve_params(c, 192, 168);
  rc.input = grey(192, 168, 0.18 * pre_exposure);
  hdrc::ref::ReferenceEngine ref;
  auto img = ref.run(rc);
  EXPECT_TRUE(img.ok());
  return img.ok() ? img->values : std::map<std::string, double>{};
}

// By hand, UE 5.5 defaults with the extended luminance range: LuminanceMax = 0.78 / 0.78 = 1;
// histogram log2 range [-10, 20] EV100 + log2(1) → scale 1/30, bias 1/3; panel width 192 − 2·64 =
// 64 px. Exposure E = 2: EV = log2(1/E) = −1, EV100 = log2((1/E)/1) = −1, the white line at
// (log2(1/E)/30 + 1/3)·64 = (−1/30 + 10/30)·64 = 19.2 px. PreExposure must not move any of them
// (2.5 moved them by log2(2.5) = 1.32 EV and 2.82 px before the fix).
TEST(VisualizeHdrExposure, PrintedNumbersIgnorePreExposure) {
  for (double pre : {1.0, 2.5, 0.25}) {
    const auto v = printed(2.0, pre);
    ASSERT_TRUE(v.count("exposure_ev100")) << pre;
    EXPECT_NEAR(v.at("exposure_without_bias_ev"), -1.0, 1e-12) << pre;
    EXPECT_NEAR(v.at("exposure_ev100"), -1.0, 1e-12) << pre;
    EXPECT_NEAR(v.at("exposure_px"), 19.2, 1e-9) << pre;
    // The meter divides the pre-exposed scene by PreExposure: 0.18 of a 0.18 grey, every time.
    // log2((0.18 / 0.18) / 1) = 0 EV100.
    EXPECT_NEAR(v.at("meter_luminance"), 0.18, 1e-9) << pre;
    EXPECT_NEAR(v.at("meter_ev100"), 0.0, 1e-9) << pre;
  }
}

}  // namespace
