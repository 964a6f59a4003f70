// Unity URP tone mapping in float32: the fitted ACES (Color.hlsl AcesTonemap with
// TONEMAPPING_USE_FULL_ACES 0), Neutral (the shared operator of the `operators` pipeline,
// ../../operators/lib/operators.glsl: one definition), the HDR bake's Tonemap and the uber pass's
// ApplyTonemap. Reference: reference/unity_urp/unity_urp.h (aces_tonemap, neutral_tonemap,
// hdr_bake_tonemap, uber_tonemap), which cites each formula and constant.
#ifndef HDRC_UNITY_TONEMAP_GLSL
#define HDRC_UNITY_TONEMAP_GLSL

#include "../../lib/d3d_math.glsl"
#include "../../operators/lib/operators.glsl"
#include "unity_color.glsl"

const int URP_TONEMAP_NONE = 0;
const int URP_TONEMAP_NEUTRAL = 1;
const int URP_TONEMAP_ACES = 2;

// ACES.hlsl: the RRT / ODT constants AcesTonemap uses.
const float URP_RRT_GLOW_GAIN = 0.05;
const float URP_RRT_GLOW_MID = 0.08;
const float URP_RRT_RED_SCALE = 0.82;
const float URP_RRT_RED_PIVOT = 0.03;
const float URP_RRT_RED_HUE = 0.0;
const float URP_RRT_RED_WIDTH = 135.0;
const float URP_RRT_SAT_FACTOR = 0.96;
const float URP_ODT_SAT_FACTOR = 0.93;
const float URP_DIM_SURROUND_GAMMA = 0.9811;
// Color.hlsl AcesTonemap: the fitted RRT + ODT tone scale's coefficients.
const float URP_ACES_FIT_A = 0.0245786;
const float URP_ACES_FIT_B = 0.000090537;
const float URP_ACES_FIT_C = 0.983729;
const float URP_ACES_FIT_D = 0.4329510;
const float URP_ACES_FIT_E = 0.238081;
const float URP_PI = 3.14159265358979323846;

// ACES.hlsl: rgb_2_saturation.
float urp_rgb_2_saturation(vec3 rgb) {
  float mi = min(min(rgb.r, rgb.g), rgb.b);
  float ma = max(max(rgb.r, rgb.g), rgb.b);
  return (max(ma, 1e-4) - max(mi, 1e-4)) / max(ma, 1e-2);
}

// ACES.hlsl: rgb_2_yc (ycRadiusWeight 1.75).
float urp_rgb_2_yc(vec3 rgb) {
  float k = max(rgb.b * (rgb.b - rgb.g) + rgb.g * (rgb.g - rgb.r) + rgb.r * (rgb.r - rgb.b), 0.0);
  return (rgb.b + rgb.g + rgb.r + 1.75 * sqrt(k)) / 3.0;
}

// ACES.hlsl: rgb_2_hue, degrees in [0, 360), 0 for r = g = b. GLSL atan(y, x) is HLSL atan2(y, x)
// (undefined only at x = y = 0, which needs r = g = b, answered first).
float urp_rgb_2_hue(vec3 rgb) {
  float hue = 0.0;
  if (!(rgb.r == rgb.g && rgb.g == rgb.b))
    hue = (180.0 / URP_PI) * atan(sqrt(3.0) * (rgb.g - rgb.b), 2.0 * rgb.r - rgb.g - rgb.b);
  if (hue < 0.0) hue += 360.0;
  return hue;
}

// ACES.hlsl: center_hue.
float urp_center_hue(float hue, float center) {
  float h = hue - center;
  if (h < -180.0)
    h += 360.0;
  else if (h > 180.0)
    h -= 360.0;
  return h;
}

// ACES.hlsl: sigmoid_shaper with Common.hlsl FastSign (+1 at ±0).
float urp_sigmoid_shaper(float x) {
  float t = max(1.0 - abs(x / 2.0), 0.0);
  float y = 1.0 + (x >= 0.0 ? 1.0 : -1.0) * (1.0 - t * t);
  return y / 2.0;
}

// ACES.hlsl: glow_fwd.
float urp_glow_fwd(float yc, float gain, float mid) {
  if (yc <= 2.0 / 3.0 * mid) return gain;
  if (yc >= 2.0 * mid) return 0.0;
  return gain * (mid / yc - 1.0 / 2.0);
}

