// The few HLSL intrinsics the CombineLUTs grading code uses, with the D3D semantics UE relies on,
// in double. Shared by the grading modules; the non-finite rules follow color/d3d_math.h
// and docs/ue55-decisions.md (D-NaN).
#pragma once

#include <cmath>

#include "color/d3d_math.h"
#include "color/vec.h"

namespace hdrc::ref::grading::hlsl {

// HLSL lerp(a, b, t) as DXC lowers it: a + t·(b − a). With t = 0 and an infinite b this is NaN
// (0·∞), which FilmToneMap relies on being cleaned by a later max (see film_tonemap.h).
inline double lerp(double a, double b, double t) {
  return a + t * (b - a);
}
inline Vec3 lerp(const Vec3& a, const Vec3& b, double t) {
  return {lerp(a[0], b[0], t), lerp(a[1], b[1], t), lerp(a[2], b[2], t)};
}
inline Vec3 lerp(double a, const Vec3& b, double t) {
  return lerp(Vec3{a, a, a}, b, t);
}

// HLSL max/min on D3D are IEEE-754-2008 maxNum/minNum: a NaN operand yields the other operand,
// exactly what std::fmax/std::fmin do.
inline double max(double a, double b) {
  return std::fmax(a, b);
}
inline double min(double a, double b) {
  return std::fmin(a, b);
}
inline Vec3 max0(const Vec3& v) {
  return {max(0.0, v[0]), max(0.0, v[1]), max(0.0, v[2])};
}

// smoothstep(a, b, x) = t²(3 − 2t), t = saturate((x − a)/(b − a)); saturate(NaN) = 0 on D3D.
inline double smoothstep(double a, double b, double x) {
  const double t = d3d::saturate((x - a) / (b - a));
  return t * t * (3.0 - 2.0 * t);
}

// The float32 range of UE's shader arithmetic: a double result beyond it is what float32 would
// round to ±Inf (|x| >= FLT_MAX + half an ulp, 2^128 − 2^103), so a later step sees the same Inf
// (and 0·Inf = NaN) as the GPU. Used where a grading control can overflow float: ColorGamma at its
// 0.01 edge raises to the power 100 (docs/precision.md, float32 overflow).
inline double f32_range(double x) {
  constexpr double kOverflow = 0x1.ffffffp+127;
  return std::fabs(x) >= kOverflow ? std::copysign(INFINITY, x) : x;
}

// HLSL sign(): −1, 0 or +1 (0 for ±0).
inline double sign(double x) {
  return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0);
}

}  // namespace hdrc::ref::grading::hlsl
