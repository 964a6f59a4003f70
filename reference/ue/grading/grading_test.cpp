// Tests for the CombineLUTs grading stages. Expected values come from outside the code under test:
// published CIE data, hand derivations, independent re-computations written differently in this
// file, and docs/spec/ue55.md §13 (each re-derived here; where it and UE differ, the comment says
// who is right). Every tolerance carries the residual measured when it was set.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "reference/color/ue_matrices.h"
#include "reference/ue/grading/color_correct.h"
#include "reference/ue/grading/color_polynomial.h"
#include "reference/ue/grading/expand_gamut.h"
#include "reference/ue/grading/film_common.h"
#include "reference/ue/grading/film_tonemap.h"
#include "reference/ue/grading/hlsl_ops.h"
#include "reference/ue/grading/white_balance.h"

namespace {

using hdrc::ref::dot;
using hdrc::ref::Mat3;
using hdrc::ref::Vec3;
using hdrc::ref::WorkingColorSpace;
namespace g = hdrc::ref::grading;
namespace lit = hdrc::ref::ue_literal;
using hdrc::ref::max_abs_diff;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void expect_matrix(const Mat3& got, const Mat3& want, double tol) {
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(got.m[i], want.m[i], tol) << "entry " << i;
}

void expect_vec(const Vec3& got, const Vec3& want, double tol) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], want[i], tol) << "channel " << i;
}

// Gauss–Jordan inverse with partial pivoting: a second derivation, independent of vec.cpp's
// cofactor formula.
Mat3 gauss_jordan_inverse(const Mat3& a) {
  double m[3][6];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 6; ++c) m[r][c] = c < 3 ? a(r, c) : (c - 3 == r ? 1.0 : 0.0);
  for (int col = 0; col < 3; ++col) {
    int pivot = col;
    for (int r = col + 1; r < 3; ++r)
      if (std::fabs(m[r][col]) > std::fabs(m[pivot][col])) pivot = r;
    for (int c = 0; c < 6; ++c) std::swap(m[col][c], m[pivot][c]);
    const double p = m[col][col];
    for (int c = 0; c < 6; ++c) m[col][c] /= p;
    for (int r = 0; r < 3; ++r) {
      if (r == col) continue;
      const double f = m[r][col];
      for (int c = 0; c < 6; ++c) m[r][c] -= f * m[col][c];
    }
  }
  Mat3 inv;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) inv(r, c) = m[r][c + 3];
  return inv;
}

// CIE 1931 xy → CIE 1960 uv.
std::pair<double, double> uv_from_xy(double x, double y) {
  const double d = -2.0 * x + 12.0 * y + 3.0;
  return {4.0 * x / d, 6.0 * y / d};
}

// McCamy 1992 CCT from xy (the formula UE carries as CorrelatedColorTemperature, unused there):
// an independent inverse of the two locus approximations, good to a few kelvin near 2856–6504 K.
double mccamy_cct(double x, double y) {
  const double n = (x - 0.3320) / (y - 0.1858);
  return -449.0 * n * n * n + 3525.0 * n * n - 6823.3 * n + 5520.33;
}

// sRGB WCS with double (not float-cast) matrices, as docs/spec/ue55.md §13's white-balance numbers
// assume.
WorkingColorSpace double_srgb_wcs() {
  WorkingColorSpace w = hdrc::ref::make_working_color_space(hdrc::ref::standard::kSrgb);
  const Mat3 to_xyz = hdrc::ref::standard::rgb_to_xyz(hdrc::ref::standard::kSrgb);
  w.to_xyz = to_xyz;
  w.from_xyz = gauss_jordan_inverse(to_xyz);
  return w;
}

const WorkingColorSpace& srgb_wcs() {
  static const WorkingColorSpace w =
      hdrc::ref::make_working_color_space(hdrc::ref::standard::kSrgb);
  return w;
}

// ---------------------------------------------------------------------------------------------
// White balance

// CIE 15:2004 daylight: D50 (0.34567, 0.35850), D65 (0.31271, 0.32902); at 4 decimals (0.3457,
// 0.3585) and (0.3127, 0.3290). UE's D_IlluminantChromaticity takes the *nominal* temperature and
// multiplies by 1.4388/1.438 itself, so D50/D65 are UE inputs 5000/6500 (→ 5002.8/6503.6 K).
// x: within the published 4-decimal precision (measured |Δx| 4.1e-5 at 5000, 2.0e-5 at 6500).
// y: the CIE y_D = −3x² + 2.87x − 0.275 quadratic itself sits ~1e-4 above the SPD-derived
// published y (it gives 0.32912 for D65 even at the exact 6504 K); measured |Δy| 1.01e-4 and
// 1.25e-4, bound 1.3e-4.
TEST(WhiteBalance, DaylightLocusMatchesCieD50AndD65) {
  const g::Chromaticity d50 = g::d_illuminant_chromaticity(5000.0);
  const g::Chromaticity d65 = g::d_illuminant_chromaticity(6500.0);
  EXPECT_NEAR(d50.x, 0.3457, 5e-5);
  EXPECT_NEAR(d65.x, 0.3127, 5e-5);
  EXPECT_NEAR(d50.y, 0.3585, 1.3e-4);
  EXPECT_NEAR(d65.y, 0.3290, 1.3e-4);
}

// The brief asked for UE's function at the CIE's CCTs 5003 K / 6504 K. That applies the
// 1.4388/1.438 correction twice: D_Illuminant(5003) evaluates the CIE formula at 5005.8 K and its x
// misses D50 by 1.28e-4 (outside the 4-decimal precision). The CIE formula proper at 5003/6504
// (UE's function with the scale undone) is within it: measured |Δx| 4.7e-5 and 1.4e-5.
TEST(WhiteBalance, DaylightInputIsNominalTemperatureNotCct) {
  const double undo = 1.438 / 1.4388;
  EXPECT_NEAR(g::d_illuminant_chromaticity(5003.0 * undo).x, 0.3457, 5e-5);
  EXPECT_NEAR(g::d_illuminant_chromaticity(6504.0 * undo).x, 0.3127, 5e-5);
  EXPECT_GT(std::fabs(g::d_illuminant_chromaticity(5003.0).x - 0.3457), 1e-4);
}

