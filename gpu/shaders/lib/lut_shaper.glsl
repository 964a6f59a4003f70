// The LUT shaper of the output device: encode as ColorLookupTable does (PostProcessTonemap.usf,
// docs/spec/ue55.md §6.1 step 7), decode as CombineLUTsCommon does (docs/spec/ue55.md §4.3). Reference: reference/ue/lut_shaper.h.
#ifndef HDRC_LUT_SHAPER_GLSL
#define HDRC_LUT_SHAPER_GLSL

#include "d3d_math.glsl"
#include "st2084.glsl"
#include "ue_log_shaper.glsl"

bool uses_pq_shaper(int output_device) { return output_device >= 3; }

// ColorLookupTable's encode: PQ of x · LinearToNitsScale (UE 5.8: of clamp(x · LinearToNitsScale,
// 0, 10000), `clamp_nits`; D3D's clamp sends NaN to 0) or LinToLog(x + LogToLin(0)). Reference:
// reference/ue/lut_shaper.h lut_encode(LutShaper, x).
vec3 lut_encode_shaper(bool pq, bool clamp_nits, vec3 x) {
  if (pq) {
    vec3 nits = x * LINEAR_TO_NITS_SCALE;
    if (clamp_nits) nits = clamp_d3d(nits, 0.0, 10000.0);
    return vec3(pq_from_nits(nits.r), pq_from_nits(nits.g), pq_from_nits(nits.b));
  }
  float black = lin_from_log(0.0);
  return vec3(log_from_lin(x.r + black), log_from_lin(x.g + black), log_from_lin(x.b + black));
}

// UE 5.5: PQ for devices 3–9, no clamp.
vec3 lut_encode(int output_device, vec3 x) {
  return lut_encode_shaper(uses_pq_shaper(output_device), false, x);
}

vec3 lut_decode(int output_device, vec3 e) {
  if (uses_pq_shaper(output_device)) {
    return vec3(nits_from_pq(e.r), nits_from_pq(e.g), nits_from_pq(e.b)) / LINEAR_TO_NITS_SCALE;
  }
  // CombineLUTs: LogToLin(e) - LogToLin(0). At the black lattice point both terms are the same
  // function at the same argument, so the decoded colour is exactly 0 (IEEE x - x), as the
  // reference computes it; there UE's pow(0, 0) gives NaN (docs/ue55-decisions.md D-NaN, "black
  // lattice point"). The compiler folds LogToLin(0) with the host's exp2 while lavapipe's run-time
  // exp2 differs by an ulp, which left a channel at +1e-9 and turned that NaN into a number; the
  // black lattice point is therefore decoded as 0 explicitly.
  float black = lin_from_log(0.0);
  vec3 lin = vec3(lin_from_log(e.r), lin_from_log(e.g), lin_from_log(e.b)) - black;
  return vec3(e.r == 0.0 ? 0.0 : lin.r, e.g == 0.0 ? 0.0 : lin.g, e.b == 0.0 ? 0.0 : lin.b);
}

// The sampler's clamp-to-edge addressing applied to the lattice coordinate.
vec3 lut_clamp(vec3 e) { return vec3(clamp_address(e.r), clamp_address(e.g), clamp_address(e.b)); }

#endif
