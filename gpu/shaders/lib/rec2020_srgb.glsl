// The sRGB <-> Rec.2020 conversions of the HDR UI composite: CompositeUIPixelShader.usf builds them
// as products of ACES.ush's literal matrices, mul(XYZ_2_Rec2020_MAT, sRGB_2_XYZ_MAT) and
// mul(XYZ_2_sRGB_MAT, Rec2020_2_XYZ_MAT) (lakeone/UE5.51MagicM 5.5.1 and izzy2lost/UnrealEngineUWP 5.5, commit 0ac46dcf:
// ComputeHDRUIColor, ComputeHDRSceneColor, ApplyColorDeficiency, Main).
// Values: float(reference/ue/ui/composite.cpp srgb_to_rec2020() / rec2020_to_srgb()), the products
// evaluated in double and rounded once, printed losslessly into the generated interface; a test
// reads them back from the GPU (gpu/ui_shader_test.cpp). Rows: out = M · v.
#ifndef HDRC_REC2020_SRGB_GLSL
#define HDRC_REC2020_SRGB_GLSL

// SRGB_TO_REC2020, REC2020_TO_SRGB: generated into hdrc/interface.glsl
// from the reference (gpu/shader_constants.cpp: shared_matrices).

vec3 srgb_to_rec2020(vec3 v) {
  return vec3(dot(SRGB_TO_REC2020[0], v), dot(SRGB_TO_REC2020[1], v), dot(SRGB_TO_REC2020[2], v));
}

vec3 rec2020_to_srgb(vec3 v) {
  return vec3(dot(REC2020_TO_SRGB[0], v), dot(REC2020_TO_SRGB[1], v), dot(REC2020_TO_SRGB[2], v));
}

#endif
