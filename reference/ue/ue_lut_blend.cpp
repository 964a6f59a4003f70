#include "reference/ue/ue_lut_blend.h"

#include <algorithm>
#include <cmath>

#include "color/gamma_correction.h"
#include "core/case.h"
#include "reference/color/device_allowance.h"
#include "reference/color/linear_tap.h"

namespace hdrc::ref {

// The loader's rounding (core/case.h: unorm8_value), so that the reference's textures are the
// texels both engines bind.
uint8_t unorm8_from_value(double v) {
  return static_cast<uint8_t>(std::nearbyint(unorm8_value(v) * 255.0));
}

UeLutTexture ue_lut_texture(const std::vector<std::array<float, 3>>& table, bool quantize_8bit) {
  UeLutTexture t;
  constexpr int n = kUeUserLutSize;
  if (table.size() != static_cast<size_t>(n) * n * n) return t;
  t.texels.resize(static_cast<size_t>(kUeUserLutWidth) * kUeUserLutHeight);
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) {
        const auto& row = table[(static_cast<size_t>(b) * n + g) * n + r];
        Vec3& out = t.texels[static_cast<size_t>(g) * kUeUserLutWidth + r + n * b];
        for (int c = 0; c < 3; ++c) out[c] = quantize_8bit ? unorm8_value(row[c]) : double(row[c]);
      }
  return t;
}

namespace {

using Tap = LinearTap;  // reference/color/linear_tap.h

Vec3 lerp(const Vec3& a, const Vec3& b, double f) {
  return {a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f, a[2] + (b[2] - a[2]) * f};
}

Vec3 bilinear(const UeLutTexture& lut, double u, double v) {
  const Tap x = linear_tap(u * kUeUserLutWidth - 0.5, kUeUserLutWidth);
  const Tap y = linear_tap(v * kUeUserLutHeight - 0.5, kUeUserLutHeight);
  return lerp(lerp(lut.at(x.i0, y.i0), lut.at(x.i1, y.i0), x.f),
              lerp(lut.at(x.i0, y.i1), lut.at(x.i1, y.i1), x.f), y.f);
}

}  // namespace

Vec3 unwrapped_texture3d_sample(const UeLutTexture& lut, const Vec3& uvw) {
  constexpr double size = kUeUserLutSize, inv_size = 1.0 / kUeUserLutSize;
  const double w = uvw[2] * size - 0.5;
  const double int_w = std::floor(w);
  const double frac_w = w - int_w;
  const double u = (uvw[0] + int_w) * inv_size;
  return lerp(bilinear(lut, u, uvw[1]), bilinear(lut, u + inv_size, uvw[1]), frac_w);
}

Vec3 blend_user_luts(const Vec3& film_color, int count, const std::array<double, 5>& weights,
                     const std::array<const UeLutTexture*, 4>& luts) {
  if (count <= 1) return film_color;
  count = std::min(count, 5);
  Vec3 g;
  // saturate: D3D maps NaN to 0 (fmax/fmin are IEEE maxNum/minNum).
  for (int c = 0; c < 3; ++c) g[c] = linear_to_srgb(std::fmin(std::fmax(film_color[c], 0.0), 1.0));
  // UVW = GammaColor · (15/16) + 0.5/16 (the shader's float literals 15.0/16.0, 0.5f/16.0).
  Vec3 uvw;
  for (int c = 0; c < 3; ++c) uvw[c] = g[c] * (15.0 / 16.0) + 0.5 / 16.0;
  Vec3 blended = {weights[0] * g[0], weights[0] * g[1], weights[0] * g[2]};
  for (int i = 1; i < count; ++i) {
    const UeLutTexture* lut = luts[static_cast<size_t>(i - 1)];
    if (!lut || lut->texels.empty()) continue;
    const Vec3 s = unwrapped_texture3d_sample(*lut, uvw);
    for (int c = 0; c < 3; ++c) blended[c] += weights[static_cast<size_t>(i)] * s[c];
  }
  return srgb_to_linear(blended);
}

