// Pipelines as modules (core/pipeline.h): the registry, case files that name their pipeline, the
// CLI's per-pipeline commands, and planted defects in the Unity URP and operators shaders that the
// suite must catch in named cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "core/pipeline.h"
#include "reference/operators/operators.h"
#include "runner/case_loader.h"
#include "runner/json_read.h"
#include "runner/test_support.h"

namespace {

namespace fs = std::filesystem;
using namespace hdrc::test;  // runner/test_support.h

const std::string kCasesDir = std::string(HDRC_SOURCE_DIR) + "/cases";

// The registry lists UE 5.5's pipeline first (the default of a case file), then the others.
TEST(Pipelines, RegistryListsEveryPipelineUe55First) {
  std::vector<std::string> names;
  for (const hdrc::Pipeline* p : hdrc::pipeline_table()) names.emplace_back(p->name);
  EXPECT_EQ(names,
            (std::vector<std::string>{"ue55", "unity_urp", "operators", "pq_grading", "ue58"}));
  EXPECT_EQ(hdrc::default_pipeline().name, "ue55");
  EXPECT_EQ(hdrc::find_pipeline("nope"), nullptr);
}

// A stage name alone names its pipeline (results.json, tolerance overlays): no two pipelines
// share one, every stage knows its owner, and every pass shader exists in the suite's shaders.
TEST(Pipelines, StageNamesAreUniqueAndOwnedAndTheirShadersExist) {
  std::set<std::string> seen;
  for (const hdrc::Pipeline* p : hdrc::pipeline_table()) {
    ASSERT_FALSE(p->stages().empty()) << p->name;
    for (const hdrc::StageInfo& s : p->stages()) {
      EXPECT_TRUE(seen.insert(std::string(s.name)).second) << s.name << " is in two pipelines";
      EXPECT_EQ(s.pipeline, p->name) << s.name;
      EXPECT_EQ(&hdrc::pipeline_of(s), p) << s.name;
      EXPECT_EQ(hdrc::find_stage(s.name), &s) << s.name;
      EXPECT_TRUE(hdrc::missing_shaders(s, std::string(HDRC_SOURCE_DIR) + "/gpu/shaders").empty())
          << s.name;
      // UE 5.5's stages are its own enumerators; UE 5.8's are kOther or the UE family's
      // enumerator whose loader and engine path they share (ue58_ui_composite: kUiComposite,
      // docs/ue58-decisions.md H2; ue58_dither: kDither, whose runner judges the grain, I);
      // every other pipeline's are kOther.
      if (p->name == "ue55") {
        EXPECT_NE(s.id, hdrc::StageId::kOther) << s.name;
      } else if (p->name != "ue58") {
        EXPECT_EQ(s.id, hdrc::StageId::kOther) << s.name;
      }
    }
  }
}

// Every stage of every pipeline has cases in the default suite, and every pipeline but UE 5.5
// (whose case ids predate pipelines) keeps them under cases/<pipeline>/.
TEST(Pipelines, EveryStageHasCasesUnderItsPipelinesFolder) {
  const hdrc::LoadedCases loaded = hdrc::load_cases(kCasesDir);
  ASSERT_TRUE(loaded.errors.empty()) << loaded.errors[0].to_string();
  std::set<std::string> stages_with_cases;
  for (const hdrc::Case& c : loaded.cases) {
    stages_with_cases.insert(std::string(c.stage->name));
    const std::string pipeline(c.stage->pipeline);
    if (pipeline != "ue55") {
      EXPECT_EQ(c.id.rfind(pipeline + "/", 0), 0u) << c.id;
    }
  }
  for (const hdrc::Pipeline* p : hdrc::pipeline_table())
    for (const hdrc::StageInfo& s : p->stages())
      EXPECT_TRUE(stages_with_cases.count(std::string(s.name))) << s.name << " has no case";
}

// A case file names its pipeline; the errors name the file's field, the value and the choices.
TEST(Pipelines, CaseFilesNameTheirPipeline) {
  struct Row {
    const char* json;
    const char* pointer;
    const char* message;  // a part of the message
    const char* choices;  // a part of the valid choices
  };
  const Row rows[] = {
      {R"({"pipeline": "unity", "stage": "lut_bake"})", "/pipeline", "unknown pipeline \"unity\"",
       "ue55, unity_urp, operators, pq_grading"},
      {R"({"pipeline": 3, "stage": "lut_bake"})", "/pipeline", "unknown pipeline 3",
       "ue55, unity_urp, operators, pq_grading"},
      {R"({"stage": "lut_bake"})", "/stage",
       "unknown stage \"lut_bake\" (it is a stage of pipeline unity_urp: set "
       "\"pipeline\": \"unity_urp\")",
       "shaper, linear_device"},
      {R"({"pipeline": "operators", "stage": "tonemap"})", "/stage",
       "unknown stage \"tonemap\" of pipeline operators (it is a stage of pipeline ue55",
       "tone_curve"},
      {R"({"pipeline": "operators", "stage": "tone_curve", "cvars": {"r.LUT.Size": 32}})", "/cvars",
       "pipeline operators has no cvars", "hdrconform cvars --pipeline operators"},
      {R"({"pipeline": "unity_urp", "stage": "lut_bake", "preset": "hdr_on"})", "/preset",
       "pipeline unity_urp has no cvars (presets set UE 5.5's cvars and settings)", "settings"},
      {R"({"pipeline": "unity_urp", "stage": "lut_bake", "settings": {"Contrast": 10}})",
       "/settings/Contrast", "unknown setting 'Contrast'", "ColorAdjustments.contrast"},
      {R"({"pipeline": "unity_urp", "stage": "lut_bake",
           "settings": {"Tonemapping.mode": "Filmic"}})",
       "/settings/Tonemapping.mode", "unknown Tonemapping.mode 'Filmic'",
       "None (0), Neutral (1), ACES (2)"},
      {R"({"pipeline": "operators", "stage": "tone_curve", "settings": {"Operator": 9}})",
       "/settings/Operator", "setting Operator = 9 is out of range", "0 to 5"},
  };
  for (const Row& row : rows) {
    std::vector<hdrc::Error> errors;
    hdrc::parse_case_file("t.json", row.json, kCasesDir, "x/t", &errors);
    ASSERT_FALSE(errors.empty()) << row.json;
    const hdrc::Error& e = errors[0];
    EXPECT_EQ(e.file, "t.json");
    EXPECT_EQ(e.pointer, row.pointer) << row.json;
    EXPECT_NE(e.message.find(row.message), std::string::npos) << e.to_string();
    EXPECT_NE(e.choices.find(row.choices), std::string::npos) << e.to_string();
  }
}

