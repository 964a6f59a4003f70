#include "core/install_paths.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <vector>

namespace hdrc {

namespace fs = std::filesystem;

std::string executable_dir() {
  std::error_code ec;
  // proc(5): /proc/self/exe is a symbolic link to the executable's actual path name.
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec || !exe.has_parent_path()) return "";
  return exe.parent_path().string();
}

std::string installed_data_dir() {
  const std::string bin = executable_dir();
  if (bin.empty()) return "";
  std::error_code ec;
  const fs::path share = fs::path(bin).parent_path() / "share" / "hdrconform";
  return fs::is_directory(share, ec) ? share.string() : "";
}

std::string data_dir(const std::string& compiled_in, const std::string& name) {
  const std::string share = installed_data_dir();
  return share.empty() ? compiled_in : (fs::path(share) / name).string();
}

std::string pipeline_cache_file(const std::string& build_default) {
  if (installed_data_dir().empty()) return build_default;
  // XDG Base Directory Specification 0.8: "If $XDG_CACHE_HOME is either not set or empty, a
  // default equal to $HOME/.cache should be used"; a relative path in it is invalid (ignored).
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  fs::path base;
  if (xdg && *xdg == '/') {
    base = xdg;
  } else if (const char* home = std::getenv("HOME"); home && *home == '/') {
    base = fs::path(home) / ".cache";
  } else {
    return "";
  }
  return (base / "hdrconform" / "vk_pipeline_cache.bin").string();
}

namespace {

// The components of a colon-separated path list, empty ones included.
std::vector<std::string> split_path_list(const std::string& list) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (true) {
    const size_t end = list.find(':', start);
    parts.push_back(list.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) return parts;
    start = end + 1;
  }
}

}  // namespace

void restore_library_path() {
  const char* bundle = std::getenv("HDRC_BUNDLE_LIB");
  if (!bundle) return;
  const std::vector<std::string> ours = split_path_list(bundle);
  std::string rest;
  bool kept = false;  // an empty component is kept too (ld.so(8): the current directory)
  if (const char* path = std::getenv("LD_LIBRARY_PATH")) {
    for (const std::string& part : split_path_list(path)) {
      if (std::find(ours.begin(), ours.end(), part) != ours.end()) continue;
      rest += (kept ? ":" : "") + part;
      kept = true;
    }
  }
  if (!kept)
    ::unsetenv("LD_LIBRARY_PATH");
  else
    ::setenv("LD_LIBRARY_PATH", rest.c_str(), 1);
  ::unsetenv("HDRC_BUNDLE_LIB");
}

}  // namespace hdrc
