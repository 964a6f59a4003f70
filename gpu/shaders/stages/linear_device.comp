#version 450
#extension GL_GOOGLE_include_directive : require
// Stage "linear_device": shaper round trip, then CombineLUTs' device 8 / 7 branch and the
// tonemapper's post conversion (docs/spec/ue55.md §4.12, §6.1 step 9). Reference: reference_engine.cpp.
#include "hdrc/interface.glsl"
#include "../lib/lut_shaper.glsl"
#include "../lib/matrix.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

vec3 linear_device(vec3 graded) {
  if (P.output_device == 8) return graded;  // HDR_LinearNoToneCurve
  // HDR_LinearEXR: PQ-encode in the output gamut (CombineLUTs), ST2084ToLinear (tonemapper).
  vec3 v = mul_rows(P.ap1_to_output, mul_rows(P.wcs_to_ap1, graded));
  vec3 stored = vec3(pq_from_nits(v.r), pq_from_nits(v.g), pq_from_nits(v.b));
  return vec3(nits_from_pq(stored.r), nits_from_pq(stored.g), nits_from_pq(stored.b));
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  vec4 px = in_px[i];
  vec3 graded = lut_decode(P.output_device, lut_clamp(lut_encode(P.output_device, px.rgb)));
  out_px[i] = vec4(linear_device(graded), px.a);
}