// A pipeline's settings are its own: a Unity case resolves to Unity's shader constants, with UE
// 5.5's settings untouched, and UE 5.5's default case still reads UE's table.
TEST(Pipelines, CasesResolveThroughTheirPipeline) {
  std::vector<hdrc::Error> errors;
  auto cases = hdrc::parse_case_file(
      "t.json",
      R"({"pipeline": "unity_urp", "stage": "lut_bake", "settings": {"LutSize": 16,
          "GradingMode": "LowDynamicRange", "ColorAdjustments.hueShift": 90}})",
      kCasesDir, "unity_urp/t", &errors);
  ASSERT_TRUE(errors.empty()) << errors[0].to_string();
  ASSERT_EQ(cases.size(), 1u);
  auto rc = hdrc::resolve_case(cases[0]);
  ASSERT_TRUE(rc) << rc.error().to_string();
  EXPECT_EQ(rc->params.lut_size, 16);
  EXPECT_EQ(rc->params.lut_layout, 1);             // Unity's H^2 x H strip
  EXPECT_EQ(rc->params.lut_format, 3);             // LDR grading: RGBA8 UNORM
  EXPECT_EQ(rc->params.urp_hue_sat_con[0], 0.25);  // ColorGradingLutPass: hueShift / 360
  EXPECT_EQ(rc->input.width, 16 * 16);             // the lattice, one texel per pixel
  EXPECT_EQ(rc->input.height, 16);
}

// `hdrconform pipelines` lists each pipeline with its stages and passes; `cvars --pipeline`
// prints that pipeline's settings with their named values; `list --pipeline` selects its cases.
TEST(Pipelines, CliListsAndSelectsPerPipeline) {
  const Ran p = run("pipelines");
  EXPECT_EQ(p.code, 0) << p.out;
  for (const char* want :
       {"ue55  Unreal Engine 5.5 HDR output (the default pipeline of a case)",
        "unity_urp  Unity URP colour grading", "operators  Classic tone-mapping operators",
        "passes: unity_urp/stages/lut_bake.comp -> unity_urp/stages/color_grading.comp",
        "passes: operators/stages/curve.comp"})
    EXPECT_NE(p.out.find(want), std::string::npos) << want << "\n" << p.out;
  const Ran c = run("cvars --pipeline unity_urp");
  EXPECT_EQ(c.code, 0) << c.out;
  EXPECT_NE(c.out.find("[LowDynamicRange (0), HighDynamicRange (1)]"), std::string::npos) << c.out;
  EXPECT_EQ(c.out.find("r.HDR.Display.OutputDevice"), std::string::npos) << c.out;
  const Ran l = run("list --pipeline operators");
  EXPECT_EQ(l.code, 0) << l.out;
  std::istringstream ids(l.out);
  size_t n = 0;
  for (std::string id; std::getline(ids, id); ++n) EXPECT_EQ(id.rfind("operators/", 0), 0u) << id;
  EXPECT_GT(n, 50u);
  const Ran bad = run("list --pipeline unreal");
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_NE(bad.out.find(
                "unknown pipeline 'unreal'; valid choices: ue55, unity_urp, operators, pq_grading"),
            std::string::npos)
      << bad.out;
}

// `coverage --pipeline NAME` checks that pipeline's cases against its own declaration
// (coverage_<name>.json): every declared value and required combination is covered.
TEST(Pipelines, CoverageIsCompletePerPipeline) {
  for (const char* pipeline : {"unity_urp", "operators", "pq_grading"}) {
    const Ran r = run(std::string("coverage --pipeline ") + pipeline);
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find(std::string("cases of pipeline ") + pipeline), std::string::npos) << r.out;
  }
  const Ran urp = run("coverage --pipeline unity_urp");
  EXPECT_NE(urp.out.find("ColorAdjustments.hueShift"), std::string::npos) << urp.out;
  EXPECT_EQ(urp.out.find("r.HDR.Display.OutputDevice"), std::string::npos) << urp.out;
  EXPECT_NE(urp.out.find("grading mode x tone mapping x LUT size"), std::string::npos) << urp.out;
  // A declaration naming another pipeline's setting is refused with the valid names.
  const fs::path dir = temp_dir("coverage_pipeline");
  fs::copy(kCasesDir, dir, fs::copy_options::recursive);
  std::string text = read(dir / "coverage_operators.json");
  const std::string from = "\"WhitePoint\"";
  text.replace(text.find(from), from.size(), "\"r.LUT.Size\"");
  write(dir / "coverage_operators.json", text);
  const Ran bad = run("coverage --pipeline operators --cases " + dir.string());
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_NE(bad.out.find("coverage_operators.json: /values/r.LUT.Size: unknown cvar or scalar "
                         "setting \"r.LUT.Size\""),
            std::string::npos)
      << bad.out;
  fs::remove_all(dir);
}

// `probe --pipeline NAME` sends colours through that pipeline's reference: Reinhard's x/(1+x)
// and Narkowicz's fit at hand-computed values, Unity's default HDR grading with the ACES tone
// map at 18 % grey (docs/spec/unity_urp.md §6.6: 0.1101979, 0.1101635, 0.1101414 for the bake's
// own lattice point; the lookup interpolates LogC-spaced texels).
TEST(Pipelines, ProbePerPipeline) {
  const fs::path dir = temp_dir("probe_pipeline");
  auto probe = [&](const std::string& args, const std::string& lines) {
    write(dir / "in.txt", lines);
    return run("probe " + args + " < " + (dir / "in.txt").string());
  };
  const Ran r = probe("--pipeline operators --setting Operator=Reinhard", "1 0.25 0\n3 0 0\n");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(r.out, "0.5 0.2 0\n0.75 0 0\n");
  const Ran n = probe("--pipeline operators --setting Operator=AcesNarkowicz", "1 1 1\n");
  EXPECT_EQ(n.code, 0) << n.out;
  EXPECT_EQ(n.out, "0.803797468 0.803797468 0.803797468\n");  // 127/158
  const Ran u = probe(
      "--pipeline unity_urp --setting GradingMode=HighDynamicRange --setting Tonemapping.mode=ACES",
      "0.18 0.18 0.18\n");
  EXPECT_EQ(u.code, 0) << u.out;
  double rgb[3] = {0, 0, 0};
  ASSERT_EQ(std::sscanf(u.out.c_str(), "%lf %lf %lf", &rgb[0], &rgb[1], &rgb[2]), 3) << u.out;
  // Measured (0.110441941, 0.111283369, 0.111195872): the 32^3 LUT's LogC-spaced, half-stored
  // texels interpolated at 18 % grey, within 1 % of the bake's lattice value.
  for (double v : rgb) EXPECT_NEAR(v, 0.1102, 2e-3) << u.out;
  // pq_grading with the identity .cube: 0.25 at Amplify 4 grades to 1, Narkowicz's fit gives
  // 2.54 / 3.16 = 127/158, RGB8's gamma (127/158)^(1/2.2) = 0.905492450 (hand-derived,
  // reference/pq_grading/pq_grading_test.cpp); without --cube the stage refuses.
  const std::string cube = std::string(HDRC_SOURCE_DIR) + "/cases/lut/cube/pq_identity_33.cube";
  const Ran pq = probe("--pipeline pq_grading --cube " + cube +
                           " --setting Amplify=4 --setting Display=SDR --setting BackBuffer=RGB8",
                       "0.25 0.25 0.25\n");
  EXPECT_EQ(pq.code, 0) << pq.out;
  EXPECT_EQ(pq.out, "0.90549245 0.90549245 0.90549245\n");
  const Ran no_cube = probe("--pipeline pq_grading", "0.25 0.25 0.25\n");
  EXPECT_EQ(no_cube.code, 2) << no_cube.out;
  EXPECT_NE(no_cube.out.find("--cube: stage pq_grade needs a user LUT"), std::string::npos)
      << no_cube.out;
  const Ran bad = probe("--pipeline unity_urp --stage tonemap", "0 0 0\n");
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_NE(bad.out.find("not a stage of pipeline unity_urp that reads colours; valid choices: "
                         "color_grading"),
            std::string::npos)
      << bad.out;
  fs::remove_all(dir);
}

