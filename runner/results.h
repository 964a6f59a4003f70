// Machine-readable results of a run: results.json (described by runner/results.schema.json) and
// junit.xml, plus the per-case images the run wrote (RunOptions::image_dir).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/result.h"
#include "report/html_report.h"
#include "runner/run.h"

namespace hdrc {

// results.json is written compact (one line): half the size of an indented one.
std::string results_json(const RunReport& r);
std::string junit_xml(const RunReport& r);  // junit_from_results(results_json(r))

// junit.xml from a results.json document: one <testcase> per case (a failure names its worst
// pixel and the case page, report/c/<slug>.html) and, when the document has a "goldens" record
// (record_goldens), a second <testsuite> "hdrconform.goldens" with one <testcase> per
// checked golden. `merge` writes junit.xml from its merged document the same way.
std::string junit_from_results(const nlohmann::ordered_json& results);

// The case page of `case_id` relative to the report folder: "c/<slug>.html".
std::string case_page_path(const std::string& case_id);

// Reads and parses a results.json; errors name the file (and /cases when it is not an array).
Result<nlohmann::ordered_json> read_results_json(const std::string& path);

// A results.json the user names (`--rerun-failed DIR`, `--timings FILE`, `merge`'s shards):
// read_results_json, then every value present checked against runner/results.schema.json
// (embedded in the binary; a missing field is left to its reader's default), so that every field
// its readers use has the type and the values the schema gives. The first error names the file,
// the JSON pointer, the value and the valid choices, and counts the others.
Result<nlohmann::ordered_json> read_given_results_json(const std::string& path);

// The schema check of read_given_results_json, for a document already read from `file`.
Status check_results_schema(const nlohmann::ordered_json& doc, const std::string& file);

// `run`'s golden check (runner/goldens.h: check_run_against_goldens wrote OUT/goldens.json) as
// test results: adds "goldens" (counts, one entry per checked case) and summary.golden_failed to
// the results document.
Status record_goldens(nlohmann::ordered_json& results, const std::string& out_dir);

// --images failing|all|none: deletes OUT/cases/<id>/{input,reference,candidate}.exr of the cases
// the policy does not keep (failing keeps FAIL, ERROR, MISSING and failed goldens) and empties
// their "images" in the document.
Status apply_image_policy(nlohmann::ordered_json& results, const std::string& out_dir,
                          const std::string& policy);

// The exit code a results document stands for (README "Exit codes"; a failed golden fails).
int exit_code_of(const nlohmann::ordered_json& results);

// The run's one-line verdict ("hdrconform: N cases: P passed, F failed, ..."), the console's last
// word on a run and a merge: the counts of results.json's summary, where "failed" counts the
// failed goldens (missing, stale, regressed) with the failed cases, as the exit code does.
std::string headline_of(const nlohmann::ordered_json& results);

// The end of `run`/`verify`, after the golden check: golden outcomes recorded (when checked),
// summary.exit_code set to the process's exit code, --images applied, results.json and junit.xml
// rewritten, the report built (on `jobs` threads, 0: one per core, as `run -j`), the headline
// printed. Returns the exit code (kExitFail when writing failed).
// `report_info`, when given, receives what the report build measured (files, size, wall and
// CPU seconds).
int finish_run_outputs(const std::string& out_dir, int exit_code, bool goldens_checked,
                       const std::string& images, int jobs = 0,
                       report::ReportInfo* report_info = nullptr);

// Writes results.json and junit.xml into `out_dir`, each atomically; the report too unless the
// run has provenance (a `run`/`verify` of the command line, which ends with finish_run_outputs).
Status write_run_outputs(const RunReport& r, const std::string& out_dir);

}  // namespace hdrc
