// Loader errors, pinned: each bad input gives one error naming the file, the JSON pointer, the
// offending value and the valid choices.
#include "runner/case_loader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <tuple>

#include "core/pipeline.h"
#include "runner/stimuli.h"

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
     "t.json: /stage: unknown stage \"tonemapp\", did you mean 'tonemap'?; valid choices: "
     "shaper, linear_device, combine_luts, tonemap, dither, ui_composite, visualize_hdr"},
    {"missing_stage", R"({"input": {"stimulus": "log_ramp"}})",
     "t.json: /stage: missing stage; valid choices: shaper, linear_device, combine_luts, tonemap, "
     "dither, ui_composite, visualize_hdr"},
    {"unknown_key", R"({"stage": "shaper", "inptu": 1, "input": {"stimulus": "log_ramp"}})",
     "t.json: /inptu: unknown key 'inptu', did you mean 'input'?; valid choices: $schema, "
     "description, pipeline, stage, preset, cvars, settings, input, bloom, bloom_dirt, ui, lut, "
     "lut_blend, "
     "matrix, tolerance, pins_nonfinite, tier"},
    {"ui_on_another_stage",
     R"({"stage": "shaper", "ui": {"stimulus": "ui_overlay"}, "input": {"stimulus": "log_ramp"}})",
     "t.json: /ui: ui is an input of a UI composite stage only; valid choices: ui_composite, "
     "ue58_ui_composite"},
    {"ui_overlay_parameter_out_of_range",
     R"({"stage": "ui_composite", "ui": {"stimulus": "ui_overlay", "transparent_rgb": 2}, "input": {"stimulus": "pq_codes", "width": 32, "height": 32}})",
     "t.json: /ui/transparent_rgb: parameter transparent_rgb = 2 is out of range; valid choices: 0 "
     "to 1"},
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
     "t.json: /matrix/mode: unknown matrix mode \"pairwize\", did you mean 'pairwise'?; valid "
     "choices: full, pairwise, covering"},
    {"unknown_stimulus", R"({"stage": "shaper", "input": {"stimulus": "log_rmap"}})",
     "t.json: /input/stimulus: unknown stimulus \"log_rmap\", did you mean 'log_ramp'?; valid "
     "choices: log_ramp, special_ramp, pq_codes, hue_sweep, colorchecker, primaries, near_black, "
     "above_peak, pq_lattice, random, ui_overlay, ui_srgb_codes, bloom"},
    {"missing_input_file", R"({"stage": "shaper", "input": {"file": "inputs/missing.exr"}})",
     "t.json: /input/file: input file \"inputs/missing.exr\" does not exist (looked for "
     "CASES/inputs/missing.exr)"},
    {"input_leaves_cases", R"({"stage": "shaper", "input": {"file": "../README.md"}})",
     "t.json: /input/file: input path \"../README.md\" leaves the cases directory; valid choices: "
     "a relative path under CASES"},
    {"missing_input", R"({"stage": "shaper"})",
     "t.json: /input: missing input; valid choices: {\"stimulus\": log_ramp, special_ramp, "
     "pq_codes, hue_sweep, colorchecker, primaries, near_black, above_peak, pq_lattice, random, "
     "ui_overlay, ui_srgb_codes, bloom} or {\"file\": PATH}"},
    {"bad_width", R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 0}})",
     "t.json: /input/width: width 0 is not valid; valid choices: integers 1 to 8192"},
    {"tolerance_without_reason",
     R"({"stage": "shaper", "input": {"stimulus": "log_ramp"}, "tolerance": {"linear_rel": 1e-5}})",
     "t.json: /tolerance/reason: a tolerance must say why (measured error and its cause); valid "
     "choices: a non-empty string"},
    {"negative_tolerance",
     R"({"stage": "shaper", "input": {"stimulus": "log_ramp"}, "tolerance": {"pq_code10": -1, "reason": "x"}})",
     "t.json: /tolerance/pq_code10: pq_code10 -1 is negative; valid choices: a number >= 0"},
    {"unknown_stimulus_parameter",
     R"({"stage": "shaper", "input": {"stimulus": "hue_sweep", "luminance": [1]}})",
     "t.json: /input/luminance: unknown key 'luminance' of stimulus hue_sweep, did you mean "
     "'luminances'?; valid choices: stimulus, width, height, name, luminances, saturation"},
    {"stimulus_parameter_out_of_range",
     R"({"stage": "shaper", "input": {"stimulus": "hue_sweep", "saturation": 2}})",
     "t.json: /input/saturation: parameter saturation = 2 is out of range; valid choices: 0 to 1"},
    {"unknown_stimulus_choice",
     R"({"stage": "shaper", "input": {"stimulus": "primaries", "gamut": "ap0"}})",
     "t.json: /input/gamut: unknown gamut \"ap0\" of stimulus primaries, did you mean 'ap1'?; "
     "valid choices: srgb, ap1, rec2020"},
    {"stimulus_list_not_array",
     R"({"stage": "shaper", "input": {"stimulus": "colorchecker", "exposures": 2}})",
     "t.json: /input/exposures: expected a non-empty array of numbers, got 2; valid choices: EV "
     "stops"},
    {"pq_codes_too_small",
     R"({"stage": "shaper", "input": {"stimulus": "pq_codes", "width": 16, "height": 16}})",
     "t.json: /input: pq_codes needs at least 1024 pixels to hold every 10-bit code, got 16x16; "
     "valid choices: width x height >= 1024"},
    {"unknown_tolerance_set",
     R"({"stage": "shaper", "input": {"stimulus": "log_ramp"}, "tolerance": "shaper_qp"})",
     "t.json: /tolerance: unknown tolerance set \"shaper_qp\", did you mean 'shaper_pq'? (sets are "
     "defined in CASES/defaults.json: /tolerances); valid choices: combine_luts, "
     "combine_luts_storage, combine_luts_storage_linear, dither, "
     "linear_dev7, linear_dev8, operators, pq_grading, shaper_log, shaper_pq, tonemap, "
     "ue58_combine_luts, ue58_tonemap, ue58_ui_composite, ue58_visualize_hdr, ui_composite, "
     "unity_urp_grading, unity_urp_lut, visualize_hdr"},
    {"unknown_preset",
     R"({"stage": "shaper", "preset": "hdr01", "input": {"stimulus": "log_ramp"}})",
     "t.json: /preset: unknown preset \"hdr01\", did you mean 'hdr10'? (presets are defined in "
     "CASES/defaults.json: /presets); valid choices: hdr10, hdr_on, hdr_on_rec2020"},
    {"unknown_full_dimension",
     R"({"stage": "shaper", "matrix": {"mode": "pairwise", "full": ["r.LUT.Sise"], "cvars": {"r.LUT.Size": [16, 32]}}, "input": {"stimulus": "log_ramp"}})",
     "t.json: /matrix/full/0: unknown matrix dimension \"r.LUT.Sise\", did you mean "
     "'r.LUT.Size'?; valid choices: r.LUT.Size"},
    {"full_needs_pairwise",
     R"({"stage": "shaper", "matrix": {"full": ["r.LUT.Size"], "cvars": {"r.LUT.Size": [16, 32]}}, "input": {"stimulus": "log_ramp"}})",
     "t.json: /matrix/full: \"full\" names the dimensions a pairwise matrix crosses exhaustively; "
     "this matrix is already full; valid choices: \"mode\": \"pairwise\" or \"covering\""},
    {"matrix_value_twice",
     R"({"stage": "shaper", "matrix": {"cvars": {"r.LUT.Size": [16, 32, 16]}}, "input": {"stimulus": "log_ramp"}})",
     "t.json: /matrix/cvars/r.LUT.Size/2: value 16 is listed twice"},
    {"matrix_setting_arity",
     R"({"stage": "shaper", "matrix": {"settings": {"ColorGain": [[1, 1, 1, 1], 2]}}, "input": {"stimulus": "log_ramp"}})",
     "t.json: /matrix/settings/ColorGain/1: setting ColorGain takes 4 numbers [r, g, b, a]; valid "
     "choices: an array of 4 numbers"},
    {"unknown_setting",
     R"({"stage": "shaper", "settings": {"LUTFromat": 1}, "input": {"stimulus": "log_ramp"}})",
     "t.json: /settings/LUTFromat: unknown setting 'LUTFromat'; valid choices: nearest: LUTFormat, "
     "LUTLayout, WhiteTemp"},
    {"bloom_outside_tonemap",
     R"({"stage": "shaper", "input": {"stimulus": "log_ramp"}, "bloom": {"stimulus": "bloom"}})",
     "t.json: /bloom: bloom is an input of a Tonemap stage only; valid choices: tonemap, "
     "ue58_tonemap"},
    {"input_name_with_slash",
     R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "name": "a/b"}})",
     "t.json: /input/name: an input name is a non-empty string without '/', ' ' or glob "
     "characters, got \"a/b\""},
    {"unknown_tolerance_key",
     R"({"stage": "shaper", "input": {"stimulus": "log_ramp"}, "tolerance": {"pq_code_10": 1, "reason": "x"}})",
     "t.json: /tolerance/pq_code_10: unknown key 'pq_code_10'; valid choices: linear_abs, "
     "linear_rel, pq_code10, pq_code12, delta_e_itp, dither, rel_floor, pq_near_black, reason"},
    {"lut_missing",
     R"({"pipeline": "pq_grading", "stage": "pq_grade", "input": {"stimulus": "log_ramp"}})",
     "t.json: /lut: stage pq_grade needs a user LUT; valid choices: \"lut\": a .cube path under "
     "cases/, or \"matrix\": {\"luts\": [...]}"},
    {"lut_on_stage_without_one",
     R"({"stage": "shaper", "input": {"stimulus": "log_ramp"}, "lut": "lut/cube/pq_identity_33.cube"})",
     "t.json: /lut: stage shaper takes no user LUT; valid choices: stages that take one: "
     "combine_luts (ue55), pq_grade (pq_grading)"},
    {"color_grading_intensity_out_of_range",
     R"({"stage": "combine_luts", "lut": "lut/cube/ue16_hue.cube", "settings": {"ColorGradingIntensity": 1.5}})",
     "t.json: /settings/ColorGradingIntensity: setting ColorGradingIntensity = 1.5 is out of "
     "range; valid choices: 0 to 1"},
    {"lut_blend_on_stage_without_one",
     R"({"pipeline": "pq_grading", "stage": "pq_grade", "input": {"stimulus": "log_ramp"}, "lut": "lut/cube/pq_identity_33.cube", "lut_blend": [{"lut": "lut/cube/pq_look_33.cube", "weight": 0.5}]})",
     "t.json: /lut_blend: stage pq_grade blends no LUTs; valid choices: stages that do: "
     "combine_luts"},
    {"lut_blend_weight_out_of_range",
     R"({"stage": "combine_luts", "lut": "lut/cube/ue16_hue.cube", "lut_blend": [{"lut": "lut/cube/ue16_square.cube", "weight": 1.5}]})",
     "t.json: /lut_blend/0/weight: expected a LerpTo weight in [0, 1], got 1.5; valid choices: a "
     "number in [0, 1]"},
    {"lut_blend_entry_without_weight",
     R"({"stage": "combine_luts", "lut_blend": [{"lut": "lut/cube/ue16_square.cube"}]})",
     "t.json: /lut_blend/0: expected {\"lut\": PATH, \"weight\": W}, got "
     "{\"lut\":\"lut/cube/ue16_square.cube\"}; valid choices: keys lut, weight"},
    {"lut_blend_empty", R"({"stage": "combine_luts", "lut_blend": []})",
     "t.json: /lut_blend: expected an array of 1-8 {\"lut\": PATH, \"weight\": W} objects, got "
     "[]"},
    {"lut_blend_wrong_size",
     R"({"stage": "combine_luts", "lut_blend": [{"lut": "lut/cube/identity_17.cube", "weight": 0.5}]})",
     "t.json: /lut_blend/0/lut: LUT file \"lut/cube/identity_17.cube\" has LUT_3D_SIZE 17; stage "
     "combine_luts takes a 16^3 LUT; valid choices: a .cube file under CASES with one 3-D table of "
     "LUT_3D_SIZE 16"},
    {"lut_not_a_string",
     R"({"pipeline": "pq_grading", "stage": "pq_grade", "input": {"stimulus": "log_ramp"}, "lut": 3})",
     "t.json: /lut: expected a .cube path string, got 3; valid choices: a .cube file under CASES "
     "with one 3-D table of LUT_3D_SIZE 33"},
    {"lut_outside_cases",
     R"({"pipeline": "pq_grading", "stage": "pq_grade", "input": {"stimulus": "log_ramp"}, "lut": "../x.cube"})",
     "t.json: /lut: LUT path \"../x.cube\" leaves the cases directory; valid choices: a .cube file "
     "under CASES with one 3-D table of LUT_3D_SIZE 33"},
    {"lut_not_cube",
     R"({"pipeline": "pq_grading", "stage": "pq_grade", "input": {"stimulus": "log_ramp"}, "lut": "lut/devices.json"})",
     "t.json: /lut: LUT path \"lut/devices.json\" does not name a .cube file; valid choices: a "
     ".cube file under CASES with one 3-D table of LUT_3D_SIZE 33"},
    {"lut_file_missing",
     R"({"pipeline": "pq_grading", "stage": "pq_grade", "input": {"stimulus": "log_ramp"}, "lut": "lut/cube/nope_33.cube"})",
     "t.json: /lut: LUT file \"lut/cube/nope_33.cube\" does not exist (looked for "
     "CASES/lut/cube/nope_33.cube); valid choices: a .cube file under CASES with one 3-D table of "
     "LUT_3D_SIZE 33"},
    {"lut_1d_only",
     R"({"pipeline": "pq_grading", "stage": "pq_grade", "input": {"stimulus": "log_ramp"}, "lut": "lut/cube/gamma_1d.cube"})",
     "t.json: /lut: LUT file \"lut/cube/gamma_1d.cube\" has no 3-D table (LUT_1D_SIZE 1024 only: a "
     "1-D LUT); valid choices: a .cube file under CASES with one 3-D table of LUT_3D_SIZE 33"},
    {"lut_with_shaper",
     R"({"pipeline": "pq_grading", "stage": "pq_grade", "input": {"stimulus": "log_ramp"}, "lut": "lut/cube/resolve_shaper.cube"})",
     "t.json: /lut: LUT file \"lut/cube/resolve_shaper.cube\" has a 1-D shaper (LUT_1D_SIZE 256) "
     "before its 3-D table, which the strip texture has no place for; valid choices: a .cube file "
     "under CASES with one 3-D table of LUT_3D_SIZE 33"},
    {"lut_wrong_size",
     R"({"pipeline": "pq_grading", "stage": "pq_grade", "input": {"stimulus": "log_ramp"}, "lut": "lut/cube/identity_17.cube"})",
     "t.json: /lut: LUT file \"lut/cube/identity_17.cube\" has LUT_3D_SIZE 17; stage pq_grade "
     "takes a 33^3 LUT; valid choices: a .cube file under CASES with one 3-D table of LUT_3D_SIZE "
     "33"},
    {"matrix_lut_listed_twice",
     R"({"pipeline": "pq_grading", "stage": "pq_grade", "input": {"stimulus": "log_ramp"}, "matrix": {"luts": ["lut/cube/pq_hue_33.cube", "lut/cube/pq_hue_33.cube"]}})",
     "t.json: /matrix/luts/1: LUT \"lut/cube/pq_hue_33.cube\" is listed twice (or shares its file "
     "name); valid choices: distinct .cube file names"},
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

