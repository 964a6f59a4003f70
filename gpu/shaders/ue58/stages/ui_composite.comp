#version 450
#extension GL_GOOGLE_include_directive : require
// Stage "ue58_ui_composite": UE 5.8's HDR UI composite over the back buffer (in_px: PQ signals
// for devices 3/4, scRGB for 5/6) with the UI layer in aux0_px (premultiplied, as Slate wrote it,
// the back buffer's size), both read at the pixel's own position as UE's point samplers do
// (CompositeUICS: RWSceneTexture[DispatchThreadId], UITexture at the texel centre).
// Reference: reference/ue/ue58/ue58_ui_composite.cpp.
#include "hdrc/interface.glsl"
#include "../lib/ui_composite58.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  // The engine binds a UI layer of the back buffer's size (it refuses another), so pixel i of
  // both is the same texel.
  out_px[i] = ue58_ui_composite_pixel(in_px[i], aux0_px[i]);
}
