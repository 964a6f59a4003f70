// Machine-readable results of a run: results.json and junit.xml.
#pragma once

#include <string>

#include "runner/run.h"

namespace hdrc {

std::string results_json(const RunReport& r);
std::string junit_xml(const RunReport& r);

// Writes results.json, junit.xml and report/index.html into `out_dir`, each atomically.
Status write_run_outputs(const RunReport& r, const std::string& out_dir);

}  // namespace hdrc
