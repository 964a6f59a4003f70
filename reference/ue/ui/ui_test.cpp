// Tests of the HDR UI composite reference against numbers from outside this code: published sRGB /
// BT.709 values, the Machado (2010) matrices as colour-science publishes them, docs/spec/ue55.md
// §13 goldens, and composite values derived by hand (a Python re-derivation from the
// docs/spec/ue55.md §2.1 literals, shown in each test). Every measured residual is recorded as a
// test property (--gtest_output=xml).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "color/gamma_correction.h"
#include "color/st2084.h"
#include "reference/ue/ui/color_deficiency.h"
#include "reference/ue/ui/composite.h"

namespace hdrc::ref::ui {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr MinNormalClamp kOn = MinNormalClamp::kOn;
constexpr MinNormalClamp kOff = MinNormalClamp::kOff;

void record(const std::string& name, double residual) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3e", residual);
  ::testing::Test::RecordProperty(name, text);
}

// max |a − b| over the channels; NaN anywhere gives NaN so that !(err <= tol) fails.
double max_err(const Vec3& a, const Vec3& b) {
  double e = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double d = std::fabs(a[c] - b[c]);
    if (std::isnan(d)) return kNaN;
    e = std::fmax(e, d);
  }
  return e;
}

Vec3 rgb(const Vec4& v) {
  return {v[0], v[1], v[2]};
}

bool same_bits(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) || (a == b && std::signbit(a) == std::signbit(b));
}

// ---------------------------------------------------------------------------------------------
// gamma_correction.h

TEST(GammaCorrection, SrgbDecodeMatchesIec61966Values) {
  // IEC 61966-2-1 decode ((V + 0.055) / 1.055)^2.4, evaluated by hand to 12 digits; the usual
  // published 6-digit value for 0.5 is 0.214041. UE's 0.0521327 truncates 0.055/1.055 by
  // 1.4e-9, which moves the result by at most 3.4e-9 (at V = 1); tolerance 5e-9.
  struct Spot {
    double v, expected;
  };
  const Spot spots[] = {
      {0.2, 0.033104766571}, {0.5, 0.214041140482}, {0.8, 0.603827338855}, {1.0, 1.0}};
  double worst = 0.0;
  for (const Spot& s : spots) {
    const double err = std::fabs(srgb_to_linear(s.v) - s.expected);
    EXPECT_LE(err, 5e-9) << "sRGB " << s.v;
    worst = std::fmax(worst, err);
  }
  record("srgb_decode_max_residual", worst);         // measured 3.41e-9 (at V = 1)
  EXPECT_NEAR(srgb_to_linear(0.5), 0.214041, 5e-7);  // the 6-digit published value
}

TEST(GammaCorrection, SrgbDecodeBoundaryAt004045) {
  // IEC 61966-2-1: the segments meet at V = 0.04045, L = 0.0031308. UE tests c > 0.04045, so
  // 0.04045 itself takes the linear segment: 0.04045 / 12.92 = 3.130804954e-3 (hand).
  EXPECT_NEAR(srgb_to_linear(0.04045), 3.130804953560e-3, 1e-15);
  // Just above, the power segment: 3.130807165e-3 at 0.04045 (hand); the step between the
  // segments is 2.2e-9, both within 1e-7 of the published 0.0031308.
  const double above = srgb_to_linear(std::nextafter(0.04045, 1.0));
  EXPECT_NEAR(above, 3.130807164986e-3, 1e-14);
  EXPECT_NEAR(srgb_to_linear(0.04045), 0.0031308, 1e-7);
  EXPECT_NEAR(above, 0.0031308, 1e-7);
  record("srgb_boundary_step", above - srgb_to_linear(0.04045));  // measured 2.21e-9
}

