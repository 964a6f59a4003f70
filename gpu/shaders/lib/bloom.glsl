// Bloom with the bloom dirt mask: PostProcessTonemap.usf TonemapCommonPS, "Sample bloom" (desktop
// path) (docs/spec/ue55.md §6.1 step 5). Bloom = RawBloom · (1 + Dirt · BloomDirtMaskTint); the bloom is
// sampled at the pixel's buffer UV (ColorToBloom is the identity when bloom and scene share the
// viewport), the dirt mask at LensUV · (1, −1) · 0.5 + 0.5. aux0 = bloom, aux1 = dirt mask; an
// absent image has width 0 (UE binds black: RawBloom 0, Dirt 0 — the same sums for finite
// values). Reference: reference/ue/tonemap.cpp, steps 4–5.
#ifndef HDRC_BLOOM_GLSL
#define HDRC_BLOOM_GLSL

#include "buffer_image.glsl"
#include "tonemap_variant.glsl"

bool has_bloom() { return P.aux0_width > 0 && P.aux0_height > 0; }
bool has_bloom_dirt() { return P.aux1_width > 0 && P.aux1_height > 0; }

vec3 bloom(vec2 bloom_uv, vec2 lens_pos) {
  vec3 raw_bloom = sample_aux0(bloom_uv).rgb;
  if (!(TONEMAP_MAY_BLOOM_DIRT && has_bloom_dirt())) return raw_bloom;
  vec2 dirt_lens_uv = lens_pos * vec2(1.0, -1.0);
  vec3 raw_dirt = sample_aux1(dirt_lens_uv * 0.5 + 0.5).rgb;
  return raw_bloom * (1.0 + raw_dirt * P.bloom_dirt_tint.rgb);
}

#endif
