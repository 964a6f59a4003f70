// UE 5.8's CombineLUTs in float32 (pipeline ue58, stage ue58_combine_luts): the inner LUT's texel
// (PostProcessCombineLUTsInner.usf: MethodLUTsCommon, ComputeOutputACES, ComputeInvOutputACES),
// its trilinear lookup (PostProcessCombineLUTs.usf: InnerLookupTable) and the outer texel
// (CombineLUTsCommon, ApplyToneCurve, ComputeGradedColor, ComputeFilmColorNoGamma). Twin of
// reference/ue/ue58/ue58_combine_luts.cpp (same function split); sources: unicorn2022/UE5.8.0 @
// 5d9a05c15b1f8c6d7b3354b360677ce30d688149. The ACES 2.0 tables are read from P texel for texel
// (docs/ue58-decisions.md E1). The inner LUT is baked by a first pass into the scratch buffer
// (../stages/combine_luts_inner.comp: texel i = (r, g, b), r fastest, at scratch_px[i]) and the
// outer pass samples it there (docs/ue58-decisions.md E2). Needs the generated interface included
// first.
#ifndef HDRC_UE58_COMBINE_LUTS_GLSL
#define HDRC_UE58_COMBINE_LUTS_GLSL

#include "../../lib/aces_output.glsl"
#include "../../lib/color_correct.glsl"
#include "../../lib/color_polynomial.glsl"
#include "../../lib/d3d_math.glsl"
#include "../../lib/expand_gamut.glsl"
#include "../../lib/film_path.glsl"
#include "../../lib/gamma_correction.glsl"
#include "../../lib/matrix.glsl"
#include "../../lib/st2084.glsl"
#include "../../lib/ue_log_shaper.glsl"
#include "../../lib/white_balance.glsl"
#include "srgb_to_linear58.glsl"

// Which ACES 2.0 set the table hooks read: 0 the forward set (peak, limiting primaries), 1 the SDR
// set (100 nits, working primaries), as ComputeOutputACES / ComputeInvOutputACES bind them.
int ue58_aces2_set = 0;

// Texture2D<float>.Load: 0 outside the texture.
float aces2_reach_load(int i) {
  if (i < 0 || i >= 360) return 0.0;
  return ue58_aces2_set == 0 ? P.ue58_reach_table[i / 4][i % 4]
                             : P.ue58_reach_table_sdr[i / 4][i % 4];
}
float aces2_cusp_load(int c, int row) {
  if (row < 0 || row >= 362 || c < 0 || c >= 3) return 0.0;
  return ue58_aces2_set == 0 ? P.ue58_cusp_table[row][c] : P.ue58_cusp_table_sdr[row][c];
}
float aces2_gamma_load(int i) {
  if (i < 0 || i >= 362) return 0.0;
  return ue58_aces2_set == 0 ? P.ue58_gamma_table[i / 4][i % 4]
                             : P.ue58_gamma_table_sdr[i / 4][i % 4];
}

#include "../../lib/aces2_output.glsl"

const float UE58_LINEAR_TO_NITS = 100.0;     // LinearToNitsScale
const float UE58_PQ_WHITE_NITS = 10000.0;    // UE_PQ_WHITE_NITS
const float UE58_SCRGB_WHITE_NITS = 80.0;    // UE_SCRGB_WHITE_NITS
const float UE58_BT1886_GAMMA = 2.4;         // Bt1886Gamma
const float UE58_FILM_PQ_SCALE = 1.9682001;  // ApplyToneCurve (Filmic): 1 / PQ(100 nits)
const float UE58_FILM_PQ_UNSCALE = .5080784215;  // MethodLUTsCommon: undoes it

Aces2Params ue58_aces2_params(int set) {
  float v[76];
  for (int k = 0; k < 76; ++k)
    v[k] = set == 0 ? P.ue58_aces2_params[k / 4][k % 4] : P.ue58_aces2_params_sdr[k / 4][k % 4];
  return aces2_unpack(v);
}

vec3 ue58_pq(vec3 nits) {
  return vec3(pq_from_nits(nits.r), pq_from_nits(nits.g), pq_from_nits(nits.b));
}
vec3 ue58_pq_inv(vec3 e) { return vec3(nits_from_pq(e.r), nits_from_pq(e.g), nits_from_pq(e.b)); }


