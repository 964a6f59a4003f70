#version 450
#extension GL_GOOGLE_include_directive : require
// Stage "visualize_hdr", pass 4 (over pixels): MainPS of PostProcessVisualizeHDR.usf. Reads the
// HDR scene (in_px), the tonemapped scene (scratch_px[0, W·H)) and what the histogram pass left at
// scratch_px[W·H ...] (lib/visualize_scratch.glsl); writes the image (out_px).
// Reference: reference/reference_engine.cpp visualize_hdr_stage → visualize::visualize_hdr.
#include "hdrc/interface.glsl"
#include "../lib/visualize_hdr.glsl"
#include "../lib/visualize_scratch.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  int n = P.width * P.height;
  if (i >= uint(n)) return;
  VisualizeInputs v;
  for (int k = 0; k < VIS_HISTOGRAM_TEXELS; ++k) {
    vec4 t = scratch_px[n + k];
    v.histogram[4 * k] = t.x;
    v.histogram[4 * k + 1] = t.y;
    v.histogram[4 * k + 2] = t.z;
    v.histogram[4 * k + 3] = t.w;
  }
  v.histogram_max = scratch_px[n + VIS_HISTOGRAM_STATS].x;
  v.meter_scene_average = scratch_px[n + VIS_METER_SCENE].rgb;
  v.exposure_without_bias_px = scratch_px[n + VIS_EXPOSURE].y;
  v.exposure_px = scratch_px[n + VIS_EXPOSURE].w;
  vec4 lines = scratch_px[n + VIS_LINES];
  v.average_luminance_px = lines.x;
  v.pos_min = lines.y;
  v.pos_max = lines.z;
  v.exposure = lines.w;
  v.one_over_pre_exposure = 1.0 / P.pre_exposure;
  v.debug_type = P.visualize_debug_type;
  int x = int(i) % P.width;
  int y = int(i) / P.width;
  out_px[i] = visualize_hdr_pixel(x, y, P.width, P.height, in_px[i], scratch_px[i], v);
}
