// VisualizeHDR's per-pixel output, PostProcessVisualizeHDR.usf: MainPS (izzy2lost/UnrealEngineUWP
// 5.5, commit 39bb2572; docs/spec/ue55.md §9; docs/ue55-decisions.md D9 and D-S2 item 5, which override the
// spec where they differ), in MainPS's order: the luminance meter and the illuminance meter return
// early; then the background by r.EyeAdaptation.VisualizeDebugType; then the histogram panel.
// Reference: reference/ue/visualize/visualize_hdr.cpp visualize_hdr (per pixel, the loop body).
//
// Not drawn, as in the reference: MainPS's MiniFont glyphs (the printed numbers, "NIT", "EV100",
// "LUX") and the FCanvas text; their numbers are in the scratch buffer (visualize_scratch.glsl)
// and the rectangles they would cover in reference VisualizeHdrText::glyph_rects. Needs the
// generated interface included first (P.visualize_debug_type, P.film_*).
#ifndef HDRC_VISUALIZE_HDR_GLSL
#define HDRC_VISUALIZE_HDR_GLSL

#include "d3d_math.glsl"
#include "film_tonemap.glsl"
#include "visualize_eye_adaptation.glsl"
#include "visualize_histogram.glsl"
#include "visualize_meter.glsl"
#include "visualize_panel.glsl"

const float VIS_LUMINANCE_SCALE = 1.0;  // r.EyeAdaptation.VisualizeLuminanceScale (default)
const bool VIS_ILLUMINANCE_METER_ENABLED = true;  // deferred shading, no path tracing

// What the histogram pass computed, as the visualize pass reads it.
struct VisualizeInputs {
  float histogram[HISTOGRAM_SIZE];
  float histogram_max;
  vec3 meter_scene_average;     // the swatch colour
  float average_luminance_px;   // blue line
  float exposure_without_bias_px;  // purple line
  float exposure_px;            // white line
  float pos_min, pos_max;       // region tint bounds
  float exposure;               // EyeAdaptationResult
  float one_over_pre_exposure;
  int debug_type;               // r.EyeAdaptation.VisualizeDebugType
};

// HLSL lerp on float4 (a + t · (b − a)).
vec4 vis_lerp(vec4 a, vec4 b, float t) { return a + t * (b - a); }