// Runs one pipeline's cases with `from` replaced by `to` in a copy of the suite's shaders; the
// ids of the failing cases.
std::vector<std::string> failing_with_planted(const std::string& shader, const std::string& from,
                                              const std::string& to, const std::string& pipeline,
                                              std::string* out, nlohmann::json* results = nullptr) {
  return planted_shader_failures(shader, from, to, "--pipeline " + pipeline, out, 1, results);
}

bool contains(const std::vector<std::string>& ids, const std::string& id) {
  return std::find(ids.begin(), ids.end(), id) != ids.end();
}

// Unity's LogC3 constant c (0.244161, Color.hlsl: LogCToLinear / LinearToLogC) off in its 5th
// decimal: the HDR grading cases whose grade the LUT's LogC lattice carries fail (the uber pass
// encodes with the same constant the bake decodes with, so most of the change cancels; it shows
// where the grade is not the identity in LogC); no LDR case (no LogC there) fails.
TEST(Pipelines, PlantedUnityLogCConstantFailsHdrGradingCases) {
  std::string out;
  const auto failing =
      failing_with_planted("unity_urp/lib/unity_color.glsl", "const float URP_LOGC_C = 0.244161;",
                           "const float URP_LOGC_C = 0.244171;", "unity_urp", &out);
  EXPECT_GE(failing.size(), 5u) << out;
  EXPECT_TRUE(contains(failing, "unity_urp/graded_look/gradingmode1_mode2_postexposure0_hue_sweep"))
      << out;
  for (const auto& id : failing) EXPECT_EQ(id.find("gradingmode0"), std::string::npos) << id;
}

// The hue shift's single RotateHue wrap (Color.hlsl) replaced by a clamp: the cases that shift
// hue (hueShift 90, +-180 and the graded look) fail; the LUT cases at hueShift 0 do not.
TEST(Pipelines, PlantedHueShiftWrapFailsTheHueShiftCases) {
  std::string out;
  const auto failing =
      failing_with_planted("unity_urp/lib/unity_color.glsl",
                           "return value < low ? value + hi : (value > hi ? value - hi : value);",
                           "return clamp(value, low, hi);", "unity_urp", &out);
  EXPECT_TRUE(contains(failing,
                       "unity_urp/color_adjustments/"
                       "gradingmode0_mode2_temperature-100_tint0_contrast0_colorfilter1-1-1-1_"
                       "hueshift-180_saturation0"))
      << out;
  for (const auto& id : failing) {
    const bool shifts =
        id.find("hueshift0_") == std::string::npos &&
        (id.find("hueshift") != std::string::npos || id.find("graded_look") != std::string::npos);
    EXPECT_TRUE(shifts) << id << " fails without a hue shift";
  }
}

// Split toning's balance read with the wrong sign (LutBuilderHdr/Ldr: the luminance offset
// _SplitShadows.w): the split-toning cases with a balance and the graded look fail, none with
// balance 0.
TEST(Pipelines, PlantedSplitToningBalanceFailsTheBalanceCases) {
  std::string out;
  const auto failing = failing_with_planted(
      "unity_urp/lib/unity_grade.glsl", "float balance = P.urp_split_shadows.w;",
      "float balance = -P.urp_split_shadows.w;", "unity_urp", &out);
  EXPECT_TRUE(contains(failing, "unity_urp/graded_look/gradingmode1_mode2_postexposure0_log_ramp"))
      << out;
  bool split_case = false;
  for (const auto& id : failing) {
    EXPECT_TRUE(
        id.find("graded_look") != std::string::npos ||
        (id.find("split_toning") != std::string::npos && id.find("balance0_") == std::string::npos))
        << id;
    split_case |= id.find("split_toning") != std::string::npos;
  }
  EXPECT_TRUE(split_case) << out;
}

// Hable's A (shoulder strength 0.22) read 0.05 % high: every Hable case fails and no other
// operator's does.
TEST(Pipelines, PlantedHableConstantFailsOnlyTheHableCases) {
  std::string out;
  const auto failing =
      failing_with_planted("operators/lib/operators.glsl", "OpRational(P.op_hable_a,",
                           "OpRational(P.op_hable_a * 1.0005,", "operators", &out);
  EXPECT_TRUE(contains(failing, "operators/operators/operator2_log_ramp")) << out;
  EXPECT_GE(failing.size(), 10u) << out;
  for (const auto& id : failing) EXPECT_NE(id.find("/operator2_"), std::string::npos) << id;
  // Both published constant sets' cases see it.
  EXPECT_TRUE(contains(failing, "operators/hable_gdc2010/operator2_log_ramp")) << out;
  EXPECT_TRUE(contains(failing, "operators/hable_blog2010/operator2_log_ramp")) << out;
}

