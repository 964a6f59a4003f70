// UE 5.8's named intermediate values of one pixel: what the worked pixels of docs/spec/ue58.md list
// (reference/spec_worked_pixels_test.cpp compares them) and `hdrconform probe --pipeline ue58
// --json` prints (Pipeline::named_values). Each comes from the reference's own stage functions and
// their traces, in the order the shaders compute them, as `hdrc::ref::NamedValue`s
// (reference/named_values.h), like UE 5.5's (reference/ue/ue55/ue55_named_values.h).
#pragma once

#include <array>
#include <vector>

#include "color/vec.h"
#include "core/pipeline.h"
#include "core/shader_interface.h"
#include "reference/named_values.h"

namespace hdrc::ref::ue58 {

// The HDR UI composite of 5.8 (CompositeUIPixelShader.usf, docs/spec/ue58.md §1) of one
// back-buffer pixel `scene` (PQ signals for devices 3/4, scRGB for 5/6) under the premultiplied
// UI pixel `ui` (r, g, b, a), from composite_pixel58's trace (reference/ue/ue58/
// ue58_ui_composite.h): ComputeHDRUIColor's un-premultiplied and linearized colour and the UI in
// nits; ComputeHDRSceneColor's scene in nits; ComposeUIAndScene's branch (the UI · UILevel; the
// gamma blend's g(Scene), g(UI) and their lerp, or the linear blend's Reinhard); the composed and
// colour-deficiency values; the encoded output and its alpha (the UI's). r.HDR.UI.CompositeMode 0
// (Slate's blend, no shader): the input and the output only.
std::vector<NamedValue> ui_composite_named_values(const ParamBlock& p, const Vec3& scene,
                                                  const std::array<double, 4>& ui);

// The Tonemap pass's vignette mask of 5.8 (PostProcessCommon.ush: VignetteSpace,
// ComputeVignetteMask; docs/spec/ue58.md §4) at screen position (pos_x, pos_y) in [-1, 1] (y up)
// of a viewport whose height / width is `aspect`, from vignette_mask's trace (reference/ue/
// tonemap.h) with the block's vignette (tonemap_vignette): "input" is (pos_x, pos_y, aspect); the
// Texture branch's V, UV, texel coordinate, four taps (red, k/255) and bilinear sample; every
// branch's weight and the mask lerp(Colour, 1, weight). A screen position is not a colour, so
// probe does not print these (the page's test evaluates them).
std::vector<NamedValue> vignette_named_values(const ParamBlock& p, double pos_x, double pos_y,
                                              double aspect);

// VisualizeHDR (stage ue58_visualize_hdr, docs/spec/ue58.md §3) of the case `c` (its input a
// uniform scene, its parameters resolved for the input's size): "input" the scene colour of pixel
// (0, 0), the numbers the pass prints (the reference image's `values`: exposure labels and their
// positions, meters, average luminance, in their names' order) and "pixel", the output at (0, 0).
// The whole pass runs (the panel and meters read the whole image); an error of the reference
// comes back as an empty list.
std::vector<NamedValue> visualize_named_values(const ResolvedCase& c);

// Pipeline::named_values of the ue58 pipeline: per colour of the row, the UI composite's values
// above (the UI pixel at the same position of the case's UI image; `probe --ui` fills it). The
// other stages name none yet: their lists are empty (probe --json refuses them).
std::vector<std::vector<NamedValue>> named_values_of(
    const ResolvedCase& c, const std::vector<std::array<double, 3>>& colours);

}  // namespace hdrc::ref::ue58
