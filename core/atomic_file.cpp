#include "core/atomic_file.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace hdrc {

Status write_file_atomic(const std::string& path, const std::string& contents) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path target(path);
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f << contents;
    f.close();
    if (!f) {
      fs::remove(tmp, ec);
      return Error{path, "", "cannot write file", ""};
    }
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    fs::remove(tmp, ec);
    return Error{path, "", "cannot move the written file into place: " + ec.message(), ""};
  }
  return {};
}

}  // namespace hdrc
