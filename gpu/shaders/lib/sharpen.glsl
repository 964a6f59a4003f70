// Sharpen against the four neighbours: PostProcessTonemap.usf TonemapCommonPS, USE_SHARPEN, the
// path without quad message passing (identical maths) (docs/spec/ue55.md §6.1 step 2). Reference:
// reference/ue/tonemap.cpp, step 2.
#ifndef HDRC_SHARPEN_GLSL
#define HDRC_SHARPEN_GLSL

#include "buffer_image.glsl"
#include "d3d_math.glsl"

// Common.ush: Luminance(LinearColor) = dot(LinearColor, (0.3, 0.59, 0.11)).
float luminance_sharpen(vec3 c) { return dot(c, vec3(0.3, 0.59, 0.11)); }

// `scene` is the pixel's colour after the fringe; the neighbours are unfringed texels
// (LookupSceneColor at ±1 texel; UE's UV clamp to the viewport's bilinear bounds = clamp-to-edge).
// edge_scale = OneOverPreExposure · LocalExposure · GlobalExposure, sharpen_div6 = Sharpen / 6.
vec3 sharpen(vec3 scene, ivec2 px, float edge_scale, float sharpen_div6) {
  vec3 c1 = scene_texel(px + ivec2(-1, 0)).rgb;
  vec3 c2 = scene_texel(px + ivec2(1, 0)).rgb;
  vec3 c3 = scene_texel(px + ivec2(0, -1)).rgb;
  vec3 c4 = scene_texel(px + ivec2(0, 1)).rgb;
  float a0 = luminance_sharpen(scene);
  vec4 d = abs(a0 - vec4(luminance_sharpen(c1), luminance_sharpen(c2), luminance_sharpen(c3),
                         luminance_sharpen(c4)));
  // max4 in HLSL: maxNum on D3D (a NaN difference loses to a number); GLSL max is undefined there.
  float hdr_edge = edge_scale * max_d3d(max_d3d(d.x, d.y), max_d3d(d.z, d.w));
  float edge_mask = saturate_d3d(1.0 - hdr_edge);  // saturate(NaN) = 0 on D3D
  float lerp_factor = -edge_mask * sharpen_div6;
  vec3 delta = (c1 + c2 + c3 + c4) - scene * 4.0;
  return scene + delta * lerp_factor;
}

#endif
