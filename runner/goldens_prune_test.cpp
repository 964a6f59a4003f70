// `goldens update` prunes only the goldens it wrote (issue 12): pointed at a folder that also
// holds other files (a project's package.json, a foreign sidecar-like JSON, an EXR of someone
// else, a symlink to another folder), it removes only its own stale pairs, lists every removed
// file, and removes only the folders its removals left empty.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "runner/case_loader.h"
#include "runner/goldens.h"

namespace fs = std::filesystem;

namespace {

void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << text;
}

bool listed(const std::vector<std::string>& lines, const std::string& line) {
  return std::find(lines.begin(), lines.end(), line) != lines.end();
}

TEST(GoldensPrune, TouchesOnlyItsOwnGoldensAndListsEveryRemoval) {
  const fs::path t = fs::temp_directory_path() / ("hdrc_prune_" + std::to_string(getpid()));
  fs::remove_all(t);
  const fs::path g = t / "goldens";
  write(t / "cases/t.json",
        R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 8, "height": 2}})");
  hdrc::LoadedCases loaded = hdrc::load_cases((t / "cases").string());
  ASSERT_TRUE(loaded.errors.empty());
  ASSERT_EQ(loaded.cases.size(), 1u);

  // Not ours: kept whatever their names.
  write(g / "package.json", R"({"name": "project"})");
  write(g / "notes/figure.exr", "not a golden");
  write(g / "other.json",
        R"({"case": "someone/else", "case_hash": "x", "reference_version": "1"})");
  write(g / "t/log_ramp_old.json", "{ not json");
  write(t / "elsewhere/z.json",
        R"({"case": "link/z", "case_hash": "x", "reference_version": "1"})");
  write(t / "elsewhere/z.exr", "x");
  fs::create_directory_symlink(t / "elsewhere", g / "link");
  // Ours, of a case no longer in the suite: removed, both files, and its folder.
  write(g / "gone/case.json",
        R"({"case": "gone/case", "case_hash": "h", "reference_version": "1/abc"})");
  write(g / "gone/case.exr", "pixels");

  const hdrc::GoldenUpdateReport rep =
      hdrc::update_goldens(loaded.cases, g.string(), /*prune=*/true, 1);
  EXPECT_TRUE(rep.errors.empty());
  EXPECT_EQ(rep.written, 1);
  EXPECT_EQ(rep.removed, 1);
  const std::string gs = g.generic_string();
  EXPECT_TRUE(listed(rep.lines, "removed " + gs + "/gone/case.exr"));
  EXPECT_TRUE(listed(rep.lines, "removed " + gs + "/gone/case.json"));
  EXPECT_TRUE(listed(rep.lines, "removed empty folder " + gs + "/gone"));
  EXPECT_FALSE(fs::exists(g / "gone"));
  for (const char* kept : {"package.json", "notes/figure.exr", "other.json", "t/log_ramp_old.json"})
    EXPECT_TRUE(fs::exists(g / kept)) << kept;
  EXPECT_TRUE(fs::exists(t / "elsewhere/z.json"));
  EXPECT_TRUE(fs::exists(t / "elsewhere/z.exr"));
  EXPECT_TRUE(fs::exists(g / "t/log_ramp.exr"));
  EXPECT_TRUE(fs::exists(g / "t/log_ramp.json"));
  size_t removals = 0;
  for (const auto& l : rep.lines) removals += l.rfind("removed ", 0) == 0;
  EXPECT_EQ(removals, 3u);  // every removal is listed, and nothing else was removed

  // A second update changes nothing.
  const hdrc::GoldenUpdateReport again =
      hdrc::update_goldens(loaded.cases, g.string(), /*prune=*/true, 1);
  EXPECT_EQ(again.unchanged, 1);
  EXPECT_EQ(again.removed, 0);
  if (!::testing::Test::HasFailure()) fs::remove_all(t);
}

}  // namespace
