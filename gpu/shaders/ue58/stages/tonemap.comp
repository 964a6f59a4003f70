#version 450
#extension GL_GOOGLE_include_directive : require
// Stage "ue58_tonemap", third pass (after combine_luts_inner.comp and combine_luts.comp have baked
// UE 5.8's LUT): the Tonemap pass, PostProcessTonemap.usf TonemapCommonPS (MainCS) as UE 5.8 has
// it. Steps 1–5 are UE 5.5's (../../lib/tonemap_effects.glsl) with 5.8's vignette
// (../../lib/vignette.glsl vignette_mask58: VignetteType, VignetteParams0–2); ColorLookupTable
// addresses the LUT by r.LUT.Shaper (log, or PQ of the clamped nits) and multiplies by LUTMax;
// device 7 (LinearEXR) is decoded to nits and every other device, scRGB included, is written as
// the LUT holds it (docs/ue58-differences.md T1–T3). One invocation per output pixel; output RGB
// = the device colour, alpha = OutLuminance. The Texture vignette at SM6 (USE_VIGNETTE_TEXTURE)
// samples the block's VignetteTexture (../lib/vignette_texture58.glsl, included before the
// vignette). Reference: reference/ue/ue58/ue58_tonemap.cpp.
#include "hdrc/interface.glsl"
#include "../lib/vignette_texture58.glsl"
#include "../../lib/lut_sample.glsl"
#include "../../lib/post_device.glsl"
#include "../../lib/screen_pass.glsl"
#include "../../lib/tonemap_effects.glsl"
#include "../../lib/tonemap_variant.glsl"
#include "../../lib/vignette.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  ivec2 px = ivec2(int(i) % P.width, int(i) / P.width);
  vec2 extent = vec2(P.width, P.height);
  vec2 uv = pixel_uv(px, extent);
  vec2 lens_pos = screen_pos_from_uv(uv, extent);  // default lens transform: lens = screen

  vec4 scene = tonemap_scene_color(px, lens_pos, extent);  // steps 1–2
  // USE_ADVANCED_VIGNETTE: VignetteType != CosineFourthLaw (BuildCommonPermutationDomain).
  vec3 vignette = vignette_mask58(lens_pos, extent.y * (1.0 / extent.x), P.ue58_vignette_type,
                                  P.ue58_vignette_type != 0, P.ue58_vignette_params0,
                                  P.ue58_vignette_params1, P.ue58_vignette_params2);
  vec3 final_linear = tonemap_final_linear_masked(scene.rgb, uv, lens_pos, vignette);  // 3–5
  vec3 encoded = lut_encode_shaper(P.ue58_lut_shaper == 1, true, final_linear);
  vec3 out_device = color_lookup_encoded(encoded, P.ue58_lut_max);
  float out_luminance = dot(out_device, vec3(0.299, 0.587, 0.114));
  vec3 post = P.output_device == 7 ? nits_from_pq3(out_device) : out_device;
  out_px[i] = vec4(post, out_luminance);
}
