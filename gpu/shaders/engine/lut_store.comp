#version 450
#extension GL_GOOGLE_include_directive : require
// The engine's store pass after a LUT bake pass (gpu/vulkan_engine.cpp, Role::kStore; not a stage
// pass, so a --shader-dir port does not provide it): texel (r, g, b) of the N³ lattice, i → (i mod
// N, (i div N) mod N, i div N²), is read from the bake image, where the bake pass stored it as
// float32 (RGBA32F: bound as lut_3d / lut_2d, read with texelFetch, unfiltered and exact), and
// written with imageStore to the LUT image of the case's format (lut_store_3d for the volume
// layout, P.lut_layout 0; lut_store_2d at (r + N·b, g) for the unwrapped layout 1). The value
// stored is the float the bake pass stored, so the format's conversion gives the bits the bake
// pass's own imageStore would have given. Kept this small on purpose: llvmpipe compiles one
// variant of it per LUT format, layout and power-of-two-ness of N, in milliseconds, while the bake
// shader keeps one variant for all of them.
#include "hdrc/interface.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

#ifdef HDRC_DEVICE_MODEL_WORST
// The worst-case device (docs/precision.md, "The worst-case device"): the format conversion rounds
// toward zero, which Vulkan allows for both formats (spec, "Fixed-Point Data Conversions": float
// to UNORM picks either of the two nearest codes; float32 to float16 is correctly rounded with an
// implementation-defined rounding mode unless the entry point declares RoundingModeRTE). The value
// passed to imageStore is one the format holds (float16), or within 2^-14 codes of one (UNORM), so
// the conversion keeps it. NaN and ±Inf pass unchanged: the store's own NaN rules apply to them.

// float16 toward zero: a normal half keeps 10 of the 23 mantissa bits (truncating the bit
// pattern is rounding the magnitude down); below 2^-14 the subnormal halves are the multiples of
// 2^-24 (below 2^-14 = 6.103515625e-05); above the largest finite half, 65504 (toward zero never
// reaches Inf).
float toward_zero_half(float v) {
  float a = abs(v);
  if (isnan(v) || isinf(v)) return v;
  if (a >= 65504.0) return v < 0.0 ? -65504.0 : 65504.0;
  if (a < 6.103515625e-05) return (v < 0.0 ? -1.0 : 1.0) * ldexp(floor(ldexp(a, 24)), -24);
  return uintBitsToFloat(floatBitsToUint(v) & 0xffffe000u);
}

// UNORM with `levels` = 2^bits − 1 toward zero: code ⌊clamp(v, 0, 1)·levels⌋, computed exactly:
// fl(v·levels) may round up onto the next integer, which the exact test v·levels < code (with
// v·levels = v·(levels + 1) − v, v·(levels + 1) a power-of-two scaling and v·(levels + 1) − code
// exact by Sterbenz's lemma) takes back. The value stored is code · (1/levels), within an ulp of
// code/levels, which the round-to-nearest conversion maps back to the code.
float toward_zero_unorm(float v, float levels, float inv_levels) {
  if (isnan(v)) return v;
  float c = clamp(v, 0.0, 1.0);
  float code = floor(c * levels);
  precise float over = c * (levels + 1.0) - code;
  if (over < c) code -= 1.0;
  return code * inv_levels;
}

vec4 toward_zero(vec4 v) {
  if (P.lut_format == 1)
    return vec4(toward_zero_half(v.r), toward_zero_half(v.g), toward_zero_half(v.b),
                toward_zero_half(v.a));
  if (P.lut_format == 0)  // A2B10G10R10: 10-bit red, green and blue, 2-bit alpha
    return vec4(toward_zero_unorm(v.r, 1023.0, 1.0 / 1023.0),
                toward_zero_unorm(v.g, 1023.0, 1.0 / 1023.0),
                toward_zero_unorm(v.b, 1023.0, 1.0 / 1023.0), toward_zero_unorm(v.a, 3.0, 1.0 / 3.0));
  return v;  // RGBA32F: no conversion
}
#else
vec4 toward_zero(vec4 v) { return v; }
#endif

void main() {
  int n = P.lut_size;
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(n * n * n)) return;
  ivec3 texel = ivec3(int(i) % n, (int(i) / n) % n, int(i) / (n * n));
  if (P.lut_layout == 0) {
    imageStore(lut_store_3d, texel, toward_zero(texelFetch(lut_3d, texel, 0)));
  } else {
    ivec2 p = ivec2(texel.r + n * texel.b, texel.g);
    imageStore(lut_store_2d, p, toward_zero(texelFetch(lut_2d, p, 0)));
  }
}
