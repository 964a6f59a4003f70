// Diff metrics with hand-computed values, ΔE_ITP against independently derived values, the
// non-finite rules (NaN vs NaN and same-sign Inf consistent, anything else a mismatch reported
// first; every comparison fails on NaN), the statistics, bands and the tolerance criteria.
#include "runner/diff.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "color/st2084.h"
#include "core/pipeline.h"
#include "reference/color/ue_matrices.h"

namespace {

using hdrc::Metric;
using hdrc::OutputEncoding;
using hdrc::StageId;

// UE 5.5's encoding of `stage`'s output for output device `device` (the other parameters at their
// block defaults; device 2's InverseGamma.z is `inverse_gamma_z`).
OutputEncoding ue_encoding(const char* stage, int device, double inverse_gamma_z = 1 / 2.2) {
  hdrc::ParamBlock p;
  p.output_device = device;
  p.inverse_gamma[2] = inverse_gamma_z;
  return hdrc::output_encoding(*hdrc::find_stage(stage), p);
}

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

hdrc::Tolerance tol(double rel, double floor, double pq) {
  hdrc::Tolerance t;
  t.linear_rel = rel;
  t.rel_floor = floor;
  t.pq_code10 = pq;
  return t;
}

hdrc::Image grey(int w, double v) {
  hdrc::Image img(w, 1);
  for (int x = 0; x < w; ++x)
    for (int c = 0; c < 4; ++c) img.px(x, 0)[c] = c == 3 ? 1.0 : v;
  return img;
}

const OutputEncoding kShaper{StageId::kShaper, 3};

TEST(Diff, HandComputedMetrics) {
  hdrc::Image in = grey(4, 0.5), ref = grey(4, 0.5), cand = grey(4, 0.5);
  cand.px(2, 0)[1] = 0.5005;  // abs 5e-4, rel 1e-3
  const auto s = hdrc::diff_images(in, ref, cand, kShaper, tol(1e-2, 1e-6, 10));
  EXPECT_EQ(s.values, 12u);
  EXPECT_EQ(s.pixels, 4u);
  EXPECT_NEAR(s[Metric::kLinearAbs].max, 5e-4, 1e-15);
  EXPECT_NEAR(s[Metric::kLinearRel].max, 1e-3, 1e-12);
  EXPECT_NEAR(s[Metric::kLinearAbs].mean, 5e-4 / 12, 1e-15);
  EXPECT_NEAR(s[Metric::kLinearAbs].rms, 5e-4 / std::sqrt(12.0), 1e-15);
  EXPECT_EQ(s[Metric::kLinearRel].worst.x, 2);
  EXPECT_EQ(s[Metric::kLinearRel].worst.channel, 1);
  // Shaper outputs are scene-linear: 0.5 → 50 nits, 0.5005 → 50.05 nits.
  namespace pq = hdrc::ref::st2084;
  const double want = (pq::pq_from_nits(50.05) - pq::pq_from_nits(50.0)) * 1023.0;
  EXPECT_NEAR(s[Metric::kPqCode10].max, want, 1e-9);
  EXPECT_NEAR(s[Metric::kPqCode12].max, want / 1023.0 * 4095.0, 1e-9);
  EXPECT_TRUE(hdrc::judge(s, tol(1e-2, 1e-6, 10)).pass);
  EXPECT_FALSE(hdrc::judge(s, tol(1e-4, 1e-6, 10)).pass);
  EXPECT_FALSE(hdrc::judge(s, tol(1e-2, 1e-6, want / 2)).pass);
}

// 1000 pixels, G of pixel k off by k·1e-6: 3000 values, 2000 of them exact. Nearest-rank p99 is
// value 2970 of the sorted list (k = 969), p99.9 value 2997 (k = 996); the mean is
// Σk·1e-6 / 3000 = 1.665e-4; RMS sqrt(Σk²·1e-12 / 3000) with Σk² = 999·1000·1999/6.
TEST(Diff, PercentilesMeanRmsAndCountOver) {
  hdrc::Image in = grey(1000, 0.5), ref = grey(1000, 0.5), cand = grey(1000, 0.5);
  for (int k = 0; k < 1000; ++k) cand.px(k, 0)[1] = 0.5 + k * 1e-6;
  hdrc::Tolerance t = tol(1, 1e-6, 10);
  t.linear_abs = 5.005e-4;
  const auto s = hdrc::diff_images(in, ref, cand, kShaper, t);
  const auto& a = s[Metric::kLinearAbs];
  EXPECT_EQ(a.count, 3000u);
  EXPECT_NEAR(a.max, 999e-6, 1e-12);
  EXPECT_NEAR(a.p99, 969e-6, 1e-12);
  EXPECT_NEAR(a.p999, 996e-6, 1e-12);
  EXPECT_NEAR(a.mean, 1.665e-4, 1e-12);
  EXPECT_NEAR(a.rms, std::sqrt(999.0 * 1000 * 1999 / 6 * 1e-12 / 3000), 1e-12);
  EXPECT_EQ(a.over, 499u);  // k = 501 … 999
  EXPECT_NEAR(a.fraction_over, 499.0 / 3000, 1e-15);
  EXPECT_EQ(a.worst.x, 999);
  EXPECT_FALSE(hdrc::judge(s, t).pass);
}

// The statistics keep only the largest values a rank can need (issue 29: all of them were 8 bytes
// a value, 13 values a pixel); every figure must be the one a sort of all values gives, in every
// arrival order. 20 000 pixels, references in all six bands (2^-11 ... 32 x 100 nits: 0.05 to
// 3200 nits), G off by k·2^-30 (exact in double) with k = 7919 i mod 20000 a permutation of
// 0 … 19999 in scattered order; R and B exact. linear_abs: 60 000 values, 40 000 zeros and then
// k·2^-30 sorted, so sorted index j ≥ 40 000 holds (j − 40 000)·2^-30. Nearest rank q is index
// ceil(q·60000) − 1: p99 59 399 → 19 399, p99.9 59 939 → 19 939, 1 − 0.3 41 999 → 1999.
TEST(Diff, PercentilesOfManyValuesInScatteredOrderAreThoseOfASort) {
  const int n = 20000;
  const double step = std::ldexp(1.0, -30);
  const double levels[hdrc::kBandCount] = {
      std::ldexp(1.0, -11), std::ldexp(1.0, -7), 0.0625, 0.5, 4.0, 32.0};
  hdrc::Image in(n, 1), ref(n, 1), cand(n, 1);
  for (int i = 0; i < n; ++i) {
    const double v = levels[i % hdrc::kBandCount];
    const int k = static_cast<int>((7919LL * i) % n);
    for (int c = 0; c < 4; ++c)
      in.px(i, 0)[c] = ref.px(i, 0)[c] = cand.px(i, 0)[c] = c == 3 ? 1 : v;
    cand.px(i, 0)[1] = v + k * step;
  }
  hdrc::Tolerance t = tol(1, 1e-6, 10);
  t.linear_abs = 10000 * step;  // over: k = 10001 … 19999
  for (double fraction : {0.0, 0.3}) {
    t.allowed_fraction[static_cast<int>(Metric::kLinearAbs)] = fraction;
    const auto s = hdrc::diff_images(in, ref, cand, kShaper, t);
    const auto& a = s[Metric::kLinearAbs];
    EXPECT_EQ(a.count, 60000u);
    EXPECT_EQ(a.max, 19999 * step);
    EXPECT_EQ(a.p99, 19399 * step);
    EXPECT_EQ(a.p999, 19939 * step);
    EXPECT_EQ(a.at_allowed_fraction, fraction == 0 ? 19999 * step : 1999 * step);
    EXPECT_EQ(a.over, 9999u);
    EXPECT_EQ(a.worst.x, 2321);  // 7919 · 2321 = 18 379 999 ≡ 19999 (mod 20000)
    // Each band holds every sixth pixel; the bands' counts add up to the whole.
    size_t counted = 0;
    for (int b = 0; b < hdrc::kBandCount; ++b) {
      EXPECT_EQ(s.band[b][static_cast<int>(Metric::kLinearAbs)].count, 3u * ((n + 5 - b) / 6))
          << "band " << b;
      counted += s.band[b][static_cast<int>(Metric::kLinearAbs)].count;
    }
    EXPECT_EQ(counted, 60000u);
  }
}

TEST(Diff, RelativeErrorUsesTheFloor) {
  hdrc::Image in = grey(1, 0), ref = grey(1, 0), cand = grey(1, 0);
  cand.px(0, 0)[0] = 1e-7;
  auto s = hdrc::diff_images(in, ref, cand, kShaper, tol(1, 1e-6, 10));
  EXPECT_NEAR(s[Metric::kLinearRel].max, 0.1, 1e-12);
  // With no floor a difference over a zero reference is infinitely wrong, never NaN.
  s = hdrc::diff_images(in, ref, cand, kShaper, tol(1, 0, 10));
  EXPECT_TRUE(std::isinf(s[Metric::kLinearRel].max));
  EXPECT_FALSE(hdrc::judge(s, tol(1, 0, 10)).pass);
}

struct NonFiniteCase {
  double ref, cand;
  bool consistent;
};

// OCIO's GPU tests (GPUUnitTest.cpp) and idiff agree: NaN matches NaN, Inf matches Inf of the
// same sign, and any other pairing with a non-finite value is a difference.
TEST(Diff, NonFiniteConsistencyRules) {
  const NonFiniteCase cases[] = {
      {kNaN, kNaN, true},  {kInf, kInf, true}, {-kInf, -kInf, true}, {kInf, -kInf, false},
      {kNaN, kInf, false}, {kNaN, 0.0, false}, {1.0, kNaN, false},   {0.0, kInf, false},
  };
  for (const auto& c : cases) {
    hdrc::Image in = grey(3, 0.1), ref = grey(3, 0.1), cand = grey(3, 0.1);
    ref.px(1, 0)[2] = c.ref;
    cand.px(1, 0)[2] = c.cand;
    const auto s = hdrc::diff_images(in, ref, cand, ue_encoding("shaper", 0), tol(1e-3, 1e-6, 1));
    EXPECT_EQ(s.nonfinite.mismatch, c.consistent ? 0u : 1u) << c.ref << " vs " << c.cand;
    const auto v = hdrc::judge(s, tol(1e-3, 1e-6, 1));
    EXPECT_EQ(v.pass, c.consistent) << v.reason;
    if (!c.consistent) {
      EXPECT_EQ(s.nonfinite.first_mismatch.x, 1);
      EXPECT_EQ(s.nonfinite.first_mismatch.channel, 2);
      EXPECT_NE(v.reason.find("non-finite"), std::string::npos) << v.reason;
    }
  }
}

TEST(Diff, NonFiniteCensusCountsEachSide) {
  hdrc::Image in = grey(6, 0.1), ref = grey(6, 0.1), cand = grey(6, 0.1);
  ref.px(0, 0)[0] = kNaN;
  cand.px(0, 0)[0] = kNaN;  // consistent
  ref.px(1, 0)[1] = kInf;
  cand.px(1, 0)[1] = kInf;  // consistent
  ref.px(2, 0)[2] = -kInf;
  cand.px(2, 0)[2] = kInf;  // mismatch
  ref.px(3, 0)[0] = -0.5;
  cand.px(3, 0)[0] = -0.5;  // negative on both sides, finite
  cand.px(4, 0)[3] = kNaN;  // alpha: judged for consistency too
  const auto s = hdrc::diff_images(in, ref, cand, kShaper, tol(1, 1e-6, 10));
  EXPECT_EQ(s.nonfinite.reference.nan, 1u);
  EXPECT_EQ(s.nonfinite.reference.pos_inf, 1u);
  EXPECT_EQ(s.nonfinite.reference.neg_inf, 1u);
  EXPECT_EQ(s.nonfinite.reference.negative, 1u);
  EXPECT_EQ(s.nonfinite.candidate.nan, 2u);
  EXPECT_EQ(s.nonfinite.candidate.pos_inf, 2u);
  EXPECT_EQ(s.nonfinite.candidate.neg_inf, 0u);
  EXPECT_EQ(s.nonfinite.candidate.negative, 1u);
  EXPECT_EQ(s.nonfinite.consistent, 2u);
  EXPECT_EQ(s.nonfinite.mismatch, 2u);
  EXPECT_EQ(s.nonfinite.first_mismatch.x, 2);
  // Numeric metrics cover values finite on both sides only: 18 − 3.
  EXPECT_EQ(s.values, 15u);
}

// A non-finite mismatch is reported before (instead of) a numeric failure elsewhere.
TEST(Diff, NonFiniteMismatchIsReportedFirst) {
  hdrc::Image in = grey(2, 1), ref = grey(2, 1), cand = grey(2, 1);
  cand.px(0, 0)[0] = 2.0;   // numeric failure at x = 0
  cand.px(1, 0)[0] = kNaN;  // non-finite mismatch at x = 1
  const auto s = hdrc::diff_images(in, ref, cand, ue_encoding("shaper", 0), tol(1e-3, 1e-6, 1));
  const auto v = hdrc::judge(s, tol(1e-3, 1e-6, 1));
  EXPECT_FALSE(v.pass);
  EXPECT_EQ(v.reason.rfind("1 non-finite mismatch", 0), 0u) << v.reason;
}

// The mapping to nits per stage and device, against published values: sRGB 0.5 → 0.214041 (IEC
// 61966-2-1), PQ 0.5080784 → 100 nits, scRGB 1.0 → 80 nits.
TEST(Diff, OutputToNits) {
  EXPECT_EQ((ue_encoding("shaper", 0).to_nits(0.5)), 50.0);
  EXPECT_EQ((ue_encoding("linear_device", 8).to_nits(0.5)), 50.0);
  EXPECT_EQ((ue_encoding("linear_device", 7).to_nits(0.5)), 0.5);
  EXPECT_NEAR((ue_encoding("tonemap", 0).to_nits(0.5)), 21.4041, 1e-3);
  EXPECT_NEAR((ue_encoding("tonemap", 3).to_nits(0.5080784)), 100.0, 1e-4);
  EXPECT_EQ((ue_encoding("tonemap", 5).to_nits(1.0)), 80.0);
  EXPECT_NEAR((ue_encoding("combine_luts", 3).to_nits(0.5080784 / 1.05)), 100.0, 1e-4);
  EXPECT_NEAR((ue_encoding("tonemap", 2, 1 / 2.2).to_nits(0.5)), 100 * std::pow(0.5, 2.2), 1e-12);
}

// The gamut of each output, against ITU-R BT.2087-0 §2's BT.709 → BT.2020 matrix (first row
// 0.6274 0.3293 0.0433): scRGB is Rec.709; a device-3 output in gamut 2 is already BT.2020.
TEST(Diff, OutputGamutToRec2020) {
  hdrc::ParamBlock p;
  p.output_device = 5;
  const auto scrgb = hdrc::output_encoding(*hdrc::find_stage("tonemap"), p);
  EXPECT_NEAR(scrgb.to_rec2020(0, 0), 0.6274, 1e-4);
  EXPECT_NEAR(scrgb.to_rec2020(0, 1), 0.3293, 1e-4);
  EXPECT_NEAR(scrgb.to_rec2020(0, 2), 0.0433, 1e-4);
  EXPECT_EQ(scrgb.describe(), "scRGB x 80 nits, Rec.709");
  p.output_device = 3;
  p.output_gamut = 2;
  const auto pq = hdrc::output_encoding(*hdrc::find_stage("tonemap"), p);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(pq.to_rec2020.m[i], i % 4 == 0 ? 1 : 0, 1e-12);
  EXPECT_EQ(pq.describe(), "PQ EOTF, Rec2020_D65");
}

// ΔE_ITP (BT.2124). For a neutral colour L = M = S (BT.2100's LMS rows each sum to 4096/4096), so
// Ct = Cp = 0, I = PQ(Y) and ΔE_ITP = 720·|PQ(Y1) − PQ(Y2)|: PQ(100 nits) = 0.5080784 (published
// in ST 2084 tables), so 100 nits against the PQ signal 0.51 is 720·(0.51 − 0.5080784) = 1.38355.
// The chromatic pairs were computed independently with colorjs.io 0.5.2 (deltaE "ITP" of
// rec2100-pq colours, which goes through XYZ with Dolby's XYZ→LMS matrix rather than BT.2100's
// RGB→LMS integers): agreement to 1e-3 relative, the two matrices' rounding.
TEST(Diff, DeltaEItpAgainstIndependentValues) {
  namespace pq = hdrc::ref::st2084;
  auto de = [](hdrc::ref::Vec3 a, hdrc::ref::Vec3 b) {
    for (double& v : a) v = pq::nits_from_pq(v);
    for (double& v : b) v = pq::nits_from_pq(v);
    return hdrc::delta_e_itp(hdrc::ictcp_from_rec2020_nits(a), hdrc::ictcp_from_rec2020_nits(b));
  };
  const hdrc::ref::Vec3 grey = hdrc::ictcp_from_rec2020_nits({100, 100, 100});
  EXPECT_NEAR(grey[0], 0.5080784, 2e-7);
  EXPECT_NEAR(grey[1], 0, 1e-15);
  EXPECT_NEAR(grey[2], 0, 1e-15);
  EXPECT_NEAR(de({0.50807842, 0.50807842, 0.50807842}, {0.51, 0.51, 0.51}), 1.3835376, 2e-6);
  EXPECT_NEAR(de({0.58, 0.50, 0.40}, {0.581, 0.495, 0.41}), 7.572024233, 7.57e-3);
  EXPECT_NEAR(de({0.3, 0.6, 0.2}, {0.3, 0.6, 0.2005}), 0.04520359044, 4.5e-5);
  // Symmetric, zero for equal colours, and ≈ 1 JND is what a tolerance of 1 means.
  EXPECT_EQ(de({0.4, 0.5, 0.6}, {0.4, 0.5, 0.6}), 0.0);
  EXPECT_DOUBLE_EQ(de({0.58, 0.50, 0.40}, {0.581, 0.495, 0.41}),
                   de({0.581, 0.495, 0.41}, {0.58, 0.50, 0.40}));
}

TEST(Diff, DeltaEItpIsJudgedPerPixel) {
  // Shaper (scene-linear × 100 nits, working colour space sRGB): 1.0 → 100 nits grey.
  hdrc::ParamBlock p;
  p.wcs_is_srgb = 1;
  p.wcs_to_ap1 =
      hdrc::ref::standard::rgb_to_rgb(hdrc::ref::standard::kSrgb, hdrc::ref::standard::kAp1);
  const OutputEncoding enc = hdrc::output_encoding(*hdrc::find_stage("shaper"), p);
  hdrc::Image in = grey(2, 1.0), ref = grey(2, 1.0), cand = grey(2, 1.0);
  for (int c = 0; c < 3; ++c) cand.px(1, 0)[c] = 1.01;  // grey 100 → 101 nits
  hdrc::Tolerance t;
  t.delta_e_itp = 1.0;
  const auto s = hdrc::diff_images(in, ref, cand, enc, t);
  // 100 → 101 nits grey: 720·(PQ(101) − PQ(100)).
  namespace pq = hdrc::ref::st2084;
  const double want = 720 * (pq::pq_from_nits(101) - pq::pq_from_nits(100));
  EXPECT_EQ(s[Metric::kDeltaEItp].count, 2u);
  EXPECT_NEAR(s[Metric::kDeltaEItp].max, want, 1e-6);
  EXPECT_EQ(s[Metric::kDeltaEItp].worst.x, 1);
  t.delta_e_itp = want * 1.01;
  EXPECT_TRUE(hdrc::judge(s, t).pass);
  t.delta_e_itp = want * 0.99;
  const auto v = hdrc::judge(s, t);
  EXPECT_FALSE(v.pass);
  EXPECT_EQ(v.reason.rfind("delta_e_itp", 0), 0u) << v.reason;
}

TEST(Diff, LuminanceBands) {
  EXPECT_EQ(hdrc::band_of_nits(0.0999), 0);
  EXPECT_EQ(hdrc::band_of_nits(0.1), 1);
  EXPECT_EQ(hdrc::band_of_nits(9.99), 2);
  EXPECT_EQ(hdrc::band_of_nits(10), 3);
  EXPECT_EQ(hdrc::band_of_nits(999), 4);
  EXPECT_EQ(hdrc::band_of_nits(1000), 5);
  EXPECT_EQ(hdrc::band_of_nits(kNaN), 0);
  EXPECT_EQ(hdrc::band_of_nits(-5), 0);
  EXPECT_STREQ(hdrc::band_name(5), ">=1000");
}

// A planted defect in a bright pixel is reported with its pixel, channel, values and band, and
// the statistics of the other bands stay clean ("fails only above 1000 nits").
TEST(Diff, PlantedDefectIsLocatedWithItsBand) {
  hdrc::ParamBlock p;
  p.wcs_is_srgb = 1;
  p.wcs_to_ap1 =
      hdrc::ref::standard::rgb_to_rgb(hdrc::ref::standard::kSrgb, hdrc::ref::standard::kAp1);
  const OutputEncoding enc = hdrc::output_encoding(*hdrc::find_stage("shaper"), p);
  hdrc::Image in(5, 2), ref(5, 2), cand(5, 2);
  const double levels[5] = {0.0005, 0.005, 0.05, 0.5, 36.0};  // 0.05 … 3600 nits grey
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 5; ++x)
      for (int c = 0; c < 4; ++c) {
        const double v = c == 3 ? 1.0 : levels[x];
        in.px(x, y)[c] = ref.px(x, y)[c] = cand.px(x, y)[c] = v;
      }
  cand.px(4, 1)[2] = 36.0 * 1.001;
  const hdrc::Tolerance t = tol(2.5e-4, 1e-4, 0.025);
  const auto s = hdrc::diff_images(in, ref, cand, enc, t);
  const auto v = hdrc::judge(s, t);
  EXPECT_FALSE(v.pass);
  EXPECT_NE(v.reason.find("at (4, 1) B, >=1000 nits: input 36 reference 36 candidate 36.036"),
            std::string::npos)
      << v.reason;
  EXPECT_EQ(s.band_pixels[0], 2u);
  EXPECT_EQ(s.band_pixels[5], 2u);
  EXPECT_NEAR(s.band[5][static_cast<int>(Metric::kLinearRel)].max, 1e-3, 1e-12);
  for (int b = 0; b < 5; ++b) EXPECT_EQ(s.band[b][static_cast<int>(Metric::kLinearRel)].max, 0);
  EXPECT_EQ(s.worst.band, 5);
}

