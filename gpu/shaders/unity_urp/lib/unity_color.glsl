// Unity URP colour utilities in float32 (desktop: URP's half/real are fp32): ALEXA LogC (EI 1000,
// fast form), ACEScc, the ACES and LMS matrices, luminance, HSV, RotateHue, SoftLight. Each
// function mirrors one of reference/unity_urp/unity_urp.h, which cites the Unity source
// (Color.hlsl, ACES.hlsl in com.unity.render-pipelines.core/ShaderLibrary) beside every formula;
// gpu/unity_urp_shader_test.cpp reads every constant back and compares each function with it.
//
// Matrices: `const mat3 M = mat3(HLSL row-major literal list)` holds M transposed (GLSL mat3 takes
// columns), so HLSL mul(M, v) is `v * M` here.
#ifndef HDRC_UNITY_COLOR_GLSL
#define HDRC_UNITY_COLOR_GLSL

#include "../../lib/d3d_math.glsl"

// Color.hlsl: ParamsLogC LogC (ARRI LogC3 EI 1000 as Unity writes it; cut, e, f are used only by
// the _Precise variants, which URP does not compile: USE_PRECISE_LOGC 0).
const float URP_LOGC_A = 5.555556;
const float URP_LOGC_B = 0.047996;
const float URP_LOGC_C = 0.244161;
const float URP_LOGC_D = 0.386036;

// Color.hlsl: LinearToLogC (fast): c·log10(max(a·x + b, 0)) + d; HLSL log10 as D3D lowers it
// (Log(x)·(ln 2/ln 10), d3d_math.glsl) with IEEE log2 at 0 (−Inf: GLSL leaves log2(0) undefined)
// and maxNum (NaN → 0 → −Inf).
float urp_logc_from_linear(float x) {
  return URP_LOGC_C * (log2_d3d(max_d3d(URP_LOGC_A * x + URP_LOGC_B, 0.0)) * LOG10_OF_2) +
         URP_LOGC_D;
}
vec3 urp_logc_from_linear(vec3 x) {
  return vec3(urp_logc_from_linear(x.r), urp_logc_from_linear(x.g), urp_logc_from_linear(x.b));
}

// Color.hlsl: LogCToLinear (fast): (10^((x − d)/c) − b)/a, pow(10, ·) as D3D lowers it.
float urp_linear_from_logc(float x) {
  return (pow10_d3d((x - URP_LOGC_D) / URP_LOGC_C) - URP_LOGC_B) / URP_LOGC_A;
}
vec3 urp_linear_from_logc(vec3 x) {
  return vec3(urp_linear_from_logc(x.r), urp_linear_from_logc(x.g), urp_linear_from_logc(x.b));
}

// ACES.hlsl: ACEScc_MIDGRAY, HALF_MAX (Common.hlsl).
const float URP_ACESCC_MIDGRAY = 0.4135884;
const float URP_HALF_MAX = 65504.0;
// ACES.hlsl: ACES_to_ACEScc(half3) thresholds (2^-15 and 2^-16 as written) and constants.
const float URP_ACESCC_LOW = 0.00003051757;
const float URP_ACESCC_OFFSET = 0.00001525878;
// ACES.hlsl: ACEScc_to_ACES(half): (9.72 − 15)/17.52 as written, and the HALF_MAX threshold
// (log2(HALF_MAX) + 9.72)/17.52 (the reference's double value rounded to float).
const float URP_ACESCC_LOW_CODE = -0.3013698630;
const float URP_ACESCC_MAX_CODE = 1.46799636;

// ACES_to_ACEScc(half3): x = clamp(x, 0, HALF_MAX); below 2^-15 (log2(2^-16 + x/2) + 9.72)/17.52,
// else (log2 x + 9.72)/17.52.
float urp_acescc_from_linear(float x) {
  x = clamp_d3d(x, 0.0, URP_HALF_MAX);
  return x < URP_ACESCC_LOW ? (log2(URP_ACESCC_OFFSET + x * 0.5) + 9.72) / 17.52
                            : (log2(x) + 9.72) / 17.52;
}

// ACEScc_to_ACES(half).
float urp_linear_from_acescc(float y) {
  if (y < URP_ACESCC_LOW_CODE) return (exp2(y * 17.52 - 9.72) - exp2(-16.0)) * 2.0;
  if (y < URP_ACESCC_MAX_CODE) return exp2(y * 17.52 - 9.72);
  return URP_HALF_MAX;
}

// ACES.hlsl matrices (HLSL row-major literal lists; `v * M` = mul(M, v)).
const mat3 URP_SRGB_TO_AP0 = mat3(0.4397010, 0.3829780, 0.1773350,
                                  0.0897923, 0.8134230, 0.0967616,
                                  0.0175440, 0.1115440, 0.8707040);
