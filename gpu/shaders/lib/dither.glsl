// The Tonemap pass's quantisation dither (docs/spec/ue55.md §6.1 step 10), in float32 as UE's shader computes
// it. Reference: reference/ue/tonemap.cpp (dither_grain, dither_image).
// UE: PostProcessTonemap.usf (5.5) GrainFromUV, TonemapCommonVS (GrainUV.zw = TexCoord +
// GrainRandomFull.xy), MainCS (UV = (DispatchThreadId + 0.5) * Color_ExtentInverse) and the end of
// TonemapCommonPS (uniform → triangular grain, OutColor.rgb += grain · BackbufferQuantizationDithering).
// UE declares these values `half`; desktop D3D evaluates half as float (docs/ue55-decisions.md 14.7).
#ifndef HDRC_DITHER_GLSL
#define HDRC_DITHER_GLSL

// GrainUV.zw of pixel (x, y) in a width × height viewport: the compute path's texel-centre UV
// (a multiply by the float inverse extent, as MainCS does) plus the frame's Halton offset.
vec2 dither_grain_uv(uvec2 pixel, ivec2 size, vec2 grain_random) {
  precise vec2 uv = (vec2(pixel) + 0.5) * (1.0 / vec2(size));
  precise vec2 grain_uv = uv + grain_random;
  return grain_uv;
}

// GrainFromUV's two hash constants (PostProcessTonemap.usf, GrainFromUV: 543.31f and 493013.0f),
// named so that the planted-constant sweep enumerates them (docs/constant-sweep.md); the shader's
// arithmetic is the literals' (a const float folds to the same SPIR-V constant).
const float DITHER_GRAIN_V_SCALE = 543.31;
const float DITHER_GRAIN_SIN_SCALE = 493013.0;

// GrainFromUV: the uniform grain frac(sin(u + v · 543.31) · 493013) in [0, 1). `precise` keeps
// the multiply-adds unfused as the reference evaluates them; the hash multiplies sin's last-bit
// differences by ~5e5, so a driver's sin that differs from the host's by one ulp changes the grain
// (docs/precision.md).
float dither_grain(vec2 grain_uv) {
  precise float a = grain_uv.x + grain_uv.y * DITHER_GRAIN_V_SCALE;
  precise float g = sin(a) * DITHER_GRAIN_SIN_SCALE;
  return g - floor(g);  // HLSL frac
}

// The triangular grain in [-1, 1] from the uniform one. UE takes the sign as
// clamp(n · +Inf, -1, 1): ±1 for n ≠ 0; at n = 0 the product is NaN, which D3D's clamp turns into
// -1, giving s - s·sqrt(1) = 0 (docs/ue55-decisions.md D6.1). GLSL's clamp(NaN) is undefined, so
// the sign is written out.
float dither_triangular(float uniform_grain) {
  float n = uniform_grain * 2.0 - 1.0;
  if (n == 0.0) return 0.0;
  float s = n > 0.0 ? 1.0 : -1.0;
  return s - s * sqrt(clamp(1.0 - abs(n), 0.0, 1.0));
}

// OutColor.rgb += TriangularGrain · BackbufferQuantizationDithering.
vec3 apply_dither(vec3 rgb, uvec2 pixel, ivec2 size, vec2 grain_random, float amount) {
  float grain = dither_triangular(dither_grain(dither_grain_uv(pixel, size, grain_random)));
  return rgb + grain * amount;
}

#endif
