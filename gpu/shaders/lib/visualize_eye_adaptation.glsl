// The auto-exposure ("eye adaptation") parameters VisualizeHDR and the histogram read, and UE's
// luminance ↔ histogram-position mapping (PostProcessHistogramCommon.ush:
// CalculateEyeAdaptationLuminance, ComputeHistogramPositionFromLogLuminance,
// ComputeLogLuminanceFromHistogramPosition; izzy2lost/UnrealEngineUWP 5.5, commit 2ad5a489).
// Reference: reference/ue/visualize/histogram.h.
//
// GetEyeAdaptationParameters (PostProcessEyeAdaptation.cpp) computes the parameters on the CPU.
// No case sets the settings they come from (the reference uses default_settings(true): a UE5
// project's extended luminance range, AutoExposure Low/High 10/90 %, Min/Max brightness −10/20
// EV100, histogram −10..20 EV100, lens attenuation 0.78, black bucket influence 0), so the block
// carries none of them: they are float(reference compute_eye_adaptation_parameters(...)) here,
// printed with 9 significant digits, and a test reads each back from the GPU
// (gpu/visualize_shader_test.cpp). When a case can set them they belong in the parameter block.
#ifndef HDRC_VISUALIZE_EYE_ADAPTATION_GLSL
#define HDRC_VISUALIZE_EYE_ADAPTATION_GLSL

#include "d3d_math.glsl"

const float EA_EXPOSURE_LOW_PERCENT = 0.100000001;   // clamp(10, 1, 99) / 100
const float EA_EXPOSURE_HIGH_PERCENT = 0.899999976;  // clamp(90, 1, 99) / 100
const float EA_MIN_AVERAGE_LUMINANCE = 0.000175781257;  // EV100ToLuminance(1, −10) · 0.18
const float EA_MAX_AVERAGE_LUMINANCE = 188743.688;      // EV100ToLuminance(1, 20) · 0.18
const float EA_HISTOGRAM_SCALE = 0.0333333351;          // 1 / (LogMax − LogMin) = 1/30
const float EA_HISTOGRAM_BIAS = 0.333333343;            // −LogMin · Scale
const float EA_LUMINANCE_MIN = 0.0009765625;            // 2^LogMin = 2^−10
const float EA_LUMINANCE_MAX = 1.0;                     // 0.78 / max(LensAttenuation, 0.01)
const float EA_BLACK_HISTOGRAM_BUCKET_INFLUENCE = 0.0;  // r.EyeAdaptation.BlackHistogramBucketInfluence
const float EA_MIDDLE_GREY = 0.18;                      // GetEyeAdaptationParameters kMiddleGrey
const float EA_ONE_THIRD = 1.0 / 3.0;
// EyeAdaptationBuffer[0].w, ExposureBiasOnly: the reference's eye-adaptation state has none (1.0,
// reference_engine.cpp visualize_hdr_stage), so the exposure with and without bias coincide.
const float EA_EXPOSURE_BIAS_ONLY = 1.0;

float histogram_position_from_log_luminance(float log2_luminance) {
  return log2_luminance * EA_HISTOGRAM_SCALE + EA_HISTOGRAM_BIAS;
}
float histogram_position_from_luminance(float luminance) {
  return histogram_position_from_log_luminance(log2_d3d(luminance));
}
float log_luminance_from_histogram_position(float position) {
  return (position - EA_HISTOGRAM_BIAS) / EA_HISTOGRAM_SCALE;
}
float luminance_from_histogram_position(float position) {
  return exp2(log_luminance_from_histogram_position(position));
}

// CalculateEyeAdaptationLuminance: max(mean(R, G, B), LuminanceMin) — HLSL max (maxNum), so a NaN
// mean gives LuminanceMin.
float eye_adaptation_luminance(vec3 rgb) {
  return max_d3d(dot(rgb, vec3(EA_ONE_THIRD)), EA_LUMINANCE_MIN);
}

#endif
