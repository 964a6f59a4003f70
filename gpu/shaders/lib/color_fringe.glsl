// Colour fringe (chromatic aberration): PostProcessTonemap.usf TonemapCommonPS, USE_COLOR_FRINGE
// (docs/spec/ue55.md §6.1 step 1). P.fringe = (CAScale R, CAScale G, StartOffset, enabled) from the host
// (ChromaticAberrationParams). Reference: reference/ue/tonemap.cpp, step 1.
#ifndef HDRC_COLOR_FRINGE_GLSL
#define HDRC_COLOR_FRINGE_GLSL

#include "buffer_image.glsl"
#include "d3d_math.glsl"
#include "screen_pass.glsl"

// CAUV = LensUV − sign(LensUV) · saturate(|LensUV| − StartOffset) · scale, back to buffer UV.
// sign_d3d/saturate_d3d: HLSL semantics (the arguments are finite here, where GLSL agrees).
vec2 fringe_uv(vec2 lens_pos, float scale, float start_offset, vec2 extent) {
  vec2 s = vec2(sign_d3d(lens_pos.x), sign_d3d(lens_pos.y));
  vec2 a = vec2(saturate_d3d(abs(lens_pos.x) - start_offset),
                saturate_d3d(abs(lens_pos.y) - start_offset));
  return uv_from_screen_pos(lens_pos - s * a * scale, extent);
}

// R (and alpha) from the first shifted sample, G from the second, B from the pixel itself
// (UE samples B at the pixel's own UV, a texel centre: the texel).
vec4 color_fringe(vec4 scene, vec2 lens_pos, vec4 fringe, vec2 extent) {
  vec4 r = sample_scene(fringe_uv(lens_pos, fringe.x, fringe.z, extent));
  float g = sample_scene(fringe_uv(lens_pos, fringe.y, fringe.z, extent)).g;
  return vec4(r.r, g, scene.b, r.a);
}

#endif
