#version 450
#extension GL_GOOGLE_include_directive : require
// Stage "tonemap", second pass (after combine_luts.comp has written the LUT): the Tonemap pass,
// PostProcessTonemap.usf TonemapCommonPS (MainCS), docs/spec/ue55.md §6.1 steps 1–9; the dither (step 10) is
// the separate stage "dither". One invocation per output pixel of P.width × P.height. Output:
// RGB = the device colour after the post conversion, alpha = OutLuminance (the luminance UE writes
// for post-process AA). Reference: reference/ue/tonemap.cpp tonemap_image.
#include "hdrc/interface.glsl"
#include "../lib/lut_sample.glsl"
#include "../lib/post_device.glsl"
#include "../lib/screen_pass.glsl"
#include "../lib/tonemap_effects.glsl"
#include "../lib/tonemap_variant.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  ivec2 px = ivec2(int(i) % P.width, int(i) / P.width);
  vec2 extent = vec2(P.width, P.height);
  vec2 uv = pixel_uv(px, extent);
  vec2 lens_pos = screen_pos_from_uv(uv, extent);  // default lens transform: lens = screen

  vec4 scene = tonemap_scene_color(px, lens_pos, extent);            // steps 1–2
  vec3 final_linear = tonemap_final_linear(scene.rgb, uv, lens_pos, extent);  // steps 3–5
  vec3 out_device = color_lookup_table(final_linear);                // step 7
  float out_luminance = dot(out_device, vec3(0.299, 0.587, 0.114));  // step 8
  // Step 9; TONEMAP_MAY_POST is false only for a device without a post conversion, for which
  // post_device returns its input.
  vec3 post = TONEMAP_MAY_POST ? post_device(P.output_device, out_device, P.output_max_luminance)
                               : out_device;
  out_px[i] = vec4(post, out_luminance);
}
