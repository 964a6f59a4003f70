#version 450
#extension GL_GOOGLE_include_directive : require
// Stage "pq_grade" of the pq_grading pipeline: each pixel's rgb graded through the case's .cube
// LUT in PQ space, display-mapped and encoded (alpha passes through). Reference:
// reference/pq_grading/pq_grading.h (grade).
#include "hdrc/interface.glsl"
#include "../lib/pq_grading.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  vec4 px = in_px[i];
  out_px[i] = vec4(pq_grading_apply(px.rgb), px.a);
}
