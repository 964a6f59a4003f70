// The golden comparison's bound (runner/golden_compare.h, docs/goldens.md): its rules on single
// values, that the repository's goldens hold for the build running this test, and that a real
// change of one of UE's constants still fails against them.
#include "runner/golden_compare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "reference/reference_engine.h"
#include "runner/case_loader.h"

#ifndef HDRC_SOURCE_DIR
#error "HDRC_SOURCE_DIR must be defined"
#endif

namespace {

float ulps_up(float v, int n) {
  for (int i = 0; i < n; ++i) v = std::nextafter(v, std::numeric_limits<float>::infinity());
  return v;
}

// Where the absolute part is below one ULP (a value at least 16 times the image's scale S, so
// 8 x 2^-24 x S < 0.5 x 2^-24 x |v|), only the relative part counts.
TEST(GoldenCompare, TwoUlpsOfTheValueMatchThreeDoNotWhereTheScaleIsSmall) {
  for (float v : {1.0f, 0.3f, -7.5e-3f, 1234.5f}) {
    const double scale = std::fabs(v) / 16;
    EXPECT_TRUE(hdrc::golden_value_close(v, ulps_up(v, 2), scale)) << v;
    EXPECT_DOUBLE_EQ(hdrc::golden_deviation(v, ulps_up(v, 2), scale), 1.0) << v;
    EXPECT_FALSE(hdrc::golden_value_close(v, ulps_up(v, 3), scale)) << v;
  }
}

TEST(GoldenCompare, TheAbsolutePartIsAFractionOfTheImagesScale) {
  // The example: values that cancel near zero in an image of scale 1 (display-encoded).
  const float golden = -1.16537242e-08f, release = -1.16537873e-08f;
  EXPECT_GT(std::fabs(golden - release) / (std::ldexp(1.0, -23) * 1.16e-8), 2.0);  // > 2 ULPs
  EXPECT_TRUE(hdrc::golden_value_close(golden, release, 1.0));
  // The floor is kGoldenScaleFloor * 2^-24 of the scale: just past it fails, at any scale.
  for (double scale : {1e-3, 1.0, 1e4}) {
    const double floor = hdrc::kGoldenScaleFloor * std::ldexp(scale, -24);
    EXPECT_TRUE(hdrc::golden_value_close(0.0f, static_cast<float>(floor * 0.99), scale)) << scale;
    EXPECT_FALSE(hdrc::golden_value_close(0.0f, static_cast<float>(floor * 1.02), scale)) << scale;
  }
}

TEST(GoldenCompare, NonFiniteValuesMatchOnlyThemselves) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::nanf("");
  EXPECT_TRUE(hdrc::golden_value_close(nan, nan, 1));
  EXPECT_TRUE(hdrc::golden_value_close(inf, inf, 1));
  EXPECT_FALSE(hdrc::golden_value_close(inf, -inf, 1));
  EXPECT_FALSE(hdrc::golden_value_close(nan, 0.0f, 1));
  EXPECT_FALSE(hdrc::golden_value_close(1.0f, nan, 1));
  EXPECT_FALSE(hdrc::golden_value_close(inf, std::numeric_limits<float>::max(), 1e38));
}

TEST(GoldenCompare, ColourAndAlphaHaveTheirOwnScales) {
  hdrc::Image g(2, 1);
  const double px[8] = {100.0, 2.0, -300.0, 0.5, 1e-9, 0.0, 1.0, 0.25};
  for (int i = 0; i < 8; ++i) g.data[i] = px[i];
  g.data[6] = std::nan("");
  const hdrc::GoldenScale s = hdrc::golden_scale(g);
  EXPECT_DOUBLE_EQ(s.colour, 300.0);
  EXPECT_DOUBLE_EQ(s.alpha, 0.5);
  // A difference the colour scale allows is over the bound in alpha.
  hdrc::Image r = g;
  r.data[4] += 1e-6;  // colour: 1e-6 < 2^-24 * 300 = 1.8e-5
  r.data[7] += 1e-6;  // alpha: 1e-6 > 2^-24 * 0.5 = 3e-8, and many ULPs of 0.25
  const hdrc::GoldenDiff d = hdrc::compare_with_golden(g, r);
  EXPECT_EQ(d.differ, 1u);
  EXPECT_EQ(d.first, 7u);
}

// The repository's golden of the example case holds for this build (whatever its
// compiler and optimisation level), and a real change of one constant fails against it.
TEST(GoldenCompare, ARealChangeOfAConstantFailsAgainstTheRepositorysGolden) {
  const std::string root = HDRC_SOURCE_DIR;
  const std::string id = "tonemap/display/hdr1_dev5_gamut3_lut33_fmt2_layout0_log_ramp";
  hdrc::LoadedCases loaded = hdrc::load_cases(root + "/cases");
  ASSERT_TRUE(loaded.errors.empty());
  const hdrc::Case* c = nullptr;
  for (const hdrc::Case& k : loaded.cases)
    if (k.id == id) c = &k;
  ASSERT_NE(c, nullptr) << id;
  auto golden = hdrc::read_image(root + "/goldens/" + id + ".exr");
  ASSERT_TRUE(golden.ok()) << golden.error().to_string();
  auto rc = hdrc::resolve_case(*c);
  ASSERT_TRUE(rc.ok());
  hdrc::ref::ReferenceEngine engine;
  auto img = engine.run(*rc);
  ASSERT_TRUE(img.ok());
  const hdrc::GoldenDiff same = hdrc::compare_with_golden(*golden, *img);
  EXPECT_EQ(same.differ, 0u) << "largest deviation " << same.largest;

  // A constant changed in its 5th significant digit, as a port that prints a literal with fewer
  // digits would have it: one coefficient of the working colour space -> AP0 matrix (this ACES
  // device's input to the output transform), or ACESMidData's first value.
  for (int which = 0; which < 2; ++which) {
    hdrc::ResolvedCase changed = *rc;
    if (which == 0)
      changed.params.wcs_to_ap0(0, 0) *= 1 + 1e-5;
    else
      changed.params.aces_mid[0] *= 1 + 1e-5;
    auto out = engine.run(changed);
    ASSERT_TRUE(out.ok());
    const hdrc::GoldenDiff diff = hdrc::compare_with_golden(*golden, *out);
    EXPECT_GT(diff.differ, 0u) << which << ": largest deviation " << diff.largest;
  }
}

}  // namespace
