// The executor: loads cases, runs the reference and the candidate engine on each, diffs, judges.
// It knows engines only through core/engine.h.
#pragma once

#include <chrono>
#include <map>
#include <string>
#include <vector>

#include "core/case.h"
#include "core/engine.h"
#include "runner/diff.h"

namespace hdrc {

// Process exit codes (documented in --help and README.md).
enum ExitCode : int {
  kExitPass = 0,      // every case passed
  kExitFail = 1,      // at least one case failed or errored
  kExitBadInput = 2,  // usage error or invalid case files; nothing was run or written
  kExitEngineUnavailable =
      3,  // no failure, but the candidate engine was unavailable: cases skipped
};

// PASS/FAIL: judged. ERROR: could not be evaluated. SKIP: the candidate engine was unavailable.
// KNOWN_LIMIT: listed in cases/known_limits.json for this engine. DEGENERATE: UE itself computes
// degenerate parameters for this combination; not evaluated. Only FAIL and ERROR fail a run.
enum class CaseVerdict { kPass, kFail, kError, kSkipped, kKnownLimit, kDegenerate };
const char* verdict_name(CaseVerdict v);

struct CaseResult {
  Case spec;
  CaseVerdict verdict = CaseVerdict::kSkipped;
  std::string reason;
  DiffStats stats;
  std::map<std::string, double> reference_values;  // named numbers the reference stage output
  double reference_seconds = 0, candidate_seconds = 0;
};

struct RunReport {
  std::vector<CaseResult> cases;
  DeviceInfo reference_device, candidate_device;
  std::string candidate_unavailable;  // reason, when the candidate engine could not start
  std::string started_utc;
  double wall_seconds = 0;
  int exit_code() const;
  int count(CaseVerdict v) const;
};

// Runs `cases` with `candidate` against `reference`. `on_case` is called after each case.
struct KnownLimit;
RunReport run_cases(const std::vector<Case>& cases, Engine& reference, Engine& candidate,
                    const std::vector<KnownLimit>& known_limits,
                    void (*on_case)(const CaseResult&, size_t index, size_t total) = nullptr);

}  // namespace hdrc
