// White balance of the CombineLUTs pass (docs/spec/ue55.md §4.4): TonemapCommon.ush: WhiteBalance, applied in
// PostProcessCombineLUTs.usf: CombineLUTsCommon unless the SKIP_TEMPERATURE permutation is chosen
// (PostProcessCombineLUTs.cpp: 6500 K and tint 0). The host builds the whole matrix, FromXYZ · CA ·
// ToXYZ, as UE's C++ and shader do it (reference/ue/grading/white_balance.h); the shader only applies
// it. Needs the generated interface ("hdrc/interface.glsl") included first.
#ifndef HDRC_WHITE_BALANCE_GLSL
#define HDRC_WHITE_BALANCE_GLSL

#include "matrix.glsl"

// Linear working colour space in and out.
vec3 white_balance(vec3 linear_wcs) {
  if (P.white_balance_enabled == 0) return linear_wcs;
  return mul_rows(P.white_balance, linear_wcs);
}

#endif
