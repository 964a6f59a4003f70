// The ACES 1.3 single-stage tone scale (SSTS) and the unpacking of UE's tone-scale parameters, in
// float32. Sources: ACES.ush (5.0-era copy, chenyong2github/UnrealEngine, commit
// 09c29cbee980f5c5fbff6c93cf6132e5f4bcf97a): TsPoint, TsParams, M1, ssts; TonemapCommon.ush 5.5
// (izzy2lost/UnrealEngineUWP, commit aff11acf0c218535669021f6e646b3bcf6ad94a5):
// FACESTonemapParams, ComputeACESTonemapParams. Reference: reference/ue/aces/aces_output.{h,cpp}
// (ssts, spline_half, compute_aces_tonemap_params). Spec §5.2.
//
// The parameters are computed on the CPU (RenderCore.cpp: ConfigureACESTonemapParams, emulated in
// reference/ue/aces/aces_params.cpp) and reach the shader through the parameter block `P`
// (aces_min_max, aces_mid, aces_coefs_low_0/high_0, aces_coefs_low_4/high_4); a shader including
// aces_tonemap_params_from_block() must include "hdrc/interface.glsl" first.
#ifndef HDRC_ACES_TONESCALE_GLSL
#define HDRC_ACES_TONESCALE_GLSL

#include "aces_common.glsl"

// ACES.ush: TsPoint / TsParams. coefsLow/coefsHigh have 6 entries, [5] = [4], so that ssts's
// j + 2 stays in range when knot_coord reaches 3.
struct TsPoint {
  float x;      // ACES (AP1, after the RRT sweeteners)
  float y;      // nits
  float slope;  // d log10(y) / d log10(x)
};

struct TsParams {
  TsPoint Min;
  TsPoint Mid;
  TsPoint Max;
  float coefsLow[6];   // log10 nits
  float coefsHigh[6];  // log10 nits
};

// TonemapCommon.ush: FACESTonemapParams.
struct FACESTonemapParams {
  TsParams AcesParams;
  float SceneColorMultiplier;
  float GamutCompression;  // clamped to [0, 1] on the CPU
};

// TonemapCommon.ush: ComputeACESTonemapParams. Min.slope and Max.slope are 0, Mid.slope is
// ACESMidData.z; coefs[4] and coefs[5] are both ACESCoefs*_4. ACESMidData.w is not read.
FACESTonemapParams compute_aces_tonemap_params(vec4 min_max_data, vec4 mid_data, vec4 coefs_low_0,
                                               vec4 coefs_high_0, float coefs_low_4,
                                               float coefs_high_4, float scene_color_multiplier,
                                               float gamut_compression) {
  FACESTonemapParams o;
  o.AcesParams.Min = TsPoint(min_max_data.x, min_max_data.y, 0.0);
  o.AcesParams.Mid = TsPoint(mid_data.x, mid_data.y, mid_data.z);
  o.AcesParams.Max = TsPoint(min_max_data.z, min_max_data.w, 0.0);
  o.AcesParams.coefsLow = float[6](coefs_low_0.x, coefs_low_0.y, coefs_low_0.z, coefs_low_0.w,
                                   coefs_low_4, coefs_low_4);
  o.AcesParams.coefsHigh = float[6](coefs_high_0.x, coefs_high_0.y, coefs_high_0.z,
                                    coefs_high_0.w, coefs_high_4, coefs_high_4);
  o.SceneColorMultiplier = scene_color_multiplier;
  o.GamutCompression = gamut_compression;
  return o;
}

// The parameters of the current case, from the parameter block (as CombineLUTs passes its
// ACESMinMaxData, ACESMidData, ... uniforms to ComputeACESTonemapParams).
FACESTonemapParams aces_tonemap_params_from_block() {
  return compute_aces_tonemap_params(P.aces_min_max, P.aces_mid, P.aces_coefs_low_0,
                                     P.aces_coefs_high_0, P.aces_coefs_low_4, P.aces_coefs_high_4,
                                     P.aces_scene_color_multiplier, P.aces_gamut_compression);
}

// ACES.ush: M1, the monomial-to-basis matrix of the quadratic B-spline, applied as mul(cf, M1)
// (row vector times matrix), i.e. GLSL `M1 * cf` with the row-major literal (aces_common.glsl).
const mat3 M1 = mat3(0.5, -1.0, 0.5,  //
                     -1.0, 1.0, 0.5,  //
                     0.5, 0.0, 0.0);

// ACES.ush: ssts — ACES (AP1) in, nits out, per channel. log10 and pow(10, .) are D3D's float32
// lowerings (log10_d3d, pow10_d3d); the reference evaluates the same formula with double log10.
// max(x, 1e-10) is maxNum, so NaN maps to Min.y like any x <= Min.x.
float ssts(float x, TsParams C) {
  const int N_KNOTS_LOW = 4;
  const int N_KNOTS_HIGH = 4;

  float logx = log10_d3d(max_d3d(x, 1e-10));
  float log_min_x = log10_d3d(C.Min.x);
  float log_mid_x = log10_d3d(C.Mid.x);
  float log_max_x = log10_d3d(C.Max.x);
  float logy;

  if (logx <= log_min_x) {
    logy = logx * C.Min.slope + (log10_d3d(C.Min.y) - C.Min.slope * log_min_x);
  } else if ((logx > log_min_x) && (logx < log_mid_x)) {
    float knot_coord = float(N_KNOTS_LOW - 1) * (logx - log_min_x) / (log_mid_x - log_min_x);
    int j = int(knot_coord);
    float t = knot_coord - float(j);
    vec3 cf = vec3(C.coefsLow[j], C.coefsLow[j + 1], C.coefsLow[j + 2]);
    vec3 monomials = vec3(t * t, t, 1.0);
    logy = dot(monomials, M1 * cf);
  } else if ((logx >= log_mid_x) && (logx < log_max_x)) {
    float knot_coord = float(N_KNOTS_HIGH - 1) * (logx - log_mid_x) / (log_max_x - log_mid_x);
    int j = int(knot_coord);
    float t = knot_coord - float(j);
    vec3 cf = vec3(C.coefsHigh[j], C.coefsHigh[j + 1], C.coefsHigh[j + 2]);
    vec3 monomials = vec3(t * t, t, 1.0);
    logy = dot(monomials, M1 * cf);
  } else {
    logy = logx * C.Max.slope + (log10_d3d(C.Max.y) - C.Max.slope * log_max_x);
  }
  return pow10_d3d(logy);  // ACES.ush: pow10(x) = pow(10, x)
}

vec3 ssts_f3(vec3 x, TsParams C) { return vec3(ssts(x.r, C), ssts(x.g, C), ssts(x.b, C)); }

#endif