// Hable published two constant sets (docs/spec/operators.md, Hable): the GDC 2010 slides'
// (142-143) and the blog post's ("Filmic Tonemapping Operators", filmicworlds.com 2010). Each has
// its own case file, named after it, that writes every constant out: the settings of each case
// are exactly its set, and the GDC set is the settings' defaults.
TEST(Pipelines, HablesTwoConstantSetsEachHaveTheirCases) {
  const hdrc::LoadedCases loaded = hdrc::load_cases(kCasesDir);
  ASSERT_TRUE(loaded.errors.empty()) << loaded.errors[0].to_string();
  const std::vector<std::string> names = {"HableA", "HableB", "HableC", "HableD",
                                          "HableE", "HableF", "HableW", "ExposureBias"};
  const std::map<std::string, std::vector<double>> sets = {
      {"operators/hable_gdc2010/", {0.22, 0.30, 0.10, 0.20, 0.01, 0.30, 11.2, 2.0}},
      {"operators/hable_blog2010/", {0.15, 0.50, 0.10, 0.20, 0.02, 0.30, 11.2, 2.0}}};
  std::map<std::string, int> count;
  for (const hdrc::Case& c : loaded.cases) {
    for (const auto& [prefix, values] : sets) {
      if (c.id.rfind(prefix, 0) != 0) continue;
      ++count[prefix];
      EXPECT_EQ(c.settings.get("Operator"), 2.0) << c.id;
      for (size_t i = 0; i < names.size(); ++i)
        EXPECT_DOUBLE_EQ(c.settings.get(names[i]), values[i]) << c.id << " " << names[i];
    }
  }
  for (const auto& [prefix, values] : sets) EXPECT_EQ(count[prefix], 3) << prefix;
  // The defaults are the GDC set: a case that sets none of the constants runs it.
  const hdrc::ref::operators::HableParams defaults;
  EXPECT_EQ(defaults.curve.a, 0.22);
  EXPECT_EQ(defaults.curve.b, 0.30);
  EXPECT_EQ(defaults.curve.e, 0.01);
}

// pq_grading's user LUTs are no setting, so coverage_pq_grading.json cannot declare them: every
// test LUT meets every display mapping and back buffer here (the issue's full product), and every
// LUT every Amplify value. The isolating cases (pq_grading/isolate/: one constant each, with a
// LUT designed for it, docs/constant-sweep.md) are outside the product.
TEST(Pipelines, PqGradingCasesCrossEveryLutDisplayAndEncoding) {
  const hdrc::LoadedCases loaded = hdrc::load_cases(kCasesDir);
  ASSERT_TRUE(loaded.errors.empty()) << loaded.errors[0].to_string();
  std::set<std::string> luts;
  std::set<std::tuple<std::string, int, int>> product;
  std::set<std::pair<std::string, double>> amplify;
  for (const hdrc::Case& c : loaded.cases) {
    if (c.stage->name != "pq_grade" || c.id.rfind("pq_grading/isolate/", 0) == 0) continue;
    ASSERT_TRUE(c.lut) << c.id;
    luts.insert(c.lut->label);
    product.insert({c.lut->label, static_cast<int>(c.settings.get("Display")),
                    static_cast<int>(c.settings.get("BackBuffer"))});
    amplify.insert({c.lut->label, c.settings.get("Amplify")});
  }
  EXPECT_EQ(luts, (std::set<std::string>{"pq_clip_33", "pq_domain_33", "pq_hue_33",
                                         "pq_identity_33", "pq_look_33"}));
  EXPECT_EQ(product.size(), luts.size() * 2 * 4);
  EXPECT_EQ(amplify.size(), luts.size() * 5);
}

// Every stage of every pipeline has its candidate page, docs/candidates/<stage>.md, in the form of
// the others (its title names the stage; it says what the output is and which params.json fields
// apply), and the candidate protocol's page links it: from the pipeline table, so a new
// pipeline's stages are checked without a change here.
TEST(Pipelines, EveryStageHasACandidatePage) {
  const fs::path docs = fs::path(HDRC_SOURCE_DIR) / "docs";
  const std::string protocol = read(docs / "candidate-protocol.md");
  for (const hdrc::Pipeline* p : hdrc::pipeline_table())
    for (const hdrc::StageInfo& s : p->stages()) {
      const std::string name(s.name);
      const fs::path page = docs / "candidates" / (name + ".md");
      ASSERT_TRUE(fs::exists(page)) << p->name << " stage " << name << ": no " << page;
      const std::string text = read(page);
      EXPECT_EQ(text.rfind("# Stage `" + name + "`", 0), 0u) << page;
      EXPECT_NE(text.find("**Output**"), std::string::npos) << page;
      // UE 5.5's pages predate the rule: their fields are the cvars they name.
      if (p != &hdrc::default_pipeline()) {
        EXPECT_NE(text.find("`params.json` fields that apply"), std::string::npos) << page;
      }
      EXPECT_NE(protocol.find("(candidates/" + name + ".md)"), std::string::npos)
          << "docs/candidate-protocol.md does not link " << page;
    }
}

// The diagnosis hints (runner/diagnosis.h) results.json gives case `id`.
std::set<std::string> hints_of(const nlohmann::json& results, const std::string& id) {
  std::set<std::string> out;
  for (const auto& c : results["cases"])
    if (c["id"] == id)
      for (const auto& h : c["hints"]) out.insert(h["id"].get<std::string>());
  return out;
}

// The ids of pq_grading's cases in the default suite whose id contains `part` ("" for all).
std::vector<std::string> pq_case_ids(const std::string& part) {
  std::vector<std::string> ids;
  for (const hdrc::Case& c : hdrc::load_cases(kCasesDir).cases)
    if (c.stage->pipeline == "pq_grading" && c.id.find(part) != std::string::npos)
      ids.push_back(c.id);
  return ids;
}

// The .cube's red and blue swapped in pq_grading's LUT lookup (the coordinate .bgr): every case
// fails, the identity LUT's included (it then returns (b, g, r)): every stimulus has colour (the
// ramps' single-channel rows, the random colours, the hue sweeps).
TEST(Pipelines, PlantedRedBlueSwapInTheLutLookupFailsEveryCase) {
  std::string out;
  nlohmann::json results;
  const auto failing =
      failing_with_planted("pq_grading/lib/pq_grading.glsl", "  return pqg_sample_strip(t);",
                           "  return pqg_sample_strip(t.bgr);", "pq_grading", &out, &results);
  EXPECT_TRUE(contains(failing, "pq_grading/luts/display1_backbuffer0_lutpq_hue_33_random")) << out;
  // The diagnosis names it (docs/diagnosis.md): the lookup's coordinate swapped.
  EXPECT_EQ(hints_of(results, "pq_grading/luts/display1_backbuffer0_lutpq_hue_33_random"),
            std::set<std::string>{"input_swap_rb"});
  EXPECT_TRUE(contains(failing, "pq_grading/luts/display0_backbuffer2_lutpq_identity_33_hues"))
      << out;
  EXPECT_EQ(failing.size(), pq_case_ids("").size()) << out;
}

