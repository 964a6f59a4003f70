// sRGBToLinear as UE 5.8 has it (GammaCorrectionCommon.ush, unicorn2022/UE5.8.0 @ 5d9a05c1): no
// min-normal clamp (docs/ue58-differences.md L16). Shared by CombineLUTs' inner-LUT decode
// (combine_luts58.glsl) and the UI composite's sRGB EOTF (ui_composite58.glsl). Reference:
// color/gamma_correction.h srgb_to_linear with MinNormalClamp::kOff.
#ifndef HDRC_UE58_SRGB_TO_LINEAR_GLSL
#define HDRC_UE58_SRGB_TO_LINEAR_GLSL

#include "../../lib/d3d_math.glsl"

float ue58_srgb_to_linear(float c) {
  return c > 0.04045 ? pow_d3d(c * (1.0 / 1.055) + 0.0521327, 2.4) : c * (1.0 / 12.92);
}

#endif
