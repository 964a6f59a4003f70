#include "reference/ue/cpp/lut_blend_table.h"

#include <algorithm>

namespace hdrc::ref {

// FinalPostProcessSettings.h: FFinalPostProcessSettings::LerpTo.
void ContributingLuts::lerp_to(int lut, float a) {
  if (a > kLutReplaceThreshold || entries_.empty()) {
    entries_ = {{lut, 1.f}};  // SetLUT(InTexture)
    return;
  }
  for (LutContribution& e : entries_) e.weight *= 1.0f - a;
  // FindIndex: a linear search by texture.
  const auto it = std::find_if(entries_.begin(), entries_.end(),
                               [lut](const LutContribution& e) { return e.lut == lut; });
  if (it != entries_.end()) {
    it->weight += a;
  } else {
    entries_.push_back({lut, a});  // PushLUT
  }
}

// SceneView.cpp: FSceneView::OverridePostProcessSettings (Weight ≤ 0 returns; Weight > 1 → 1;
// the LUT line of IF_PP: LerpTo(Src.ColorGradingLUT, Src.ColorGradingIntensity · Weight) with the
// intensity clamped to [0, 1]).
void ContributingLuts::override_from_source(int lut, float intensity, float blend_weight) {
  if (!(blend_weight > 0.f)) return;
  const float weight = std::min(blend_weight, 1.0f);
  const float a = std::clamp(intensity, 0.0f, 1.0f) * weight;
  lerp_to(lut, a);
}

// PostProcessCombineLUTs.cpp: GenerateFinalTable.
LutBlendTable generate_final_table(const std::vector<LutContribution>& entries,
                                   const std::vector<bool>* has_resource) {
  // A texture's render resource: null for the neutral entry and for a texture without one. The
  // LUT index stands for the resource (one per texture).
  auto resource = [&](const LutContribution& e) {
    if (e.lut == kNeutralLut) return kNeutralLut;
    if (has_resource && (e.lut < 0 || static_cast<size_t>(e.lut) >= has_resource->size() ||
                         !(*has_resource)[static_cast<size_t>(e.lut)]))
      return kNeutralLut;
    return e.lut;
  };
  LutBlendTable t;
  t.weight = {0.f, 0.f, 0.f, 0.f, 0.f};
  // Slot 0: the weight of the first neutral entry, or 0.
  const auto neutral = std::find_if(entries.begin(), entries.end(),
                                    [](const LutContribution& e) { return e.lut == kNeutralLut; });
  t.weight[0] = neutral != entries.end() ? neutral->weight : 0.f;
  float sum = t.weight[0];
  int n = 1;
  while (n < kMaxLutBlendCount) {
    const LutContribution* best = nullptr;
    int best_resource = kNeutralLut;
    for (const LutContribution& e : entries) {
      const int r = resource(e);
      if (std::find(t.lut.begin(), t.lut.begin() + n, r) != t.lut.begin() + n) continue;
      // "best ≤ candidate": on a tie the later entry wins.
      if (!best || best->weight <= e.weight) {
        best = &e;
        best_resource = r;
      }
    }
    if (!best || best->weight < kLutMinWeight) break;
    t.lut[static_cast<size_t>(n)] = best_resource;
    t.weight[static_cast<size_t>(n)] = best->weight;
    sum += best->weight;
    ++n;
  }
  if (sum > kLutMinSum) {
    const float inv = 1.0f / sum;
    for (int i = 0; i < n; ++i) t.weight[static_cast<size_t>(i)] *= inv;
  } else {
    t.weight = {1.f, 0.f, 0.f, 0.f, 0.f};
    for (int i = 1; i < kMaxLutBlendCount; ++i) t.lut[static_cast<size_t>(i)] = kNeutralLut;
    n = 1;
  }
  t.count = n;
  return t;
}

}  // namespace hdrc::ref
