#include "reference/ue/visualize/visualize_hdr.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "color/d3d_math.h"

namespace hdrc::ref::visualize {

namespace {

// HLSL lerp as DXC lowers it, a + t·(b − a): a NaN operand stays NaN even at t = 0 or 1.
double lerp(double a, double b, double t) {
  return a + t * (b - a);
}
Vec3 lerp(const Vec3& a, const Vec3& b, double t) {
  return {lerp(a[0], b[0], t), lerp(a[1], b[1], t), lerp(a[2], b[2], t)};
}
Vec4 lerp(const Vec4& a, const Vec4& b, double t) {
  return {lerp(a[0], b[0], t), lerp(a[1], b[1], t), lerp(a[2], b[2], t), lerp(a[3], b[3], t)};
}

Vec4 texel(const Image& img, int x, int y) {
  const double* c = img.px(x, y);
  return {c[0], c[1], c[2], c[3]};
}

// Bilinear sample with clamp addressing at texel-space coordinates (texel i's centre at i), i.e.
// UV·extent − 0.5. The meters only sample at integer or half-integer coordinates, where a GPU's
// reduced-precision filter weights (0, ½, 1) are exact.
Vec4 sample_bilinear(const Image& img, double fx, double fy) {
  const double x0 = std::floor(fx);
  const double y0 = std::floor(fy);
  const double tx = fx - x0;
  const double ty = fy - y0;
  auto clamp_x = [&](double v) { return static_cast<int>(std::clamp(v, 0.0, img.width - 1.0)); };
  auto clamp_y = [&](double v) { return static_cast<int>(std::clamp(v, 0.0, img.height - 1.0)); };
  const int xa = clamp_x(x0), xb = clamp_x(x0 + 1), ya = clamp_y(y0), yb = clamp_y(y0 + 1);
  Vec4 r{};
  for (int c = 0; c < 4; ++c) {
    const double top = img.px(xa, ya)[c] * (1.0 - tx) + img.px(xb, ya)[c] * tx;
    const double bottom = img.px(xa, yb)[c] * (1.0 - tx) + img.px(xb, yb)[c] * tx;
    r[c] = top * (1.0 - ty) + bottom * ty;
  }
  return r;
}

Vec3 rgb_of(const Vec4& c) {
  return {c[0], c[1], c[2]};
}

NumberFormat number_format(double value) {
  if (value < 1000.0) return NumberFormat::kFraction;
  if (value < 999999.0) return NumberFormat::kNoFractionLarge;
  return NumberFormat::kNoFraction10;  // also NaN: both comparisons are false
}

// Pixels from a MiniFont value's first cell to the end of its unit label: the value takes up to
// 60 px (7 or 6 cells) or 100 px (PrintFloatNoFraction(…, 10)), then 3 label cells of 8 px.
int value_and_unit_width(NumberFormat f) {
  return (f == NumberFormat::kNoFraction10 ? 100 : 60) + 3 * 8;
}

IntRect clip(const IntRect& r, const IntRect& to) {
  return {std::max(r.x0, to.x0), std::max(r.y0, to.y0), std::min(r.x1, to.x1),
          std::min(r.y1, to.y1)};
}

}  // namespace

ToneCurve per_channel(std::function<double(double)> curve) {
  return [curve = std::move(curve)](const Vec3& v) {
    return Vec3{curve(v[0]), curve(v[1]), curve(v[2])};
  };
}

PanelGeometry panel_geometry(int viewport_width, int viewport_height) {
  return {64, viewport_height - 128 - 32, viewport_width - 64 * 2, 128};
}

double distance_to_rect(int x, int y, const PanelGeometry& g) {
  const int rx = std::max(0, x - g.right()) + std::max(0, g.left - x);
  const int ry = std::max(0, y - g.bottom()) + std::max(0, g.top - y);
  return std::sqrt(static_cast<double>(rx) * rx + static_cast<double>(ry) * ry);
}

Vec3 colorize(double x) {
  x = d3d::saturate(x);
  const Vec3 heat{1.0, 0.0, 0.0};
  const Vec3 middle{0.0, 1.0, 0.0};
  const Vec3 cold{0.0, 0.0, 1.0};
  return lerp(middle, lerp(cold, heat, x), std::fabs(0.5 - x) * 2.0);
}

double ue_luminance(const Vec3& rgb) {
  return dot(rgb, Vec3{0.3, 0.59, 0.11});
}

VisualizeHdrResult visualize_hdr(const VisualizeHdrInputs& in) {
  if (!in.scene_color || !in.hdr_scene_color || !in.tone_curve) {
    throw std::invalid_argument("visualize_hdr: scene_color, hdr_scene_color and tone_curve");
  }
  const Image& scene = *in.scene_color;
  const Image& hdr = *in.hdr_scene_color;
  if (scene.width != hdr.width || scene.height != hdr.height || scene.width <= 0 ||
      scene.height <= 0) {
    throw std::invalid_argument("visualize_hdr: scene colour images must share one size");
  }
  const int w = scene.width;
  const int h = scene.height;
  const EyeAdaptationParameters& p = in.params;

  VisualizeHdrResult result;
  result.image = Image(w, h);
  VisualizeHdrText& text = result.text;

  // OutputViewportCenter = (int2)(ViewportMin + ViewportSize/2).
  const int cx = static_cast<int>(w / 2.0);
  const int cy = static_cast<int>(h / 2.0);

  // Luminance meter: 21×21 samples at UVViewportCenter + offset·ExtentInverse.
  {
    Vec4 hdr_sum{}, scene_sum{};
    for (int ox = -10; ox <= 10; ++ox) {
      for (int oy = -10; oy <= 10; ++oy) {
        const double fx = w * 0.5 + ox - 0.5;
        const double fy = h * 0.5 + oy - 0.5;
        const Vec4 a = sample_bilinear(hdr, fx, fy);
        const Vec4 b = sample_bilinear(scene, fx, fy);
        for (int c = 0; c < 3; ++c) {
          hdr_sum[c] += a[c];
          scene_sum[c] += b[c];
        }
      }
    }
    for (int c = 0; c < 3; ++c) {
      text.meter_hdr_average[c] = hdr_sum[c] / 441.0 * in.one_over_pre_exposure;
      text.meter_scene_average[c] = scene_sum[c] / 441.0;
    }
    text.meter_luminance = ue_luminance(text.meter_hdr_average);
    text.meter_luminance_format = number_format(text.meter_luminance);
    text.meter_ev100 = std::log2((text.meter_luminance / kMiddleGrey) / p.luminance_max);
  }
  const IntRect meter_region{cx - 179, cy - 41, cx + 180, cy + 42};
  text.glyph_rects.push_back(
      {clip(
           {cx + 11, cy + 11, cx + 11 + value_and_unit_width(text.meter_luminance_format), cy + 19},
           meter_region),
       "luminance meter value + NIT"});
  text.glyph_rects.push_back(
      {clip({cx + 11, cy + 22, cx + 11 + 60 + 5 * 8, cy + 30}, meter_region), "EV100 + label"});

  // Illuminance meter: centre OutputViewportCenter − uint2(0, 100) (unsigned: wraps when cy < 100),
  // 16×16 samples at offsets −8…7 around centre·ExtentInverse (a texel corner).
  const double ix = cx;
  const double iy = cy >= 100 ? cy - 100.0 : cy - 100.0 + 4294967296.0;
  if (in.illuminance_meter_enabled) {
    Vec3 sum{};
    for (int ox = -8; ox < 8; ++ox) {
      for (int oy = -8; oy < 8; ++oy) {
        const Vec4 a = sample_bilinear(hdr, ix + ox - 0.5, iy + oy - 0.5);
        for (int c = 0; c < 3; ++c) sum[c] += a[c];
      }
    }
    for (int c = 0; c < 3; ++c) {
      text.illuminance_rgb[c] = sum[c] / 256.0 * in.one_over_pre_exposure * std::numbers::pi;
    }
    text.illuminance_lux = ue_luminance(text.illuminance_rgb);
    if (cy >= 100) {
      const int ixi = cx, iyi = cy - 100;
      const IntRect region{ixi - 19, iyi - 19, ixi + 300, iyi + 40};
      const NumberFormat f = number_format(text.illuminance_lux);
      text.glyph_rects.push_back(
          {clip({ixi + 11, iyi + 11, ixi + 11 + value_and_unit_width(f), iyi + 19}, region),
           "illuminance value + LUX"});
      text.glyph_rects.push_back(
          {clip({ixi + 11, iyi + 22, ixi + 11 + 200 + 100, iyi + 30}, region),
           "illuminance R G B"});
    }
  }

  // Histogram panel and exposure lines.
  const PanelGeometry g = panel_geometry(w, h);
  const double hist_max = histogram_max(in.histogram);
  const double pos_min =
      histogram_position_from_luminance(p.min_average_luminance / kMiddleGrey, p);
  const double pos_max =
      histogram_position_from_luminance(p.max_average_luminance / kMiddleGrey, p);
  const double ear = in.eye.exposure;
  const double ear_without_bias = ear / in.eye.exposure_bias_only;
  text.average_luminance_px =
      histogram_position_from_luminance(in.eye.average_scene_luminance / kMiddleGrey, p) * g.width;
  text.exposure_without_bias_ev = std::log2(1.0 / ear_without_bias);
  text.exposure_without_bias_px =
      histogram_position_from_luminance(1.0 / ear_without_bias, p) * g.width;
  text.exposure_ev100 = std::log2((1.0 / ear) / p.luminance_max);
  text.exposure_px = histogram_position_from_luminance(1.0 / ear, p) * g.width;

  const IntRect interior{g.left, g.top, g.right() + 1, g.bottom() + 1};
  // PrintSmallFloatWithSign at HistogramLeftTop + int2(ValuePx − 6·8 − 3, 1): six 8-px cells.
  auto label_rect = [&](double value_px) {
    const double start = value_px - 6 * 8 - 3;
    const int x0 = g.left + (std::isfinite(start) ? static_cast<int>(start) : 0);
    return clip({x0, g.top + 1, x0 + 6 * 8, g.top + 9}, interior);
  };
  text.glyph_rects.push_back(
      {label_rect(text.exposure_without_bias_px), "exposure without bias EV (purple)"});
  text.glyph_rects.push_back({label_rect(text.exposure_px), "exposure EV100 (white)"});

  const double axis_log_min = log2_to_ev100(p.luminance_max, p.histogram_log_min);
  const double axis_log_max = log2_to_ev100(p.luminance_max, p.histogram_log_max);
  for (int i = 0; i <= 4; ++i) {
    text.axis_ev100[i] = lerp(axis_log_min, axis_log_max, i / 4.0);
    const int x_add = static_cast<int>(i * (w - 64 * 2 - 20.0) / 4.0);
    text.axis_anchor[i] = {64.0 + 8 + x_add - 5, h - 68.0 + 14};
  }

  const int debug_type = p.visualize_debug_type;
  result.alpha_defined = debug_type == 0;

  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      Vec4 out{};
      double* dst = result.image.px(x, y);
      auto store = [&](const Vec4& c) { std::copy(c.begin(), c.end(), dst); };

      const double dx = std::fabs(static_cast<double>(x - cx));
      const double dy = std::fabs(static_cast<double>(y - cy));
      if (dx < 180 && dy < 42) {
        if (dx < 10 && dy < 10) {
          out = (dx == 9 || dy == 9)
                    ? Vec4{1, 1, 1, 1}
                    : Vec4{text.meter_scene_average[0], text.meter_scene_average[1],
                           text.meter_scene_average[2], 1.0};
        } else {
          out = texel(scene, x, y);
        }
        store(out);
        continue;
      }

      if (in.illuminance_meter_enabled) {
        const double pdx = x - ix;
        const double pdy = y - iy;
        if (pdx > -20 && pdx < 300 && pdy < 40 && pdy > -20) {
          out = texel(scene, x, y);
          const int adx = static_cast<int>(std::fabs(pdx));
          const int ady = static_cast<int>(std::fabs(pdy));
          if (adx < 10 && ady < 10 && (adx == 9 || ady == 9)) out = {1, 1, 1, 1};
          store(out);
          continue;
        }
      }

      if (debug_type == 0) {
        out = texel(scene, x, y);
      } else if (debug_type == 1) {
        const Vec4 c = texel(hdr, x, y);
        const Vec3 rgb{c[0] * in.one_over_pre_exposure, c[1] * in.one_over_pre_exposure,
                       c[2] * in.one_over_pre_exposure};
        const double percentile = place_in_histogram(rgb, in.histogram, p);
        out = {percentile, percentile, percentile, 0.0};
        if (percentile < p.exposure_low_percent) {
          out = {0.5, 0.0, 0.0, 0.0};
        } else if (percentile >= p.exposure_high_percent) {
          out = {0.0, 0.0, 0.5, 0.0};
        }
      } else if (debug_type == 2) {
        const Vec4 c = texel(hdr, x, y);
        const Vec3 rgb{c[0] * in.one_over_pre_exposure, c[1] * in.one_over_pre_exposure,
                       c[2] * in.one_over_pre_exposure};
        const double l = eye_adaptation_luminance(rgb, p) * in.luminance_scale;
        out = {l, l, l, 0.0};
      } else {
        out = {0.0, 0.0, 0.0, 0.0};
      }

      const double inset_x = x - g.left;
      const double inset_y = y - g.top;
      const double u = inset_x / g.width;
      const double v = inset_y / g.height;
      const Vec3 border = colorize(u);
      const double distance = distance_to_rect(x, y, g);
      Vec3 rgb = rgb_of(out);
      rgb = lerp(Vec3{0, 0, 0}, rgb, d3d::saturate(distance - (4 + 2)));  // outer black ring
      rgb = lerp(border, rgb, d3d::saturate(distance - (4 + 1)));         // Colorize band
      rgb = lerp(Vec3{0, 0, 0}, rgb, d3d::saturate(distance - 1));        // inner black ring
      out = {rgb[0], rgb[1], rgb[2], out[3]};
      if (distance > 0) {
        store(out);
        continue;
      }

      // Inside the histogram.
      const int bucket = std::min(static_cast<int>(u * kHistogramSize), kHistogramSize - 1);
      const Vec3 grey{0.5, 0.5, 0.5};
      const Vec3 tint = (u < pos_min || !(u < pos_max)) ? grey : Vec3{0.5, 0.8, 0.5};
      rgb = lerp(rgb, tint, 0.5);
      if (in.histogram[bucket] / hist_max >= 1.0 - v) rgb = lerp(rgb, colorize(u), 0.5);

      const double lum = luminance_from_histogram_position(u, p);
      const Vec3 mapped = in.tone_curve(Vec3{ear * lum, ear * lum, ear * lum});
      for (int c = 0; c < 3; ++c) {
        const double mask = d3d::saturate(1.0 - 100.0 * std::fabs(mapped[c] - (1.0 - v)));
        rgb[c] = lerp(rgb[c], 1.0, mask);
      }
      out = {rgb[0], rgb[1], rgb[2], out[3]};

      if (std::fabs(inset_x - text.average_luminance_px) < 3) {
        out = lerp(out, Vec4{0, 0, 1, 0}, 0.5);  // blue: average scene luminance
      }
      if (std::fabs(inset_x - text.exposure_without_bias_px) < 2 && y > g.top + 9) {
        out = lerp(out, Vec4{0.5, 0, 0.5, 0}, 1.0);  // purple: exposure without bias
      }
      if (std::fabs(inset_x - text.exposure_px) < 2 && y > g.top + 18) {
        out = lerp(out, Vec4{1, 1, 1, 0}, 1.0);  // white: exposure
      }
      store(out);
    }
  }
  return result;
}

}  // namespace hdrc::ref::visualize
