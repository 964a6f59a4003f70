// sRGBToLinear as UE 5.8 has it (GammaCorrectionCommon.ush, unicorn2022/UE5.8.0 @ 5d9a05c1): no
// min-normal clamp (docs/ue58-differences.md L16). Shared by CombineLUTs' inner-LUT decode
// (combine_luts58.glsl) and the UI composite's sRGB EOTF (ui_composite58.glsl). Reference:
// color/gamma_correction.h srgb_to_linear with MinNormalClamp::kOff.
#ifndef HDRC_UE58_SRGB_TO_LINEAR_GLSL
#define HDRC_UE58_SRGB_TO_LINEAR_GLSL

#include "../../lib/d3d_math.glsl"

// UE's literals, named so that a port's rounding of each can be planted (bench/constant_sweep.py).
const float UE58_SRGB_THRESHOLD = 0.04045;
const float UE58_SRGB_SCALE = 1.0 / 1.055;
const float UE58_SRGB_OFFSET = 0.0521327;
const float UE58_SRGB_GAMMA = 2.4;
const float UE58_SRGB_LINEAR_SCALE = 1.0 / 12.92;

float ue58_srgb_to_linear(float c) {
  return c > UE58_SRGB_THRESHOLD ? pow_d3d(c * UE58_SRGB_SCALE + UE58_SRGB_OFFSET, UE58_SRGB_GAMMA)
                                 : c * UE58_SRGB_LINEAR_SCALE;
}

#endif
