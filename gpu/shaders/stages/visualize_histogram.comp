#version 450
#extension GL_GOOGLE_include_directive : require
// Stage "visualize_hdr", pass 3 (dispatched as ONE workgroup): the 64-bucket histogram of the HDR
// scene (in_px), its outlier-free average luminance, the two meters' averages and the numbers
// MainPS prints, written to scratch_px[W·H, W·H + 22) (layout: lib/visualize_scratch.glsl).
// scratch_px[0, W·H) holds the tonemapped scene from the tonemap pass.
// Reference: reference/reference_engine.cpp visualize_hdr_stage, reference/ue/visualize/*.
//
// The histogram sums every pixel's 13.19 fixed-point weights exactly, as Histogram.usf's atomic
// path does, but in 64 bits (two 32-bit words with carry): with 2^19 per unit weight a 32-bit
// bucket would overflow after 8192 pixels (the reference sums in uint64).
#include "hdrc/interface.glsl"
#include "../lib/visualize_histogram.glsl"
#include "../lib/visualize_meter.glsl"
#include "../lib/visualize_panel.glsl"
#include "../lib/visualize_scratch.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

shared uint bucket_lo[HISTOGRAM_SIZE];
shared uint bucket_hi[HISTOGRAM_SIZE];
shared vec3 partial_meter_hdr[HDRC_LOCAL_SIZE_X];
shared vec3 partial_meter_scene[HDRC_LOCAL_SIZE_X];
shared vec3 partial_illuminance[HDRC_LOCAL_SIZE_X];

// Exact 64-bit add: the low word's atomic returns its old value; a wrap carries into the high word.
void bucket_add(int bucket, uint weight) {
  if (weight == 0u) return;
  uint old = atomicAdd(bucket_lo[bucket], weight);
  if (old > 0xffffffffu - weight) atomicAdd(bucket_hi[bucket], 1u);
}

vec3 sample_hdr(vec2 f, int w, int h) {
  BilinearTaps t = bilinear_taps(f.x, f.y, w, h);
  return bilinear_combine(in_px[t.i00].rgb, in_px[t.i10].rgb, in_px[t.i01].rgb, in_px[t.i11].rgb,
                          t);
}

vec3 sample_tonemapped(vec2 f, int w, int h) {
  BilinearTaps t = bilinear_taps(f.x, f.y, w, h);
  return bilinear_combine(scratch_px[t.i00].rgb, scratch_px[t.i10].rgb, scratch_px[t.i01].rgb,
                          scratch_px[t.i11].rgb, t);
}

