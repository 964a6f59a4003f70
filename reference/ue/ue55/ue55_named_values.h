// UE 5.5's named intermediate values of one pixel: what the worked pixels of docs/spec/ue55.md list
// (reference/spec_worked_pixels_test.cpp compares them). Each comes from the reference's own stage
// functions and traces, in the order the shaders compute them, as `hdrc::ref::NamedValue`s
// (reference/named_values.h), like operators::named_values and pq_grading::named_values.
#pragma once

#include <vector>

#include "color/vec.h"
#include "core/shader_interface.h"
#include "reference/named_values.h"

namespace hdrc::ref::ue55 {

// The Tonemap pass at the centre of the screen (PostProcessTonemap.usf: TonemapCommonPS, spec
// docs/spec/ue55.md §6.1) with CombineLUTs evaluated analytically at the lookup's coordinate (§4),
// as `hdrconform probe --lut analytic` does: the scene colour's exposure and shaper encode, the
// texel's steps (decode, white balance, AP1, fake wide gamut, ColorCorrectAll), the device's own
// path (the SDR film path for devices 0–2 and 9 with FilmToneMap's steps as detail values; the
// ACES output transform's steps for devices 3–6; GradedColor for 7 and 8), the device encoding,
// the stored value, the lookup's ×1.05 and the per-device post conversion.
std::vector<NamedValue> tonemap_named_values(const ParamBlock& p, const Vec3& scene);

// The HDR UI composite (CompositeUIPixelShader.usf, §8) of one back-buffer pixel `scene` (PQ
// signals for devices 3/4, scRGB for 5/6) under the premultiplied UI pixel `ui`
// (r, g, b, a: sRGB-encoded colour times alpha, then alpha).
std::vector<NamedValue> ui_composite_named_values(const ParamBlock& p, const Vec3& scene,
                                                  const std::array<double, 4>& ui);

// VisualizeHDR's false colour (PostProcessVisualizeHDR.usf, §9) of one pre-exposed HDR scene
// colour: the eye-adaptation luminance, its histogram position and Colorize of it.
std::vector<NamedValue> visualize_false_colour_named_values(const ParamBlock& p, const Vec3& scene);

}  // namespace hdrc::ref::ue55
