// Device allowances: what a conformant Vulkan device may store and filter differently from a
// float32-exact one, as intervals the reference carries (core/image.h, Image::device_admissible;
// docs/precision.md, "Device allowances"). Pipeline-agnostic; each pipeline's reference applies
// them at its own LUT stores and lookups.
//
//  * Storage: a float → UNORM conversion returns "one of the two unsigned binary integer values
//    ... closest to" the value ("Implementations should round to nearest": a recommendation;
//    Vulkan spec, fundamentals-fpfixedconv), and a float → float16 conversion rounds with the
//    implementation's rounding mode unless the device's float controls guarantee RTE
//    (shaderRoundingModeRTEFloat16). store_either_way admits both neighbours.
//  * Filtering: the fraction of a linear filter's texel-space coordinate keeps
//    subTexelPrecisionBits fraction bits (Vulkan spec, textures-texel-filtering; the rounding is
//    not specified), so a weight α may be either grid value around the exact one: the box
//    [floor(α·2^b), ceil(α·2^b)]/2^b. The filtered value is linear in each weight, so its extremes
//    lie at the box's corners (VK-GL-CTS vktSampleVerifier.cpp checks the same way).
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "color/st2084.h"
#include "reference/color/linear_tap.h"
#include "reference/color/noise_range.h"
#include "reference/color/spirv_precision.h"