// The tolerance criteria combine: an allowed fraction over max with a hard cap, and a warn level.
TEST(Diff, AllowedFractionHardCapAndWarn) {
  hdrc::Image in = grey(1000, 0.5), ref = grey(1000, 0.5), cand = grey(1000, 0.5);
  cand.px(10, 0)[0] = 0.5 * 1.002;  // rel 2e-3: one value of 3000 (0.033 %)
  cand.px(20, 0)[1] = 0.5 * 1.0005;
  hdrc::Tolerance t = tol(1e-3, 1e-6, 100);
  const int rel = static_cast<int>(Metric::kLinearRel);
  EXPECT_FALSE(hdrc::judge(hdrc::diff_images(in, ref, cand, kShaper, t), t).pass);
  t.allowed_fraction[rel] = 0.0005;  // 0.05 % may be over
  t.hard[rel] = 5e-3;
  auto v = hdrc::judge(hdrc::diff_images(in, ref, cand, kShaper, t), t);
  EXPECT_TRUE(v.pass) << v.reason;
  t.hard[rel] = 1.5e-3;  // but nothing over the hard cap
  v = hdrc::judge(hdrc::diff_images(in, ref, cand, kShaper, t), t);
  EXPECT_FALSE(v.pass);
  EXPECT_NE(v.reason.find("hard cap"), std::string::npos) << v.reason;
  t.hard[rel] = 5e-3;
  t.allowed_fraction[rel] = 0.0002;  // 0.02 % < 0.033 %
  v = hdrc::judge(hdrc::diff_images(in, ref, cand, kShaper, t), t);
  EXPECT_FALSE(v.pass);
  EXPECT_NE(v.reason.find("1 of 3000 values over"), std::string::npos) << v.reason;
  t.allowed_fraction[rel] = 0.0005;
  t.warn[rel] = 1e-3;
  v = hdrc::judge(hdrc::diff_images(in, ref, cand, kShaper, t), t);
  EXPECT_TRUE(v.pass);
  ASSERT_EQ(v.warnings.size(), 1u);
  EXPECT_NE(v.warnings[0].find("linear_rel"), std::string::npos);
}

