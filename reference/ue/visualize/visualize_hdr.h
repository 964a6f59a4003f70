// VisualizeHDR ("Show → Visualize → HDR (Eye Adaptation)"): UE 5.5's
// Engine/Shaders/Private/PostProcessVisualizeHDR.usf: MainPS (izzy2lost/UnrealEngineUWP, commit
// 39bb2572…; the 5.6.1 copy in orgitcog/u9n has the same logic), per output pixel, in double
// precision (docs/spec/ue55.md §9; docs/ue55-decisions.md D9, which overrides the spec where they
// differ).
//
// What is reproduced, in MainPS's order (the first two regions return early):
//  1. Luminance meter: |x − cx| < 180 and |y − cy| < 42 around the output viewport centre
//     (cx, cy) = trunc(ViewportMin + ViewportSize/2). Scene colour there, except the 17×17 swatch
//     (|dx|, |dy| ≤ 8) filled with the average tonemapped colour of a 21×21 bilinear sample block
//     around the centre, framed by a white ring at |dx| = 9 or |dy| = 9 (alpha 1 in both). The
//     samples sit at UV 0.5 + offset/extent: for an even extent that is a texel corner, so each
//     sample is the mean of 2×2 texels and the block covers 22×22 texels, edges at half weight.
//  2. Illuminance meter (IlluminanceMeterEnabled): −20 < x − ix < 300, −20 < y − iy < 40 around
//     (ix, iy) = (cx, cy − 100): scene colour with a white ring at trunc|dx| or trunc|dy| = 9.
//  3. Background by r.EyeAdaptation.VisualizeDebugType: 0 tonemapped scene; 1
//  ComputePlaceInHistogram
//     as grey, (0.5, 0, 0) below ExposureLowPercent, (0, 0, 0.5) at/above ExposureHighPercent;
//     2 CalculateEyeAdaptationLuminance · r.EyeAdaptation.VisualizeLuminanceScale; other → black.
//  4. Histogram panel (see PanelGeometry): black ring, Colorize(u) band, black ring by
//     ComputeDistanceToRect (round corners); inside: black, region tints, bars, the tone-curve
//     overlay FilmToneMap(EyeAdaptationResult · L(u)), the blue average-luminance line, the purple
//     exposure-without-bias line and the white exposure line.
//
// Not reproduced: the MiniFont glyphs MainPS prints (numbers and "NIT", "EV100", "LUX") and the
// FCanvas text drawn after the pass. Their numbers are returned in VisualizeHdrText and the
// rectangles the shader's glyphs can touch in VisualizeHdrText::glyph_rects; a comparison must
// exclude those rectangles (a glyph pixel is lerp(colour, font colour, font texel)). Canvas text
// (the settings block at the top left, "Luminance meter" captions, the EV100 axis labels) is
// drawn by the engine's stats font; only its numbers and anchors are given.
//
// Scope: the output image, the tonemapped SceneColor and the pre-tonemap HDRSceneColor have one
// size and the viewport is the whole image (AddVisualizeHDRPass creates the output from the scene
// colour). Every texture sample at a pixel's own UV then reads that texel exactly; the meters'
// offset samples are bilinear with clamp addressing (the pass's sampler), with exact weights.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "color/vec.h"
#include "core/image.h"
#include "reference/ue/visualize/histogram.h"

