// The sRGB <-> Rec.2020 conversions of the HDR UI composite: CompositeUIPixelShader.usf builds them
// as products of ACES.ush's literal matrices, mul(XYZ_2_Rec2020_MAT, sRGB_2_XYZ_MAT) and
// mul(XYZ_2_sRGB_MAT, Rec2020_2_XYZ_MAT) (izzy2lost/UnrealEngineUWP 5.5, commit 0ac46dcf:
// ComputeHDRUIColor, ComputeHDRSceneColor, ApplyColorDeficiency, Main).
// Values: float(reference/ui/composite.cpp srgb_to_rec2020() / rec2020_to_srgb()), the products
// evaluated in double and rounded once, printed with 9 significant digits; a test reads them back
// from the GPU (gpu/ui_shader_test.cpp). Rows: out = M · v.
#ifndef HDRC_REC2020_SRGB_GLSL
#define HDRC_REC2020_SRGB_GLSL

const vec3 SRGB_TO_REC2020[3] = vec3[](vec3(0.627488017, 0.329267114, 0.0433014743),
                                       vec3(0.069108218, 0.9195171, 0.0113595454),
                                       vec3(0.0163962338, 0.0880229846, 0.895499706));

const vec3 REC2020_TO_SRGB[3] = vec3[](vec3(1.66053164, -0.58764261, -0.0728400499),
                                       vec3(-0.124553561, 1.1329025, -0.00834836345),
                                       vec3(-0.0181512013, -0.100579083, 1.11858058));

vec3 srgb_to_rec2020(vec3 v) {
  return vec3(dot(SRGB_TO_REC2020[0], v), dot(SRGB_TO_REC2020[1], v), dot(SRGB_TO_REC2020[2], v));
}

vec3 rec2020_to_srgb(vec3 v) {
  return vec3(dot(REC2020_TO_SRGB[0], v), dot(REC2020_TO_SRGB[1], v), dot(REC2020_TO_SRGB[2], v));
}

#endif
