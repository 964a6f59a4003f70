// PQ-space grading with a .cube LUT (pipeline `pq_grading`) in float32. Reference (double, with
// the citations and decisions): reference/pq_grading/pq_grading.h; docs/pq_grading.md. Needs the
// generated interface included first (P.pq_*, P.film_*, P.user_lut_*, sampler user_lut).
// One definition each: PQ is ../../lib/st2084.glsl, FilmToneMap ../../lib/film_tonemap.glsl and
// Narkowicz's fit the operators pipeline's op_aces_narkowicz.
#ifndef HDRC_PQ_GRADING_GLSL
#define HDRC_PQ_GRADING_GLSL

#include "../../lib/d3d_math.glsl"
#include "../../lib/film_tonemap.glsl"
#include "../../lib/matrix.glsl"
#include "../../lib/st2084.glsl"
#include "../../operators/lib/operators.glsl"

// Values of P.pq_display and P.pq_back_buffer (reference: pq_grading::Display, BackBuffer).
const int PQG_DISPLAY_SDR = 0;
const int PQG_DISPLAY_HDR = 1;
const int PQG_BB_R10G10B10A2 = 0;
const int PQG_BB_RGBA16F = 1;
const int PQG_BB_SRGB8 = 2;
const int PQG_BB_RGB8 = 3;

const float PQG_HALF_MAX = 65504.0;       // largest finite binary16
const float PQG_SCRGB_WHITE_NITS = 80.0;  // scRGB 1.0 (IEC 61966-2-2)
const float PQG_RGB8_GAMMA = 2.2;
// IEC 61966-2-1:1999 sRGB encoding.
const float PQG_SRGB_BREAK = 0.0031308;
const float PQG_SRGB_LINEAR_SCALE = 12.92;
const float PQG_SRGB_SCALE = 1.055;
const float PQG_SRGB_OFFSET = 0.055;
const float PQG_SRGB_EXPONENT = 1.0 / 2.4;

// The lighting target RGBA16F: clamp to ±65504, round to half (packHalf2x16); NaN stays NaN.
float pqg_store_rgba16f(float v) {
  if (isnan(v)) return v;
  return unpackHalf2x16(packHalf2x16(vec2(clamp(v, -PQG_HALF_MAX, PQG_HALF_MAX), 0.0))).x;
}

// DOMAIN: saturate((v − min) / (max − min)), honoured in the lookup.
vec3 pqg_domain_normalise(vec3 v) {
  vec3 lo = P.user_lut_domain_min.rgb;
  vec3 hi = P.user_lut_domain_max.rgb;
  vec3 t = (v - lo) / (hi - lo);
  return vec3(saturate_d3d(t.r), saturate_d3d(t.g), saturate_d3d(t.b));
}

// The strip N² × N (texel (r + N b, g)): two hardware bilinear taps in neighbouring slices,
// lerped by the fractional slice (UE's UnwrappedTexture3DSample scheme).
vec3 pqg_sample_strip(vec3 t) {
  float n = float(P.user_lut_size);
  vec3 uvw = t * ((n - 1.0) / n) + 0.5 / n;
  float w = uvw.b * n - 0.5;
  float int_w = floor(w);
  float frac_w = w - int_w;
  float u = (uvw.r + int_w) / n;
  vec3 s0 = textureLod(user_lut[0], vec2(u, uvw.g), 0.0).rgb;
  vec3 s1 = textureLod(user_lut[0], vec2(u + 1.0 / n, uvw.g), 0.0).rgb;
  return lerp_d3d(s0, s1, frac_w);
}

vec3 pqg_lookup(vec3 pq) {
  vec3 t = pqg_domain_normalise(pq);
  return pqg_sample_strip(t);
}

// HDR: UE's FilmToneMap on Rec.709 (AP1 in, max(0, ·) after FromAP1); SDR: Narkowicz's fit.
vec3 pqg_display_map(vec3 c) {
  if (P.pq_display == PQG_DISPLAY_HDR)
    return max_d3d(mul_rows(P.pq_ap1_to_rec709, film_tone_map(mul_rows(P.pq_rec709_to_ap1, c))),
                   0.0);
  if (P.pq_display == PQG_DISPLAY_SDR)
    return vec3(op_aces_narkowicz(c.r, 1.0), op_aces_narkowicz(c.g, 1.0),
                op_aces_narkowicz(c.b, 1.0));
  return vec3(hdrc_nan());
}

float pqg_srgb_encode(float v) {
  if (!(v > PQG_SRGB_BREAK)) return PQG_SRGB_LINEAR_SCALE * v;
  return PQG_SRGB_SCALE * pow_d3d(v, PQG_SRGB_EXPONENT) - PQG_SRGB_OFFSET;
}

float pqg_encode_output(float d) {
  switch (P.pq_back_buffer) {
    case PQG_BB_R10G10B10A2:
      return saturate_d3d(pq_from_nits(d * P.pq_white_nits));
    case PQG_BB_RGBA16F:
      return d * P.pq_white_nits / PQG_SCRGB_WHITE_NITS;
    case PQG_BB_SRGB8:
      return pqg_srgb_encode(saturate_d3d(d));
    case PQG_BB_RGB8:
      return pow_d3d(saturate_d3d(d), 1.0 / PQG_RGB8_GAMMA);
  }
  return hdrc_nan();
}

vec3 pq_grading_apply(vec3 scene) {
  vec3 stored =
      vec3(pqg_store_rgba16f(scene.r), pqg_store_rgba16f(scene.g), pqg_store_rgba16f(scene.b));
  vec3 e = stored * P.pq_exposure_fract;
  e = vec3(saturate_d3d(e.r), saturate_d3d(e.g), saturate_d3d(e.b));
  vec3 pq = vec3(pq_from_nits(e.r * PQ_PEAK_NITS), pq_from_nits(e.g * PQ_PEAK_NITS),
                 pq_from_nits(e.b * PQ_PEAK_NITS));
  vec3 graded_pq = pqg_lookup(pq);
  vec3 lin = vec3(nits_from_pq(graded_pq.r), nits_from_pq(graded_pq.g), nits_from_pq(graded_pq.b)) /
             PQ_PEAK_NITS;
  vec3 graded = lin / P.pq_exposure_fract * P.pq_amplify;
  vec3 d = pqg_display_map(graded);
  return vec3(pqg_encode_output(d.r), pqg_encode_output(d.g), pqg_encode_output(d.b));
}

#endif