// Under 10 % of every max: could be tightened; NaN in a limit never passes.
TEST(Diff, CouldBeTightenedAndNaNLimits) {
  hdrc::Image in = grey(4, 0.5), ref = grey(4, 0.5), cand = grey(4, 0.5);
  cand.px(0, 0)[0] = 0.5 * (1 + 1e-5);
  const auto s = hdrc::diff_images(in, ref, cand, kShaper, tol(1e-3, 1e-6, 10));
  auto v = hdrc::judge(s, tol(1e-3, 1e-6, 10));
  EXPECT_TRUE(v.pass);
  EXPECT_TRUE(v.could_be_tightened);
  EXPECT_NEAR(v.budget_used, 1e-2, 1e-6);
  v = hdrc::judge(s, tol(5e-5, 1e-6, 10));
  EXPECT_TRUE(v.pass);
  EXPECT_FALSE(v.could_be_tightened);  // 20 % of 5e-5
  EXPECT_FALSE(hdrc::judge(s, tol(kNaN, 1e-6, 10)).pass);
}

// Issue 14: budget_used is the one figure for "how much of the tolerance": with an allowed
// fraction it is the value that fraction may exceed over max (not max/max, which read 1.91e+08 %
// for a passing dither case), it is over 1 for every failing case, and the passing reason line
// never claims "max <= limit" where max is over the limit.
TEST(Diff, BudgetUsedHonoursAllowedFractionAndFailures) {
  hdrc::Image in = grey(1000, 0.5), ref = grey(1000, 0.5), cand = grey(1000, 0.5);
  cand.px(10, 0)[0] = 0.5 * 1.002;  // one value of 3000 at rel 2e-3 (0.033 %)
  hdrc::Tolerance t = tol(1e-3, 1e-6, 100);
  const int rel = static_cast<int>(Metric::kLinearRel);
  t.allowed_fraction[rel] = 0.0005;  // 0.05 %: the allowed values may be over max
  t.hard[rel] = 5e-3;
  auto s = hdrc::diff_images(in, ref, cand, kShaper, t);
  auto v = hdrc::judge(s, t);
  ASSERT_TRUE(v.pass) << v.reason;
  // Nearest rank 1 − 0.0005 of 3000 values is an exact 0; max/hard = 2e-3/5e-3 = 0.4; the share
  // of the allowed fraction used is (1/3000)/0.0005 = 2/3, the largest (by hand); the PQ metric
  // (limit 100 codes) uses far less.
  EXPECT_NEAR(v.budget_used, 2.0 / 3.0, 1e-3);
  EXPECT_EQ(v.budget_used, hdrc::budget_used(s, t));
  EXPECT_EQ(v.reason.find("0.002 <= 0.001"), std::string::npos) << v.reason;
  EXPECT_NE(v.reason.find("% of values over 0.001"), std::string::npos) << v.reason;
  // Failing: over 1, by max / limit = 2e-3 / 1e-3 = 2 (by hand).
  hdrc::Tolerance strict = tol(1e-3, 1e-6, 100);
  s = hdrc::diff_images(in, ref, cand, kShaper, strict);
  v = hdrc::judge(s, strict);
  ASSERT_FALSE(v.pass);
  EXPECT_NEAR(v.budget_used, 2.0, 1e-3);
  // A non-finite mismatch uses all of it.
  cand.px(3, 0)[1] = kNaN;
  s = hdrc::diff_images(in, ref, cand, kShaper, strict);
  EXPECT_TRUE(std::isinf(hdrc::judge(s, strict).budget_used));
}

}  // namespace

