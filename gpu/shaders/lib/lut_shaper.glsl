// The LUT shaper of the output device: encode as ColorLookupTable does (PostProcessTonemap.usf,
// docs/spec/ue55.md §6.1 step 7), decode as CombineLUTsCommon does (docs/spec/ue55.md §4.3). Reference: reference/ue/lut_shaper.h.
#ifndef HDRC_LUT_SHAPER_GLSL
#define HDRC_LUT_SHAPER_GLSL

#include "st2084.glsl"
#include "ue_log_shaper.glsl"

bool uses_pq_shaper(int output_device) { return output_device >= 3; }

vec3 lut_encode(int output_device, vec3 x) {
  if (uses_pq_shaper(output_device)) {
    return vec3(pq_from_nits(x.r * LINEAR_TO_NITS_SCALE), pq_from_nits(x.g * LINEAR_TO_NITS_SCALE),
                pq_from_nits(x.b * LINEAR_TO_NITS_SCALE));
  }
  float black = lin_from_log(0.0);
  return vec3(log_from_lin(x.r + black), log_from_lin(x.g + black), log_from_lin(x.b + black));
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