// The storage rounding of a LUT texel (reference: quantize_lut_value): 10-bit UNORM (NaN → 0,
// clamp, nearest k/1023), half (round to nearest even), float32.
float ue58_round_to_half_rne(float v) {
  if (isnan(v) || isinf(v)) return v;
  float a = abs(v);
  if (a >= 65520.0) return v > 0.0 ? uintBitsToFloat(0x7f800000u) : uintBitsToFloat(0xff800000u);
  if (a < 6.103515625e-05) return roundEven(v * 16777216.0) * 5.9604644775390625e-08;
  uint b = floatBitsToUint(v);
  b += 0x0fffu + ((b >> 13) & 1u);
  return uintBitsToFloat(b & 0xffffe000u);
}
float ue58_quantize(int format, float v) {
  if (format == 0) return isnan(v) ? 0.0 : floor(clamp(v, 0.0, 1.0) * 1023.0 + 0.5) / 1023.0;
  if (format == 1) return ue58_round_to_half_rne(v);
  return v;
}

// ComputeOutputACES: graded colour (working space) → nits in the output gamut.
vec3 ue58_output_aces(vec3 graded) {
  if (P.ue58_aces_version > 1) {
    ue58_aces2_set = 0;
    vec3 ap0 = mul_rows(P.wcs_to_ap0, graded * P.ue58_total_scene_color_multiplier);
    return aces2_aces_output_transform_nits(ap0, ue58_aces2_params(0), P.ue58_scale_white != 0);
  }
  return mul_rows(P.ap1_to_output, aces_output_transforms_1000(graded));
}

// ComputeInvOutputACES: the SDR inverse (ACES 2.0 only; ACES 1.3 returns magenta (1, 0, 1)).
vec3 ue58_inv_output_aces(vec3 film_nits) {
  if (P.ue58_aces_version <= 1) return vec3(1.0, 0.0, 1.0);
  ue58_aces2_set = 1;
  Aces2Params p = ue58_aces2_params(1);
  // TonemapCommon.ush: ACESInvOutputTransform (reference: aces_inv_output_transform_nits).
  vec3 xyz = aces2_mul_rows(p.output_rgb_to_xyz, film_nits / ACES2_REFERENCE_LUMINANCE);
  if (P.ue58_scale_white_sdr != 0) xyz = xyz / aces2_white_scale(p);
  xyz = aces2_clamp_zero_to_peak(xyz, p);
  vec3 ap0 = aces2_output_transform_inv(xyz, p);
  return mul_rows(P.ue58_wcs_from_ap0, ap0) / P.aces_scene_color_multiplier;
}

// MethodLUTsCommon at lattice coordinate e.
vec3 ue58_inner_texel(vec3 e) {
  vec3 graded;
  if (P.ue58_tonemapping_method == 1) {
    graded = mul_rows(P.wcs_from_ap1, ue58_pq_inv(e) / UE58_LINEAR_TO_NITS);
  } else {
    graded = ue58_inv_output_aces(ue58_pq_inv(e * UE58_FILM_PQ_UNSCALE));
  }
  vec3 out_nits = ue58_output_aces(graded);
  if (P.output_max_luminance > UE58_LINEAR_TO_NITS)
    return ue58_pq(clamp_d3d(out_nits, 0.0, UE58_PQ_WHITE_NITS));
  return linear_to_srgb(clamp_d3d(out_nits / UE58_LINEAR_TO_NITS, 0.0, 1.0));
}

// The inner LUT's stored texel (i, j, k) as the first pass bakes it: MainCS's lattice coordinate
// (DispatchThreadId * InvLUTSizeMinusOne), the format's rounding (CreateLUTRenderTarget).
vec3 ue58_inner_bake(ivec3 idx) {
  vec3 v = ue58_inner_texel(vec3(idx) / float(P.ue58_inner_lut_size - 1));
  int f = P.ue58_inner_format;
  return vec3(ue58_quantize(f, v.r), ue58_quantize(f, v.g), ue58_quantize(f, v.b));
}
// The outer pass's read of that texel.
vec3 ue58_inner_stored(ivec3 idx) {
  int m = P.ue58_inner_lut_size;
  return scratch_px[(idx.z * m + idx.y) * m + idx.x].rgb;
}

// InnerLookupTable: trilinear, clamp-to-edge, then the decode.
vec3 ue58_inner_lookup(vec3 encoded, bool inv_eotf_pq) {
  int m = P.ue58_inner_lut_size;
  vec3 color = vec3(0.0);
  if (any(isnan(encoded))) {
    color = vec3(hdrc_nan());
  } else {
    float inv = 1.0 / float(m);
    vec3 x = (encoded * (1.0 - inv) + 0.5 * inv) * float(m) - 0.5;
    vec3 fl = floor(x);
    vec3 f = x - fl;
    ivec3 i = ivec3(clamp(fl, vec3(-1.0), vec3(float(m))));
    ivec3 i0 = clamp(i, ivec3(0), ivec3(m - 1));
    ivec3 i1 = clamp(i + 1, ivec3(0), ivec3(m - 1));
    for (int corner = 0; corner < 8; ++corner) {
      bvec3 hi = bvec3((corner & 1) != 0, (corner & 2) != 0, (corner & 4) != 0);
      vec3 w3 = mix(1.0 - f, f, vec3(hi));
      float w = w3.x * w3.y * w3.z;
      if (w == 0.0) continue;  // a texel with weight 0 adds nothing (as the reference skips it)
      color += w * ue58_inner_stored(ivec3(hi.x ? i1.x : i0.x, hi.y ? i1.y : i0.y,
                                           hi.z ? i1.z : i0.z));
    }
  }
  if (P.output_max_luminance > UE58_LINEAR_TO_NITS) {
    if (!inv_eotf_pq) color = ue58_pq_inv(color) / UE58_LINEAR_TO_NITS;
  } else {
    color = vec3(ue58_srgb_to_linear(color.r), ue58_srgb_to_linear(color.g),
                 ue58_srgb_to_linear(color.b));
    if (inv_eotf_pq) color = ue58_pq(color * UE58_LINEAR_TO_NITS);
  }
  return color;
}

