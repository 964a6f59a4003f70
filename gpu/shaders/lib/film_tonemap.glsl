// UE's SDR filmic curve, TonemapCommon.ush: FilmToneMap (izzy2lost/UnrealEngineUWP 5.5, commit
// aff11acf0c218535669021f6e646b3bcf6ad94a5; docs/spec/ue55.md §4.8), AP1 in, AP1 out (>= 0). The ACES RRT
// helpers and constants it borrows from ACES.ush (rgb_2_saturation, rgb_2_yc, sigmoid_shaper,
// glow_fwd, rgb_2_hue, center_hue, RRT_*, AP0_2_AP1_MAT, AP1_RGB2Y) come from aces_common.glsl.
// Reference: reference/ue/grading/film_tonemap.h. Needs the generated interface included first
// (P.film_*).
#ifndef HDRC_FILM_TONEMAP_GLSL
#define HDRC_FILM_TONEMAP_GLSL

#include "aces_common.glsl"
#include "d3d_math.glsl"

// FilmToneMap's own constants (reference film_tonemap.cpp kPreDesaturate, kPostDesaturate,
// kMatch): desaturation before and after the curve, and InMatch = OutMatch.
const float FILM_PRE_DESATURATE = 0.96;
const float FILM_POST_DESATURATE = 0.93;
const float FILM_MATCH = 0.18;

// FilmToneMap's local AP1_2_AP0 = mul(XYZ_2_AP0_MAT, AP1_2_XYZ_MAT): the product of the ACES.ush
// literals evaluated in double and rounded to float (reference: film_tone_map's
// kAp1ToAp0Product), not the AP1_2_AP0_MAT literal. Rows: out = M · v.
// FILM_AP1_TO_AP0: generated into hdrc/interface.glsl
// from the reference (gpu/shader_constants.cpp: shared_matrices).

vec3 mul_film_ap1_to_ap0(vec3 v) {
  return vec3(dot(FILM_AP1_TO_AP0[0], v), dot(FILM_AP1_TO_AP0[1], v), dot(FILM_AP1_TO_AP0[2], v));
}

// FilmToneMap's red-modifier hue weight: smoothstep(0, 1, 1 − |2·centered_hue / RED_WIDTH|)²
// (UE's approximation of the RRT's cubic_basis_shaper).
float film_red_modifier_hue_weight(float hue_deg) {
  float centered = center_hue(hue_deg, RRT_RED_HUE);
  float s = smoothstep_d3d(0.0, 1.0, 1.0 - abs(2.0 * centered / RRT_RED_WIDTH));
  return s * s;
}

// The curve's match points from P.film_* (FilmToneMap computes them per pixel, in float):
//  ToeMatch: Toe > 0.8 ? (1 − Toe − 0.18)/Slope + log10(0.18)
//            : log10(0.18) − ½·ln((1 + bt)/(1 − bt))·ToeScale/Slope, bt = (0.18 + B)/ToeScale − 1
//  StraightMatch = (1 − Toe)/Slope − ToeMatch;  ShoulderMatch = Shoulder/Slope − StraightMatch.
struct FilmCurve {
  float slope, black_clip, white_clip;
  float toe_scale, shoulder_scale;
  float toe_match, straight_match, shoulder_match;
};

FilmCurve film_curve_params() {
  FilmCurve m;
  m.slope = P.film_slope;
  m.black_clip = P.film_black_clip;
  m.white_clip = P.film_white_clip;
  m.toe_scale = 1.0 + P.film_black_clip - P.film_toe;
  m.shoulder_scale = 1.0 + P.film_white_clip - P.film_shoulder;
  float log_match = log10_d3d(FILM_MATCH);
  if (P.film_toe > 0.8) {
    // "0.18 will be on straight segment"
    m.toe_match = (1.0 - P.film_toe - FILM_MATCH) / P.film_slope + log_match;
  } else {
    // "0.18 will be on toe segment"
    float bt = (FILM_MATCH + P.film_black_clip) / m.toe_scale - 1.0;
    m.toe_match = log_match - 0.5 * log_d3d((1.0 + bt) / (1.0 - bt)) * (m.toe_scale / P.film_slope);
  }
  m.straight_match = (1.0 - P.film_toe) / P.film_slope - m.toe_match;
  m.shoulder_match = P.film_shoulder / P.film_slope - m.straight_match;
  return m;
}

