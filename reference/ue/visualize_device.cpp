#include "reference/ue/visualize_device.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "color/d3d_math.h"
#include "reference/color/noise_range.h"
#include "reference/color/spirv_precision.h"
#include "reference/ue/ue_pixel_device.h"

namespace hdrc::ref::visualize {

namespace {

using spirv::Interval;
using ue_device::constant;

constexpr double kU = 0x1p-24;  // float32's unit roundoff: 0.5 ULP relative
constexpr double kInf = std::numeric_limits<double>::infinity();

Interval pt(double v) {
  return Interval::point(v);
}
Interval hull(Interval a, Interval b) {
  return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)};
}
// saturate: clamp to [0, 1] (nondecreasing; saturate(NaN) = 0 never arises on these ranges).
Interval sat(Interval a) {
  return {std::clamp(a.lo, 0.0, 1.0), std::clamp(a.hi, 0.0, 1.0)};
}
Interval abs_i(Interval a) {
  if (a.lo >= 0) return a;
  if (a.hi <= 0) return {-a.hi, -a.lo};
  return {0.0, std::max(-a.lo, a.hi)};
}
Interval min_i(Interval a, Interval b) {
  return {std::min(a.lo, b.lo), std::min(a.hi, b.hi)};
}
Interval max_i(Interval a, Interval b) {
  return {std::max(a.lo, b.lo), std::max(a.hi, b.hi)};
}

// HLSL/GLSL lerp a + t·(b − a) over ranges: multilinear in (a, b, t), so the exact extremes lie at
// the eight corners, and so do the largest |b − a|, |t·(b − a)| and |result|; then the three
// correctly rounded steps (OpFSub, OpFMul, OpFAdd: 0.5 ULP each, the subtraction's error scaled by
// |t|; fusing the multiply-add removes one rounding, so the unfused bound covers it).
Interval lerp_range_impl(Interval a, Interval b, Interval t) {
  double lo = kInf, hi = -kInf, m_diff = 0, m_prod = 0, m_res = 0;
  const double m_t = std::max(std::fabs(t.lo), std::fabs(t.hi));
  for (double av : {a.lo, a.hi})
    for (double bv : {b.lo, b.hi})
      for (double tv : {t.lo, t.hi}) {
        const double d = bv - av, p = tv * d, r = av + p;
        lo = std::min(lo, r);
        hi = std::max(hi, r);
        m_diff = std::max(m_diff, std::fabs(d));
        m_prod = std::max(m_prod, std::fabs(p));
        m_res = std::max(m_res, std::fabs(r));
      }
  const double e_diff = 0.5 * spirv::ulp32(m_diff);
  const double e_prod = m_t * e_diff + 0.5 * spirv::ulp32(m_prod + m_t * e_diff);
  const double e = e_prod + 0.5 * spirv::ulp32(m_res + e_prod);
  return {lo - e, hi + e};
}

// Outcomes of `a < b` over ranges: {can be true, can be false}.
struct Outcomes {
  bool t, f;
};
Outcomes less(Interval a, Interval b) {
  return {a.lo < b.hi, !(a.hi < b.lo)};
}

// sqrt of a positive integer: inherited from 1.0 / inversesqrt() (inversesqrt 2 ULP, OpFDiv 2.5
// ULP; Vulkan spec, "Precision and Operation of SPIR-V Instructions").
Interval sqrt_range_impl(double n) {
  const double r = 1.0 / std::sqrt(n);
  return spirv::div(pt(1.0), spirv::widen_ulp(pt(r), 2.0));
}

// A pixel's value on a device: RGBA ranges, NaN admissible per channel.
struct Box {
  std::array<Interval, 4> c{};
  std::array<bool, 4> nan{};
  bool valid = true;  // false: the point value alone (a non-finite value on a lerped path)
};
Box hull(const Box& a, const Box& b) {
  Box r;
  for (int k = 0; k < 4; ++k) {
    r.c[k] = hull(a.c[k], b.c[k]);
    r.nan[k] = a.nan[k] || b.nan[k];
  }
  r.valid = a.valid && b.valid;
  return r;
}
Box box_of(double r, double g, double b, double a) {
  Box out;
  out.c = {pt(r), pt(g), pt(b), pt(a)};
  return out;
}

