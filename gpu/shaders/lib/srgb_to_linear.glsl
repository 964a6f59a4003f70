// UE's sRGB decode, GammaCorrectionCommon.ush: sRGBToLinear (chenyong2github/UnrealEngine 5.0-era
// copy, commit 109c6a2d; docs/spec/ue55.md §3.3). Reference: color/gamma_correction.h srgb_to_linear.
#ifndef HDRC_SRGB_TO_LINEAR_GLSL
#define HDRC_SRGB_TO_LINEAR_GLSL

#include "d3d_math.glsl"

// max(6.10352e-5, x) "minimum positive non-denormal": present in UE 4.x/5.0, absent in 5.8; the
// reference keeps it ON by default (docs/ue55-decisions.md D3) and so does this port.
const float SRGB_MIN_NORMAL_CLAMP = 6.10352e-5;
const float SRGB_DECODE_THRESHOLD = 0.04045;
const float SRGB_DECODE_SCALE = 1.0 / 1.055;  // UE writes Color * (1.0 / 1.055)
const float SRGB_DECODE_OFFSET = 0.0521327;   // UE's truncation of 0.055 / 1.055
const float SRGB_DECODE_GAMMA = 2.4;
const float SRGB_LINEAR_SCALE = 1.0 / 12.92;  // UE writes Color * (1.0 / 12.92)

// sRGBToLinear(c) = c > 0.04045 ? (c / 1.055 + 0.0521327)^2.4 : c / 12.92 after the clamp. The
// clamp is HLSL max (maxNum), so NaN decodes as 6.10352e-5 / 12.92.
float srgb_to_linear(float c) {
  c = max_d3d(SRGB_MIN_NORMAL_CLAMP, c);
  return c > SRGB_DECODE_THRESHOLD
             ? pow_d3d(c * SRGB_DECODE_SCALE + SRGB_DECODE_OFFSET, SRGB_DECODE_GAMMA)
             : c * SRGB_LINEAR_SCALE;
}

vec3 srgb_to_linear(vec3 c) {
  return vec3(srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b));
}

#endif
