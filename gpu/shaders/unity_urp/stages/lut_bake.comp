#version 450
#extension GL_GOOGLE_include_directive : require
// Unity URP's internal LUT bake (LutBuilderHdr / LutBuilderLdr), one invocation per texel. Texel i
// of the N³ dispatch (N = P.lut_size) is (r, g, b) with r fastest, then g, then b; its lattice code
// is (r, g, b)/(N − 1) (LogC in HDR grading, linear in LDR grading), and the graded (HDR: tone
// mapped) value goes to texel (r + N·b, g) of the N² × N strip, rounded first to what the storage
// format holds (P.lut_format 1: RGBA16F, 3: RGBA8 UNORM) so that any store keeps it. Reference:
// reference/unity_urp/unity_urp.cpp (bake_lut_strip).
#include "hdrc/interface.glsl"
#include "../lib/unity_grade.glsl"
#include "../lib/unity_lut.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

void main() {
  int n = P.lut_size;
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(n * n * n)) return;
  ivec3 texel = ivec3(int(i) % n, (int(i) / n) % n, int(i) / (n * n));
  vec3 stored = urp_quantize_texel(urp_lut_texel(urp_lattice_code(texel, n)));
  imageStore(lut_store_2d, ivec2(texel.r + n * texel.b, texel.g), vec4(stored, 1.0));
}