TEST(GammaCorrection, MinNormalClampSwitch) {
  // D3: with the clamp every input below 6.10352e-5 (NaN and negatives included, maxNum) decodes
  // to 6.10352e-5 / 12.92 = 4.724086687e-6; without it 0 stays 0, negatives stay linear, NaN
  // stays NaN.
  const double floor_value = 4.724086687306502e-6;  // 6.10352e-5 / 12.92 (hand)
  for (double x : {0.0, -0.0, -0.1, -kInf, kNaN, 1e-7}) {
    EXPECT_NEAR(srgb_to_linear(x, kOn), floor_value, 1e-20) << x;
    EXPECT_NEAR(srgb_to_linear(x), floor_value, 1e-20) << "default is ON: " << x;
  }
  EXPECT_EQ(srgb_to_linear(0.0, kOff), 0.0);
  EXPECT_NEAR(srgb_to_linear(-0.1, kOff), -0.00773993808049536, 1e-17);
  EXPECT_TRUE(std::isnan(srgb_to_linear(kNaN, kOff)));
  EXPECT_EQ(srgb_to_linear(kInf, kOff), kInf);
  // Rec.709 black: 6.10352e-5 / 4.5 decoded, 4.5 · 6.10352e-5 = 2.74658e-4 encoded (D3 table).
  EXPECT_NEAR(rec709_to_linear(0.0, kOn), 1.356337777777778e-5, 1e-20);
  EXPECT_EQ(rec709_to_linear(0.0, kOff), 0.0);
  EXPECT_NEAR(linear_to_rec709_branchless(0.0, kOn), 2.74658e-4, 1e-9);
  EXPECT_EQ(linear_to_rec709_branchless(0.0, kOff), 0.0);
  // LinearToSrgbBranchless black: 12.92 · 6.10352e-5 = 7.88575e-4 (D3 table: 7.886e-4).
  EXPECT_NEAR(linear_to_srgb_branchless(0.0, kOn), 7.885748e-4, 1e-9);
  EXPECT_EQ(linear_to_srgb_branchless(0.0, kOff), 0.0);
  // The branching encoder never clamps: 0 → 0, −1 → −12.92, NaN → NaN.
  EXPECT_EQ(linear_to_srgb(0.0), 0.0);
  EXPECT_EQ(linear_to_srgb(-1.0), -12.92);
  EXPECT_TRUE(std::isnan(linear_to_srgb(kNaN)));
  // maxNum/minNum: the branchless encoder without clamp turns NaN into min(NaN, 0.04045…) =
  // 1.055 · 0.00313067^(1/2.4) − 0.055 = 0.0404482561 (docs/spec/ue55.md §13 value for 0.00313067).
  EXPECT_NEAR(linear_to_srgb_branchless(kNaN, kOff), 0.0404482561, 1e-10);
}

TEST(GammaCorrection, Rec709DecodeBreakpointAndSpecGoldens) {
  // BT.709: V = 0.081 ↔ L = 0.018; UE tests c > 0.081, so 0.081 decodes linearly to 0.018.
  EXPECT_NEAR(rec709_to_linear(0.081), 0.018, 1e-17);
  // The power segment just above gives ((0.081 + 0.099) / 1.099)^(1/0.45) = 0.017945023 (hand):
  // BT.709's rounded constants leave a 3e-4 relative step at the breakpoint.
  EXPECT_NEAR(rec709_to_linear(std::nextafter(0.081, 1.0)), 0.017945023367, 1e-11);
  // Spec §13 goldens for the encoders (hand-computed there; re-derived: identical to 10 digits).
  EXPECT_NEAR(linear_to_rec709_branchless(0.18), 0.4090077289, 1e-10);
  EXPECT_NEAR(linear_to_rec709_branchless(0.5), 0.7055150899, 1e-10);
  EXPECT_NEAR(linear_to_srgb(0.18), 0.4613561295, 1e-10);
  EXPECT_NEAR(linear_to_srgb(0.5), 0.7353569831, 1e-10);
  EXPECT_NEAR(linear_to_srgb(0.00313067), 0.0404482561, 1e-10);
  EXPECT_NEAR(linear_to_srgb_branchless(0.18), 0.4613561295, 1e-10);
}

TEST(GammaCorrection, RoundTrips) {
  // Decode(encode(x)), clamp off. UE's encoder/decoder pairs are not exact inverses, and the
  // mismatch is concentrated in a band just above each breakpoint (hand analysis):
  //  * sRGB: the encoder switches to the power segment at 0.00313067, the decoder at V > 0.04045,
  //    which the encoder reaches only at x = 0.00313081; in between a power-encoded value is
  //    decoded linearly: worst 7.4e-7 relative (hand, at x = 0.0031308).
  //  * Rec.709: at 0.018 BT.709's power segment gives 0.08124 > 4.5 · 0.018, so the branchless
  //    encoder's min() keeps the linear segment up to x = 0.0199989 (V = 0.089995) while the
  //    decoder switches at V > 0.081: worst 3.05e-3 relative just above 0.018 (hand).
  // Elsewhere only UE's 0.0521327 (vs 0.055 / 1.055 = 0.05213270142) remains: a 1.42e-9 shift
  // of the base, largest relative to the smallest base (0.0905 at V = 0.04045): 2.4 · 1.42e-9 /
  // 0.0905 = 3.77e-8 relative (hand); tolerance 4e-8.
  struct Pair {
    const char* name;
    double (*round_trip)(double);
    double band_lo, band_hi, band_tol;
  };
  const Pair pairs[] = {
      {"srgb", [](double x) { return srgb_to_linear(linear_to_srgb(x), kOff); }, 0.00313067,
       0.00313082, 8e-7},
      {"srgb_branchless",
       [](double x) { return srgb_to_linear(linear_to_srgb_branchless(x, kOff), kOff); },
       0.00313067, 0.00313082, 8e-7},
      {"rec709",
       [](double x) { return rec709_to_linear(linear_to_rec709_branchless(x, kOff), kOff); }, 0.018,
       0.0200, 3.1e-3},
  };
  for (const Pair& pair : pairs) {
    double outside = 0.0, inside = 0.0;
    for (int i = 0; i <= 4000; ++i) {  // log-spaced over [1e-4, 1]
      const double x = std::pow(10.0, -4.0 + 4.0 * i / 4000.0);
      const double rel = std::fabs(pair.round_trip(x) - x) / x;
      if (x < pair.band_lo || x > pair.band_hi) outside = std::fmax(outside, rel);
    }
    for (int i = 0; i <= 20000; ++i) {  // dense inside the band
      const double x = pair.band_lo + (pair.band_hi - pair.band_lo) * i / 20000.0;
      inside = std::fmax(inside, std::fabs(pair.round_trip(x) - x) / x);
    }
    EXPECT_LE(outside, 4e-8) << pair.name;
    EXPECT_LE(inside, pair.band_tol) << pair.name;
    record(std::string(pair.name) + "_roundtrip_outside_band_max_rel", outside);
    record(std::string(pair.name) + "_roundtrip_band_max_rel", inside);
  }
}

