// The tree's layering (docs/pipelines.md, "Layering"), checked on the sources themselves: every
// quoted #include of a layer names a folder that layer may depend on.
//   color/, interface/  the floor: each other only;
//   core/               the floor and itself (never reference/, gpu/, runner/, report/);
//   reference/, gpu/    anything but runner/ and report/.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct Layer {
  const char* folder;
  std::set<std::string> may_include;  // top-level folders; empty = any but `never`
  std::set<std::string> never;
};

// Every quoted include of every C++ file under `tree`/`layer.folder` that the layer may not
// have, as "file:line: path".
std::vector<std::string> violations(const fs::path& tree, const Layer& layer) {
  static const std::regex include(R"re(^\s*#\s*include\s*"([^"]+)")re");
  std::vector<std::string> out;
  const fs::path root = tree / layer.folder;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const std::string ext = entry.path().extension().string();
    if (!entry.is_regular_file() || (ext != ".h" && ext != ".cpp")) continue;
    std::ifstream in(entry.path());
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
      std::smatch m;
      if (!std::regex_search(line, m, include)) continue;
      const std::string path = m[1];
      const auto slash = path.find('/');
      if (slash == std::string::npos) continue;  // a sibling header of the same folder
      const std::string top = path.substr(0, slash);
      const bool allowed =
          layer.may_include.empty() ? !layer.never.count(top) : layer.may_include.count(top) > 0;
      if (!allowed)
        out.push_back(fs::relative(entry.path(), tree).string() + ":" + std::to_string(n) + ": " +
                      path);
    }
  }
  return out;
}

TEST(Layering, CoreIncludesOnlyTheFloor) {
  const std::vector<Layer> layers = {
      {"color", {"color", "interface"}, {}},
      {"interface", {"color", "interface"}, {}},
      {"core", {"core", "color", "interface"}, {}},
      {"reference", {}, {"runner", "report"}},
      {"gpu", {}, {"runner", "report"}},
  };
  for (const Layer& layer : layers) {
    const std::vector<std::string> bad = violations(HDRC_SOURCE_DIR, layer);
    std::string list;
    for (const std::string& b : bad) list += "\n  " + b;
    EXPECT_TRUE(bad.empty()) << layer.folder << "/ includes what its layer may not:" << list;
  }
}

// The check itself: an include of reference/ planted in a copy of core/'s shape is found, and a
// sibling or floor include is not.
TEST(Layering, APlantedIncludeIsFound) {
  const fs::path tree = fs::temp_directory_path() / ("hdrc_layering_" + std::to_string(::getpid()));
  fs::create_directories(tree / "core");
  std::ofstream(tree / "core" / "planted.h")
      << "#pragma once\n#include \"reference/ue/tonemap.h\"\n#include \"color/vec.h\"\n"
      << "#include \"stage.h\"\n";
  const std::vector<std::string> bad =
      violations(tree, {"core", {"core", "color", "interface"}, {}});
  fs::remove_all(tree);
  ASSERT_EQ(bad.size(), 1u);
  EXPECT_EQ(bad[0], "core/planted.h:2: reference/ue/tonemap.h");
}

}  // namespace