// The sign-boundary rule (docs/diff-metrics.md): where a NaN marks the power-law encoding of a
// negative value (CombineLUTs' PQ texels of device 3 here), NaN against a value within float32
// noise of zero (|nits| < 2^-20 x the pixel's largest |nits|) is consistent and counted; a value
// above that noise is a mismatch, and so is NaN vs 0 where NaN marks nothing (the shaper).
TEST(Diff, SignBoundaryNaNAgainstNoiseOfZero) {
  const OutputEncoding lut3 = ue_encoding("combine_luts", 3);
  ASSERT_TRUE(lut3.nan_marks_negative());
  ASSERT_FALSE((ue_encoding("shaper", 3).nan_marks_negative()));
  ASSERT_FALSE((ue_encoding("combine_luts", 0).nan_marks_negative()));
  // 0.5 as a stored texel: PQ 0.525 is ~112 nits, so the bound is ~1.1e-4 nits. PQ 0.000196 is
  // 2.5e-6 nits (inside); PQ 0.05 is 0.06 nits (outside).
  for (const auto& [cand, boundary] : {std::pair{0.000196, true}, std::pair{0.05, false}}) {
    for (bool nan_in_reference : {true, false}) {
      hdrc::Image in = grey(3, 0.5), ref = grey(3, 0.5), cnd = grey(3, 0.5);
      (nan_in_reference ? ref : cnd).px(1, 0)[2] = kNaN;
      (nan_in_reference ? cnd : ref).px(1, 0)[2] = cand;
      const auto s = hdrc::diff_images(in, ref, cnd, lut3, tol(1, 1e-6, 100));
      EXPECT_EQ(s.nonfinite.sign_boundary, boundary ? 1u : 0u) << cand;
      EXPECT_EQ(s.nonfinite.mismatch, boundary ? 0u : 1u) << cand;
      EXPECT_EQ(s.values, 8u);  // the pair is in no numeric metric
      const auto v = hdrc::judge(s, tol(1, 1e-6, 100));
      EXPECT_EQ(v.pass, boundary) << v.reason;
      if (boundary) {
        EXPECT_EQ(s.nonfinite.first_sign_boundary.x, 1);
        EXPECT_NE(v.reason.find("sign boundary"), std::string::npos) << v.reason;
      }
    }
  }
  // A NaN in a pixel whose every other value is zero has no noise to hide in: a mismatch.
  hdrc::Image in = grey(1, 0.0), ref = grey(1, 0.0), cnd = grey(1, 0.0);
  ref.px(0, 0)[0] = kNaN;
  EXPECT_EQ(hdrc::diff_images(in, ref, cnd, lut3, tol(1, 1e-6, 100)).nonfinite.mismatch, 1u);
}

