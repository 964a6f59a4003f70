// ACES RRT helper functions shared by the HDR output transform (aces_output.h) and UE's SDR
// FilmToneMap (TonemapCommon.ush), in double precision.
//
// Source: Engine/Shaders/Private/ACES.ush (UE 5.0-era copy, chenyong2github/UnrealEngine, commit
// 09c29cbee980f5c5fbff6c93cf6132e5f4bcf97a; the 5.5 file is not public, docs/spec/ue55.md §5.1
// [R]), which follows ACESlib.RRT_Common.ctl / ACESlib.Utilities_Color.ctl of aces-dev v1.3. Spec
// §4.8 step 2 and §5.1 step 1.
//
// Non-finite values follow D3D HLSL (color/d3d_math.h): HLSL min/max are IEEE-754-2008
// minNum/maxNum (a NaN operand yields the other operand), which is what std::fmin/std::fmax and
// their inlined equivalents d3d::min_num/max_num do; comparisons with NaN are false; clamp(x, a,
// b) is min(max(x, a), b) and therefore maps NaN to a.
#pragma once

#include <cmath>
#include <numbers>

#include "color/d3d_math.h"
#include "color/vec.h"

namespace hdrc::ref::aces {

// ACES.ush RRT constants, shared by the output transform's sweeteners and FilmToneMap.
inline constexpr double kRrtGlowGain = 0.05;   // RRT_GLOW_GAIN
inline constexpr double kRrtGlowMid = 0.08;    // RRT_GLOW_MID
inline constexpr double kRrtRedScale = 0.82;   // RRT_RED_SCALE
inline constexpr double kRrtRedPivot = 0.03;   // RRT_RED_PIVOT
inline constexpr double kRrtRedHue = 0.0;      // RRT_RED_HUE, degrees
inline constexpr double kRrtRedWidth = 135.0;  // RRT_RED_WIDTH, degrees

// ACES.ush: rgb_2_saturation. (max(maxc, 1e-10) − max(minc, 1e-10)) / max(maxc, 0.01).
// NaN channels are skipped by maxNum/minNum; all-NaN gives (1e-10 − 1e-10)/0.01 = 0.
inline double rgb_2_saturation(const Vec3& rgb) {
  const double minrgb = d3d::min_num(d3d::min_num(rgb[0], rgb[1]), rgb[2]);
  const double maxrgb = d3d::max_num(d3d::max_num(rgb[0], rgb[1]), rgb[2]);
  return (d3d::max_num(maxrgb, 1e-10) - d3d::max_num(minrgb, 1e-10)) / d3d::max_num(maxrgb, 1e-2);
}

// ACES.ush: rgb_2_yc, YC = (r + g + b + w·sqrt(b(b−g) + g(g−r) + r(r−b))) / 3, w = 1.75.
// The radicand equals ½((r−g)² + (g−b)² + (b−r)²) ≥ 0, so sqrt only sees NaN from NaN input.
inline double rgb_2_yc(const Vec3& rgb, double yc_radius_weight = 1.75) {
  const double r = rgb[0], g = rgb[1], b = rgb[2];
  const double chroma = std::sqrt(b * (b - g) + g * (g - r) + r * (r - b));
  return (b + g + r + yc_radius_weight * chroma) / 3.0;
}

// HLSL sign(): −1, 0 or +1; DXIL lowers it to (x > 0) − (x < 0), so sign(NaN) = 0.
inline double hlsl_sign(double x) {
  return static_cast<double>((x > 0.0) - (x < 0.0));
}

// ACES.ush: sigmoid_shaper, a sigmoid from 0 to 1 spanning x in [−2, 2].
inline double sigmoid_shaper(double x) {
  const double t = d3d::max_num(1.0 - std::fabs(0.5 * x), 0.0);
  const double y = 1.0 + hlsl_sign(x) * (1.0 - t * t);
  return 0.5 * y;
}

// ACES.ush: glow_fwd. A NaN yc fails both comparisons and takes the last branch (NaN).
inline double glow_fwd(double yc_in, double glow_gain_in, double glow_mid) {
  if (yc_in <= 2.0 / 3.0 * glow_mid) return glow_gain_in;
  if (yc_in >= 2.0 * glow_mid) return 0.0;
  return glow_gain_in * (glow_mid / yc_in - 0.5);
}

// ACES.ush: rgb_2_hue, in degrees [0, 360]. UE returns 0 (not the CTL's NaN) for r = g = b.
// A NaN hue from atan2 becomes 0 through HLSL clamp (max(NaN, 0) = 0).
inline double rgb_2_hue(const Vec3& rgb) {
  double hue;
  if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) {
    hue = 0.0;
  } else {
    hue = (180.0 / std::numbers::pi) *
          std::atan2(std::sqrt(3.0) * (rgb[1] - rgb[2]), 2.0 * rgb[0] - rgb[1] - rgb[2]);
  }
  if (hue < 0.0) hue += 360.0;
  return d3d::min_num(d3d::max_num(hue, 0.0), 360.0);
}

// ACES.ush: center_hue, wraps hue − centre into [−180, 180].
inline double center_hue(double hue, double center_h) {
  double hue_centered = hue - center_h;
  if (hue_centered < -180.0) {
    hue_centered += 360.0;
  } else if (hue_centered > 180.0) {
    hue_centered -= 360.0;
  }
  return hue_centered;
}

// ACES.ush: cubic_basis_shaper, the RRT red modifier's uniform cubic B-spline of full base width
// `w` degrees, scaled by 1.5 so that it peaks at 1 for x = 0; 0 outside (−w/2, w/2).
// knot_coord = (x + w/2)·4/w, j = int(knot_coord) (truncation; knot_coord > 0 here),
// t = knot_coord − j, y = Σ_k m_k·M[k][3−j] with m = (t³, t², t, 1) and
// M = (1/6)[[−1, 3, −3, 1], [3, −6, 3, 0], [−3, 0, 3, 0], [1, 4, 1, 0]].
inline double cubic_basis_shaper(double x, double w) {
  static constexpr double kM[4][4] = {{-1.0 / 6, 3.0 / 6, -3.0 / 6, 1.0 / 6},
                                      {3.0 / 6, -6.0 / 6, 3.0 / 6, 0.0 / 6},
                                      {-3.0 / 6, 0.0 / 6, 3.0 / 6, 0.0 / 6},
                                      {1.0 / 6, 4.0 / 6, 1.0 / 6, 0.0 / 6}};
  double y = 0.0;
  if (x > -0.5 * w && x < 0.5 * w) {
    const double knot_coord = (x + 0.5 * w) * 4.0 / w;
    const int j = static_cast<int>(knot_coord);
    const double t = knot_coord - j;
    const double m[4] = {t * t * t, t * t, t, 1.0};
    if (j >= 0 && j <= 3) {
      const int col = 3 - j;
      y = m[0] * kM[0][col] + m[1] * kM[1][col] + m[2] * kM[2][col] + m[3] * kM[3][col];
    }
  }
  return y * 1.5;
}

}  // namespace hdrc::ref::aces