// ACES.hlsl: darkSurround_to_dimSurround (XYZ_2_xyY, xyY_2_XYZ with their 1e-4 guards).
vec3 urp_dark_to_dim_surround(vec3 linear_cv) {
  vec3 xyz = linear_cv * URP_AP1_TO_XYZ;
  float divisor = max(xyz.x + xyz.y + xyz.z, 1e-4);
  float x = xyz.x / divisor;
  float y = xyz.y / divisor;
  float big_y = pow_d3d(clamp(xyz.y, 0.0, URP_HALF_MAX), URP_DIM_SURROUND_GAMMA);
  float m = big_y / max(y, 1e-4);
  return vec3(x * m, big_y, (1.0 - x - y) * m) * URP_XYZ_TO_AP1;
}

vec3 urp_desaturate_ap1(vec3 c, float factor) {
  return lerp_d3d(vec3(urp_luminance_ap1(c)), c, factor);
}

// Color.hlsl: AcesTonemap (fitted): ACES2065-1 in, linear Rec.709 out, not clamped.
vec3 urp_aces_tonemap(vec3 aces) {
  // Glow module.
  float saturation = urp_rgb_2_saturation(aces);
  float yc_in = urp_rgb_2_yc(aces);
  float s = urp_sigmoid_shaper((saturation - 0.4) / 0.2);
  float added_glow = 1.0 + urp_glow_fwd(yc_in, URP_RRT_GLOW_GAIN * s, URP_RRT_GLOW_MID);
  aces *= added_glow;
  // Red modifier.
  float centered_hue = urp_center_hue(urp_rgb_2_hue(aces), URP_RRT_RED_HUE);
  float hue_weight = smoothstep_d3d(0.0, 1.0, 1.0 - abs(2.0 * centered_hue / URP_RRT_RED_WIDTH));
  hue_weight *= hue_weight;
  aces.r += hue_weight * saturation * (URP_RRT_RED_PIVOT - aces.r) * (1.0 - URP_RRT_RED_SCALE);
  // ACES to ACEScg, clamp, global desaturation.
  vec3 acescg = max_d3d(aces * URP_AP0_TO_AP1, 0.0);
  acescg = urp_desaturate_ap1(acescg, URP_RRT_SAT_FACTOR);
  // The fitted tone scale.
  vec3 rgb_post = (acescg * (acescg + URP_ACES_FIT_A) - URP_ACES_FIT_B) /
                  (acescg * (URP_ACES_FIT_C * acescg + URP_ACES_FIT_D) + URP_ACES_FIT_E);
  vec3 linear_cv = urp_dark_to_dim_surround(rgb_post);
  linear_cv = urp_desaturate_ap1(linear_cv, URP_ODT_SAT_FACTOR);
  return ((linear_cv * URP_AP1_TO_XYZ) * URP_D60_TO_D65_CAT) * URP_XYZ_TO_REC709;
}

// Color.hlsl: NeutralTonemap, per channel (the operators pipeline's definition, scale 1).
vec3 urp_neutral_tonemap(vec3 x) {
  return vec3(op_unity_neutral(x.r, 1.0), op_unity_neutral(x.g, 1.0), op_unity_neutral(x.b, 1.0));
}

// LutBuilderHdr.shader: Tonemap (ACES from ACEScg via AP1_2_AP0_MAT). Not clamped.
vec3 urp_hdr_bake_tonemap(vec3 graded, int mode) {
  if (mode == URP_TONEMAP_NEUTRAL) return urp_neutral_tonemap(graded);
  if (mode == URP_TONEMAP_ACES) return urp_aces_tonemap(graded * URP_AP1_TO_AP0);
  return graded;
}

// Common.hlsl: ApplyTonemap (LDR grading, uber pass): ACES on sRGB_2_AP0 · x, or Neutral, then
// saturate (NaN → 0).
vec3 urp_uber_tonemap(vec3 x, int mode) {
  if (mode == URP_TONEMAP_ACES) x = urp_aces_tonemap(x * URP_SRGB_TO_AP0);
  if (mode == URP_TONEMAP_NEUTRAL) x = urp_neutral_tonemap(x);
  return vec3(saturate_d3d(x.r), saturate_d3d(x.g), saturate_d3d(x.b));
}

#endif