// Pairwise: the `full` dimensions crossed, every pair of the others covered, settings in the
// matrix named in the ids.
TEST(CaseLoader, PairwiseMatrixCrossesFullDimensionsAndCoversPairs) {
  std::vector<hdrc::Error> errors;
  auto cases = hdrc::parse_case_file("t.json",
                                     R"({"stage": "combine_luts", "matrix": {"mode": "pairwise",
          "full": ["r.HDR.EnableHDROutput", "r.HDR.Display.OutputDevice"],
          "cvars": {"r.HDR.EnableHDROutput": [1, 0], "r.HDR.Display.OutputDevice": [0, 3, 8],
                    "r.LUT.Size": [16, 32]},
          "settings": {"LUTFormat": [0, 1, 2], "LUTLayout": [0, 1]}}})",
                                     kCasesDir, "lut/x", &errors);
  ASSERT_TRUE(errors.empty()) << errors[0].to_string();
  std::set<std::pair<int, int>> hdr_dev;
  std::set<std::tuple<int, int, int>> size_fmt, fmt_layout, dev_fmt;
  for (const auto& c : cases) {
    const int hdr = c.cvars.get_int("r.HDR.EnableHDROutput");
    const int dev = c.cvars.get_int("r.HDR.Display.OutputDevice");
    const int size = c.cvars.get_int("r.LUT.Size");
    const int fmt = static_cast<int>(c.settings.get("LUTFormat"));
    const int layout = static_cast<int>(c.settings.get("LUTLayout"));
    hdr_dev.emplace(hdr, dev);
    size_fmt.emplace(0, size, fmt);
    fmt_layout.emplace(0, fmt, layout);
    dev_fmt.emplace(0, dev, fmt);
    EXPECT_EQ(c.id, "lut/x/hdr" + std::to_string(hdr) + "_dev" + std::to_string(dev) + "_lut" +
                        std::to_string(size) + "_fmt" + std::to_string(fmt) + "_layout" +
                        std::to_string(layout));
  }
  EXPECT_EQ(hdr_dev.size(), 6u);
  EXPECT_EQ(size_fmt.size(), 6u);
  EXPECT_EQ(fmt_layout.size(), 6u);
  EXPECT_EQ(dev_fmt.size(), 9u);
  EXPECT_LE(cases.size(), 12u) << "pairwise, not the 72 of the full cross product";
  // Stable: the same file expands to the same ids.
  std::vector<hdrc::Error> again_errors;
  auto again = hdrc::parse_case_file("t.json",
                                     R"({"stage": "combine_luts", "matrix": {"mode": "pairwise",
          "full": ["r.HDR.EnableHDROutput", "r.HDR.Display.OutputDevice"],
          "cvars": {"r.HDR.EnableHDROutput": [1, 0], "r.HDR.Display.OutputDevice": [0, 3, 8],
                    "r.LUT.Size": [16, 32]},
          "settings": {"LUTFormat": [0, 1, 2], "LUTLayout": [0, 1]}}})",
                                     kCasesDir, "lut/x", &again_errors);
  ASSERT_EQ(again.size(), cases.size());
  for (size_t i = 0; i < cases.size(); ++i) EXPECT_EQ(again[i].id, cases[i].id);
}

