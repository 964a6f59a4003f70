#version 450
#extension GL_GOOGLE_include_directive : require
// A per-pixel port of the Tonemap pass: it bakes no LUT. Where UE samples the baked LUT
// (PostProcessTonemap.usf ColorLookupTable), this evaluates CombineLUTs' colour function at the
// pixel's shaper-encoded coordinate, clamped to [0, 1] as the LUT sampler addresses it. Such a port
// misses UE's LUT interpolation error (up to 11 10-bit PQ codes for a 32^3 10-bit LUT), so it is
// judged against the analytic reference: `hdrconform verify --reference analytic` (README,
// "Verifying a port"). Everything else is the project's own tonemap.comp: the library files are
// included from gpu/shaders/lib (paths relative to this file).
#include "hdrc/interface.glsl"
#include "../../../gpu/shaders/lib/combine_luts.glsl"
#include "../../../gpu/shaders/lib/lut_shaper.glsl"
#include "../../../gpu/shaders/lib/post_device.glsl"
#include "../../../gpu/shaders/lib/screen_pass.glsl"
#include "../../../gpu/shaders/lib/tonemap_effects.glsl"

layout(local_size_x = HDRC_LOCAL_SIZE_X) in;

// OutDeviceColor without a LUT. A NaN coordinate (PQ of a negative channel) gives NaN in every
// channel, as the baked path does (docs/ue55-decisions.md, D-NF).
vec3 color_per_pixel(vec3 final_linear) {
  vec3 encoded = lut_encode(P.output_device, final_linear);
  if (any(isnan(encoded))) return vec3(hdrc_nan());
  return combine_luts_device_color(clamp(encoded, 0.0, 1.0));
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  ivec2 px = ivec2(int(i) % P.width, int(i) / P.width);
  vec2 extent = vec2(P.width, P.height);
  vec2 uv = pixel_uv(px, extent);
  vec2 lens_pos = screen_pos_from_uv(uv, extent);

  vec4 scene = tonemap_scene_color(px, lens_pos, extent);
  vec3 final_linear = tonemap_final_linear(scene.rgb, uv, lens_pos, extent);
  vec3 out_device = color_per_pixel(final_linear);
  float out_luminance = dot(out_device, vec3(0.299, 0.587, 0.114));
  out_px[i] = vec4(post_device(P.output_device, out_device, P.output_max_luminance),
                   out_luminance);
}