void main() {
  const uint lane = gl_LocalInvocationID.x;
  const uint lanes = gl_WorkGroupSize.x;
  const int w = P.width;
  const int h = P.height;
  const float one_over_pre_exposure = 1.0 / P.pre_exposure;  // View.OneOverPreExposure

  for (uint b = lane; b < uint(HISTOGRAM_SIZE); b += lanes) {
    bucket_lo[b] = 0u;
    bucket_hi[b] = 0u;
  }
  barrier();

  // Histogram.usf MainAtomicCS over every pixel (the viewport is the whole image; ScreenWeight 1).
  const uint n = uint(w * h);
  for (uint i = lane; i < n; i += lanes) {
    int b0, b1;
    uint w0, w1;
    histogram_splat(in_px[i].rgb * one_over_pre_exposure, b0, w0, b1, w1);
    bucket_add(b0, w0);
    bucket_add(b1, w1);
  }

  // The meters' samples, spread over the lanes.
  vec3 meter_hdr = vec3(0.0), meter_scene = vec3(0.0), illuminance = vec3(0.0);
  for (int k = int(lane); k < METER_SAMPLES * METER_SAMPLES; k += int(lanes)) {
    vec2 f = meter_sample_position(k, w, h);
    meter_hdr += sample_hdr(f, w, h);
    meter_scene += sample_tonemapped(f, w, h);
  }
  for (int k = int(lane); k < ILLUMINANCE_SAMPLES * ILLUMINANCE_SAMPLES; k += int(lanes)) {
    illuminance += sample_hdr(illuminance_sample_position(k, w, h), w, h);
  }
  partial_meter_hdr[lane] = meter_hdr;
  partial_meter_scene[lane] = meter_scene;
  partial_illuminance[lane] = illuminance;
  barrier();
  if (lane != 0u) return;

  float hist[HISTOGRAM_SIZE];
  for (int b = 0; b < HISTOGRAM_SIZE; ++b)
    hist[b] = histogram_bucket_value(bucket_hi[b], bucket_lo[b], w, h);
  meter_hdr = vec3(0.0);
  meter_scene = vec3(0.0);
  illuminance = vec3(0.0);
  for (uint l = 0u; l < lanes; ++l) {
    meter_hdr += partial_meter_hdr[l];
    meter_scene += partial_meter_scene[l];
    illuminance += partial_illuminance[l];
  }

  const int base = w * h;
  for (int k = 0; k < VIS_HISTOGRAM_TEXELS; ++k)
    scratch_px[base + k] = vec4(hist[4 * k], hist[4 * k + 1], hist[4 * k + 2], hist[4 * k + 3]);
  const float average_scene_luminance = average_luminance_without_outliers(hist);
  scratch_px[base + VIS_HISTOGRAM_STATS] =
      vec4(histogram_max(hist), histogram_sum(hist), average_scene_luminance, 0.0);

  // Luminance meter: Luminance(mean HDR · OneOverPreExposure) "NIT" and its EV100
  // log2((L / 0.18) / LuminanceMax).
  const float meter_count = float(METER_SAMPLES * METER_SAMPLES);
  vec3 meter_hdr_mean = meter_hdr / meter_count * one_over_pre_exposure;
  float meter_luminance = ue_luminance(meter_hdr_mean);
  float meter_ev100 = log2_d3d((meter_luminance / EA_MIDDLE_GREY) / EA_LUMINANCE_MAX);
  scratch_px[base + VIS_METER_HDR] = vec4(meter_hdr_mean, meter_luminance);
  scratch_px[base + VIS_METER_SCENE] = vec4(meter_scene / meter_count, meter_ev100);

  // Illuminance meter: E = π · mean HDR · OneOverPreExposure, printed as Luminance(E) "LUX".
  vec3 illuminance_rgb = illuminance / float(ILLUMINANCE_SAMPLES * ILLUMINANCE_SAMPLES) *
                         one_over_pre_exposure * VIS_PI;
  scratch_px[base + VIS_ILLUMINANCE] = vec4(illuminance_rgb, ue_luminance(illuminance_rgb));

  // Exposure lines and labels (EyeAdaptationBuffer: EyeAdaptationResult = the Exposure setting,
  // ExposureBiasOnly 1, so the "without bias" exposure equals it). The buffer holds the plain
  // exposure: the Tonemap pass reads the same entry and applies OneOverPreExposure separately
  // (PostProcessVisualizeHDR.usf MainPS: EyeAdaptationBuffer[0].r). P.exposure is
  // Exposure · OneOverPreExposure (the Tonemap pass's product), so PreExposure is multiplied back.
  const float panel_width = float(panel_geometry(w, h).width);
  const float exposure = P.exposure * P.pre_exposure;
  const float exposure_without_bias = exposure / EA_EXPOSURE_BIAS_ONLY;
  scratch_px[base + VIS_EXPOSURE] = vec4(
      log2_d3d(1.0 / exposure_without_bias),
      histogram_position_from_luminance(1.0 / exposure_without_bias) * panel_width,
      log2_d3d((1.0 / exposure) / EA_LUMINANCE_MAX),
      histogram_position_from_luminance(1.0 / exposure) * panel_width);
  scratch_px[base + VIS_LINES] =
      vec4(histogram_position_from_luminance(average_scene_luminance / EA_MIDDLE_GREY) * panel_width,
           histogram_position_from_luminance(EA_MIN_AVERAGE_LUMINANCE / EA_MIDDLE_GREY),
           histogram_position_from_luminance(EA_MAX_AVERAGE_LUMINANCE / EA_MIDDLE_GREY), exposure);
}