// Tolerance sets and presets come from cases/defaults.json; the case's own values override a
// preset; a tolerance can start from a set and change one number (with its own reason).
TEST(CaseLoader, NamedTolerancesAndPresets) {
  std::vector<hdrc::Error> errors;
  auto cases = hdrc::parse_case_file(
      "t.json",
      R"({"stage": "tonemap", "preset": "hdr10", "cvars": {"r.HDR.Display.ColorGamut": 0},
          "input": {"stimulus": "log_ramp"}, "tolerance": "shaper_pq"})",
      kCasesDir, "t", &errors);
  ASSERT_TRUE(errors.empty()) << errors[0].to_string();
  ASSERT_EQ(cases.size(), 1u);
  EXPECT_EQ(cases[0].cvars.get_int("r.HDR.EnableHDROutput"), 1);
  EXPECT_EQ(cases[0].cvars.get_int("r.HDR.Display.OutputDevice"), 3);
  EXPECT_EQ(cases[0].cvars.get_int("r.HDR.Display.ColorGamut"), 0);
  EXPECT_EQ(cases[0].tolerance.source, kCasesDir + "/defaults.json: /tolerances/shaper_pq");
  EXPECT_EQ(cases[0].tolerance.linear_rel, 0.00025);
  auto over = hdrc::parse_case_file("t.json",
                                    R"({"stage": "tonemap", "input": {"stimulus": "log_ramp"},
          "tolerance": {"base": "shaper_pq", "pq_code10": 0.5, "reason": "wider here because"}})",
                                    kCasesDir, "t", &errors);
  ASSERT_TRUE(errors.empty()) << errors[0].to_string();
  ASSERT_EQ(over.size(), 1u);
  EXPECT_EQ(over[0].tolerance.pq_code10, 0.5);
  EXPECT_EQ(over[0].tolerance.linear_rel, 0.00025);
  EXPECT_EQ(over[0].tolerance.reason, "wider here because");
  EXPECT_NE(over[0].tolerance.source.find("over " + kCasesDir + "/defaults.json"),
            std::string::npos)
      << over[0].tolerance.source;
}