// Spec §13: D_Illuminant(6500) = (0.3127203, 0.3291253), Planckian(6500) = (0.3135342, 0.3235233).
// Re-derived: the CIE 15 daylight polynomial written out term by term (not Horner) at
// 6500·1.4388/1.438, and McCamy's CCT of both points (D65 is 6504 K; the Planckian point 6500 K;
// McCamy measured 6503.1 and 6499.6 K).
TEST(WhiteBalance, SixFiveHundredKelvinPointsMatchSpecAndCrossChecks) {
  const g::Chromaticity d = g::d_illuminant_chromaticity(6500.0);
  const g::Chromaticity p = g::planckian_locus_chromaticity(6500.0);
  EXPECT_NEAR(d.x, 0.3127203, 5e-8);
  EXPECT_NEAR(d.y, 0.3291253, 5e-8);
  EXPECT_NEAR(p.x, 0.3135342, 5e-8);
  EXPECT_NEAR(p.y, 0.3235233, 5e-8);

  const double t = 6500.0 * 1.4388 / 1.438;
  const double x = -4.6070e9 / (t * t * t) + 2.9678e6 / (t * t) + 99.11 / t + 0.244063;
  EXPECT_NEAR(d.x, x, 1e-15);
  EXPECT_NEAR(d.y, 2.87 * x - 3.0 * x * x - 0.275, 1e-15);

  EXPECT_NEAR(mccamy_cct(d.x, d.y), 6504.0, 2.0);
  EXPECT_NEAR(mccamy_cct(p.x, p.y), 6500.0, 2.0);
  // Not the same point: this is why UE skips white balance at 6500 K / tint 0.
  EXPECT_GT(std::fabs(d.y - p.y), 5e-3);
}

// CIE illuminant A is a Planckian radiator at 2856 K (c2 = 1.4388e-2 m·K): xy (0.44757, 0.40745).
// Krystek's approximation misses it by Δu = −7.3e-5, Δv = +8.3e-5 in CIE 1960 uv (measured; the
// xy residual is 9.8e-5 / 3.2e-4); bound 1e-4 in uv. McCamy gives 2858.4 K for the UE point.
TEST(WhiteBalance, PlanckianMatchesIlluminantA) {
  const g::Chromaticity a = g::planckian_locus_chromaticity(2856.0);
  const auto [u, v] = uv_from_xy(a.x, a.y);
  const auto [ua, va] = uv_from_xy(0.44757, 0.40745);
  EXPECT_NEAR(u, ua, 1e-4);
  EXPECT_NEAR(v, va, 1e-4);
  EXPECT_NEAR(mccamy_cct(a.x, a.y), 2856.0, 3.0);
}

// PlanckianIsothermal moves the Planckian point by 0.05·tint along the locus normal. The tangent
// is taken here by a central difference of the locus (independent of UE's closed-form ud/vd):
// |offset| = 0.05·|tint| (measured error 2e-17) and offset ⟂ tangent up to |cos| 1.4e-6
// (measured; the same for steps 0.5 K and 0.05 K, so it is UE's 6–9-digit derivative
// coefficients, not the difference quotient); bound 2e-6.
TEST(WhiteBalance, IsothermalOffsetIsNormalToLocus) {
  for (double temp : {2000.0, 4500.0, 6500.0, 10000.0}) {
    for (double tint : {-1.0, 0.3, 1.0}) {
      const g::Chromaticity p = g::planckian_locus_chromaticity(temp);
      const g::Chromaticity q = g::planckian_isothermal(temp, tint);
      const auto [up, vp] = uv_from_xy(p.x, p.y);
      const auto [uq, vq] = uv_from_xy(q.x, q.y);
      const g::Chromaticity lo = g::planckian_locus_chromaticity(temp - 0.5);
      const g::Chromaticity hi = g::planckian_locus_chromaticity(temp + 0.5);
      const auto [u0, v0] = uv_from_xy(lo.x, lo.y);
      const auto [u1, v1] = uv_from_xy(hi.x, hi.y);
      const double du = uq - up, dv = vq - vp, tu = u1 - u0, tv = v1 - v0;
      const double len = std::hypot(du, dv);
      EXPECT_NEAR(len, 0.05 * std::fabs(tint), 1e-12) << temp << " K, tint " << tint;
      EXPECT_LT(std::fabs(du * tu + dv * tv) / (len * std::hypot(tu, tv)), 2e-6)
          << temp << " K, tint " << tint;
    }
    const g::Chromaticity p = g::planckian_locus_chromaticity(temp);
    const g::Chromaticity q = g::planckian_isothermal(temp, 0.0);
    EXPECT_EQ(p.x, q.x);
    EXPECT_EQ(p.y, q.y);
  }
}

// UE's InvConeResponse literal against the inverse of the Bradford cone matrix derived here by
// Gauss–Jordan: entries agree to 5e-8 (measured 4.83e-8; the literal has 7 decimals). For the
// 5000 K → D65 adaptation the whole CA matrix moves by at most 1e-7 (measured 8.2e-8).
TEST(WhiteBalance, LiteralInvConeAgainstDerivedBradford) {
  const Mat3 exact_inv = gauss_jordan_inverse(g::kBradfordCone);
  EXPECT_LT(max_abs_diff(g::kBradfordInvConeLiteral, exact_inv), 5e-8);
  EXPECT_GT(max_abs_diff(g::kBradfordInvConeLiteral, exact_inv), 0.0);

  const g::WhiteBalanceWhites w = g::white_balance_whites({5000.0, 0.0});
  const Vec3 src = g::xyz_from_xy(w.src), dst = g::xyz_from_xy(w.dst);
  const Vec3 cs = g::kBradfordCone * src, cd = g::kBradfordCone * dst;
  const Mat3 exact_ca =
      exact_inv * Mat3::diag({cd[0] / cs[0], cd[1] / cs[1], cd[2] / cs[2]}) * g::kBradfordCone;
  const Mat3 ue_ca = g::chromatic_adaptation(w.src, w.dst);
  EXPECT_LT(max_abs_diff(ue_ca, exact_ca), 1e-7);
  // The project's standard::bradford (exact inverse) is the same matrix as the derivation here.
  EXPECT_LT(max_abs_diff(hdrc::ref::standard::bradford(src, dst), exact_ca), 1e-14);
  // Adaptation sends the source white to the destination white (exact with the exact inverse;
  // measured 5.1e-8 with UE's literal).
  expect_vec(ue_ca * src, dst, 1e-7);
  expect_vec(exact_ca * src, dst, 1e-14);
}

