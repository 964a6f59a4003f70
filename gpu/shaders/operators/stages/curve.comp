#version 450
#extension GL_GOOGLE_include_directive : require
// Stage "curve" of the operators pipeline: the classic tone-mapping operator P.op_operator on each
// pixel's rgb (alpha passes through). Reference: reference/operators/operators.h (apply_operator).
#include "hdrc/interface.glsl"
#include "../lib/operators.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  vec4 px = in_px[i];
  out_px[i] = vec4(operators_apply(px.rgb), px.a);
}
