// The user colour-grading LUT's blend weights, as UE 5.5's C++ computes them on the host
// (docs/ue55-lut-blend-spec.md §2): the view's list of contributing LUTs that every post-process
// source feeds through LerpTo, and the final table of at most five entries (the neutral one plus
// the four strongest textures) that AddCombineLUTPass hands to the shader as LUTWeights[5] and the
// BLENDCOUNT permutation. Float32 arithmetic throughout, as UE's CPU does it.
//
// Sources (lakeone/UE5.51MagicM, stock 5.5.1):
//   Engine/Source/Runtime/Engine/Public/FinalPostProcessSettings.h: FFinalPostProcessSettings
//     (constructor, SetLUT, PushLUT, FindIndex, LerpTo);
//   Engine/Source/Runtime/Engine/Private/SceneView.cpp: FSceneView::OverridePostProcessSettings
//     (the IF_PP test of ColorGradingLUT, the Weight clamp, ColorGradingIntensity × Weight);
//   Engine/Source/Runtime/Renderer/Private/PostProcess/PostProcessCombineLUTs.cpp:
//     GMaxLUTBlendCount, GenerateFinalTable.
#pragma once

#include <array>
#include <vector>

namespace hdrc::ref {

// GMaxLUTBlendCount: "including the neutral one at index 0".
inline constexpr int kMaxLutBlendCount = 5;
// LerpTo: a blend weight above 254/255 replaces the whole list by the new LUT.
inline constexpr float kLutReplaceThreshold = 254.0f / 255.0f;
// GenerateFinalTable: entries weaker than 1/512 are dropped.
inline constexpr float kLutMinWeight = 1.0f / 512.0f;
// GenerateFinalTable: a kept sum at or below this falls back to the neutral LUT alone.
inline constexpr float kLutMinSum = 0.001f;

// The neutral LUT (UE's null UTexture*): identity, computed in the shader.
inline constexpr int kNeutralLut = -1;

// One entry of FFinalPostProcessSettings::ContributingLUTs: a LUT (kNeutralLut or the index of
// the case's LUT, which stands for UE's texture pointer: equal index, equal texture) and its
// weight.
struct LutContribution {
  int lut = kNeutralLut;
  float weight = 0.f;
};

// FFinalPostProcessSettings::ContributingLUTs: starts as [(neutral, 1)] (the constructor's
// SetLUT(nullptr)).
class ContributingLuts {
 public:
  ContributingLuts() : entries_{{kNeutralLut, 1.f}} {}
  // LerpTo(T, a), 0 <= a <= 1 and T not neutral (UE checks both): a > 254/255 or an empty list
  // makes the list [(T, 1)]; otherwise every weight is scaled by (1 - a) and T gains a (added to
  // its existing entry, else appended).
  void lerp_to(int lut, float a);
  // FSceneView::OverridePostProcessSettings for one source whose ColorGradingLUT is set: nothing
  // when blend_weight <= 0; blend_weight clamped to 1; LerpTo(lut, clamp(intensity, 0, 1) ·
  // blend_weight).
  void override_from_source(int lut, float intensity, float blend_weight);
  const std::vector<LutContribution>& entries() const { return entries_; }

 private:
  std::vector<LutContribution> entries_;
};

// What GenerateFinalTable returns: `count` entries (BLENDCOUNT), entry 0 the neutral one
// (lut[0] = kNeutralLut), entries 1.. the textures strongest first (Textures_1..4); weights
// normalised to sum 1 (float32). Entries from `count` on are kNeutralLut / 0.
struct LutBlendTable {
  int count = 1;
  std::array<int, kMaxLutBlendCount> lut{kNeutralLut, kNeutralLut, kNeutralLut, kNeutralLut,
                                         kNeutralLut};
  std::array<float, kMaxLutBlendCount> weight{1.f, 0.f, 0.f, 0.f, 0.f};
};

// GenerateFinalTable(Settings, OutTextures, OutWeights, GMaxLUTBlendCount). `has_resource(i)`
// says whether LUT i has a render resource (a texture without one compares equal to the neutral
// entry's null and is never picked); nullptr: every LUT has one.
LutBlendTable generate_final_table(const std::vector<LutContribution>& entries,
                                   const std::vector<bool>* has_resource = nullptr);

}  // namespace hdrc::ref