// Spec §13 white-balance matrices (sRGB WCS). The spec computed them with the *double* WCS
// matrices: reproduced to 1e-9. UE feeds the float-cast WorkingColorSpace.ToXYZ/FromXYZ (spec
// §2.3), which moves entries by up to 3.6e-8 (measured): the reference uses the float ones, the
// spec's 9-decimal figures are the double ones — both shown. Independent check: M maps the RGB of
// the source white onto D65 white (1,1,1) (measured 6.0e-8 with the InvCone literal).
TEST(WhiteBalance, MatricesAt5000And6500Kelvin) {
  const Mat3 spec_5000{{0.939388616, -0.093800757, -0.017502384, 0.004436915, 1.024114810,
                        -0.006549990, 0.008163207, 0.029563677, 1.333021305}};
  const Mat3 spec_6500{{1.000161328, 0.000401310, -0.000017000, -0.000020491, 0.999788660,
                        -0.000023444, 0.000016190, 0.000083449, 1.000823322}};
  const WorkingColorSpace dbl = double_srgb_wcs();
  expect_matrix(g::white_balance_matrix({5000.0, 0.0}, dbl), spec_5000, 1e-9);
  expect_matrix(g::white_balance_matrix({6500.0, 0.0}, dbl), spec_6500, 1e-9);
  const Mat3 m5000 = g::white_balance_matrix({5000.0, 0.0}, srgb_wcs());
  expect_matrix(m5000, spec_5000, 1e-7);
  expect_matrix(g::white_balance_matrix({6500.0, 0.0}, srgb_wcs()), spec_6500, 1e-7);

  const g::WhiteBalanceWhites w = g::white_balance_whites({5000.0, 0.0});
  const Vec3 src_rgb = dbl.from_xyz * g::xyz_from_xy(w.src);
  expect_vec(g::white_balance_matrix({5000.0, 0.0}, dbl) * src_rgb, {1.0, 1.0, 1.0}, 1e-7);
}

// C++ skip rule: |WhiteTemp − 6500| <= 1e-8 && |WhiteTint| <= 1e-8. At 6500 K the unskipped
// matrix is not the identity (largest entry gap 8.2e-4, docs/spec/ue55.md §13), so the rule is
// visible.
TEST(WhiteBalance, SkipRuleAtSixFiveHundredKelvin) {
  EXPECT_TRUE(g::white_balance_skipped({6500.0, 0.0}));
  EXPECT_TRUE(g::white_balance_skipped({6500.0 + 5e-9, -5e-9}));
  EXPECT_FALSE(g::white_balance_skipped({6500.0 + 2e-8, 0.0}));
  EXPECT_FALSE(g::white_balance_skipped({6500.0, 1e-7}));
  EXPECT_FALSE(g::white_balance_skipped({5000.0, 0.0}));

  const Vec3 c{0.2, 0.5, 0.9};
  const Vec3 skipped = g::white_balance(c, {6500.0, 0.0}, srgb_wcs());
  EXPECT_EQ(skipped, c);
  const Vec3 applied = g::white_balance(c, {6500.0 + 1e-3, 0.0}, srgb_wcs());
  EXPECT_GT(std::fabs(applied[2] - c[2]), 5e-4);
  EXPECT_GT(max_abs_diff(g::white_balance_matrix({6500.0, 0.0}, srgb_wcs()), Mat3::identity()),
            8e-4);
}

// T < 4000 K uses the Planckian point, T >= 4000 K the daylight point; both plus the isotherm
// offset. TemperatureType = ColorTemperature swaps source and destination, so its matrix is the
// inverse of the white-balance one up to the InvCone literal (measured |M·M' − I| 4.2e-7).
TEST(WhiteBalance, LocusSwitchAndTemperatureTypeSwap) {
  const g::WhiteBalanceWhites low = g::white_balance_whites({3999.0, 0.0});
  const g::Chromaticity p = g::planckian_locus_chromaticity(3999.0);
  EXPECT_EQ(low.src.x, p.x);
  EXPECT_EQ(low.src.y, p.y);
  const g::WhiteBalanceWhites high = g::white_balance_whites({4000.0, 0.0});
  const g::Chromaticity d = g::d_illuminant_chromaticity(4000.0);
  EXPECT_EQ(high.src.x, d.x);
  EXPECT_EQ(high.src.y, d.y);
  EXPECT_EQ(high.dst.x, 0.3127);
  EXPECT_EQ(high.dst.y, 0.3290);

  const g::WhiteBalanceParams wb{4200.0, 0.4, g::TemperatureType::kWhiteBalance};
  g::WhiteBalanceParams ct = wb;
  ct.temperature_type = g::TemperatureType::kColorTemperature;
  const g::WhiteBalanceWhites a = g::white_balance_whites(wb), b = g::white_balance_whites(ct);
  EXPECT_EQ(a.src.x, b.dst.x);
  EXPECT_EQ(a.dst.y, b.src.y);
  const Mat3 prod =
      g::white_balance_matrix(wb, srgb_wcs()) * g::white_balance_matrix(ct, srgb_wcs());
  EXPECT_LT(max_abs_diff(prod, Mat3::identity()), 1e-6);
}

// ---------------------------------------------------------------------------------------------
// Fake wide gamut

// ExpandMat from UE 5.5's 10-digit ACES.ush literals and PostProcessCombineLUTs.usf's
// Wide_2_XYZ_MAT (product to 10 decimals by hand in Python). Spec §4.5 printed the product of the
// pre-5.3 literals, 1.3704127095, -0.3292913010, ... (up to 1.4e-6 away).
TEST(ExpandGamut, MatrixOfUe55Literals) {
  expect_matrix(g::expand_gamut_matrix(),
                Mat3{{1.3704123718, -0.3292921877, -0.0636831194, -0.0834334917, 1.0970927480,
                      -0.0108613795, -0.0257933209, -0.0986257988, 1.2036949526}},
                5e-10);
}

// Spec §13: sRGB (1,0,0) → AP1 (0.613097, 0.070194, 0.020616), luma 0.215326, |Chroma−1|²
// 4.684494, ExpandAmount 0.120632; (2, 0.1, 0.1) → 0.512479. Re-derived with a second formula:
// |c/L − 1|² = |c|²/L² − 2Σc/L + 3, 2^−k = e^(−k ln 2). Code vs re-derivation: 1e-12 (measured
// 2e-16); vs spec's 6 decimals: 5e-7 (measured 0.120631646; the float-cast ToAP1 changes it
// by less than 1e-9).
TEST(ExpandGamut, AmountMatchesSpecAndSecondDerivation) {
  auto amount = [](const Vec3& c, double expand) {
    const double l = dot(c, lit::kAp1RgbToY);
    const double d2 = dot(c, c) / (l * l) - 2.0 * (c[0] + c[1] + c[2]) / l + 3.0;
    const double ln2 = std::numbers::ln2;
    return (1.0 - std::exp(-4.0 * ln2 * d2)) * (1.0 - std::exp(-4.0 * ln2 * expand * l * l));
  };
  const Vec3 red = srgb_wcs().to_ap1 * Vec3{1.0, 0.0, 0.0};
  expect_vec(red, {0.613097, 0.070194, 0.020616}, 5e-7);
  EXPECT_NEAR(dot(red, lit::kAp1RgbToY), 0.215326, 5e-7);
  EXPECT_NEAR(g::expand_gamut_amount(red, 1.0), 0.120632, 5e-7);
  EXPECT_NEAR(g::expand_gamut_amount(red, 1.0), amount(red, 1.0), 1e-12);
  const Vec3 bright = srgb_wcs().to_ap1 * Vec3{2.0, 0.1, 0.1};
  EXPECT_NEAR(g::expand_gamut_amount(bright, 1.0), 0.512479, 5e-7);
  EXPECT_NEAR(g::expand_gamut_amount(bright, 1.0), amount(bright, 1.0), 1e-12);
  EXPECT_NEAR(g::expand_gamut_amount(bright, 0.3), amount(bright, 0.3), 1e-12);

  const Vec3 out = g::expand_gamut(red, 1.0);
  const Vec3 full = g::expand_gamut_matrix() * red;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(out[i], red[i] + 0.120632 * (full[i] - red[i]), 1e-6);
}

