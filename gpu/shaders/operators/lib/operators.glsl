// The classic tone-mapping operators (pipeline `operators`) in float32, one function per operator.
// Reference (double, with the citations of every formula and constant):
// reference/operators/operators.h. Needs the generated interface included first (P.op_*, and
// P.film_* for UE's FilmToneMap, which is ../../lib/film_tonemap.glsl, called unchanged).
//
// The reference evaluates each published formula in IEEE double with HLSL semantics (NaN and ±Inf
// included). GLSL leaves division by zero, ∞/∞, and division by |y| > 2^126 undefined, and a float
// product can overflow where the reference's double does not, so every function here:
//  * answers a NaN or ±Inf input explicitly with the reference's value;
//  * takes its input scale (exposure, bias, pre-scale) as an argument and, above |y| = 1,
//    evaluates the rational in 1/y (numerator and denominator divided by y or y²), so a finite
//    input whose scaled value overflows float32 still gets the curve's value there (1/y taken as
//    0 above 2^126, which moves no result by a float ulp);
//  * spells out a zero denominator (a pole at a negative input) as IEEE's ±Inf or NaN.
#ifndef HDRC_OPERATORS_GLSL
#define HDRC_OPERATORS_GLSL

#include "../../lib/d3d_math.glsl"
#include "../../lib/film_tonemap.glsl"
#include "../../lib/matrix.glsl"

// Operator ids (reference: operators::Operator; P.op_operator).
const int OP_REINHARD = 0;
const int OP_REINHARD_WHITE = 1;
const int OP_HABLE = 2;
const int OP_ACES_NARKOWICZ = 3;
const int OP_UNITY_NEUTRAL = 4;
const int OP_UE_FILMIC = 5;

// Narkowicz 2016's fit (reference: operators::kNarkowicz).
const float OP_NARKOWICZ_A = 2.51;
const float OP_NARKOWICZ_B = 0.03;
const float OP_NARKOWICZ_C = 2.43;
const float OP_NARKOWICZ_D = 0.59;
const float OP_NARKOWICZ_E = 0.14;

// Unity's Color.hlsl: NeutralTonemap constants (reference: operators::kUnityNeutralCurve,
// kUnityNeutralWhiteLevel, kUnityNeutralWhiteClip).
const float OP_UNITY_NEUTRAL_A = 0.2;
const float OP_UNITY_NEUTRAL_B = 0.29;
const float OP_UNITY_NEUTRAL_C = 0.24;
const float OP_UNITY_NEUTRAL_D = 0.272;
const float OP_UNITY_NEUTRAL_E = 0.02;
const float OP_UNITY_NEUTRAL_F = 0.3;
const float OP_UNITY_NEUTRAL_WHITE_LEVEL = 5.3;
const float OP_UNITY_NEUTRAL_WHITE_CLIP = 1.0;

// Above this |y|, 1/y is below float32's normal range; GLSL's division is only defined (2.5 ulp)
// for divisors up to 2^126.
const float OP_RECIP_LIMIT = 8.50705917e37;  // 2^126

float op_inf() { return uintBitsToFloat(0x7f800000u); }

// IEEE num / (+0): ±Inf by the numerator's sign, NaN for 0 or NaN (x / 0 is undefined in GLSL).
float op_div_by_zero(float num) {
  if (isnan(num) || num == 0.0) return hdrc_nan();
  return num > 0.0 ? op_inf() : -op_inf();
}

// 1 / y for |y| > 1, with 0 for |y| > 2^126 (and for the ±Inf of an overflowed scaling).
float op_recip_large(float y) { return abs(y) > OP_RECIP_LIMIT ? 0.0 : 1.0 / y; }

// x / (1 + x) of y = scale · x (Reinhard eq. 3); NaN for NaN and ±Inf (∞/∞).
float op_reinhard(float x, float scale) {
  if (isnan(x) || isinf(x)) return hdrc_nan();
  float y = scale * x;
  if (abs(y) <= 1.0) {
    float den = 1.0 + y;
    return den == 0.0 ? op_div_by_zero(y) : y / den;  // y = −1: −Inf
  }
  return 1.0 / (1.0 + op_recip_large(y));
}

// y (1 + y / Lw²) / (1 + y), y = scale · x (Reinhard eq. 4): 1 at y = Lw; NaN for NaN and ±Inf.
float op_reinhard_white(float x, float scale, float white) {
  if (isnan(x) || isinf(x)) return hdrc_nan();
  float y = scale * x;
  float t = 1.0 + (scale / (white * white)) * x;  // 1 + y / Lw²
  if (abs(y) <= 1.0) {
    float den = 1.0 + y;
    return den == 0.0 ? op_div_by_zero(y * t) : y * t / den;
  }
  return t / (1.0 + op_recip_large(y));
}

// The rational curve of Hable and Unity's Neutral (reference: operators::rational_curve):
// f(y) = (y (A y + C B) + D E) / (y (A y + B) + D F) − E / F, for y = scale · x with x finite.
struct OpRational {
  float a, b, c, d, e, f;
};

