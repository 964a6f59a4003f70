// The host's LUT blend table against the hand-derived float32 values of
// docs/ue55-lut-blend-spec.md §2.7 (one LUT at each intensity) and §2.8 (the LerpTo sequences
// S1-S11), and GenerateFinalTable's edge cases: the tie rule, the 1/512 threshold, normalisation,
// more than four textures, the 254/255 replace rule, resource-less textures and a vanishing sum.
// The expected weights are the spec's 9-digit values, which name one float each: compared exactly.
#include "reference/ue/cpp/lut_blend_table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <utility>

namespace {

using hdrc::ref::ContributingLuts;
using hdrc::ref::generate_final_table;
using hdrc::ref::kNeutralLut;
using hdrc::ref::LutBlendTable;

constexpr int A = 0, B = 1, C = 2, D = 3, E = 4;

LutBlendTable table_of(std::initializer_list<std::pair<int, float>> steps) {
  ContributingLuts list;
  for (const auto& [lut, a] : steps) list.lerp_to(lut, a);
  return generate_final_table(list.entries());
}

void expect_table(const LutBlendTable& t, std::initializer_list<int> luts,
                  std::initializer_list<float> weights) {
  ASSERT_EQ(static_cast<size_t>(t.count), weights.size());
  ASSERT_EQ(luts.size() + 1, weights.size());
  EXPECT_EQ(t.lut[0], kNeutralLut);
  size_t i = 1;
  for (int l : luts) EXPECT_EQ(t.lut[i++], l) << "texture slot " << i - 1;
  i = 0;
  for (float w : weights) {
    EXPECT_EQ(t.weight[i], w) << "LUTWeights[" << i << "]";
    ++i;
  }
  for (; i < t.weight.size(); ++i) {
    EXPECT_EQ(t.weight[i], 0.f);
    EXPECT_EQ(t.lut[i], kNeutralLut);
  }
}

// §2.7: one source at BlendWeight 1, ColorGradingIntensity I.
TEST(LutBlendTable, OneLutIntensities) {
  struct Row {
    float intensity;
    int count;
    float w0, w1;
  };
  const Row rows[] = {
      {0.f, 1, 1.f, 0.f},
      {0.001f, 1, 1.f, 0.f},
      {0.002f, 2, 0.998000026f, 0.00200000009f},
      {0.3f, 2, 0.699999988f, 0.300000012f},
      {0.5f, 2, 0.5f, 0.5f},
      {0.996f, 2, 0.00400000811f, 0.995999992f},
      {254.f / 255.f, 2, 0.00392156839f, 0.996078432f},
      {0.999f, 2, 0.f, 1.f},
      {1.f, 2, 0.f, 1.f},
  };
  for (const Row& r : rows) {
    SCOPED_TRACE(testing::Message() << "intensity " << r.intensity);
    ContributingLuts list;
    list.override_from_source(A, r.intensity, 1.f);
    const LutBlendTable t = generate_final_table(list.entries());
    if (r.count == 1)
      expect_table(t, {}, {r.w0});
    else
      expect_table(t, {A}, {r.w0, r.w1});
  }
}

TEST(LutBlendTable, SourceWeightAndIntensityClamps) {
  ContributingLuts none;
  none.override_from_source(A, 1.f, 0.f);  // BlendWeight 0: no LerpTo at all
  ASSERT_EQ(none.entries().size(), 1u);
  ContributingLuts over;
  over.override_from_source(A, 0.5f, 3.f);  // BlendWeight clamped to 1
  expect_table(generate_final_table(over.entries()), {A}, {0.5f, 0.5f});
  ContributingLuts high;
  high.override_from_source(A, 7.f, 0.5f);  // intensity clamped to 1, times 0.5
  expect_table(generate_final_table(high.entries()), {A}, {0.5f, 0.5f});
}

// §2.8's sequences.
TEST(LutBlendTable, Sequences) {
  expect_table(table_of({}), {}, {1.f});                                       // S1
  expect_table(table_of({{A, 0.f}}), {}, {1.f});                               // S2
  expect_table(table_of({{A, 0.5f}}), {A}, {0.5f, 0.5f});                      // S3
  expect_table(table_of({{A, 1.f}}), {A}, {0.f, 1.f});                         // S4
  expect_table(table_of({{A, .5f}, {B, .5f}}), {B, A}, {0.25f, 0.5f, 0.25f});  // S5
  expect_table(table_of({{A, .5f}, {B, .5f}, {C, .5f}}), {C, B, A},
               {0.125f, 0.5f, 0.25f, 0.125f});  // S6
  expect_table(table_of({{A, .5f}, {B, .5f}, {C, .5f}, {D, .5f}}), {D, C, B, A},
               {0.0625f, 0.5f, 0.25f, 0.125f, 0.0625f});  // S7
  // S8: five textures, A dropped (table full); sum 0.96875 normalised by the float 1/S.
  expect_table(table_of({{A, .5f}, {B, .5f}, {C, .5f}, {D, .5f}, {E, .5f}}), {E, D, C, B},
               {0.0322580636f, 0.516129017f, 0.258064508f, 0.129032254f, 0.0645161271f});
  // S9: A replaces the neutral (a = 1), then B at 0.5 ties with A: the later entry wins.
  expect_table(table_of({{A, 1.f}, {B, .5f}}), {B, A}, {0.f, 0.5f, 0.5f});
  // S10: the same LUT twice accumulates in its one entry.
  expect_table(table_of({{A, .5f}, {A, .5f}}), {A}, {0.25f, 0.75f});
  // S11: B below 1/512 is dropped; the rest normalised by 1/0.999.
  const LutBlendTable s11 = table_of({{A, .5f}, {B, .001f}});
  ASSERT_EQ(s11.count, 2);
  EXPECT_EQ(s11.lut[1], A);
  EXPECT_NEAR(s11.weight[0], 0.5f, 1e-7f);
  EXPECT_NEAR(s11.weight[1], 0.5f, 1e-7f);
}

TEST(LutBlendTable, ThresholdIsOneOver512) {
  // Entries exactly at 1/512 are kept, just below are dropped (the test is "< 1/512").
  const float t = 1.0f / 512.0f;
  std::vector<hdrc::ref::LutContribution> at = {{kNeutralLut, 1.f - t}, {A, t}};
  EXPECT_EQ(generate_final_table(at).count, 2);
  std::vector<hdrc::ref::LutContribution> below = {{kNeutralLut, 1.f - t},
                                                   {A, std::nextafter(t, 0.f)}};
  EXPECT_EQ(generate_final_table(below).count, 1);
}

TEST(LutBlendTable, VanishingSumFallsBackToNeutral) {
  // No neutral entry and every texture below the threshold: S = 0 ≤ 0.001 → neutral only.
  std::vector<hdrc::ref::LutContribution> weak = {{A, 0.001f}, {B, 0.0015f}};
  expect_table(generate_final_table(weak), {}, {1.f});
  // No neutral entry and one texture at 0.002: S = 0.002 > 0.001, kept and normalised to 1.
  std::vector<hdrc::ref::LutContribution> small = {{A, 0.002f}};
  const LutBlendTable t = generate_final_table(small);
  ASSERT_EQ(t.count, 2);
  EXPECT_EQ(t.weight[0], 0.f);
  EXPECT_NEAR(t.weight[1], 1.f, 1e-7f);
}

TEST(LutBlendTable, ReplaceRuleJustAbove254Over255) {
  ContributingLuts list;
  list.lerp_to(A, 0.5f);
  list.lerp_to(B, std::nextafter(254.f / 255.f, 1.f));
  ASSERT_EQ(list.entries().size(), 1u);
  EXPECT_EQ(list.entries()[0].lut, B);
  EXPECT_EQ(list.entries()[0].weight, 1.f);
  ContributingLuts at;
  at.lerp_to(A, 0.5f);
  at.lerp_to(B, 254.f / 255.f);  // not above: scaled and appended
  EXPECT_EQ(at.entries().size(), 3u);
}

TEST(LutBlendTable, ResourcelessTexturesAreSkipped) {
  ContributingLuts list;
  list.lerp_to(A, 0.5f);
  list.lerp_to(B, 0.5f);
  const std::vector<bool> resources = {true, false};  // B has no render resource
  expect_table(generate_final_table(list.entries(), &resources), {A}, {0.25f / 0.5f, 0.25f / 0.5f});
  // The neutral slot takes the first neutral entry only.
  std::vector<hdrc::ref::LutContribution> two_neutral = {
      {kNeutralLut, 0.25f}, {A, 0.5f}, {kNeutralLut, 0.25f}};
  expect_table(generate_final_table(two_neutral), {A},
               {0.25f * (1.0f / 0.75f), 0.5f * (1.0f / 0.75f)});
}

}  // namespace