// ---------------------------------------------------------------------------------------------
// color_deficiency.h

// Machado (2010) Φ_CVD for severity 1.0 and 0.5 as colour-science publishes them
// (colour/blindness/datasets/machado2010.py, CVD_MATRICES_MACHADO2010), typed in here
// independently of the table in color_deficiency.cpp. UE severity s ↔ Machado severity s / 10.
struct Published {
  CvdType type;
  int severity;
  Mat3 m;
};
const Published kPublished[] = {
    {CvdType::kProtanope,
     10,
     {{0.152286, 1.052583, -0.204868, 0.114503, 0.786281, 0.099216, -0.003882, -0.048116,
       1.051998}}},
    {CvdType::kDeuteranope,
     10,
     {{0.367322, 0.860646, -0.227968, 0.280085, 0.672501, 0.047413, -0.011820, 0.042940,
       0.968881}}},
    {CvdType::kTritanope,
     10,
     {{1.255528, -0.076749, -0.178779, -0.078411, 0.930809, 0.147602, 0.004733, 0.691367,
       0.303900}}},
    {CvdType::kProtanope,
     5,
     {{0.458064, 0.679578, -0.137642, 0.092785, 0.846313, 0.060902, -0.007494, -0.016807,
       1.024301}}},
    {CvdType::kDeuteranope,
     5,
     {{0.547494, 0.607765, -0.155259, 0.181692, 0.781742, 0.036566, -0.010410, 0.027275,
       0.983136}}},
    {CvdType::kTritanope,
     5,
     {{1.017277, 0.027029, -0.044306, -0.006113, 0.958479, 0.047634, 0.006379, 0.248708,
       0.744913}}},
    // Spec §8 quotes protanomaly severity 1 row 0 = (0.856167, 0.182038, −0.038205).
    {CvdType::kProtanope,
     1,
     {{0.856167, 0.182038, -0.038205, 0.029342, 0.955115, 0.015544, -0.002880, -0.001563,
       1.004443}}},
};

TEST(ColorDeficiency, TablesMatchMachado2010Published) {
  for (const Published& p : kPublished) {
    const Mat3& m = machado_matrix(p.type, p.severity);
    for (int i = 0; i < 9; ++i) {
      EXPECT_EQ(m.m[i], p.m.m[i]) << "type " << static_cast<int>(p.type) << " severity "
                                  << p.severity << " entry " << i;
    }
  }
}

TEST(ColorDeficiency, SimulationIsMatrixTimesColumnVector) {
  // Simulation of a basis vector returns the matrix column: rows are output channels (HLSL
  // float3x3(row0, row1, row2), mul(M, v)). Protanomaly 1.0, input green: column 1 of the
  // published matrix = (1.052583, 0.786281, −0.048116); row 0 appears as out.r for e0, e1, e2.
  const Vec3 g = color_deficiency({0, 1, 0}, CvdType::kProtanope, 10, 0, 0);
  EXPECT_EQ(g[0], 1.052583);
  EXPECT_EQ(g[1], 0.786281);
  EXPECT_EQ(g[2], -0.048116);
  EXPECT_EQ(color_deficiency({1, 0, 0}, CvdType::kProtanope, 10, 0, 0)[0], 0.152286);
  EXPECT_EQ(color_deficiency({0, 0, 1}, CvdType::kProtanope, 10, 0, 0)[0], -0.204868);
}