const mat3 URP_AP0_TO_AP1 = mat3(1.4514393161, -0.2365107469, -0.2149285693,
                                 -0.0765537734, 1.1762296998, -0.0996759264,
                                 0.0083161484, -0.0060324498, 0.9977163014);
const mat3 URP_AP1_TO_AP0 = mat3(0.6954522414, 0.1406786965, 0.1638690622,
                                 0.0447945634, 0.8596711185, 0.0955343182,
                                 -0.0055258826, 0.0040252103, 1.0015006723);
const mat3 URP_AP1_TO_XYZ = mat3(0.6624541811, 0.1340042065, 0.1561876870,
                                 0.2722287168, 0.6740817658, 0.0536895174,
                                 -0.0055746495, 0.0040607335, 1.0103391003);
const mat3 URP_XYZ_TO_AP1 = mat3(1.6410233797, -0.3248032942, -0.2364246952,
                                 -0.6636628587, 1.6153315917, 0.0167563477,
                                 0.0117218943, -0.0082844420, 0.9883948585);
const mat3 URP_XYZ_TO_REC709 = mat3(3.2409699419, -1.5373831776, -0.4986107603,
                                    -0.9692436363, 1.8759675015, 0.0415550574,
                                    0.0556300797, -0.2039769589, 1.0569715142);
const mat3 URP_D60_TO_D65_CAT = mat3(0.98722400, -0.00611327, 0.0159533,
                                     -0.00759836, 1.00186000, 0.0053302,
                                     0.00307257, -0.00509595, 1.0816800);
// ACES.hlsl: AP1_RGB2Y.
const vec3 URP_AP1_RGB_TO_Y = vec3(0.272229, 0.674082, 0.0536895);

// Color.hlsl: LinearToLMS (LIN_2_LMS_MAT) and LMSToLinear (LMS_2_LIN_MAT).
const mat3 URP_LINEAR_TO_LMS = mat3(3.90405e-1, 5.49941e-1, 8.92632e-3,
                                    7.08416e-2, 9.63172e-1, 1.35775e-3,
                                    2.31082e-2, 1.28021e-1, 9.36245e-1);
const mat3 URP_LMS_TO_LINEAR = mat3(2.85847e+0, -1.62879e+0, -2.48910e-2,
                                    -2.10182e-1, 1.15820e+0, 3.24281e-4,
                                    -4.18120e-2, -1.18169e-1, 1.06867e+0);
// Color.hlsl: Luminance.
const vec3 URP_REC709_RGB_TO_Y = vec3(0.2126729, 0.7151522, 0.0721750);

float urp_luminance_rec709(vec3 c) { return dot(c, URP_REC709_RGB_TO_Y); }
float urp_luminance_ap1(vec3 c) { return dot(c, URP_AP1_RGB_TO_Y); }

// Color.hlsl: RgbToHsv, ties as HLSL step(a, x) = (x >= a); ε = 1e-4.
const float URP_HSV_EPSILON = 1.0e-4;
vec3 urp_hsv_from_rgb(vec3 c) {
  vec4 p = c.g >= c.b ? vec4(c.g, c.b, 0.0, -1.0 / 3.0) : vec4(c.b, c.g, -1.0, 2.0 / 3.0);
  vec4 q = c.r >= p.x ? vec4(c.r, p.y, p.z, p.x) : vec4(p.x, p.y, p.w, c.r);
  float d = q.x - min(q.w, q.y);
  return vec3(abs(q.z + (q.w - q.y) / (6.0 * d + URP_HSV_EPSILON)), d / (q.x + URP_HSV_EPSILON),
              q.x);
}

// Color.hlsl: HsvToRgb: v · lerp(1, saturate(|frac(h + K)·6 − 3| − 1), s), K = (1, 2/3, 1/3).
vec3 urp_rgb_from_hsv(vec3 hsv) {
  vec3 p = abs(fract(hsv.xxx + vec3(1.0, 2.0 / 3.0, 1.0 / 3.0)) * 6.0 - 3.0);
  return hsv.z * lerp_d3d(vec3(1.0), clamp(p - 1.0, 0.0, 1.0), hsv.y);
}

// Color.hlsl: RotateHue(value, low, hi).
float urp_rotate_hue(float value, float low, float hi) {
  return value < low ? value + hi : (value > hi ? value - hi : value);
}

// Color.hlsl: SoftLight, per channel, branch by step(0.5, blend).
float urp_soft_light(float base, float blend) {
  float r1 = 2.0 * base * blend + base * base * (1.0 - 2.0 * blend);
  float r2 = sqrt(base) * (2.0 * blend - 1.0) + 2.0 * base * (1.0 - blend);
  return blend >= 0.5 ? r2 : r1;
}

#endif