// The PQ metric's noise floor: a channel that is zero in a bright pixel carries float32 noise of
// ~1e-6 of the pixel; PQ, unbounded in slope at 0, must not read that as codes. The floor is
// relative: in a dark pixel the same values are far apart, and a real error in the bright
// pixel's small channel above the floor is still measured.
TEST(Diff, PqNoiseFloorIsRelativeToThePixel) {
  const OutputEncoding linear7 = ue_encoding("linear_device", 7);  // values are nits
  auto pq10 = [&](double big, double r, double c) {
    hdrc::Image in = grey(1, 0.0), ref = grey(1, 0.0), cnd = grey(1, 0.0);
    ref.px(0, 0)[1] = cnd.px(0, 0)[1] = big;
    ref.px(0, 0)[2] = r;
    cnd.px(0, 0)[2] = c;
    const auto s = hdrc::diff_images(in, ref, cnd, linear7, tol(1, 1e-6, 100));
    return s[hdrc::Metric::kPqCode10].max;
  };
  // Measured on lavapipe (tonemap/linear_dev7/gamut0_log_ramp): 6.9e-9 vs 1.9e-6 nits beside
  // 83.5 nits: 0.16 codes without the floor (f = 83.5 * 2^-20 = 8.0e-5 nits), 0 with it.
  EXPECT_EQ(pq10(83.5, 6.91e-9, 1.91e-6), 0.0);
  EXPECT_EQ(pq10(83.5, -1e-9, 3e-5), 0.0);
  // Without a bright channel the same pair is measured (f = 1.9e-6 nits here): PQ's full slope.
  EXPECT_GT(pq10(0.0, 6.91e-9, 1.91e-6), 0.1);
  // A real error above the floor is measured against it: 1e-3 vs 2e-3 nits beside 83.5 nits.
  const double f = 83.5 * hdrc::kSignBoundaryNoise;
  auto pq = [](double nits) { return hdrc::ref::st2084::pq_from_nits(nits); };
  const double want = (pq(2e-3) - pq(1e-3)) * 1023.0;
  EXPECT_NEAR(pq10(83.5, 1e-3, 2e-3), want, 1e-12);
  EXPECT_NEAR(pq10(83.5, 0.0, 2e-3), (pq(2e-3) - pq(f)) * 1023.0, 1e-12);
}

