// UE 5.8's Texture vignette at feature level SM6 (USE_VIGNETTE_TEXTURE): the VignetteTexture and
// its sampler as PostProcessTonemap.cpp AddTonemapPass binds them (the post-process settings'
// texture, else GSystemTextures' white dummy; TStaticSamplerState<SF_Bilinear>: bilinear,
// clamp-to-edge on both axes, SampleLevel 0 in ComputeVignetteMask). The texture's red channel
// travels in the parameter block (P.ue58_vignette_tex, texel i at [i/4][i%4], row 0 at V 0;
// P.ue58_vignette_tex_width/height); it is sampled here as buffer_image.glsl samples the bloom:
// the taps and weights of clamp-to-edge bilinear filtering in float32 (a texture unit quantises
// the weights to its sub-texel precision: the reference's device ranges admit that,
// ue58_tonemap.h vignette_texture_device_range). Include before ../../lib/vignette.glsl (and
// before anything that includes it), which then has the Texture branch.
// Reference: reference/ue/tonemap.cpp vignette_texture_uv, vignette_texture_sample.
#ifndef HDRC_VIGNETTE_TEXTURE58_GLSL
#define HDRC_VIGNETTE_TEXTURE58_GLSL

// The permutation: RemapPermutation keeps USE_VIGNETTE_TEXTURE above SM5 only (host-resolved).
#define HDRC_VIGNETTE_TEXTURE (P.ue58_vignette_texture != 0)

float vignette_texel58(int x, int y) {
  int i = y * P.ue58_vignette_tex_width + x;
  return P.ue58_vignette_tex[i / 4][i % 4];
}

// The red channel at `uv` (texel centres at (i + 0.5) / size).
float vignette_texture_sample(vec2 uv) {
  ivec2 size = ivec2(P.ue58_vignette_tex_width, P.ue58_vignette_tex_height);
  vec2 t = uv * vec2(size) - 0.5;
  vec2 fl = floor(t);
  vec2 f = t - fl;
  ivec2 i = ivec2(fl);
  ivec2 p0 = clamp(i, ivec2(0), size - 1);
  ivec2 p1 = clamp(i + 1, ivec2(0), size - 1);
  float t00 = vignette_texel58(p0.x, p0.y), t10 = vignette_texel58(p1.x, p0.y);
  float t01 = vignette_texel58(p0.x, p1.y), t11 = vignette_texel58(p1.x, p1.y);
  float top = t00 + (t10 - t00) * f.x;
  float bottom = t01 + (t11 - t01) * f.x;
  return top + (bottom - top) * f.y;
}

#endif
