// Interval evaluation of the steps after a value whose sign float32 cannot decide (core/image.h,
// AdmissibleRange). The reference computes each texel once, in double; where a channel is within
// float32 noise of zero when it reaches a function that is steep or undefined at zero (PQ, a pow
// with an exponent under 1, a pow of a negative), it also carries the interval that channel may
// take in a correct float32 evaluation on a Vulkan device, [v - e, v + e] with e = kShaderNoise x
// the largest |channel|, through the remaining steps: matrices (exact interval products),
// nondecreasing per-channel functions (the end points), and functions undefined below zero (NaN
// admissible). docs/diff-metrics.md, "Admissible ranges".
#pragma once

#include <array>
#include <cmath>

#include "core/image.h"
#include "color/vec.h"

namespace hdrc::ref {

// The relative noise of UE's float32 shader arithmetic as a Vulkan device may evaluate it, bounding
// what a correct port's value may differ from the exact one, relative to the largest |channel|:
// 2^-15. Vulkan's precision rules (Vulkan spec, "Precision and Operation of SPIR-V Instructions")
// let log2 err by 2^-21 absolute on [0.5, 2] and pow inherits exp2(y log2 x): PQ's pow(., m2)
// with m2 = 78.84 then errs by up to 78.84 x 2^-21 x ln 2 = 2.6e-5 relative, under 2^-15
// (3.05e-5). Measured on lavapipe: a 64^3 ACES LUT (device 6, gamut 3) agrees with the reference
// within 1.8e-5 of its largest texel; a channel 1.1e-6 of its pixel's largest above zero came out
// negative (docs/diff-metrics.md, "Admissible ranges"). It applies where PQ's exponent is on the
// path (devices 3-7); the SDR and linear paths have no such amplification and use kFloat32Noise
// (2^-20, core/image.h), which a planted 1e-4 change of a film constant must exceed.
inline constexpr double kShaderNoise = 1.0 / 32768.0;

struct Range3 {
  Vec3 lo{}, hi{};
  std::array<bool, 3> nan{};  // NaN is admissible in the channel