// Half a texel of offset in the strip sampling (UVW = t (N - 1)/N + 1/N instead of + 0.5/N):
// every LUT's cases fail, the identity's too.
TEST(Pipelines, PlantedHalfTexelOffsetInTheStripSamplingFailsEveryLut) {
  std::string out;
  nlohmann::json results;
  const auto failing = failing_with_planted(
      "pq_grading/lib/pq_grading.glsl", "vec3 uvw = t * ((n - 1.0) / n) + 0.5 / n;",
      "vec3 uvw = t * ((n - 1.0) / n) + 1.0 / n;", "pq_grading", &out, &results);
  EXPECT_TRUE(contains(failing, "pq_grading/luts/display1_backbuffer0_lutpq_identity_33_random"))
      << out;
  // The diagnosis names it (docs/diagnosis.md).
  for (const char* id : {"pq_grading/luts/display1_backbuffer0_lutpq_identity_33_random",
                         "pq_grading/luts/display1_backbuffer0_lutpq_hue_33_random"})
    EXPECT_EQ(hints_of(results, id), std::set<std::string>{"lut_half_texel_up"}) << id;
  for (const char* lut :
       {"lutpq_identity_33", "lutpq_look_33", "lutpq_hue_33", "lutpq_clip_33", "lutpq_domain_33"})
    EXPECT_TRUE(std::any_of(failing.begin(), failing.end(), [&](const std::string& id) {
      return id.find(lut) != std::string::npos;
    })) << lut;
}

// DOMAIN ignored in the lookup (the PQ signal used as the coordinate as it is): only the LUT with
// a non-default DOMAIN_MIN/MAX (pq_domain_33) can show it, and its cases fail.
TEST(Pipelines, PlantedDomainIgnoredFailsTheDomainLutCases) {
  std::string out;
  const auto failing = failing_with_planted(
      "pq_grading/lib/pq_grading.glsl", "  vec3 t = pqg_domain_normalise(pq);",
      "  vec3 t = vec3(saturate_d3d(pq.r), saturate_d3d(pq.g), saturate_d3d(pq.b));", "pq_grading",
      &out);
  EXPECT_TRUE(contains(failing, "pq_grading/luts/display1_backbuffer0_lutpq_domain_33_random"))
      << out;
  EXPECT_EQ(failing, pq_case_ids("lutpq_domain_33")) << out;  // every one of them, no other
}

// The user LUT's texture is `lut convert --to strip`'s image, texel for texel (and the export's
// user_lut.exr with it): one layout for the CLI, the loader and both engines.
TEST(Pipelines, UserLutTextureIsLutConvertsStrip) {
  const fs::path dir = temp_dir("user_lut_strip");
  const std::string cube = kCasesDir + "/lut/cube/pq_domain_33.cube";
  const Ran r =
      run("lut convert --to strip --format exr --out " + (dir / "strip.exr").string() + " " + cube);
  ASSERT_EQ(r.code, 0) << r.out;
  auto converted = hdrc::read_image((dir / "strip.exr").string());
  ASSERT_TRUE(converted.ok()) << converted.error().to_string();
  auto lut = hdrc::read_user_lut(kCasesDir, "lut/cube/pq_domain_33.cube", nullptr);
  ASSERT_TRUE(lut.ok()) << lut.error().to_string();
  const hdrc::Image strip = hdrc::user_lut_strip(**lut);
  ASSERT_EQ(strip.width, converted->width);
  ASSERT_EQ(strip.height, converted->height);
  size_t differ = 0;
  for (size_t p = 0; p < strip.pixel_count(); ++p)
    for (int c = 0; c < 3; ++c) differ += strip.data[p * 4 + c] != converted->data[p * 4 + c];
  EXPECT_EQ(differ, 0u);
  fs::remove_all(dir);
}

// A port renders a pq_grading case from what export writes alone: params.json, input.exr and the
// user LUT beside them (user_lut.exr, the strip it binds; user_lut.cube, the table). The example
// candidate (examples/vulkan_candidate.cpp: load_exported_case and the Vulkan engine) passes.
TEST(Pipelines, PqGradingCasesRenderFromTheirExportAlone) {
  const fs::path out = temp_dir("pq_export");
  const Ran v =
      run("verify --filter 'pq_grading/luts/display[01]_backbuffer0_lutpq_domain_33_*' "
          "-j 2 --candidate-cmd '" +
          std::string(HDRC_EXAMPLE_CANDIDATE) + " --params {params} --output {output}' --out " +
          out.string());
  EXPECT_EQ(v.code, 0) << v.out;
  EXPECT_NE(v.out.find("4 passed"), std::string::npos) << v.out;
  const fs::path dir = out / "cases/pq_grading/luts/display1_backbuffer0_lutpq_domain_33_random";
  EXPECT_TRUE(fs::exists(dir / "user_lut.cube"));
  EXPECT_TRUE(hdrc::read_image((dir / "user_lut.exr").string()).ok());
  const auto params = nlohmann::json::parse(read(dir / "params.json"));
  EXPECT_EQ(params["user_lut"]["source"], "lut/cube/pq_domain_33.cube");
  EXPECT_EQ(params["user_lut"]["size"], 33);
  EXPECT_EQ(params["params"]["user_lut_size"], 33);
  fs::remove_all(out);
}

// ---- UE's user colour-grading LUT blend (docs/ue55-lut-blend-spec.md, issue 16) ----------------

// A port renders UE's BLENDCOUNT 5 case from its export alone: params.json carries the table
// (lut_blend_count, LUTWeights) and one strip per slot (user_lut.exr, user_lut_1..3.exr, the
// 8-bit values the host rounded); the example candidate passes.
TEST(Pipelines, UeUserLutBlendCasesRenderFromTheirExportAlone) {
  const fs::path out = temp_dir("ue_lut_export");
  const Ran v = run("verify --filter 'lut/user_lut/blend5/dev[09]' -j 2 --candidate-cmd '" +
                    std::string(HDRC_EXAMPLE_CANDIDATE) +
                    " --params {params} --output {output}' --out " + out.string());
  EXPECT_EQ(v.code, 0) << v.out;
  EXPECT_NE(v.out.find("2 passed"), std::string::npos) << v.out;
  const fs::path dir = out / "cases/lut/user_lut/blend5/dev0";
  const auto params = nlohmann::json::parse(read(dir / "params.json"));
  EXPECT_EQ(params["params"]["lut_blend_count"], 5);
  EXPECT_EQ(params["user_lut"]["textures"].size(), 4u);
  for (const char* f : {"user_lut.exr", "user_lut_1.exr", "user_lut_2.exr", "user_lut_3.exr"}) {
    auto img = hdrc::read_image((dir / f).string());
    ASSERT_TRUE(img.ok()) << f;
    EXPECT_EQ(img->width, 256) << f;
    EXPECT_EQ(img->height, 16) << f;
  }
  fs::remove_all(out);
}

