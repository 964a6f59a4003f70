// results.json as the one record of a run (issue 14): golden outcomes as test results, the exit
// code it stands for, --images, and junit.xml written from it.
#include "runner/results.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

struct TempDir {
  fs::path p;
  explicit TempDir(const std::string& name)
      : p(fs::temp_directory_path() / ("hdrc_results_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(p);
    fs::create_directories(p);
  }
  ~TempDir() { fs::remove_all(p); }
};

json two_cases() {
  return json::parse(R"({"tool": "hdrconform", "wall_seconds": 2, "interrupted": false,
    "cases": [
      {"id": "shaper/a", "stage": "shaper", "verdict": "PASS", "reason": "ok", "warn": false,
       "images": {"reference": "cases/shaper/a/reference.exr"}},
      {"id": "shaper/b", "stage": "shaper", "verdict": "FAIL", "reason": "linear_rel 0.1 > 0.001",
       "warn": false, "tolerance": {"source": "cases/shaper.json"},
       "images": {"reference": "cases/shaper/b/reference.exr"}}],
    "summary": {"total": 2, "pass": 1, "fail": 1, "exit_code": 1}})");
}

// A golden regression alone fails the run: a JUnit test case with a failure, a results.json whose
// exit code is 1, and the counts.
TEST(Results, GoldenRegressionsAreTestResults) {
  TempDir d("goldens");
  json doc = two_cases();
  doc["cases"][1]["verdict"] = "PASS";
  EXPECT_EQ(hdrc::exit_code_of(doc), 0);
  std::ofstream(d.p / "goldens.json") << R"({"goldens_dir": "/g", "reference_version": "1/abc",
      "cases": [{"id": "shaper/a", "outcome": "match", "message": ""},
                {"id": "shaper/b", "outcome": "regression", "message": "3 value(s) differ"}]})";
  ASSERT_TRUE(hdrc::record_goldens(doc, d.p.string()));
  EXPECT_EQ(doc["goldens"]["checked"], 2);
  EXPECT_EQ(doc["goldens"]["regression"], 1);
  EXPECT_EQ(doc["goldens"]["failed"], 1);
  EXPECT_EQ(doc["summary"]["golden_failed"], 1);
  EXPECT_EQ(hdrc::exit_code_of(doc), 1);
  const std::string x = hdrc::junit_from_results(doc);
  EXPECT_NE(x.find("<testsuite name=\"hdrconform.goldens\" tests=\"2\" failures=\"1\""),
            std::string::npos)
      << x;
  EXPECT_NE(x.find("name=\"shaper/b\">\n    <failure message=\"golden regression: 3 value(s)"),
            std::string::npos)
      << x;
  EXPECT_NE(x.find("classname=\"hdrconform.goldens\" name=\"shaper/a\"/>"), std::string::npos);
}

// JUnit failures name the case page; counts come from the verdicts.
TEST(Results, JunitFailuresLinkTheCasePage) {
  const std::string x = hdrc::junit_from_results(two_cases());
  EXPECT_NE(x.find("tests=\"2\" failures=\"1\" errors=\"0\" skipped=\"0\""), std::string::npos);
  EXPECT_NE(x.find("case page: report/c/shaper__b.html</failure>"), std::string::npos) << x;
  EXPECT_EQ(x.find("hdrconform.goldens"), std::string::npos);  // no golden check recorded
}

// --images failing keeps the failing case's files and deletes the passing case's.
TEST(Results, ImagePolicyFailingDeletesPassingCasesImages) {
  TempDir d("images");
  for (const char* id : {"a", "b"}) {
    fs::create_directories(d.p / "cases" / "shaper" / id);
    std::ofstream(d.p / "cases" / "shaper" / id / "reference.exr") << "x";
  }
  json doc = two_cases();
  ASSERT_TRUE(hdrc::apply_image_policy(doc, d.p.string(), "failing"));
  EXPECT_FALSE(fs::exists(d.p / "cases" / "shaper" / "a"));
  EXPECT_TRUE(fs::exists(d.p / "cases" / "shaper" / "b" / "reference.exr"));
  EXPECT_TRUE(doc["cases"][0]["images"].empty());
  EXPECT_EQ(doc["cases"][1]["images"]["reference"], "cases/shaper/b/reference.exr");
  ASSERT_TRUE(hdrc::apply_image_policy(doc, d.p.string(), "none"));
  EXPECT_FALSE(fs::exists(d.p / "cases" / "shaper"));
  // A hostile path in results.json is never followed out of OUT/cases.
  json bad = two_cases();
  bad["cases"][0]["images"]["reference"] = "cases/../../victim";
  std::ofstream(d.p.parent_path() / "victim") << "keep";
  ASSERT_TRUE(hdrc::apply_image_policy(bad, d.p.string(), "none"));
  EXPECT_TRUE(fs::exists(d.p.parent_path() / "victim"));
  fs::remove(d.p.parent_path() / "victim");
}

TEST(Results, ExitCodePrecedence) {
  json doc = two_cases();
  EXPECT_EQ(hdrc::exit_code_of(doc), 1);
  doc["interrupted"] = true;
  EXPECT_EQ(hdrc::exit_code_of(doc), 130);
  doc = two_cases();
  doc["cases"][1]["verdict"] = "SKIP";
  EXPECT_EQ(hdrc::exit_code_of(doc), 3);
  doc["cases"][1]["verdict"] = "PASS";
  doc["cases"][1]["warn"] = true;
  EXPECT_EQ(hdrc::exit_code_of(doc), 4);
}

}  // namespace
