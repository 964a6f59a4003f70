// The executor: runs the reference and a candidate engine on each case, diffs, judges. It knows
// engines only through core/engine.h, and makes one engine of each kind per worker thread
// (EngineFactory), so no engine is ever shared between threads.
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/case.h"
#include "core/engine.h"
#include "runner/case_loader.h"
#include "runner/diagnosis.h"
#include "runner/diff.h"
#include "runner/dither.h"
#include "runner/tolerance.h"

namespace hdrc {

// Process exit codes (documented in --help and README.md), in order of precedence when several
// apply: interrupted, fail, engine unavailable, pass with warnings, pass.
enum ExitCode : int {
  kExitPass = 0,      // every case passed
  kExitFail = 1,      // at least one case failed, errored or had no candidate image
  kExitBadInput = 2,  // usage error or invalid case files; nothing was run or written
  kExitEngineUnavailable =
      3,                      // no failure, but the candidate engine was unavailable: cases skipped
  kExitPassWithWarnings = 4,  // every case passed; at least one is over a warn level
  kExitInterrupted = 130,     // SIGINT (128 + 2): finished cases written, the rest NOT_RUN
};

// PASS/FAIL: judged. ERROR: could not be evaluated. SKIP: the candidate engine was unavailable.
// KNOWN_LIMIT: listed in cases/known_limits.json for this engine. DEGENERATE: UE itself computes
// degenerate parameters for this combination; not evaluated. MISSING: `verify` found no candidate
// image. NOT_RUN: the run was interrupted first. UNSUPPORTED: the candidate declined the case or
// its stage (verify's candidate protocol); never a pass, fails the run only under
// `verify --require-all`. FAIL, ERROR and MISSING fail a run.
enum class CaseVerdict {
  kPass,
  kFail,
  kError,
  kSkipped,
  kKnownLimit,
  kDegenerate,
  kMissing,
  kNotRun,
  kUnsupported
};
const char* verdict_name(CaseVerdict v);

struct CaseResult {
  Case spec;
  CaseVerdict verdict = CaseVerdict::kNotRun;
  std::string reason;
  Tolerance tolerance;     // the tolerance applied: the case's, with any overlays
  bool has_stats = false;  // the images were diffed (PASS and FAIL)
  DiffStats stats;
  bool has_dither = false;  // the tolerance has a dither criterion and the images were diffed
  DitherStats dither;
  bool exact_pattern_judged = false;  // the dither's exact pattern was judged (runner/dither.h)
  std::string encoding;               // how outputs were decoded to nits (OutputEncoding::describe)
  std::vector<std::string> warnings;
  // A FAIL's possible causes, where its error matches a known mistake's signature
  // (runner/diagnosis.h); each is also in `reason`. Never changes the verdict.
  std::vector<Hint> hints;
  bool could_be_tightened = false;
  double budget_used = 0;  // largest observed/max ratio (Verdict::budget_used)
  bool has_params = false;
  ParamBlock params;                               // the resolved parameters
  std::map<std::string, double> reference_values;  // named numbers the reference stage output
  std::map<std::string, std::string> images;  // "input"/"reference"/"candidate" → path relative
                                              // to the output directory, for those written
  // A PASS within a device allowance only (RunOptions::device_allowances): the classes the
  // reference's device ranges take in, how many values lay outside the tight bounds but inside
  // those ranges, and the tight verdict's reason. Empty for a tight PASS.
  std::vector<std::string> device_allowances;
  size_t allowance_values = 0;
  PixelRef first_allowance;
  std::string tight_reason;
  double reference_seconds = 0, candidate_seconds = 0, diff_seconds = 0;
  double seconds() const { return reference_seconds + candidate_seconds + diff_seconds; }
};

// Where a run came from (runner/provenance.h fills it; results.json "provenance").
struct RunProvenance {
  std::string commit;          // git HEAD of the source tree (+ "-dirty"), or "unknown"
  std::string command_line;    // shell-quoted argv
  std::string reproduce;       // command_line without the options choosing cases and outputs
  std::string reproduce_args;  // the same after the subcommand: what a case's reproduce repeats
  std::string cwd;
  std::string hostname;                 // gethostname(2): JUnit's testsuite hostname
  std::string shader_dir, shader_hash;  // the Vulkan engine's shaders (path, directory_hash)
  std::string build_type, compiler, tool_version;
  std::string suite_fingerprint;  // SHA-256 of the selected (unsharded) ids and case hashes
  size_t suite_cases = 0;         // how many cases the unsharded selection has
  std::string shard_plan;         // how --shard split them (shard_plan_description)
  std::string images = "all";     // --images: failing, all, none
};

struct RunReport {
  std::string command = "run";  // "run" or "verify"
  std::vector<CaseResult> cases;
  DeviceInfo reference_device, candidate_device;
  std::string candidate_unavailable;  // reason, when the candidate engine could not start
  std::string started_utc;
  double wall_seconds = 0;
  int jobs = 1;
  std::string shard;  // "K/N", or "" when unsharded
  bool interrupted = false;
  int max_fail = 0;                  // --maxfail N (0: none)
  bool stopped_by_max_fail = false;  // N cases failed and the rest did not start (NOT_RUN)
  bool require_all = false;          // verify --require-all: UNSUPPORTED cases fail the run
  // verify --candidate-limits FILE: the port's declared deviations (shown by the report).
  std::string candidate_limits_file;
  std::vector<KnownLimit> candidate_limits;
  std::string reference_mode = "baked";  // verify --reference: "baked" or "analytic"
  std::string reproduce_args;            // options a case's reproduce command repeats (verify.h)
  RunProvenance provenance;
  int exit_code() const;
  int count(CaseVerdict v) const;
  int warned() const;  // passing cases with warnings
};

using EngineFactory = std::function<std::unique_ptr<Engine>()>;

struct KnownLimit;
struct RunOptions {
  int jobs = 0;  // worker threads; 0 = every core
  std::vector<KnownLimit> known_limits;
  std::vector<ToleranceOverlay> overlays;
  // Where cases/<case id>/{input,reference,candidate}.exr are written ("": nowhere).
  std::string image_dir;
  // Set (e.g. by a SIGINT handler) to stop starting cases; cases not started are NOT_RUN.
  const std::atomic<bool>* interrupt = nullptr;
  // --maxfail N (pytest's): no case starts once N cases have failed (FAIL, ERROR, MISSING); the
  // cases not started are NOT_RUN. 0: no limit.
  int max_fail = 0;
  // Called for each case in case order as soon as it and every case before it have finished,
  // so the output is the same for any -j. `done` counts finished cases.
  std::function<void(const CaseResult&, size_t index, size_t total)> on_case;
  // verify --candidate-dir: a non-empty answer marks the case MISSING with that reason before
  // the candidate engine is asked.
  std::function<std::string(const Case&)> missing_candidate;
  // A case that fails the tight bounds (a float32-exact device) is judged again against the
  // device allowances its reference derives from the candidate's precision properties
  // (docs/precision.md, "Device allowances"); within them it passes with a named allowance.
  // false (`--no-device-allowance`): such a case fails, for reference-grade results.
  bool device_allowances = true;
  // The memory the run's cases may hold at once (bytes; runner/budget.h run_memory_budget): a
  // worker starts a case only when its estimate (case_cost) fits beside the cases running, and
  // cases start in case order, so a large one is not overtaken for ever by small ones; a case
  // alone always starts. 0: no gate (every worker starts its next case at once).
  double memory_budget = 0;
};

// Runs `cases` with a candidate engine against the reference engine. Each worker creates its own
// engines from the factories.
RunReport run_cases(const std::vector<Case>& cases, const EngineFactory& reference,
                    const EngineFactory& candidate, const RunOptions& options);

// "K/N" with 1 <= K <= N: which shard of a CI matrix to run.
struct Shard {
  int k = 1, n = 1;
};
Result<Shard> parse_shard(const std::string& text);
// Cost-balanced shards: each case has a cost (its seconds in the shard timings when they list
// it, else static_case_cost); cases are taken from the most to the least costly (ties by id) and
// each goes to the shard with the least total cost so far (ties: the lowest K). The result is in
// the input's order. Deterministic for the same cases and timings, and the shards of one N are
// disjoint and together the whole list.
std::vector<Case> select_shard(const std::vector<Case>& cases, const Shard& shard);
// The assignment select_shard makes (longest processing time first): case i's shard, 0-based, for
// `costs[i]` and `ids[i]` (the tie-break) over `n` shards.
std::vector<int> plan_shards(const std::vector<double>& costs, const std::vector<std::string>& ids,
                             int n);

// A deterministic cost estimate in seconds, for cases no timings list: its stage's measured
// figures (core/pipeline.h StageCost) over the case's pixels and baked LUT texels as its pipeline
// resolves them; 0 for a degenerate case (never evaluated).
double static_case_cost(const Case& c);

// The timings --shard balances with (process-wide, set once before select_shard): `path` (a
// results.json; its cases' seconds.total), else `out_dir`/results.json when it exists, else none
// (static costs only). An unreadable `path` is an error naming it.
Status use_shard_timings(const std::string& path, const std::string& out_dir);
// "static" or "timings sha256 <12 hex> (N cases timed)", by content, not path: recorded per
// run; `merge` refuses shards planned differently (they could overlap or leave cases out).
std::string shard_plan_description();

// Where a case's images go, relative to the output directory: "cases/<case id>" (case ids
// contain '/', so these are nested folders).
std::string case_image_dir(const std::string& case_id);  // "cases/<case id>"

}  // namespace hdrc