namespace hdrc::ref::visualize {

using Vec4 = std::array<double, 4>;

// EyeAdaptationBuffer[0] as the eye-adaptation pass leaves it (docs/spec/ue55.md §9).
struct EyeAdaptationState {
  double exposure = 1.0;                  // .x: EyeAdaptationResult (smoothed, with bias)
  double target_exposure = 1.0;           // .y: not read by MainPS
  double average_scene_luminance = 0.18;  // .z
  double exposure_bias_only = 1.0;        // .w
};

// FilmToneMap(AP1 grey triple) with the view's final post-process Film* settings (D9: the overlay
// feeds the grey straight in as AP1, no working-colour-space conversion or blue correction).
// Plug reference/grading's film_tone_map here; per channel because FilmToneMap's matrices do not
// map grey exactly to grey and the overlay masks each channel separately.
using ToneCurve = std::function<Vec3(const Vec3&)>;

// Wraps a curve of one variable as a per-channel ToneCurve (tests; neutral approximations).
ToneCurve per_channel(std::function<double(double)> curve);

struct VisualizeHdrInputs {
  const Image* scene_color = nullptr;      // tonemapped output of the tonemap pass (RGBA)
  const Image* hdr_scene_color = nullptr;  // scene colour before tonemapping, pre-exposed
  double one_over_pre_exposure = 1.0;      // View.OneOverPreExposure
  Histogram histogram{};                   // HistogramTexture (build_histogram)
  EyeAdaptationState eye;
  EyeAdaptationParameters params;
  ToneCurve tone_curve;
  bool illuminance_meter_enabled = true;  // deferred shading, not path tracing (5.8 C++)
  double luminance_scale = 1.0;           // r.EyeAdaptation.VisualizeLuminanceScale
};

struct IntRect {  // [x0, x1) × [y0, y1), pixels
  int x0, y0, x1, y1;
  bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
};

// Histogram panel placement for an output viewport (PostProcessVisualizeHDR.usf: MainPS):
// LeftTop = (Min.x + 64, Max.y − 160), Size = (Width − 128, 128); the last interior pixel is
// LeftTop + Size − 1. The frame reaches 6 px (7 at the round corners' blend) beyond the interior.
struct PanelGeometry {
  int left, top;                                   // HistogramLeftTop
  int width, height;                               // HistogramSize
  int right() const { return left + width - 1; }   // inclusive
  int bottom() const { return top + height - 1; }  // inclusive
};
PanelGeometry panel_geometry(int viewport_width, int viewport_height);

// PostProcessCommon.ush: ComputeDistanceToRect(Pos, LeftTop, Extent, round corners): Euclidean
// length of the per-axis pixel overshoot beyond [LeftTop, LeftTop + Extent − 1]; 0 inside.
double distance_to_rect(int x, int y, const PanelGeometry& g);

// Colorize(x): x = saturate(x); lerp(green, lerp(blue, red, x), |0.5 − x|·2). 0 blue, 0.5 green,
// 1 red. saturate(NaN) = 0 on D3D, so NaN gives blue.
Vec3 colorize(double x);

// Luminance() of Common.ush: dot(rgb, (0.3, 0.59, 0.11)).
double ue_luminance(const Vec3& rgb);

// Which MiniFont branch prints the meter value (PrintFloat, PrintFloatNoFractionLarge,
// PrintFloatNoFraction(…, 10)).
enum class NumberFormat { kFraction, kNoFractionLarge, kNoFraction10 };

struct GlyphRect {
  IntRect rect;
  std::string what;
};

// The numbers the pass prints, so a port can be checked without pixel-exact text.
struct VisualizeHdrText {
  // Luminance meter: Luminance(mean of the 21×21 HDR samples · OneOverPreExposure), the
  // scene-linear value UE labels NIT, and EV100 = log2((L/0.18)/LuminanceMax).
  double meter_luminance = 0.0;
  NumberFormat meter_luminance_format = NumberFormat::kFraction;
  double meter_ev100 = 0.0;
  Vec3 meter_hdr_average{};    // mean HDR colour · OneOverPreExposure
  Vec3 meter_scene_average{};  // mean tonemapped colour (the swatch)
  // Illuminance meter: E = mean of the 16×16 HDR samples · OneOverPreExposure · π (LUX) and its
  // Luminance(). Valid when illuminance_meter_enabled.
  Vec3 illuminance_rgb{};
  double illuminance_lux = 0.0;
  // Purple label: log2(1/EyeAdaptationResultWithoutExposureBias) (no LuminanceMax term);
  // white label: log2((1/EyeAdaptationResult)/LuminanceMax). Positions in histogram pixels.
  double exposure_without_bias_ev = 0.0;
  double exposure_without_bias_px = 0.0;
  double exposure_ev100 = 0.0;
  double exposure_px = 0.0;
  double average_luminance_px = 0.0;  // blue line, pos(AverageSceneLuminance/0.18) · width
  // FCanvas (PostProcessVisualizeHDR.cpp: AddVisualizeHDRPass overlay, read in the 5.8 copy):
  // the five EV100 axis labels lerp(HistogramLogMin, HistogramLogMax, i/4) (Log2ToEV100 of them in
  // the legacy range), anchored at (Min.x + 72 + trunc(i·(Width − 148)/4) − 5, Max.y − 54).
  std::array<double, 5> axis_ev100{};
  std::array<std::array<double, 2>, 5> axis_anchor{};
  // Every rectangle a MainPS glyph can touch (8×8 MiniFont cells, clipped to the region that
  // prints them). Pixels inside must be excluded from a pixel comparison.
  std::vector<GlyphRect> glyph_rects;
};

struct VisualizeHdrResult {
  Image image;
  VisualizeHdrText text;
  // MainPS writes only .rgb for VisualizeDebugType 1, 2 and other values, so outside the meters
  // the alpha it outputs is undefined there; the reference writes 0 and sets this false.
  bool alpha_defined = true;
};

// Runs MainPS over every pixel. Requires scene_color and hdr_scene_color of equal size and a
// tone_curve.
VisualizeHdrResult visualize_hdr(const VisualizeHdrInputs& in);

}  // namespace hdrc::ref::visualize
