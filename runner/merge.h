// `hdrconform merge OUT DIR...`: the outputs of `run --shard K/N` (or `verify --shard K/N`),
// every K of one N, merged into OUT as one unsharded run writes them: results.json (cases in id
// order, counts summed, goldens joined, the exit code recomputed), junit.xml, the case images and
// the report. Modelled on Playwright's merge-reports.
//
// Refused with exit 2 and an error naming both directories and the field: shards of different
// suites (results.json provenance.suite_fingerprint: the selected cases and their definitions),
// of different builds (commit, build type, compiler, shader hash, tool version), engines or
// devices, planned from different timings (provenance.shard_plan), of different N, a K given
// twice or missing, or a case in two shards.
//
// OUT is an output folder as `run --out` is (runner/output_set.h, docs/output-folder.md): checked
// by the same code (not the cases or goldens folder, the default ones or those the shards ran on,
// nor inside or around them; not a shard, nor inside or around one; not a folder holding outputs
// hdrconform did not write), locked, and published as a whole by run's own publication, so a
// kill -9 at any moment leaves the previous complete content or this merge's, and a finished
// merge's OUT holds exactly its outputs.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/result.h"

namespace hdrc {

// One merged run, computed from the shards' results.json documents alone (no file is read or
// written): every check above, then the merged document.
struct MergedRun {
  nlohmann::ordered_json doc;    // results.json of the merged run
  std::vector<size_t> shard_of;  // doc["cases"][i] came from shard shard_of[i]
  int n = 0;                     // N of the shards' K/N
  int exit_code = 0;             // the merged run's (README "Exit codes")
};
// `docs[i]` is `dirs[i]`/results.json, schema-checked (read_given_results_json); `dirs` name the
// shards in errors. Errors carry the whole message (file, field and both values).
Result<MergedRun> merge_results(const std::vector<nlohmann::ordered_json>& docs,
                                const std::vector<std::string>& dirs);

// A case image's path as a results.json names it ("cases/<id>/<name>.exr"): relative, inside the
// run folder (no "..", no absolute path, no empty component). False for anything else.
bool safe_image_path(const std::string& rel);

// The cases and goldens folders a shard ran on, from its results.json provenance (`--cases` and
// `--goldens` of provenance.command_line, resolved against provenance.cwd); none when absent.
std::vector<std::string> shard_input_folders(const nlohmann::ordered_json& doc);

// `hdrconform merge OUT DIR...`. `protected_dirs`: the folders OUT must not be, be inside or hold
// besides the shards (the default cases and goldens folders). Returns the process exit code: the
// merged run's, or 2 when refused (nothing written outside OUT, OUT's published run unchanged).
int merge_runs(const std::string& out_dir, const std::vector<std::string>& shard_dirs,
               const std::vector<std::string>& protected_dirs = {});

}  // namespace hdrc
