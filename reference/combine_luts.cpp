#include "reference/combine_luts.h"

#include <Imath/half.h>

#include <algorithm>
#include <cmath>

#include "reference/aces/aces_output.h"
#include "reference/color/d3d_math.h"
#include "reference/color/fast_paths.h"
#include "reference/color/gamma_correction.h"
#include "reference/color/st2084.h"
#include "reference/color/ue_matrices.h"
#include "reference/grading/color_correct.h"
#include "reference/grading/color_polynomial.h"
#include "reference/grading/expand_gamut.h"
#include "reference/grading/film_tonemap.h"
#include "reference/grading/hlsl_ops.h"
#include "reference/lut_shaper.h"

namespace hdrc::ref {

namespace {

// UE stores OutDeviceColor / 1.05 and the tonemapper multiplies by 1.05 again (spec §4.12).
constexpr double kLutScale = 1.05;

grading::ColorCorrectZone zone(const std::array<double, 4>& sat, const std::array<double, 4>& con,
                               const std::array<double, 4>& gam, const std::array<double, 4>& gain,
                               const std::array<double, 4>& off) {
  grading::ColorCorrectZone z;
  z.saturation = sat;
  z.contrast = con;
  z.gamma = gam;
  z.gain = gain;
  z.offset = off;
  return z;
}

grading::ColorCorrectParams color_correct_params(const ParamBlock& p) {
  grading::ColorCorrectParams c;
  c.global = zone(p.cc_saturation, p.cc_contrast, p.cc_gamma, p.cc_gain, p.cc_offset);
  c.shadows = zone(p.cc_saturation_shadows, p.cc_contrast_shadows, p.cc_gamma_shadows,
                   p.cc_gain_shadows, p.cc_offset_shadows);
  c.midtones = zone(p.cc_saturation_midtones, p.cc_contrast_midtones, p.cc_gamma_midtones,
                    p.cc_gain_midtones, p.cc_offset_midtones);
  c.highlights = zone(p.cc_saturation_highlights, p.cc_contrast_highlights, p.cc_gamma_highlights,
                      p.cc_gain_highlights, p.cc_offset_highlights);
  c.shadows_max = p.cc_shadows_max;
  c.highlights_min = p.cc_highlights_min;
  c.highlights_max = p.cc_highlights_max;
  return c;
}

WorkingColorSpace working_color_space(const ParamBlock& p) {
  WorkingColorSpace w;
  w.to_ap1 = p.wcs_to_ap1;
  w.from_ap1 = p.wcs_from_ap1;
  w.to_ap0 = p.wcs_to_ap0;
  w.is_srgb = p.wcs_is_srgb != 0;
  return w;
}

Vec3 pq_encode(const Vec3& nits) {
  Vec3 out;
  for (int c = 0; c < 3; ++c) {
    const double v = nits[c];
    out[c] = (std::isnan(v) || v < 0.0) ? d3d::kNaN : st2084::pq_from_nits(v);
  }
  return out;
}

}  // namespace

aces::AcesShaderParams aces_params(const ParamBlock& p) {
  aces::AcesTonemapParams packed;
  for (int i = 0; i < 4; ++i) {
    packed.min_max_data[i] = static_cast<float>(p.aces_min_max[i]);
    packed.mid_data[i] = static_cast<float>(p.aces_mid[i]);
    packed.coefs_low_0[i] = static_cast<float>(p.aces_coefs_low_0[i]);
    packed.coefs_high_0[i] = static_cast<float>(p.aces_coefs_high_0[i]);
  }
  packed.coefs_low_4 = static_cast<float>(p.aces_coefs_low_4);
  packed.coefs_high_4 = static_cast<float>(p.aces_coefs_high_4);
  packed.scene_color_multiplier = static_cast<float>(p.aces_scene_color_multiplier);
  packed.gamut_compression = static_cast<float>(p.aces_gamut_compression);
  return aces::compute_aces_tonemap_params(packed);
}

Vec3 combine_luts_texel(const ParamBlock& p, const Vec3& lattice, CombineLutsTrace* trace) {
  CombineLutsTrace t;
  t.lattice = lattice;
  const int device = p.output_device;
  // §4.3 decode.
  for (int c = 0; c < 3; ++c) t.decoded[c] = lut_decode(device, lattice[c]);
  // §4.4 white balance (skipped by the SKIP_TEMPERATURE permutation).
  t.white_balanced = p.white_balance_enabled ? p.white_balance * t.decoded : t.decoded;
  // §4.5 to AP1 and fake wide gamut.
  t.ap1 = p.wcs_to_ap1 * t.white_balanced;
  t.expanded = grading::expand_gamut(t.ap1, p.expand_gamut);
  // §4.6 ColorCorrectAll.
  t.color_corrected = grading::color_correct_all(t.expanded, color_correct_params(p));

  const WorkingColorSpace wcs = working_color_space(p);
  const grading::Fade fade{
      {p.color_scale[0], p.color_scale[1], p.color_scale[2]},
      {p.overlay_color[0], p.overlay_color[1], p.overlay_color[2], p.overlay_color[3]}};
  // §4.7 GradedColor for the HDR / linear devices. The matrix product in float32's range: a
  // ColorGamma-0.01 texel near FLT_MAX overflows to +Inf here on the GPU, and the fade's lerp makes
  // it NaN (Inf + 0 · −Inf), as in UE's shader (docs/ue55-decisions.md, issue 11 closures).
  const Vec3 graded_ap1 = p.wcs_from_ap1 * t.color_corrected;
  t.graded = grading::apply_fade(
      {grading::hlsl::f32_range(graded_ap1[0]), grading::hlsl::f32_range(graded_ap1[1]),
       grading::hlsl::f32_range(graded_ap1[2])},
      fade);
  // §4.8, §4.10, §4.11 the SDR film path (devices 0–2 and 9).
  grading::FilmPathParams film;
  film.blue_correction = p.blue_correction;
  film.tone_curve_amount = p.tone_curve_amount;
  film.film = {p.film_slope, p.film_toe, p.film_shoulder, p.film_black_clip, p.film_white_clip};
  const Vec3 film_color = grading::apply_mapping_polynomial(
      grading::film_color(t.color_corrected, film, wcs),
      {p.mapping_polynomial[0], p.mapping_polynomial[1], p.mapping_polynomial[2]});
  t.film = grading::apply_fade(film_color, fade);  // FilmColorNoGamma
  const Vec3 film_gamma = grading::apply_film_gamma(
      t.film, {p.inverse_gamma[0], p.inverse_gamma[1], p.inverse_gamma[2]});

  // §4.12 device encodings.
  const Mat3& to_output = p.ap1_to_output;
  switch (device) {
    case 0: {
      const Vec3 x = p.wcs_is_srgb ? film_gamma : to_output * (p.wcs_to_ap1 * film_gamma);
      t.device = linear_to_srgb(x);
      break;
    }
    case 1:
      t.device = linear_to_rec709_branchless(to_output * (p.wcs_to_ap1 * film_gamma));
      break;
    case 3:
    case 4:
    case 5:
    case 6: {
      t.aces_nits = aces::aces_output_transforms_1000(t.graded, p.wcs_to_ap0, aces_params(p));
      // ScRGB devices (5/6) keep AP1: the tonemapper converts (spec §3.5).
      t.device = pq_encode(device <= 4 ? to_output * t.aces_nits : t.aces_nits);
      break;
    }
    case 7:
      t.device = pq_encode(to_output * (p.wcs_to_ap1 * t.graded));
      break;
    case 8:
      t.device = t.graded;
      break;
    case 9:
      t.device = to_output * (p.wcs_to_ap1 * t.film);
      break;
    default: {  // 2 (SDR_ExplicitGammaMapping) is also the shader's final "else"
      const Vec3 x = to_output * (p.wcs_to_ap1 * film_gamma);
      const double g = p.inverse_gamma[2];
      t.device = {d3d::pow(x[0], g), d3d::pow(x[1], g), d3d::pow(x[2], g)};
      break;
    }
  }
  for (int c = 0; c < 3; ++c) t.stored[c] = t.device[c] / kLutScale;
  if (trace) *trace = t;
  return t.stored;
}

TexelEvaluator::TexelEvaluator(const ParamBlock& p)
    : p_(p),
      cc_(color_correct_params(p)),
      wcs_(working_color_space(p)),
      fade_{{p.color_scale[0], p.color_scale[1], p.color_scale[2]},
            {p.overlay_color[0], p.overlay_color[1], p.overlay_color[2], p.overlay_color[3]}},
      polynomial_{p.mapping_polynomial[0], p.mapping_polynomial[1], p.mapping_polynomial[2]},
      inverse_gamma_{p.inverse_gamma[0], p.inverse_gamma[1], p.inverse_gamma[2]},
      aces_(aces_params(p)) {
  film_.blue_correction = p.blue_correction;
  film_.tone_curve_amount = p.tone_curve_amount;
  film_.film = {p.film_slope, p.film_toe, p.film_shoulder, p.film_black_clip, p.film_white_clip};
}

// The same operations as combine_luts_texel, in the same order, for the device's path only.
Vec3 TexelEvaluator::operator()(const Vec3& lattice) const {
  const ParamBlock& p = p_;
  if (!fast_paths()) return combine_luts_texel(p, lattice);
  const int device = p.output_device;
  Vec3 decoded;
  for (int c = 0; c < 3; ++c) decoded[c] = lut_decode(device, lattice[c]);
  const Vec3 balanced = p.white_balance_enabled ? p.white_balance * decoded : decoded;
  const Vec3 expanded = grading::expand_gamut(p.wcs_to_ap1 * balanced, p.expand_gamut);
  const Vec3 corrected = grading::color_correct_all(expanded, cc_);
  const Mat3& to_output = p.ap1_to_output;
  Vec3 out;
  if (device >= 3 && device <= 8) {
    // In float32's range, as texel() does (the ColorGamma-0.01 overflow, issue 11).
    const Vec3 graded_ap1 = p.wcs_from_ap1 * corrected;
    const Vec3 graded = grading::apply_fade(
        {grading::hlsl::f32_range(graded_ap1[0]), grading::hlsl::f32_range(graded_ap1[1]),
         grading::hlsl::f32_range(graded_ap1[2])},
        fade_);
    if (device <= 6) {
      const Vec3 nits = aces::aces_output_transforms_1000(graded, p.wcs_to_ap0, aces_);
      out = pq_encode(device <= 4 ? to_output * nits : nits);
    } else if (device == 7) {
      out = pq_encode(to_output * (p.wcs_to_ap1 * graded));
    } else {
      out = graded;
    }
  } else {
    const Vec3 film_color =
        grading::apply_mapping_polynomial(grading::film_color(corrected, film_, wcs_), polynomial_);
    const Vec3 film = grading::apply_fade(film_color, fade_);
    if (device == 9) {
      out = to_output * (p.wcs_to_ap1 * film);
    } else {
      const Vec3 film_gamma = grading::apply_film_gamma(film, inverse_gamma_);
      if (device == 0) {
        out = linear_to_srgb(p.wcs_is_srgb ? film_gamma : to_output * (p.wcs_to_ap1 * film_gamma));
      } else if (device == 1) {
        out = linear_to_rec709_branchless(to_output * (p.wcs_to_ap1 * film_gamma));
      } else {
        const Vec3 x = to_output * (p.wcs_to_ap1 * film_gamma);
        const double g = p.inverse_gamma[2];
        out = {d3d::pow(x[0], g), d3d::pow(x[1], g), d3d::pow(x[2], g)};
      }
    }
  }
  for (int c = 0; c < 3; ++c) out[c] /= kLutScale;
  return out;
}

double quantize_lut_value(int lut_format, double v) {
  switch (lut_format) {
    case 0: {  // A2B10G10R10 UNORM: D3D float→UNORM converts NaN to 0 and clamps.
      if (std::isnan(v)) return 0.0;
      const double c = v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v);
      return std::nearbyint(c * 1023.0) / 1023.0;
    }
    case 1:
      return static_cast<double>(static_cast<float>(Imath::half(static_cast<float>(v))));
    default:
      return static_cast<double>(static_cast<float>(v));
  }
}

