// Nuke-style colour correction of the CombineLUTs pass (docs/spec/ue55.md §4.6), in AP1.
//
// Source: Engine/Shaders/Private/PostProcessCombineLUTs.usf: ColorCorrect, ColorCorrectAll (read in
// Mephisto1024/Toon_Engine ~5.1/5.2, commit 2dc09e8226da45ca87f8fcb812453ad02a75987b; identical in
// the 5.8 copy). Parameters: FPostProcessSettings Color{Saturation,Contrast,Gamma,Gain,Offset}
// {,Shadows,Midtones,Highlights} and ColorCorrection{ShadowsMax,HighlightsMin,HighlightsMax};
// defaults from Scene.cpp FPostProcessSettings (docs/spec/ue55.md §4.1).
#pragma once

#include <array>

#include "color/vec.h"

namespace hdrc::ref::grading {

using Vec4 = std::array<double, 4>;  // FVector4f: rgb per channel, w for all channels

// One zone's (or the global) controls. .w multiplies .rgb for saturation, contrast, gamma and gain,
// and is added to .rgb for offset.
struct ColorCorrectZone {
  Vec4 saturation{1, 1, 1, 1};
  Vec4 contrast{1, 1, 1, 1};
  Vec4 gamma{1, 1, 1, 1};
  Vec4 gain{1, 1, 1, 1};
  Vec4 offset{0, 0, 0, 0};
};

struct ColorCorrectParams {
  ColorCorrectZone global, shadows, midtones, highlights;
  double shadows_max = 0.09;    // ColorCorrectionShadowsMax (AP1 luma)
  double highlights_min = 0.5;  // ColorCorrectionHighlightsMin
  double highlights_max = 1.0;  // ColorCorrectionHighlightsMax
};

// A zone combined with the global controls as ColorCorrectAll passes them: component-wise (.w
// included) product for saturation/contrast/gamma/gain, sum for offset.
ColorCorrectZone combine_with_global(const ColorCorrectZone& zone, const ColorCorrectZone& global);

// PostProcessCombineLUTs.usf: ColorCorrect — AP1 in, AP1 out:
//  1. C = max(0, lerp(luma, C, S.rgb·S.w)), luma = dot(C, AP1_RGB2Y)
//  2. C = pow(C/0.18, K.rgb·K.w)·0.18
//  3. C = pow(C, 1/(G.rgb·G.w))
//  4. C = C·(A.rgb·A.w) + (O.rgb + O.w)
// Step 1's max is D3D maxNum, so NaN input becomes 0 there; pow follows d3d::pow.
Vec3 color_correct(const Vec3& ap1, const ColorCorrectZone& z);

// Zone weights from the input's AP1 luma: shadows = 1 − smoothstep(0, ShadowsMax, luma),
// highlights = smoothstep(HighlightsMin, HighlightsMax, luma), midtones = 1 − shadows − highlights.
// A NaN luma gives (1, 0, 0) (saturate(NaN) = 0 on D3D).
struct ZoneWeights {
  double shadows, midtones, highlights;
};
ZoneWeights color_correct_weights(double luma_ap1, const ColorCorrectParams& p);

// PostProcessCombineLUTs.usf: ColorCorrectAll — Σ weight_Z · ColorCorrect(C, zone Z ∘ global).
Vec3 color_correct_all(const Vec3& ap1, const ColorCorrectParams& p);

}  // namespace hdrc::ref::grading