// The near-black floor (docs/tolerances.md, "The near-black floor"): X is where the linear
// criterion's absolute bound below rel_floor, a = linear_rel x rel_floor, moves PQ by the PQ
// limit. For UE's FilmToneMap in `operators` (cases/tolerance_overlays.json: linear_rel 2.5e-4,
// rel_floor 1e-3 of 100 nits, pq_code10 0.012) that is 0.0407 nits. The pixel is the one a
// second float32 evaluation (examples/float32_candidate.cpp) met in operators/operators/
// operator5_log_ramp: 0.0308 PQ codes without the floor, 0 with it; a dark channel that the
// linear criterion or ΔE_ITP sees as wrong keeps PQ's full judgement.
TEST(Diff, NearBlackFloorIsWhereLinearAndPqLimitsMeet) {
  auto pq = [](double nits) { return hdrc::ref::st2084::pq_from_nits(nits); };
  const double a = 2.5e-4 * 1e-3 * 100.0, limit = 0.012;
  double lo = 1e-9, hi = 1e4;  // 1023 (PQ(x + a) - PQ(x)) falls with x: bisect for the limit
  for (int i = 0; i < 200; ++i) {
    const double mid = std::sqrt(lo * hi);
    ((pq(mid + a) - pq(mid)) * 1023.0 > limit ? lo : hi) = mid;
  }
  EXPECT_NEAR(hi, 0.0407, 0.0001);

  const OutputEncoding linear7 = ue_encoding("linear_device", 7);  // values are nits
  hdrc::Tolerance t = tol(2.5e-4, 0.1, limit);                     // rel_floor 1e-3 x 100 nits
  t.delta_e_itp = 3e-4;
  hdrc::Image in = grey(1, 0.0), ref = grey(1, 0.0), cnd = grey(1, 0.0);
  const double r[3] = {4.29910846, 1.56323576e-4, 88.855766};
  const double c[3] = {4.29908819, 1.60053185e-4, 88.8557792};
  for (int ch = 0; ch < 3; ++ch) {
    ref.px(0, 0)[ch] = r[ch];
    cnd.px(0, 0)[ch] = c[ch];
  }
  auto stats = [&](const hdrc::Tolerance& with) {
    return hdrc::diff_images(in, ref, cnd, linear7, with);
  };
  const auto without = stats(t);
  EXPECT_NEAR(without[Metric::kPqCode10].max, 0.0308, 0.0005);
  EXPECT_LT(without[Metric::kDeltaEItp].max, 3e-4);
  EXPECT_LT(without[Metric::kLinearRel].max, 2.5e-4);
  t.pq_near_black = 0.0407;
  EXPECT_TRUE(hdrc::judge(stats(t), t).pass);
  EXPECT_LT(stats(t)[Metric::kPqCode10].max, 1e-3);  // the 4.3-nit channel's own codes
  // A dark channel off by 10x the linear bound fails linear_rel: no floor, PQ judges it too.
  cnd.px(0, 0)[1] = r[1] + 2.5e-4;
  const auto wrong = stats(t);
  EXPECT_GT(wrong[Metric::kLinearRel].max, 2.5e-4);
  EXPECT_GT(wrong[Metric::kPqCode10].max, 1.0);
  // Within the linear bound but a colour ΔE_ITP sees: the floor does not apply either.
  hdrc::Tolerance strict_de = t;
  strict_de.delta_e_itp = 1e-6;
  cnd.px(0, 0)[1] = c[1];
  EXPECT_NEAR(stats(strict_de)[Metric::kPqCode10].max, 0.0308, 0.0005);
}

