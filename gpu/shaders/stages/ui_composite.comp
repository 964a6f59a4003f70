#version 450
#extension GL_GOOGLE_include_directive : require
// Stage "ui_composite": the HDR UI composite over the back buffer (in_px: PQ signals for devices
// 3/4, scRGB for 5/6) with the UI layer in aux0_px (premultiplied, sRGB-encoded, the back
// buffer's size), both read at the pixel's own position as UE's point samplers do.
// Reference: reference/reference_engine.cpp ui_composite_stage → reference/ue/ui/composite.cpp.
#include "hdrc/interface.glsl"
#include "../lib/ui_composite.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  int x = int(i) % P.width;
  int y = int(i) / P.width;
  // The engine binds a UI layer of the back buffer's size; a texel outside a smaller one reads as
  // transparent black rather than out of bounds.
  vec4 ui = vec4(0.0);
  if (x < P.aux0_width && y < P.aux0_height) ui = aux0_px[y * P.aux0_width + x];

  out_px[i] = ui_composite_pixel(in_px[i], ui, ui_composite_params_from_block());
}