std::vector<std::string> failing_user_lut_cases(const std::string& from, const std::string& to,
                                                std::string* out,
                                                nlohmann::json* results = nullptr) {
  return hdrc::test::planted_shader_failures("lib/ue_lut_blend.glsl", from, to,
                                             "--filter 'lut/user_lut/*'", out, 1, results);
}

// Red and blue swapped in the lookup (a BGRA texture read as RGBA): every case where a LUT
// changes the colour fails; the HDR device (3), where 5.5 ignores the LUT, and intensity 0
// (BLENDCOUNT 1: the block is absent) do not.
TEST(Pipelines, PlantedUeLutRedBlueSwapFailsTheBlendCases) {
  std::string out;
  nlohmann::json results;
  const auto failing = failing_user_lut_cases("return mix(rg0, rg1, frac_w);",
                                              "return mix(rg0, rg1, frac_w).bgr;", &out, &results);
  // The diagnosis names it where the LUT's value is the output (intensity 1; docs/diagnosis.md).
  EXPECT_EQ(
      hints_of(results, "lut/user_lut/intensity/dev0_colorgradingintensity1_lutue16_contrast"),
      std::set<std::string>{"channel_swap_rb"});
  EXPECT_TRUE(
      contains(failing, "lut/user_lut/intensity/dev0_colorgradingintensity1_lutue16_contrast"))
      << out;
  EXPECT_TRUE(contains(failing, "lut/user_lut/intensity/dev9_colorgradingintensity0.5_lutue16_hue"))
      << out;
  EXPECT_TRUE(contains(failing, "lut/user_lut/blend5/dev2")) << out;
  for (const auto& id : failing) {
    EXPECT_EQ(id.find("/dev3_"), std::string::npos) << id;
    EXPECT_EQ(id.find("/dev4"), std::string::npos) << id;
    EXPECT_EQ(id.find("intensity0_"), std::string::npos) << id;
  }
}

// A half-texel offset in the 16-point sampling: UVW without UE's + 0.5/16.
TEST(Pipelines, PlantedUeLutHalfTexelOffsetFailsTheBlendCases) {
  std::string out;
  nlohmann::json results;
  const auto failing = failing_user_lut_cases("gamma_color * (15.0 / 16.0) + 0.5 / 16.0",
                                              "gamma_color * (15.0 / 16.0)", &out, &results);
  // The diagnosis names it (docs/diagnosis.md).
  for (const char* id : {"lut/user_lut/blend4/dev0",
                         "lut/user_lut/intensity/dev1_colorgradingintensity0.5_lutue16_contrast"})
    EXPECT_EQ(hints_of(results, id), std::set<std::string>{"lut_half_texel_down"}) << id;
  EXPECT_TRUE(
      contains(failing, "lut/user_lut/intensity/dev1_colorgradingintensity0.5_lutue16_contrast"))
      << out;
  EXPECT_TRUE(contains(failing, "lut/user_lut/blend4/dev0")) << out;
  for (const auto& id : failing) EXPECT_EQ(id.find("intensity0_"), std::string::npos) << id;
}

// The neutral weight LUTWeights[0] dropped: the cases where it is not 0 fail (intensity 0.5,
// BLENDCOUNT 3-5); intensity 1 (weights 0, 1) and the tie (0, 0.5, 0.5) do not.
TEST(Pipelines, PlantedUeLutNeutralWeightDroppedFailsWhereItIsNotZero) {
  std::string out;
  const auto failing = failing_user_lut_cases("vec3 blended = P.lut_weights.x * g;",
                                              "vec3 blended = vec3(0.0);", &out);
  EXPECT_TRUE(contains(failing, "lut/user_lut/intensity/dev0_colorgradingintensity0.5_lutue16_hue"))
      << out;
  EXPECT_TRUE(contains(failing, "lut/user_lut/blend3/dev9")) << out;
  for (const auto& id : failing) {
    EXPECT_EQ(id.find("intensity1_"), std::string::npos) << id;
    EXPECT_EQ(id.find("/tie/"), std::string::npos) << id;
  }
}

// UE 5.8's CombineLUTs (cases/ue58/devices.json at one device and gamut: Filmic and StandardACES,
// ACES 1.3 and 2.0): a planted defect in the ACES 2.0 path fails the two ACES 2.0 cases
// (StandardACES forward; Filmic's automatic HDR, inverse then forward) and neither ACES 1.3 case.
std::vector<std::string> ue58_planted(const std::string& shader, const std::string& from,
                                      const std::string& to, const std::string& cases) {
  std::string out;
  const auto failing = hdrc::test::planted_shader_failures(
      shader, from, to, "--pipeline ue58 --filter 'ue58/devices/" + cases + "_*'", &out);
  for (const char* method : {"0", "1"}) {
    const std::string id = "ue58/devices/" + cases + "_tonemappingmethod" + method + "_version2";
    EXPECT_TRUE(contains(failing, id)) << id << "\n" << out;
  }
  for (const auto& id : failing) EXPECT_NE(id.find("version2"), std::string::npos) << id;
  return failing;
}

// The Hellwig 2022 matrix (XYZ_2_CAM16_MAT, ACESOutputTransform.ush) transposed.
TEST(Pipelines, PlantedUe58HellwigMatrixTransposedFailsTheAces2Cases) {
  ue58_planted(
      "lib/aces2_common.glsl",
      "return aces2_mul(ACES2_XYZ_2_CAM16_0, ACES2_XYZ_2_CAM16_1, ACES2_XYZ_2_CAM16_2, v);",
      "return aces2_mul(vec3(ACES2_XYZ_2_CAM16_0.x, ACES2_XYZ_2_CAM16_1.x, "
      "ACES2_XYZ_2_CAM16_2.x), vec3(ACES2_XYZ_2_CAM16_0.y, ACES2_XYZ_2_CAM16_1.y, "
      "ACES2_XYZ_2_CAM16_2.y), vec3(ACES2_XYZ_2_CAM16_0.z, ACES2_XYZ_2_CAM16_1.z, "
      "ACES2_XYZ_2_CAM16_2.z), v);",
      "dev3_gamut2");
}

