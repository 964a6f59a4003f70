// The IEEE behaviour of the HLSL intrinsics UE's shaders rely on, as D3D (the platform UE 5.5 ships
// its HDR path on) defines them, so the double-precision reference produces the same non-finite
// values. GLSL leaves several of these undefined; the GPU port spells each out (gpu/shaders/lib/
// d3d_math.glsl). Decisions: docs/ue55-decisions.md, "Non-finite values".
#pragma once

#include <cmath>
#include <limits>

namespace hdrc::ref::d3d {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// HLSL pow(x, y) compiles to exp2(y · log2(x)): NaN for x < 0 (also for x = −Inf, where C's pow
// would give +Inf), NaN for NaN input, and NaN for pow(0, 0) (0 · −Inf), where C's pow gives 1.
inline double pow(double x, double y) {
  if (std::isnan(x) || x < 0.0 || (x == 0.0 && y == 0.0)) return kNaN;
  return std::pow(x, y);
}

// HLSL max/min: IEEE-754-2008 maxNum/minNum, which is what std::fmax/std::fmin compute. Without
// -ffinite-math-only GCC cannot inline those and calls libm for each. These answer the unambiguous
// case inline (ordered, unequal operands: the larger/smaller one, the only result maxNum/minNum
// allow) and hand NaN operands and equal operands (where ±0 may differ) to std::fmax/std::fmin,
// so the result is the library's bit for bit in every case.
inline double max_num(double a, double b) {
  if (std::islessgreater(a, b)) [[likely]] {
    return a > b ? a : b;  // maxsd, no branch
  }
  return std::fmax(a, b);
}

inline double min_num(double a, double b) {
  if (std::islessgreater(a, b)) [[likely]] {
    return a < b ? a : b;  // minsd
  }
  return std::fmin(a, b);
}

// saturate(NaN) = 0 on D3D (D3D11.3 functional spec §3.1.3 / DXIL saturate).
inline double saturate(double x) {
  if (std::isnan(x)) return 0.0;
  return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x);
}

// A sampler's clamp-to-edge addressing on a coordinate in [0, 1] units. A NaN coordinate selects no
// defined texel on any API; the reference propagates NaN so that a port producing NaN there is
// "consistent" and one producing a number is a visible mismatch (docs/ue55-decisions.md).
inline double clamp_address(double x) {
  if (std::isnan(x)) return x;
  return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x);
}

}  // namespace hdrc::ref::d3d
