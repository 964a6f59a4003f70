// UE 5.8's HDR UI composite in float32 (pipeline ue58, stage ue58_ui_composite):
// CompositeUIPixelShader.usf (unicorn2022/UE5.8.0 @ 5d9a05c1): Main / CompositeUICS,
// ComputeHDRUIColor, LinearizeColor, ComposeUIAndScene; parameters as
// SlateRHIRenderer.cpp FSlateRHIRenderer::DrawWindowViewport_RenderThread sets them
// (docs/ue58-differences.md U1-U5, docs/ue58-decisions.md H). What 5.8 shares with 5.5 is 5.5's
// port (../../lib/ui_composite.glsl): the back-buffer decode, the Reinhard, the colour deficiency,
// the encode and r.HDR.UI.CompositeMode 0's blend. Twin of reference/ue/ue58/ue58_ui_composite.cpp.
// Needs the generated interface included first.
#ifndef HDRC_UE58_UI_COMPOSITE_GLSL
#define HDRC_UE58_UI_COMPOSITE_GLSL

#include "../../lib/d3d_math.glsl"
#include "../../lib/rec2020_srgb.glsl"
#include "../../lib/ui_composite.glsl"
#include "srgb_to_linear58.glsl"

const float UE58_PQ_WHITE_NITS = 10000.0;  // UE_PQ_WHITE_NITS (GammaCorrectionCommon.ush)

// LinearizeColor: UICompositeEOTF 0 pow(x, UICompositeEOTFGamma), else sRGBToLinear (5.8's).
vec3 ue58_ui_linearize(vec3 c) {
  if (P.ue58_ui_eotf == 0) return pow_d3d(c, P.ue58_ui_eotf_gamma);
  return vec3(ue58_srgb_to_linear(c.r), ue58_srgb_to_linear(c.g), ue58_srgb_to_linear(c.b));
}

// ComputeHDRUIColor: "Undo premultiplied alpha" (a > 0: rgb / a, else 0), LinearizeColor,
// sRGB_2_Rec2020 · UILuminance; alpha unchanged.
vec4 ue58_ui_hdr_ui_color(vec4 ui, UiCompositeParams p) {
  vec3 c = ui.a > 0.0 ? ui.rgb / ui.a : vec3(0.0);
  return vec4(srgb_to_rec2020(ue58_ui_linearize(c)) * p.ui_luminance, ui.a);
}

// ComposeUIAndScene: a > 0: UI · UILevel; a < 1: blended (UICompositeBlend != 0: Reinhard then
// lerp; 0: in the gamma space pow(saturate(x / 10000), InvGamma), saturate as clamp_d3d, NaN →
// 0); a >= 1: the UI; a <= 0 (and NaN): the scene.
vec3 ue58_ui_compose(vec3 scene, vec4 ui, float level) {
  if (!(ui.a > 0.0)) return scene;
  vec3 u = ui.rgb * level;
  if (!(ui.a < 1.0)) return u;
  if (P.ue58_ui_blend != 0) return lerp_d3d(ui_reinhard_under_ui(scene, ui.a, level), u, ui.a);
  vec3 gu = pow_d3d(clamp_d3d(u / UE58_PQ_WHITE_NITS, 0.0, 1.0), P.ue58_ui_blend_inv_gamma);
  vec3 gs = pow_d3d(clamp_d3d(scene / UE58_PQ_WHITE_NITS, 0.0, 1.0), P.ue58_ui_blend_inv_gamma);
  return pow_d3d(lerp_d3d(gs, gu, ui.a), P.ue58_ui_blend_gamma) * UE58_PQ_WHITE_NITS;
}

// One back-buffer pixel after the UI pass: mode != 0 the shader with "OutColor.w = UIColor.w",
// mode 0 Slate's fixed-function blend (5.5's, unchanged).
vec4 ue58_ui_composite_pixel(vec4 scene, vec4 ui) {
  UiCompositeParams p = ui_composite_params_from_block();
  bool scrgb = ui_uses_scrgb(p.output_device);
  if (p.composite_mode == 0) return ui_standard_blend(scene, ui, scrgb);
  vec4 ui_nits = ue58_ui_hdr_ui_color(ui, p);
  vec3 scene_nits = ui_hdr_scene_color(scene.rgb, scrgb);
  vec3 composed = ue58_ui_compose(scene_nits, ui_nits, p.ui_level);
  vec3 after_cvd = ui_apply_color_deficiency(composed, p);
  return vec4(ui_encode_output(after_cvd, scrgb), ui.a);
}

#endif
