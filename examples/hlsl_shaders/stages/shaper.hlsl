// The `shaper` stage written in HLSL, as a UE port would write it, for
// `hdrconform run --shader-dir examples/hlsl_shaders` (docs/gpu-interface.md, "HLSL"). glslang's
// HLSL front end compiles it in place of stages/shaper.comp; the interface (parameter block `P`,
// in_px / out_px, the shared constants) comes from the generated "hdrc/interface.hlsl".
// UE: TonemapCommon.ush LinearToST2084 / ST2084ToLinear / LinToLog / LogToLin; the tonemapper's
// encode, the LUT sampler's clamp, CombineLUTs' decode (spec 3.1, 3.4, 4.3, 6.1 step 7).
#include "hdrc/interface.hlsl"

// D3D's pow: NaN for a negative or NaN base (SPIR-V's Pow leaves it undefined), and 0^y exact.
float pow_d3d(float x, float y) {
  if (isnan(x) || x < 0.0 || (x == 0.0 && y == 0.0)) return asfloat(0x7fc00000u);
  if (x == 0.0) return y > 0.0 ? 0.0 : asfloat(0x7f800000u);
  return pow(x, y);
}

float linear_to_st2084(float nits) {
  float lm = pow_d3d(nits / PQ_PEAK_NITS, PQ_M1);
  return pow_d3d((PQ_C1 + PQ_C2 * lm) * (1.0 / (1.0 + PQ_C3 * lm)), PQ_M2);
}

float st2084_to_linear(float pq) {
  float np = pow_d3d(pq, 1.0 / PQ_M2);
  float l = max(np - PQ_C1, 0.0) / (PQ_C2 - PQ_C3 * np);
  if (isnan(np)) l = np;  // SPIR-V's max of NaN is undefined; the result is NaN either way
  return pow_d3d(l, 1.0 / PQ_M1) * PQ_PEAK_NITS;
}

float saturate_d3d(float x) { return isnan(x) ? 0.0 : clamp(x, 0.0, 1.0); }
float log_to_lin(float x) { return exp2((x - LOG_GREY_CODE) * LOG_LINEAR_RANGE) * LOG_LINEAR_GREY; }
float lin_to_log(float x) {
  return saturate_d3d(log2(x) / LOG_LINEAR_RANGE - log2(LOG_LINEAR_GREY) / LOG_LINEAR_RANGE +
                      LOG_GREY_CODE);
}

// Encode, clamp as the sampler addresses (NaN stays NaN), decode.
float round_trip(int device, float x) {
  if (device >= 3) {
    float e = linear_to_st2084(x * LINEAR_TO_NITS_SCALE);
    if (!isnan(e)) e = clamp(e, 0.0, 1.0);
    return st2084_to_linear(e) / LINEAR_TO_NITS_SCALE;
  }
  // LogToLin(e) - LogToLin(0): exactly 0 at e = 0 (IEEE x - x). The compiler folds LogToLin(0)
  // with the host's exp2 and the device's run-time exp2 may differ by an ulp, so the black code
  // is decoded as 0 explicitly (as gpu/shaders/lib/lut_shaper.glsl does).
  float black = log_to_lin(0.0);
  float e = lin_to_log(x + black);
  return e == 0.0 ? 0.0 : log_to_lin(e) - black;
}

[numthreads(HDRC_LOCAL_SIZE_X, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {
  uint i = id.x;
  if (i >= uint(P.width * P.height)) return;
  float4 px = in_px[i];
  int d = P.output_device;
  out_px[i] = float4(round_trip(d, px.r), round_trip(d, px.g), round_trip(d, px.b), px.a);
}
