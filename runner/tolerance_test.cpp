// The tolerance policy as data: the JSON form, its pinned error messages (file, pointer, value,
// valid choices), layering over a base, and the overlays of cases/tolerance_overlays.json.
#include "runner/tolerance.h"

#include <gtest/gtest.h>

namespace {

using json = nlohmann::ordered_json;
using hdrc::Metric;

struct BadTolerance {
  const char* name;
  const char* json;
  const char* error;
};

const BadTolerance kBad[] = {
    {"not_object", R"(3)",
     "t.json: /tolerance: a tolerance is an object, got number 3; valid choices: an object with "
     "keys linear_abs, linear_rel, pq_code10, pq_code12, delta_e_itp, dither, rel_floor, "
     "pq_near_black, reason"},
    {"unknown_key", R"({"pq_code": 1, "reason": "x"})",
     "t.json: /tolerance/pq_code: unknown key 'pq_code'; valid choices: linear_abs, linear_rel, "
     "pq_code10, pq_code12, delta_e_itp, dither, rel_floor, pq_near_black, reason"},
    {"negative", R"({"pq_code10": -1, "reason": "x"})",
     "t.json: /tolerance/pq_code10: pq_code10 -1 is negative; valid choices: a number >= 0"},
    {"string", R"({"linear_rel": "1e-5", "reason": "x"})",
     "t.json: /tolerance/linear_rel: linear_rel must be a number, null or an object, got string "
     "\"1e-5\"; valid choices: a number >= 0 (the max), null (not judged) or {max, "
     "allowed_fraction, hard, warn}"},
    {"unknown_limit_key", R"({"delta_e_itp": {"mx": 1}, "reason": "x"})",
     "t.json: /tolerance/delta_e_itp/mx: unknown key 'mx'; valid choices: max, allowed_fraction, "
     "hard, warn"},
    {"fraction_over_one", R"({"linear_rel": {"allowed_fraction": 2, "hard": 1}, "reason": "x"})",
     "t.json: /tolerance/linear_rel/allowed_fraction: allowed_fraction 2 is over 1; valid "
     "choices: a number from 0 to 1"},
    {"fraction_without_hard",
     R"({"linear_rel": {"max": 1e-5, "allowed_fraction": 0.01}, "reason": "x"})",
     "t.json: /tolerance/linear_rel: linear_rel: allowed_fraction 0.01 needs a hard cap, or the "
     "allowed values could be off by any amount; valid choices: add \"hard\": a number >= max"},
    {"hard_below_max", R"({"pq_code10": {"max": 1, "hard": 0.5}, "reason": "x"})",
     "t.json: /tolerance/pq_code10: pq_code10: hard 0.5 is below max 1; valid choices: hard >= "
     "max"},
    {"warn_above_max", R"({"pq_code10": {"max": 1, "warn": 2}, "reason": "x"})",
     "t.json: /tolerance/pq_code10: pq_code10: warn 2 is above max 1; a warn level sits below "
     "the fail limit; valid choices: warn <= max"},
    {"no_reason", R"({"linear_rel": 1e-5})",
     "t.json: /tolerance/reason: a tolerance must say why (measured error and its cause); valid "
     "choices: a non-empty string"},
    {"near_black_without_delta_e", R"({"pq_near_black": 0.04, "reason": "x"})",
     "t.json: /tolerance/pq_near_black: pq_near_black 0.04 needs delta_e_itp and linear_rel (or "
     "linear_abs) judged with a max: the floor applies where they agree that a pixel is right; "
     "valid choices: set delta_e_itp and linear_rel, or \"pq_near_black\": null"},
    {"near_black_negative", R"({"pq_near_black": -1, "reason": "x"})",
     "t.json: /tolerance/pq_near_black: pq_near_black -1 is negative; valid choices: a number "
     ">= 0"},
    {"null_floor", R"({"rel_floor": null, "reason": "x"})",
     "t.json: /tolerance/rel_floor: rel_floor must be a number, got null null; valid choices: a "
     "number >= 0"},
};

class ToleranceErrors : public ::testing::TestWithParam<BadTolerance> {};

TEST_P(ToleranceErrors, PinnedMessage) {
  const auto r = hdrc::parse_tolerance(json::parse(GetParam().json), "t.json", "/tolerance");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().to_string(), GetParam().error);
}