Vec3 lattice_coordinate(int layout, int size, int r, int g, int b) {
  const double n1 = size - 1.0;
  if (layout == 0) return {r / n1, g / n1, b / n1};
  // 2-D unwrapped (N² × N): UV = ((x, y) + 0.5)/(N², N) − (0.49999/N², 0.49999/N); r =
  // frac(UV.x·N); b = UV.x − r/N; g = UV.y; Neutral = (r, g, b)·N/(N − 1).
  const double n = size, w = n * n;
  const double ux = (r + n * b + 0.5) / w - 0.49999 / w;
  const double uy = (g + 0.5) / n - 0.49999 / n;
  const double fr = ux * n - std::floor(ux * n);
  const double fb = ux - fr / n;
  return {fr * n / n1, uy * n / n1, fb * n / n1};
}

BakedLut bake_lut(const ParamBlock& p) {
  BakedLut lut;
  lut.size = p.lut_size;
  lut.layout = p.lut_layout;
  const int n = p.lut_size;
  lut.texels.resize(static_cast<size_t>(n) * n * n);
  const TexelEvaluator texel(p);
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) {
        const Vec3 v = texel(lattice_coordinate(p.lut_layout, n, r, g, b));
        Vec3& out = lut.texels[(static_cast<size_t>(b) * n + g) * n + r];
        for (int c = 0; c < 3; ++c) out[c] = quantize_lut_value(p.lut_format, v[c]);
      }
  return lut;
}