// Grey has Chroma = 1 (amount measured exactly 0), ExpandGamut = 0 disables; black (LumaAP1 = 0)
// takes the D-NaN decision (amount 0, no NaN); NaN in gives NaN out.
TEST(ExpandGamut, GreyBlackAndNaN) {
  EXPECT_LT(g::expand_gamut_amount({0.5, 0.5, 0.5}, 1.0), 1e-30);
  EXPECT_EQ(g::expand_gamut_amount({3.0, 0.1, 0.1}, 0.0), 0.0);
  EXPECT_EQ(g::expand_gamut_amount({0.0, 0.0, 0.0}, 1.0), 0.0);
  EXPECT_EQ(g::expand_gamut({0.0, 0.0, 0.0}, 1.0), (Vec3{0.0, 0.0, 0.0}));
  const Vec3 n = g::expand_gamut({kNaN, 0.2, 0.2}, 1.0);
  EXPECT_TRUE(std::isnan(n[0]) && std::isnan(n[1]) && std::isnan(n[2]));
}

// ---------------------------------------------------------------------------------------------
// ColorCorrectAll

// Defaults: every zone is the identity, so any input with non-negative channels passes unchanged
// (greys over 1e-4..100, and a chromatic colour). Measured max relative error 2.2e-16.
TEST(ColorCorrect, DefaultsAreIdentityAndNeutralStaysNeutral) {
  const g::ColorCorrectParams p;
  for (double v = 1e-4; v < 100.0; v *= 1.5) {
    const Vec3 out = g::color_correct_all({v, v, v}, p);
    EXPECT_NEAR(out[0], v, 1e-14 * v);
    EXPECT_EQ(out[0], out[1]);
    EXPECT_EQ(out[1], out[2]);
  }
  expect_vec(g::color_correct_all({0.7, 0.2, 0.05}, p), {0.7, 0.2, 0.05}, 1e-14);
}

// Zone weights: smoothstep at the zone mid-points is exactly 1/2; they always sum to 1; a NaN luma
// gives all weight to shadows (saturate(NaN) = 0).
TEST(ColorCorrect, ZoneWeights) {
  const g::ColorCorrectParams p;
  const g::ZoneWeights mid_shadow = g::color_correct_weights(0.045, p);
  EXPECT_NEAR(mid_shadow.shadows, 0.5, 1e-15);
  EXPECT_NEAR(mid_shadow.highlights, 0.0, 0.0);
  const g::ZoneWeights mid_high = g::color_correct_weights(0.75, p);
  EXPECT_NEAR(mid_high.highlights, 0.5, 1e-15);
  EXPECT_NEAR(mid_high.midtones, 0.5, 1e-15);
  for (double l : {-1.0, 0.0, 0.02, 0.3, 0.6, 0.99, 5.0}) {
    const g::ZoneWeights w = g::color_correct_weights(l, p);
    EXPECT_NEAR(w.shadows + w.midtones + w.highlights, 1.0, 1e-15);
  }
  const g::ZoneWeights n = g::color_correct_weights(kNaN, p);
  EXPECT_EQ(n.shadows, 1.0);
  EXPECT_EQ(n.midtones, 0.0);
  EXPECT_EQ(n.highlights, 0.0);
}

// Hand-computed single-zone results. Contrast pivots on 0.18: (0.09/0.18)²·0.18 = 0.045.
// Gamma 2: 0.25^(1/2) = 0.5. Gain (2,1,1)·w 1.5 and offset (0.1,0,0) + w 0.05 on 0.3:
// (0.3·3 + 0.15, 0.3·1.5 + 0.05, 0.3·1.5 + 0.05). Saturation 0 gives the AP1 luma.
TEST(ColorCorrect, HandComputedZone) {
  g::ColorCorrectZone z;
  z.contrast = {2, 2, 2, 1};
  EXPECT_NEAR(g::color_correct({0.09, 0.09, 0.09}, z)[0], 0.045, 1e-16);
  EXPECT_NEAR(g::color_correct({0.18, 0.18, 0.18}, z)[1], 0.18, 1e-16);
  z = {};
  z.gamma = {1, 1, 1, 2};
  EXPECT_NEAR(g::color_correct({0.25, 0.25, 0.25}, z)[2], 0.5, 1e-16);
  z = {};
  z.gain = {2, 1, 1, 1.5};
  z.offset = {0.1, 0, 0, 0.05};
  expect_vec(g::color_correct({0.3, 0.3, 0.3}, z), {1.05, 0.5, 0.5}, 1e-15);
  z = {};
  z.saturation = {0, 0, 0, 1};
  const Vec3 c{0.8, 0.1, 0.3};
  const double luma = 0.2722287168 * 0.8 + 0.6740817658 * 0.1 + 0.0536895174 * 0.3;
  expect_vec(g::color_correct(c, z), {luma, luma, luma}, 1e-16);
}

// Global controls combine component-wise with each zone (.w included); offsets add. With the same
// change in all zones the weights (summing to 1) drop out: global gain 2 doubles any colour.
TEST(ColorCorrect, GlobalCombinesWithZones) {
  g::ColorCorrectZone zone, global;
  zone.saturation = {1, 2, 3, 4};
  global.saturation = {5, 6, 7, 8};
  zone.offset = {0.1, 0.2, 0.3, 0.4};
  global.offset = {1, 2, 3, 4};
  const g::ColorCorrectZone c = g::combine_with_global(zone, global);
  EXPECT_EQ(c.saturation, (g::Vec4{5, 12, 21, 32}));
  EXPECT_EQ(c.offset, (g::Vec4{1.1, 2.2, 3.3, 4.4}));

  g::ColorCorrectParams p;
  p.global.gain = {1, 1, 1, 2};
  for (const Vec3& v : {Vec3{0.01, 0.02, 0.03}, Vec3{0.3, 0.2, 0.1}, Vec3{4.0, 2.0, 1.0}})
    expect_vec(g::color_correct_all(v, p), {2 * v[0], 2 * v[1], 2 * v[2]}, 1e-15);

  g::ColorCorrectParams shadows_only;
  shadows_only.shadows.gain = {1, 1, 1, 3};
  // Luma 0.01 → shadow weight 1 − smoothstep(0, 0.09, 0.01) = 1 − t²(3 − 2t), t = 1/9.
  const double t = 0.01 / 0.09, ws = 1.0 - t * t * (3.0 - 2.0 * t);
  const Vec3 out = g::color_correct_all({0.01, 0.01, 0.01}, shadows_only);
  EXPECT_NEAR(out[0], 0.01 * (3.0 * ws + (1.0 - ws)), 1e-16);
}

