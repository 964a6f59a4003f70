// The Tonemap pass up to FinalLinearColor: colour fringe, sharpen, vignette, tint and exposure,
// bloom (PostProcessTonemap.usf TonemapCommonPS, docs/spec/ue55.md §6.1 steps 1–5, in UE's order). Local
// exposure is 1 (neither bilateral nor fusion local exposure is modelled, as the reference) and
// there is no film-grain texture (step 6). Reference: reference/ue/tonemap.cpp tonemap_image.
#ifndef HDRC_TONEMAP_EFFECTS_GLSL
#define HDRC_TONEMAP_EFFECTS_GLSL

#include "bloom.glsl"
#include "buffer_image.glsl"
#include "color_fringe.glsl"
#include "screen_pass.glsl"
#include "sharpen.glsl"
#include "tonemap_variant.glsl"
#include "vignette.glsl"

// Steps 1–2: the scene colour of pixel `px` after the fringe (USE_COLOR_FRINGE, P.fringe.w) and
// the sharpen (USE_SHARPEN when Sharpen > 0). Alpha is the fringe's R sample's alpha.
vec4 tonemap_scene_color(ivec2 px, vec2 lens_pos, vec2 extent) {
  vec4 s = scene_texel(px);
  if (TONEMAP_MAY_FRINGE && P.fringe.w != 0.0) s = color_fringe(s, lens_pos, P.fringe, extent);
  // OneOverPreExposure · LocalExposure · GlobalExposure, LocalExposure = 1.
  if (TONEMAP_MAY_SHARPEN && P.sharpen_div6 > 0.0) s.rgb = sharpen(s.rgb, px, P.exposure, P.sharpen_div6);
  return s;
}

// UE 5.5's VignetteMask (BRANCH on TonemapperParams.x > 0): 5.8's ComputeVignetteMask at the
// cosine-fourth law, centre (0.5, 0.5), black colour (the same to the bit); AspectRatio =
// Output_ViewportSize.y · Output_ViewportSizeInverse.x. MobileVignette = 1 on desktop.
vec3 tonemap_vignette(vec2 lens_pos, vec2 extent) {
  return vignette_mask58(lens_pos, extent.y * (1.0 / extent.x), 0, false,
                         vec4(P.vignette_intensity, 0.0, 0.0, 0.0), vec4(0.5, 0.5, 1.0, 1.0), 1.0);
}

// Steps 4–5 with the vignette mask `vignette` (UE 5.5 and 5.8): FinalLinearColor = S ·
// SceneColorTint · (OneOverPreExposure · GlobalExposure · VignetteMask · LocalExposure) + Bloom ·
// (OneOverPreExposure · GlobalExposure · VignetteMask). P.exposure = OneOverPreExposure ·
// GlobalExposure (host).
vec3 tonemap_final_linear_masked(vec3 scene, vec2 uv, vec2 lens_pos, vec3 vignette) {
  vec3 final_linear = scene * P.scene_color_tint.rgb * (P.exposure * vignette);
  if (TONEMAP_MAY_BLOOM && has_bloom()) final_linear += bloom(uv, lens_pos) * (P.exposure * vignette);
  return final_linear;
}

// Steps 3–5 of UE 5.5.
vec3 tonemap_final_linear(vec3 scene, vec2 uv, vec2 lens_pos, vec2 extent) {
  return tonemap_final_linear_masked(scene, uv, lens_pos, tonemap_vignette(lens_pos, extent));
}

#endif
