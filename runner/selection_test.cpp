// --filter patterns, --rerun-failed, and the command-line hints (issue 14).
#include "runner/selection.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace {

namespace fs = std::filesystem;

hdrc::Case named(const std::string& id) {
  hdrc::Case c;
  c.id = id;
  return c;
}

TEST(Selection, SplitsRepeatedAndCommaSeparatedPatterns) {
  EXPECT_EQ(hdrc::split_filter("a,b\nc , ,d"), (std::vector<std::string>{"a", "b", "c", "d"}));
  EXPECT_TRUE(hdrc::split_filter("").empty());
}

TEST(Selection, SubstringGlobAndExactPatterns) {
  auto sel = hdrc::make_selection("lut", "");
  ASSERT_TRUE(sel);
  EXPECT_TRUE(sel->matches("lut/devices/dev3"));
  EXPECT_TRUE(sel->matches("tonemap/baked_lut_x"));  // a substring anywhere
  EXPECT_FALSE(sel->matches("tonemap/shaper_pq/dev3"));
  sel = hdrc::make_selection("tonemap/*,dither", "");
  ASSERT_TRUE(sel);
  EXPECT_TRUE(sel->matches("tonemap/a/b"));  // '*' crosses '/'
  EXPECT_TRUE(sel->matches("dither/x"));
  EXPECT_FALSE(sel->matches("lut/x"));
  EXPECT_FALSE(sel->matches("x/tonemap/y"));  // a glob is anchored at both ends
  sel = hdrc::make_selection("=lut/a", "");
  ASSERT_TRUE(sel);
  EXPECT_TRUE(sel->matches("lut/a"));
  EXPECT_FALSE(sel->matches("lut/a_2"));
  EXPECT_TRUE(hdrc::make_selection("", "")->matches("anything"));
}

TEST(Selection, NoMatchSuggestsCloseIdParts) {
  const std::vector<hdrc::Case> all = {named("tonemap/shaper_pq/dev3_log_ramp"),
                                       named("lut/devices/dev4_gamut2")};
  auto sel = hdrc::make_selection("tonemapp", "");
  ASSERT_TRUE(sel);
  const std::string msg = hdrc::no_match_message(*sel, all, "cases");
  EXPECT_NE(msg.find("no case matches --filter 'tonemapp' in cases"), std::string::npos) << msg;
  EXPECT_NE(msg.find("did you mean tonemap"), std::string::npos) << msg;
  EXPECT_NE(msg.find("substring"), std::string::npos) << msg;
}

TEST(Selection, RerunFailedReadsTheFailedIds) {
  const fs::path dir = fs::temp_directory_path() / ("hdrc_sel_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "results.json") << R"({"cases": [
      {"id": "a", "verdict": "PASS"}, {"id": "b", "verdict": "FAIL"},
      {"id": "c", "verdict": "ERROR"}, {"id": "d", "verdict": "MISSING"},
      {"id": "e", "verdict": "SKIP"}, {"id": "f", "verdict": "PASS"}],
      "goldens": {"cases": [{"id": "f", "outcome": "regression"}, {"id": "a", "outcome": "match"}]}})";
  auto ids = hdrc::failed_case_ids(dir.string());
  ASSERT_TRUE(ids);
  EXPECT_EQ(*ids, (std::set<std::string>{"b", "c", "d", "f"}));
  auto sel = hdrc::make_selection("", dir.string());
  ASSERT_TRUE(sel);
  EXPECT_TRUE(sel->matches("b"));
  EXPECT_FALSE(sel->matches("a"));
  // Filter and rerun combine (both must hold).
  sel = hdrc::make_selection("c,d", dir.string());
  EXPECT_FALSE(sel->matches("b"));
  EXPECT_TRUE(sel->matches("d"));
  auto missing = hdrc::make_selection("", (dir / "nope").string());
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().to_string().find("nope/results.json"), std::string::npos);
  fs::remove_all(dir);
}

TEST(Selection, ClosestCommand) {
  const std::vector<std::string> cmds = {"run", "list", "verify", "report", "merge", "export"};
  EXPECT_EQ(hdrc::closest_command("lsit", cmds), "list");
  EXPECT_EQ(hdrc::closest_command("verfy", cmds), "verify");
  EXPECT_EQ(hdrc::closest_command("mer", cmds), "merge");  // a prefix
  EXPECT_EQ(hdrc::closest_command("xyzzy", cmds), "");
  EXPECT_EQ(hdrc::closest_command("--help", cmds), "");
}

}  // namespace
