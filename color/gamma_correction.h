// UE 5.5's display transfer functions (GammaCorrectionCommon.ush, docs/spec/ue55.md §3.3), in
// double precision, for the HDR UI composite (CompositeUIPixelShader.usf: LinearizeColor) and the
// SDR output devices.
//
// Source: chenyong2github/UnrealEngine, Engine/Shaders/Private/GammaCorrectionCommon.ush (5.0-era,
// commit 109c6a2d): sRGBToLinear, Rec709ToLinear, LinearToSrgbBranchingChannel,
// LinearToSrgbBranchless, LinearTo709Branchless. The constants are UE's (0.0521327 is UE's
// truncation of 0.055 / 1.055; 0.00313067 is UE's linear-segment threshold, IEC 61966-2-1 has
// 0.0031308).
//
// The max(6.10352e-5, x) clamp: UE 4.x/5.0 copies apply it first in the four non-branching
// functions ("minimum positive non-denormal"); the 5.8 copy does not. Whether 5.5 has it is open
// (docs/ue55-decisions.md D3); every function that might clamp takes a MinNormalClamp argument,
// default ON as D3 decides. LinearToSrgbBranchingChannel never clamps in any version.
//
// Non-finite inputs follow D3D (docs/ue55-decisions.md D-NF): max/min are IEEE maxNum/minNum
// (std::fmax/fmin: a NaN operand yields the other operand), HLSL pow is d3d::pow.
#pragma once

#include <cmath>

#include "color/d3d_math.h"
#include "color/vec.h"

namespace hdrc::ref {

// docs/ue55-decisions.md D3: whether 5.5 clamps to the smallest positive float16 normal.
enum class MinNormalClamp { kOff, kOn };
inline constexpr MinNormalClamp kDefaultMinNormalClamp = MinNormalClamp::kOn;  // D3 decision
inline constexpr double kMinNormal = 6.10352e-5;  // UE's literal; float16 min normal 2^-14

namespace detail {
inline double apply_clamp(double x, MinNormalClamp clamp) {
  return clamp == MinNormalClamp::kOn ? std::fmax(kMinNormal, x) : x;
}
}  // namespace detail

// sRGBToLinear(c): c > 0.04045 ? (c / 1.055 + 0.0521327)^2.4 : c / 12.92. HLSL select()
// evaluates both arms; the unselected pow of a negative base is discarded, so negatives (clamp
// off) map to c / 12.92 and NaN (clamp off) stays NaN. With the clamp, NaN and everything below
// 6.10352e-5 map to 6.10352e-5 / 12.92 = 4.72409e-6.
inline double srgb_to_linear(double c, MinNormalClamp clamp = kDefaultMinNormalClamp) {
  c = detail::apply_clamp(c, clamp);
  return c > 0.04045 ? d3d::pow(c * (1.0 / 1.055) + 0.0521327, 2.4) : c * (1.0 / 12.92);
}

// Rec709ToLinear(c): c > 0.081 ? ((c + 0.099) / 1.099)^(1 / 0.45) : c / 4.5 (BT.709 OETF
// inverse). Same select and clamp behaviour as srgb_to_linear.
inline double rec709_to_linear(double c, MinNormalClamp clamp = kDefaultMinNormalClamp) {
  c = detail::apply_clamp(c, clamp);
  return c > 0.081 ? d3d::pow((c + 0.099) / 1.099, 1.0 / 0.45) : c / 4.5;
}

// LinearToSrgbBranchingChannel: the desktop LinearToSrgb (FEATURE_LEVEL > ES3_1). Never clamped.
// x < 0.00313067 (negatives included) → 12.92·x; NaN fails the test and reaches pow → NaN.
inline double linear_to_srgb(double x) {
  if (x < 0.00313067) return x * 12.92;
  return d3d::pow(x, 1.0 / 2.4) * 1.055 - 0.055;
}

// LinearToSrgbBranchless: min(12.92·x, 1.055·max(x, 0.00313067)^(1/2.4) − 0.055) (mobile
// LinearToSrgb; LinearToPostTonemapSpace). With the clamp, black maps to 7.8858e-4, not 0.
inline double linear_to_srgb_branchless(double x, MinNormalClamp clamp = kDefaultMinNormalClamp) {
  x = detail::apply_clamp(x, clamp);
  return std::fmin(x * 12.92, d3d::pow(std::fmax(x, 0.00313067), 1.0 / 2.4) * 1.055 - 0.055);
}

// LinearTo709Branchless: min(4.5·x, 1.099·max(x, 0.018)^0.45 − 0.099) (device 1, SDR_Rec709).
// With the clamp, black maps to 4.5 · 6.10352e-5 = 2.74658e-4.
inline double linear_to_rec709_branchless(double x, MinNormalClamp clamp = kDefaultMinNormalClamp) {
  x = detail::apply_clamp(x, clamp);
  return std::fmin(x * 4.5, d3d::pow(std::fmax(x, 0.018), 0.45) * 1.099 - 0.099);
}

// Per-channel versions (HLSL's half3 overloads).
inline Vec3 srgb_to_linear(const Vec3& c, MinNormalClamp clamp = kDefaultMinNormalClamp) {
  return {srgb_to_linear(c[0], clamp), srgb_to_linear(c[1], clamp), srgb_to_linear(c[2], clamp)};
}
inline Vec3 rec709_to_linear(const Vec3& c, MinNormalClamp clamp = kDefaultMinNormalClamp) {
  return {rec709_to_linear(c[0], clamp), rec709_to_linear(c[1], clamp),
          rec709_to_linear(c[2], clamp)};
}
inline Vec3 linear_to_srgb(const Vec3& x) {
  return {linear_to_srgb(x[0]), linear_to_srgb(x[1]), linear_to_srgb(x[2])};
}
inline Vec3 linear_to_srgb_branchless(const Vec3& x,
                                      MinNormalClamp clamp = kDefaultMinNormalClamp) {
  return {linear_to_srgb_branchless(x[0], clamp), linear_to_srgb_branchless(x[1], clamp),
          linear_to_srgb_branchless(x[2], clamp)};
}
inline Vec3 linear_to_rec709_branchless(const Vec3& x,
                                        MinNormalClamp clamp = kDefaultMinNormalClamp) {
  return {linear_to_rec709_branchless(x[0], clamp), linear_to_rec709_branchless(x[1], clamp),
          linear_to_rec709_branchless(x[2], clamp)};
}

}  // namespace hdrc::ref
