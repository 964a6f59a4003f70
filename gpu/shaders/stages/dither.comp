#version 450
#extension GL_GOOGLE_include_directive : require
// Stage "dither": the Tonemap pass's quantisation dither added to the input image (docs/spec/ue55.md §6.1 step
// 10); alpha passes through. Reference: reference/ue/tonemap.cpp (dither_image).
#include "hdrc/interface.glsl"
#include "../lib/dither.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  uvec2 pixel = uvec2(i % uint(P.width), i / uint(P.width));
  vec4 px = in_px[i];
  vec3 rgb = apply_dither(px.rgb, pixel, ivec2(P.width, P.height), P.grain_random.xy,
                          P.dither_amount);
  out_px[i] = vec4(rgb, px.a);
}
