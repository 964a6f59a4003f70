// Where a relocated hdrconform finds its data. A build-tree binary reads the source tree's cases/,
// goldens/ and gpu/shaders/ (compiled-in absolute paths); a bundle (scripts/bundle.sh) or any
// other copy lays its data out beside the executable:
//
//   <prefix>/bin/hdrconform
//   <prefix>/share/hdrconform/{cases,goldens,shaders}
//
// and the folder <exe dir>/../share/hdrconform, when it exists, wins over the compiled-in paths:
// a bundle on the machine that built it still checks its own cases against its own goldens, not
// a source tree that may have moved on since. Command-line flags (--cases, --goldens,
// --shader-dir) override both. README.md, "Running on a GPU machine (bundle)".
#pragma once

#include <string>

namespace hdrc {

// The folder of the running executable (/proc/self/exe, symbolic links resolved); "" when the
// link cannot be read.
std::string executable_dir();

// <exe dir>/../share/hdrconform when that folder exists, else "".
std::string installed_data_dir();

// installed_data_dir()/name when installed_data_dir() is not "", else compiled_in.
std::string data_dir(const std::string& compiled_in, const std::string& name);

// The on-disk VkPipelineCache file for a build whose default is build_default (its build folder):
// build_default in a build-tree binary. An installed binary (installed_data_dir() not "") must not
// write into its own folder (it may be read-only, and is shared by every device that runs it):
// $XDG_CACHE_HOME/hdrconform/vk_pipeline_cache.bin, else $HOME/.cache/hdrconform/... (the XDG
// Base Directory Specification's default), else "" (no disk cache).
std::string pipeline_cache_file(const std::string& build_default);

// The launcher of a bundle (scripts/bundle.sh) prepends its library folders to LD_LIBRARY_PATH and
// names them in HDRC_BUNDLE_LIB (a colon-separated list). Once the dynamic linker has loaded the
// libraries, they are taken out of LD_LIBRARY_PATH again (unset when nothing else was in it), so
// that the commands hdrconform starts (verify --candidate-cmd) see the caller's environment, not
// the bundle's libraries. No-op without HDRC_BUNDLE_LIB.
void restore_library_path();

}  // namespace hdrc
