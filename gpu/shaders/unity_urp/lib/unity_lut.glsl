// Unity URP's internal LUT in float32: the strip lattice (Color.hlsl GetLutStripValue), the storage
// rounding the bake does itself, ApplyLut2D through the interface's `lut_2d` sampler (linear
// filtering, clamp-to-edge) and the uber pass's ApplyColorGrading without the user LUT. Needs the
// generated interface included first. Reference: reference/unity_urp/unity_urp.h (lattice_code,
// quantize_texel, apply_lut_2d, apply_color_grading).
#ifndef HDRC_UNITY_LUT_GLSL
#define HDRC_UNITY_LUT_GLSL

#include "../../lib/d3d_math.glsl"
#include "unity_color.glsl"
#include "unity_tonemap.glsl"

// GetLutStripValue for texel (r, g, b): (r, g, b)/(H − 1) (Unity derives it from the texel centre's
// texcoord in float; the exact quotient differs from that by an ulp at most).
vec3 urp_lattice_code(ivec3 texel, int size) { return vec3(texel) / float(size - 1); }

// float → half, round to nearest even, as a D3D render target of R16G16B16A16_SFloat stores it.
// Vulkan leaves an image store's rounding to the implementation (lavapipe truncates), so the value
// is first rounded here to one a half holds exactly. Done by exact scaling: the half ulp of |v| is
// 2^(e − 10) for a normal half with exponent e ≥ −14 and 2^-24 below; ldexp by a power of two is
// exact (division and exp2 need not be), roundEven rounds half to even, and scaling back is exact.
// |v| rounding to 2^16 or more overflows to ±Inf; NaN and ±Inf pass through.
float urp_round_to_half(float v) {
  if (isnan(v) || isinf(v)) return v;
  float a = abs(v);
  int e = a < 6.103515625e-05 ? -14 : int((floatBitsToUint(a) >> 23) & 0xffu) - 127;
  float r = ldexp(roundEven(ldexp(v, 10 - e)), e - 10);
  if (abs(r) >= 65536.0) return v > 0.0 ? uintBitsToFloat(0x7f800000u) : uintBitsToFloat(0xff800000u);
  return r;
}

// float → 8-bit UNORM as the nearest k/255 (saturate; NaN → 0); the store's float → UNORM
// conversion (round to nearest, as Vulkan recommends and D3D requires) then yields k.
float urp_round_to_unorm8(float v) { return roundEven(saturate_d3d(v) * 255.0) / 255.0; }

// The value P.lut_format stores: 1 RGBA16F, 3 RGBA8 UNORM, otherwise unchanged.
vec3 urp_quantize_texel(vec3 v) {
  if (P.lut_format == 1)
    return vec3(urp_round_to_half(v.r), urp_round_to_half(v.g), urp_round_to_half(v.b));
  if (P.lut_format == 3)
    return vec3(urp_round_to_unorm8(v.r), urp_round_to_unorm8(v.g), urp_round_to_unorm8(v.b));
  return v;
}

// Color.hlsl: ApplyLut2D(tex, uvw, (1/W, 1/H, H − 1)): two hardware-bilinear taps one slice apart,
// lerped by the fractional blue slice (HLSL lerp).
vec3 urp_apply_lut_2d(vec3 uvw, vec3 scale_offset) {
  uvw.z *= scale_offset.z;
  float shift = floor(uvw.z);
  vec2 uv = uvw.xy * scale_offset.z * scale_offset.xy + scale_offset.xy * 0.5;
  uv.x += shift * scale_offset.y;
  return lerp_d3d(textureLod(lut_2d, uv, 0.0).rgb,
                  textureLod(lut_2d, uv + vec2(scale_offset.y, 0.0), 0.0).rgb, uvw.z - shift);
}

// Common.hlsl: ApplyColorGrading without the user LUT: post exposure; HDR grading: ApplyLut2D of
// saturate(LinearToLogC(x)); LDR grading: ApplyLut2D of ApplyTonemap(x).
vec3 urp_apply_color_grading(vec3 x) {
  x *= P.urp_post_exposure;
  vec3 uvw;
  if (P.urp_grading_mode == 1) {
    vec3 l = urp_logc_from_linear(x);
    uvw = vec3(saturate_d3d(l.r), saturate_d3d(l.g), saturate_d3d(l.b));
  } else {
    uvw = urp_uber_tonemap(x, P.urp_tonemap_mode);
  }
  return urp_apply_lut_2d(uvw, P.urp_lut_params.xyz);
}

#endif
