// What a run was: the source commit, the command line, the shaders it ran (path and content
// hash), the build, and the suite (a fingerprint of the selected cases, the same for every shard
// of one run). Recorded in results.json ("provenance"); `merge` refuses shards whose suite or
// build differ, and every case page shows a command that reproduces the case.
#pragma once

#include <string>
#include <vector>

#include "core/case.h"
#include "runner/run.h"

namespace hdrc {

// SHA-256 over the sorted relative paths and contents of every file under `dir` ("" when `dir`
// is empty or unreadable).
std::string directory_hash(const std::string& dir);

// The shell-quoted command line ('…' where a word needs it).
std::string shell_quote(const std::string& word);
std::string command_line(int argc, char** argv);

// `cases`: the selected cases before --shard. `shader_dir`: the Vulkan engine's shader
// directory ("" for other engines). `images`: the --images policy.
RunProvenance run_provenance(int argc, char** argv, const std::vector<Case>& cases,
                             const std::string& shader_dir, const std::string& images);

}  // namespace hdrc
