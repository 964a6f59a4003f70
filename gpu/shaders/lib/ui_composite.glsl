// The HDR UI composite: CompositeUIPixelShader.usf (izzy2lost/UnrealEngineUWP 5.5, commit
// 0ac46dcf): Main / CompositeUICS, ComputeHDRUIColor, ComputeHDRSceneColor, ComposeUIAndScene,
// ApplyColorDeficiency, LinearizeColor with USE_LUT_FOR_UI = 0 and USE_709 undefined (docs/spec/ue55.md §8,
// docs/ue55-decisions.md D3, D8, D8a). Reference: reference/ue/ui/composite.cpp, whose header
// documents r.HDR.UI.CompositeMode 0 (Slate's fixed-function blend, no composite shader).
#ifndef HDRC_UI_COMPOSITE_GLSL
#define HDRC_UI_COMPOSITE_GLSL

#include "color_deficiency.glsl"
#include "d3d_math.glsl"
#include "rec2020_srgb.glsl"
#include "srgb_to_linear.glsl"
#include "st2084.glsl"

// ScRGBScaleFactor: nits at scRGB 1.0.
const float UI_SCRGB_SCALE_FACTOR = 80.0;
// ComposeUIAndScene's Rec.2020 luma weights KR, KG, KB, as UE writes them.
const vec3 UI_REC2020_LUMA_WEIGHTS = vec3(0.2627, 0.678, 0.0593);

struct UiCompositeParams {
  int composite_mode;   // r.HDR.UI.CompositeMode: 0 Slate's standard blend, else the shader
  int output_device;    // the viewport's EDisplayOutputFormat: 5/6 scRGB, others PQ (D8a)
  float ui_level;       // r.HDR.UI.Level (UILevel)
  float ui_luminance;   // r.HDR.UI.Luminance (UILuminance), nits of UI white
  int cvd_type;         // ColorVisionDeficiencyType
  int cvd_severity;     // ColorVisionDeficiencySeverity, 0..10
  bool cvd_correct;     // bCorrectDeficiency
  bool cvd_show_correction;  // bSimulateCorrectionWithDeficiency
};

// The composite's parameters from the parameter block (the interface must be included first).
UiCompositeParams ui_composite_params_from_block() {
  UiCompositeParams p;
  p.composite_mode = P.ui_composite_mode;
  p.output_device = P.output_device;
  p.ui_level = P.ui_level;
  p.ui_luminance = P.ui_luminance;
  p.cvd_type = P.cvd_type;
  p.cvd_severity = P.cvd_severity;
  p.cvd_correct = P.cvd_correct != 0;
  p.cvd_show_correction = P.cvd_show_correction != 0;
  return p;
}

// SCRGB_ENCODING permutation (SlateRHIRenderer.cpp: DrawWindow_RenderThread, bUseScRGB).
bool ui_uses_scrgb(int output_device) { return output_device == 5 || output_device == 6; }

// APPLY_COLOR_DEFICIENCY permutation: type != NormalVision && severity > 0.
bool ui_color_deficiency_active(UiCompositeParams p) {
  return p.cvd_type != CVD_NORMAL_VISION && p.cvd_severity > 0;
}

// ComputeHDRUIColor: premultiplied sRGB-encoded UI → nits in Rec.2020 (alpha unchanged).
vec4 ui_hdr_ui_color(vec4 ui, UiCompositeParams p) {
  return vec4(srgb_to_rec2020(srgb_to_linear(ui.rgb)) * p.ui_luminance, ui.a);
}

// ComputeHDRSceneColor: back-buffer code → nits in Rec.2020 (PQ: the back buffer's own gamut).
vec3 ui_hdr_scene_color(vec3 scene, bool scrgb) {
  if (!scrgb) return vec3(nits_from_pq(scene.r), nits_from_pq(scene.g), nits_from_pq(scene.b));
  return srgb_to_rec2020(scene) * UI_SCRGB_SCALE_FACTOR;
}