// One channel of the curve: toe / straight / shoulder segments in log10, blended by a smoothstep
// between ToeMatch and ShoulderMatch (backwards when ShoulderMatch < ToeMatch, as the defaults
// are). For w = 0 UE evaluates log10(0) = −∞ and lerp(toe, −∞, 0) = 0·∞ = NaN (for any finite
// parameters); GLSL's log2(0) is undefined, so that NaN is returned explicitly, as for negative
// and NaN w (log of those is NaN on D3D). FilmToneMap's final max(0, ·) cleans it.
float film_curve(float w, FilmCurve m) {
  if (!(w > 0.0)) return hdrc_nan();
  float log_color = log10_d3d(w);
  float straight = m.slope * (log_color + m.straight_match);
  float toe = -m.black_clip + (2.0 * m.toe_scale) /
                                  (1.0 + exp_d3d((-2.0 * m.slope / m.toe_scale) *
                                                 (log_color - m.toe_match)));
  float shoulder = (1.0 + m.white_clip) -
                   (2.0 * m.shoulder_scale) /
                       (1.0 + exp_d3d((2.0 * m.slope / m.shoulder_scale) *
                                      (log_color - m.shoulder_match)));
  float toe_color = log_color < m.toe_match ? toe : straight;
  float shoulder_color = log_color > m.shoulder_match ? shoulder : straight;
  float t = saturate_d3d((log_color - m.toe_match) / (m.shoulder_match - m.toe_match));
  if (m.shoulder_match < m.toe_match) t = 1.0 - t;
  t = (3.0 - 2.0 * t) * t * t;
  return lerp_d3d(toe_color, shoulder_color, t);
}

// lerp(dot(C, AP1_RGB2Y), C, amount).
vec3 film_desaturate(vec3 c, float amount) { return lerp_d3d(vec3(dot(c, AP1_RGB2Y)), c, amount); }

// FilmToneMap, AP1 in, AP1 out:
//  1. AP0 = FILM_AP1_TO_AP0 · C
//  2. glow: AP0 ·= 1 + glow_fwd(rgb_2_yc(AP0), 0.05·sigmoid_shaper((sat − 0.4)/0.2), 0.08)
//  3. red modifier: AP0.r += w(hue)·sat·(0.03 − AP0.r)·(1 − 0.82), sat from before the glow
//  4. W = max(0, AP0_2_AP1_MAT · AP0); W = lerp(dot(W, AP1_RGB2Y), W, 0.96)
//  5. per channel film_curve
//  6. max(0, lerp(dot(T, AP1_RGB2Y), T, 0.93))   (maxNum: a NaN channel makes all three 0)
vec3 film_tone_map(vec3 ap1) {
  vec3 ap0 = mul_film_ap1_to_ap0(ap1);
  float saturation = rgb_2_saturation(ap0);
  float yc_in = rgb_2_yc(ap0);
  float s = sigmoid_shaper((saturation - 0.4) / 0.2);
  float added_glow = 1.0 + glow_fwd(yc_in, RRT_GLOW_GAIN * s, RRT_GLOW_MID);
  ap0 *= added_glow;

  float hue_weight = film_red_modifier_hue_weight(rgb_2_hue(ap0));
  ap0.r += hue_weight * saturation * (RRT_RED_PIVOT - ap0.r) * (1.0 - RRT_RED_SCALE);

  vec3 working = max_d3d(aces_mul(AP0_2_AP1_MAT, ap0), 0.0);
  working = film_desaturate(working, FILM_PRE_DESATURATE);

  FilmCurve m = film_curve_params();
  vec3 tone = vec3(film_curve(working.r, m), film_curve(working.g, m), film_curve(working.b, m));
  return max_d3d(film_desaturate(tone, FILM_POST_DESATURATE), 0.0);
}

#endif
