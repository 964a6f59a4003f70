// Loader errors, pinned: each bad input gives one error naming the file, the JSON pointer, the
// offending value and the valid choices.
#include "runner/case_loader.h"

#include <gtest/gtest.h>

#include <filesystem>

#ifndef HDRC_SOURCE_DIR
#error "HDRC_SOURCE_DIR must be defined"
#endif

namespace {

const std::string kCasesDir = std::string(HDRC_SOURCE_DIR) + "/cases";

struct BadCase {
  const char* name;
  const char* json;
  const char* expected;  // the full error line
};

void PrintTo(const BadCase& bc, std::ostream* os) {
  *os << bc.name;
}

const BadCase kBadCases[] = {
    {"malformed_json", R"({"stage": "shaper",)",
     "t.json: malformed JSON: [json.exception.parse_error.101] parse error at line 1, column 20: "
     "syntax error while parsing object key - unexpected end of input; expected string literal"},
    {"not_an_object", R"([1, 2])", "t.json: a case file is a JSON object, got array"},
    {"unknown_stage", R"({"stage": "tonemapp", "input": {"stimulus": "log_ramp"}})",
     "t.json: /stage: unknown stage \"tonemapp\"; valid choices: shaper, linear_device, "
     "combine_luts, tonemap, dither, ui_composite, visualize_hdr"},
    {"missing_stage", R"({"input": {"stimulus": "log_ramp"}})",
     "t.json: /stage: missing stage; valid choices: shaper, linear_device, combine_luts, tonemap, "
     "dither, ui_composite, visualize_hdr"},
    {"unknown_key", R"({"stage": "shaper", "inptu": 1, "input": {"stimulus": "log_ramp"}})",
     "t.json: /inptu: unknown key 'inptu'; valid choices: $schema, description, stage, cvars, "
     "settings, input, bloom, bloom_dirt, matrix, tolerance"},
    {"unknown_cvar",
     R"({"stage": "shaper", "cvars": {"r.HDR.Display.OutputDevise": 3}, "input": {"stimulus": "log_ramp"}})",
     "t.json: /cvars/r.HDR.Display.OutputDevise: unknown cvar 'r.HDR.Display.OutputDevise'; valid "
     "choices: nearest: r.HDR.Display.OutputDevice, r.HDR.Display.MaxLuminance, "
     "r.HDR.Display.MidLuminance"},
    {"cvar_out_of_range",
     R"({"stage": "shaper", "cvars": {"r.HDR.Display.OutputDevice": 10}, "input": {"stimulus": "log_ramp"}})",
     "t.json: /cvars/r.HDR.Display.OutputDevice: cvar r.HDR.Display.OutputDevice = 10 is out of "
     "range; valid choices: 0 to 9"},
    {"cvar_not_integer",
     R"({"stage": "shaper", "cvars": {"r.HDR.Display.ColorGamut": 1.5}, "input": {"stimulus": "log_ramp"}})",
     "t.json: /cvars/r.HDR.Display.ColorGamut: cvar r.HDR.Display.ColorGamut is an integer, got "
     "1.5; valid choices: integers 0 to 4"},
    {"cvar_wrong_type",
     R"({"stage": "shaper", "cvars": {"r.HDR.Display.ColorGamut": "2"}, "input": {"stimulus": "log_ramp"}})",
     "t.json: /cvars/r.HDR.Display.ColorGamut: expected a number, got string \"2\""},
    {"matrix_value_out_of_range",
     R"({"stage": "shaper", "matrix": {"cvars": {"r.HDR.Display.ColorGamut": [0, 7]}}, "input": {"stimulus": "log_ramp"}})",
     "t.json: /matrix/cvars/r.HDR.Display.ColorGamut/1: cvar r.HDR.Display.ColorGamut = 7 is out "
     "of range; valid choices: 0 to 4"},
    {"device_not_in_stage",
     R"({"stage": "linear_device", "matrix": {"cvars": {"r.HDR.Display.OutputDevice": [8, 3]}}, "input": {"stimulus": "log_ramp"}})",
     "t.json: /matrix/cvars/r.HDR.Display.OutputDevice/1: stage linear_device is not defined for "
     "output device 3; valid choices: 7, 8"},
    {"unknown_matrix_mode",
     R"({"stage": "shaper", "matrix": {"mode": "pairwize", "cvars": {"r.LUT.Size": [16]}}, "input": {"stimulus": "log_ramp"}})",
     "t.json: /matrix/mode: unknown matrix mode \"pairwize\"; valid choices: full"},
    {"unknown_stimulus", R"({"stage": "shaper", "input": {"stimulus": "rampp"}})",
     "t.json: /input/stimulus: unknown stimulus \"rampp\"; valid choices: log_ramp, special_ramp, "
     "pq_codes, ui_overlay"},
    {"missing_input_file", R"({"stage": "shaper", "input": {"file": "inputs/missing.exr"}})",
     "t.json: /input/file: input file \"inputs/missing.exr\" does not exist (looked for "
     "CASES/inputs/missing.exr)"},
    {"input_leaves_cases", R"({"stage": "shaper", "input": {"file": "../README.md"}})",
     "t.json: /input/file: input path \"../README.md\" leaves the cases directory; valid choices: "
     "a "
     "relative path under CASES"},
    {"missing_input", R"({"stage": "shaper"})",
     "t.json: /input: missing input; valid choices: {\"stimulus\": log_ramp, special_ramp, "
     "pq_codes, ui_overlay} or {\"file\": PATH}"},
    {"bad_width", R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 0}})",
     "t.json: /input/width: width 0 is not valid; valid choices: integers 1 to 8192"},
    {"tolerance_without_reason",
     R"({"stage": "shaper", "input": {"stimulus": "log_ramp"}, "tolerance": {"linear_rel": 1e-5}})",
     "t.json: /tolerance/reason: a tolerance must say why (measured error and its cause); valid "
     "choices: a non-empty string"},
    {"negative_tolerance",
     R"({"stage": "shaper", "input": {"stimulus": "log_ramp"}, "tolerance": {"pq_code10": -1, "reason": "x"}})",
     "t.json: /tolerance/pq_code10: pq_code10 -1 is negative; valid choices: a number >= 0"},
};

