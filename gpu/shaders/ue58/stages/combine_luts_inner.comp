#version 450
#extension GL_GOOGLE_include_directive : require
// Stage "ue58_combine_luts", first pass: UE 5.8's inner LUT (PostProcessCombineLUTsInner.usf:
// MainCS / MethodLUTsCommon), M^3 texels (M = P.ue58_inner_lut_size), texel i = (r, g, b) with r
// fastest, each rounded to the inner LUT's format, written to out_px[i] — the scratch buffer
// (StagePass::output_to_scratch), which holds the case's N^3 pixels plus 1024 vec4: the cases keep
// M^3 within that (docs/ue58-decisions.md E2); a larger inner LUT is written as NaN at texel 0, so
// that every texel sampling it fails rather than reads past the buffer. Dispatched over N^3
// invocations, each bakes texels i, i + N^3, ... Nothing is baked when the inner LUT is not needed
// (AddCombineLUTPass binds a black volume then, which no path samples).
#include "hdrc/interface.glsl"
#include "../lib/combine_luts58.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

void main() {
  if (P.ue58_inner_needed == 0) return;
  int m = P.ue58_inner_lut_size;
  uint count = uint(m * m * m);
  uint stride = uint(P.width * P.height);
  uint i = gl_GlobalInvocationID.x;
  if (i >= stride) return;
  if (count > stride + 1024u) {
    if (i == 0u) out_px[0] = vec4(hdrc_nan());
    return;
  }
  for (uint k = i; k < count; k += stride) {
    ivec3 idx = ivec3(int(k) % m, (int(k) / m) % m, int(k) / (m * m));
    out_px[k] = vec4(ue58_inner_bake(idx), 0.0);
  }
}
