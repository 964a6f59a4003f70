// The range a conformant Vulkan device may return from a 3-D LUT stored as an N² × N strip
// (texel (r, g, b) at (r + N b, g)) and sampled by the two-slice scheme every engine's 2-D LUT
// uses: two hardware bilinear taps (linear filtering, clamp-to-edge) one slice apart, lerped in
// the shader by the fractional slice. pq_grading's pqg_sample_strip (UE's
// UnwrappedTexture3DSample) and Unity's ApplyLut2D (Color.hlsl) both reduce to it: for the
// normalised coordinate t in [0, 1]³ the strip's texel-space x is t.r·(N − 1) + N·floor(s), y is
// t.g·(N − 1) and the slice s = t.b·(N − 1), its fraction the lerp's weight (docs/precision.md,
// "Device allowances").
//
// Per lookup (reference/color/device_allowance.h): each bilinear weight takes the box of
// linear_tap_box for `bits` sub-texel bits (Vulkan spec, textures-texel-filtering); the filtered
// value is linear in each weight, so its extremes lie at the box's corners, the lower texel
// bounds giving the minimum and the upper ones the maximum (as combine_luts.cpp
// sample_lut_device_range). The shader's lerp by the slice fraction is exact up to float32: the
// coordinate's noise opens that weight like a filter weight. A coordinate that is itself a range
// (a device's PQ encode before the lookup) is evaluated at both ends and at every lattice plane
// between them: within one cell the lookup is multilinear in the coordinate, so its extremes over
// a box lie at the corners of the box's pieces.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/image.h"
#include "reference/color/device_allowance.h"
#include "reference/color/noise_range.h"
#include "reference/color/spirv_precision.h"