TEST(ColorDeficiency, CorrectionByHand) {
  // Protanope severity 10, rgb (1, 0, 0): deficient = column 0 = (0.152286, 0.114503,
  // −0.003882); error = (0.847714, −0.114503, 0.003882); RED_BLIND · error =
  // (0.5·0.847714 − 0.114503 + 0.003882, 0.5·0.737093, 0.5·0.737093) = (0.313236, 0.3685465,
  // 0.3685465); out = rgb + that. Simulated with the deficiency: M · out (hand).
  const Vec3 corrected = color_deficiency({1, 0, 0}, CvdType::kProtanope, 10, 1, 0);
  const Vec3 seen = color_deficiency({1, 0, 0}, CvdType::kProtanope, 10, 1, 1);
  const double e1 = max_err(corrected, {1.313236, 0.3685465, 0.3685465});
  const double e2 = max_err(seen, {0.5124098537435, 0.4767162818185, 0.364879215361});
  EXPECT_LE(e1, 1e-15);
  EXPECT_LE(e2, 1e-15);
  // Deuteranope severity 5 on (0.2, 0.5, 0.9): simulation, correction (GREEN_BLIND), both (hand).
  const Vec3 in{0.2, 0.5, 0.9};
  const double e3 = max_err(color_deficiency(in, CvdType::kDeuteranope, 5, 0, 0),
                            {0.2736482, 0.4601188, 0.8963779});
  const double e4 = max_err(color_deficiency(in, CvdType::kDeuteranope, 5, 1, 0),
                            {0.16498695, 0.4299739, 0.86498695});
  const double e5 = max_err(color_deficiency(in, CvdType::kDeuteranope, 5, 1, 1),
                            {0.21735544366675, 0.3977345782669, 0.8604098340482});
  EXPECT_LE(e3, 1e-15);
  EXPECT_LE(e4, 1e-15);
  EXPECT_LE(e5, 1e-15);
  record("cvd_hand_max_residual", std::fmax(std::fmax(e1, e2), std::fmax(e3, std::fmax(e4, e5))));
  // The simulate flag only acts with correction on (UE nests it inside bCorrectDeficiency == 1).
  EXPECT_EQ(color_deficiency(in, CvdType::kDeuteranope, 5, 0, 1),
            color_deficiency(in, CvdType::kDeuteranope, 5, 0, 0));
}

TEST(ColorDeficiency, SeverityIsTruncated) {
  // HLSL (int)Severity: 5.9 → 5, 0.99 → 0; outside 0..10 UE reads past its table → NaN here.
  const Vec3 in{0.3, 0.6, 0.1};
  EXPECT_EQ(color_deficiency(in, CvdType::kTritanope, 5.9, 1, 1),
            color_deficiency(in, CvdType::kTritanope, 5, 1, 1));
  EXPECT_EQ(color_deficiency(in, CvdType::kTritanope, 0.99, 0, 0), in);
  for (double bad : {-1.0, 11.0, 11.5, kNaN, kInf}) {
    EXPECT_TRUE(std::isnan(color_deficiency(in, CvdType::kTritanope, bad, 0, 0)[0])) << bad;
  }
}

TEST(ColorDeficiency, SeverityZeroAndNormalVisionAreIdentity) {
  const std::vector<Vec3> inputs = {
      {0, 0, 0}, {1, 1, 1}, {0.25, 0.5, 0.75}, {-0.2, 1.7, 30.0}, {1e-30, 65504, -0.0}};
  const CvdType types[] = {CvdType::kNormalVision, CvdType::kDeuteranope, CvdType::kProtanope,
                           CvdType::kTritanope};
  for (const Vec3& in : inputs) {
    for (CvdType t : types) {
      for (double correct : {0.0, 1.0}) {
        for (double sim : {0.0, 1.0}) {
          // Severity 0 (identity table) for every type and flag, finite inputs: exact.
          const Vec3 s0 = color_deficiency(in, t, 0, correct, sim);
          for (int c = 0; c < 3; ++c) EXPECT_EQ(s0[c], in[c]) << "type " << static_cast<int>(t);
        }
      }
    }
    // NormalVision at every severity and flag: exact, non-finite inputs included.
    for (int s = 0; s <= 10; ++s) {
      for (double correct : {0.0, 1.0}) {
        for (double sim : {0.0, 1.0}) {
          const Vec3 out = color_deficiency(in, CvdType::kNormalVision, s, correct, sim);
          for (int c = 0; c < 3; ++c) EXPECT_EQ(out[c], in[c]);
        }
      }
    }
  }
  const Vec3 nan_in{kNaN, 0.5, kInf};
  const Vec3 nv = color_deficiency(nan_in, CvdType::kNormalVision, 7, 1, 1);
  EXPECT_TRUE(std::isnan(nv[0]));
  EXPECT_EQ(nv[1], 0.5);
  EXPECT_EQ(nv[2], kInf);
  // Documented: inside ColorDeficiency the severity-0 matrix still multiplies, so one NaN
  // channel spreads to all three (1·NaN, 0·NaN). The composite never runs it at severity 0
  // (the APPLY_COLOR_DEFICIENCY permutation is off) — see Composite.CvdOffIsBitIdentical.
  const Vec3 spread = color_deficiency(nan_in, CvdType::kProtanope, 0, 0, 0);
  EXPECT_TRUE(std::isnan(spread[0]) && std::isnan(spread[1]) && std::isnan(spread[2]));
}

// ---------------------------------------------------------------------------------------------
// composite.h

