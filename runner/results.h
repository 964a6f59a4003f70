// Machine-readable results of a run: results.json (described by runner/results.schema.json) and
// junit.xml, plus the per-case images the run wrote (RunOptions::image_dir).
#pragma once

#include <string>

#include "runner/run.h"

namespace hdrc {

std::string results_json(const RunReport& r);
std::string junit_xml(const RunReport& r);

// Writes results.json and junit.xml into `out_dir`, each atomically, then the HTML report.
Status write_run_outputs(const RunReport& r, const std::string& out_dir);

}  // namespace hdrc
