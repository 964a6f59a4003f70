// Unity URP's grade in float32: LutBuilderHdr.shader ColorGrade (HDR grading; ACES spaces under
// _TONEMAP_ACES) and LutBuilderLdr.shader FragLutBuilderLdr (LDR grading), step by step, with the
// shader constants of the parameter block (P.urp_*, derived on the host as ColorGradingLutPass
// does) and the colour curves at their defaults (reference/unity_urp/unity_urp.h explains why).
// Needs the generated interface included first. Reference: reference/unity_urp/unity_urp.h
// (white_balance ... default_yrgb_curves, color_grade, ldr_bake, lut_texel).
#ifndef HDRC_UNITY_GRADE_GLSL
#define HDRC_UNITY_GRADE_GLSL

#include "../../lib/d3d_math.glsl"
#include "unity_color.glsl"
#include "unity_tonemap.glsl"

// The last texel of a 128-texel identity curve: the default YRGB curves are clamp(t, 0, 127/128).
const float URP_CURVE_CAP = 127.0 / 128.0;

// True when the HDR bake grades in ACES spaces (HDR grading, ACES tone mapping).
bool urp_grades_in_aces() { return P.urp_grading_mode == 1 && P.urp_tonemap_mode == URP_TONEMAP_ACES; }

// Common.hlsl: GetLuminance (AcesLuminance under _TONEMAP_ACES).
float urp_grade_luminance(vec3 c, bool aces) {
  return aces ? urp_luminance_ap1(c) : urp_luminance_rec709(c);
}

// Step 2: white balance in LMS.
vec3 urp_white_balance(vec3 c) {
  return ((c * URP_LINEAR_TO_LMS) * P.urp_color_balance.xyz) * URP_LMS_TO_LINEAR;
}

// Step 3: contrast about ACEScc_MIDGRAY in LogC, or in ACEScc of sRGB_2_AP0 · c (→ ACEScg).
vec3 urp_contrast(vec3 c, bool aces) {
  float k = P.urp_hue_sat_con.z;
  if (aces) {
    vec3 ap0 = c * URP_SRGB_TO_AP0;
    vec3 l = vec3(urp_acescc_from_linear(ap0.r), urp_acescc_from_linear(ap0.g),
                  urp_acescc_from_linear(ap0.b));
    l = (l - URP_ACESCC_MIDGRAY) * k + URP_ACESCC_MIDGRAY;
    return vec3(urp_linear_from_acescc(l.r), urp_linear_from_acescc(l.g),
                urp_linear_from_acescc(l.b)) * URP_AP0_TO_AP1;
  }
  vec3 l = (urp_logc_from_linear(c) - URP_ACESCC_MIDGRAY) * k + URP_ACESCC_MIDGRAY;
  return urp_linear_from_logc(l);
}

// Steps 4-5: colour filter, then max(0, c).
vec3 urp_color_filter(vec3 c) { return max_d3d(c * P.urp_color_filter.xyz, 0.0); }

// Step 6: split toning in gamma space (PositivePow = pow(|x|, p)).
vec3 urp_split_toning(vec3 c, bool aces) {
  float balance = P.urp_split_shadows.w;
  vec3 g = vec3(pow_d3d(abs(c.r), 1.0 / 2.2), pow_d3d(abs(c.g), 1.0 / 2.2),
                pow_d3d(abs(c.b), 1.0 / 2.2));
  float luma = saturate_d3d(urp_grade_luminance(clamp(g, 0.0, 1.0), aces) + balance);
  vec3 sh = lerp_d3d(vec3(0.5), P.urp_split_shadows.xyz, 1.0 - luma);
  vec3 hi = lerp_d3d(vec3(0.5), P.urp_split_highlights.xyz, luma);
  for (int i = 0; i < 3; ++i) g[i] = urp_soft_light(urp_soft_light(g[i], sh[i]), hi[i]);
  return vec3(pow_d3d(abs(g.r), 2.2), pow_d3d(abs(g.g), 2.2), pow_d3d(abs(g.b), 2.2));
}

// Step 7: channel mixer.
vec3 urp_channel_mixer(vec3 c) {
  return vec3(dot(c, P.urp_channel_mixer_red.xyz), dot(c, P.urp_channel_mixer_green.xyz),
              dot(c, P.urp_channel_mixer_blue.xyz));
}

