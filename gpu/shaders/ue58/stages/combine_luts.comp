#version 450
#extension GL_GOOGLE_include_directive : require
// Stage "ue58_combine_luts": UE 5.8's CombineLUTs bake (PostProcessCombineLUTs.usf: MainCS), one
// invocation per outer texel (r, g, b), r fastest (N = P.lut_size), at DispatchThreadId / (N - 1);
// the inner LUT it samples is the first pass's (combine_luts_inner.comp), in the scratch buffer. The stored value
// OutDeviceColor * LUTInvMax goes to the volume image, whose format (A2B10G10R10 UNORM, RGBA16F)
// does the storage rounding; the half rounding and the 10-bit NaN are made explicit as in
// gpu/shaders/stages/combine_luts.comp. Reference: reference/ue/ue58/ue58_combine_luts.cpp.
#include "hdrc/interface.glsl"
#include "../lib/combine_luts58.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

void main() {
  int n = P.lut_size;
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(n * n * n)) return;
  ivec3 texel = ivec3(int(i) % n, (int(i) / n) % n, int(i) / (n * n));
  vec3 stored = ue58_outer_texel(vec3(texel) / float(n - 1));
  if (P.lut_format == 1) {
    stored = vec3(ue58_round_to_half_rne(stored.r), ue58_round_to_half_rne(stored.g),
                  ue58_round_to_half_rne(stored.b));
  }
  if (P.lut_format == 0) {
    stored = vec3(isnan(stored.r) ? 0.0 : stored.r, isnan(stored.g) ? 0.0 : stored.g,
                  isnan(stored.b) ? 0.0 : stored.b);
  }
  imageStore(lut_store_3d, texel, vec4(stored, 0.0));
}