namespace {

using spirv::Interval;

// OpFAdd, OpFSub and OpFMul are correctly rounded (the specification's table): a result lies
// between the float32 neighbours of the exact result over the operands (device_allowance.h
// float_round_down / float_round_up), so an exact one (1/32 + IntW, UVW at black) stays exact.
Interval rounded(Interval exact) {
  return {float_round_down(exact.lo), float_round_up(exact.hi)};
}
Interval rounded_add(Interval a, Interval b) {
  return rounded({a.lo + b.lo, a.hi + b.hi});
}
Interval rounded_sub(Interval a, Interval b) {
  return rounded({a.lo - b.hi, a.hi - b.lo});
}
Interval rounded_mul(Interval a, Interval b) {
  return rounded(spirv::mul_exact(a, b));
}
// A shader literal: the float32 the compiler makes of it, one of the neighbours of the value.
Interval literal(double v) {
  return rounded({v, v});
}
// a·b + c fused (one rounding) or not (two): the unfused interval contains the fused one.
Interval rounded_mul_add(Interval a, Interval b, Interval c) {
  return rounded_add(rounded_mul(a, b), c);
}

// One axis of a hardware linear fetch over a texel-space coordinate interval [t_lo, t_hi]
// (narrower than a texel): for each texel pair the interval reaches (two where it crosses a texel
// centre), the pair and the box of the weight of its second texel: linear_tap_box's box over that
// pair's part [a, b] of the interval, [floor((a − k)·2^bits), ceil((b − k)·2^bits)] / 2^bits.
// Returns the number of pairs.
int tap_boxes(double t_lo, double t_hi, int size, int bits, TapBox out[2]) {
  const double grid = std::ldexp(1.0, bits);
  int n = 0;
  // The hardware's unnormalised coordinate as the CTS bounds it (device_allowance.h
  // cts_texel_range).
  const CoordRange range = cts_texel_range(t_lo, t_hi, size);
  t_lo = range.lo;
  t_hi = range.hi;
  if (t_lo == t_hi) {  // a point: linear_tap_box itself
    out[n++] = linear_tap_box(t_lo, size, bits, 0.0);
    return n;
  }
  for (double k = std::floor(t_lo); k <= std::floor(t_hi) && n < 2; k += 1) {
    const LinearTap pair = linear_tap(k + 0.5, size);  // the texels of this part, clamped
    TapBox box;
    box.i0 = pair.i0;
    box.i1 = pair.i1;
    box.f_lo = std::floor((std::max(t_lo, k) - k) * grid) / grid;
    box.f_hi = std::ceil((std::min(t_hi, k + 1) - k) * grid) / grid;
    out[n++] = box;
  }
  return n;
}

// One hardware bilinear sample of the strip at every corner of its weight boxes: per channel the
// extremes (the filter is linear in each weight, so they lie at the corners).
void bilinear_extremes(const UeLutTexture& lut, Interval u, Interval v, int bits, Vec3* lo,
                       Vec3* hi) {
  TapBox xs[2], ys[2];
  const int nx = tap_boxes(u.lo * kUeUserLutWidth - 0.5, u.hi * kUeUserLutWidth - 0.5,
                           kUeUserLutWidth, bits, xs);
  const int ny = tap_boxes(v.lo * kUeUserLutHeight - 0.5, v.hi * kUeUserLutHeight - 0.5,
                           kUeUserLutHeight, bits, ys);
  for (int c = 0; c < 3; ++c) {
    (*lo)[c] = HUGE_VAL;
    (*hi)[c] = -HUGE_VAL;
  }
  for (int ix = 0; ix < nx; ++ix)
    for (int iy = 0; iy < ny; ++iy) {
      const TapBox& x = xs[ix];
      const TapBox& y = ys[iy];
      for (const double fx : {x.f_lo, x.f_hi})
        for (const double fy : {y.f_lo, y.f_hi}) {
          // The filter's own arithmetic in float32, the precision of the RGBA32F strip the engine
          // binds, each tap's weight on the sub-texel grid (device_allowance.h filter_taps; tap k:
          // bit 0 the upper x, bit 1 the upper y).
          const double alpha[2] = {fx, fy};
          const Vec3* t[4] = {&lut.at(x.i0, y.i0), &lut.at(x.i1, y.i0), &lut.at(x.i0, y.i1),
                              &lut.at(x.i1, y.i1)};
          for (int c = 0; c < 3; ++c) {
            const double tc[4] = {(*t[0])[c], (*t[1])[c], (*t[2])[c], (*t[3])[c]};
            const FilteredRange f =
                filter_taps(2, alpha, tc, tc, FilterArithmetic::float32(), bits);
            (*lo)[c] = std::fmin((*lo)[c], f.lo);
            (*hi)[c] = std::fmax((*hi)[c], f.hi);
          }
        }
    }
}

// A branch select over an interval: `below(x)` for x < threshold (or <= where `at_below`), else
// `above(x)`; both pieces increasing, so an interval across the threshold is the union of each
// piece's part.
template <class Below, class Above>
Interval select_increasing(Interval x, double threshold, bool at_below, Below below, Above above) {
  const bool lo_below = at_below ? x.lo <= threshold : x.lo < threshold;
  const bool hi_below = at_below ? x.hi <= threshold : x.hi < threshold;
  if (hi_below) return below(x);
  if (!lo_below) return above(x);
  const Interval a = below(Interval{x.lo, threshold}), b = above(Interval{threshold, x.hi});
  return {std::fmin(a.lo, b.lo), std::fmax(a.hi, b.hi)};
}

// LinearToSrgb (LinearToSrgbBranchingChannel) on a device: x < 0.00313067 ? 12.92·x :
// pow(x, 1/2.4)·1.055 − 0.055, each operation within its bound. x within [0, 1] (saturated).
Interval linear_to_srgb_device(Interval x) {
  return select_increasing(
      x, 0.00313067, false, [](Interval v) { return rounded_mul(v, literal(12.92)); },
      [](Interval v) {
        return rounded_mul_add(spirv::pow(v, static_cast<float>(1.0 / 2.4)), literal(1.055),
                               literal(-0.055));
      });
}

// sRGBToLinear on a device: c = max(6.10352e-5, c); c > 0.04045 ? pow(c·(1/1.055) + 0.0521327,
// 2.4) : c·(1/12.92).
Interval srgb_to_linear_device(Interval c) {
  c = {std::fmax(kMinNormal, c.lo), std::fmax(kMinNormal, c.hi)};
  return select_increasing(
      c, 0.04045, true, [](Interval v) { return rounded_mul(v, literal(1.0 / 12.92)); },
      [](Interval v) {
        return spirv::pow(rounded_mul_add(v, literal(1.0 / 1.055), literal(0.0521327)),
                          static_cast<float>(2.4));
      });
}

}  // namespace

