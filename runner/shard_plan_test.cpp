// The shard planner (runner/run.h: plan_shards, static_case_cost): longest processing time first,
// each case to the least loaded shard, and the static estimate built from each stage's measured
// figures (core/pipeline.h StageCost) over the sizes its pipeline resolves.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/pipeline.h"
#include "runner/case_loader.h"
#include "runner/run.h"

namespace {

const std::string kCasesDir = std::string(HDRC_SOURCE_DIR) + "/cases";

std::vector<hdrc::Case> cases_of(const std::string& text) {
  std::vector<hdrc::Error> errors;
  auto cases = hdrc::parse_case_file("t.json", text, kCasesDir, "t", &errors);
  EXPECT_TRUE(errors.empty()) << errors[0].to_string();
  return cases;
}

// Graham's LPT by hand: 5 (b) to shard 0; 4 (d) to 1; then the 3s in id order: a to 1 (4 < 5),
// c to 0 (5 < 7), e to 1 (7 < 8). Loads 8 and 10.
TEST(ShardPlan, LongestFirstEachToTheLeastLoaded) {
  const std::vector<double> costs = {3, 5, 3, 4, 3};
  const std::vector<std::string> ids = {"a", "b", "c", "d", "e"};
  EXPECT_EQ(hdrc::plan_shards(costs, ids, 2), (std::vector<int>{1, 0, 0, 1, 1}));
  EXPECT_EQ(hdrc::plan_shards(costs, ids, 1), (std::vector<int>{0, 0, 0, 0, 0}));
  // More shards than cases: one case each, the dearest in shard 0; the rest empty.
  EXPECT_EQ(hdrc::plan_shards({1, 2, 3}, {"x", "y", "z"}, 5), (std::vector<int>{2, 1, 0}));
  // Equal costs: by id, and equal loads go to the lowest shard.
  EXPECT_EQ(hdrc::plan_shards({1, 1, 1, 1}, {"d", "c", "b", "a"}, 2),
            (std::vector<int>{1, 0, 1, 0}));
}

// The estimate follows the stage's declared figures: a bake stage's lattice is r.LUT.Size³, so
// 64 costs (64³ - 32³) per-pixel figures more than 32; a degenerate case (never evaluated: an
// ACES device with HDR output off) costs nothing; an image stage grows with its pixels.
TEST(ShardPlan, StaticCostFromTheStageFigures) {
  const auto luts =
      cases_of(R"({"stage": "combine_luts", "matrix": {"cvars": {"r.LUT.Size": [32, 64]}}})");
  ASSERT_EQ(luts.size(), 2u);
  const hdrc::StageCost k = hdrc::stage_cost(*luts[0].stage);
  ASSERT_GT(k.us_per_pixel, 0);
  EXPECT_NEAR(hdrc::static_case_cost(luts[1]) - hdrc::static_case_cost(luts[0]),
              k.us_per_pixel * (64.0 * 64 * 64 - 32.0 * 32 * 32) * 1e-6, 1e-12);
  EXPECT_NEAR(hdrc::static_case_cost(luts[0]), (k.us + k.us_per_pixel * 32 * 32 * 32) * 1e-6,
              1e-12);

  const auto degenerate = cases_of(
      R"({"stage": "tonemap", "cvars": {"r.HDR.EnableHDROutput": 0,
          "r.HDR.Display.OutputDevice": 3}, "input": {"stimulus": "log_ramp"}})");
  ASSERT_EQ(degenerate.size(), 1u);
  EXPECT_EQ(hdrc::static_case_cost(degenerate[0]), 0);

  const auto ramps = cases_of(
      R"({"stage": "tonemap", "matrix": {"inputs": [{"stimulus": "log_ramp", "width": 64,
          "height": 4}, {"stimulus": "log_ramp", "width": 256, "height": 4}]}})");
  ASSERT_EQ(ramps.size(), 2u);
  const hdrc::StageCost t = hdrc::stage_cost(*ramps[0].stage);
  EXPECT_NEAR(hdrc::static_case_cost(ramps[1]) - hdrc::static_case_cost(ramps[0]),
              t.us_per_pixel * (256 - 64) * 4 * 1e-6, 1e-12);
}

// Every pipeline's figures name its own stages: a renamed stage would silently take the dearest
// figures (stage_cost), as a stage not measured yet does.
TEST(ShardPlan, StageFiguresNameTheirPipelinesStages) {
  for (const hdrc::Pipeline* p : hdrc::pipeline_table())
    for (const hdrc::StageCost& c : p->stage_costs) {
      EXPECT_NE(hdrc::find_stage(*p, c.stage), nullptr) << p->name << ": " << c.stage;
      EXPECT_GT(c.us, 0) << c.stage;
    }
}

}  // namespace