// The eye-adaptation parameters as the shader holds them: float32 constants
// (visualize_eye_adaptation.glsl), the interval between the exact value's float32 neighbours.
struct EaConstants {
  Interval scale, bias, lum_min, low, high, third, grey;
};

// histogram_position_from_luminance: log2(L)·Scale + Bias (one multiply-add, fused or not).
Interval position(Interval lum, const EaConstants& k) {
  return spirv::mul_add(spirv::log2(lum), k.scale, k.bias);
}
// log_luminance_from_histogram_position of bucket i's centre i/63.
Interval centre_log_luminance(int i, const EaConstants& k) {
  const Interval centre = spirv::div(pt(i), pt(kHistogramSize - 1));
  return spirv::div(spirv::sub(centre, k.bias), k.scale);
}

// One pixel's splat weights (13.19 fixed point) at a position f in [0, 63], with the rounding of
// frac0 = 1 − frac1 either way: [lo, hi] per bucket, 0 for the buckets not touched (Histogram.usf
// CalculateBucketsAndWeights, PackFloatToUINT32 truncation).
struct Splat {
  std::array<int64_t, kHistogramSize> lo{}, hi{};
};
Splat splat_at(double f, const EyeAdaptationParameters& p) {
  Splat s;
  const int b0 = std::min(static_cast<int>(f), kHistogramSize - 1);
  const int b1 = std::min(b0 + 1, kHistogramSize - 1);
  const double frac1 = f - std::floor(f);
  const double exact0 = 1.0 - frac1;
  double f0lo = std::max(exact0 - 0.5 * spirv::ulp32(exact0), 0.0);
  double f0hi = std::min(exact0 + 0.5 * spirv::ulp32(exact0), 1.0);
  if (b0 == 0) {
    f0lo *= p.black_histogram_bucket_influence;
    f0hi *= p.black_histogram_bucket_influence;
  }
  const auto w1 = static_cast<int64_t>(frac1 * 524288.0);
  s.lo[b0] += static_cast<int64_t>(f0lo * 524288.0);
  s.hi[b0] += static_cast<int64_t>(f0hi * 524288.0);
  s.lo[b1] += w1;
  s.hi[b1] += w1;
  return s;
}

struct HistogramRanges {
  std::array<Interval, kHistogramSize> h{};
  Interval max{}, average_px{};
};