TEST(CaseLoader, StimulusParametersAndInputNames) {
  std::vector<hdrc::Error> errors;
  auto cases = hdrc::parse_case_file("t.json",
                                     R"({"stage": "shaper", "matrix": {"inputs": [
          {"stimulus": "primaries", "gamut": "rec2020", "scales": [1, 10]},
          {"stimulus": "colorchecker", "exposures": [-1, 1]},
          {"stimulus": "pq_lattice", "n": 4},
          {"stimulus": "random", "seed": 3, "name": "noise"},
          {"file": "inputs/corner_gradient.exr"}]}})",
                                     kCasesDir, "t", &errors);
  ASSERT_TRUE(errors.empty()) << errors[0].to_string();
  ASSERT_EQ(cases.size(), 5u);
  EXPECT_EQ(cases[0].id, "t/primaries_rec2020_scales1-10");
  EXPECT_EQ(cases[0].input.params.at("gamut"), std::vector<double>{2});
  EXPECT_EQ(cases[1].id, "t/colorchecker_exposures-1-1");
  EXPECT_EQ(cases[2].id, "t/pq_lattice_n4");
  EXPECT_EQ(cases[2].input.width, 16);
  EXPECT_EQ(cases[2].input.height, 4);
  EXPECT_EQ(cases[3].id, "t/noise");
  EXPECT_EQ(cases[4].id, "t/corner_gradient");
  auto resolved = hdrc::resolve_case(cases[0]);
  ASSERT_TRUE(resolved.ok()) << resolved.error().to_string();
  EXPECT_LT(resolved->input.px(8, 0)[0], 0.0) << "Rec.2020 green has negative sRGB red";
  auto file = hdrc::resolve_case(cases[4]);
  ASSERT_TRUE(file.ok()) << file.error().to_string();
  EXPECT_EQ(file->input.width, 32);
}

