#version 450
#extension GL_GOOGLE_include_directive : require
// Stage "combine_luts": CombineLUTs bakes the LUT, one invocation per texel. Texel i of the N³
// dispatch is (r, g, b) with r fastest, then g, then b (N = P.lut_size). The stored value,
// OutDeviceColor / 1.05, goes to the 3-D image for the volume layout (P.lut_layout 0) or to texel
// (r + N·b, g) of the N² × N image for the unwrapped layout (1); the image's format (A2B10G10R10
// UNORM, RGBA16F or RGBA32F) does the storage rounding. Reference: reference/ue/combine_luts.cpp
// (bake_lut).
#include "hdrc/interface.glsl"
#include "../lib/combine_luts.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

// float → half with round-to-nearest-even, as D3D converts a float stored to an R16G16B16A16_FLOAT
// target (D3D11.3 functional spec 3.2.3.4: float32 → float16 rounds to nearest even). Vulkan
// leaves the rounding of an image store implementation-defined and lavapipe truncates, so the
// value is rounded here to one a half holds exactly, which any store keeps as it is. Reference:
// quantize_lut_value (Imath::half, round to nearest even). Written with integer arithmetic:
// packHalf2x16's rounding is implementation-defined too.
float round_to_half_rne(float v) {
  if (isnan(v) || isinf(v)) return v;
  float a = abs(v);
  if (a >= 65520.0) return v > 0.0 ? uintBitsToFloat(0x7f800000u) : uintBitsToFloat(0xff800000u);
  if (a < 6.103515625e-05) {
    // Half subnormals: multiples of 2^-24 (exact scalings, roundEven is round-half-even).
    return roundEven(v * 16777216.0) * 5.9604644775390625e-08;
  }
  // Normal halves keep 10 of float's 23 mantissa bits: add half of the dropped part (less one,
  // plus the kept part's lowest bit: ties go to even) and clear the 13 dropped bits.
  uint b = floatBitsToUint(v);
  b += 0x0fffu + ((b >> 13) & 1u);
  return uintBitsToFloat(b & 0xffffe000u);
}

void main() {
  int n = P.lut_size;
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(n * n * n)) return;
  ivec3 texel = ivec3(int(i) % n, (int(i) / n) % n, int(i) / (n * n));
  vec3 stored = combine_luts_texel(lut_lattice_coordinate(P.lut_layout, n, texel));
  // D3D's float → UNORM conversion turns NaN into 0 (D3D11.3 functional spec, 3.2.3.6); Vulkan
  // leaves NaN undefined (lavapipe stores 1). The NaN texels are the PQ / gamma encodes of
  // negative values (docs/ue55-decisions.md D-NF), so for the 10-bit format they are zeroed here.
  // The half and float formats keep NaN on both APIs.
  if (P.lut_format == 1) {
    stored = vec3(round_to_half_rne(stored.r), round_to_half_rne(stored.g),
                  round_to_half_rne(stored.b));
  }
  if (P.lut_format == 0) {
    stored = vec3(isnan(stored.r) ? 0.0 : stored.r, isnan(stored.g) ? 0.0 : stored.g,
                  isnan(stored.b) ? 0.0 : stored.b);
  }
  if (P.lut_layout == 0) {
    imageStore(lut_store_3d, texel, vec4(stored, 0.0));
  } else {
    imageStore(lut_store_2d, ivec2(texel.r + n * texel.b, texel.g), vec4(stored, 0.0));
  }
}