// ComputeGradedColor.
vec3 ue58_graded_color(vec3 color_ap1) { return apply_fade(mul_rows(P.wcs_from_ap1, color_ap1)); }

// ApplyToneCurve(ColorAP1, PeakLuminance, AP1_2_Output, InvEOTF).
vec3 ue58_apply_tone_curve(vec3 color_ap1, float peak, bool inv_eotf_pq) {
  if (P.ue58_tonemapping_method == 1) {
    vec3 graded_ap1 = mul_rows(P.wcs_to_ap1, ue58_graded_color(color_ap1));
    vec3 enc = ue58_pq(clamp_d3d(graded_ap1 * UE58_LINEAR_TO_NITS, 0.0, UE58_PQ_WHITE_NITS));
    return ue58_inner_lookup(enc, inv_eotf_pq);
  }
  vec3 film = apply_film_gamma(apply_fade(apply_mapping_polynomial(film_color(color_ap1))));
  vec3 out_color = (P.wcs_is_srgb != 0 && P.output_gamut == 0)
                       ? film
                       : mul_rows(P.ap1_to_output, mul_rows(P.wcs_to_ap1, film));
  if (peak > UE58_LINEAR_TO_NITS) {
    if (P.ue58_sdr_inv_eotf == 0) out_color = pow_d3d(linear_to_srgb(out_color), UE58_BT1886_GAMMA);
    vec3 enc = ue58_pq(clamp_d3d(out_color * UE58_LINEAR_TO_NITS, 0.0, UE58_PQ_WHITE_NITS)) *
               UE58_FILM_PQ_SCALE;
    return ue58_inner_lookup(enc, inv_eotf_pq);
  }
  return inv_eotf_pq ? ue58_pq(out_color * UE58_LINEAR_TO_NITS) : out_color;
}

// CombineLUTsCommon: the stored value OutDeviceColor * LUTInvMax.
vec3 ue58_outer_texel(vec3 e) {
  vec3 linear = P.ue58_lut_shaper != 0
                    ? ue58_pq_inv(e) / UE58_LINEAR_TO_NITS
                    : vec3(lin_from_log(e.r), lin_from_log(e.g), lin_from_log(e.b)) -
                          lin_from_log(0.0);
  vec3 ap1 = expand_gamut(mul_rows(P.wcs_to_ap1, white_balance(linear)), P.expand_gamut);
  vec3 cc = color_correct_all(ap1);
  int device = P.output_device;
  vec3 device_color;
  if (device == 0) {
    vec3 x = ue58_apply_tone_curve(cc, UE58_LINEAR_TO_NITS, false);
    device_color = P.ue58_sdr_inv_eotf == 0 ? linear_to_srgb(x) : pow_d3d(x, 1.0 / UE58_BT1886_GAMMA);
  } else if (device == 1) {
    device_color = linear_to_rec709_branchless(ue58_apply_tone_curve(cc, UE58_LINEAR_TO_NITS, false));
  } else if (device == 3 || device == 4) {
    device_color = ue58_apply_tone_curve(cc, P.output_max_luminance, true);
  } else if (device == 5 || device == 6) {
    device_color = (UE58_LINEAR_TO_NITS / UE58_SCRGB_WHITE_NITS) *
                   ue58_apply_tone_curve(cc, P.output_max_luminance, false);
  } else if (device == 7) {
    device_color = ue58_pq(mul_rows(P.ap1_to_output, mul_rows(P.wcs_to_ap1, ue58_graded_color(cc))));
  } else if (device == 8) {
    device_color = ue58_graded_color(cc);
  } else if (device == 9) {
    device_color = ue58_apply_tone_curve(cc, UE58_LINEAR_TO_NITS, false);
  } else {
    device_color = pow_d3d(ue58_apply_tone_curve(cc, UE58_LINEAR_TO_NITS, false), P.inverse_gamma.z);
  }
  return device_color * P.ue58_lut_inv_max;
}

#endif
