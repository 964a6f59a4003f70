// SMPTE ST 2084 (PQ) as UE writes it: GammaCorrectionCommon.ush LinearToST2084 / ST2084ToLinear
// (docs/spec/ue55.md §3.1). Constants come from the generated interface (color/st2084.h).
#ifndef HDRC_ST2084_GLSL
#define HDRC_ST2084_GLSL

#include "d3d_math.glsl"

// nits → PQ signal. No clamp (UE has none): negative nits are NaN, as pow is on D3D.
float pq_from_nits(float nits) {
  float lm = pow_d3d(nits / PQ_PEAK_NITS, PQ_M1);
  return pow_d3d((PQ_C1 + PQ_C2 * lm) * (1.0 / (1.0 + PQ_C3 * lm)), PQ_M2);
}

// PQ signal → nits.
float nits_from_pq(float pq) {
  float np = pow_d3d(pq, 1.0 / PQ_M2);
  float l = max(np - PQ_C1, 0.0) / (PQ_C2 - PQ_C3 * np);
  if (isnan(np)) l = np;  // GLSL max(NaN, 0) is undefined; D3D's max would also return 0 here,
                          // but np is NaN only for a NaN or negative signal, whose result is NaN.
  return pow_d3d(l, 1.0 / PQ_M1) * PQ_PEAK_NITS;
}

#endif
