#include "reference/ue/combine_luts.h"

#include <Imath/half.h>

#include <algorithm>
#include <cmath>

#include "color/d3d_math.h"
#include "color/gamma_correction.h"
#include "color/st2084.h"
#include "reference/color/device_allowance.h"
#include "reference/color/fast_paths.h"
#include "reference/color/linear_tap.h"
#include "reference/color/noise_range.h"
#include "reference/color/ue_matrices.h"
#include "reference/ue/aces/aces_output.h"
#include "reference/ue/grading/color_correct.h"
#include "reference/ue/grading/color_polynomial.h"
#include "reference/ue/grading/expand_gamut.h"
#include "reference/ue/grading/film_tonemap.h"
#include "reference/ue/grading/hlsl_ops.h"
#include "reference/ue/lut_shaper.h"
#include "reference/ue/lut_store_range.h"
#include "reference/ue/ue_pixel_device.h"

namespace hdrc::ref {

namespace {

// UE stores OutDeviceColor / 1.05 and the tonemapper multiplies by 1.05 again (docs/spec/ue55.md
// §4.12).
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

Vec3 pq_encode(const Vec3& nits) {
  Vec3 out;
  for (int c = 0; c < 3; ++c) {
    const double v = nits[c];
    out[c] = (std::isnan(v) || v < 0.0) ? d3d::kNaN : st2084::pq_from_nits(v);
  }
  return out;
}

}  // namespace

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

namespace {

// combine_luts_texel from its decoded LinearColor on (§4.4 onwards): `decoded` is
// lut_decode(lattice) there, or that value moved within the decode's device range
// (decode_device_spread).
Vec3 combine_luts_texel_decoded(const ParamBlock& p, const Vec3& lattice, const Vec3& decoded,
                                CombineLutsTrace* trace, const UeLutSet* luts) {
  CombineLutsTrace t;
  t.lattice = lattice;
  const int device = p.output_device;
  t.decoded = decoded;
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
  // §4.9 the user LUT blend (only for BLENDCOUNT > 1), between FilmColor = max(0, FromAP1 ·
  // ColorAP1) and ColorCorrection (docs/ue55-lut-blend-spec.md §3.1 steps 8-10).
  Vec3 film_tone_mapped = grading::film_color(t.color_corrected, film, wcs);
  if (luts && p.lut_blend_count > 1) film_tone_mapped = blend_user_luts(film_tone_mapped, p, *luts);
  const Vec3 film_color = grading::apply_mapping_polynomial(
      film_tone_mapped,
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
      // ScRGB devices (5/6) keep AP1: the tonemapper converts (docs/spec/ue55.md §3.5).
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

}  // namespace

Vec3 combine_luts_texel(const ParamBlock& p, const Vec3& lattice, CombineLutsTrace* trace,
                        const UeLutSet* luts) {
  // §4.3 decode.
  Vec3 decoded;
  for (int c = 0; c < 3; ++c) decoded[c] = lut_decode(p.output_device, lattice[c]);
  return combine_luts_texel_decoded(p, lattice, decoded, trace, luts);
}

// FilmColor's gamma, the output matrices and the SDR encodes of devices 0 and 1 over a range of
// FilmColorNoGamma (each step nondecreasing per channel, or an exact interval matrix); device 2's
// explicit-gamma encode is left to the caller.
Range3 sdr_encode_range(const ParamBlock& p, const grading::InverseGamma& inverse_gamma, Range3 r) {
  const int device = p.output_device;
  r = map_nondecreasing(r, [&](double v) {
    return grading::apply_film_gamma({v, v, v}, inverse_gamma)[0];
  });
  if (device != 0 || !p.wcs_is_srgb)
    r = apply_matrix(p.ap1_to_output, apply_matrix(p.wcs_to_ap1, r));
  if (device == 0) return map_nondecreasing(r, [](double v) { return linear_to_srgb(v); });
  if (device == 1)
    return map_nondecreasing(r, [](double v) { return linear_to_rec709_branchless(v); });
  return r;
}

TexelRange stored_range(const ParamBlock& p, const grading::InverseGamma& inverse_gamma,
                        const Vec3& film, const Vec3& pq_in) {
  TexelRange t;
  const int device = p.output_device;
  const Mat3& to_output = p.ap1_to_output;
  Range3 r;
  bool ambiguous = false;
  if (device <= 2) {
    // FilmColor = pow(max(0, FilmColorNoGamma), InverseGamma.y): steep at 0 for gammas over 1.
    r = Range3::point(film);
    ambiguous = widen_near_zero(film, kFloat32Noise, &r);
    // Device 2's explicit-gamma encode, pow(x, 1/gamma): NaN below 0.
    Vec3 x{};
    Range3 x_widened;
    bool x_ambiguous = false;
    if (device == 2) {
      x = to_output * (p.wcs_to_ap1 * grading::apply_film_gamma(film, inverse_gamma));
      x_widened = Range3::point(x);
      x_ambiguous = widen_near_zero(x, kFloat32Noise, &x_widened);
    }
    if (!ambiguous && !x_ambiguous) return t;
    r = sdr_encode_range(p, inverse_gamma, r);
    if (device == 2) {
      for (int c = 0; c < 3; ++c) {
        r.lo[c] = std::fmin(r.lo[c], x_widened.lo[c]);
        r.hi[c] = std::fmax(r.hi[c], x_widened.hi[c]);
      }
      const double g = p.inverse_gamma[2];
      r = map_nonnegative(r, [g](double v) { return d3d::pow(v, g); });
    }
    ambiguous = true;
  } else if (device <= 7) {
    // LinearToST2084: NaN below 0, and steep for a channel much darker than its pixel's brightest.
    // Every channel carries the same absolute noise e = kShaderNoise x max|channel| into the PQ
    // encode, whose slope grows without bound towards 0: a channel a thousandth of its pixel's
    // brightest moves by codes where the brightest moves by a hundredth of one. A channel is
    // undecided when its PQ interval [pq(x - e), pq(x + e)] admits NaN (x within e of zero), is
    // wider than a quarter of a 10-bit PQ code, or (10-bit UNORM storage) straddles a rounding
    // boundary (docs/diff-metrics.md, "Admissible ranges").
    Range3 all = Range3::point(pq_in);
    ambiguous = widen_noise(pq_in, kShaderNoise, &all);
    if (ambiguous) {
      const Range3 pq = map_nonnegative(all, [](double v) { return st2084::pq_from_nits(v); });
      r = Range3::point({st2084::pq_from_nits(pq_in[0]), st2084::pq_from_nits(pq_in[1]),
                         st2084::pq_from_nits(pq_in[2])});
      ambiguous = false;
      for (int c = 0; c < 3; ++c) {
        const bool straddles = p.lut_format == 0 && !pq.nan[c] &&
                               std::nearbyint(pq.lo[c] / kLutScale * 1023.0) !=
                                   std::nearbyint(pq.hi[c] / kLutScale * 1023.0);
        if (!(pq.nan[c] || pq.hi[c] - pq.lo[c] > kUndecidedPqWidth || straddles)) continue;
        r.lo[c] = pq.lo[c];
        r.hi[c] = pq.hi[c];
        r.nan[c] = pq.nan[c];
        ambiguous = true;
      }
    }
  }
  if (!ambiguous) return t;
  t.range = scale(r, 1.0 / kLutScale);
  t.ambiguous = true;
  return t;
}

TexelEvaluator::TexelEvaluator(const ParamBlock& p, const UeLutSet* luts)
    : p_(p),
      cc_(color_correct_params(p)),
      wcs_(working_color_space(p)),
      fade_{{p.color_scale[0], p.color_scale[1], p.color_scale[2]},
            {p.overlay_color[0], p.overlay_color[1], p.overlay_color[2], p.overlay_color[3]}},
      polynomial_{p.mapping_polynomial[0], p.mapping_polynomial[1], p.mapping_polynomial[2]},
      inverse_gamma_{p.inverse_gamma[0], p.inverse_gamma[1], p.inverse_gamma[2]},
      aces_(aces_params(p)),
      luts_(luts) {
  film_.blue_correction = p.blue_correction;
  film_.tone_curve_amount = p.tone_curve_amount;
  film_.film = {p.film_slope, p.film_toe, p.film_shoulder, p.film_black_clip, p.film_white_clip};
}

// The same operations as combine_luts_texel, in the same order, for the device's path only.
Vec3 TexelEvaluator::operator()(const Vec3& lattice, TexelRange* range) const {
  const ParamBlock& p = p_;
  if (!fast_paths()) {
    CombineLutsTrace t;
    const Vec3 stored = combine_luts_texel(p, lattice, range ? &t : nullptr, luts_);
    if (range) {
      const Mat3& to_output = p.ap1_to_output;
      const int d = p.output_device;
      const Vec3 pq_in = d == 7   ? to_output * (p.wcs_to_ap1 * t.graded)
                         : d <= 4 ? to_output * t.aces_nits
                                  : t.aces_nits;
      *range = stored_range(p, inverse_gamma_, t.film, pq_in);
      if (range->ambiguous) range->range.include(stored);
    }
    return stored;
  }
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
    if (device <= 7) {
      Vec3 pq_in;
      if (device <= 6) {
        const Vec3 nits = aces::aces_output_transforms_1000(graded, p.wcs_to_ap0, aces_);
        pq_in = device <= 4 ? to_output * nits : nits;
      } else {
        pq_in = to_output * (p.wcs_to_ap1 * graded);
      }
      out = pq_encode(pq_in);
      if (range) *range = stored_range(p, inverse_gamma_, {}, pq_in);
    } else {
      out = graded;
      if (range) *range = {};
    }
  } else {
    Vec3 film_tone_mapped = grading::film_color(corrected, film_, wcs_);
    if (luts_ && p.lut_blend_count > 1)
      film_tone_mapped = blend_user_luts(film_tone_mapped, p, *luts_);
    const Vec3 film_color = grading::apply_mapping_polynomial(film_tone_mapped, polynomial_);
    const Vec3 film = grading::apply_fade(film_color, fade_);
    if (range) *range = stored_range(p, inverse_gamma_, film, {});
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
  if (range && range->ambiguous) range->range.include(out);
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

namespace {

// Stores texel i of `lut` from its evaluated value `v` and range: the value quantised to the
// storage format and, where float32 cannot decide it, its admissible bounds (BakedLut::lo/hi/flags,
// made at the first ambiguous texel). Returns whether the texel is ambiguous. The point values of
// the texels that are not ambiguous are the caller's to fill once the arrays exist.
bool store_texel(BakedLut& lut, const ParamBlock& p, size_t i, const Vec3& v, TexelRange range) {
  Vec3& out = lut.texels[i];
  for (int c = 0; c < 3; ++c) out[c] = quantize_lut_value(p.lut_format, v[c]);
  // 10-bit UNORM: a value within float32 noise of a rounding boundary (k + 1/2)/1023 may be
  // stored as either neighbour (the noise of PQ's exponent on devices 3-7).
  if (p.lut_format == 0) {
    if (!range.ambiguous) range.range = Range3::point(v);
    const bool pq_path = p.output_device >= 3 && p.output_device <= 7;
    const double noise = pq_path ? kShaderNoise : kFloat32Noise;
    range.ambiguous =
        widen_near_rounding_boundary(v, 1023.0, noise, &range.range) || range.ambiguous;
  }
  if (!range.ambiguous) return false;
  if (!lut.has_ranges()) {  // the first ambiguous texel: the arrays are made (filled by the caller)
    lut.lo.resize(lut.texels.size());
    lut.hi.resize(lut.texels.size());
    lut.flags.assign(lut.texels.size(), 0);
  }
  // Quantisation is nondecreasing; a stored NaN is what the format makes of it (UNORM: 0).
  uint8_t flags = BakedLut::kAmbiguous;
  for (int c = 0; c < 3; ++c) {
    double lo = quantize_lut_value(p.lut_format, range.range.lo[c]);
    double hi = quantize_lut_value(p.lut_format, range.range.hi[c]);
    if (range.range.nan[c]) {
      const double stored_nan = quantize_lut_value(p.lut_format, d3d::kNaN);
      if (std::isnan(stored_nan)) {
        flags |= uint8_t(1u << c);
      } else {
        lo = std::isnan(lo) ? stored_nan : std::fmin(lo, stored_nan);
        hi = std::isnan(hi) ? stored_nan : std::fmax(hi, stored_nan);
      }
    }
    lut.lo[i][c] = lo;
    lut.hi[i][c] = hi;
  }
  lut.flags[i] = flags;
  return true;
}

// A texel that is not ambiguous, in a LUT that has ranges: its point value.
void store_point_range(BakedLut& lut, size_t k) {
  lut.lo[k] = lut.hi[k] = lut.texels[k];
  lut.flags[k] = 0;
  for (int c = 0; c < 3; ++c)
    if (std::isnan(lut.texels[k][c])) lut.flags[k] |= uint8_t(1u << c);
}

}  // namespace

BakedLut bake_lut(const ParamBlock& p, const UeLutSet* luts) {
  BakedLut lut;
  lut.size = p.lut_size;
  lut.layout = p.lut_layout;
  lut.lut_format = p.lut_format;
  const int n = p.lut_size;
  lut.texels.resize(static_cast<size_t>(n) * n * n);
  const TexelEvaluator texel(p, luts);
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) {
        TexelRange range;
        const Vec3 v = texel(lattice_coordinate(p.lut_layout, n, r, g, b), &range);
        store_texel(lut, p, lut.index(r, g, b), v, range);
      }
  if (lut.has_ranges()) {  // every texel that is not ambiguous: its point value
    for (size_t k = 0; k < lut.texels.size(); ++k)
      if (!(lut.flags[k] & BakedLut::kAmbiguous)) store_point_range(lut, k);
  }
  return lut;
}

// kEncodePowNoise's derivation: lut_store_range.h.
Range3 widen_relative(Range3 r, double k) {
  for (int c = 0; c < 3; ++c) {
    r.lo[c] -= std::fabs(r.lo[c]) * k;
    r.hi[c] += std::fabs(r.hi[c]) * k;
  }
  return r;
}

namespace {

// What a conformant device may compute for the stored value (before storage), from the texel's
// trace: the shader arithmetic's noise, kShaderNoise · max|channel| (the derivation of
// reference/color/noise_range.h, from the same table), on the value the device's encode takes,
// carried through the encode: PQ (devices 3-7) with the specification's bounds on its own steps
// (pq_encode_on_device), the SDR encodes as nondecreasing maps plus their pow's own error.
// `blend_film`: FilmColorNoGamma's range from the user-LUT blend's device range (film devices with
// BLENDCOUNT > 1), admitted besides the widened point.
Range3 device_texel_range(const ParamBlock& p, const grading::InverseGamma& inverse_gamma,
                          const CombineLutsTrace& t, const Range3* blend_film = nullptr) {
  const int device = p.output_device;
  const Mat3& to_output = p.ap1_to_output;
  Range3 r;
  if (device <= 2 || device == 9) {
    r = Range3::point(t.film);
    widen_noise(t.film, kShaderNoise, &r);
    if (blend_film) {
      for (int c = 0; c < 3; ++c) {
        r.lo[c] = std::fmin(r.lo[c], blend_film->lo[c]);
        r.hi[c] = std::fmax(r.hi[c], blend_film->hi[c]);
      }
    }
    if (device == 9) return apply_matrix(to_output, apply_matrix(p.wcs_to_ap1, r));
    r = sdr_encode_range(p, inverse_gamma, r);
    if (device == 2) {
      const double g = p.inverse_gamma[2];
      r = map_nonnegative(r, [g](double v) { return d3d::pow(v, g); });
    }
    return widen_relative(r, kEncodePowNoise);
  }
  if (device == 8) {
    r = Range3::point(t.graded);
    widen_noise(t.graded, kShaderNoise, &r);
    return r;
  }
  const Vec3 pq_in = device == 7   ? to_output * (p.wcs_to_ap1 * t.graded)
                     : device <= 4 ? to_output * t.aces_nits
                                   : t.aces_nits;
  double scale = 0;
  for (int c = 0; c < 3; ++c)
    if (std::isfinite(pq_in[c])) scale = std::fmax(scale, std::fabs(pq_in[c]));
  const double e = kShaderNoise * scale;
  // The same noise where the upstream arithmetic ends, before the output matrices (GradedColor
  // through ToAP1 and AP1 → output for device 7, the ACES output's AP1 nits through AP1 → output
  // for 3-4), carried through them as exact interval products (noise_range.h apply_matrix): a
  // row with cancelling coefficients turns its inputs' noise into more than kShaderNoise of its
  // dark output.
  Range3 before{};
  const bool matrices = device == 7 || device <= 4;
  if (matrices) {
    const Vec3& upstream = device == 7 ? t.graded : t.aces_nits;
    before = Range3::point(upstream);
    widen_noise(upstream, kShaderNoise, &before);
    before = device == 7 ? apply_matrix(to_output, apply_matrix(p.wcs_to_ap1, before))
                         : apply_matrix(to_output, before);
  }
  for (int c = 0; c < 3; ++c) {
    if (!std::isfinite(pq_in[c])) {
      r.lo[c] = r.hi[c] = st2084::pq_from_nits(pq_in[c]);
      r.nan[c] = std::isnan(r.lo[c]);
      continue;
    }
    double lo = pq_in[c] - e, hi = pq_in[c] + e;
    if (matrices && std::isfinite(before.lo[c]) && std::isfinite(before.hi[c])) {
      lo = std::fmin(lo, before.lo[c]);
      hi = std::fmax(hi, before.hi[c]);
    }
    if (lo < 0) r.nan[c] = true;  // PQ (pow) of a negative value: NaN
    if (hi < 0) {
      r.lo[c] = r.hi[c] = d3d::kNaN;
      continue;
    }
    lo = std::fmax(lo, 0.0);
    const spirv::Interval pq = pq_encode_on_device(lo, hi);
    r.lo[c] = pq.lo;
    r.hi[c] = pq.hi;
  }
  return r;
}

// The lattice decode's own error on a conformant device, carried to the stored value. The shaper's
// decode of the lattice coordinate (combine_luts.glsl lut_lattice_coordinate: texel/(N − 1), a 2.5
// ULP division, plus the unwrapped layout's bias add, 0.5 ULP) is evaluated op by op with the
// precision table's bounds (ue_pixel_device.h lut_decode). PQ (devices 3-9; lut_shaper.glsl
// lut_decode, ST2084ToLinear: pow(e, 1/m2), the subtraction of c1 and c2 − c3·np, a division,
// pow(·, 1/m1) = 6.28): relative to the decoded value ±5.2e-5 at lattice 1/31, ±9.6e-5 at 15/31,
// ±1.7e-4 at 30/31, 2 to 6 times kShaderNoise. Log (devices 0-2, LogToLin(e) − LogToLin(0)):
// 2.5e-6 relative at mid-grey, but near black the subtraction cancels and leaves an absolute
// ~1e-8 (1.3e-4 relative at lattice 0.0023). noise_range.h's convention (the arithmetic's noise at
// the end of the upstream steps, relative to the largest channel) holds neither: each channel's
// error enters before the working colour space and AP1 matrices, so a cancelling row turns it
// into a larger relative error of a dark output channel, and a texel near black has no large
// channel. Carried through the rest of the texel function (combine_luts_texel_decoded) to first
// order: the function's change for each decoded channel moved on its own to its range's farther
// end, summed in absolute value per output channel (the hull of a linear map over the decode's
// box). Returns those sums (stored units); zero for a lattice channel at 0 (0/(N − 1) and its
// decode are exact).
Vec3 decode_device_spread(const ParamBlock& p, const CombineLutsTrace& t, const UeLutSet* luts) {
  Vec3 spread{0.0, 0.0, 0.0};
  const Vec3& v = t.stored;
  for (int c = 0; c < 3; ++c) {
    if (!(t.lattice[c] > 0) || !std::isfinite(t.decoded[c])) continue;
    const spirv::Interval e = spirv::widen_ulp(spirv::Interval::point(t.lattice[c]), 3.0);
    const spirv::Interval d = ue_device::lut_decode(p.output_device, e);
    const double h = std::fmax(d.hi - t.decoded[c], t.decoded[c] - d.lo);
    if (!(h > 0)) continue;
    Vec3 moved = t.decoded;
    moved[c] += h;
    const Vec3 w = combine_luts_texel_decoded(p, t.lattice, moved, nullptr, luts);
    for (int k = 0; k < 3; ++k)
      if (std::isfinite(w[k]) && std::isfinite(v[k])) spread[k] += std::fabs(w[k] - v[k]);
  }
  return spread;
}

void widen_by(const Vec3& spread, Range3* r) {
  for (int c = 0; c < 3; ++c) {
    r->lo[c] -= spread[c];
    r->hi[c] += spread[c];
  }
}

}  // namespace

void store_either_way(int lut_format, bool fp16_rte, const Range3& r, Vec3* lo, Vec3* hi,
                      uint8_t* nan_flags) {
  for (int c = 0; c < 3; ++c) {
    double l = r.lo[c], h = r.hi[c];
    const bool nan = r.nan[c] || std::isnan(l) || std::isnan(h);
    switch (lut_format) {
      case 0:
        l = std::isnan(l) ? 0.0 : unorm_floor(l, 1023.0);
        h = std::isnan(h) ? 0.0 : unorm_ceil(h, 1023.0);
        if (nan) l = 0.0;  // D3D's NaN → 0 (the port zeroes NaN before the store)
        break;
      case 1:
        l = fp16_rte ? quantize_lut_value(1, l) : half_round_down(l);
        h = fp16_rte ? quantize_lut_value(1, h) : half_round_up(h);
        if (nan) *nan_flags |= uint8_t(1u << c);
        break;
      default:
        l = float_round_down(l);
        h = float_round_up(h);
        if (nan) *nan_flags |= uint8_t(1u << c);
        break;
    }
    (*lo)[c] = l;
    (*hi)[c] = h;
  }
}

namespace {

// FilmColorNoGamma's range on a device from the user-LUT blend's (BLENDCOUNT > 1): the blend's
// range (blend_user_luts_device_range, from FilmColor before the blend: the film tone curve of
// the trace's ColorCorrected) through r.Color's polynomial a·x² + b·x + c (its extremes at the
// ends and, inside, the vertex −b/2a) and the fade (ColorScale, then the lerp to OverlayColor:
// linear per channel), then widened by kShaderNoise of the largest channel for that arithmetic
// (noise_range.h).
Range3 blend_film_range(const ParamBlock& p, const UeLutSet& luts, int bits,
                        const grading::FilmPathParams& film, const WorkingColorSpace& wcs,
                        const grading::Fade& fade, const CombineLutsTrace& t) {
  const Vec3 film_color = grading::film_color(t.color_corrected, film, wcs);
  const Range3 b = blend_user_luts_device_range(film_color, p, luts, bits);
  const grading::MappingPolynomial poly{p.mapping_polynomial[0], p.mapping_polynomial[1],
                                        p.mapping_polynomial[2]};
  auto polynomial = [&](double x) { return poly.a * (x * x) + poly.b * x + poly.c; };
  Range3 r;
  double scale = 0;
  for (int c = 0; c < 3; ++c) {
    double lo = std::fmin(polynomial(b.lo[c]), polynomial(b.hi[c]));
    double hi = std::fmax(polynomial(b.lo[c]), polynomial(b.hi[c]));
    if (poly.a != 0) {
      const double vertex = -poly.b / (2 * poly.a);
      if (vertex > b.lo[c] && vertex < b.hi[c]) {
        lo = std::fmin(lo, polynomial(vertex));
        hi = std::fmax(hi, polynomial(vertex));
      }
    }
    // apply_fade: lerp(x·ColorScale, OverlayColor.rgb, OverlayColor.a), per channel.
    const double alpha = fade.overlay_color[3];
    auto faded = [&](double x) {
      return x * fade.color_scale[c] * (1 - alpha) + fade.overlay_color[c] * alpha;
    };
    r.lo[c] = std::fmin(faded(lo), faded(hi));
    r.hi[c] = std::fmax(faded(lo), faded(hi));
    scale = std::fmax(scale, std::fmax(std::fabs(r.lo[c]), std::fabs(r.hi[c])));
  }
  const double e = kShaderNoise * scale;
  for (int c = 0; c < 3; ++c) {
    r.lo[c] -= e;
    r.hi[c] += e;
  }
  return r;
}

}  // namespace

BakedLut bake_lut_device(const ParamBlock& p, const DevicePrecision& device, const UeLutSet* luts) {
  BakedLut lut = bake_lut(p, luts);
  const int n = p.lut_size;
  const grading::InverseGamma inverse_gamma{p.inverse_gamma[0], p.inverse_gamma[1],
                                            p.inverse_gamma[2]};
  std::vector<Vec3> lo(lut.texels.size()), hi(lut.texels.size());
  std::vector<uint8_t> flags(lut.texels.size(), BakedLut::kAmbiguous);
  // The user-LUT blend (film devices, BLENDCOUNT > 1): its lookups' weight boxes and pow pair.
  const int d = p.output_device;
  const bool blend = luts && p.lut_blend_count > 1 && (d <= 2 || d == 9);
  grading::FilmPathParams film;
  film.blue_correction = p.blue_correction;
  film.tone_curve_amount = p.tone_curve_amount;
  film.film = {p.film_slope, p.film_toe, p.film_shoulder, p.film_black_clip, p.film_white_clip};
  const WorkingColorSpace wcs = working_color_space(p);
  const grading::Fade fade{
      {p.color_scale[0], p.color_scale[1], p.color_scale[2]},
      {p.overlay_color[0], p.overlay_color[1], p.overlay_color[2], p.overlay_color[3]}};
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) {
        const size_t i = lut.index(r, g, b);
        CombineLutsTrace t;
        const Vec3 v =
            combine_luts_texel(p, lattice_coordinate(p.lut_layout, n, r, g, b), &t, luts);
        Range3 blend_film;
        if (blend)
          blend_film = blend_film_range(p, *luts, device.sub_texel_bits, film, wcs, fade, t);
        Range3 range = scale(device_texel_range(p, inverse_gamma, t, blend ? &blend_film : nullptr),
                             1.0 / kLutScale);
        widen_by(decode_device_spread(p, t, luts), &range);
        range.include(v);
        store_either_way(p.lut_format, device.fp16_rte, range, &lo[i], &hi[i], &flags[i]);
        // The tight range (and the stored point) stay admissible.
        const Vec3& tl = lut.has_ranges() ? lut.lo[i] : lut.texels[i];
        const Vec3& th = lut.has_ranges() ? lut.hi[i] : lut.texels[i];
        for (int c = 0; c < 3; ++c) {
          if (!std::isnan(tl[c]))
            lo[i][c] = std::isnan(lo[i][c]) ? tl[c] : std::fmin(lo[i][c], tl[c]);
          if (!std::isnan(th[c]))
            hi[i][c] = std::isnan(hi[i][c]) ? th[c] : std::fmax(hi[i][c], th[c]);
          if (std::isnan(lut.texels[i][c]) || (lut.has_ranges() && (lut.flags[i] & (1u << c))))
            flags[i] |= uint8_t(1u << c);
        }
      }
  lut.lo = std::move(lo);
  lut.hi = std::move(hi);
  lut.flags = std::move(flags);
  return lut;
}

Range3 combine_luts_texel_device_range(const ParamBlock& p, const Vec3& lattice) {
  const grading::InverseGamma inverse_gamma{p.inverse_gamma[0], p.inverse_gamma[1],
                                            p.inverse_gamma[2]};
  CombineLutsTrace t;
  const Vec3 v = combine_luts_texel(p, lattice, &t);
  Range3 range = scale(device_texel_range(p, inverse_gamma, t), 1.0 / kLutScale);
  widen_by(decode_device_spread(p, t, nullptr), &range);
  range.include(v);
  return range;
}

LazyBakedLut::LazyBakedLut(const ParamBlock& p) : p_(p), texel_(p_) {
  const size_t n = static_cast<size_t>(p.lut_size);
  lut_.size = p.lut_size;
  lut_.layout = p.lut_layout;
  lut_.lut_format = p.lut_format;
  lut_.texels.resize(n * n * n);
  done_.assign(lut_.texels.size(), 0);
}

void LazyBakedLut::bake(int r, int g, int b) {
  const size_t i = lut_.index(r, g, b);
  if (done_[i]) return;
  done_[i] = 1;
  ++baked_;
  TexelRange range;
  const Vec3 v = texel_(lattice_coordinate(p_.lut_layout, p_.lut_size, r, g, b), &range);
  const bool had_ranges = lut_.has_ranges();
  const bool ambiguous = store_texel(lut_, p_, i, v, range);
  if (!lut_.has_ranges()) return;
  if (!had_ranges) {  // the arrays were just made: the point values of every texel baked so far
    for (size_t k = 0; k < done_.size(); ++k)
      if (done_[k] && k != i) store_point_range(lut_, k);
  } else if (!ambiguous) {
    store_point_range(lut_, i);
  }
}

namespace {

using Tap = LinearTap;  // reference/color/linear_tap.h

Vec3 mix(const Vec3& a, const Vec3& b, double f) {
  return {a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f, a[2] + (b[2] - a[2]) * f};
}

// The lookup's taps and weights, generic over what a texel holds: `at(r, g, b)` reads one and
// `lerp(a, b, f)` blends two (for the flags: their union, whatever the weight).
template <class At, class Lerp>
auto sample_texels(const BakedLut& lut, const Vec3& uvw, At at, Lerp lerp) {
  const int n = lut.size;
  if (lut.layout == 0) {
    const Tap tr = linear_tap(uvw[0] * n - 0.5, n), tg = linear_tap(uvw[1] * n - 0.5, n),
              tb = linear_tap(uvw[2] * n - 0.5, n);
    auto plane = [&](int b) {
      return lerp(lerp(at(tr.i0, tg.i0, b), at(tr.i1, tg.i0, b), tr.f),
                  lerp(at(tr.i0, tg.i1, b), at(tr.i1, tg.i1, b), tr.f), tg.f);
    };
    return lerp(plane(tb.i0), plane(tb.i1), tb.f);
  }
  // PostProcessCommon.ush: UnwrappedTexture3DSample(Texture, UVW, Size, InvSize): two bilinear
  // samples of the 2-D unwrapped texture (width N², height N, clamp addressing).
  const double w = uvw[2] * n - 0.5;
  const double int_w = std::floor(w);
  const double frac_w = w - int_w;
  const double u0 = (uvw[0] + int_w) / n;
  auto sample_2d = [&](double u, double v) {
    const Tap tx = linear_tap(u * n * n - 0.5, n * n);
    const Tap ty = linear_tap(v * n - 0.5, n);
    auto texel = [&](int x, int y) { return at(x % n, y, x / n); };
    return lerp(lerp(texel(tx.i0, ty.i0), texel(tx.i1, ty.i0), tx.f),
                lerp(texel(tx.i0, ty.i1), texel(tx.i1, ty.i1), tx.f), ty.f);
  };
  return lerp(sample_2d(u0, uvw[1]), sample_2d(u0 + 1.0 / n, uvw[1]), frac_w);
}

// UVW = enc·(N−1)/N + 0.5/N; false for a NaN coordinate (see d3d::clamp_address).
bool lookup_uvw(const BakedLut& lut, const Vec3& encoded, Vec3* uvw) {
  const int n = lut.size;
  const double scale = (n - 1.0) / n, offset = 0.5 / n;
  for (int c = 0; c < 3; ++c) {
    if (std::isnan(encoded[c])) return false;
    (*uvw)[c] = encoded[c] * scale + offset;
  }
  return true;
}

}  // namespace

Vec3 sample_lut(const BakedLut& lut, const Vec3& encoded, double lut_max) {
  Vec3 uvw;
  if (!lookup_uvw(lut, encoded, &uvw)) return {d3d::kNaN, d3d::kNaN, d3d::kNaN};
  const Vec3 s = sample_texels(
      lut, uvw, [&](int r, int g, int b) -> Vec3 { return lut.at(r, g, b); }, mix);
  return {s[0] * lut_max, s[1] * lut_max, s[2] * lut_max};
}

bool sample_lut_range(const BakedLut& lut, const Vec3& encoded, Range3* out) {
  Vec3 uvw;
  if (!lut.has_ranges() || !lookup_uvw(lut, encoded, &uvw)) return false;
  const uint8_t flags = sample_texels(
      lut, uvw, [&](int r, int g, int b) { return lut.flags[lut.index(r, g, b)]; },
      [](uint8_t a, uint8_t b, double) { return uint8_t(a | b); });
  if (!(flags & BakedLut::kAmbiguous)) return false;
  const Vec3 lo = sample_texels(
      lut, uvw, [&](int r, int g, int b) -> Vec3 { return lut.lo[lut.index(r, g, b)]; }, mix);
  const Vec3 hi = sample_texels(
      lut, uvw, [&](int r, int g, int b) -> Vec3 { return lut.hi[lut.index(r, g, b)]; }, mix);
  Range3 r;
  for (int c = 0; c < 3; ++c) {
    r.lo[c] = lo[c] * kLutScale;
    r.hi[c] = hi[c] * kLutScale;
    r.nan[c] = (flags & (1u << c)) != 0 || std::isnan(lo[c]) || std::isnan(hi[c]);
  }
  *out = r;
  return true;
}

bool sample_lut_device_range(const BakedLut& lut, const Vec3& encoded, int bits, Range3* out,
                             double lut_max, const spirv::Interval* encoded_range) {
  Vec3 uvw;
  if (!lut.has_ranges() || !lookup_uvw(lut, encoded, &uvw)) return false;
  const int n = lut.size;
  // The shader's coordinate (its encode and the scale/offset) carries its own float32 error:
  // kShaderNoise of the coordinate (noise_range.h's convention for the steps before the encode),
  // and with `encoded_range` the encode's own range on a conformant device, derived op by op
  // (ue_pixel_device.h lut_encode_clamped), then lut_sample.glsl lut_uvw (enc · ((N − 1)/N) +
  // 0.5/N: a multiply and an add, fused or not, the constants as float32 neighbours). Per axis the
  // hull of both, in texel units t = uvw·N − 0.5: [t_lo[c], t_hi[c]].
  const double coord_noise = kShaderNoise * n;
  double t_lo[3], t_hi[3];
  for (int c = 0; c < 3; ++c) {
    const double t = uvw[c] * n - 0.5;
    t_lo[c] = t - coord_noise;
    t_hi[c] = t + coord_noise;
    if (!encoded_range) continue;
    const spirv::Interval u = spirv::mul_add(
        encoded_range[c],
        spirv::Interval{float_round_down((n - 1.0) / n), float_round_up((n - 1.0) / n)},
        spirv::Interval{float_round_down(0.5 / n), float_round_up(0.5 / n)});
    t_lo[c] = std::fmin(t_lo[c], u.lo * n - 0.5);
    t_hi[c] = std::fmax(t_hi[c], u.hi * n - 0.5);
  }
  // The filter's own arithmetic in the storage format's precision (device_allowance.h
  // FilterArithmetic, VK-GL-CTS's filtering precision): 10-bit UNORM, RGBA16F or float32; each
  // tap's weight on the sub-texel grid (filter_taps' weight_bits).
  const FilterArithmetic fa = lut.lut_format == 0   ? FilterArithmetic::unorm(10)
                              : lut.lut_format == 1 ? FilterArithmetic::float16()
                                                    : FilterArithmetic::float32();
  Range3 r;
  for (int c = 0; c < 3; ++c) {
    r.lo[c] = HUGE_VAL;
    r.hi[c] = -HUGE_VAL;
  }
  uint8_t nan = 0;
  auto lo_at = [&](size_t i) -> const Vec3& { return lut.lo[i]; };
  auto hi_at = [&](size_t i) -> const Vec3& { return lut.hi[i]; };
  // One bilinear/trilinear filter over `taps` (2 or 3 axes; per axis the boxes of
  // linear_tap_boxes) at every corner of every combination of boxes: the per-channel extremes of
  // the lower and upper texel bounds.
  auto filter_extremes = [&](const std::vector<TapBox>* taps, int axes, auto index_of, Vec3* mins,
                             Vec3* maxs) {
    for (int c = 0; c < 3; ++c) {
      (*mins)[c] = HUGE_VAL;
      (*maxs)[c] = -HUGE_VAL;
    }
    size_t combos = 1;
    for (int a = 0; a < axes; ++a) combos *= taps[a].size();
    for (size_t combo = 0; combo < combos; ++combo) {
      const TapBox* box[3] = {nullptr, nullptr, nullptr};
      for (size_t a = 0, rest = combo; a < static_cast<size_t>(axes); ++a) {
        box[a] = &taps[a][rest % taps[a].size()];
        rest /= taps[a].size();
      }
      for (int corner = 0; corner < (1 << axes); ++corner) {
        double alpha[3] = {0, 0, 0};
        for (int a = 0; a < axes; ++a) alpha[a] = (corner >> a) & 1 ? box[a]->f_hi : box[a]->f_lo;
        // Tap k: bit a set for axis a's upper texel (filter_taps' order).
        double t_lo[3][8], t_hi[3][8];
        for (int k = 0; k < (1 << axes); ++k) {
          double w = 1;
          int idx[3] = {0, 0, 0};
          for (int a = 0; a < axes; ++a) {
            const bool second = (k >> a) & 1;
            w *= second ? alpha[a] : 1 - alpha[a];
            idx[a] = second ? box[a]->i1 : box[a]->i0;
          }
          const size_t i = index_of(idx);
          if (w != 0) nan |= lut.flags[i] & 0x7;
          for (int c = 0; c < 3; ++c) {
            t_lo[c][k] = lo_at(i)[c];
            t_hi[c][k] = hi_at(i)[c];
          }
        }
        FilteredRange f[3];
        filter_taps_channels(axes, alpha, 3, &t_lo[0][0], &t_hi[0][0], fa, bits, f);
        for (int c = 0; c < 3; ++c) {
          (*mins)[c] = std::fmin((*mins)[c], f[c].lo);
          (*maxs)[c] = std::fmax((*maxs)[c], f[c].hi);
        }
      }
    }
  };
  if (lut.layout == 0) {
    const std::vector<TapBox> taps[3] = {linear_tap_boxes_over(t_lo[0], t_hi[0], n, bits),
                                         linear_tap_boxes_over(t_lo[1], t_hi[1], n, bits),
                                         linear_tap_boxes_over(t_lo[2], t_hi[2], n, bits)};
    filter_extremes(
        taps, 3, [&](const int* i) { return lut.index(i[0], i[1], i[2]); }, &r.lo, &r.hi);
  } else {
    // UnwrappedTexture3DSample: the shader's lerp by frac(w) between two hardware bilinear samples
    // one slice apart, u = (uvw.r + floor(w))/N. The slice coordinate w = uvw.b·N − 0.5 carries
    // the coordinate's noise like the filter's axes: at both ends of its range and at every
    // integer between (where floor(w) steps and the lerp's weight wraps from 1 to 0), each with
    // its own slice pair and exact fraction. Along the strip's x the noise (N times larger in
    // texels) may cross a slice's first texel into the previous slice's last one, which
    // linear_tap_boxes reads (the strip's clamp-to-edge only at its ends). The lerp's own float32
    // rounding: a + t·(b − a), three correctly rounded steps, 2.5 ULP of the larger sample
    // (spirv_precision.h; as strip_device_range.h).
    std::vector<double> ws = {t_lo[2]};
    for (double k = std::floor(t_lo[2]) + 1; k < t_hi[2]; k += 1) ws.push_back(k);
    ws.push_back(t_hi[2]);
    const std::vector<TapBox> ty = linear_tap_boxes_over(t_lo[1], t_hi[1], n, bits);
    for (const double wc : ws) {
      const double int_w = std::floor(wc);
      const double frac_w = wc - int_w;
      Vec3 s_lo[2], s_hi[2];
      for (int s = 0; s < 2; ++s) {
        // The strip's x in texels, (uvw.r + floor(w) + s)·N − 0.5: the red coordinate's noise as
        // coord_noise·N strip texels (the sum and the division included), widened by the
        // derived encode's reach beyond kShaderNoise (t_lo/t_hi) where that is larger.
        const double x = uvw[0] * n + (int_w + s) * n - 0.5;
        const double below = (uvw[0] * n - 0.5 - coord_noise) - t_lo[0];
        const double above = t_hi[0] - (uvw[0] * n - 0.5 + coord_noise);
        const std::vector<TapBox> taps[2] = {
            linear_tap_boxes_over(x - coord_noise * n - below, x + coord_noise * n + above, n * n,
                                  bits),
            ty};
        filter_extremes(
            taps, 2, [&](const int* i) { return lut.index(i[0] % n, i[1], i[0] / n); }, &s_lo[s],
            &s_hi[s]);
      }
      for (int c = 0; c < 3; ++c) {
        const double big = std::fmax(std::fmax(std::fabs(s_lo[0][c]), std::fabs(s_lo[1][c])),
                                     std::fmax(std::fabs(s_hi[0][c]), std::fabs(s_hi[1][c])));
        const double e = 2.5 * spirv::ulp32(big);
        double lo = s_lo[0][c] + (s_lo[1][c] - s_lo[0][c]) * frac_w - e;
        // Non-negative samples lerp to a non-negative value (rounding is monotone).
        if (s_lo[0][c] >= 0 && s_lo[1][c] >= 0) lo = std::fmax(lo, 0.0);
        r.lo[c] = std::fmin(r.lo[c], lo);
        r.hi[c] = std::fmax(r.hi[c], s_hi[0][c] + (s_hi[1][c] - s_hi[0][c]) * frac_w + e);
      }
    }
  }
  for (int c = 0; c < 3; ++c) {
    r.lo[c] *= lut_max;
    r.hi[c] *= lut_max;
    r.nan[c] = (nan & (1u << c)) != 0 || std::isnan(r.lo[c]) || std::isnan(r.hi[c]);
  }
  *out = r;
  return true;
}

const BakedLut& LazyBakedLut::prepare(const Vec3& encoded) {
  Vec3 uvw;
  if (lookup_uvw(lut_, encoded, &uvw))  // a NaN coordinate reads no texel
    sample_texels(
        lut_, uvw,
        [&](int r, int g, int b) {
          bake(r, g, b);
          return 0;
        },
        [](int, int, double) { return 0; });
  return lut_;
}

}  // namespace hdrc::ref