// Step 8: shadows / midtones / highlights (HLSL smoothstep semantics for equal limits).
vec3 urp_shadows_midtones_highlights(vec3 c, bool aces) {
  float luma = urp_grade_luminance(c, aces);
  vec4 lim = P.urp_sha_hi_limits;
  float ws = 1.0 - smoothstep_d3d(lim.x, lim.y, luma);
  float wh = smoothstep_d3d(lim.z, lim.w, luma);
  float wm = 1.0 - ws - wh;
  return c * P.urp_shadows.xyz * ws + c * P.urp_midtones.xyz * wm + c * P.urp_highlights.xyz * wh;
}

// Step 9: c · gain + lift, then sign(c) · |c|^gamma (GLSL pow of 0 with a positive exponent is 0;
// the exponent is 1/max(·, 1e-3) > 0).
vec3 urp_lift_gamma_gain(vec3 c) {
  c = c * P.urp_gain.xyz + P.urp_lift.xyz;
  vec3 a = abs(c);
  return vec3(sign_d3d(c.r) * pow_d3d(a.r, P.urp_gamma.x), sign_d3d(c.g) * pow_d3d(a.g, P.urp_gamma.y),
              sign_d3d(c.b) * pow_d3d(a.b, P.urp_gamma.z));
}

// Step 10: hue shift through HSV (default curves: no hue-vs-hue offset), one RotateHue wrap.
vec3 urp_hue_shift(vec3 c) {
  vec3 hsv = urp_hsv_from_rgb(c);
  hsv.x = urp_rotate_hue(hsv.x + P.urp_hue_sat_con.x, 0.0, 1.0);
  return urp_rgb_from_hsv(hsv);
}

// Step 11: global saturation (satMult = 1 at the default curves).
vec3 urp_saturation(vec3 c, bool aces) {
  float luma = urp_grade_luminance(c, aces);
  return luma + P.urp_hue_sat_con.y * (c - luma);
}

// Step 12, default curves: HDR wraps clamp(t, 0, 127/128) in FastTonemap / FastTonemapInvert; LDR
// applies it to c directly.
vec3 urp_default_yrgb_curves(vec3 c, bool hdr) {
  if (!hdr) return clamp(c, 0.0, URP_CURVE_CAP);
  vec3 t = clamp(c * (1.0 / (max(max(c.r, c.g), c.b) + 1.0)), 0.0, URP_CURVE_CAP);
  return t * (1.0 / (1.0 - max(max(t.r, t.g), t.b)));
}

// LutBuilderHdr.shader: ColorGrade for a LogC lattice code.
vec3 urp_color_grade(vec3 code) {
  bool aces = urp_grades_in_aces();
  vec3 c = urp_linear_from_logc(code);
  c = urp_white_balance(c);
  c = urp_contrast(c, aces);
  c = urp_color_filter(c);
  c = urp_split_toning(c, aces);
  c = urp_channel_mixer(c);
  c = urp_shadows_midtones_highlights(c, aces);
  c = urp_lift_gamma_gain(c);
  c = urp_hue_shift(c);
  c = urp_saturation(c, aces);
  c = urp_default_yrgb_curves(c, true);
  return max_d3d(c, 0.0);
}

// LutBuilderLdr.shader: FragLutBuilderLdr for a linear lattice code, saturated.
vec3 urp_ldr_bake(vec3 code) {
  vec3 c = urp_white_balance(code);
  c = urp_contrast(c, false);
  c = urp_color_filter(c);
  c = urp_split_toning(c, false);
  c = urp_channel_mixer(c);
  c = urp_shadows_midtones_highlights(c, false);
  c = urp_lift_gamma_gain(c);
  c = urp_hue_shift(c);
  c = urp_saturation(c, false);
  c = urp_default_yrgb_curves(c, false);
  return clamp(c, 0.0, 1.0);
}

// The texel the bake writes for lattice code `code`, before storage rounding.
vec3 urp_lut_texel(vec3 code) {
  if (P.urp_grading_mode != 1) return urp_ldr_bake(code);
  return urp_hdr_bake_tonemap(urp_color_grade(code), P.urp_tonemap_mode);
}

#endif