// A case that compares no finite value cannot fail, so it must not pass: an ERROR naming the
// count. A case that declares it pins non-finite behaviour is judged by the census instead, and
// is an ERROR when there is nothing non-finite to pin.
TEST(Diff, NothingComparedIsAnErrorUnlessTheCasePinsNonFinite) {
  hdrc::Image in = grey(3, 0.1), ref = grey(3, kNaN), cand = grey(3, kNaN);
  const auto s = hdrc::diff_images(in, ref, cand, kShaper, tol(1e-3, 1e-6, 1));
  ASSERT_EQ(s.values, 0u);
  auto v = hdrc::judge(s, tol(1e-3, 1e-6, 1));
  EXPECT_FALSE(v.pass);
  EXPECT_TRUE(v.error);
  EXPECT_EQ(v.reason, "nothing compared: 9 of 9 values are non-finite on both sides");
  v = hdrc::judge(s, tol(1e-3, 1e-6, 1), /*pins_nonfinite=*/true);
  EXPECT_TRUE(v.pass) << v.reason;
  EXPECT_FALSE(v.could_be_tightened);
  EXPECT_EQ(v.reason.rfind("non-finite census: 9 consistent", 0), 0u) << v.reason;
  // Pinned, but a candidate that turns one NaN into a number fails on the census.
  cand.px(1, 0)[0] = 0.25;
  v = hdrc::judge(hdrc::diff_images(in, ref, cand, kShaper, tol(1e-3, 1e-6, 1)), tol(1e-3, 1e-6, 1),
                  true);
  EXPECT_FALSE(v.pass);
  EXPECT_FALSE(v.error);
  // Pinned, with nothing non-finite: an ERROR, not a pass.
  const hdrc::Image fine = grey(3, 0.1);
  v = hdrc::judge(hdrc::diff_images(in, fine, fine, kShaper, tol(1e-3, 1e-6, 1)),
                  tol(1e-3, 1e-6, 1), true);
  EXPECT_TRUE(v.error);
  EXPECT_FALSE(v.pass);
  // One finite value compared: judged as usual.
  hdrc::Image ref1 = grey(3, kNaN), cand1 = grey(3, kNaN);
  ref1.px(2, 0)[1] = cand1.px(2, 0)[1] = 0.5;
  v = hdrc::judge(hdrc::diff_images(in, ref1, cand1, kShaper, tol(1e-3, 1e-6, 1)),
                  tol(1e-3, 1e-6, 1));
  EXPECT_TRUE(v.pass) << v.reason;
}

