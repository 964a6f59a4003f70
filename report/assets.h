// The report's static files (report/assets/: the stylesheet and the script every page loads),
// compiled into the binary by report/embed_assets.cmake so the report builder needs no data files.
#pragma once

#include <string_view>
#include <vector>

namespace hdrc::report {

struct Asset {
  std::string_view name;      // file name, written to report/assets/<name>
  std::string_view contents;  // bytes
};

const std::vector<Asset>& assets();

// The JSON schemas the runner validates inputs against (runner/results.schema.json), embedded the
// same way (report/CMakeLists.txt); `name` is the file name.
const std::vector<Asset>& schemas();

// The data files the runner reads (runner/diagnosis_signatures.json), embedded the same way.
const std::vector<Asset>& runner_data();

}  // namespace hdrc::report