INSTANTIATE_TEST_SUITE_P(All, ToleranceErrors, ::testing::ValuesIn(kBad),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(Tolerance, ParsesEveryCriterionOverTheDefault) {
  const auto r = hdrc::parse_tolerance(json::parse(R"({
      "linear_rel": 2.5e-4,
      "pq_code10": {"max": 0.025, "allowed_fraction": 0.001, "hard": 0.5, "warn": 0.02},
      "delta_e_itp": {"warn": 0.5},
      "rel_floor": 1e-4,
      "reason": "measured"})"),
                                       "cases/a.json", "/tolerance");
  ASSERT_TRUE(r.ok()) << r.error().to_string();
  const int pq = static_cast<int>(Metric::kPqCode10);
  EXPECT_EQ(r->linear_rel, 2.5e-4);
  EXPECT_EQ(r->pq_code10, 0.025);
  EXPECT_EQ(r->allowed_fraction[pq], 0.001);
  EXPECT_EQ(r->hard[pq], 0.5);
  EXPECT_EQ(r->warn[pq], 0.02);
  EXPECT_EQ(r->warn[static_cast<int>(Metric::kDeltaEItp)], 0.5);
  EXPECT_FALSE(r->delta_e_itp < hdrc::kNotJudged);  // a warn level only
  EXPECT_TRUE(r->judged(Metric::kDeltaEItp));
  EXPECT_FALSE(r->judged(Metric::kLinearAbs));
  EXPECT_EQ(r->rel_floor, 1e-4);
  EXPECT_EQ(r->reason, "measured");
  EXPECT_EQ(r->source, "cases/a.json: /tolerance");
  // Keys left out keep the base: the default's pq_code10 0.05 and floor.
  const auto d = hdrc::parse_tolerance(json::parse(R"({"linear_rel": 1e-3, "reason": "r"})"), "f",
                                       "/tolerance");
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(d->pq_code10, hdrc::default_tolerance_policy().pq_code10);
  EXPECT_EQ(d->rel_floor, hdrc::default_tolerance_policy().rel_floor);
  // null: not judged.
  const auto n = hdrc::parse_tolerance(json::parse(R"({"pq_code10": null, "reason": "r"})"), "f",
                                       "/tolerance");
  ASSERT_TRUE(n.ok());
  EXPECT_FALSE(n->judged(Metric::kPqCode10));
  // The near-black floor over delta_e_itp and linear_rel; null removes it.
  const auto nb = hdrc::parse_tolerance(
      json::parse(R"({"delta_e_itp": 3e-4, "pq_near_black": 0.0407, "reason": "r"})"), "f",
      "/tolerance");
  ASSERT_TRUE(nb.ok()) << nb.error().to_string();
  EXPECT_EQ(nb->pq_near_black, 0.0407);
  EXPECT_EQ(hdrc::tolerance_json(*nb)["pq_near_black"], 0.0407);
  const auto off = hdrc::parse_tolerance(json::parse(R"({"pq_near_black": null, "reason": "r"})"),
                                         "f", "/tolerance", *nb);
  ASSERT_TRUE(off.ok()) << off.error().to_string();
  EXPECT_EQ(off->pq_near_black, 0.0);
  EXPECT_TRUE(hdrc::tolerance_json(*off)["pq_near_black"].is_null());
}

hdrc::Case shaper_case(const std::string& id) {
  hdrc::Case c;
  c.id = id;
  c.stage = hdrc::find_stage("shaper");
  c.tolerance = hdrc::default_tolerance_policy();
  c.tolerance.source = "cases/x.json: /tolerance";
  c.tolerance.reason = "measured";
  return c;
}