Range3 unwrapped_texture3d_sample_device(const UeLutTexture& lut,
                                         const std::array<Interval, 3>& uvw, int bits) {
  constexpr double size = kUeUserLutSize, inv_size = 1.0 / kUeUserLutSize;
  // w = UVW.z·16 − 0.5 (the multiply by 16 exact, fused or not); IntW = floor of a w in that
  // interval; FracW = w − IntW from a w the device may round again (the shader writes it twice).
  const Interval w = rounded_mul_add(uvw[2], Interval::point(size), Interval::point(-0.5));
  Range3 r;
  for (int c = 0; c < 3; ++c) {
    r.lo[c] = HUGE_VAL;
    r.hi[c] = -HUGE_VAL;
  }
  for (double int_w = std::floor(w.lo); int_w <= std::floor(w.hi); int_w += 1) {
    const Interval frac_w = rounded_sub(w, Interval::point(int_w));
    const Interval u =
        rounded_mul(rounded_add(uvw[0], Interval::point(int_w)), Interval::point(inv_size));
    const Interval u1 = rounded_add(u, Interval::point(inv_size));
    Vec3 lo0, hi0, lo1, hi1;
    bilinear_extremes(lut, u, uvw[1], bits, &lo0, &hi0);
    bilinear_extremes(lut, u1, uvw[1], bits, &lo1, &hi1);
    // mix(rg0, rg1, FracW) = rg0·(1 − FracW) + rg1·FracW (GLSL.std.450 FMix: inherited), each
    // product and the sum correctly rounded. Linear in FracW for given samples: its extremes lie
    // at FracW's ends (taken one at a time, so that rg0's and rg1's weights stay complementary).
    for (const double a : {frac_w.lo, frac_w.hi}) {
      const Interval fa = Interval::point(a);
      const Interval one_minus = rounded_sub(Interval::point(1.0), fa);
      for (int c = 0; c < 3; ++c) {
        const Interval m = rounded_add(rounded_mul(Interval{lo0[c], hi0[c]}, one_minus),
                                       rounded_mul(Interval{lo1[c], hi1[c]}, fa));
        r.lo[c] = std::fmin(r.lo[c], m.lo);
        r.hi[c] = std::fmax(r.hi[c], m.hi);
      }
    }
  }
  return r;
}

