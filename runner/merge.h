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
#pragma once

#include <string>
#include <vector>

namespace hdrc {

// Returns the process exit code: the merged run's (README "Exit codes"), or 2 when refused.
int merge_runs(const std::string& out_dir, const std::vector<std::string>& shard_dirs);

}  // namespace hdrc
