// Nuke-style colour correction of the CombineLUTs pass (docs/spec/ue55.md §4.6), in AP1:
// PostProcessCombineLUTs.usf: ColorCorrect, ColorCorrectAll. Parameters are
// FPostProcessSettings Color{Saturation,Contrast,Gamma,Gain,Offset}{,Shadows,Midtones,Highlights}
// and ColorCorrection{ShadowsMax,HighlightsMin,HighlightsMax} (P.cc_*). Reference:
// reference/ue/grading/color_correct.h. Needs the generated interface included first.
#ifndef HDRC_COLOR_CORRECT_GLSL
#define HDRC_COLOR_CORRECT_GLSL

#include "aces_common.glsl"  // AP1_RGB2Y
#include "d3d_math.glsl"

// ColorCorrect's contrast pivot: pow(C * (1 / 0.18), K) * 0.18, the reciprocal folded to a float
// constant (reference grading::color_correct writes 1.0 / 0.18).
const float CC_CONTRAST_PIVOT = 0.18;
const float CC_ONE_OVER_CONTRAST_PIVOT = 5.55555534;

// One zone's controls combined with the global ones as ColorCorrectAll passes them:
// component-wise product (.w included) for saturation/contrast/gamma/gain, sum for offset.
struct ColorCorrectZone {
  vec4 saturation, contrast, gamma, gain, offset;
};

ColorCorrectZone cc_with_global(vec4 saturation, vec4 contrast, vec4 gamma, vec4 gain,
                                vec4 offset) {
  return ColorCorrectZone(saturation * P.cc_saturation, contrast * P.cc_contrast,
                          gamma * P.cc_gamma, gain * P.cc_gain, offset + P.cc_offset);
}

// ColorCorrect, AP1 in and out:
//  1. C = max(0, lerp(luma, C, S.rgb·S.w))   (D3D maxNum: NaN → 0)
//  2. C = pow(C / 0.18, K.rgb·K.w) · 0.18     (pow_d3d: HLSL pow)
//  3. C = pow(C, 1 / (G.rgb·G.w))
//  4. C = C · (A.rgb·A.w) + (O.rgb + O.w)
vec3 color_correct(vec3 ap1, ColorCorrectZone z) {
  float luma = dot(ap1, AP1_RGB2Y);
  vec3 s = z.saturation.rgb * z.saturation.w;
  vec3 k = z.contrast.rgb * z.contrast.w;
  vec3 g = z.gamma.rgb * z.gamma.w;
  vec3 c;
  for (int i = 0; i < 3; ++i) {
    float v = max_d3d(lerp_d3d(luma, ap1[i], s[i]), 0.0);
    v = pow_d3d(v * CC_ONE_OVER_CONTRAST_PIVOT, k[i]) * CC_CONTRAST_PIVOT;
    c[i] = pow_d3d(v, 1.0 / g[i]);
  }
  return c * (z.gain.rgb * z.gain.w) + (z.offset.rgb + z.offset.w);
}

// ColorCorrectAll: the three zones blended by weights from the input's AP1 luma,
// shadows = 1 − smoothstep(0, ShadowsMax, luma), highlights = smoothstep(HighlightsMin,
// HighlightsMax, luma), midtones = 1 − shadows − highlights (smoothstep_d3d: a NaN luma gives
// shadows 1).
vec3 color_correct_all(vec3 ap1) {
  float luma = dot(ap1, AP1_RGB2Y);
  float w_shadows = 1.0 - smoothstep_d3d(0.0, P.cc_shadows_max, luma);
  float w_highlights = smoothstep_d3d(P.cc_highlights_min, P.cc_highlights_max, luma);
  float w_midtones = 1.0 - w_shadows - w_highlights;
  vec3 s = color_correct(ap1, cc_with_global(P.cc_saturation_shadows, P.cc_contrast_shadows,
                                             P.cc_gamma_shadows, P.cc_gain_shadows,
                                             P.cc_offset_shadows));
  vec3 h = color_correct(ap1, cc_with_global(P.cc_saturation_highlights, P.cc_contrast_highlights,
                                             P.cc_gamma_highlights, P.cc_gain_highlights,
                                             P.cc_offset_highlights));
  vec3 m = color_correct(ap1, cc_with_global(P.cc_saturation_midtones, P.cc_contrast_midtones,
                                             P.cc_gamma_midtones, P.cc_gain_midtones,
                                             P.cc_offset_midtones));
  return s * w_shadows + m * w_midtones + h * w_highlights;
}

#endif