TEST(ToleranceOverlays, MatchAndLayerWithReasons) {
  std::vector<hdrc::Error> errors;
  const auto overlays = hdrc::parse_tolerance_overlays("ov.json", R"({
    "overlays": [
      {"engine": "vulkan", "device": "*NVIDIA*",
       "tolerance": {"pq_code10": 0.1, "reason": "NVIDIA's pow is 2 ulp"}},
      {"stage": "shaper", "cases": "tonemap/shaper_pq/*",
       "tolerance": {"linear_rel": 1e-3, "reason": "PQ decode near peak"}}
    ]})",
                                                       &errors);
  ASSERT_TRUE(errors.empty()) << errors[0].to_string();
  ASSERT_EQ(overlays.size(), 2u);
  const hdrc::Case c = shaper_case("tonemap/shaper_pq/dev3_log_ramp");
  auto t = hdrc::apply_overlays(c, "vulkan", "NVIDIA GeForce RTX 4090", overlays);
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t->pq_code10, 0.1);
  EXPECT_EQ(t->linear_rel, 1e-3);
  EXPECT_EQ(t->source,
            "cases/x.json: /tolerance + overlay ov.json: /overlays/0/tolerance + overlay ov.json: "
            "/overlays/1/tolerance");
  EXPECT_EQ(t->reason, "measured; overlay: NVIDIA's pow is 2 ulp; overlay: PQ decode near peak");
  // lavapipe: only the stage overlay applies.
  t = hdrc::apply_overlays(c, "vulkan", "llvmpipe (LLVM 15.0.6, 256 bits)", overlays);
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t->pq_code10, c.tolerance.pq_code10);
  EXPECT_EQ(t->linear_rel, 1e-3);
  // Another case: nothing applies.
  t = hdrc::apply_overlays(shaper_case("tonemap/shaper_log/dev0"), "reference", "cpu", overlays);
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t->source, "cases/x.json: /tolerance");
}

TEST(ToleranceOverlays, EveryOverlayNeedsASelectorAndAReason) {
  std::vector<hdrc::Error> errors;
  hdrc::parse_tolerance_overlays("ov.json", R"({
    "overlays": [
      {"tolerance": {"pq_code10": 0.1, "reason": "x"}},
      {"engine": "vulkan", "tolerance": {"pq_code10": 0.1}},
      {"stage": "shapr", "tolerance": {"pq_code10": 0.1, "reason": "x"}},
      {"engine": "vulkan", "gpu": "x", "tolerance": {"reason": "x"}}
    ]})",
                                 &errors);
  ASSERT_EQ(errors.size(), 4u);
  EXPECT_EQ(errors[0].to_string(),
            "ov.json: /overlays/0: an overlay must select what it applies to (it would change "
            "every tolerance of the suite); valid choices: one or more of stage, cases, engine, "
            "device");
  EXPECT_EQ(errors[1].to_string(),
            "ov.json: /overlays/1/tolerance/reason: a tolerance must say why (measured error and "
            "its cause); valid choices: a non-empty string");
  EXPECT_EQ(errors[2].pointer, "/overlays/2/stage");
  EXPECT_EQ(errors[3].to_string(),
            "ov.json: /overlays/3/gpu: unknown key 'gpu'; valid choices: stage, cases, engine, "
            "device, tolerance");
}

TEST(ToleranceOverlays, TheSuitesOverlayFileLoads) {
  std::vector<hdrc::Error> errors;
  hdrc::load_tolerance_overlays(std::string(HDRC_SOURCE_DIR) + "/cases", &errors);
  for (const auto& e : errors) ADD_FAILURE() << e.to_string();
}

TEST(Tolerance, JsonFormNamesEveryCriterion) {
  hdrc::Tolerance t = hdrc::default_tolerance_policy();
  t.hard[static_cast<int>(Metric::kPqCode10)] = 1;
  const json j = hdrc::tolerance_json(t);
  EXPECT_TRUE(j["linear_abs"].is_null());
  EXPECT_EQ(j["linear_rel"]["max"], 1e-5);
  EXPECT_TRUE(j["linear_rel"]["hard"].is_null());
  EXPECT_EQ(j["pq_code10"]["hard"], 1.0);
  EXPECT_EQ(j["source"], "default");
  // The JSON form parses back to the same criteria.
  json again = j;
  again.erase("source");
  const auto back = hdrc::parse_tolerance(again, "f", "", hdrc::Tolerance{});
  ASSERT_TRUE(back.ok()) << back.error().to_string();
  EXPECT_EQ(back->linear_rel, t.linear_rel);
  EXPECT_EQ(back->hard, t.hard);
  EXPECT_EQ(back->rel_floor, t.rel_floor);
}

}  // namespace