TEST(Composite, EncodingAndCvdActivationRules) {
  // D8a: scRGB iff device 5 or 6.
  for (int d = 0; d <= 9; ++d) {
    EXPECT_EQ(back_buffer_encoding(d) == BackBufferEncoding::kScRgb, d == 5 || d == 6) << d;
  }
  // D8a: CVD permutation iff type != NormalVision and severity > 0.
  EXPECT_FALSE(color_deficiency_active({CvdType::kNormalVision, 10, true, true}));
  EXPECT_FALSE(color_deficiency_active({CvdType::kProtanope, 0, true, true}));
  EXPECT_TRUE(color_deficiency_active({CvdType::kProtanope, 1, false, false}));
  // Defaults are the 5.5 cvar defaults (docs/spec/ue55.md §10, decisions D10) and D3's clamp ON.
  const UiCompositeParams p;
  EXPECT_EQ(p.ui_level, 1.0);
  EXPECT_EQ(p.ui_luminance, 300.0);
  EXPECT_EQ(p.composite_mode, 1);
  EXPECT_EQ(p.min_normal_clamp, MinNormalClamp::kOn);
  EXPECT_FALSE(p.use_709);
}

// Hand derivation (Python from UE 5.5's 10-digit ACES.ush literals, docs/ue55-decisions.md): the
// literal product XYZ_2_Rec2020 · sRGB_2_XYZ maps sRGB white (1, 1, 1) to its row sums
// (1.000000000038, 1.000000000109, 0.999999999816): Rec.2020 white to 2e-10. (The pre-5.3
// 7-digit literals (docs/spec/ue55.md §2.1) gave 1.0000566, 0.9999849, 0.9999189.)
constexpr Vec3 kWhiteRowSums{1.000000000038, 1.000000000109, 0.999999999816};

TEST(Composite, OpaqueWhiteUiIsPqOf300NitsWhateverTheScene) {
  // UI (1, 1, 1, 1): sRGBToLinear(1) = (1/1.055 + 0.0521327)^2.4 = 0.999999996588 (hand);
  // × 300 × row sums ≈ 300 nits; alpha 1 skips the Reinhard and scene · (1 − 1) = 0; PQ of those
  // (hand): below, within 1e-9 of the docs/spec/ue55.md §13 PQ(300) = 0.6218628370 (the 7-digit
  // literals of UE <= 5.0 left a gap of 8.6e-6 here).
  const Vec3 expected{0.621862836664, 0.621862836672, 0.621862836641};
  UiCompositeParams p;
  double worst = 0.0, worst_vs_spec = 0.0;
  for (const Vec4& scene :
       {Vec4{0, 0, 0, 1}, Vec4{1, 1, 1, 1}, Vec4{0.3, 0.7, 0.1, 0}, Vec4{0.9, 0.02, 0.5, 1}}) {
    for (MinNormalClamp clamp : {kOn, kOff}) {
      p.min_normal_clamp = clamp;
      const Vec4 out = composite_pixel(scene, {1, 1, 1, 1}, p);
      const double err = max_err(rgb(out), expected);
      EXPECT_LE(err, 1e-11);
      EXPECT_EQ(out[3], 1.0);
      worst = std::fmax(worst, err);
      worst_vs_spec =
          std::fmax(worst_vs_spec, max_err(rgb(out), {0.6218628370, 0.6218628370, 0.6218628370}));
    }
  }
  EXPECT_LE(worst_vs_spec, 2e-9);
  record("opaque_white_max_residual", worst);          // measured 5.0e-13
  record("opaque_white_gap_to_pq300", worst_vs_spec);  // measured 4e-10 (literal row sums)
  // Opaque UI hides the scene only arithmetically: a NaN or Inf scene gives NaN · 0 = NaN,
  // as IEEE hardware does.
  const Vec4 nan_out = composite_pixel({kNaN, 0.5, 0.5, 1}, {1, 1, 1, 1}, p);
  EXPECT_TRUE(std::isnan(nan_out[0]));
  EXPECT_LE(max_err({nan_out[1], nan_out[2], 0}, {expected[1], expected[2], 0}), 1e-11);
}

TEST(Composite, TransparentUiLeavesPqSceneUnchangedWithoutClamp) {
  // UI (0, 0, 0, 0), clamp off: UI nits are exactly 0 and scene · 1 + 0 is the scene, so the
  // output is LinearToST2084(ST2084ToLinear(code)). Over codes 0.01..1 the PQ round trip in
  // double is the only error: measured 1.9e-14 (the hand values carry 12 digits), tolerance 1e-13.
  UiCompositeParams p;
  p.min_normal_clamp = kOff;
  double worst = 0.0;
  for (int i = 1; i <= 100; ++i) {
    const double code = i / 100.0;
    const Vec4 out = composite_pixel({code, code * 0.5, 1.0 - code * 0.9, 1}, {0, 0, 0, 0}, p);
    worst = std::fmax(worst, max_err(rgb(out), {code, code * 0.5, 1.0 - code * 0.9}));
  }
  EXPECT_LE(worst, 1e-13);
  record("transparent_pq_roundtrip_max_residual", worst);
  // Code 0 is the exception: ST2084ToLinear(0) = 0 but LinearToST2084(0) = c1^m2 = 7.3096e-7
  // (hand; docs/spec/ue55.md §13: PQ(0) = 7.310e-7), so black comes back as 7.31e-7.
  const Vec4 black = composite_pixel({0, 0, 0, 1}, {0, 0, 0, 0}, p);
  EXPECT_NEAR(black[0], 7.309559025784e-7, 1e-18);
}