// chromaCompressionNorm's constant term 77.12896 off in its third digit. Measured: device 3 with
// Rec.2020 output stays within its tolerance (0.8 % of values one code off); the scRGB device 5
// with sRGB output, judged relatively, moves by up to 25 %.
TEST(Pipelines, PlantedUe58ChromaCompressionConstantFailsTheAces2Cases) {
  ue58_planted("lib/aces2_output.glsl", "9.19364 * sin_hr3 + 77.12896;",
               "9.19364 * sin_hr3 + 77.22896;", "dev5_gamut0");
}

// The reach-M table read at 2 degrees instead of 1 (each odd hue reads its even neighbour's
// texel: a table of half the hue resolution). Host side, the same table changes both engines
// and the goldens catch it (reference/ue/ue58/ue58_test.cpp PlantedReachTableAtTwoDegrees...).
TEST(Pipelines, PlantedUe58ReachTableHueResolutionFailsTheAces2Cases) {
  ue58_planted("ue58/lib/combine_luts58.glsl", "  if (i < 0 || i >= 360) return 0.0;\n  return",
               "  if (i < 0 || i >= 360) return 0.0;\n  i = i / 2 * 2;\n  return", "dev3_gamut2");
}

// UE 5.8's Tonemap pass (cases/ue58/tonemap_devices.json at one device: r.LUT.Shaper x LUT format x
// method): a planted defect fails exactly the cases where the changed value matters.
std::vector<std::string> ue58_tonemap_planted(const std::string& from, const std::string& to,
                                              const std::string& device, std::string* out) {
  return hdrc::test::planted_shader_failures(
      "ue58/stages/tonemap.comp", from, to,
      "--pipeline ue58 --filter 'ue58/tonemap_devices/" + device + "_*'", out);
}

// r.LUT.Shaper ignored (the log address for every case, as 5.5's SDR devices): every PQ-shaper
// case of the HDR device 3 fails, no log-shaper case.
TEST(Pipelines, PlantedUe58TonemapShaperIgnoredFailsThePqShaperCases) {
  std::string out;
  const auto failing = ue58_tonemap_planted("lut_encode_shaper(P.ue58_lut_shaper == 1, true,",
                                            "lut_encode_shaper(false, true,", "dev3", &out);
  EXPECT_EQ(failing.size(), 4u) << out;
  for (const auto& id : failing) EXPECT_NE(id.find("_shaper1_"), std::string::npos) << id;
}

// 5.5's LUT scale 1.05 applied on every device (5.8 multiplies by GetTonemappingMax, 1 except for
// Filmic on devices 0, 1, 9): on device 0 every StandardACES case fails, no Filmic case.
TEST(Pipelines, PlantedUe58TonemapLutMaxEverywhereFailsTheUnscaledCases) {
  std::string out;
  const auto failing = ue58_tonemap_planted("color_lookup_encoded(encoded, P.ue58_lut_max)",
                                            "color_lookup_encoded(encoded, 1.05)", "dev0", &out);
  EXPECT_EQ(failing.size(), 4u) << out;
  for (const auto& id : failing) EXPECT_NE(id.find("tonemappingmethod1"), std::string::npos) << id;
}

// UE 5.8's Texture vignette at SM6 (cases/ue58/tonemap_vignette_texture.json): the texture read
// upside down, V flipped as the dirt mask's DirtLensUV is (a port that treats the texture like
// the dirt mask). UE samples at (InvSize · V − (Centre − 0.5)) · 0.5 + 0.5 with V up, so the
// texture's row 0 lies at the bottom of the screen. Both cases with the Ramp texture
// (VignetteTexture 2, rising down its rows) fail; the white dummy's (VignetteTexture 0, one
// texel) cannot.
TEST(Pipelines, PlantedUe58VignetteTextureUpsideDownFailsTheRampCases) {
  std::string out;
  const auto failing = hdrc::test::planted_shader_failures(
      "ue58/lib/vignette_texture58.glsl", "vec2 t = uv * vec2(size) - 0.5;",
      "vec2 t = vec2(uv.x, 1.0 - uv.y) * vec2(size) - 0.5;",
      "--pipeline ue58 --filter 'ue58/tonemap_vignette_texture/*'", &out);
  int ramp = 0;
  for (const auto& id : failing) {
    EXPECT_EQ(id.find("_vignettetexture0_"), std::string::npos) << id;
    if (id.find("_vignettetexture2_") != std::string::npos) ++ramp;
  }
  EXPECT_EQ(ramp, 2) << out;
}

// Three cases of cases/ue58/ui_composite.json: 5.8's defaults on device 3 (gamma blend, gamma
// EOTF, paper white 203), and a linear-blend one.
constexpr const char* kUe58UiDefaults =
    "ue58/ui_composite/dev3_uilevel1_uinits203_uimode1_uiblend0_uieotf0_uinitsmode0_paperwhite203_"
    "uiblendgamma2.4_uieotfgamma2.4_pq_codes";
constexpr const char* kUe58UiLinear =
    "ue58/ui_composite/dev4_uilevel0.5_uinits203_uimode1_uiblend1_uieotf1_uinitsmode0_"
    "paperwhite203_uiblendgamma2.4_uieotfgamma2.2_pq_codes";

// UE 5.8's UI composite (cases/ue58/ui_composite.json): a planted defect in its GLSL
// (gpu/shaders/ue58/lib/ui_composite58.glsl) fails the cases whose pixels take the planted step.
std::vector<std::string> ue58_ui_planted(const std::string& from, const std::string& to,
                                         std::string* out) {
  return hdrc::test::planted_shader_failures("ue58/lib/ui_composite58.glsl", from, to,
                                             "--pipeline ue58 --filter 'ue58/ui_composite/*'", out);
}

// The gamma-space blend done linearly (lerp of the nits): the shader-composite cases with
// r.HDR.UI.CompositeBlend 0 fail at their translucent texels; none with 1 or with CompositeMode 0.
TEST(Pipelines, PlantedUe58UiGammaBlendDoneLinearlyFailsTheGammaBlendCases) {
  std::string out;
  const auto failing = ue58_ui_planted(
      "  return pow_d3d(lerp_d3d(gs, gu, ui.a), P.ue58_ui_blend_gamma) * UE58_PQ_WHITE_NITS;",
      "  return lerp_d3d(scene, u, ui.a);", &out);
  EXPECT_TRUE(contains(failing, kUe58UiDefaults)) << out;
  EXPECT_GE(failing.size(), 6u) << out;
  for (const auto& id : failing) {
    EXPECT_NE(id.find("_uiblend0_"), std::string::npos) << id;
    EXPECT_EQ(id.find("_uimode0_"), std::string::npos) << id;
  }
}