  static Range3 point(const Vec3& v) {
    Range3 r;
    r.lo = r.hi = v;
    for (int c = 0; c < 3; ++c) r.nan[c] = std::isnan(v[c]);
    return r;
  }
  // Extends the range to admit `v` itself. The reference's own value is admissible by definition;
  // the interval end points are computed along another path (e.g. st2084::pq_from_nits rather than
  // the texel's pq_encode), which may round one ulp the other way, differently at -O0 and -O3.
  void include(const Vec3& v) {
    for (int c = 0; c < 3; ++c) {
      if (std::isnan(v[c])) {
        nan[c] = true;
        continue;
      }
      lo[c] = std::isnan(lo[c]) ? v[c] : std::fmin(lo[c], v[c]);
      hi[c] = std::isnan(hi[c]) ? v[c] : std::fmax(hi[c], v[c]);
    }
  }
  // Whether the range admits anything besides the point value `v`.
  bool wider_than(const Vec3& v) const {
    for (int c = 0; c < 3; ++c) {
      if (nan[c] != std::isnan(v[c])) return true;
      if (!std::isnan(v[c]) && (lo[c] != v[c] || hi[c] != v[c])) return true;
    }
    return false;
  }
};

// Widens each finite channel of `at` within noise x max|finite channel| of zero to
// [v - e, v + e] in `r` (keeping what `r` already admits). Returns whether any channel was widened.
inline bool widen_near_zero(const Vec3& at, double noise, Range3* r) {
  double scale = 0;
  for (int c = 0; c < 3; ++c)
    if (std::isfinite(at[c])) scale = std::fmax(scale, std::fabs(at[c]));
  const double e = noise * scale;
  if (!(e > 0)) return false;
  bool widened = false;
  for (int c = 0; c < 3; ++c) {
    if (!std::isfinite(at[c]) || std::fabs(at[c]) > e) continue;
    r->lo[c] = std::fmin(r->lo[c], at[c] - e);
    r->hi[c] = std::fmax(r->hi[c], at[c] + e);
    widened = true;
  }
  return widened;
}

// Widens every finite channel of `at` to [v - e, v + e] in `r`, e = noise x max|finite channel|
// (keeping what `r` already admits). Returns whether anything was widened (false for black).
inline bool widen_noise(const Vec3& at, double noise, Range3* r) {
  double scale = 0;
  for (int c = 0; c < 3; ++c)
    if (std::isfinite(at[c])) scale = std::fmax(scale, std::fabs(at[c]));
  const double e = noise * scale;
  if (!(e > 0)) return false;
  for (int c = 0; c < 3; ++c) {
    if (!std::isfinite(at[c])) continue;
    r->lo[c] = std::fmin(r->lo[c], at[c] - e);
    r->hi[c] = std::fmax(r->hi[c], at[c] + e);
  }
  return true;
}

// The width of a PQ signal interval from which a channel counts as undecided: a quarter of a
// 10-bit code. Below it the noise is the uniform float32 noise the tolerances were measured with.
inline constexpr double kUndecidedPqWidth = 0.25 / 1023.0;

// Widens each finite channel of `at` within noise x max|finite channel| of a rounding
// boundary (k + 1/2)/levels of a fixed-point quantisation to (k + 1/2 -+ 1/4)/levels, which
// quantise to k and k + 1: either may be stored. Returns whether any channel was widened.
inline bool widen_near_rounding_boundary(const Vec3& at, double levels, double noise, Range3* r) {
  double scale = 0;
  for (int c = 0; c < 3; ++c)
    if (std::isfinite(at[c])) scale = std::fmax(scale, std::fabs(at[c]));
  const double e = noise * scale * levels;  // in steps of the quantisation
  bool widened = false;
  for (int c = 0; c < 3; ++c) {
    if (!std::isfinite(at[c])) continue;
    const double t = at[c] * levels;
    const double boundary = std::floor(t) + 0.5;  // the nearest one: |t - boundary| <= 1/2
    if (!(std::fabs(t - boundary) <= e)) continue;
    r->lo[c] = std::fmin(r->lo[c], (boundary - 0.25) / levels);
    r->hi[c] = std::fmax(r->hi[c], (boundary + 0.25) / levels);
    widened = true;
  }
  return widened;
}

// m · r, exactly: each output's bounds are sums of the products' bounds. NaN admissible in an
// input reaches every output it has a non-zero coefficient in.
inline Range3 apply_matrix(const Mat3& m, const Range3& r) {
  Range3 out;
  for (int i = 0; i < 3; ++i) {
    double lo = 0, hi = 0;
    bool nan = false;
    for (int j = 0; j < 3; ++j) {
      const double a = m(i, j) * r.lo[j], b = m(i, j) * r.hi[j];
      lo += std::isnan(a) || std::isnan(b) ? a + b : std::fmin(a, b);
      hi += std::isnan(a) || std::isnan(b) ? a + b : std::fmax(a, b);
      nan = nan || (r.nan[j] && m(i, j) != 0.0);
    }
    out.lo[i] = lo;
    out.hi[i] = hi;
    out.nan[i] = nan || std::isnan(lo) || std::isnan(hi);
  }
  return out;
}

// f applied to a range, for f nondecreasing where defined. `f(NaN)` decides what an admissible NaN
// becomes (HLSL max(NaN, 0) is 0, pow(NaN) NaN).
template <class F>
Range3 map_nondecreasing(const Range3& r, F f) {
  Range3 out;
  for (int c = 0; c < 3; ++c) {
    out.lo[c] = f(r.lo[c]);
    out.hi[c] = f(r.hi[c]);
    out.nan[c] = std::isnan(out.lo[c]) || std::isnan(out.hi[c]);
    if (r.nan[c]) {
      const double v = f(std::nan(""));
      if (std::isnan(v)) {
        out.nan[c] = true;
      } else {
        out.lo[c] = std::fmin(out.lo[c], v);
        out.hi[c] = std::fmax(out.hi[c], v);
      }
    }
  }
  return out;
}

// f applied to a range, for f nondecreasing on [0, inf) and NaN below 0 (PQ's and pow's negative
// base): the negative part of a range becomes an admissible NaN.
template <class F>
Range3 map_nonnegative(const Range3& r, F f) {
  Range3 lifted = r;
  for (int c = 0; c < 3; ++c) {
    if (std::isnan(r.lo[c]) || std::isnan(r.hi[c]) || !(r.lo[c] < 0.0)) continue;
    lifted.nan[c] = true;
    if (r.hi[c] < 0.0) {
      lifted.lo[c] = lifted.hi[c] = std::nan("");
    } else {
      lifted.lo[c] = 0.0;
    }
  }
  return map_nondecreasing(lifted, f);
}

// A pixel's admissible range for core/image.h: the colour channels from `rgb`, alpha [lo, hi]
// with NaN admissible where `alpha_nan`.
inline AdmissibleRange to_admissible(size_t pixel, const Range3& rgb, double alpha_lo,
                                     double alpha_hi, bool alpha_nan) {
  AdmissibleRange a;
  a.pixel = pixel;
  for (int c = 0; c < 3; ++c) {
    a.lo[c] = rgb.lo[c];
    a.hi[c] = rgb.hi[c];
    if (rgb.nan[c]) a.nan_ok |= uint8_t(1u << c);
  }
  a.lo[3] = alpha_lo;
  a.hi[3] = alpha_hi;
  if (alpha_nan) a.nan_ok |= uint8_t(1u << 3);
  return a;
}

// The luminance OutLuminance takes from a LUT value's range (non-negative weights: the ends map
// to the ends), for the Tonemap pass's alpha.
inline std::array<double, 2> luminance_range(const Range3& r) {
  return {r.lo[0] * 0.299 + r.lo[1] * 0.587 + r.lo[2] * 0.114,
          r.hi[0] * 0.299 + r.hi[1] * 0.587 + r.hi[2] * 0.114};
}

inline Range3 scale(const Range3& r, double k) {  // k > 0
  Range3 out = r;
  for (int c = 0; c < 3; ++c) {
    out.lo[c] = r.lo[c] * k;
    out.hi[c] = r.hi[c] * k;
  }
  return out;
}

}  // namespace hdrc::ref
