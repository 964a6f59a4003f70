// The tonemapper's lookup into the baked LUT: PostProcessTonemap.usf ColorLookupTable (docs/spec/ue55.md §6.1
// step 7): shaper encode, UVW = enc · LUTScale + LUTOffset, a hardware-filtered sample of the
// volume LUT (Texture3DSample) or of the unwrapped 2-D LUT (PostProcessCommon.ush
// UnwrappedTexture3DSample), times 1.05. The samplers are the interface's lut_3d / lut_2d (linear
// filtering, clamp-to-edge), bound to the image CombineLUTs wrote. Reference:
// reference/ue/combine_luts.cpp sample_lut.
#ifndef HDRC_LUT_SAMPLE_GLSL
#define HDRC_LUT_SAMPLE_GLSL

#include "d3d_math.glsl"
#include "lut_shaper.glsl"
#include "tonemap_variant.glsl"

// LUTScale = (N − 1)/N and LUTOffset = 0.5/N, which UE's C++ computes in float
// (PostProcessTonemap.cpp); both are exact in float32 for N a power of two.
vec3 lut_uvw(vec3 encoded, float size) { return encoded * ((size - 1.0) / size) + 0.5 / size; }

// Texture3DSample: the hardware's trilinear filter. textureLod at level 0: a compute shader has
// no implicit derivatives (UE's Texture3DSample also reads the only level).
vec3 sample_lut_volume(vec3 uvw) { return textureLod(lut_3d, uvw, 0.0).rgb; }

// UnwrappedTexture3DSample(Texture, Sampler, UVW, Size, InvSize): the N slices side by side in an
// N² × N texture; two bilinear taps in neighbouring slices, blended by the fractional slice
// (lerp = a + t·(b − a) as HLSL's lerp).
vec3 sample_lut_unwrapped(vec3 uvw, float size) {
  float inv_size = 1.0 / size;
  float int_w = floor(uvw.z * size - 0.5);
  float frac_w = uvw.z * size - 0.5 - int_w;
  float u = (uvw.x + int_w) * inv_size;
  vec3 rg0 = textureLod(lut_2d, vec2(u, uvw.y), 0.0).rgb;
  vec3 rg1 = textureLod(lut_2d, vec2(u + inv_size, uvw.y), 0.0).rgb;
  return lerp_d3d(rg0, rg1, frac_w);
}

// The lookup of an encoded colour, times LUTMax: UE 5.5's 1.05 (CombineLUTs stored OutDeviceColor
// / 1.05, docs/spec/ue55.md §4.12), UE 5.8's GetTonemappingMax (1.05 or 1).
vec3 color_lookup_encoded(vec3 encoded, float lut_max) {
  // A NaN coordinate (PQ of a negative or infinite channel: no max(0, ·) in 5.5, D6.1) selects no
  // defined texel on any API; GLSL and D3D both leave the fetched value implementation-defined.
  // The port returns NaN in every channel, as the reference does (docs/ue55-decisions.md, D-NF).
  if (any(isnan(encoded))) return vec3(hdrc_nan());
  float size = float(P.lut_size);
  vec3 uvw = lut_uvw(encoded, size);
  vec3 s = tonemap_lut_layout() == 0 ? sample_lut_volume(uvw) : sample_lut_unwrapped(uvw, size);
  return s * lut_max;
}

// UE 5.5: OutDeviceColor = sample · 1.05.
vec3 color_lookup_table(vec3 final_linear) {
  return color_lookup_encoded(lut_encode(P.output_device, final_linear), 1.05);
}

#endif
