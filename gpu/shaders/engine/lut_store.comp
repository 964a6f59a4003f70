#version 450
#extension GL_GOOGLE_include_directive : require
// The engine's store pass after a LUT bake pass (gpu/vulkan_engine.cpp, Role::kStore; not a stage
// pass, so a --shader-dir port does not provide it): texel (r, g, b) of the N³ lattice, i → (i mod
// N, (i div N) mod N, i div N²), is read from the bake image, where the bake pass stored it as
// float32 (RGBA32F: bound as lut_3d / lut_2d, read with texelFetch, unfiltered and exact), and
// written with imageStore to the LUT image of the case's format (lut_store_3d for the volume
// layout, P.lut_layout 0; lut_store_2d at (r + N·b, g) for the unwrapped layout 1). The value
// stored is the float the bake pass stored, so the format's conversion gives the bits the bake
// pass's own imageStore would have given. Kept this small on purpose: llvmpipe compiles one
// variant of it per LUT format, layout and power-of-two-ness of N, in milliseconds, while the bake
// shader keeps one variant for all of them.
#include "hdrc/interface.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

void main() {
  int n = P.lut_size;
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(n * n * n)) return;
  ivec3 texel = ivec3(int(i) % n, (int(i) / n) % n, int(i) / (n * n));
  if (P.lut_layout == 0) {
    imageStore(lut_store_3d, texel, texelFetch(lut_3d, texel, 0));
  } else {
    ivec2 p = ivec2(texel.r + n * texel.b, texel.g);
    imageStore(lut_store_2d, p, texelFetch(lut_2d, p, 0));
  }
}