// Negative channels are clipped by ColorCorrect's first max(0, ·) (at saturation 1); NaN input
// becomes the black result (0, or the offsets) — D3D maxNum, docs/ue55-decisions.md D-NaN.
TEST(ColorCorrect, NegativesAndNaN) {
  g::ColorCorrectParams p;
  const Vec3 out = g::color_correct_all({-0.1, 0.2, 0.3}, p);
  EXPECT_EQ(out[0], 0.0);
  EXPECT_NEAR(out[1], 0.2, 1e-15);
  EXPECT_EQ(g::color_correct_all({kNaN, kNaN, kNaN}, p), (Vec3{0.0, 0.0, 0.0}));
  p.global.offset = {0.0, 0.0, 0.0, 0.1};
  EXPECT_EQ(g::color_correct_all({kNaN, kNaN, kNaN}, p), g::color_correct_all({0, 0, 0}, p));
  expect_vec(g::color_correct_all({kNaN, kNaN, kNaN}, p), {0.1, 0.1, 0.1}, 1e-17);
}

// ---------------------------------------------------------------------------------------------
// FilmToneMap

// A scalar restatement of the curve in tanh form, independent of the code's logistic form:
// toe(L) = (1 − Toe) + ToeScale·tanh(Slope/ToeScale·(L − ToeMatch)),
// shoulder(L) = Shoulder + ShoulderScale·tanh(Slope/ShoulderScale·(L − ShoulderMatch)).
// ToeMatch is found by bisection on toe(log10 0.18) = 0.18 instead of the closed form.
struct IndependentCurve {
  double slope, toe, shoulder, toe_scale, shoulder_scale, toe_match, straight_match, shoulder_match;
  explicit IndependentCurve(const g::FilmParams& p)
      : slope(p.slope), toe(p.toe), shoulder(p.shoulder) {
    toe_scale = 1.0 + p.black_clip - p.toe;
    shoulder_scale = 1.0 + p.white_clip - p.shoulder;
    const double l18 = std::log10(0.18);
    double lo = -5.0, hi = 5.0;  // toe(l18) decreases as ToeMatch grows
    for (int i = 0; i < 200; ++i) {
      const double m = 0.5 * (lo + hi);
      (toe_value(l18, m) > 0.18 ? lo : hi) = m;
    }
    toe_match = 0.5 * (lo + hi);
    // The straight line through the toe's midpoint (ToeMatch, 1 − Toe) with the given slope, and
    // the shoulder's midpoint where that line reaches Shoulder.
    straight_match = (1.0 - toe) / slope - toe_match;
    shoulder_match = shoulder / slope - straight_match;
  }
  double toe_value(double l, double match) const {
    return (1.0 - toe) + toe_scale * std::tanh(slope / toe_scale * (l - match));
  }
  double operator()(double x) const {
    const double l = std::log10(x);
    const double straight = slope * (l + straight_match);
    const double toe_c = l < toe_match ? toe_value(l, toe_match) : straight;
    const double shoulder_c =
        l > shoulder_match
            ? shoulder + shoulder_scale * std::tanh(slope / shoulder_scale * (l - shoulder_match))
            : straight;
    double t = std::clamp((l - toe_match) / (shoulder_match - toe_match), 0.0, 1.0);
    if (shoulder_match < toe_match) t = 1.0 - t;
    const double s = t * t * (3.0 - 2.0 * t);
    return toe_c * (1.0 - s) + shoulder_c * s;
  }
};

// Spec §13 match points: ToeMatch −0.3902772321, StraightMatch 0.9016408685, ShoulderMatch
// −0.6061863230 (ShoulderMatch < ToeMatch: the blend flip is active with the defaults).
// Bisection vs closed form: measured 1.1e-16.
TEST(FilmToneMap, MatchPoints) {
  const g::FilmCurveMatch m = g::film_curve_match({});
  const IndependentCurve ref{g::FilmParams{}};
  EXPECT_NEAR(m.toe_match, -0.3902772321, 5e-11);
  EXPECT_NEAR(m.straight_match, 0.9016408685, 5e-11);
  EXPECT_NEAR(m.shoulder_match, -0.6061863230, 5e-11);
  EXPECT_NEAR(m.toe_match, ref.toe_match, 1e-13);
  EXPECT_NEAR(m.shoulder_match, ref.shoulder_match, 1e-13);
  EXPECT_LT(m.shoulder_match, m.toe_match);
  // Toe > 0.8 puts 0.18 on the straight segment: S·(log10 0.18 + StraightMatch) = 0.18.
  const g::FilmParams steep{0.9, 0.85, 0.26, 0.0, 0.04};
  const g::FilmCurveMatch ms = g::film_curve_match(steep);
  EXPECT_NEAR(steep.slope * (std::log10(0.18) + ms.straight_match), 0.18, 1e-15);
}

// Spec §13 grey values, through the whole FilmToneMap (AP1 grey → AP0 → glow/red modifier, which
// vanish for grey → AP1 → curve → desaturations, which vanish too). Against the tanh curve:
// measured relative 1.5e-10, channels differ by 2.2e-10 relative (the literal AP1→AP0→AP1 round
// trip is not exactly grey-preserving). Against the spec's 10 digits: measured 4.8e-11, bound
// 5e-10. f(0.18) = 0.18 by construction of ToeMatch (measured 3e-13).
TEST(FilmToneMap, GreyValues) {
  const IndependentCurve ref{g::FilmParams{}};
  const std::pair<double, double> spec[] = {
      {0.0001, 6.651e-7},  {0.01, 0.0016565677}, {0.05, 0.0248374933},
      {0.18, 0.18},        {0.5, 0.5184078229},  {1.0, 0.7233594566},
      {2.0, 0.8616130976}, {10.0, 0.9994755605}, {100.0, 1.0356549972}};
  for (const auto& [x, want] : spec) {
    const Vec3 out = g::film_tone_map({x, x, x}, {});
    const double tol = x == 0.0001 ? 5e-11 : 5e-10;
    EXPECT_NEAR(out[0], want, tol) << "x = " << x;
    EXPECT_NEAR(out[0], ref(x), 2e-9 * ref(x)) << "x = " << x;
    EXPECT_NEAR(out[1], out[0], 1e-9 * out[0]);
    EXPECT_NEAR(out[2], out[0], 1e-9 * out[0]);
  }
  EXPECT_NEAR(g::film_tone_map({0.18, 0.18, 0.18}, {})[1], 0.18, 1e-10);
}

