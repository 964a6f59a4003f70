// UE 5.5's ACES 1.3 HDR output transform (output devices 3-6), float32 as UE's shaders evaluate it.
// Sources: TonemapCommon.ush 5.5 (izzy2lost/UnrealEngineUWP, commit
// aff11acf0c218535669021f6e646b3bcf6ad94a5): ACESOutputTransforms1000 / ACESOutputTransforms2000;
// ACES.ush (5.0-era copy, chenyong2github/UnrealEngine, commit
// 09c29cbee980f5c5fbff6c93cf6132e5f4bcf97a): limit_to_primaries, outputTransform. The 5.5
// TsParams overload of outputTransform is reconstructed (docs/ue55-decisions.md D2): the 5.0 body
// with Y_MIN = Min.y, Y_MAX = Max.y, display and limiting primaries ACEScg (D60), EOTF 4 (linear),
// dark surround, STRETCH_BLACK, no D60 simulation, full range. Reference (double):
// reference/ue/aces/aces_output.{h,cpp}. Spec §5.1.
//
// Non-finite input (D3D semantics, as the reference): a NaN or +-Inf channel makes compressColor
// NaN in every channel; lerp(aces, NaN, GamutCompression) is NaN even for GamutCompression = 0;
// the glow then makes every channel NaN and rrt_sweeteners' clamp turns them into 0, so the pixel
// leaves as black. Negative channels are clamped to 0 in AP0 and AP1 by rrt_sweeteners.
//
// The functions reading the parameter block need "hdrc/interface.glsl" included first.
#ifndef HDRC_ACES_OUTPUT_GLSL
#define HDRC_ACES_OUTPUT_GLSL

#include "aces_common.glsl"
#include "aces_gamut_compress.glsl"
#include "aces_rrt.glsl"
#include "aces_tonescale.glsl"
#include "matrix.glsl"

// ACES.ush: Y_2_linCV / linCV_2_Y.
vec3 y_2_lin_cv(vec3 y, float y_max, float y_min) { return (y - y_min) / (y_max - y_min); }
vec3 lin_cv_2_y(vec3 lin_cv, float y_max, float y_min) { return lin_cv * (y_max - y_min) + y_min; }

// ACES.ush: limit_to_primaries with LIMITING_PRI = ACEScg (XYZ_2_AP1_MAT / AP1_2_XYZ_MAT).
vec3 limit_to_ap1(vec3 xyz) {
  vec3 rgb = aces_mul(XYZ_2_AP1_MAT, xyz);
  return aces_mul(AP1_2_XYZ_MAT, clamp_d3d(rgb, 0.0, 1.0));
}

// ACES.ush: outputTransform, the TsParams overload as UE 5.5 calls it. AP0 in, display-referred
// linear nits with AP1 primaries (D60 white) out, each channel in [0, Max.y].
vec3 aces_output_transform(vec3 aces, TsParams params) {
  float y_min = params.Min.y;  // Y_MIN, nits
  float y_max = params.Max.y;  // Y_MAX, nits

  vec3 rgb_pre = rrt_sweeteners(aces);
  vec3 rgb_post = ssts_f3(rgb_pre, params);  // nits, AP1
  vec3 linear_cv = y_2_lin_cv(rgb_post, y_max, y_min);
  vec3 xyz = aces_mul(AP1_2_XYZ_MAT, linear_cv);
  // Dark surround: no adjustment. Limit to the AP1 primaries; the display white is D60, so no CAT.
  xyz = limit_to_ap1(xyz);
  linear_cv = aces_mul(XYZ_2_AP1_MAT, xyz);
  linear_cv = clamp_d3d(linear_cv, 0.0, HALF_POS_INF);
  // EOTF 4 (linear) with STRETCH_BLACK.
  return clamp_d3d(lin_cv_2_y(linear_cv, y_max, 0.0), 0.0, HALF_POS_INF);
}

// TonemapCommon.ush: the body shared by ACESOutputTransforms1000 and ACESOutputTransforms2000.
// scene_linear: working colour space; wcs_to_ap0: WorkingColorSpace.ToAP0 (rows).
vec3 aces_output_transforms(vec3 scene_linear, vec4 wcs_to_ap0[3], FACESTonemapParams params) {
  vec3 aces = mul_rows(wcs_to_ap0, scene_linear * params.SceneColorMultiplier);
  aces = lerp_d3d(aces, compress_color(aces), params.GamutCompression);
  return aces_output_transform(aces, params.AcesParams);
}

// TonemapCommon.ush: ACESOutputTransforms1000 / ACESOutputTransforms2000 with the case's
// parameters (P.wcs_to_ap0 and the ACES block of P). The two bodies are identical in UE; the name
// only says which output device selected the parameters. Working colour space in, nits (AP1) out.
vec3 aces_output_transforms_1000(vec3 scene_linear) {
  return aces_output_transforms(scene_linear, P.wcs_to_ap0, aces_tonemap_params_from_block());
}

vec3 aces_output_transforms_2000(vec3 scene_linear) {
  return aces_output_transforms(scene_linear, P.wcs_to_ap0, aces_tonemap_params_from_block());
}

#endif
