// The tail of CombineLUTs' grading (docs/spec/ue55.md §4.10, §4.11): the r.Color.Min/Mid/Max mapping
// polynomial (PostProcessCommon.ush: ColorCorrection), the camera fade (View.ColorScale /
// View.OverlayColor) and the film gamma (pow by InverseGamma.y), all in the linear working colour
// space. The host computes the polynomial and InverseGamma as UE's C++ does
// (reference/ue/grading/color_polynomial.h); needs the generated interface included first.
#ifndef HDRC_COLOR_POLYNOMIAL_GLSL
#define HDRC_COLOR_POLYNOMIAL_GLSL

#include "d3d_math.glsl"

// a·C² + b·C + c per channel, (a, b, c) = P.mapping_polynomial.xyz.
vec3 apply_mapping_polynomial(vec3 film_color) {
  vec4 m = P.mapping_polynomial;
  return m.x * (film_color * film_color) + m.y * film_color + m.z;
}

// lerp(C · ColorScale, OverlayColor.rgb, OverlayColor.a): FilmColorNoGamma and GradedColor.
vec3 apply_fade(vec3 color) {
  return lerp_d3d(color * P.color_scale.rgb, P.overlay_color.rgb, P.overlay_color.a);
}

// FilmColor = pow(max(0, FilmColorNoGamma), InverseGamma.y); max is maxNum (NaN → 0) and pow is
// HLSL's, exp2(y·log2 x), even at the default exponent 1.
vec3 apply_film_gamma(vec3 film_color_no_gamma) {
  return pow_d3d(max_d3d(film_color_no_gamma, 0.0), P.inverse_gamma.y);
}

#endif