// Every error of a file is reported, and none of its cases is produced.
// A user LUT that does not parse: the error names the case file and pointer, then the .cube, its
// line and what core/cube found there. A file named in a matrix is read once and shared by the
// cases it expands to; /lut and /matrix/luts together are refused.
TEST(CaseLoader, UserLutErrorsNameTheCubeLineAndLutsAreShared) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("hdrc_user_lut_" + std::to_string(::getpid()));
  fs::create_directories(dir / "lut");
  std::ofstream(dir / "lut/bad_33.cube") << "LUT_3D_SIZE 33\n0 0 zero\n";
  fs::copy_file(kCasesDir + "/lut/cube/pq_identity_33.cube", dir / "lut/id_33.cube");
  fs::copy_file(kCasesDir + "/lut/cube/pq_hue_33.cube", dir / "lut/hue_33.cube");
  const std::string head =
      R"({"pipeline": "pq_grading", "stage": "pq_grade", "input": {"stimulus": "log_ramp"}, )";
  std::vector<hdrc::Error> errors;
  auto cases = hdrc::parse_case_file("t.json", head + R"("lut": "lut/bad_33.cube"})", dir.string(),
                                     "t", &errors);
  EXPECT_TRUE(cases.empty());
  ASSERT_EQ(errors.size(), 1u);
  const std::string got = errors[0].to_string();
  EXPECT_EQ(got.rfind("t.json: /lut: LUT file \"lut/bad_33.cube\": ", 0), 0u) << got;
  EXPECT_NE(got.find("bad_33.cube: line 2: "), std::string::npos) << got;
  EXPECT_NE(got.find("zero"), std::string::npos) << got;

  errors.clear();
  cases = hdrc::parse_case_file(
      "t.json",
      head +
          R"("matrix": {"settings": {"Display": ["SDR", "HDR"]}, "luts": ["lut/id_33.cube", "lut/hue_33.cube"]}})",
      dir.string(), "t", &errors);
  ASSERT_TRUE(errors.empty()) << errors[0].to_string();
  ASSERT_EQ(cases.size(), 4u);
  EXPECT_EQ(cases[0].id, "t/display0_lutid_33_log_ramp");
  EXPECT_EQ(cases[0].lut, cases[2].lut);  // one UserLut per file
  EXPECT_NE(cases[0].lut, cases[1].lut);
  EXPECT_EQ(cases[1].lut->label, "hue_33");
  EXPECT_EQ(cases[1].lut->size, 33);
  EXPECT_EQ(cases[1].lut->table.size(), 33u * 33 * 33);

  errors.clear();
  cases = hdrc::parse_case_file(
      "t.json", head + R"("lut": "lut/id_33.cube", "matrix": {"luts": ["lut/hue_33.cube"]}})",
      dir.string(), "t", &errors);
  EXPECT_TRUE(cases.empty());
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].to_string(),
            "t.json: /matrix/luts: a case names either /lut or /matrix/luts");
  fs::remove_all(dir);
}