// ComposeUIAndScene's Reinhard under translucent UI (shared with UE 5.8's linear blend,
// ../ue58/lib/ui_composite58.glsl): the scene is clamped with HLSL max (maxNum: NaN → 0) and
// Reinhard-compressed towards UILevel, faded in by the UI's alpha: scene *= lerp(1, level / (L +
// 1), a).
vec3 ui_reinhard_under_ui(vec3 scene, float a, float level) {
  scene = max_d3d(scene, 0.0);
  float luminance = dot(scene, UI_REC2020_LUMA_WEIGHTS) / level;
  float out_l = 1.0 / (luminance + 1.0);
  return scene * lerp_d3d(1.0, out_l * level, a);
}

// ComposeUIAndScene(SceneColor, UIColor, UILevel): the Reinhard only under translucent UI (0 < a
// < 1; NaN alpha fails the test), then the premultiplied over.
vec3 ui_compose(vec3 scene, vec4 ui, float level) {
  if (ui.a > 0.0 && ui.a < 1.0) scene = ui_reinhard_under_ui(scene, ui.a, level);
  return scene * (1.0 - ui.a) + ui.rgb * level;
}

// ApplyColorDeficiency: through linear sRGB primaries and back, only when the permutation is on
// (otherwise the colour passes bit-exactly).
vec3 ui_apply_color_deficiency(vec3 rec2020, UiCompositeParams p) {
  if (!ui_color_deficiency_active(p)) return rec2020;
  vec3 srgb = rec2020_to_srgb(rec2020);
  srgb = color_deficiency(srgb, p.cvd_type, p.cvd_severity, p.cvd_correct, p.cvd_show_correction);
  return srgb_to_rec2020(srgb);
}

// The output encode of Main: PQ: LinearToST2084 (no clamp, a negative channel after the CVD
// matrices is NaN as on D3D); scRGB: Rec2020_2_sRGB · (x / ScRGBScaleFactor).
vec3 ui_encode_output(vec3 rec2020_nits, bool scrgb) {
  if (!scrgb) {
    return vec3(pq_from_nits(rec2020_nits.r), pq_from_nits(rec2020_nits.g),
                pq_from_nits(rec2020_nits.b));
  }
  return rec2020_to_srgb(rec2020_nits / UI_SCRGB_SCALE_FACTOR);
}

// r.HDR.UI.CompositeMode 0: no composite shader; Slate blends the premultiplied UI into the back
// buffer's code values (BF_One, BF_InverseSourceAlpha). A PQ (UNORM10) target clamps blender
// inputs and output to [0, 1] with D3D's UNORM rules (NaN → 0); scRGB (FP16) does not clamp.
vec4 ui_standard_blend(vec4 scene, vec4 ui, bool scrgb) {
  if (scrgb) return ui + (1.0 - ui.a) * scene;
  float a = saturate_d3d(ui.a);
  vec4 out_px;
  for (int c = 0; c < 4; ++c) {
    out_px[c] = saturate_d3d(saturate_d3d(ui[c]) + (1.0 - a) * saturate_d3d(scene[c]));
  }
  return out_px;
}

// One back-buffer pixel after the UI pass: `scene` is the back-buffer code, `ui` the UI texel
// (point-sampled at the same pixel). Mode != 0: the shader, alpha 1.
vec4 ui_composite_pixel(vec4 scene, vec4 ui, UiCompositeParams p) {
  bool scrgb = ui_uses_scrgb(p.output_device);
  if (p.composite_mode == 0) return ui_standard_blend(scene, ui, scrgb);
  vec4 ui_nits = ui_hdr_ui_color(ui, p);
  vec3 scene_nits = ui_hdr_scene_color(scene.rgb, scrgb);
  vec3 composed = ui_compose(scene_nits, ui_nits, p.ui_level);
  vec3 after_cvd = ui_apply_color_deficiency(composed, p);
  return vec4(ui_encode_output(after_cvd, scrgb), 1.0);
}

#endif
