// UE 5.5's user colour-grading LUT blend in CombineLUTs (docs/ue55-lut-blend-spec.md §3):
// PostProcessCombineLUTs.usf: CombineLUTsCommon's `#if BLENDCOUNT > 1` block and
// PostProcessCommon.ush: UnwrappedTexture3DSample (lakeone/UE5.51MagicM, stock 5.5.1).
// Reference: reference/ue/ue_lut_blend.cpp (unwrapped_texture3d_sample, blend_user_luts).
// The texture is a 16-point LUT unwrapped to 256 × 16 (texel (r + 16 b, g)), sampled with
// linear filtering and clamp-to-edge: the GPU's bilinear filter does red and green, the shader's
// lerp by the fractional slice does blue, as in UE.
#ifndef HDRC_UE_LUT_BLEND_GLSL
#define HDRC_UE_LUT_BLEND_GLSL

#include "d3d_math.glsl"
#include "gamma_correction.glsl"
#include "srgb_to_linear.glsl"

// The shader literals of CombineLUTsCommon: a 16-point LUT whatever the texture's size.
const float UE_USER_LUT_SIZE = 16.0;
const float UE_USER_LUT_INV_SIZE = 1.0 / 16.0;

// UnwrappedTexture3DSample(Texture, Sampler, UVW, Size = 16, InvSize = 1/16).
vec3 ue_unwrapped_texture3d_sample(sampler2D tex, vec3 uvw) {
  float int_w = floor(uvw.z * UE_USER_LUT_SIZE - 0.5);
  float frac_w = uvw.z * UE_USER_LUT_SIZE - 0.5 - int_w;
  float u = (uvw.x + int_w) * UE_USER_LUT_INV_SIZE;
  vec3 rg0 = textureLod(tex, vec2(u, uvw.y), 0.0).rgb;
  vec3 rg1 = textureLod(tex, vec2(u + UE_USER_LUT_INV_SIZE, uvw.y), 0.0).rgb;
  return mix(rg0, rg1, frac_w);
}

// The blend's prologue: GammaColor = LinearToSrgb(saturate(FilmColor)) and the lookup
// coordinate UVW = GammaColor · 15/16 + 0.5/16 (the shader's literals 15.0/16.0, 0.5f/16.0).
vec3 ue_lut_blend_gamma(vec3 film_color) {
  return linear_to_srgb(vec3(saturate_d3d(film_color.r), saturate_d3d(film_color.g),
                             saturate_d3d(film_color.b)));
}
vec3 ue_lut_blend_uvw(vec3 gamma_color) { return gamma_color * (15.0 / 16.0) + 0.5 / 16.0; }

// One LUT at weights (w0, w1), BLENDCOUNT 2: sRGBToLinear(w0·g + w1·sample(lut, UVW)).
vec3 ue_lut_blend_one(vec3 film_color, float w0, float w1, sampler2D lut) {
  vec3 g = ue_lut_blend_gamma(film_color);
  return srgb_to_linear(w0 * g + w1 * ue_unwrapped_texture3d_sample(lut, ue_lut_blend_uvw(g)));
}

// The block for BLENDCOUNT = P.lut_blend_count ≥ 2, with LUTWeights (P.lut_weights,
// P.lut_weight_4) from the host's GenerateFinalTable and Textures_1..4 = user_lut[0..3]; summed
// in UE's order (neutral first, then Textures_1..). Needs the generated interface.
vec3 ue_lut_blend(vec3 film_color) {
  int count = P.lut_blend_count;
  vec3 g = ue_lut_blend_gamma(film_color);
  vec3 uvw = ue_lut_blend_uvw(g);
  vec3 blended = P.lut_weights.x * g;
  if (count > 1) blended += P.lut_weights.y * ue_unwrapped_texture3d_sample(user_lut[0], uvw);
  if (count > 2) blended += P.lut_weights.z * ue_unwrapped_texture3d_sample(user_lut[1], uvw);
  if (count > 3) blended += P.lut_weights.w * ue_unwrapped_texture3d_sample(user_lut[2], uvw);
  if (count > 4) blended += P.lut_weight_4 * ue_unwrapped_texture3d_sample(user_lut[3], uvw);
  return srgb_to_linear(blended);
}

#endif
