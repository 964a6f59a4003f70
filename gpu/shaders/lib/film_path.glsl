// The SDR film path of CombineLUTs (docs/spec/ue55.md §4.8): blue correction, FilmToneMap, un-blue-correction,
// all in AP1, then FromAP1 and max(0, ·). PostProcessCombineLUTs.usf: CombineLUTsCommon and its
// BlueCorrect / BlueCorrectInv literals (Toon_Engine, commit 2dc09e82;
// docs/ue55-decisions.md D1). Reference: reference/ue/grading/film_tonemap.h (film_path_ap1,
// film_color). Needs the generated interface included first.
#ifndef HDRC_FILM_PATH_GLSL
#define HDRC_FILM_PATH_GLSL

#include "d3d_math.glsl"
#include "film_tonemap.glsl"
#include "matrix.glsl"

// BlueCorrectAP1 = (XYZ_2_AP1 · AP0_2_XYZ) · BlueCorrect · (XYZ_2_AP0 · AP1_2_XYZ) and the same
// with BlueCorrectInv, as the shader builds them from the literals: evaluated in double, rounded
// to float (reference grading::blue_correct_ap1(), blue_correct_inv_ap1()). Rows.
// BLUE_CORRECT_AP1, BLUE_CORRECT_INV_AP1: generated into hdrc/interface.glsl
// from the reference (gpu/shader_constants.cpp: shared_matrices).

vec3 mul_blue_correct(vec3 v) {
  return vec3(dot(BLUE_CORRECT_AP1[0], v), dot(BLUE_CORRECT_AP1[1], v), dot(BLUE_CORRECT_AP1[2], v));
}
vec3 mul_blue_correct_inv(vec3 v) {
  return vec3(dot(BLUE_CORRECT_INV_AP1[0], v), dot(BLUE_CORRECT_INV_AP1[1], v),
              dot(BLUE_CORRECT_INV_AP1[2], v));
}

// AP1 → AP1:
//  C = lerp(C, BlueCorrectAP1·C, BlueCorrection); C = lerp(C, FilmToneMap(C), ToneCurveAmount);
//  C = lerp(C, BlueCorrectInvAP1·C, BlueCorrection).
vec3 film_path_ap1(vec3 color_ap1) {
  vec3 c = lerp_d3d(color_ap1, mul_blue_correct(color_ap1), P.blue_correction);
  c = lerp_d3d(c, film_tone_map(c), P.tone_curve_amount);
  return lerp_d3d(c, mul_blue_correct_inv(c), P.blue_correction);
}

// FilmColor = max(0, WorkingColorSpace.FromAP1 · film_path_ap1(C)): linear working colour space.
vec3 film_color(vec3 color_ap1) {
  return max_d3d(mul_rows(P.wcs_from_ap1, film_path_ap1(color_ap1)), 0.0);
}

#endif