// Monotonic on a grey ramp 1e-6 … 1e4 (4000 log steps), below the 1 + WhiteClip asymptote.
TEST(FilmToneMap, MonotonicOnGreyRamp) {
  double prev = -1.0;
  for (int i = 0; i <= 4000; ++i) {
    const double x = std::pow(10.0, -6.0 + 10.0 * i / 4000.0);
    const double y = g::film_tone_map({x, x, x}, {})[1];
    ASSERT_GE(y, prev) << "x = " << x;
    prev = y;
  }
  EXPECT_LT(prev, 1.04);
  EXPECT_GT(prev, 1.039);
}

// Spec §13 red-modifier weights at hue 0/10/30/60°: UE's smoothstep² 1, 0.884840, 0.339878,
// 0.001176; ACES 1.3's cubic_basis_shaper(h, 135) 1, 0.887822, 0.341564, 0.002743. Both
// re-derived here: smoothstep by hand, the B-spline from its piecewise-cubic basis.
TEST(FilmToneMap, RedModifierWeights) {
  auto smooth_sq = [](double h) {
    const double t = std::clamp(1.0 - std::fabs(2.0 * h / 135.0), 0.0, 1.0);
    const double s = t * t * (3.0 - 2.0 * t);
    return s * s;
  };
  auto aces_bspline = [](double h) {      // uniform cubic B-spline, knots every 135/4 degrees
    const double u = (h + 67.5) / 33.75;  // 0..4 across the support
    if (u <= 0.0 || u >= 4.0) return 0.0;
    const int j = static_cast<int>(u);
    const double t = u - j;
    const double b[4] = {t * t * t / 6.0, (-3 * t * t * t + 3 * t * t + 3 * t + 1) / 6.0,
                         (3 * t * t * t - 6 * t * t + 4) / 6.0, (1 - t) * (1 - t) * (1 - t) / 6.0};
    return 1.5 * b[j];
  };
  const double hues[] = {0.0, 10.0, 30.0, 60.0};
  const double ue[] = {1.0, 0.884840, 0.339878, 0.001176};
  const double aces[] = {1.0, 0.887822, 0.341564, 0.002743};
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(g::red_modifier_hue_weight(hues[i]), ue[i], 5e-7) << hues[i];
    EXPECT_NEAR(g::red_modifier_hue_weight(hues[i]), smooth_sq(hues[i]), 1e-15) << hues[i];
    EXPECT_NEAR(aces_bspline(hues[i]), aces[i], 5e-7) << hues[i];
  }
  EXPECT_EQ(g::red_modifier_hue_weight(350.0), g::red_modifier_hue_weight(10.0));
  EXPECT_EQ(g::red_modifier_hue_weight(70.0), 0.0);
}

// The ACES helpers at hand-computed points.
TEST(FilmToneMap, AcesHelpers) {
  namespace f = g::film;
  EXPECT_EQ(f::sigmoid_shaper(-2.0), 0.0);
  EXPECT_EQ(f::sigmoid_shaper(0.0), 0.5);
  EXPECT_EQ(f::sigmoid_shaper(1.0), 0.875);  // t = 0.5: (1 + 0.75)/2
  EXPECT_EQ(f::sigmoid_shaper(3.0), 1.0);
  EXPECT_EQ(f::glow_fwd(0.05, 0.04, 0.08), 0.04);
  EXPECT_EQ(f::glow_fwd(0.16, 0.04, 0.08), 0.0);
  EXPECT_NEAR(f::glow_fwd(0.1, 0.04, 0.08), 0.04 * (0.8 - 0.5), 1e-17);
  EXPECT_NEAR(f::rgb_2_yc({1, 1, 1}), 1.0, 1e-16);
  EXPECT_NEAR(f::rgb_2_yc({1, 0, 0}), 2.75 / 3.0, 1e-16);
  EXPECT_NEAR(f::rgb_2_saturation({1, 0, 0}), 1.0 - 1e-10, 1e-16);
  EXPECT_EQ(f::rgb_2_saturation({0.5, 0.5, 0.5}), 0.0);
  EXPECT_EQ(f::rgb_2_hue({1, 0, 0}), 0.0);
  EXPECT_NEAR(f::rgb_2_hue({0, 1, 0}), 120.0, 1e-12);
  EXPECT_NEAR(f::rgb_2_hue({0, 0, 1}), 240.0, 1e-12);
  EXPECT_EQ(f::rgb_2_hue({0.3, 0.3, 0.3}), 0.0);
  EXPECT_EQ(f::center_hue(350.0, 0.0), -10.0);
}

// A saturated dark red stays ordered (red largest) and non-negative through FilmToneMap.
TEST(FilmToneMap, ChromaticStaysOrderedAndNonNegative) {
  const Vec3 out = g::film_tone_map({0.05, 0.002, 0.002}, {});
  EXPECT_GT(out[0], out[1]);
  EXPECT_GE(out[1], 0.0);
  EXPECT_GE(out[2], 0.0);
}