TEST(Composite, TransparentUiWithClampLiftsBlack) {
  // D3 with the clamp (default): sRGBToLinear(0) = 6.10352e-5 / 12.92 = 4.72409e-6, × 300 ×
  // row sums = 1.417226e-3 nits added to every pixel; over a black scene PQ gives 7.652841e-3
  // (hand; D3: ≈ 7.65e-3, ≈ 7.8 ten-bit codes).
  const UiCompositeParams p;
  UiCompositeTrace t;
  const Vec4 out = composite_pixel({0, 0, 0, 1}, {0, 0, 0, 0}, p, &t);
  const double err_nits =
      max_err(rgb(t.ui), {1.417226006245e-3, 1.417226006347e-3, 1.417226005932e-3});
  const double err_pq =
      max_err(rgb(out), {7.652840998016e-3, 7.652840998319e-3, 7.652840997079e-3});
  EXPECT_LE(err_nits, 1e-15);
  EXPECT_LE(err_pq, 1e-13);
  record("transparent_clamp_black_residual", err_pq);
  EXPECT_NEAR(out[0] * 1023.0, 7.83, 0.01);  // the ≈ 7.8-code lift of D3
}

TEST(Composite, ReinhardUnderHalfTransparentUiByHand) {
  // Scene PQ 0.5080784215 = 99.99999998267 nits grey (hand ST2084ToLinear). UI premultiplied
  // (0.5, 0.5, 0.5, 0.5): sRGBToLinear(0.5) = 0.214041139094 (UE constants) × 300 × row sums.
  // L = 99.99999998267 · (0.2627 + 0.678 + 0.0593) / 1 ≈ 100; OutL = 1/(1 + L) ≈ 1/101;
  // scale = lerp(1, 1/101, 0.5) = 0.504950495050; out = 100 · scale · (1 − 0.5) + UI (hand):
  const UiCompositeParams p;
  UiCompositeTrace t;
  const double g = 0.5080784215;
  const Vec4 out = composite_pixel({g, g, g, 1}, {0.5, 0.5, 0.5, 0.5}, p, &t);
  const double err_nits = max_err(t.composed, {89.459866478756, 89.459866483359, 89.459866464545});
  const double err_pq = max_err(rgb(out), {0.496942658100, 0.496942658105, 0.496942658084});
  EXPECT_LE(err_nits, 1e-9);
  EXPECT_LE(err_pq, 1e-11);
  record("reinhard_level1_nits_residual", err_nits);  // measured 3.6e-13
  // UILevel 2: L = 100 / 2 = 50; scale = lerp(1, 2/51, 0.5) = 0.519607843141; UI × 2 (hand).
  UiCompositeParams p2;
  p2.ui_level = 2.0;
  composite_pixel({g, g, g, 1}, {0.5, 0.5, 0.5, 0.5}, p2, &t);
  const double err2 = max_err(t.composed, {154.405075613753, 154.405075622961, 154.405075585332});
  EXPECT_LE(err2, 1e-9);
  record("reinhard_level2_nits_residual", err2);
  // max(scene, 0) under translucent UI turns NaN and negatives into 0: the NaN scene gives the
  // black-scene result exactly.
  const Vec4 from_nan = composite_pixel({kNaN, kNaN, kNaN, 1}, {0.5, 0.5, 0.5, 0.5}, p);
  const Vec4 from_black = composite_pixel({0, 0, 0, 1}, {0.5, 0.5, 0.5, 0.5}, p);
  for (int c = 0; c < 4; ++c) EXPECT_EQ(from_nan[c], from_black[c]);
  // Under fully transparent UI (alpha 0, no Reinhard) NaN stays NaN.
  EXPECT_TRUE(std::isnan(composite_pixel({kNaN, 0, 0, 1}, {0, 0, 0, 0}, p)[0]));
}

TEST(Composite, ScRgbRoundTripOfUe55Literals) {
  // Devices 5/6, transparent UI, clamp off: out = Rec2020_2_sRGB · (sRGB_2_Rec2020 · s · 80) / 80.
  // UE 5.5's literals (all 10 digits) are inverses of each other to 1.6e-10 (hand), so the scene
  // comes back to 2.4e-10 relative; UE <= 5.0's 7-digit sRGB_2_XYZ against the 10-digit
  // XYZ_2_sRGB scaled it by up to 2.4e-4. Expected values (hand) for s = (0.25, 0.5, 1.0):
  UiCompositeParams p;
  p.output_device = 5;
  p.min_normal_clamp = kOff;
  const Vec4 out = composite_pixel({0.25, 0.5, 1.0, 1}, {0, 0, 0, 0}, p);
  const double err = max_err(rgb(out), {0.250000000051, 0.500000000055, 0.999999999765});
  EXPECT_LE(err, 1e-12);
  record("scrgb_roundtrip_residual", err);
  EXPECT_LT(std::fabs(out[2] - 1.0), 1e-9);  // UE <= 5.0's literals: 2.4e-4
  // Opaque white on scRGB: 300 nits / 80 = 3.75 times the literal round-trip row sums (hand).
  p.output_device = 6;
  const Vec4 w = composite_pixel({0.1, 0.2, 0.3, 1}, {1, 1, 1, 1}, p);
  const double errw = max_err(rgb(w), {3.749999987790, 3.749999987345, 3.749999985956});
  EXPECT_LE(errw, 1e-11);
  record("scrgb_opaque_white_residual", errw);
  // Negative scRGB (out of sRGB gamut) passes through the matrices without clamping.
  EXPECT_LT(composite_pixel({-0.05, 0.5, 0.5, 1}, {0, 0, 0, 0}, p)[0], 0.0);
}