TEST(CaseLoader, ReportsEveryErrorOfAFile) {
  std::vector<hdrc::Error> errors;
  auto cases =
      hdrc::parse_case_file("t.json",
                            R"({"stage": "shaper", "cvars": {"r.LUT.Size": 8, "r.Colr.Min": 0},
          "input": {"stimulus": "log_ramp", "height": -1}})",
                            kCasesDir, "t", &errors);
  EXPECT_TRUE(cases.empty());
  EXPECT_EQ(errors.size(), 3u);
}

TEST(CaseLoader, TheDefaultSuiteLoads) {
  auto loaded = hdrc::load_cases(kCasesDir);
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.to_string();
  // Per file. Full matrices: devices x gamuts (lut/devices 10 x 5), devices x inputs (shaper
  // 3 x 8 and 7 x 8, linear 5 gamuts x 8, tonemap 10 x 2, stimuli 2 x 9, out_of_gamut 3 x 2,
  // effects 2). Pairwise ones are pinned by the covering design (runner/pairwise.h): display is
  // exactly its 100 crossed combinations, the others are at or near their lower bound (cvars: 10
  // devices x 5 gamuts; dither 10 x 4; visualize 10 x 3; UI 4 devices x 4 levels).
  std::map<std::string, size_t> per_file;
  for (const auto& c : loaded.cases) ++per_file[c.id.substr(0, c.id.rfind('/'))];
  const std::map<std::string, size_t> expected = {{"lut/devices", 50},
                                                  {"lut/grading_cc", 14},
                                                  {"lut/grading_film", 15},
                                                  {"lut/grading_white", 14},
                                                  {"lut/storage", 13},
                                                  {"lut/user_lut/blend3", 5},
                                                  {"lut/user_lut/blend4", 5},
                                                  {"lut/user_lut/blend5", 5},
                                                  {"lut/user_lut/intensity", 45},
                                                  {"lut/user_lut/storage", 12},
                                                  {"lut/user_lut/tie", 2},
                                                  {"lut/working_color_space", 71},
                                                  {"lut/working_color_space_custom", 50},
                                                  {"operators/exposure", 30},
                                                  {"operators/film_presets", 15},
                                                  {"operators/hable_blog2010", 3},
                                                  {"operators/hable_gdc2010", 3},
                                                  {"operators/operators", 30},
                                                  {"operators/parameters", 13},
                                                  {"pq_grading/amplify", 25},
                                                  {"pq_grading/isolate/pq_m1_m2_roundtrip", 1},
                                                  {"pq_grading/isolate/srgb_exponent", 1},
                                                  {"pq_grading/luts", 80},
                                                  {"tonemap/cvars", 55},
                                                  {"tonemap/degenerate", 1},
                                                  {"tonemap/display", 100},
                                                  {"tonemap/dither", 40},
                                                  {"tonemap/effects", 2},
                                                  {"tonemap/linear_dev7", 40},
                                                  {"tonemap/linear_dev8", 40},
                                                  {"tonemap/nonfinite_pin", 1},
                                                  {"tonemap/out_of_gamut", 6},
                                                  {"tonemap/shaper_log", 24},
                                                  {"tonemap/shaper_pq", 56},
                                                  {"tonemap/stimuli", 18},
                                                  {"tonemap/tonemap", 20},
                                                  {"tonemap/working_color_space", 71},
                                                  {"tonemap/working_color_space_dither", 35},
                                                  {"tonemap/working_color_space_linear_dev7", 14},
                                                  {"tonemap/working_color_space_linear_dev8", 14},
                                                  {"tonemap/working_color_space_shaper", 21},
                                                  {"tonemap/working_color_space_shaper_pq", 21},
                                                  {"ui/color_deficiency", 13},
                                                  {"ui/composite", 16},
                                                  {"ui/working_color_space", 28},
                                                  {"unity_urp/channel_mixer", 10},
                                                  {"unity_urp/color_adjustments", 17},
                                                  {"unity_urp/graded_look", 54},
                                                  {"unity_urp/grading_modes", 90},
                                                  {"unity_urp/lift_gamma_gain", 10},
                                                  {"unity_urp/lut_modes", 18},
                                                  {"unity_urp/shadows_midtones_highlights", 10},
                                                  {"unity_urp/split_toning", 10},
                                                  {"ue58/devices", 200},
                                                  {"ue58/dither", 10},
                                                  {"ue58/dither_8bit", 2},
                                                  {"ue58/grading", 9},
                                                  {"ue58/hdr_display", 24},
                                                  {"ue58/isolate/ui_srgb_linear_segment", 1},
                                                  {"ue58/isolate/ui_srgb_offset", 1},
                                                  {"ue58/shaper_eotf", 14},
                                                  {"ue58/tonemap_devices", 80},
                                                  {"ue58/tonemap_effects", 4},
                                                  {"ue58/tonemap_stimuli", 33},
                                                  {"ue58/tonemap_vignette", 10},
                                                  {"ue58/tonemap_vignette_texture", 6},
                                                  {"ue58/ui_composite", 17},
                                                  {"ue58/ui_composite_cvd", 4},
                                                  {"ue58/visualize_hdr", 6},
                                                  {"ue58/visualize_hdr_devices", 1},
                                                  {"ue58/visualize_hdr_sdr", 2},
                                                  {"visualize/pre_exposure", 8},
                                                  {"visualize/visualize_hdr", 30},
                                                  {"visualize/working_color_space", 21}};
  EXPECT_EQ(per_file, expected);
  EXPECT_EQ(loaded.cases.size(), 1840u);
  for (const auto& c : loaded.cases) EXPECT_NE(c.tolerance.source, "default") << c.id;
}

