// VisualizeHDR's histogram panel geometry and colour ramp (PostProcessVisualizeHDR.usf: MainPS,
// izzy2lost/UnrealEngineUWP 5.5, commit 39bb2572; PostProcessCommon.ush: ComputeDistanceToRect).
// Reference: reference/ue/visualize/visualize_hdr.cpp panel_geometry, distance_to_rect, colorize.
#ifndef HDRC_VISUALIZE_PANEL_GLSL
#define HDRC_VISUALIZE_PANEL_GLSL

#include "d3d_math.glsl"

const int PANEL_MARGIN_X = 64;   // HistogramLeftTop.x = ViewportMin.x + 64, width − 2 · 64
const int PANEL_BOTTOM = 160;    // HistogramLeftTop.y = ViewportMax.y − 128 − 32
const int PANEL_HEIGHT = 128;    // HistogramSize.y

struct PanelGeometry {
  int left, top, width, height;  // interior [left, left + width) × [top, top + height)
};

// The panel of an output viewport covering the whole image.
PanelGeometry panel_geometry(int viewport_width, int viewport_height) {
  return PanelGeometry(PANEL_MARGIN_X, viewport_height - PANEL_BOTTOM,
                       viewport_width - 2 * PANEL_MARGIN_X, PANEL_HEIGHT);
}

// ComputeDistanceToRect with round corners: length of the per-axis pixel overshoot beyond the
// interior's first and last pixels; 0 inside.
float distance_to_rect(int x, int y, PanelGeometry g) {
  int right = g.left + g.width - 1;
  int bottom = g.top + g.height - 1;
  int rx = max(0, x - right) + max(0, g.left - x);
  int ry = max(0, y - bottom) + max(0, g.top - y);
  return sqrt(float(rx * rx + ry * ry));
}

// Colorize(x): x = saturate(x) (NaN → 0); lerp(green, lerp(blue, red, x), |0.5 − x| · 2).
vec3 colorize(float x) {
  x = saturate_d3d(x);
  const vec3 heat = vec3(1.0, 0.0, 0.0);
  const vec3 middle = vec3(0.0, 1.0, 0.0);
  const vec3 cold = vec3(0.0, 0.0, 1.0);
  return lerp_d3d(middle, lerp_d3d(cold, heat, x), abs(0.5 - x) * 2.0);
}

#endif
