// SDR output curves of UE 5.5 (GammaCorrectionCommon.ush, spec §3.3).
#pragma once

#include <cmath>

#include "reference/color/d3d_math.h"

namespace hdrc::ref::srgb {

// UE4/5.0 copies clamp to the smallest positive float16 normal before the branchless curves
// ("minimum positive non-denormal"); whether 5.5 still does is open (docs/ue55-decisions.md D3).
// The reference keeps the clamp (D3's decision), which lifts Rec.709 black to 2.7466e-4.
inline constexpr bool kMinNormalClamp = true;
inline constexpr double kMinNormal = 6.10352e-5;

// LinearToSrgbBranchingChannel: the desktop sRGB device (FEATURE_LEVEL > ES3_1). No clamp.
inline double linear_to_srgb(double x) {
  if (std::isnan(x)) return x;
  return x < 0.00313067 ? 12.92 * x : 1.055 * d3d::pow(x, 1.0 / 2.4) - 0.055;
}

// LinearToSrgbBranchless (mobile / ES3.1).
inline double linear_to_srgb_branchless(double x) {
  if (kMinNormalClamp) x = std::fmax(kMinNormal, x);
  return std::fmin(12.92 * x, 1.055 * d3d::pow(std::fmax(x, 0.00313067), 1.0 / 2.4) - 0.055);
}

// LinearTo709Branchless: device 1 (SDR_Rec709).
inline double linear_to_rec709(double x) {
  if (kMinNormalClamp) x = std::fmax(kMinNormal, x);
  return std::fmin(4.5 * x, 1.099 * d3d::pow(std::fmax(x, 0.018), 0.45) - 0.099);
}

// sRGBToLinear (UI textures; the diff's SDR decode): c > 0.04045 ? (c/1.055 + 0.0521327)^2.4 :
// c/12.92, with the optional minimum-normal clamp.
inline double srgb_to_linear(double c) {
  if (kMinNormalClamp) c = std::fmax(kMinNormal, c);
  return c > 0.04045 ? d3d::pow(c / 1.055 + 0.0521327, 2.4) : c / 12.92;
}

// Rec709ToLinear: c > 0.081 ? ((c + 0.099)/1.099)^(1/0.45) : c/4.5.
inline double rec709_to_linear(double c) {
  if (kMinNormalClamp) c = std::fmax(kMinNormal, c);
  return c > 0.081 ? d3d::pow((c + 0.099) / 1.099, 1.0 / 0.45) : c / 4.5;
}

}  // namespace hdrc::ref::srgb
