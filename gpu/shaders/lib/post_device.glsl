// The Tonemap pass's per-device post conversion of OutDeviceColor (PostProcessTonemap.usf
// TonemapCommonPS, docs/spec/ue55.md §6.1 step 9): devices 5/6 (ACES scRGB) ST2084ToScRGB, device 7
// (LinearEXR) ST2084ToLinear, every other device unchanged. Reference: reference/ue/tonemap.cpp
// post_convert, st2084_to_scrgb.
#ifndef HDRC_POST_DEVICE_GLSL
#define HDRC_POST_DEVICE_GLSL

#include "d3d_math.glsl"
#include "st2084.glsl"

// UE_ACES_HDR_Y_MIN (TonemapCommon.ush): the ODT's minimum luminance, nits.
const float ACES_HDR_Y_MIN = 9.99999975e-05;  // float(0.0001)

// TonemapCommon.ush ST2084ToScRGB: AP1_2_sRGB = XYZ_2_sRGB_MAT · D60_2_D65_CAT · AP1_2_XYZ_MAT,
// UE's literal product (reference: ue_matrices ap1_to_output_gamut(0)), rows, float32.
// gpu/tonemap_shader_test.cpp asserts float(reference) == the values the GPU holds.
// AP1_TO_SRGB (rows): generated into hdrc/interface.glsl
// from the reference (gpu/shader_constants.cpp: shared_matrices).

vec3 nits_from_pq3(vec3 pq) { return vec3(nits_from_pq(pq.r), nits_from_pq(pq.g), nits_from_pq(pq.b)); }

// nits = clamp(ST2084ToLinear(pq), Y_MIN, MaxODTNits); linCV = (nits − Y_MIN)/(Max − Y_MIN);
// scRGB = AP1_2_sRGB · linCV · (MaxODTNits / 80). The input is PQ-coded AP1 (the LUT skips the
// output-gamut matrix for devices 5/6); `nits` = nits_from_pq3(pq), which the caller has.
vec3 st2084_to_scrgb(vec3 pq, vec3 nits, float max_odt_nits) {
  vec3 lin_cv = (clamp_d3d(nits, ACES_HDR_Y_MIN, max_odt_nits) - ACES_HDR_Y_MIN) /
                (max_odt_nits - ACES_HDR_Y_MIN);
  // D3D's clamp would turn a NaN signal into Y_MIN; a NaN here only comes from the LUT sample of
  // a NaN coordinate, which the port (as the reference) propagates (docs/ue55-decisions.md D-NF).
  if (isnan(pq.r)) lin_cv.r = pq.r;
  if (isnan(pq.g)) lin_cv.g = pq.g;
  if (isnan(pq.b)) lin_cv.b = pq.b;
  vec3 s = vec3(dot(AP1_TO_SRGB[0], lin_cv), dot(AP1_TO_SRGB[1], lin_cv),
                dot(AP1_TO_SRGB[2], lin_cv));
  return s * (max_odt_nits / 80.0);
}

vec3 post_device(int output_device, vec3 out_device, float max_luminance) {
  if (output_device != 5 && output_device != 6 && output_device != 7) return out_device;
  // ST2084ToLinear of the signal is the first step of both conversions: evaluated once (the same
  // float32 operations; a device that runs both sides of a branch no longer pays it twice).
  vec3 nits = nits_from_pq3(out_device);
  return output_device == 7 ? nits : st2084_to_scrgb(out_device, nits, max_luminance);
}

#endif