TEST(Composite, CvdOffIsBitIdentical) {
  // Severity 0 or NormalVision: the permutation is compiled out, so even NaN scenes and any
  // flags give bit-identical output to the plain composite.
  const Vec4 scenes[] = {{0.4, 0.6, 0.2, 1}, {kNaN, 0.5, 0.1, 1}, {0, 0, 0, 1}};
  const Vec4 uis[] = {{0.2, 0.1, 0.3, 0.4}, {0, 0, 0, 0}, {1, 0, 0, 1}};
  for (int device : {3, 5}) {
    UiCompositeParams plain;
    plain.output_device = device;
    for (const CvdSettings& cvd : {CvdSettings{CvdType::kProtanope, 0, true, true},
                                   CvdSettings{CvdType::kNormalVision, 10, true, false}}) {
      UiCompositeParams with = plain;
      with.cvd = cvd;
      for (const Vec4& s : scenes) {
        for (const Vec4& u : uis) {
          const Vec4 a = composite_pixel(s, u, plain);
          const Vec4 b = composite_pixel(s, u, with);
          for (int c = 0; c < 4; ++c) EXPECT_TRUE(same_bits(a[c], b[c]));
        }
      }
    }
  }
}

TEST(Composite, CvdSandwichByHand) {
  // Protanope severity 10, simulation, UI opaque sRGB red, clamp off: UI nits =
  // 300 · sRGBToLinear(1) · column 0 of sRGB_2_Rec2020 = (188.221168156, 20.729186745,
  // 4.917431633); after Rec2020→sRGB, Machado, sRGB→Rec2020 (hand, UE 5.5 literals; the spec's
  // pre-5.3 literals gave 188.246396900, 20.732464940, 4.918870006):
  UiCompositeParams p;
  p.min_normal_clamp = kOff;
  p.cvd = {CvdType::kProtanope, 10, false, false};
  UiCompositeTrace t;
  const Vec4 out = composite_pixel({0.2, 0.2, 0.2, 1}, {1, 0, 0, 1}, p, &t);
  EXPECT_LE(max_err(rgb(t.ui), {188.221168155710, 20.729186745379, 4.917431632670}), 1e-9);
  const double err = max_err(t.after_cvd, {39.924175106876, 34.730572432055, 2.729182075084});
  EXPECT_LE(err, 1e-9);
  record("cvd_sandwich_nits_residual", err);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(out[c], st2084::pq_from_nits(t.after_cvd[c]));
}

TEST(Composite, NegativeChannelBeforePqEncodeIsNaN) {
  // No clamp before LinearToST2084 (as UE): a negative composed channel encodes to NaN.
  const Vec3 enc = encode_output({-1.0, 100.0, 0.0}, BackBufferEncoding::kPq);
  EXPECT_TRUE(std::isnan(enc[0]));
  EXPECT_NEAR(enc[1], 0.5080784215, 1e-10);  // docs/spec/ue55.md §13 PQ(100)
  EXPECT_NEAR(enc[2], 7.309559025784e-7, 1e-18);
  // A UI texel above 1 (e.g. from a float UI target) is not clamped either: sRGB 2 decodes to
  // ((2 / 1.055 + 0.0521327)^2.4) × 300 nits.
  const UiCompositeParams p;
  const Vec4 ui = compute_hdr_ui_color({2, 2, 2, 1}, p);
  EXPECT_NEAR(ui[1], std::pow(2 / 1.055 + 0.0521327, 2.4) * 300 * kWhiteRowSums[1], 1e-9);
}