float op_rational(float x, float scale, OpRational k) {
  float y = scale * x;
  float num, den;
  if (abs(y) <= 1.0) {
    num = y * (k.a * y + k.c * k.b) + k.d * k.e;
    den = y * (k.a * y + k.b) + k.d * k.f;
  } else {
    float r = op_recip_large(y);  // both divided by y²
    num = k.a + r * (k.c * k.b + r * (k.d * k.e));
    den = k.a + r * (k.b + r * (k.d * k.f));
  }
  float q = den == 0.0 ? op_div_by_zero(num) : num / den;
  return q - k.e / k.f;
}

OpRational op_hable_curve() {
  return OpRational(P.op_hable_a, P.op_hable_b, P.op_hable_c, P.op_hable_d, P.op_hable_e,
                    P.op_hable_f);
}

// Hable: f(bias · scale · x) / f(W); NaN for NaN and ±Inf (f(∞) is ∞/∞).
float op_hable(float x, float scale) {
  if (isnan(x) || isinf(x)) return hdrc_nan();
  OpRational k = op_hable_curve();
  return op_rational(x, P.op_hable_exposure_bias * scale, k) / op_rational(P.op_hable_w, 1.0, k);
}

// Narkowicz: saturate(y (a y + b) / (y (c y + d) + e)), y = scale · x. ±Inf give ∞/∞ = NaN and
// NaN gives NaN, which saturate turns into 0. The denominator has no real root.
float op_aces_narkowicz(float x, float scale) {
  if (isnan(x) || isinf(x)) return 0.0;
  float y = scale * x;
  float q;
  if (abs(y) <= 1.0) {
    q = (y * (OP_NARKOWICZ_A * y + OP_NARKOWICZ_B)) /
        (y * (OP_NARKOWICZ_C * y + OP_NARKOWICZ_D) + OP_NARKOWICZ_E);
  } else {
    float r = op_recip_large(y);  // divided by y²
    q = (OP_NARKOWICZ_A + r * OP_NARKOWICZ_B) /
        (OP_NARKOWICZ_C + r * (OP_NARKOWICZ_D + r * OP_NARKOWICZ_E));
  }
  return saturate_d3d(q);
}

// Unity's NeutralTonemap of scale · x: max(·, 0) (maxNum: NaN → 0), ws = 1 / N(whiteLevel),
// N(x · ws) · ws / whiteClip. +Inf gives NaN (N(∞) is ∞/∞); −Inf gives 0.
float op_unity_neutral(float x, float scale) {
  x = max_d3d(x, 0.0);
  if (isinf(x)) return hdrc_nan();
  OpRational k = OpRational(OP_UNITY_NEUTRAL_A, OP_UNITY_NEUTRAL_B, OP_UNITY_NEUTRAL_C,
                            OP_UNITY_NEUTRAL_D, OP_UNITY_NEUTRAL_E, OP_UNITY_NEUTRAL_F);
  float white_scale = 1.0 / op_rational(OP_UNITY_NEUTRAL_WHITE_LEVEL, 1.0, k);
  return op_rational(x, scale * white_scale, k) * white_scale / OP_UNITY_NEUTRAL_WHITE_CLIP;
}

// UE's FilmToneMap on Rec.709: max(0, FromAP1 · FilmToneMap(ToAP1 · scale · rgb)) with the sRGB
// working colour space's matrices (P.op_rec709_to_ap1, P.op_ap1_to_rec709) and P.film_*.
// Float32 range: FilmToneMap's rgb_2_yc squares AP0 values, so scaled inputs above about 1.8e19
// overflow here (the result is 0) where the reference reaches the shoulder, 1 + FilmWhiteClip.
vec3 op_ue_filmic(vec3 rgb, float scale) {
  vec3 ap1 = mul_rows(P.op_rec709_to_ap1, scale * rgb);
  return max_d3d(mul_rows(P.op_ap1_to_rec709, film_tone_map(ap1)), 0.0);
}

// The stage: the operator P.op_operator on P.op_exposure · scene_linear (NaN for an unknown id).
vec3 operators_apply(vec3 scene_linear) {
  float s = P.op_exposure;
  vec3 c = scene_linear;
  switch (P.op_operator) {
    case OP_REINHARD:
      return vec3(op_reinhard(c.r, s), op_reinhard(c.g, s), op_reinhard(c.b, s));
    case OP_REINHARD_WHITE: {
      float w = P.op_white_point;
      return vec3(op_reinhard_white(c.r, s, w), op_reinhard_white(c.g, s, w),
                  op_reinhard_white(c.b, s, w));
    }
    case OP_HABLE:
      return vec3(op_hable(c.r, s), op_hable(c.g, s), op_hable(c.b, s));
    case OP_ACES_NARKOWICZ: {
      float k = s * P.op_narkowicz_pre_scale;
      return vec3(op_aces_narkowicz(c.r, k), op_aces_narkowicz(c.g, k),
                  op_aces_narkowicz(c.b, k));
    }
    case OP_UNITY_NEUTRAL:
      return vec3(op_unity_neutral(c.r, s), op_unity_neutral(c.g, s), op_unity_neutral(c.b, s));
    case OP_UE_FILMIC:
      return op_ue_filmic(c, s);
  }
  return vec3(hdrc_nan());
}

#endif
