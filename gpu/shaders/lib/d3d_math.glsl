// HLSL intrinsic behaviour that UE's shaders rely on, written out where GLSL leaves it undefined
// (reference: reference/color/d3d_math.h; decisions in docs/ue55-decisions.md).
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

#endif
