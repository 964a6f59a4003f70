#version 450
#extension GL_GOOGLE_include_directive : require
// Stage "shaper": encode with the device's LUT shaper, clamp as the LUT sampler does, decode as
// CombineLUTs does. Reference: reference/reference_engine.cpp (shaper_round_trip).
#include "hdrc/interface.glsl"
#include "../lib/lut_shaper.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  vec4 px = in_px[i];
  vec3 rgb = lut_decode(P.output_device, lut_clamp(lut_encode(P.output_device, px.rgb)));
  out_px[i] = vec4(rgb, px.a);
}