namespace hdrc::ref {

// The two neighbours a UNORM store of `v` (levels = 2^b − 1) may give, for a range: [floor, ceil]
// of the clamped ends. NaN: what a UNORM store makes of NaN is undefined in Vulkan; the callers
// decide (UE's D3D gives 0).
inline double unorm_floor(double v, double levels) {
  return std::floor(std::clamp(v, 0.0, 1.0) * levels) / levels;
}
inline double unorm_ceil(double v, double levels) {
  return std::ceil(std::clamp(v, 0.0, 1.0) * levels) / levels;
}

// The float16 values either side of `v` (v itself where a half holds it), by the same rounding
// as Imath::half's conversion: toward −inf and toward +inf. Overflow gives ±Inf (the RTE
// neighbour beyond 65504).
double half_round_down(double v);
double half_round_up(double v);

// float32 neighbours (the value a float32 store keeps: exact for a float already, else either).
inline double float_round_down(double v) {
  const float f = static_cast<float>(v);
  return static_cast<double>(f) <= v ? f : std::nextafter(f, -HUGE_VALF);
}
inline double float_round_up(double v) {
  const float f = static_cast<float>(v);
  return static_cast<double>(f) >= v ? f : std::nextafter(f, HUGE_VALF);
}

// One axis of a linear filter with the weight's box: the taps of linear_tap, and the range of the
// weight of i1 a device with `bits` sub-texel bits may use. `coord_noise` (texel units) widens the
// exact fraction first for the shader's own float32 error in the coordinate it passes.
struct TapBox {
  int i0 = 0, i1 = 0;
  double f_lo = 0, f_hi = 0;
};
inline TapBox linear_tap_box(double t, int size, int bits, double coord_noise) {
  const LinearTap tap = linear_tap(t, size);
  const double grid = std::ldexp(1.0, bits);
  TapBox b;
  b.i0 = tap.i0;
  b.i1 = tap.i1;
  b.f_lo = std::max(0.0, std::floor((tap.f - coord_noise) * grid) / grid);
  b.f_hi = std::min(1.0, std::ceil((tap.f + coord_noise) * grid) / grid);
  return b;
}

// `v` rounded down (upward false) or up onto the grid of a float format with `bits` fraction bits
// whose exponent is at least `min_exp` (tcuFloatFormat.cpp FloatFormat::round toward −inf or
// +inf): the quantum is 2^(max(E, min_exp) − bits) for |v| in [2^E, 2^(E+1)). Exact for 0 and
// non-finite values. Powers of two are formed from their bits and the scaling by them is exact (no
// frexp/ldexp: the worst-case device model rounds several times per tap of every filtered sample).
// Valid for min_exp − bits ≥ −1022 and |v| < 2^1023, which every format here meets.
inline double pow2_exact(int e) {  // 2^e for e in [−1022, 1023]
  return std::bit_cast<double>(static_cast<std::uint64_t>(e + 1023) << 52);
}
inline double round_to_float_grid(double v, bool upward, int bits, int min_exp) {
  if (v == 0 || !std::isfinite(v)) return v;
  const int biased = static_cast<int>((std::bit_cast<std::uint64_t>(v) >> 52) & 0x7ff);
  // A subnormal double (biased 0) lies far below min_exp; its own exponent does not matter.
  const int quantum = std::max(biased - 1023, min_exp) - bits;
  const double scaled = v * pow2_exact(-quantum);
  return (upward ? std::ceil(scaled) : std::floor(scaled)) * pow2_exact(quantum);
}

// The unnormalised coordinate as VK-GL-CTS lets a conformant device form it
// (vktSampleVerifier.cpp, SampleVerifier::verifySampleMipmapLevel and calcUnnormalizedCoordRange):
// the normalised coordinate u, then its product u·size, each rounded outward in
// FloatFormat(-32, 32, 16) — 16 fraction bits, "accurate to about 1 part in 10^5" as the
// specification's fundamentals-numerics asks of sampling — before calcTexelGridCoordRange snaps
// the range's ends to the sub-texel grid. The texel-space interval [t_lo, t_hi] (t = u·size − 1/2)
// widened so: at the far end of a 1024-texel strip about ±2^-6 texel (4 steps of an 8-bit
// weight), along a 17-texel LUT axis at most about ±2^-12. docs/precision.md, "Filter
// arithmetic".
inline double coord_format_round(double v, bool upward) {
  return round_to_float_grid(v, upward, 16, -32);
}
struct CoordRange {
  double lo = 0, hi = 0;
};
inline CoordRange cts_texel_range(double t_lo, double t_hi, int size) {
  const double s = static_cast<double>(size);
  const double u_lo = coord_format_round((t_lo + 0.5) / s, false);
  const double u_hi = coord_format_round((t_hi + 0.5) / s, true);
  return {coord_format_round(u_lo * s, false) - 0.5, coord_format_round(u_hi * s, true) - 0.5};
}

// The same where the coordinate's noise may carry it across a texel plane (a coordinate at or near
// a texel centre: a lattice stimulus, the first texel of an unwrapped LUT's slice): the filter then
// reads another pair of texels, with the lower one's weight near 1 − 2^-bits (the box of a
// fraction just under 1). The boxes at both ends of [t − noise, t + noise] and at every texel plane
// strictly between them (weight 0 of the upper neighbour there, the value the piece below reaches
// at weight 1): within one piece the filtered value is linear in the weight, so its extremes over
// the whole range lie among these boxes' corners (as strip_device_range.h's candidates).
// The coordinate's range also takes the CTS's rounding of the unnormalised coordinate
// (cts_texel_range): the boxes a hardware filter may use. Consecutive boxes of the same two taps
// are merged into one: the coordinates between theirs reach every fraction between, so the merged
// box is exact, and a lookup then evaluates one box per axis where the range stays in one cell.
// linear_tap_boxes_over: the same over a texel-space range [lo, hi] of the coordinate.
inline std::vector<TapBox> linear_tap_boxes_over(double lo, double hi, int size, int bits) {
  const CoordRange range = cts_texel_range(lo, hi, size);
  const double a = range.lo, b = range.hi;
  std::vector<TapBox> boxes;
  auto add = [&](const TapBox& box) {
    if (!boxes.empty() && boxes.back().i0 == box.i0 && boxes.back().i1 == box.i1) {
      boxes.back().f_lo = std::fmin(boxes.back().f_lo, box.f_lo);
      boxes.back().f_hi = std::fmax(boxes.back().f_hi, box.f_hi);
    } else {
      boxes.push_back(box);
    }
  };
  add(linear_tap_box(a, size, bits, 0.0));
  for (double k = std::floor(a) + 1; k < b; k += 1) add(linear_tap_box(k, size, bits, 0.0));
  if (b > a) add(linear_tap_box(b, size, bits, 0.0));
  return boxes;
}
inline std::vector<TapBox> linear_tap_boxes(double t, int size, int bits, double coord_noise) {
  return linear_tap_boxes_over(t - coord_noise, t + coord_noise, size, bits);
}

// The arithmetic of the filter itself: the precision in which a conformant device may form the
// products of the axis weights and sum the weighted texels. The specification gives the formula
// (textures-texel-linear-filtering: tau_2D = sum (w_i)(w_j) tau_ij, w from the snapped fractions)
// and no precision for it beyond fundamentals-numerics ("Floating-Point Computation" applies to
// texture sampling: "accurate to about 1 part in 10^5"; "the representation and/or precision of
// operations is implicitly limited by the specified format of ... texel data"). VK-GL-CTS makes
// that concrete (vktTextureFilteringExplicitLodTests.cpp getPrecision(format, 0), passed to
// vktSampleVerifier.cpp SampleVerifier as the filtering precision): every product weight and
// every partial sum is rounded outward in the texel format's own precision, a UNORM channel of b
// bits on the grid 1/(2^b − 1) (tcuFloatFormat.cpp NormalizedFormat::round), RGBA16F in a float of
// 10 fraction bits (FloatFormat(-14, 15, 10)), RGBA32F in float32 (FloatFormat(-126, 127, 23)).
// Its relaxed retry (fp16 with 4 fraction bits, SNORM8 with 6) reports a quality warning, not a
// pass, and is not admitted here. docs/precision.md, "Filter arithmetic".
struct FilterArithmetic {
  enum class Kind { kExact, kUnorm, kFloat };
  Kind kind = Kind::kExact;
  int bits = 0;     // kUnorm: the channel's bits b; kFloat: fraction bits
  int min_exp = 0;  // kFloat: the least exponent (below it the quantum stays 2^(min_exp − bits))
  static FilterArithmetic exact() { return {}; }
  static FilterArithmetic unorm(int b) { return {Kind::kUnorm, b, 0}; }
  static FilterArithmetic float16() { return {Kind::kFloat, 10, -14}; }
  static FilterArithmetic float32() { return {Kind::kFloat, 23, -126}; }
};

// `d` rounded down (upward false) or up onto the format's grid: tcuFloatFormat.cpp
// NormalizedFormat::round (floor or ceil of d·(2^b − 1), over 2^b − 1) and FloatFormat::round (the
// significand of d cut to `bits` fraction bits toward −inf or +inf, the exponent at least
// min_exp). Exact for kExact, 0 and non-finite values.
inline double filter_round(double d, bool upward, const FilterArithmetic& fa) {
  if (fa.kind == FilterArithmetic::Kind::kExact || d == 0 || !std::isfinite(d)) return d;
  if (fa.kind == FilterArithmetic::Kind::kUnorm) {
    const double levels = pow2_exact(fa.bits) - 1;
    return (upward ? std::ceil(d * levels) : std::floor(d * levels)) / levels;
  }
  return round_to_float_grid(d, upward, fa.bits, fa.min_exp);
}

// One filtered sample as VK-GL-CTS's SampleVerifier::getFilteredSample1D/2D/3D bounds it: `axes`
// (1–3) fractions alpha[a] (the weight of axis a's upper texel, already on the sub-texel grid),
// 2^axes taps whose index has bit a set where the tap is axis a's upper texel, each tap's value
// within [t_lo, t_hi]. Per tap the weight is the product of the axis weights taken from the last
// axis to the first, rounded outward after every factor; the sum adds the taps in index order,
// rounded outward after every addition (interval arithmetic throughout). With kExact it is the
// exact weighted sum of the lower and of the upper bounds.
//
// `weight_bits` > 0: each tap's weight, the product of its axes' weights, may also snap to the
// nearest point of the 2^-weight_bits grid (a tie either way), each on its own (the weights' sum
// need not stay 1); the range is the hull of the filter with every weight snapped and the filter
// with every weight the product as formed. The
// specification's VkPhysicalDeviceLimits::subTexelPrecisionBits: "Sub-texel values calculated
// during image sampling will snap to these locations when generating the filtered results" — a
// tap's weight is such a value (the fraction of the texel's area under the footprint), so with
// weight_bits = subTexelPrecisionBits this is the sentence read for every sub-texel value, not only
// each axis's fraction (whose rounding the CTS leaves open: either neighbour, linear_tap_box). A
// conformant device does it: the NVIDIA H200's bilinear results lie at the edges of these ranges
// (docs/precision.md, "Filter arithmetic").
struct FilteredRange {
  double lo = 0, hi = 0;
};
//
// filter_taps_channels: the same for `channels` channels filtered with the same weights (an RGB
// texel): tap k of channel c is t_lo[c · 8 + k], t_hi[c · 8 + k], and out[c] its range. Each
// channel's range is exactly filter_taps' of that channel alone; the weights, which do not depend
// on the channel, are formed once.
inline void filter_taps_channels(int axes, const double* alpha, int channels, const double* t_lo,
                                 const double* t_hi, const FilterArithmetic& fa, int weight_bits,
                                 FilteredRange* out) {
  const int taps = 1 << axes;
  // Every tap's weight range, the product as formed ([0]) and snapped to the grid ([1]).
  double w_lo[2][8], w_hi[2][8];
  const double grid = std::ldexp(1.0, weight_bits);
  for (int k = 0; k < taps; ++k) {
    double lo = 1, hi = 1;
    for (int a = axes - 1; a >= 0; --a) {
      const double f = (k >> a) & 1 ? alpha[a] : 1 - alpha[a];
      lo = filter_round(lo * f, false, fa);  // weights are non-negative
      hi = filter_round(hi * f, true, fa);
    }
    w_lo[0][k] = lo;
    w_hi[0][k] = hi;
    // The nearest grid point; at a tie either one.
    w_lo[1][k] = filter_round(std::ceil(lo * grid - 0.5) / grid, false, fa);
    w_hi[1][k] = filter_round(std::floor(hi * grid + 0.5) / grid, true, fa);
  }
  // A device snaps its tap weights or forms them as products (the CTS's model): both admitted.
  // One axis: the weight is the fraction, already snapped.
  const int filters = weight_bits > 0 && axes > 1 ? 2 : 1;
  for (int c = 0; c < channels; ++c) {
    const double* tl = t_lo + 8 * c;
    const double* th = t_hi + 8 * c;
    FilteredRange r{HUGE_VAL, -HUGE_VAL};
    for (int snap = 0; snap < filters; ++snap) {
      double lo = 0, hi = 0;
      for (int k = 0; k < taps; ++k) {
        const double wl = w_lo[snap][k], wh = w_hi[snap][k];
        if (wh == 0) continue;  // 0·t = 0 for any finite texel; a NaN texel is the caller's flag
        const double p[4] = {wl * tl[k], wl * th[k], wh * tl[k], wh * th[k]};
        lo = filter_round(lo + std::min({p[0], p[1], p[2], p[3]}), false, fa);
        hi = filter_round(hi + std::max({p[0], p[1], p[2], p[3]}), true, fa);
      }
      r.lo = std::fmin(r.lo, lo);
      r.hi = std::fmax(r.hi, hi);
    }
    out[c] = r;
  }
}
inline FilteredRange filter_taps(int axes, const double* alpha, const double* t_lo,
                                 const double* t_hi, const FilterArithmetic& fa,
                                 int weight_bits = 0) {
  double lo[8], hi[8];
  for (int k = 0; k < (1 << axes); ++k) {
    lo[k] = t_lo[k];
    hi[k] = t_hi[k];
  }
  FilteredRange r;
  filter_taps_channels(axes, alpha, 1, lo, hi, fa, weight_bits, &r);
  return r;
}

// UE's LinearToST2084 (GammaCorrectionCommon.ush) of `nits` as a conformant device may evaluate
// it in float32: Y = nits · 1e-4 (a multiply), P = pow(Y, m1), pow((c1 + c2·P) / (1 + c3·P), m2),
// each step within its bound (spirv_precision.h). nits ≤ 0 enters as P = 0 (exp2(−inf)).
inline spirv::Interval pq_encode_on_device(double nits) {
  using namespace spirv;
  Interval p = Interval::point(0.0);  // pow(0, m1) = exp2(m1 · −inf) = 0
  if (nits > 0) {
    const Interval y = mul(Interval::point(nits), Interval::point(1.0 / st2084::kPeakNits));
    p = pow(Interval{std::max(y.lo, 0x1p-149), y.hi}, st2084::kM1);
  }
  const Interval num = mul_add(Interval::point(st2084::kC2), p, Interval::point(st2084::kC1));
  const Interval den = mul_add(Interval::point(st2084::kC3), p, Interval::point(1.0));
  return pow(div(num, den), st2084::kM2);
}

// The same over a range of nits (PQ is increasing): [device low end of lo, device high end of hi].
inline spirv::Interval pq_encode_on_device(double lo_nits, double hi_nits) {
  return {pq_encode_on_device(lo_nits).lo, pq_encode_on_device(hi_nits).hi};
}

// UE's ST2084ToLinear (GammaCorrectionCommon.ush) of a PQ signal as a conformant device may
// evaluate it: Np = pow(pq, 1/m2), L = pow(max(Np − c1, 0) / (c2 − c3·Np), 1/m1) · 10 000.
// Increasing in pq; the subtraction near black (Np ≈ c1) is where its absolute error lives.
inline spirv::Interval pq_decode_on_device(double pq) {
  using namespace spirv;
  if (!(pq > 0)) return Interval::point(0.0);
  const Interval np = pow(Interval::point(pq), 1.0 / st2084::kM2);
  Interval num = sub(np, Interval::point(st2084::kC1));
  num.lo = std::max(num.lo, 0.0);
  num.hi = std::max(num.hi, 0.0);
  if (num.hi == 0) return Interval::point(0.0);
  const Interval den = sub(Interval::point(st2084::kC2), mul(Interval::point(st2084::kC3), np));
  Interval ratio = div(num, den);
  Interval out{0.0, 0.0};
  if (ratio.hi > 0) {
    const Interval pos{std::max(ratio.lo, 0x1p-149), ratio.hi};
    out = pow(pos, 1.0 / st2084::kM1);
    if (ratio.lo <= 0) out.lo = 0.0;
  }
  return mul(out, Interval::point(st2084::kPeakNits));
}

}  // namespace hdrc::ref