Range3 blend_user_luts_device_range(const Vec3& film_color, int count,
                                    const std::array<double, 5>& weights,
                                    const std::array<const UeLutTexture*, 4>& luts, int bits) {
  if (count <= 1) return Range3::point(film_color);
  count = std::min(count, 5);
  // FilmColor as the device's upstream arithmetic may have it (kShaderNoise, noise_range.h).
  Range3 f = Range3::point(film_color);
  widen_noise(film_color, kShaderNoise, &f);
  std::array<Interval, 3> g, uvw, blended;
  for (int c = 0; c < 3; ++c) {
    // saturate (NaN → 0, as blend_user_luts), then LinearToSrgb.
    const double lo = std::isnan(film_color[c]) ? 0.0 : std::clamp(f.lo[c], 0.0, 1.0);
    const double hi = std::isnan(film_color[c]) ? 0.0 : std::clamp(f.hi[c], 0.0, 1.0);
    g[c] = linear_to_srgb_device({lo, hi});
    uvw[c] = rounded_mul_add(g[c], Interval::point(15.0 / 16.0), Interval::point(0.5 / 16.0));
    blended[c] = rounded_mul(Interval::point(weights[0]), g[c]);
  }
  for (int i = 1; i < count; ++i) {
    const UeLutTexture* lut = luts[static_cast<size_t>(i - 1)];
    if (!lut || lut->texels.empty()) continue;
    const Range3 s = unwrapped_texture3d_sample_device(*lut, uvw, bits);
    for (int c = 0; c < 3; ++c)
      blended[c] = rounded_mul_add(Interval::point(weights[static_cast<size_t>(i)]),
                                   Interval{s.lo[c], s.hi[c]}, blended[c]);
  }
  Range3 out;
  for (int c = 0; c < 3; ++c) {
    const Interval l = srgb_to_linear_device(blended[c]);
    out.lo[c] = l.lo;
    out.hi[c] = l.hi;
  }
  return out;
}

Range3 blend_user_luts_device_range(const Vec3& film_color, const ParamBlock& p,
                                    const UeLutSet& luts, int bits) {
  const std::array<double, 5> w = {p.lut_weights[0], p.lut_weights[1], p.lut_weights[2],
                                   p.lut_weights[3], p.lut_weight_4};
  return blend_user_luts_device_range(
      film_color, p.lut_blend_count, w,
      {&luts.slots[0], &luts.slots[1], &luts.slots[2], &luts.slots[3]}, bits);
}

UeLutSet ue_lut_set(const std::array<Image, kUserLutSlots>& strips) {
  UeLutSet set;
  for (size_t s = 0; s < strips.size(); ++s) {
    const Image& img = strips[s];
    if (img.width != kUeUserLutWidth || img.height != kUeUserLutHeight) continue;
    UeLutTexture& t = set.slots[s];
    t.texels.resize(img.pixel_count());
    for (size_t i = 0; i < t.texels.size(); ++i)
      t.texels[i] = {img.data[i * 4], img.data[i * 4 + 1], img.data[i * 4 + 2]};
  }
  return set;
}

Vec3 blend_user_luts(const Vec3& film_color, const ParamBlock& p, const UeLutSet& luts) {
  const std::array<double, 5> w = {p.lut_weights[0], p.lut_weights[1], p.lut_weights[2],
                                   p.lut_weights[3], p.lut_weight_4};
  return blend_user_luts(film_color, p.lut_blend_count, w,
                         {&luts.slots[0], &luts.slots[1], &luts.slots[2], &luts.slots[3]});
}

}  // namespace hdrc::ref