// UILuminance 300 (5.5's r.HDR.UI.Luminance default) instead of the host's value (the paper white
// 203 by default): the shader-composite cases whose UILuminance is not 300 fail.
TEST(Pipelines, PlantedUe58UiLuminance300FailsThePaperWhiteCases) {
  std::string out;
  const auto failing = ue58_ui_planted("* p.ui_luminance, ui.a);", "* 300.0, ui.a);", &out);
  EXPECT_TRUE(contains(failing, kUe58UiDefaults)) << out;
  for (const auto& id : failing) EXPECT_EQ(id.find("_uimode0_"), std::string::npos) << id;
}

// No un-premultiply (5.5's EOTF of the premultiplied code): the shader-composite cases fail at
// their translucent texels, with either blend space.
TEST(Pipelines, PlantedUe58UiNoUnpremultiplyFailsTheTranslucentCases) {
  std::string out;
  const auto failing =
      ue58_ui_planted("vec3 c = ui.a > 0.0 ? ui.rgb / ui.a : vec3(0.0);", "vec3 c = ui.rgb;", &out);
  EXPECT_TRUE(contains(failing, kUe58UiDefaults)) << out;
  EXPECT_TRUE(contains(failing, kUe58UiLinear)) << out;
  for (const auto& id : failing) EXPECT_EQ(id.find("_uimode0_"), std::string::npos) << id;
}

// VisualizeHDR's histogram over a 32-EV range instead of HistogramLogMax - HistogramLogMin = 30
// (UE 5.5's pass, which ue58_visualize_hdr runs over 5.8's scene): on lavapipe the ue58 cases fail
// at the panel (the buckets, the green range, the overlay and the exposure lines move). The row of
// planted_shader_defects.json; the worst-case model runs it in
// PlantedDefectsFailOnTheWorstCaseDevice.
TEST(Pipelines, PlantedHistogramEvRangeFailsTheUe58VisualizeCases) {
  std::string out;
  const auto failing = planted_shader_failures("lib/visualize_eye_adaptation.glsl",
                                               "const float EA_HISTOGRAM_SCALE = 0.0333333351;",
                                               "const float EA_HISTOGRAM_SCALE = 0.03125;",
                                               "--filter 'ue58/visualize_hdr*/dev[37]_*'", &out);
  EXPECT_TRUE(
      contains(failing, "ue58/visualize_hdr/dev3_debug0_tonemappingmethod0_version1_log_ramp"))
      << out;
  EXPECT_TRUE(contains(failing, "ue58/visualize_hdr_devices/dev7_log_ramp")) << out;
}

}  // namespace

// The planted shader defects every conformant device must fail (runner/planted_shader_defects.json,
// shared with scripts/gpu-check.py, which runs them on a real GPU).
struct PlantedDefect {
  std::string shader, from, to, cases, must_fail, what;
};

std::vector<PlantedDefect> planted_defects() {
  const std::string path = std::string(HDRC_SOURCE_DIR) + "/runner/planted_shader_defects.json";
  auto j = hdrc::read_json_file<nlohmann::json>(path, "planted defects");
  EXPECT_TRUE(j.ok()) << path;
  std::vector<PlantedDefect> rows;
  if (!j.ok()) return rows;
  for (const auto& d : (*j)["defects"])
    rows.push_back({d["shader"], d["from"], d["to"], d["cases"], d["must_fail"], d["what"]});
  return rows;
}

// The H200's lut33 texel (issue 25; docs/ue55-decisions.md D-UV): UE's own form of the unwrapped
// LUT's lattice coordinate, frac(UV.x·N) at r = 0, wraps to the neighbouring slice when a
// conformant device's division rounds UV.x below the slice boundary. Lavapipe's division is
// correctly rounded, so only the worst-case device model shows it: planted back, the layout-1
// storage cases fail under the model (texel (0, g, b) holding (1, g, b − 1)'s colour); the
// port's closed form passes them under the model.
TEST(Pipelines, WorstCaseDeviceCatchesTheUnwrappedCoordinate) {
  PlantedDefect ue_form;
  for (const auto& d : planted_defects())
    if (d.shader == "lib/combine_luts.glsl") ue_form = d;
  ASSERT_FALSE(ue_form.from.empty()) << "no lib/combine_luts.glsl row";
  std::string out;
  // On lavapipe, without the model, UE's form passes: its divisions are correctly rounded.
  const auto exact = planted_shader_failures(ue_form.shader, ue_form.from, ue_form.to,
                                             "--filter '" + ue_form.cases + "'", &out, 0);
  EXPECT_TRUE(exact.empty()) << out;
  const auto failing =
      planted_shader_failures(ue_form.shader, ue_form.from, ue_form.to,
                              "--filter '" + ue_form.cases + "' --device-model worst", &out);
  EXPECT_GE(failing.size(), 2u) << out;
  EXPECT_TRUE(contains(failing, ue_form.must_fail)) << out;
  for (const auto& id : failing) EXPECT_NE(id.find("layout1"), std::string::npos) << id;
  // The port's form under the model: every layout-1 storage case passes.
  const Ran fixed =
      run("run --filter 'lut/storage/*layout1*' --device-model worst --no-goldens --out " +
          temp_dir("unwrapped_fixed").string());
  EXPECT_EQ(fixed.code, 0) << fixed.out;
}

// Every planted shader defect of runner/planted_shader_defects.json (those of this file, of
// cli_test.cpp and of dither_test.cpp) still fails on the worst-case conformant device
// (issue 25): the device allowances the reference derives there must not absorb a wrong constant
// or a wrong lookup. Each row runs its cases under `--device-model worst` and needs the named case
// to FAIL (not pass with an allowance, not be a known limit of the model).
TEST(Pipelines, PlantedDefectsFailOnTheWorstCaseDevice) {
  const auto rows = planted_defects();
  EXPECT_GE(rows.size(), 12u);
  for (const auto& row : rows) {
    std::string out;
    const auto failing = planted_shader_failures(
        row.shader, row.from, row.to, "--filter '" + row.cases + "' --device-model worst", &out);
    if (row.must_fail == "*")
      EXPECT_FALSE(failing.empty()) << row.what << ": no case failed\n" << out;
    else
      EXPECT_TRUE(contains(failing, row.must_fail))
          << row.what << ": " << row.to << " did not fail " << row.must_fail << "\n"
          << out;
  }
}
