// UE's log shaper against values derived by hand from TonemapCommon.ush's formulas
// (docs/spec/ue55.md §13).
#include "reference/color/ue_log_shaper.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace lg = hdrc::ref::ue_log;

namespace {

TEST(UeLogShaper, HandDerivedValues) {
  // LogToLin(0) = 0.18 · 2^(−444/1023 · 14); LogToLin(1) = 0.18 · 2^(579/1023 · 14).
  EXPECT_NEAR(lg::lin_from_log(0.0), 0.18 * std::exp2(-444.0 * 14.0 / 1023.0), 1e-18);
  EXPECT_NEAR(lg::lin_from_log(0.0), 2.667719095257e-3, 1e-14);
  EXPECT_NEAR(lg::lin_from_log(1.0), 43.7079096567, 1e-9);
  EXPECT_NEAR(lg::log_from_lin(0.18), 444.0 / 1023.0, 1e-15);
}

TEST(UeLogShaper, RoundTripInsideTheRange) {
  for (double x = 0.0; x <= 1.0; x += 1.0 / 1024) {
    EXPECT_NEAR(lg::log_from_lin(lg::lin_from_log(x)), x, 1e-14);
  }
}

// saturate() follows D3D: NaN and log2 of negatives become 0, +Inf becomes 1.
TEST(UeLogShaper, SaturatesLikeD3D) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(lg::log_from_lin(-1.0), 0.0);
  EXPECT_EQ(lg::log_from_lin(std::nan("")), 0.0);
  EXPECT_EQ(lg::log_from_lin(inf), 1.0);
  EXPECT_EQ(lg::log_from_lin(0.0), 0.0);  // log2(0) = −Inf
  EXPECT_EQ(lg::log_from_lin(1e6), 1.0);
}

}  // namespace
