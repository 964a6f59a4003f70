// Images held in storage buffers (vec4 per texel, row-major, as the interface binds in_px, aux0_px
// and aux1_px), read as UE reads its textures in the Tonemap pass: texel fetches, and bilinear
// samples with clamp-to-edge addressing at a buffer UV. Reference: reference/ue/tonemap.cpp
// (sample_bilinear). Needs the generated interface ("hdrc/interface.glsl") included first.
//
// UE samples the scene colour, the bloom and the dirt mask with bilinear samplers and clamps the UV
// to the viewport's bilinear bounds (PostProcessTonemap.usf: SampleSceneColor,
// Color_UVViewportBilinearMin/Max; BloomUVViewportBilinearMin/Max): the same texels and weights as
// clamp-to-edge addressing. The weights are computed here in float32 (a texture unit would
// quantise them to its sub-texel precision; these images are storage buffers, so they are exact
// up to float32 rounding).
#ifndef HDRC_BUFFER_IMAGE_GLSL
#define HDRC_BUFFER_IMAGE_GLSL

// The four texels and weights of a bilinear sample at `uv` in an image of `size` texels.
struct BilinearTaps {
  ivec2 p0;  // top-left texel, clamped to the image
  ivec2 p1;  // bottom-right texel, clamped to the image
  vec2 f;    // fractional weights of p1 along x and y
};

BilinearTaps bilinear_taps(vec2 uv, ivec2 size) {
  vec2 t = uv * vec2(size) - 0.5;  // texel space: texel centres at integers
  vec2 fl = floor(t);
  BilinearTaps b;
  b.f = t - fl;
  ivec2 i = ivec2(fl);
  b.p0 = clamp(i, ivec2(0), size - 1);
  b.p1 = clamp(i + 1, ivec2(0), size - 1);
  return b;
}

// lerp(lerp(t00, t10, f.x), lerp(t01, t11, f.x), f.y), written as HLSL's lerp a + (b − a)·t.
vec4 bilinear_blend(BilinearTaps b, vec4 t00, vec4 t10, vec4 t01, vec4 t11) {
  vec4 top = t00 + (t10 - t00) * b.f.x;
  vec4 bottom = t01 + (t11 - t01) * b.f.x;
  return top + (bottom - top) * b.f.y;
}

int texel_index(ivec2 p, int width) { return p.y * width + p.x; }

// The scene colour (in_px, P.width × P.height).
vec4 scene_texel(ivec2 p) {
  ivec2 size = ivec2(P.width, P.height);
  return in_px[texel_index(clamp(p, ivec2(0), size - 1), P.width)];
}

vec4 sample_scene(vec2 uv) {
  BilinearTaps b = bilinear_taps(uv, ivec2(P.width, P.height));
  return bilinear_blend(b, in_px[texel_index(b.p0, P.width)],
                        in_px[texel_index(ivec2(b.p1.x, b.p0.y), P.width)],
                        in_px[texel_index(ivec2(b.p0.x, b.p1.y), P.width)],
                        in_px[texel_index(b.p1, P.width)]);
}

// The bloom (aux0_px, P.aux0_width × P.aux0_height).
vec4 sample_aux0(vec2 uv) {
  BilinearTaps b = bilinear_taps(uv, ivec2(P.aux0_width, P.aux0_height));
  int w = P.aux0_width;
  return bilinear_blend(b, aux0_px[texel_index(b.p0, w)], aux0_px[texel_index(ivec2(b.p1.x, b.p0.y), w)],
                        aux0_px[texel_index(ivec2(b.p0.x, b.p1.y), w)], aux0_px[texel_index(b.p1, w)]);
}

// The bloom dirt mask (aux1_px, P.aux1_width × P.aux1_height).
vec4 sample_aux1(vec2 uv) {
  BilinearTaps b = bilinear_taps(uv, ivec2(P.aux1_width, P.aux1_height));
  int w = P.aux1_width;
  return bilinear_blend(b, aux1_px[texel_index(b.p0, w)], aux1_px[texel_index(ivec2(b.p1.x, b.p0.y), w)],
                        aux1_px[texel_index(ivec2(b.p0.x, b.p1.y), w)], aux1_px[texel_index(b.p1, w)]);
}

#endif
