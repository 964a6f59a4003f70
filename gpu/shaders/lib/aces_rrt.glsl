// ACES RRT sweeteners (glow module, red modifier, clamps, AP0 -> AP1 and the global
// desaturation), float32. Source: ACES.ush (5.0-era copy, chenyong2github/UnrealEngine, commit
// 09c29cbee980f5c5fbff6c93cf6132e5f4bcf97a): rrt_sweeteners. Reference:
// reference/ue/aces/aces_output.cpp (rrt_sweeteners). Spec §5.1 step 1.
#ifndef HDRC_ACES_RRT_GLSL
#define HDRC_ACES_RRT_GLSL

#include "aces_common.glsl"

// ACES2065-1 (AP0) in, AP1 out. Finite and >= 0 for every input: a NaN anywhere makes the glow
// gain NaN, which the HLSL clamp(aces, 0, HALF_POS_INF) turns into 0 (clamp_d3d).
vec3 rrt_sweeteners(vec3 in_value) {
  vec3 aces = in_value;

  // Glow module.
  float saturation = rgb_2_saturation(aces);
  float yc_in = rgb_2_yc(aces);
  float s = sigmoid_shaper((saturation - 0.4) / 0.2);
  float added_glow = 1.0 + glow_fwd(yc_in, RRT_GLOW_GAIN * s, RRT_GLOW_MID);
  aces *= added_glow;

  // Red modifier: the hue after the glow, the saturation from before it (as ACES.ush).
  float hue = rgb_2_hue(aces);
  float centered_hue = center_hue(hue, RRT_RED_HUE);
  float hue_weight = cubic_basis_shaper(centered_hue, RRT_RED_WIDTH);
  aces.r += hue_weight * saturation * (RRT_RED_PIVOT - aces.r) * (1.0 - RRT_RED_SCALE);

  // ACES to the AP1 rendering space.
  aces = clamp_d3d(aces, 0.0, HALF_POS_INF);
  vec3 rgb_pre = aces_mul(AP0_2_AP1_MAT, aces);
  rgb_pre = clamp_d3d(rgb_pre, 0.0, HALF_MAX);

  // Global desaturation: lerp(dot(rgbPre, AP1_RGB2Y).xxx, rgbPre, RRT_SAT_FACTOR).
  return lerp_d3d(vec3(dot(rgb_pre, AP1_RGB2Y)), rgb_pre, RRT_SAT_FACTOR);
}

#endif