TEST(Composite, Mode0IsStandardBlendingInBackBufferCodes) {
  // r.HDR.UI.CompositeMode 0: no composite shader; Slate blends straight into the back buffer.
  UiCompositeParams p;
  p.composite_mode = 0;
  // PQ back buffer: UI (0.5, 0.5, 0.5, 0.5) over code 0.6 → 0.5 + 0.5 · 0.6 = 0.8 (hand);
  // alpha 0.5 + 0.5 · 1 = 1.
  Vec4 out = composite_pixel({0.6, 0.6, 0.6, 1}, {0.5, 0.5, 0.5, 0.5}, p);
  EXPECT_NEAR(out[0], 0.8, 1e-15);
  EXPECT_NEAR(out[3], 1.0, 1e-15);
  // Opaque white UI writes PQ code 1.0 = 10000 nits: mode 0 is not luminance-aware.
  out = composite_pixel({0.3, 0.3, 0.3, 1}, {1, 1, 1, 1}, p);
  EXPECT_EQ(st2084::nits_from_pq(out[0]), 10000.0);
  // UNORM clamps: out-of-range and NaN inputs land in [0, 1] (NaN → 0).
  out = composite_pixel({1.5, kNaN, -0.2, 1}, {0, 0, 0, 0}, p);
  EXPECT_EQ(out[0], 1.0);
  EXPECT_EQ(out[1], 0.0);
  EXPECT_EQ(out[2], 0.0);
  // scRGB (FP16) back buffer: no clamp. UI (0.1, 0.1, 0.1, 0.25) over 3.0 (240 nits) →
  // 0.1 + 0.75 · 3 = 2.35 (hand); white UI = scRGB 1.0 = 80 nits.
  p.output_device = 6;
  out = composite_pixel({3.0, 3.0, 3.0, 1}, {0.1, 0.1, 0.1, 0.25}, p);
  EXPECT_NEAR(out[0], 2.35, 1e-15);
  out = composite_pixel({3.0, 3.0, 3.0, 1}, {1, 1, 1, 1}, p);
  EXPECT_EQ(out[0] * kScRgbScaleFactor, 80.0);
  // Transparent UI leaves the scene exactly unchanged in mode 0 (no decode/encode).
  out = composite_pixel({0.123, -0.5, 7.0, 1}, {0, 0, 0, 0}, p);
  EXPECT_EQ(out[0], 0.123);
  EXPECT_EQ(out[1], -0.5);
  EXPECT_EQ(out[2], 7.0);
}

TEST(Composite, ImageCompositeMatchesHandValues) {
  // A 2×1 image: pixel 0 opaque white UI over black, pixel 1 transparent UI over PQ 0.5
  // (clamp off). Expected: the hand values of the pixel tests above.
  Image scene(2, 1), ui(2, 1);
  for (int c = 0; c < 3; ++c) scene.px(1, 0)[c] = 0.5;
  for (int c = 0; c < 4; ++c) ui.px(0, 0)[c] = 1.0;
  UiCompositeParams p;
  p.min_normal_clamp = kOff;
  const Result<Image> out = composite_ui(scene, ui, p);
  ASSERT_TRUE(out.ok()) << out.error().to_string();
  const double* w = out->px(0, 0);
  EXPECT_LE(max_err({w[0], w[1], w[2]}, {0.621862836664, 0.621862836672, 0.621862836641}), 1e-11);
  const double* s = out->px(1, 0);
  EXPECT_LE(max_err({s[0], s[1], s[2]}, {0.5, 0.5, 0.5}), 1e-13);
  EXPECT_EQ(w[3], 1.0);
  EXPECT_EQ(s[3], 1.0);
}

TEST(Composite, ErrorsArePinned) {
  struct Case {
    const char* name;
    UiCompositeParams p;
    const char* pointer;
    const char* message_part;
  };
  std::vector<Case> cases;
  {
    UiCompositeParams p;
    p.cvd = {CvdType::kTritanope, 11, false, false};
    cases.push_back({"severity 11", p, "cvd.severity", "out of range: 11"});
  }
  {
    UiCompositeParams p;
    p.cvd = {static_cast<CvdType>(4), 3, false, false};
    cases.push_back({"type 4", p, "cvd.type", "unknown EColorVisionDeficiency 4"});
  }
  {
    UiCompositeParams p;
    p.output_device = 10;
    cases.push_back({"device 10", p, "output_device", "out of range: 10"});
  }
  {
    UiCompositeParams p;
    p.ui_level = kNaN;
    cases.push_back({"level NaN", p, "r.HDR.UI.Level", "must be finite"});
  }
  {
    UiCompositeParams p;
    p.ui_luminance = kInf;
    cases.push_back({"luminance Inf", p, "r.HDR.UI.Luminance", "must be finite"});
  }
  {
    UiCompositeParams p;
    p.composite_mode = 0;
    p.cvd = {CvdType::kDeuteranope, 4, true, false};
    cases.push_back({"mode 0 + CVD", p, "r.HDR.UI.CompositeMode", "not modelled"});
  }
  for (const Case& c : cases) {
    const Status s = validate(c.p);
    ASSERT_FALSE(s.ok()) << c.name;
    EXPECT_EQ(s.error().pointer, c.pointer) << c.name;
    EXPECT_NE(s.error().message.find(c.message_part), std::string::npos)
        << c.name << ": " << s.error().message;
  }
  EXPECT_TRUE(validate(UiCompositeParams{}).ok());
  const Result<Image> r = composite_ui(Image(2, 2), Image(2, 1), UiCompositeParams{});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "UI image is 2x1, scene is 2x2; the composite needs equal sizes");
}

}  // namespace
}  // namespace hdrc::ref::ui
