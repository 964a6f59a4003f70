// "Fake wide gamut" (ExpandGamut) of the CombineLUTs pass (docs/spec/ue55.md §4.5): bright saturated AP1
// colours are pushed towards a gamut between P3 and AP1. PostProcessCombineLUTs.usf:
// CombineLUTsCommon (docs/ue55-decisions.md D1). Reference: reference/ue/grading/expand_gamut.h.
#ifndef HDRC_EXPAND_GAMUT_GLSL
#define HDRC_EXPAND_GAMUT_GLSL

#include "aces_common.glsl"  // AP1_RGB2Y
#include "d3d_math.glsl"

// ExpandMat = (XYZ_2_AP1_MAT · Wide_2_XYZ_MAT) · (XYZ_2_sRGB_MAT · D60_2_D65_CAT · AP1_2_XYZ_MAT),
// AP1 → AP1, the product of UE's shader literals evaluated in double and rounded to float
// (reference grading::expand_gamut_matrix()). Rows.
// EXPAND_GAMUT_MAT: generated into hdrc/interface.glsl
// from the reference (gpu/shader_constants.cpp: shared_matrices).

vec3 mul_expand_gamut(vec3 v) {
  return vec3(dot(EXPAND_GAMUT_MAT[0], v), dot(EXPAND_GAMUT_MAT[1], v), dot(EXPAND_GAMUT_MAT[2], v));
}

// ExpandAmount = (1 − 2^(−4·|Chroma − 1|²)) · (1 − 2^(−4·ExpandGamut·LumaAP1²)),
// Chroma = ColorAP1 / LumaAP1.
//
// LumaAP1 == 0 (the black lattice point): UE divides without a guard and gets NaN, which D3D's
// max(0, ·) and saturate(NaN) = 0 in ColorCorrectAll turn back into the black result
// (docs/ue55-decisions.md D-NaN). GLSL leaves those NaN rules undefined, so the port takes the
// decision's guard: ExpandAmount = 0 there, as the reference does.
float expand_gamut_amount(vec3 color_ap1, float expand_gamut) {
  float luma = dot(color_ap1, AP1_RGB2Y);
  if (luma == 0.0) return 0.0;
  vec3 d = color_ap1 / luma - 1.0;
  float dist_sqr = dot(d, d);
  return (1.0 - exp2(-4.0 * dist_sqr)) * (1.0 - exp2(-4.0 * expand_gamut * luma * luma));
}

// ColorAP1 = lerp(ColorAP1, ExpandMat · ColorAP1, ExpandAmount). AP1 in, AP1 out.
vec3 expand_gamut(vec3 color_ap1, float expand_gamut) {
  return lerp_d3d(color_ap1, mul_expand_gamut(color_ap1), expand_gamut_amount(color_ap1, expand_gamut));
}

#endif
