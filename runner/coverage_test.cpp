// Coverage: the default suite covers everything it declares; the declaration is complete (every
// cvar, with its default and edges); missing and degenerate-only combinations are reported.
#include "runner/coverage.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "runner/case_loader.h"
#include "runner/test_support.h"

#ifndef HDRC_SOURCE_DIR
#error "HDRC_SOURCE_DIR must be defined"
#endif

namespace {

namespace fs = std::filesystem;
using hdrc::test::run;
const std::string kCasesDir = std::string(HDRC_SOURCE_DIR) + "/cases";

TEST(Coverage, TheDefaultSuiteCoversEverythingItDeclares) {
  auto loaded = hdrc::load_cases(kCasesDir);
  ASSERT_TRUE(loaded.errors.empty()) << loaded.errors[0].to_string();
  std::vector<hdrc::Error> errors;
  const hdrc::CoverageSpec spec = hdrc::load_coverage_spec(kCasesDir, &errors);
  ASSERT_TRUE(errors.empty()) << errors[0].to_string();
  const hdrc::CoverageReport rep = hdrc::compute_coverage(spec, loaded.cases);
  EXPECT_TRUE(rep.complete()) << rep.text();
  EXPECT_EQ(rep.values_covered(), rep.values_declared());
  // The issue's matrix: HDR x device x gamut for the tonemap path, every one of the 100.
  const auto it = std::find_if(rep.requirements.begin(), rep.requirements.end(), [](const auto& r) {
    return r.requirement.name.rfind("tonemap: HDR x device x gamut", 0) == 0;
  });
  ASSERT_NE(it, rep.requirements.end());
  EXPECT_EQ(it->combinations, 100u);
  EXPECT_EQ(it->covered, 100u);
  // HDR off with an ACES device and MaxLuminance 0 is degenerate (spec 5.4): listed, with why.
  ASSERT_FALSE(it->degenerate.empty());
  EXPECT_NE(it->degenerate[0].find("r.HDR.EnableHDROutput=0"), std::string::npos);
  EXPECT_NE(it->degenerate[0].find("MaxLuminance resolves to 0"), std::string::npos);
}

// Every cvar is declared with its default, its minimum and its maximum (and, by the file's own
// rule, a middle value); the LUT storage settings with every value.
TEST(Coverage, EveryCvarIsDeclaredWithItsDefaultAndEdges) {
  std::vector<hdrc::Error> errors;
  const hdrc::CoverageSpec spec = hdrc::load_coverage_spec(kCasesDir, &errors);
  ASSERT_TRUE(errors.empty()) << errors[0].to_string();
  for (const auto& c : hdrc::cvar_table()) {
    const std::string name(c.name);
    ASSERT_TRUE(spec.values.count(name)) << name << " is not declared in cases/coverage.json";
    const auto& v = spec.values.at(name);
    for (double want : {c.default_value, c.min_value, c.max_value})
      EXPECT_NE(std::find(v.begin(), v.end(), want), v.end()) << name << " lacks " << want;
    if (c.max_value - c.min_value > 1) {
      EXPECT_GE(v.size(), 3u) << name << ": default, edges and a middle value";
    }
  }
  EXPECT_EQ(spec.values.at("LUTFormat"), (std::vector<double>{0, 1, 2}));
  EXPECT_EQ(spec.values.at("LUTLayout"), (std::vector<double>{0, 1}));
  // The issue's LUT sizes.
  for (double size : {16.0, 32.0, 64.0})
    EXPECT_NE(
        std::count(spec.values.at("r.LUT.Size").begin(), spec.values.at("r.LUT.Size").end(), size),
        0);
}

hdrc::Case make_case(const char* stage, std::vector<std::pair<const char*, double>> cvars) {
  hdrc::Case c;
  c.id = "t/" + std::to_string(cvars.size());
  c.stage = hdrc::find_stage(stage);
  for (auto [k, v] : cvars) EXPECT_TRUE(c.cvars.set(k, v).ok()) << k;
  c.input.stimulus = "log_ramp";
  c.input.width = 8;
  c.input.height = 1;
  return c;
}

TEST(Coverage, ReportsMissingValuesAndPairsAndDegenerateOnes) {
  hdrc::CoverageSpec spec;
  spec.values["r.HDR.EnableHDROutput"] = {0, 1};
  spec.values["r.HDR.Display.OutputDevice"] = {0, 3};
  spec.values["r.HDR.UI.Level"] = {1, 5};
  spec.order = {"r.HDR.EnableHDROutput", "r.HDR.Display.OutputDevice", "r.HDR.UI.Level"};
  spec.requirements.push_back(
      {"display", {"tonemap"}, {"r.HDR.EnableHDROutput", "r.HDR.Display.OutputDevice"}, {}, {}});
  // ui_composite has no device 0: its domain is {3}.
  spec.requirements.push_back(
      {"ui", {"ui_composite"}, {}, {"r.HDR.UI.Level"}, {"r.HDR.Display.OutputDevice"}});
  std::vector<hdrc::Case> cases = {
      make_case("tonemap", {{"r.HDR.EnableHDROutput", 1}, {"r.HDR.Display.OutputDevice", 0}}),
      make_case("tonemap", {{"r.HDR.EnableHDROutput", 1}, {"r.HDR.Display.OutputDevice", 3}}),
      // HDR off, device 3, MaxLuminance 0: degenerate.
      make_case("tonemap", {{"r.HDR.EnableHDROutput", 0}, {"r.HDR.Display.OutputDevice", 3}}),
      make_case("ui_composite", {{"r.HDR.EnableHDROutput", 1}, {"r.HDR.Display.OutputDevice", 3}}),
  };
  const hdrc::CoverageReport rep = hdrc::compute_coverage(spec, cases);
  EXPECT_FALSE(rep.complete());
  ASSERT_EQ(rep.requirements.size(), 2u);
  EXPECT_EQ(rep.requirements[0].combinations, 4u);
  EXPECT_EQ(rep.requirements[0].covered, 3u);
  EXPECT_EQ(rep.requirements[0].missing,
            std::vector<std::string>{"r.HDR.EnableHDROutput=0, r.HDR.Display.OutputDevice=0"});
  ASSERT_EQ(rep.requirements[0].degenerate.size(), 1u);
  EXPECT_EQ(rep.requirements[0].degenerate[0].rfind(
                "r.HDR.EnableHDROutput=0, r.HDR.Display.OutputDevice=3: ACES device 3", 0),
            0u);
  EXPECT_EQ(rep.requirements[1].combinations, 2u);
  EXPECT_EQ(rep.requirements[1].missing,
            std::vector<std::string>{"r.HDR.UI.Level=5, r.HDR.Display.OutputDevice=3"});
  // Per value: UI.Level 5 is run by no ui_composite case.
  const auto& ui = rep.names[2];
  ASSERT_EQ(ui.values.size(), 2u);
  EXPECT_EQ(ui.values[0].cases, 1);
  EXPECT_EQ(ui.values[1].cases, 0);
  const std::string text = rep.text();
  EXPECT_NE(text.find("UNCOVERED:\n  value r.HDR.UI.Level=5"), std::string::npos) << text;
  EXPECT_NE(text.find("combinations 4/6"), std::string::npos) << text;
}

TEST(Coverage, DeclarationErrorsAreLocated) {
  const fs::path dir = fs::temp_directory_path() / ("hdrc_cov_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "coverage.json") << R"({"values": {"r.LUT.Sise": [16], "r.LUT.Size": [8]},
      "requirements": [{"name": "x", "stages": ["tonemapp"], "full": ["r.LUT.Size"]}]})";
  std::vector<hdrc::Error> errors;
  hdrc::load_coverage_spec(dir.string(), &errors);
  ASSERT_EQ(errors.size(), 3u);
  EXPECT_EQ(errors[0].pointer, "/values/r.LUT.Sise");
  EXPECT_NE(errors[0].choices.find("r.LUT.Size"), std::string::npos);
  EXPECT_EQ(errors[1].to_string(), (dir / "coverage.json").generic_string() +
                                       ": /values/r.LUT.Size/0: declared value 8 is not valid; "
                                       "valid choices: 16 to 64");
  EXPECT_EQ(errors[2].pointer, "/requirements/0/stages/0");
  fs::remove_all(dir);
}

// `hdrconform coverage` exits 0 on the default suite and 1 when a declared value is uncovered.
TEST(Coverage, CommandExitCodes) {
  const auto ok = run("coverage");
  EXPECT_EQ(ok.code, 0) << ok.out;
  EXPECT_NE(ok.out.find("(100.0 %), combinations"), std::string::npos) << ok.out;
  const fs::path dir = fs::temp_directory_path() / ("hdrc_covcli_" + std::to_string(::getpid()));
  fs::create_directories(dir / "s");
  std::ofstream(dir / "s/a.json")
      << R"({"stage": "shaper", "cvars": {"r.HDR.Display.OutputDevice": 3}, "input": {"stimulus": "log_ramp", "width": 8}})";
  std::ofstream(dir / "coverage.json") << R"({"values": {"r.HDR.Display.OutputDevice": [3, 4]},
      "requirements": [{"name": "devices", "stages": ["shaper"], "of": ["r.HDR.Display.OutputDevice"], "with": ["r.HDR.Display.OutputDevice"]}]})";
  const auto missing = run("coverage --cases " + dir.string());
  EXPECT_EQ(missing.code, 1) << missing.out;
  EXPECT_NE(missing.out.find("value r.HDR.Display.OutputDevice=4"), std::string::npos)
      << missing.out;
  fs::remove_all(dir);
}

}  // namespace