HistogramRanges histogram_ranges(const Image& hdr, const EyeAdaptationParameters& p,
                                 Interval one_over_pre_exposure, const EaConstants& k,
                                 int panel_width) {
  std::array<int64_t, kHistogramSize> sum_lo{}, sum_hi{};
  for (size_t i = 0; i < hdr.pixel_count(); ++i) {
    const double* c = &hdr.data[i * 4];
    Splat range;
    bool first = true;
    auto take = [&](double f) {
      const Splat s = splat_at(f, p);
      for (int b = 0; b < kHistogramSize; ++b) {
        range.lo[b] = first ? s.lo[b] : std::min(range.lo[b], s.lo[b]);
        range.hi[b] = first ? s.hi[b] : std::max(range.hi[b], s.hi[b]);
      }
      first = false;
    };
    if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2])) {
      // NaN: L = LuminanceMin (maxNum); ±Inf: the reference's position; either exact.
      const Vec3 rgb{c[0] * one_over_pre_exposure.lo, c[1] * one_over_pre_exposure.lo,
                     c[2] * one_over_pre_exposure.lo};
      take(d3d::saturate(histogram_position_from_luminance(eye_adaptation_luminance(rgb, p), p)) *
           (kHistogramSize - 1));
    } else {
      // CalculateEyeAdaptationLuminance: dot(rgb · OneOverPreExposure, 1/3) (contracted or
      // not), maxNum with LuminanceMin; the position; f = saturate(position) · 63.
      Interval dot = spirv::mul(spirv::mul(pt(c[0]), one_over_pre_exposure), k.third);
      dot = spirv::mul_add(spirv::mul(pt(c[1]), one_over_pre_exposure), k.third, dot);
      dot = spirv::mul_add(spirv::mul(pt(c[2]), one_over_pre_exposure), k.third, dot);
      const Interval lum = max_i(dot, k.lum_min);
      Interval f = spirv::mul(sat(position(lum, k)), pt(kHistogramSize - 1));
      f = {std::clamp(f.lo, 0.0, 63.0), std::clamp(f.hi, 0.0, 63.0)};  // 63·[0, 1] is exact
      // The weights are continuous and piecewise linear in f between integers: their extremes
      // over [f.lo, f.hi] lie at the ends, at each integer crossed and at the float32 below it.
      take(f.lo);
      take(f.hi);
      for (double n = std::ceil(f.lo); n <= f.hi; n += 1.0) {
        take(n);
        if (n > 0) take(std::nextafter(static_cast<float>(n), 0.0f));
      }
    }
    for (int b = 0; b < kHistogramSize; ++b) {
      sum_lo[b] += range.lo[b];
      sum_hi[b] += range.hi[b];
    }
  }
  HistogramRanges r;
  // HistogramConvertCS: float(hi)·2^32 + float(lo) (two roundings), / 2^19, · 0.5,
  // · (1/W)·(1/H).
  const Interval inv =
      spirv::mul(spirv::div(pt(1.0), pt(hdr.width)), spirv::div(pt(1.0), pt(hdr.height)));
  for (int b = 0; b < kHistogramSize; ++b) {
    Interval s =
        spirv::widen_ulp({static_cast<double>(sum_lo[b]), static_cast<double>(sum_hi[b])}, 1.0);
    s.lo = std::max(s.lo, 0.0);
    s = spirv::mul(spirv::mul(spirv::div(s, pt(524288.0)), pt(0.5)), inv);
    s.lo = std::max(s.lo, 0.0);
    r.h[b] = s;
    r.max = b == 0 ? max_i(pt(0.0), s) : max_i(r.max, s);
  }
  // ComputeAverageLuminanceWithoutOutlier over the ranges.
  Interval sum = pt(0.0);
  for (int b = 0; b < kHistogramSize; ++b) sum = spirv::add(sum, r.h[b]);
  Interval min_fraction = spirv::mul(sum, k.low), max_fraction = spirv::mul(sum, k.high);
  Interval weighted_log = pt(0.0), weight = pt(0.0);
  for (int b = 0; b < kHistogramSize; ++b) {
    Interval value = r.h[b];
    const Interval sub = min_i(value, min_fraction);
    value = spirv::sub(value, sub);
    min_fraction = spirv::sub(min_fraction, sub);
    max_fraction = spirv::sub(max_fraction, sub);
    value = min_i(value, max_fraction);
    max_fraction = spirv::sub(max_fraction, value);
    weighted_log = spirv::mul_add(centre_log_luminance(b, k), value, weighted_log);
    weight = spirv::add(weight, value);
  }
  const Interval average = spirv::exp2(spirv::div(weighted_log, max_i(constant(0.0001), weight)));
  r.average_px = spirv::mul(position(spirv::div(average, k.grey), k), pt(panel_width));
  return r;
}

// Colorize(x) over a range of x: saturate, lerp(cold, heat, x), lerp(middle, ·, |0.5 − x|·2).
std::array<Interval, 3> colorize_i(Interval x) {
  x = sat(x);
  const Interval s = spirv::mul(abs_i(spirv::sub(pt(0.5), x)), pt(2.0));
  const double heat[3] = {1, 0, 0}, middle[3] = {0, 1, 0}, cold[3] = {0, 0, 1};
  std::array<Interval, 3> out;
  for (int c = 0; c < 3; ++c) {
    out[c] = lerp_range_impl(pt(middle[c]), lerp_range_impl(pt(cold[c]), pt(heat[c]), x), s);
  }
  return out;
}

