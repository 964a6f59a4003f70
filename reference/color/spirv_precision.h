// What a conformant Vulkan device may compute for a float32 operation, as an interval around the
// exact value: the error bounds of the Vulkan specification's "Precision and Operation of SPIR-V
// Instructions" (appendix spirvenv, spirvenv-op-prec; float32, no RelaxedPrecision) applied in
// interval arithmetic, the way VK-GL-CTS's vktShaderBuiltinPrecisionTests.cpp checks a result
// against the range its inputs' ranges admit. docs/precision.md, "Device allowances".
//
//   OpFAdd, OpFSub, OpFMul, conversions   correctly rounded        (0.5 ULP, either direction here)
//   OpFDiv                                2.5 ULP                  (|y| in [2^-126, 2^126])
//   exp2(x), exp(x)                       3 + 2·|x| ULP
//   log2(x), log(x)                       3 ULP outside [0.5, 2], absolute < 2^-21 inside
//   pow(x, y)                             inherited from exp2(y · log2(x))
//   a·b + c                               fused (one rounding) or not (two), unless NoContraction
//
// ULP as the specification defines it (spirvenv-ulp): the distance between the two float32 values
// nearest x, 2^(e − 23) for a normal float of exponent e, 2^-149 for subnormals.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace hdrc::ref::spirv {

// ulp(x) of float32 (spirvenv-ulp): 2^(floor(log2|x|) − 23) for |x| ≥ 2^-126, 2^-149 below.
inline double ulp32(double x) {
  const double a = std::fabs(x);
  if (!(a >= 0x1p-126)) return 0x1p-149;
  if (std::isinf(a)) return std::numeric_limits<double>::infinity();
  // 2^E for a in [2^E, 2^(E+1)): a's exponent bits alone (a is a normal double here), times 2^-23.
  return std::bit_cast<double>(std::bit_cast<std::uint64_t>(a) & 0x7ff0000000000000ULL) * 0x1p-23;
}

// A closed interval of real numbers a float32 evaluation may produce. Every operation widens
// outward by the specification's bound of the operation on top of the exact result over the
// operand intervals (monotone pieces only: the callers pass operands where the functions are
// monotone, as PQ's and the encodes' steps are).
struct Interval {
  double lo = 0, hi = 0;
  static Interval point(double v) { return {v, v}; }
  double width() const { return hi - lo; }
  bool contains(double v) const { return lo <= v && v <= hi; }
};

// [lo − n·ulp(lo), hi + n·ulp(hi)].
inline Interval widen_ulp(Interval r, double n) {
  return {r.lo - n * ulp32(r.lo), r.hi + n * ulp32(r.hi)};
}

inline Interval add(Interval a, Interval b) {
  return widen_ulp({a.lo + b.lo, a.hi + b.hi}, 0.5);
}
inline Interval sub(Interval a, Interval b) {
  return widen_ulp({a.lo - b.hi, a.hi - b.lo}, 0.5);
}
inline Interval mul_exact(Interval a, Interval b) {
  const double p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
  return {*std::min_element(p, p + 4), *std::max_element(p, p + 4)};
}
inline Interval mul(Interval a, Interval b) {
  return widen_ulp(mul_exact(a, b), 0.5);
}
// OpFDiv: 2.5 ULP. `b` must not contain 0.
inline Interval div(Interval a, Interval b) {
  const double q[4] = {a.lo / b.lo, a.lo / b.hi, a.hi / b.lo, a.hi / b.hi};
  return widen_ulp({*std::min_element(q, q + 4), *std::max_element(q, q + 4)}, 2.5);
}
// a·b + c where the device may or may not fuse: the union of one rounding (fused) and two
// (unfused) — the unfused one contains the fused one's, since its first rounding only widens.
inline Interval mul_add(Interval a, Interval b, Interval c) {
  return add(mul(a, b), c);
}
// fused only (GLSL fma(), OpExtInst Fma: inherited from OpFMul then OpFAdd — the same bound).
inline Interval fma(Interval a, Interval b, Interval c) {
  return mul_add(a, b, c);
}

// exp2: 3 + 2·|x| ULP of the result. Nondecreasing.
inline Interval exp2(Interval x) {
  const double lo = std::exp2(x.lo), hi = std::exp2(x.hi);
  return {lo - (3.0 + 2.0 * std::fabs(x.lo)) * ulp32(lo),
          hi + (3.0 + 2.0 * std::fabs(x.hi)) * ulp32(hi)};
}

// log2: 3 ULP outside [0.5, 2], absolute 2^-21 inside. Nondecreasing; x.lo > 0.
inline Interval log2(Interval x) {
  auto bound = [](double v, double r) { return v >= 0.5 && v <= 2.0 ? 0x1p-21 : 3.0 * ulp32(r); };
  const double lo = std::log2(x.lo), hi = std::log2(x.hi);
  return {lo - bound(x.lo, lo), hi + bound(x.hi, hi)};
}

// pow(x, y), y > 0 a constant: inherited from exp2(y·log2 x) (spirvenv-inherited-from): the
// formula's own steps each within their bounds; the multiply by y correctly rounded. x.lo > 0.
inline Interval pow(Interval x, double y) {
  return exp2(mul(log2(x), Interval::point(y)));
}

}  // namespace hdrc::ref::spirv