// Chromatic input, where glow and the red modifier act: FilmToneMap recomputed here from the spec
// §4.8 step list in plain scalar form (ACES formulas written out, the tanh curve above), for a dark
// saturated red (full glow: yc < (2/3)·0.08) and a brighter red (glow's middle branch). Both reds
// sit at AP0 hues within ±67.5° so the red modifier is active. Measured agreement 6.9e-17 absolute;
// bound 1e-12.
TEST(FilmToneMap, ChromaticMatchesStepByStepRecomputation) {
  const IndependentCurve curve{g::FilmParams{}};
  const Mat3 ap1_to_ap0 = lit::kXyzToAp0 * lit::kAp1ToXyz;
  auto recompute = [&](const Vec3& ap1, double* yc_out, double* hue_out) {
    Vec3 a = ap1_to_ap0 * ap1;
    const double mx = std::max({a[0], a[1], a[2]}), mn = std::min({a[0], a[1], a[2]});
    const double sat = (mx - mn) / std::max(mx, 0.01);  // all channels > 1e-10 here
    const double chroma =
        std::sqrt(0.5 * ((a[0] - a[1]) * (a[0] - a[1]) + (a[1] - a[2]) * (a[1] - a[2]) +
                         (a[2] - a[0]) * (a[2] - a[0])));
    const double yc = (a[0] + a[1] + a[2] + 1.75 * chroma) / 3.0;
    const double x = (sat - 0.4) / 0.2;  // sigmoid_shaper for x in [0, 2]: 1 − (1 − x/2)²/2
    EXPECT_GE(x, 0.0);
    const double sig = x >= 2.0 ? 1.0 : 1.0 - 0.5 * (1.0 - 0.5 * x) * (1.0 - 0.5 * x);
    const double gain = 0.05 * sig;
    const double glow =
        yc <= 0.08 * 2.0 / 3.0 ? gain : (yc >= 0.16 ? 0.0 : gain * (0.08 / yc - 0.5));
    for (double& c : a) c *= 1.0 + glow;
    double hue = std::atan2(std::sqrt(3.0) * (a[1] - a[2]), 2 * a[0] - a[1] - a[2]) * 180.0 /
                 std::numbers::pi;
    if (hue < 0) hue += 360.0;
    const double centred = hue > 180.0 ? hue - 360.0 : hue;
    const double t = std::clamp(1.0 - std::fabs(centred) / 67.5, 0.0, 1.0);
    const double w = (t * t * (3 - 2 * t)) * (t * t * (3 - 2 * t));
    a[0] += w * sat * (0.03 - a[0]) * 0.18;
    Vec3 wc = lit::kAp0ToAp1 * a;
    for (double& c : wc) c = std::max(c, 0.0);
    const double l1 = dot(wc, lit::kAp1RgbToY);
    Vec3 tone;
    for (int i = 0; i < 3; ++i) tone[i] = curve(0.96 * wc[i] + 0.04 * l1);
    const double l2 = dot(tone, lit::kAp1RgbToY);
    for (double& c : tone) c = std::max(0.93 * c + 0.07 * l2, 0.0);
    *yc_out = yc;
    *hue_out = centred;
    return tone;
  };
  double yc = 0, hue = 0;
  const Vec3 dark{0.05, 0.004, 0.003};
  const Vec3 want_dark = recompute(dark, &yc, &hue);
  EXPECT_LT(yc, 0.08 * 2.0 / 3.0);
  EXPECT_LT(std::fabs(hue), 67.5);
  expect_vec(g::film_tone_map(dark, {}), want_dark, 1e-12);
  const Vec3 mid{0.15, 0.02, 0.015};
  const Vec3 want_mid = recompute(mid, &yc, &hue);
  EXPECT_GT(yc, 0.08 * 2.0 / 3.0);
  EXPECT_LT(yc, 0.16);
  EXPECT_LT(std::fabs(hue), 67.5);
  expect_vec(g::film_tone_map(mid, {}), want_mid, 1e-12);
}

// Zero, negative and NaN input. Spec §4.8 says a zero channel comes out as −BlackClip; UE's code
// actually computes lerp(toe, straight = −∞, t = 0) = −B + 0·(−∞) = NaN for log10(0) = −∞, and the
// final max(0, ·) (D3D maxNum) turns it into 0. Only pure black reaches the curve with a zero (the
// 0.96 pre-desaturation lifts lone zero channels). A tiny positive value shows the −BlackClip
// limit.
TEST(FilmToneMap, ZeroNegativeAndNaN) {
  EXPECT_TRUE(std::isnan(g::film_curve(0.0, {})));
  g::FilmParams clip;
  clip.black_clip = 0.01;
  EXPECT_NEAR(g::film_curve(1e-30, clip), -0.01, 1e-15);
  EXPECT_EQ(g::film_tone_map({0.0, 0.0, 0.0}, clip), (Vec3{0.0, 0.0, 0.0}));
  EXPECT_EQ(g::film_tone_map({-1.0, -2.0, -0.5}, {}), (Vec3{0.0, 0.0, 0.0}));
  EXPECT_EQ(g::film_tone_map({kNaN, 0.2, 0.2}, {}), (Vec3{0.0, 0.0, 0.0}));
  const Vec3 lone_zero = g::film_tone_map({0.3, 0.0, 0.0}, {});
  EXPECT_FALSE(std::isnan(lone_zero[1]));
  EXPECT_GT(lone_zero[0], 0.0);
}

// ---------------------------------------------------------------------------------------------
// Blue correction and the SDR film path

// Spec §4.8 AP1 forms (printed to 10 decimals; re-derived as the same literal products). The
// BlueCorrect literal keeps AP0 grey (row sums measured 1 ± 1.0e-10); the 6-digit inverse literal
// makes Inv·Blue miss the identity by 3.4e-6 (measured).
TEST(BlueCorrection, MatricesAndRoundTrip) {
  expect_matrix(g::blue_correct_ap1(),
                Mat3{{0.9386393778, 0, 0.0613606221, 0, 0.8307941329, 0.1692058671, 0, 0, 1}},
                5e-10);
  expect_matrix(g::blue_correct_inv_ap1(),
                Mat3{{1.0653748754, 0.0000014468, -0.0653710053, -0.0000003455, 1.2036635244,
                      -0.2036677199, 0.0000000199, 0.0000000212, 0.9999996001}},
                5e-10);
  for (int r = 0; r < 3; ++r) {
    const double row =
        g::kBlueCorrectAp0(r, 0) + g::kBlueCorrectAp0(r, 1) + g::kBlueCorrectAp0(r, 2);
    EXPECT_NEAR(row, 1.0, 2e-10);
  }
  const Mat3 round_trip = g::blue_correct_inv_ap1() * g::blue_correct_ap1();
  EXPECT_LT(max_abs_diff(round_trip, Mat3::identity()), 5e-6);
  EXPECT_GT(max_abs_diff(round_trip, Mat3::identity()), 1e-7);
}

// With ToneCurveAmount 0 the film path is blue-correct then un-blue-correct: grey drifts only by
// the inverse literal's error (measured 3.2e-6 relative at BlueCorrection 0.6; spec: ~5e-6).
TEST(BlueCorrection, FilmPathWithoutCurveNearlyIdentityOnGrey) {
  g::FilmPathParams p;
  p.tone_curve_amount = 0.0;
  const Vec3 out = g::film_path_ap1({0.18, 0.18, 0.18}, p);
  for (double c : out) EXPECT_NEAR(c, 0.18, 0.18 * 5e-6);
  p.blue_correction = 0.0;
  EXPECT_EQ(g::film_path_ap1({0.3, 0.2, 0.1}, p), (Vec3{0.3, 0.2, 0.1}));
}