Box scene_box(const Image& scene, const std::vector<const AdmissibleRange*>& by_pixel, size_t i) {
  Box b;
  const double* v = &scene.data[i * 4];
  const AdmissibleRange* r = by_pixel[i];
  for (int c = 0; c < 4; ++c) {
    if (std::isnan(v[c]) || std::isinf(v[c])) b.valid = false;
    b.c[c] = pt(v[c]);
    if (r && r->lo[c] <= r->hi[c]) b.c[c] = hull(b.c[c], {r->lo[c], r->hi[c]});
    if (r && (r->nan_ok & (1u << c))) b.nan[c] = true;
  }
  return b;
}

}  // namespace

Interval lerp_range(Interval a, Interval b, Interval t) {
  return lerp_range_impl(a, b, t);
}
Interval sqrt_range(double n) {
  return sqrt_range_impl(n);
}

std::vector<AdmissibleRange> visualize_hdr_device_ranges(const VisualizeDeviceInputs& d) {
  const VisualizeHdrInputs& in = *d.in;
  const Image& scene = *in.scene_color;
  const Image& hdr = *in.hdr_scene_color;
  const Image& ref = *d.reference;
  const int w = scene.width, h = scene.height;
  const EyeAdaptationParameters& p = in.params;
  std::vector<const AdmissibleRange*> by_pixel(scene.pixel_count(), nullptr);
  for (const AdmissibleRange& r : *d.scene_ranges) by_pixel[r.pixel] = &r;

  EaConstants k;
  k.scale = constant(p.histogram_scale);
  k.bias = constant(p.histogram_bias);
  k.lum_min = constant(p.luminance_min);
  k.low = constant(p.exposure_low_percent);
  k.high = constant(p.exposure_high_percent);
  k.third = constant(1.0 / 3.0);
  k.grey = constant(kMiddleGrey);

  const PanelGeometry g = panel_geometry(w, h);
  // visualize_hdr.comp: OneOverPreExposure = 1.0 / P.pre_exposure; the histogram pass's
  // EyeAdaptationResult = P.exposure · P.pre_exposure.
  const Interval oop = spirv::div(pt(1.0), constant(d.pre_exposure));
  const Interval exposure = spirv::mul(constant(d.exposure), constant(d.pre_exposure));
  const HistogramRanges hist = histogram_ranges(hdr, p, oop, k, g.width);
  const Interval width_i = pt(g.width);
  const Interval exposure_without_bias = spirv::div(exposure, pt(1.0));
  const Interval exposure_without_bias_px =
      spirv::mul(position(spirv::div(pt(1.0), exposure_without_bias), k), width_i);
  const Interval exposure_px = spirv::mul(position(spirv::div(pt(1.0), exposure), k), width_i);
  const Interval pos_min = position(spirv::div(constant(p.min_average_luminance), k.grey), k);
  const Interval pos_max = position(spirv::div(constant(p.max_average_luminance), k.grey), k);

  // The swatch: the mean of 441 bilinear samples of the scene (weights 0, ½, 1: exact), each
  // sample's three additions and the sum of 441 terms in any order ((n − 1)·u of the sum of
  // magnitudes), then / 441 (2.5 ULP).
  Box swatch = box_of(0, 0, 0, 1);
  {
    std::array<double, 3> s_lo{}, s_hi{}, s_abs{};
    for (int ox = -10; ox <= 10; ++ox)
      for (int oy = -10; oy <= 10; ++oy) {
        const double fx = w * 0.5 + ox - 0.5, fy = h * 0.5 + oy - 0.5;
        const double x0 = std::floor(fx), y0 = std::floor(fy), tx = fx - x0, ty = fy - y0;
        auto cx = [&](double v) { return static_cast<int>(std::clamp(v, 0.0, w - 1.0)); };
        auto cy = [&](double v) { return static_cast<int>(std::clamp(v, 0.0, h - 1.0)); };
        const int xs[2] = {cx(x0), cx(x0 + 1)}, ys[2] = {cy(y0), cy(y0 + 1)};
        const double wx[2] = {1 - tx, tx}, wy[2] = {1 - ty, ty};
        for (int j = 0; j < 2; ++j)
          for (int i = 0; i < 2; ++i) {
            const size_t idx = static_cast<size_t>(ys[j]) * w + xs[i];
            const Box b = scene_box(scene, by_pixel, idx);
            if (!b.valid) swatch.valid = false;
            for (int c = 0; c < 3; ++c) {
              const double wt = wx[i] * wy[j];
              s_lo[c] += wt * b.c[c].lo;
              s_hi[c] += wt * b.c[c].hi;
              s_abs[c] += wt * std::max(std::fabs(b.c[c].lo), std::fabs(b.c[c].hi));
            }
          }
      }
    for (int c = 0; c < 3; ++c) {
      const double e = (440.0 + 3.0) * kU * s_abs[c] / (1.0 - 443.0 * kU);
      swatch.c[c] = spirv::div({s_lo[c] - e, s_hi[c] + e}, pt(441.0));
    }
  }

  // The overlay's tone curve per column: L(u) = exp2((u − Bias)/Scale), FilmToneMap of the grey
  // EyeAdaptationResult · L at the ends of its range, widened by kShaderNoise × its largest
  // channel.
  std::vector<std::array<Interval, 3>> mapped(static_cast<size_t>(g.width));
  std::vector<Interval> column_u(static_cast<size_t>(g.width));
  for (int ix = 0; ix < g.width; ++ix) {
    const Interval u = spirv::div(pt(ix), width_i);
    column_u[static_cast<size_t>(ix)] = u;
    const Interval lum = spirv::exp2(spirv::div(spirv::sub(u, k.bias), k.scale));
    const Interval grey = spirv::mul(exposure, lum);
    const Vec3 a = in.tone_curve(Vec3{grey.lo, grey.lo, grey.lo});
    const Vec3 b = in.tone_curve(Vec3{grey.hi, grey.hi, grey.hi});
    double scale = 0;
    for (int c = 0; c < 3; ++c) scale = std::max({scale, std::fabs(a[c]), std::fabs(b[c])});
    for (int c = 0; c < 3; ++c) {
      mapped[static_cast<size_t>(ix)][c] = {std::min(a[c], b[c]) - kShaderNoise * scale,
                                            std::max(a[c], b[c]) + kShaderNoise * scale};
    }
  }

  const int cx = static_cast<int>(w / 2.0), cy = static_cast<int>(h / 2.0);
  const double ix_centre = cx;
  const double iy_centre = cy >= 100 ? cy - 100.0 : cy - 100.0 + 4294967296.0;
  const int debug_type = p.visualize_debug_type;

  std::vector<AdmissibleRange> out;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = static_cast<size_t>(y) * w + x;
      Box box;
      const double dx = std::fabs(static_cast<double>(x - cx));
      const double dy = std::fabs(static_cast<double>(y - cy));
      bool done = false;
      if (dx < 180 && dy < 42) {
        if (dx < 10 && dy < 10) {
          box = (dx == 9 || dy == 9) ? box_of(1, 1, 1, 1) : swatch;
        } else {
          box = scene_box(scene, by_pixel, i);
          box.valid = true;  // passed through unchanged: the scene's own range
        }
        done = true;
      } else if (in.illuminance_meter_enabled) {
        const double pdx = x - ix_centre, pdy = y - iy_centre;
        if (pdx > -20 && pdx < 300 && pdy < 40 && pdy > -20) {
          const int adx = static_cast<int>(std::fabs(pdx)), ady = static_cast<int>(std::fabs(pdy));
          box = (adx < 10 && ady < 10 && (adx == 9 || ady == 9)) ? box_of(1, 1, 1, 1)
                                                                 : scene_box(scene, by_pixel, i);
          box.valid = true;
          done = true;
        }
      }
      if (!done) {
        // Background.
        const double* c = &hdr.data[i * 4];
        const bool finite = std::isfinite(c[0]) && std::isfinite(c[1]) && std::isfinite(c[2]);
        if (debug_type == 0) {
          box = scene_box(scene, by_pixel, i);
        } else if (debug_type == 1) {
          // ComputePlaceInHistogram: log2(dot(rgb, 1)/3), per bucket saturate((logL − lo)/(hi −
          // lo)), Σ h·t / Σ h; then the bands < Low (red), ≥ High (blue).
          const double* rv = &ref.data[i * 4];
          Box grey = box_of(rv[0], rv[1], rv[2], 0.0);
          Outcomes below{false, true}, above{false, true};
          if (finite) {
            Interval s = spirv::mul(pt(c[0]), oop);
            s = spirv::add(s, spirv::mul(pt(c[1]), oop));
            s = spirv::add(s, spirv::mul(pt(c[2]), oop));
            const Interval mean = spirv::div(s, pt(3.0));
            Interval below_sum = pt(0.0), total = pt(0.0);
            const bool positive = mean.lo > 0;
            const Interval lg = positive
                                    ? spirv::log2(mean)
                                    : Interval{-kInf, mean.hi > 0 ? std::log2(mean.hi) : -kInf};
            for (int b = 0; b < kHistogramSize; ++b) {
              const Interval lo = centre_log_luminance(b, k), hi = centre_log_luminance(b + 1, k);
              Interval t{0.0, 0.0};
              if (lg.hi > -kInf) {
                const Interval num = positive
                                         ? spirv::sub(lg, lo)
                                         : Interval{-kInf, lg.hi - lo.lo + spirv::ulp32(lg.hi)};
                const Interval q =
                    spirv::div({std::max(num.lo, -1e30), num.hi}, spirv::sub(hi, lo));
                t = sat(q);
              }
              below_sum = spirv::mul_add(hist.h[b], t, below_sum);
              total = spirv::add(total, hist.h[b]);
            }
            if (total.lo > 0) {
              const Interval perc = spirv::div(below_sum, total);
              for (int ch = 0; ch < 3; ++ch) grey.c[ch] = hull(grey.c[ch], perc);
              below = less(perc, k.low);
              const Outcomes under_high = less(perc, k.high);
              above = {under_high.f, under_high.t};
            }
          }
          // Outcomes: grey where neither band, red where below, blue where not below and above.
          Box r;
          bool any = false;
          auto take = [&](const Box& b) {
            r = any ? hull(r, b) : b;
            any = true;
          };
          if (finite) {
            if (below.f && above.f) take(grey);
            if (below.t) take(box_of(0.5, 0, 0, 0));
            if (below.f && above.t) take(box_of(0, 0, 0.5, 0));
          } else {
            take(box_of(rv[0], rv[1], rv[2], 0.0));
          }
          box = r;
        } else if (debug_type == 2) {
          if (finite) {
            Interval dot = spirv::mul(spirv::mul(pt(c[0]), oop), k.third);
            dot = spirv::mul_add(spirv::mul(pt(c[1]), oop), k.third, dot);
            dot = spirv::mul_add(spirv::mul(pt(c[2]), oop), k.third, dot);
            const Interval l = spirv::mul(max_i(dot, k.lum_min), constant(in.luminance_scale));
            box.c = {l, l, l, pt(0.0)};
          } else {
            box.valid = false;
          }
        } else {
          box = box_of(0, 0, 0, 0);
        }

        // The frame: u = inset_x / width, Colorize(u), distance = sqrt(rx² + ry²), three lerps.
        const int inset_x = x - g.left, inset_y = y - g.top;
        const Interval u = spirv::div(pt(inset_x), width_i);
        const int rx = std::max(0, x - g.right()) + std::max(0, g.left - x);
        const int ry = std::max(0, y - g.bottom()) + std::max(0, g.top - y);
        const double n = static_cast<double>(rx) * rx + static_cast<double>(ry) * ry;
        // Every pixel outside the meters takes the three lerps (inside the panel, distance 0 makes
        // them black: 0 + 0·(rgb − 0)); sqrt(0) = 1/inversesqrt(0) = 1/+Inf = 0 exactly.
        const Interval dist = n > 0 ? sqrt_range_impl(n) : pt(0.0);
        const std::array<Interval, 3> border = colorize_i(u);
        for (int ch = 0; ch < 3; ++ch) {
          Interval v = lerp_range_impl(pt(0.0), box.c[ch], sat(spirv::sub(dist, pt(6.0))));
          v = lerp_range_impl(border[ch], v, sat(spirv::sub(dist, pt(5.0))));
          box.c[ch] = lerp_range_impl(pt(0.0), v, sat(spirv::sub(dist, pt(1.0))));
        }
        if (n == 0) {
          // Inside: the region tint, the bar, the overlay, the lines.
          auto both = [](const Box& a, const Box& b, Outcomes o) {
            return o.t && o.f ? hull(a, b) : (o.t ? a : b);
          };
          auto lerp_box = [](const Box& a, const std::array<Interval, 4>& to, Interval t,
                             int channels) {
            Box r = a;
            for (int ch = 0; ch < channels; ++ch) r.c[ch] = lerp_range_impl(a.c[ch], to[ch], t);
            return r;
          };
          const Outcomes lt_min = less(u, pos_min), lt_max = less(u, pos_max);
          const Outcomes grey_tint{lt_min.t || lt_max.f, lt_min.f && lt_max.t};
          const Box grey = lerp_box(box, {pt(0.5), pt(0.5), pt(0.5), pt(0)}, pt(0.5), 3);
          const Box green = lerp_box(box, {pt(0.5), pt(0.8), pt(0.5), pt(0)}, pt(0.5), 3);
          box = both(grey, green, grey_tint);
          const int bucket = std::min(inset_x * kHistogramSize / g.width, kHistogramSize - 1);
          const Interval v = spirv::div(pt(inset_y), pt(g.height));
          const Interval target = spirv::sub(pt(1.0), v);
          const Outcomes bar_below = less(spirv::div(hist.h[bucket], hist.max), target);
          const std::array<Interval, 3> cz = colorize_i(u);
          const Box bar = lerp_box(box, {cz[0], cz[1], cz[2], pt(0)}, pt(0.5), 3);
          box = both(box, bar, bar_below);  // below the target: no bar
          const auto& m = mapped[static_cast<size_t>(inset_x)];
          for (int ch = 0; ch < 3; ++ch) {
            const Interval mask = sat(spirv::mul_add(
                pt(-100.0), abs_i(spirv::sub(m[static_cast<size_t>(ch)], target)), pt(1.0)));
            box.c[ch] = lerp_range_impl(box.c[ch], pt(1.0), mask);
          }
          auto near = [&](Interval px, double limit) {
            return less(abs_i(spirv::sub(pt(inset_x), px)), pt(limit));
          };
          const Box blue = lerp_box(box, {pt(0), pt(0), pt(1), pt(0)}, pt(0.5), 4);
          box = both(blue, box, near(hist.average_px, 3.0));
          if (y > g.top + 9) {
            const Box purple = lerp_box(box, {pt(0.5), pt(0), pt(0.5), pt(0)}, pt(1.0), 4);
            box = both(purple, box, near(exposure_without_bias_px, 2.0));
          }
          if (y > g.top + 18) {
            const Box white = lerp_box(box, {pt(1), pt(1), pt(1), pt(0)}, pt(1.0), 4);
            box = both(white, box, near(exposure_px, 2.0));
          }
        }
      }
      if (!box.valid) continue;
      // The reference's own value is admissible (it is computed along another path).
      const double* rv = &ref.data[i * 4];
      AdmissibleRange a;
      a.pixel = i;
      bool wider = false;
      for (int ch = 0; ch < 4; ++ch) {
        double lo = box.c[ch].lo, hi = box.c[ch].hi;
        if (std::isnan(rv[ch])) {
          if (!box.nan[ch]) lo = hi = rv[ch];
          a.nan_ok |= uint8_t(1u << ch);
        } else {
          lo = std::min(lo, rv[ch]);
          hi = std::max(hi, rv[ch]);
          if (box.nan[ch]) a.nan_ok |= uint8_t(1u << ch);
        }
        a.lo[ch] = lo;
        a.hi[ch] = hi;
        wider = wider || box.nan[ch] != std::isnan(rv[ch]) ||
                (!std::isnan(rv[ch]) && (lo != rv[ch] || hi != rv[ch]));
      }
      if (wider) out.push_back(a);
    }
  }
  return out;
}

}  // namespace hdrc::ref::visualize
