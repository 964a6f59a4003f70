// HLSL intrinsic behaviour that UE's shaders rely on, written out where GLSL leaves it undefined
// (reference: color/d3d_math.h; decisions in docs/ue55-decisions.md).
#ifndef HDRC_D3D_MATH_GLSL
#define HDRC_D3D_MATH_GLSL

float hdrc_nan() { return uintBitsToFloat(0x7fc00000u); }

// HLSL pow(x, y) = exp2(y * log2(x)): NaN for negative or NaN x and for pow(0, 0). GLSL pow is
// undefined for x < 0 and for x = 0, y <= 0.
float pow_d3d(float x, float y) {
  if (isnan(x) || x < 0.0 || (x == 0.0 && y == 0.0)) return hdrc_nan();
  if (x == 0.0) return y > 0.0 ? 0.0 : uintBitsToFloat(0x7f800000u);
  return pow(x, y);
}

// HLSL saturate(NaN) = 0 on D3D. GLSL clamp() with NaN is undefined.
float saturate_d3d(float x) { return isnan(x) ? 0.0 : clamp(x, 0.0, 1.0); }

// Clamp-to-edge addressing of a [0,1] coordinate; NaN propagates (no texel is defined for it).
float clamp_address(float x) { return isnan(x) ? x : clamp(x, 0.0, 1.0); }

// HLSL max/min are IEEE-754-2008 maxNum/minNum on D3D (DXIL FMax/FMin): a NaN operand yields the
// other operand (reference: std::fmax/std::fmin). GLSL max/min with NaN are undefined.
float max_d3d(float a, float b) { return isnan(a) ? b : (isnan(b) ? a : max(a, b)); }
float min_d3d(float a, float b) { return isnan(a) ? b : (isnan(b) ? a : min(a, b)); }
vec3 max_d3d(vec3 a, float b) { return vec3(max_d3d(a.x, b), max_d3d(a.y, b), max_d3d(a.z, b)); }
vec3 min_d3d(vec3 a, float b) { return vec3(min_d3d(a.x, b), min_d3d(a.y, b), min_d3d(a.z, b)); }

// HLSL clamp(x, lo, hi) = min(max(x, lo), hi) with maxNum/minNum: NaN -> lo.
float clamp_d3d(float x, float lo, float hi) { return min_d3d(max_d3d(x, lo), hi); }
vec3 clamp_d3d(vec3 x, float lo, float hi) { return min_d3d(max_d3d(x, lo), hi); }

// HLSL sign(): DXIL lowers it to (x > 0) - (x < 0), so sign(NaN) = 0 (GLSL sign(NaN) is undefined).
float sign_d3d(float x) { return float(int(x > 0.0) - int(x < 0.0)); }

// HLSL lerp(a, b, t) = a + t * (b - a) (GLSL mix is a * (1 - t) + b * t, which rounds differently).
float lerp_d3d(float a, float b, float t) { return a + t * (b - a); }
vec3 lerp_d3d(vec3 a, vec3 b, float t) { return a + t * (b - a); }

// HLSL log10(x): DXC lowers it to Log(x) * (ln 2 / ln 10) with DXIL Log = log2 and the constant
// rounded to float (HLOperationLower.cpp: TranslateLog10). GLSL has no log10; this is the same
// float32 formula, so the port has D3D's rounding, not a correctly rounded log10.
const float LOG10_OF_2 = 0.30102999566398120;  // ln 2 / ln 10
float log10_d3d(float x) { return log2(x) * LOG10_OF_2; }

// HLSL pow(10, y): DXC lowers pow(x, y) to Exp(y * Log(x)) (HLOperationLower.cpp: TranslatePow),
// DXIL Exp/Log being exp2/log2; for the literal base 10 Log(10) is a float constant.
const float LOG2_OF_10 = 3.32192809488736235;  // ln 10 / ln 2
float pow10_d3d(float y) { return exp2(y * LOG2_OF_10); }

// HLSL smoothstep(a, b, x) = t * t * (3 - 2 * t), t = saturate((x - a) / (b - a)); saturate(NaN)
// = 0 on D3D (GLSL smoothstep is undefined for a >= b and for NaN).
float smoothstep_d3d(float a, float b, float x) {
  float t = saturate_d3d((x - a) / (b - a));
  return t * t * (3.0 - 2.0 * t);
}

// HLSL exp(x) and log(x): DXC lowers them to Exp(x * log2(e)) and Log(x) * ln 2 with DXIL
// Exp/Log = exp2/log2 and the constants rounded to float (HLOperationLower.cpp: TranslateExp,
// TranslateLog). Written out so the port rounds as D3D does.
const float LOG2_OF_E = 1.44269504088896341;  // 1 / ln 2
const float LN_OF_2 = 0.69314718055994531;    // ln 2
float exp_d3d(float x) { return exp2(x * LOG2_OF_E); }
float log_d3d(float x) { return log2(x) * LN_OF_2; }

vec3 pow_d3d(vec3 x, float y) { return vec3(pow_d3d(x.x, y), pow_d3d(x.y, y), pow_d3d(x.z, y)); }

// HLSL sqrt(x): NaN for x < 0 or NaN (IEEE); GLSL sqrt of a negative is undefined.
float sqrt_d3d(float x) { return (isnan(x) || x < 0.0) ? hdrc_nan() : sqrt(x); }

// HLSL log2(x): −Inf at ±0, NaN for x < 0 or NaN, +Inf at +Inf (IEEE, DXIL Log); GLSL log2 is
// undefined for x <= 0.
float log2_d3d(float x) {
  if (isnan(x) || x < 0.0) return hdrc_nan();
  if (x == 0.0) return uintBitsToFloat(0xff800000u);
  return log2(x);
}

#endif