namespace {

// Linear interpolation between texels along one axis with clamp-to-edge addressing, in texel
// space: coordinate t = uvw·N − 0.5.
struct Tap {
  int i0, i1;
  double f;
};
Tap tap(double t, int n) {
  const double fl = std::floor(t);
  const double f = t - fl;
  const int i = static_cast<int>(fl);
  return {std::clamp(i, 0, n - 1), std::clamp(i + 1, 0, n - 1), f};
}

Vec3 mix(const Vec3& a, const Vec3& b, double f) {
  return {a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f, a[2] + (b[2] - a[2]) * f};
}

// Bilinear sample of the 2-D unwrapped texture (width N², height N) at uv, clamp addressing.
Vec3 sample_2d(const BakedLut& lut, double u, double v) {
  const int n = lut.size;
  const Tap tx = tap(u * n * n - 0.5, n * n);
  const Tap ty = tap(v * n - 0.5, n);
  auto texel = [&](int x, int y) -> const Vec3& { return lut.at(x % n, y, x / n); };
  return mix(mix(texel(tx.i0, ty.i0), texel(tx.i1, ty.i0), tx.f),
             mix(texel(tx.i0, ty.i1), texel(tx.i1, ty.i1), tx.f), ty.f);
}

}  // namespace

Vec3 sample_lut(const BakedLut& lut, const Vec3& encoded) {
  const int n = lut.size;
  const double scale = (n - 1.0) / n, offset = 0.5 / n;
  Vec3 uvw;
  for (int c = 0; c < 3; ++c) {
    if (std::isnan(encoded[c])) return {d3d::kNaN, d3d::kNaN, d3d::kNaN};  // see d3d::clamp_address
    uvw[c] = encoded[c] * scale + offset;
  }
  Vec3 s;
  if (lut.layout == 0) {
    const Tap tr = tap(uvw[0] * n - 0.5, n), tg = tap(uvw[1] * n - 0.5, n),
              tb = tap(uvw[2] * n - 0.5, n);
    auto plane = [&](int b) {
      return mix(mix(lut.at(tr.i0, tg.i0, b), lut.at(tr.i1, tg.i0, b), tr.f),
                 mix(lut.at(tr.i0, tg.i1, b), lut.at(tr.i1, tg.i1, b), tr.f), tg.f);
    };
    s = mix(plane(tb.i0), plane(tb.i1), tb.f);
  } else {
    // PostProcessCommon.ush: UnwrappedTexture3DSample(Texture, UVW, Size, InvSize).
    const double w = uvw[2] * n - 0.5;
    const double int_w = std::floor(w);
    const double frac_w = w - int_w;
    const double u = (uvw[0] + int_w) / n;
    s = mix(sample_2d(lut, u, uvw[1]), sample_2d(lut, u + 1.0 / n, uvw[1]), frac_w);
  }
  return {s[0] * kLutScale, s[1] * kLutScale, s[2] * kLutScale};
}

}  // namespace hdrc::ref
