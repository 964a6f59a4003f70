// ACES RRT helper functions that TonemapCommon.ush: FilmToneMap borrows from ACES.ush, restated in
// double. Source: Engine/Shaders/Private/ACES.ush (chenyong2github/UnrealEngine, 5.0-era ACES 1.3
// copy, commit 09c29cbee980f5c5fbff6c93cf6132e5f4bcf97a): rgb_2_saturation, rgb_2_yc,
// sigmoid_shaper, glow_fwd, rgb_2_hue, center_hue. They are the ACES 1.3 RRT functions
// (aces-dev ACESlib.RRT_Common.ctl / ACESlib.Utilities_Color.ctl) except that rgb_2_hue returns 0
// instead of NaN for neutral input and clamps to [0, 360].
//
// reference/aces/aces_common.h will hold the same helpers for the ACES output transform; these are
// kept separate on purpose until the two are deduplicated.
#pragma once

#include <cmath>
#include <numbers>

#include "reference/color/vec.h"
#include "reference/grading/hlsl_ops.h"

namespace hdrc::ref::grading::film {

// ACES.ush: rgb_2_saturation — (max(maxc, 1e-10) − max(minc, 1e-10)) / max(maxc, 0.01).
inline double rgb_2_saturation(const Vec3& rgb) {
  const double minc = hlsl::min(hlsl::min(rgb[0], rgb[1]), rgb[2]);
  const double maxc = hlsl::max(hlsl::max(rgb[0], rgb[1]), rgb[2]);
  return (hlsl::max(maxc, 1e-10) - hlsl::max(minc, 1e-10)) / hlsl::max(maxc, 1e-2);
}

// ACES.ush: rgb_2_yc — luminance proxy (r + g + b + w·chroma)/3, chroma = √(b(b−g) + g(g−r) +
// r(r−b)); the radicand is ½Σ(differences²) ≥ 0 for every real input. Default weight 1.75.
inline double rgb_2_yc(const Vec3& rgb, double yc_radius_weight = 1.75) {
  const double r = rgb[0], g = rgb[1], b = rgb[2];
  const double chroma = std::sqrt(b * (b - g) + g * (g - r) + r * (r - b));
  return (b + g + r + yc_radius_weight * chroma) / 3.0;
}

// ACES.ush: sigmoid_shaper — sigmoid in [0, 1] spanning x ∈ [−2, 2].
inline double sigmoid_shaper(double x) {
  const double t = hlsl::max(1.0 - std::fabs(0.5 * x), 0.0);
  const double y = 1.0 + hlsl::sign(x) * (1.0 - t * t);
  return 0.5 * y;
}

// ACES.ush: glow_fwd — gain G below (2/3)·mid, 0 above 2·mid, G·(mid/yc − 1/2) between.
inline double glow_fwd(double yc_in, double glow_gain_in, double glow_mid) {
  if (yc_in <= 2.0 / 3.0 * glow_mid) return glow_gain_in;
  if (yc_in >= 2.0 * glow_mid) return 0.0;
  return glow_gain_in * (glow_mid / yc_in - 0.5);
}

// ACES.ush: rgb_2_hue — geometric hue in degrees, (180/π)·atan2(√3(g − b), 2r − g − b), +360 when
// negative, clamped to [0, 360] (HLSL clamp: a NaN hue becomes 0). Neutral input returns 0 (UE's
// change; ACES returns NaN).
inline double rgb_2_hue(const Vec3& rgb) {
  double hue = 0.0;
  if (!(rgb[0] == rgb[1] && rgb[1] == rgb[2])) {
    hue = (180.0 / std::numbers::pi) *
          std::atan2(std::sqrt(3.0) * (rgb[1] - rgb[2]), 2.0 * rgb[0] - rgb[1] - rgb[2]);
  }
  if (hue < 0.0) hue += 360.0;
  return hlsl::min(hlsl::max(hue, 0.0), 360.0);
}

// ACES.ush: center_hue — hue − centre wrapped into [−180, 180].
inline double center_hue(double hue, double center) {
  double centered = hue - center;
  if (centered < -180.0) {
    centered += 360.0;
  } else if (centered > 180.0) {
    centered -= 360.0;
  }
  return centered;
}

}  // namespace hdrc::ref::grading::film
