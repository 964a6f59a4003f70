// PQ against independent values: OpenColorIO 2.1's built-in ST 2084 curves (which scale linear
// 1.0 to 100 nits) and published ST 2084 signal values.
#include "color/st2084.h"

#include <OpenColorIO/OpenColorIO.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace OCIO = OCIO_NAMESPACE;
namespace pq = hdrc::ref::st2084;

namespace {

OCIO::ConstCPUProcessorRcPtr builtin(const char* style) {
  auto bt = OCIO::BuiltinTransform::Create();
  bt->setStyle(style);
  // OPTIMIZATION_NONE: no SSE fast-pow approximation (~1e-4 relative at low values).
  return OCIO::Config::CreateRaw()->getProcessor(bt)->getOptimizedCPUProcessor(
      OCIO::BIT_DEPTH_F32, OCIO::BIT_DEPTH_F32, OCIO::OPTIMIZATION_NONE);
}

TEST(St2084, ConstantsAreTheStandardsFractions) {
  EXPECT_EQ(pq::kM1, 0.1593017578125);
  EXPECT_EQ(pq::kM2, 78.84375);
  EXPECT_EQ(pq::kC1, 0.8359375);
  EXPECT_EQ(pq::kC2, 18.8515625);
  EXPECT_EQ(pq::kC3, 18.6875);
  EXPECT_EQ(pq::kC1, pq::kC3 - pq::kC2 + 1.0);  // ST 2084 eq. 5.3
}

// Published values (ITU-R BT.2100 / BT.2390 tables): signal for 0.0001, 100, 1000, 10000 nits.
TEST(St2084, PublishedSignalValues) {
  EXPECT_NEAR(pq::pq_from_nits(10000.0), 1.0, 1e-15);
  EXPECT_NEAR(pq::pq_from_nits(1000.0), 0.7518271, 5e-8);
  EXPECT_NEAR(pq::pq_from_nits(100.0), 0.5080784, 5e-8);
  EXPECT_NEAR(pq::pq_from_nits(0.0), std::pow(pq::kC1, pq::kM2), 1e-18);  // 7.31e-7, not 0
  EXPECT_NEAR(pq::nits_from_pq(0.5), 92.245709, 5e-6);
  EXPECT_NEAR(pq::nits_from_pq(0.75), 983.377856, 5e-6);
}

// OCIO 2.1 implements its ST 2084 built-ins as half-float-domain 1-D LUTs (linear 1.0 = 100
// nits), exact at half-representable inputs and linearly interpolated between them. We therefore
// sample every 13th half-float significand over the normal half range (6.1e-5 .. 64 linear):
// measured max relative difference 5e-8. (Between half values, or in the half denormal range,
// OCIO's interpolation differs from the formula by up to 1.1e-4 relative: OCIO's, not ours.)
std::vector<float> half_exact_values(int min_exp, int max_exp) {
  std::vector<float> v;
  for (int e = min_exp; e <= max_exp; ++e)
    for (int m = 1024; m < 2048; m += 13) v.push_back(std::ldexp(static_cast<float>(m), e - 10));
  return v;
}

TEST(St2084, MatchesOcioBuiltinForward) {
  auto cpu = builtin("CURVE - LINEAR_to_ST-2084");
  for (float linear : half_exact_values(-14, 6)) {
    float rgb[3] = {linear, 0.f, 0.f};
    cpu->applyRGB(rgb);
    const double ours = pq::pq_from_nits(linear * 100.0);
    EXPECT_NEAR(rgb[0], ours, 2e-7 * ours) << linear;
  }
}

// OCIO 2.1's inverse built-in is a sampled LUT with linear interpolation; measured against the
// formula it deviates by up to 2.4x at signals near 2^-14 and by at most 2.6e-6 above 0.125, so it
// is an oracle for the upper part of the curve (0.125 .. 1, i.e. 0.33 .. 10 000 nits) only.
TEST(St2084, MatchesOcioBuiltinInverse) {
  auto cpu = builtin("CURVE - ST-2084_to_LINEAR");
  for (float signal : half_exact_values(-3, -1)) {
    float rgb[3] = {signal, 0.f, 0.f};
    cpu->applyRGB(rgb);
    const double ours = pq::nits_from_pq(signal) / 100.0;
    EXPECT_NEAR(rgb[0], ours, 3e-6 * ours) << signal;  // measured 2.6e-6
  }
}

TEST(St2084, RoundTrip) {
  for (double log_nits = -6.0; log_nits <= 4.0; log_nits += 0.01) {
    const double nits = std::pow(10.0, log_nits);
    EXPECT_NEAR(pq::nits_from_pq(pq::pq_from_nits(nits)), nits, 1e-9 * nits + 1e-12);
  }
}

// UE's LinearToST2084 has no clamp: negatives and +Inf are NaN (docs/spec/ue55.md §3.1, §12.5).
TEST(St2084, NonFiniteAndNegativeBehaveAsUe) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(std::isnan(pq::pq_from_nits(-1.0)));
  EXPECT_TRUE(std::isnan(pq::pq_from_nits(std::nan(""))));
  EXPECT_TRUE(std::isnan(pq::pq_from_nits(inf)));  // Inf · rcp(Inf) = Inf · 0
  EXPECT_TRUE(std::isnan(pq::nits_from_pq(std::nan(""))));
  EXPECT_EQ(pq::nits_from_pq(0.0), 0.0);  // below c1 clamps to black
}

}  // namespace