// cases/schema.json documents what the loader accepts: the same stages, stimuli and their
// parameters, matrix modes and top-level keys (the loader's own list, read from its error).
TEST(CaseLoader, SchemaMatchesTheLoader) {
  std::ifstream f(kCasesDir + "/schema.json");
  const nlohmann::ordered_json schema = nlohmann::ordered_json::parse(f);
  std::vector<std::string> stages;
  for (const hdrc::Pipeline* p : hdrc::pipeline_table())
    for (const auto& s : p->stages()) stages.emplace_back(s.name);
  EXPECT_EQ(schema["$defs"]["stage"]["enum"].get<std::vector<std::string>>(), stages);
  std::vector<std::string> stimuli;
  for (const auto& v : schema["$defs"]["input"]["oneOf"]) {
    if (!v["properties"].contains("stimulus")) continue;
    const std::string name = v["properties"]["stimulus"]["const"];
    stimuli.push_back(name);
    const hdrc::StimulusInfo* info = hdrc::find_stimulus(name);
    ASSERT_NE(info, nullptr) << name;
    std::set<std::string> params, want;
    for (auto it = v["properties"].begin(); it != v["properties"].end(); ++it)
      if (it.key() != "stimulus" && it.key() != "width" && it.key() != "height" &&
          it.key() != "name")
        params.insert(it.key());
    for (const auto& p : info->params) want.emplace(p.name);
    EXPECT_EQ(params, want) << name;
  }
  std::vector<std::string> table;
  for (const auto& s : hdrc::stimulus_table()) table.emplace_back(s.name);
  EXPECT_EQ(stimuli, table);
  EXPECT_EQ(schema["$defs"]["matrix"]["properties"]["mode"]["enum"],
            nlohmann::ordered_json::array({"full", "pairwise", "covering"}));
  std::vector<hdrc::Error> errors;
  hdrc::parse_case_file("t.json", R"({"stage": "shaper", "zzz": 1})", kCasesDir, "t", &errors);
  ASSERT_FALSE(errors.empty());
  std::string keys;
  for (auto it = schema["properties"].begin(); it != schema["properties"].end(); ++it)
    keys += (keys.empty() ? "" : ", ") + it.key();
  EXPECT_EQ(errors[0].choices, keys);
}

TEST(CaseLoader, SuiteConfigurationFilesAreNotCases) {
  EXPECT_TRUE(hdrc::is_suite_config_file(kCasesDir, kCasesDir + "/defaults.json"));
  EXPECT_TRUE(hdrc::is_suite_config_file(kCasesDir, kCasesDir + "/coverage.json"));
  EXPECT_TRUE(hdrc::is_suite_config_file(kCasesDir, kCasesDir + "/schema.json"));
  EXPECT_FALSE(hdrc::is_suite_config_file(kCasesDir, kCasesDir + "/lut/defaults.json"));
  EXPECT_FALSE(hdrc::is_suite_config_file(kCasesDir, kCasesDir + "/a.json"));
}

TEST(CaseLoader, FilterIsAGlob) {
  EXPECT_TRUE(hdrc::matches_filter("tonemap/shaper/dev3_log_ramp", "tonemap/shaper/*"));
  EXPECT_TRUE(hdrc::matches_filter("tonemap/shaper/dev3_log_ramp", "*dev3*"));
  EXPECT_FALSE(hdrc::matches_filter("tonemap/shaper/dev3_log_ramp", "*dev4*"));
  EXPECT_TRUE(hdrc::matches_filter("anything", ""));
}

}  // namespace