class LoaderErrors : public ::testing::TestWithParam<BadCase> {};

TEST_P(LoaderErrors, PinnedMessage) {
  const BadCase& bc = GetParam();
  std::vector<hdrc::Error> errors;
  auto cases = hdrc::parse_case_file("t.json", bc.json, kCasesDir, "t", &errors);
  EXPECT_TRUE(cases.empty());
  ASSERT_EQ(errors.size(), 1u);
  std::string got = errors[0].to_string();
  for (size_t at; (at = got.find(kCasesDir)) != std::string::npos;)
    got.replace(at, kCasesDir.size(), "CASES");
  EXPECT_EQ(got, bc.expected);
}

INSTANTIATE_TEST_SUITE_P(Table, LoaderErrors, ::testing::ValuesIn(kBadCases),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(CaseLoader, MatrixExpandsToReadableStableIds) {
  std::vector<hdrc::Error> errors;
  auto cases = hdrc::parse_case_file(
      "t.json",
      R"({"stage": "linear_device", "matrix": {"cvars": {"r.HDR.Display.OutputDevice": [7, 8],
          "r.HDR.Display.ColorGamut": [0, 2]}, "inputs": [{"stimulus": "log_ramp"},
          {"stimulus": "special_ramp", "width": 32}]}})",
      kCasesDir, "tonemap/linear", &errors);
  ASSERT_TRUE(errors.empty()) << errors[0].to_string();
  ASSERT_EQ(cases.size(), 8u);
  EXPECT_EQ(cases[0].id, "tonemap/linear/dev7_gamut0_log_ramp");
  EXPECT_EQ(cases[1].id, "tonemap/linear/dev7_gamut0_special_ramp");
  EXPECT_EQ(cases[7].id, "tonemap/linear/dev8_gamut2_special_ramp");
  EXPECT_EQ(cases[7].cvars.get_int("r.HDR.Display.ColorGamut"), 2);
  EXPECT_EQ(cases[7].input.width, 32);
  EXPECT_EQ(cases[0].tolerance.source, "default");
}

TEST(CaseLoader, TheDefaultSuiteLoads) {
  auto loaded = hdrc::load_cases(kCasesDir);
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.to_string();
  // shaper 10 devices x 2 inputs, linear 2 x 5 x 2, LUT 10 x 5 + 2 x 3, tonemap 10 x 2,
  // dither 2, degenerate 1, UI composite 2 x 2 x 2 + 2, VisualizeHDR 2 x 3, tonemap effects 2.
  EXPECT_EQ(loaded.cases.size(), 20u + 20u + 56u + 20u + 2u + 1u + 10u + 6u + 2u);
  for (const auto& c : loaded.cases) EXPECT_NE(c.tolerance.source, "default") << c.id;
}

TEST(CaseLoader, FilterIsAGlob) {
  EXPECT_TRUE(hdrc::matches_filter("tonemap/shaper/dev3_log_ramp", "tonemap/shaper/*"));
  EXPECT_TRUE(hdrc::matches_filter("tonemap/shaper/dev3_log_ramp", "*dev3*"));
  EXPECT_FALSE(hdrc::matches_filter("tonemap/shaper/dev3_log_ramp", "*dev4*"));
  EXPECT_TRUE(hdrc::matches_filter("anything", ""));
}

}  // namespace
