// UE's display encodes of the SDR output devices, GammaCorrectionCommon.ush (chenyong2github/
// UnrealEngine 5.0-era copy, commit 109c6a2d; docs/spec/ue55.md §3.3): LinearToSrgbBranchingChannel (device 0,
// the desktop LinearToSrgb) and LinearTo709Branchless (device 1). Reference:
// color/gamma_correction.h. Device 2's explicit gamma is pow_d3d by InverseGamma.z.
#ifndef HDRC_GAMMA_CORRECTION_GLSL
#define HDRC_GAMMA_CORRECTION_GLSL

#include "d3d_math.glsl"

// LinearToSrgbBranchingChannel: x < 0.00313067 ? 12.92·x : 1.055·x^(1/2.4) − 0.055. UE's
// threshold (IEC 61966-2-1 has 0.0031308); never clamped; NaN fails the test and reaches pow (NaN).
const float SRGB_ENCODE_THRESHOLD = 0.00313067;
const float SRGB_ENCODE_LINEAR_SCALE = 12.92;
const float SRGB_ENCODE_EXPONENT = 1.0 / 2.4;
const float SRGB_ENCODE_SCALE = 1.055;
const float SRGB_ENCODE_OFFSET = 0.055;

float linear_to_srgb(float x) {
  if (x < SRGB_ENCODE_THRESHOLD) return x * SRGB_ENCODE_LINEAR_SCALE;
  return pow_d3d(x, SRGB_ENCODE_EXPONENT) * SRGB_ENCODE_SCALE - SRGB_ENCODE_OFFSET;
}
vec3 linear_to_srgb(vec3 x) {
  return vec3(linear_to_srgb(x.r), linear_to_srgb(x.g), linear_to_srgb(x.b));
}

// LinearTo709Branchless: min(4.5·x, 1.099·max(x, 0.018)^0.45 − 0.099), after UE's
// max(6.10352e-5, x) "minimum positive non-denormal" clamp (kept ON as the reference decides,
// docs/ue55-decisions.md D3). max/min are HLSL's (maxNum/minNum).
const float REC709_MIN_NORMAL_CLAMP = 6.10352e-5;
const float REC709_LINEAR_SCALE = 4.5;
const float REC709_THRESHOLD = 0.018;
const float REC709_EXPONENT = 0.45;
const float REC709_SCALE = 1.099;
const float REC709_OFFSET = 0.099;

float linear_to_rec709_branchless(float x) {
  x = max_d3d(REC709_MIN_NORMAL_CLAMP, x);
  return min_d3d(x * REC709_LINEAR_SCALE,
                 pow_d3d(max_d3d(x, REC709_THRESHOLD), REC709_EXPONENT) * REC709_SCALE -
                     REC709_OFFSET);
}
vec3 linear_to_rec709_branchless(vec3 x) {
  return vec3(linear_to_rec709_branchless(x.r), linear_to_rec709_branchless(x.g),
              linear_to_rec709_branchless(x.b));
}

#endif
