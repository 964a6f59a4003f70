// core/install_paths.h: a build-tree binary keeps the compiled-in paths; a bundle's launcher's
// library folders leave LD_LIBRARY_PATH before hdrconform starts other commands. The relocated
// case (share/hdrconform beside bin/) is the CTest test `bundle` (runner/bundle_test.sh).
#include "core/install_paths.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <optional>
#include <string>

namespace {

namespace fs = std::filesystem;

// Sets (or, with nullopt, unsets) a variable for one test and puts the old value back.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, std::optional<std::string> value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    set(value);
  }
  ~ScopedEnv() { set(old_); }

 private:
  void set(const std::optional<std::string>& v) {
    if (v)
      ::setenv(name_, v->c_str(), 1);
    else
      ::unsetenv(name_);
  }
  const char* name_;
  std::optional<std::string> old_;
};

std::optional<std::string> env(const char* name) {
  const char* v = std::getenv(name);
  return v ? std::optional<std::string>(v) : std::nullopt;
}

TEST(InstallPaths, BuildTreeKeepsCompiledInPaths) {
  EXPECT_EQ(fs::path(hdrc::executable_dir()), fs::canonical(fs::path(HDRC_BINARY).parent_path()));
  // build/runner/../share/hdrconform does not exist.
  EXPECT_EQ(hdrc::installed_data_dir(), "");
  EXPECT_EQ(hdrc::data_dir("/src/cases", "cases"), "/src/cases");
  ScopedEnv xdg("XDG_CACHE_HOME", "/elsewhere");
  EXPECT_EQ(hdrc::pipeline_cache_file("/build/vk_pipeline_cache.bin"),
            "/build/vk_pipeline_cache.bin");
}

TEST(InstallPaths, LauncherFoldersLeaveTheLibraryPath) {
  ScopedEnv bundle("HDRC_BUNDLE_LIB", "/b/lib:/b/lib/compat");
  ScopedEnv path("LD_LIBRARY_PATH", "/b/lib:/b/lib/compat:/user/a::/user/b");
  hdrc::restore_library_path();
  EXPECT_EQ(env("LD_LIBRARY_PATH"), "/user/a::/user/b");  // the empty entry is the caller's too
  EXPECT_EQ(env("HDRC_BUNDLE_LIB"), std::nullopt);
}

TEST(InstallPaths, OnlyTheLauncherFoldersUnsetTheLibraryPath) {
  ScopedEnv bundle("HDRC_BUNDLE_LIB", "/b/lib");
  ScopedEnv path("LD_LIBRARY_PATH", "/b/lib");
  hdrc::restore_library_path();
  EXPECT_EQ(env("LD_LIBRARY_PATH"), std::nullopt);
}

TEST(InstallPaths, WithoutALauncherNothingChanges) {
  ScopedEnv bundle("HDRC_BUNDLE_LIB", std::nullopt);
  ScopedEnv path("LD_LIBRARY_PATH", "/b/lib:/user/a");
  hdrc::restore_library_path();
  EXPECT_EQ(env("LD_LIBRARY_PATH"), "/b/lib:/user/a");
}

}  // namespace