// "Could be tightened" weighs every criterion: with an allowed fraction, the share of it used and
// the hard cap count too, so exact-but-for-a-few-flips values are not "under 10 %".
TEST(Diff, CouldBeTightenedCountsFractionAndHardCap) {
  hdrc::Image in = grey(1000, 0.5), ref = grey(1000, 0.5), cand = grey(1000, 0.5);
  cand.px(10, 0)[0] = 0.5 + 9e-4;  // one value of 3000 off by 9e-4, the rest exact
  hdrc::Tolerance t;
  const int abs = static_cast<int>(Metric::kLinearAbs);
  t.linear_abs = 2e-5;
  t.allowed_fraction[abs] = 0.01;
  t.hard[abs] = kInf;  // no cap: the share of the fraction decides
  auto s = hdrc::diff_images(in, ref, cand, kShaper, t);
  auto v = hdrc::judge(s, t);
  ASSERT_TRUE(v.pass) << v.reason;
  EXPECT_TRUE(v.could_be_tightened);  // 1/3000 of 1 %: 3.3 %
  EXPECT_NEAR(v.budget_used, (1.0 / 3000) / 0.01, 1e-12);
  t.allowed_fraction[abs] = 0.002;  // 1/3000 of 0.2 %: 17 %
  t.hard[abs] = 1e-2;
  s = hdrc::diff_images(in, ref, cand, kShaper, t);
  v = hdrc::judge(s, t);
  EXPECT_FALSE(v.could_be_tightened);
  t.allowed_fraction[abs] = 0.01;
  t.hard[abs] = 9.8e-4;  // the flip uses 92 % of the cap
  s = hdrc::diff_images(in, ref, cand, kShaper, t);
  v = hdrc::judge(s, t);
  EXPECT_FALSE(v.could_be_tightened);
  EXPECT_NEAR(v.budget_used, 9e-4 / 9.8e-4, 1e-6);
}

// Admissible ranges (core/image.h): a candidate anywhere in the range is judged against itself,
// one outside against the nearest bound, NaN only where admitted; a planted error beyond the
// range still fails.
TEST(Diff, AdmissibleRangeJudgesAgainstTheNearestAdmissibleValue) {
  hdrc::Image in = grey(3, 0.5), ref = grey(3, 0.5), cand = grey(3, 0.5);
  hdrc::AdmissibleRange a;
  a.pixel = 1;
  a.lo = {0.5, 0.0, 0.5, 1.0};
  a.hi = {0.5, 0.1, 0.5, 1.0};
  a.nan_ok = 1u << 2;
  ref.px(1, 0)[1] = 0.05;
  ref.admissible = {a};
  cand.px(1, 0)[1] = 0.0;   // in the range: exact
  cand.px(1, 0)[2] = kNaN;  // admitted
  auto s = hdrc::diff_images(in, ref, cand, kShaper, tol(1e-6, 1e-6, 10));
  EXPECT_EQ(s.admissible, 2u);
  EXPECT_EQ(s[Metric::kLinearAbs].max, 0.0);
  EXPECT_EQ(s.nonfinite.mismatch, 0u);
  EXPECT_TRUE(hdrc::judge(s, tol(1e-6, 1e-6, 10)).pass);
  EXPECT_NE(hdrc::judge(s, tol(1e-6, 1e-6, 10)).reason.find("admissible range"), std::string::npos);
  // 0.3 is 0.2 beyond the range's top: judged against 0.1.
  cand.px(1, 0)[1] = 0.3;
  cand.px(1, 0)[2] = 0.5;
  s = hdrc::diff_images(in, ref, cand, kShaper, tol(1e-6, 1e-6, 10));
  EXPECT_NEAR(s[Metric::kLinearAbs].max, 0.2, 1e-15);
  EXPECT_FALSE(hdrc::judge(s, tol(1e-6, 1e-6, 10)).pass);
  // NaN where the range does not admit it is a mismatch; so is any value on another pixel.
  cand.px(1, 0)[1] = 0.05;
  cand.px(1, 0)[0] = kNaN;
  s = hdrc::diff_images(in, ref, cand, kShaper, tol(1e-6, 1e-6, 10));
  EXPECT_EQ(s.nonfinite.mismatch, 1u);
  cand = grey(3, 0.5);
  cand.px(1, 0)[1] = 0.05;
  cand.px(2, 0)[1] = 0.05;
  s = hdrc::diff_images(in, ref, cand, kShaper, tol(1e-6, 1e-6, 10));
  EXPECT_FALSE(hdrc::judge(s, tol(1e-6, 1e-6, 10)).pass);
  EXPECT_EQ(s[Metric::kLinearAbs].worst.x, 2);
}