namespace hdrc::ref {

// The per-texel bounds of a stored strip: what a device may hold in each texel (the bake's own
// error and the storage format's rounding either way). Both images N² × N, rgb used.
struct StripBounds {
  const Image* lo = nullptr;
  const Image* hi = nullptr;
  int size = 0;  // N
};

// The lookup of the strip at every normalised coordinate in `t` (per channel [t.lo, t.hi], clamped
// to [0, 1]) as a device with `bits` sub-texel bits may filter it; `coord_noise` the shader's
// float32 error of the normalised coordinate (kShaderNoise where the engine's coordinate arithmetic
// is not modelled step by step), in the coordinate's units: N² · noise texels along the strip's x,
// N · noise along y and the slice. Includes the lerp's own float32 rounding (a + t·(b − a): three
// correctly rounded steps, 0.5 ULP each of values up to twice the larger sample, 2.5 ULP of it in
// all; spirv_precision.h). NaN texels make the
// channel's NaN admissible.
//
// `snap_weights` (the default): each of a tap's four bilinear weights (the products (1 − α)(1 − β),
// α(1 − β), ...) also snaps to the 2^-bits grid, either way and each on its own
// (device_allowance.h filter_taps, weight_bits: the specification's "Sub-texel values calculated
// during image sampling will snap to these locations" read for every sub-texel value of the
// filter). False: only each axis's fraction (a hand check of the per-axis box).
//
// `fa`: the precision of the filter's own arithmetic (device_allowance.h filter_taps, VK-GL-CTS's
// filtering precision of the strip's storage format): each product weight and partial sum rounded
// outward in it. Exact by default.
inline Range3 strip_lookup_device_range(const StripBounds& s, const Range3& t, int bits,
                                        double coord_noise,
                                        const FilterArithmetic& fa = FilterArithmetic::exact(),
                                        bool snap_weights = true) {
  const int n = s.size;
  const int width = n * n;
  // The candidate coordinates per axis, in texel units: both ends of the coordinate's range
  // widened by the noise, and the texel planes strictly between them (the noise may carry a
  // coordinate across a plane: a strip's x below a slice's first texel reads the previous slice's
  // last one). At each candidate the weight takes its sub-texel box.
  // The slice coordinate (the shader's own lerp, no sub-texel rounding): both ends of its range
  // widened by the noise and the texel planes strictly between them (the noise may carry it across
  // a plane). The hardware axes: linear_tap_boxes_over, the CTS's coordinate rounding included and
  // the boxes of one texel pair merged (a strip's x below a slice's first texel reads the previous
  // slice's last one: another pair).
  auto candidates = [](double a, double b, double noise) {
    std::vector<double> v;
    a -= noise;
    b += noise;
    v.push_back(a);
    for (double k = std::floor(a) + 1; k < b; k += 1) v.push_back(k);
    if (b > a) v.push_back(b);
    return v;
  };
  double a[3], b[3];
  for (int c = 0; c < 3; ++c) {
    // A NaN coordinate reads the clamp-to-edge texel 0 (as the references' samplers take it).
    a[c] = std::isnan(t.lo[c]) ? 0.0 : std::clamp(t.lo[c], 0.0, 1.0) * (n - 1);
    b[c] = std::isnan(t.hi[c]) ? a[c] : std::max(a[c], std::clamp(t.hi[c], 0.0, 1.0) * (n - 1));
  }
  const std::vector<TapBox> boxes_g =
      linear_tap_boxes_over(a[1] - coord_noise * n, b[1] + coord_noise * n, n, bits);
  const std::vector<double> pos_b = candidates(a[2], b[2], coord_noise * n);
  Range3 r;
  for (int c = 0; c < 3; ++c) {
    r.lo[c] = HUGE_VAL;
    r.hi[c] = -HUGE_VAL;
  }
  bool nan[3] = {false, false, false};
  double least[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL};  // the least lower texel bound read
  auto at = [](const Image& img, int x, int y, int c) { return img.px(x, y)[c]; };
  for (const TapBox& ty : boxes_g)
    for (const double pb : pos_b) {
      const double slice = std::floor(pb);
      const double frac = pb - slice;
      Vec3 s_lo[2], s_hi[2];
      for (int k = 0; k < 2; ++k) {
        for (int c = 0; c < 3; ++c) {
          s_lo[k][c] = HUGE_VAL;
          s_hi[k][c] = -HUGE_VAL;
        }
        for (const TapBox& tx :
             linear_tap_boxes_over(a[0] + n * (slice + k) - coord_noise * width,
                                   b[0] + n * (slice + k) + coord_noise * width, width, bits)) {
          for (const double fx : {tx.f_lo, tx.f_hi})
            for (const double fy : {ty.f_lo, ty.f_hi}) {
              const double w00 = (1 - fx) * (1 - fy), w10 = fx * (1 - fy), w01 = (1 - fx) * fy,
                           w11 = fx * fy;
              const double alpha[2] = {fx, fy};
              // Tap j: bit 0 the upper x texel, bit 1 the upper y texel (filter_taps' order);
              // channel c's taps at [8c, 8c + 4) (filter_taps_channels).
              const int xs[4] = {tx.i0, tx.i1, tx.i0, tx.i1}, ys[4] = {ty.i0, ty.i0, ty.i1, ty.i1};
              const double ws[4] = {w00, w10, w01, w11};
              double tls[3 * 8], ths[3 * 8];
              for (int c = 0; c < 3; ++c) {
                for (int j = 0; j < 4; ++j) {
                  tls[8 * c + j] = at(*s.lo, xs[j], ys[j], c);
                  ths[8 * c + j] = at(*s.hi, xs[j], ys[j], c);
                  if (ws[j] == 0) continue;
                  const double tl = tls[8 * c + j], th = ths[8 * c + j];
                  if (std::isnan(tl) || std::isnan(th)) nan[c] = true;
                  least[c] = std::fmin(least[c], tl);
                }
              }
              FilteredRange f[3];
              filter_taps_channels(2, alpha, 3, tls, ths, fa, snap_weights ? bits : 0, f);
              for (int c = 0; c < 3; ++c) {
                s_lo[k][c] = std::fmin(s_lo[k][c], f[c].lo);
                s_hi[k][c] = std::fmax(s_hi[k][c], f[c].hi);
              }
            }
        }
      }
      // The slice lerp's weight is the shader's own fraction (no sub-texel rounding).
      {
        const double f_lo = frac, f_hi = frac;
        for (int c = 0; c < 3; ++c) {
          for (const double f : {f_lo, f_hi}) {
            const double lo = s_lo[0][c] + (s_lo[1][c] - s_lo[0][c]) * f;
            const double hi = s_hi[0][c] + (s_hi[1][c] - s_hi[0][c]) * f;
            const double big = std::fmax(std::fmax(std::fabs(s_lo[0][c]), std::fabs(s_lo[1][c])),
                                         std::fmax(std::fabs(s_hi[0][c]), std::fabs(s_hi[1][c])));
            const double e = 2.5 * spirv::ulp32(big);  // the lerp's three roundings
            r.lo[c] = std::fmin(r.lo[c], lo - e);
            r.hi[c] = std::fmax(r.hi[c], hi + e);
          }
        }
      }
    }
  for (int c = 0; c < 3; ++c) {
    // Non-negative texels filter to a non-negative value (weights in [0, 1]), and the lerp keeps
    // it: a + t·(b − a) with t in [0, 1] rounds to at least 0 (t·(b − a) ≥ −a exactly, and
    // rounding is monotone). The lerp's rounding allowance does not take the range below 0.
    if (least[c] >= 0) r.lo[c] = std::fmax(r.lo[c], 0.0);
    r.nan[c] = nan[c] || std::isnan(r.lo[c]) || std::isnan(r.hi[c]);
  }
  return r;
}

}  // namespace hdrc::ref