vec4 visualize_hdr_pixel(int x, int y, int width, int height, vec4 hdr, vec4 scene,
                         VisualizeInputs in_v) {
  ivec2 c = meter_centre(width, height);
  // Luminance meter: |dx| < 180, |dy| < 42; the 17×17 swatch of the mean tonemapped colour inside
  // a white ring at |dx| or |dy| = 9.
  float dx = abs(float(x - c.x));
  float dy = abs(float(y - c.y));
  if (dx < 180.0 && dy < 42.0) {
    if (dx < 10.0 && dy < 10.0) {
      return (dx == 9.0 || dy == 9.0) ? vec4(1.0) : vec4(in_v.meter_scene_average, 1.0);
    }
    return scene;
  }

  // Illuminance meter: −20 < x − ix < 300, −20 < y − iy < 40, white ring at trunc|d| = 9.
  if (VIS_ILLUMINANCE_METER_ENABLED) {
    float pdx = float(x) - float(c.x);
    float pdy = float(y) - illuminance_centre_y(c.y);
    if (pdx > -20.0 && pdx < 300.0 && pdy < 40.0 && pdy > -20.0) {
      int adx = int(abs(pdx));
      int ady = int(abs(pdy));
      return (adx < 10 && ady < 10 && (adx == 9 || ady == 9)) ? vec4(1.0) : scene;
    }
  }

  // Background. Debug types 1 and 2 write only .rgb in MainPS; alpha 0 as the reference writes.
  vec4 out_c = vec4(0.0);
  if (in_v.debug_type == 0) {
    out_c = scene;
  } else if (in_v.debug_type == 1) {
    float percentile = place_in_histogram(hdr.rgb * in_v.one_over_pre_exposure, in_v.histogram);
    out_c = vec4(vec3(percentile), 0.0);
    if (percentile < EA_EXPOSURE_LOW_PERCENT) {
      out_c = vec4(0.5, 0.0, 0.0, 0.0);
    } else if (percentile >= EA_EXPOSURE_HIGH_PERCENT) {
      out_c = vec4(0.0, 0.0, 0.5, 0.0);
    }
  } else if (in_v.debug_type == 2) {
    float l = eye_adaptation_luminance(hdr.rgb * in_v.one_over_pre_exposure) * VIS_LUMINANCE_SCALE;
    out_c = vec4(vec3(l), 0.0);
  }

  // Panel frame: black ring beyond 6 px, the Colorize(u) band, black ring beyond 1 px.
  PanelGeometry g = panel_geometry(width, height);
  float inset_x = float(x - g.left);
  float inset_y = float(y - g.top);
  float u = inset_x / float(g.width);
  float v = inset_y / float(g.height);
  vec3 border = colorize(u);
  float distance = distance_to_rect(x, y, g);
  vec3 rgb = out_c.rgb;
  rgb = lerp_d3d(vec3(0.0), rgb, saturate_d3d(distance - (4.0 + 2.0)));
  rgb = lerp_d3d(border, rgb, saturate_d3d(distance - (4.0 + 1.0)));
  rgb = lerp_d3d(vec3(0.0), rgb, saturate_d3d(distance - 1.0));
  out_c = vec4(rgb, out_c.a);
  if (distance > 0.0) return out_c;

  // Inside the panel: region tint, bars, the tone-curve overlay, the three lines.
  // The bar's bucket, floor(u · 64) with u = inset / width, in integers: the float form lands on
  // the previous bucket at every exact boundary where the division rounds down, as the 2.5 ULP
  // Vulkan allows may (a whole column of the neighbouring bar; the worst-case device model shows
  // it, docs/precision.md). Exact arithmetic, so the reference's value.
  int bucket = min(int(x - g.left) * HISTOGRAM_SIZE / g.width, HISTOGRAM_SIZE - 1);
  vec3 tint = (u < in_v.pos_min || !(u < in_v.pos_max)) ? vec3(0.5) : vec3(0.5, 0.8, 0.5);
  rgb = lerp_d3d(rgb, tint, 0.5);
  if (in_v.histogram[bucket] / in_v.histogram_max >= 1.0 - v) rgb = lerp_d3d(rgb, colorize(u), 0.5);

  // FilmToneMap(EyeAdaptationResult · L(u)) fed as an AP1 grey (D9), white where it crosses 1 − v.
  float lum = luminance_from_histogram_position(u);
  vec3 mapped = film_tone_map(vec3(in_v.exposure * lum));
  for (int k = 0; k < 3; ++k) {
    float mask = saturate_d3d(1.0 - 100.0 * abs(mapped[k] - (1.0 - v)));
    rgb[k] = lerp_d3d(rgb[k], 1.0, mask);
  }
  out_c = vec4(rgb, out_c.a);

  if (abs(inset_x - in_v.average_luminance_px) < 3.0) {
    out_c = vis_lerp(out_c, vec4(0.0, 0.0, 1.0, 0.0), 0.5);  // blue: average scene luminance
  }
  if (abs(inset_x - in_v.exposure_without_bias_px) < 2.0 && y > g.top + 9) {
    out_c = vis_lerp(out_c, vec4(0.5, 0.0, 0.5, 0.0), 1.0);  // purple: exposure without bias
  }
  if (abs(inset_x - in_v.exposure_px) < 2.0 && y > g.top + 18) {
    out_c = vis_lerp(out_c, vec4(1.0, 1.0, 1.0, 0.0), 1.0);  // white: exposure
  }
  return out_c;
}

#endif
