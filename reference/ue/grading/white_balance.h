// White balance of the CombineLUTs pass (docs/spec/ue55.md §4.4), as UE 5.5 computes it.
//
// Shader: Engine/Shaders/Private/TonemapCommon.ush (izzy2lost/UnrealEngineUWP 5.5, commit
// aff11acf0c218535669021f6e646b3bcf6ad94a5): PlanckianLocusChromaticity, D_IlluminantChromaticity,
// PlanckianIsothermal, WhiteBalance. Chromatic adaptation: ACES.ush: ChromaticAdaptation (Bradford
// with UE's 7-digit InvConeResponse literal). C++ side: PostProcessCombineLUTs.cpp (5.5) selects
// the SKIP_TEMPERATURE permutation and sets bIsTemperatureWhiteBalance.
//
// All chromaticities are CIE 1931 xy; temperatures are kelvin; tint is UE's WhiteTint (offset along
// the isotherm in units of 0.05 CIE 1960 uv).
#pragma once

#include "color/vec.h"
#include "reference/color/ue_matrices.h"

namespace hdrc::ref::grading {

struct Chromaticity {
  double x = 0.0, y = 0.0;  // CIE 1931
};

// TonemapCommon.ush: PlanckianLocusChromaticity — Krystek 1985 rational approximation of the
// Planckian locus in CIE 1960 (u, v), converted to xy. UE states it is accurate for 1000–15000 K.
Chromaticity planckian_locus_chromaticity(double temp_k);

// TonemapCommon.ush: D_IlluminantChromaticity — CIE daylight locus (CIE 15, eq. 3.3/3.2) evaluated
// at temp_k·1.4388/1.438: UE's input is the *nominal* temperature (pre-1968 c2 = 1.438e-2 m·K), so
// 6500 gives the D65 CCT 6503.6 K and 5000 gives D50's 5002.8 K. UE states 4000–25000 K.
Chromaticity d_illuminant_chromaticity(double temp_k);

// TonemapCommon.ush: PlanckianIsothermal — the Planckian point moved by tint·0.05 along the unit
// normal of the locus in (u, v): u += vd·tint·0.05, v −= ud·tint·0.05, (ud, vd) the normalised
// derivative of Krystek's (u, v) with respect to temperature.
Chromaticity planckian_isothermal(double temp_k, double tint);

// CIE 1931 xy → XYZ at Y = 1, as ACES.ush: xyY_2_XYZ (y guarded by max(y, 1e-10)).
Vec3 xyz_from_xy(Chromaticity xy);

// Bradford cone-response matrix and UE's literal for its inverse (ACES.ush: ChromaticAdaptation).
// The literal is rounded to 7 digits; it is not the exact inverse (see grading_test.cpp for the
// gap).
extern const Mat3 kBradfordCone;
extern const Mat3 kBradfordInvConeLiteral;

// ACES.ush: ChromaticAdaptation(src_xy, dst_xy) — von Kries in Bradford cone space, XYZ → XYZ:
// InvCone_literal · diag((Cone·XYZ_dst)/(Cone·XYZ_src)) · Cone.
Mat3 chromatic_adaptation(Chromaticity src, Chromaticity dst);

// D65 as TonemapCommon.ush: WhiteBalance writes it.
inline constexpr Chromaticity kWhiteBalanceD65{0.31270, 0.32900};

// FPostProcessSettings::TemperatureType (ETemperatureMethod).
enum class TemperatureType : int { kWhiteBalance = 0, kColorTemperature = 1 };

// The white-balance inputs of FCombineLUTParameters. Defaults: Scene.cpp FPostProcessSettings.
struct WhiteBalanceParams {
  double white_temp = 6500.0;  // kelvin
  double white_tint = 0.0;
  TemperatureType temperature_type = TemperatureType::kWhiteBalance;
};

// PostProcessCombineLUTs.cpp: the SKIP_TEMPERATURE permutation is chosen when
// FMath::IsNearlyEqual(WhiteTemp, 6500) && FMath::IsNearlyEqual(WhiteTint, 0) with UE's default
// tolerance UE_SMALL_NUMBER = 1e-8 (|a − b| <= 1e-8). The maths is *not* an identity at 6500 K
// (D_Illuminant(6500) ≠ D65), so skipping changes the result by up to ~8e-4 per channel.
inline constexpr double kSkipTemperatureTolerance = 1e-8;
bool white_balance_skipped(const WhiteBalanceParams& p);

// The source and destination whites TonemapCommon.ush: WhiteBalance adapts between:
// src = (T < 4000 ? Planckian(T) : D_Illuminant(T)) + (PlanckianIsothermal(T, tint) −
// Planckian(T)), dst = D65; swapped when TemperatureType is kColorTemperature
// (bIsTemperatureWhiteBalance == 0).
struct WhiteBalanceWhites {
  Chromaticity src, dst;
};
WhiteBalanceWhites white_balance_whites(const WhiteBalanceParams& p);

// M = FromXYZ · ChromaticAdaptation(src, dst) · ToXYZ with the working colour space's (float-cast)
// matrices; out = M · in, linear working-colour-space RGB. Ignores the skip rule.
Mat3 white_balance_matrix(const WhiteBalanceParams& p, const WorkingColorSpace& wcs);

// CombineLUTsCommon's white-balance step: the input unchanged when white_balance_skipped(p), else
// white_balance_matrix(p, wcs) · linear.
Vec3 white_balance(const Vec3& linear, const WhiteBalanceParams& p, const WorkingColorSpace& wcs);

}  // namespace hdrc::ref::grading