// Spec §13: SDR sRGB code for scene grey 0.18 ≈ 0.4613561 (= LinearToSrgb(0.18) = 0.4613561295) and
// for 1.0 ≈ 0.8668283 (FilmToneMap then the IEC 61966-2-1 encode, ignoring blue-correction drift).
// Full film path, sRGB WCS, BlueCorrection 0: measured 1.9e-8 (bound 1e-7: the spec's 7 decimals).
// With the default BlueCorrection 0.6 the inverse literal's drift shows: measured 2.7e-6, bound
// 5e-6.
TEST(BlueCorrection, SdrGreyCodes) {
  auto srgb_encode = [](double v) {
    return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
  };
  const WorkingColorSpace& wcs = srgb_wcs();
  g::FilmPathParams no_blue;
  no_blue.blue_correction = 0.0;
  for (const auto& [p, tol] : {std::pair{no_blue, 1e-7}, std::pair{g::FilmPathParams{}, 5e-6}}) {
    const Vec3 grey = g::film_color(wcs.to_ap1 * Vec3{0.18, 0.18, 0.18}, p, wcs);
    const Vec3 one = g::film_color(wcs.to_ap1 * Vec3{1.0, 1.0, 1.0}, p, wcs);
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(srgb_encode(grey[i]), 0.4613561295, tol) << i;
      EXPECT_NEAR(srgb_encode(one[i]), 0.8668283, tol) << i;
    }
  }
  const Vec3 nan_out = g::film_color({kNaN, 0.1, 0.1}, {}, wcs);
  EXPECT_EQ(nan_out, (Vec3{0.0, 0.0, 0.0}));
}

// ---------------------------------------------------------------------------------------------
// r.Color polynomial, fade, gamma

// Defaults (0, 0.5, 1) give a = 0, b = 1, c = 0 exactly. A non-default set must pass through
// (0, Min), (0.5, Mid), (1, Max) — the property GetMappingPolynomial solves for.
TEST(ColorPolynomial, MappingPolynomial) {
  const g::MappingPolynomial d = g::get_mapping_polynomial({});
  EXPECT_EQ(d.a, 0.0);
  EXPECT_EQ(d.b, 1.0);
  EXPECT_EQ(d.c, 0.0);
  EXPECT_EQ(g::apply_mapping_polynomial({0.3, 0.7, 2.0}, d), (Vec3{0.3, 0.7, 2.0}));

  const g::MappingPolynomial p = g::get_mapping_polynomial({0.1, 0.6, 0.9});
  const Vec3 out = g::apply_mapping_polynomial({0.0, 0.5, 1.0}, p);
  EXPECT_NEAR(out[0], 0.1, 1e-7);  // float arithmetic on the host (UE's C++)
  EXPECT_NEAR(out[1], 0.6, 1e-7);
  EXPECT_NEAR(out[2], 0.9, 1e-7);
  EXPECT_EQ(p.a, static_cast<double>(0.9f - 0.1f - (4 * 0.6f - 3 * 0.1f - 0.9f)));

  // Clamped to [−10, 10]; FMath::Clamp sends NaN to the upper bound.
  const g::MappingPolynomial c = g::get_mapping_polynomial({-20.0, 0.5, kNaN});
  EXPECT_EQ(c.c, -10.0);
  EXPECT_EQ(c.b, 4 * 0.5 + 30.0 - 10.0);
}

// Fade: defaults are the identity; OverlayColor.a blends towards OverlayColor.rgb.
TEST(ColorPolynomial, Fade) {
  const Vec3 c{0.2, 0.4, 0.8};
  EXPECT_EQ(g::apply_fade(c, {}), c);
  g::Fade f;
  f.color_scale = {0.5, 0.5, 0.5};
  f.overlay_color = {1.0, 0.0, 0.0, 0.25};
  expect_vec(g::apply_fade(c, f), {0.1 * 0.75 + 0.25, 0.2 * 0.75, 0.4 * 0.75}, 1e-16);
  f.overlay_color[3] = 1.0;
  EXPECT_EQ(g::apply_fade(c, f), (Vec3{1.0, 0.0, 0.0}));
}

// InverseGamma = (1/DisplayGamma, 2.2/DisplayGamma, 1/max(Gamma, 1)) in float: at the default
// DisplayGamma 2.2 the film-path exponent is exactly 1. Gamma 0 (unset) gives z = 1.
TEST(ColorPolynomial, InverseGamma) {
  const g::InverseGamma d = g::get_inverse_gamma(2.2, 0.0);
  EXPECT_EQ(d.x, static_cast<double>(1.0f / 2.2f));
  EXPECT_EQ(d.y, 1.0);
  EXPECT_EQ(d.z, 1.0);
  const g::InverseGamma m = g::get_inverse_gamma(2.4, 2.2);
  EXPECT_NEAR(m.y, 2.2 / 2.4, 1e-7);
  EXPECT_EQ(m.z, static_cast<double>(1.0f / 2.2f));
  const Vec3 out = g::apply_film_gamma({0.25, -0.1, kNaN}, {0.5, 0.5, 1.0});
  EXPECT_EQ(out[0], 0.5);
  EXPECT_EQ(out[1], 0.0);
  EXPECT_EQ(out[2], 0.0);
}

}  // namespace

namespace {

// ColorGamma at its 0.01 edge raises to the power 100: float32 (UE's shader) overflows to +Inf
// above 2^(128/100) = 2.42, where double would carry 3.0^100 = 5.2e47 on. The reference keeps
// float32's range (docs/ue55-decisions.md, closures of issue 11): 2.4^100 = 1.0e38 stays finite,
// 2.5^100 = 6.2e39 is +Inf; the zone blend's Inf · 0 is then NaN, as on the GPU.
TEST(GradingColorCorrect, Float32OverflowAtTheGammaEdge) {
  namespace g = hdrc::ref::grading;
  g::ColorCorrectZone z;
  z.gamma = {0.01, 0.01, 0.01, 1.0};
  // AP1 grey 2.4 (luma 2.4): saturation 1 keeps it; contrast 1: pow(2.4/0.18, 1)·0.18 = 2.4.
  const Vec3 low = g::color_correct({2.4, 2.4, 2.4}, z);
  EXPECT_TRUE(std::isfinite(low[0]));
  EXPECT_NEAR(low[0] / std::pow(2.4, 100.0), 1.0, 1e-12);
  const Vec3 high = g::color_correct({2.5, 2.5, 2.5}, z);
  EXPECT_EQ(high[0], std::numeric_limits<double>::infinity());
  // The float32 threshold itself: the largest float, FLT_MAX, is finite; half an ulp more is Inf.
  EXPECT_EQ(hdrc::ref::grading::hlsl::f32_range(0x1.fffffep+127), 0x1.fffffep+127);
  EXPECT_TRUE(std::isinf(hdrc::ref::grading::hlsl::f32_range(0x1.ffffffp+127)));
  EXPECT_EQ(hdrc::ref::grading::hlsl::f32_range(-1e39), -std::numeric_limits<double>::infinity());
  // Blended with a zero weight (ColorCorrectAll: highlights weight 0 for a mid grey) Inf · 0 is
  // NaN in float32 and here.
  EXPECT_TRUE(std::isnan(high[0] * 0.0));
}

}  // namespace
