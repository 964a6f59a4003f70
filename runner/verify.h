// Running the suite from the command line (`run` and `verify`), and the candidates `verify` uses:
// images in a directory, or a command run per case. Both are engines (core/engine.h), so they get
// the same executor, metrics, tolerances, exit codes and report as `run`.
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "core/engine.h"
#include "core/image.h"
#include "runner/case_loader.h"
#include "runner/run.h"

namespace hdrc {

// verify --candidate-dir DIR: the candidate output of case ID is DIR/ID.exr (ids contain '/',
// so these are nested folders), RGBA or RGB float EXR the size of the case's input.
class CandidateDirEngine final : public Engine {
 public:
  explicit CandidateDirEngine(std::string dir) : dir_(std::move(dir)) {}
  std::string name() const override { return "candidate-dir"; }
  Status init() override;
  DeviceInfo device() const override;
  Result<Image> run(const ResolvedCase& c) override;
  std::string image_path(const std::string& case_id) const;  // DIR/ID.exr
  // "" when the image exists, else why it is missing.
  std::string missing(const std::string& case_id) const;

 private:
  std::string dir_;
};

// Splits a command template into argv like a shell would split words, without a shell:
// whitespace separates words; '…' quotes literally; "…" quotes with \" and \\ escapes; a
// backslash outside quotes escapes the next character. Nothing else is special ($, `, ;, |, *).
Result<std::vector<std::string>> split_command_template(const std::string& text);

// The first word of the form {name} (lower-case letters, digits, '_'; not ${name}, a shell's)
// that is none of the placeholders below, e.g. a misspelt "{ouput}"; "" when there is none.
std::string unknown_placeholder(const std::vector<std::string>& argv);

// Replaces {input}, {params}, {output} and {id} in every word (after splitting, so no value is
// ever split or interpreted).
std::vector<std::string> expand_placeholders(const std::vector<std::string>& argv,
                                             const std::string& input, const std::string& params,
                                             const std::string& output, const std::string& id);

struct CommandResult {
  int exit_status = -1;  // the exit status, or -1 when killed by a signal or timed out
  int signal = 0;        // the signal that ended it (0: none)
  bool timed_out = false;
  std::string error;          // fork/exec failure
  std::string output;         // stdout and stderr, the first CommandLimits::max_log_bytes, UTF-8
  size_t output_dropped = 0;  // bytes of output past that limit (read and dropped)
};
struct CommandLimits {
  size_t max_log_bytes = size_t{1} << 20;      // output kept (and written to the log)
  size_t max_file_bytes = kMaxImageFileBytes;  // RLIMIT_FSIZE: no file it writes grows past this
};
// Runs argv (fork/exec, PATH search, no shell) in its own process group, reading its stdout and
// stderr through a pipe (kept up to the limit, the rest dropped) and writing them to `log_path`
// ("" : nowhere). `timeout_s` covers the whole command and the reading of its output. When the
// command ends (exit, signal or timeout) its whole process group is killed, so no child it
// started survives the case.
CommandResult run_command(const std::vector<std::string>& argv, const std::string& log_path,
                          double timeout_s, const CommandLimits& limits = {});

// verify --timeout: seconds, finite, > 0 and <= kMaxTimeoutSeconds (NaN and inf are refused).
// A CLI11 validator: "" when valid, else the message.
inline constexpr double kMaxTimeoutSeconds = 86400;
std::string check_timeout_seconds(std::string& text);

// verify --sandbox: the bubblewrap program (bwrap on PATH; "" when there is none), and argv wrapped
// in it so the command sees the system read-only, no network, its own PID namespace (its
// processes end with it), and can write only `case_dir` (absolute inside the sandbox).
std::string sandbox_program();
std::vector<std::string> sandbox_argv(const std::vector<std::string>& argv,
                                      const std::string& case_dir);

// The candidate protocol's exit statuses (README, "Verifying a port"): besides 0 (image written)
// a candidate command may decline. Declined cases are UNSUPPORTED: never a pass, counted apart,
// and they fail the run only under `verify --require-all`. The first line the command printed is
// the reason shown.
inline constexpr int kCandidateDeclinesCase = 77;   // "unsupported: skip this case"
inline constexpr int kCandidateDeclinesStage = 78;  // "unsupported: this whole stage"; the stage's
                                                    // later cases are not even started

// The stages a candidate declined, shared by every worker's engine of one run.
class DeclinedStages {
 public:
  void add(const std::string& stage, const std::string& reason);
  std::string reason(const std::string& stage) const;  // "" when not declined

 private:
  mutable std::mutex mu_;
  std::map<std::string, std::string> stages_;
};

// verify --candidate-cmd TEMPLATE: for each case, exports it into OUT/cases/ID/ (params.json,
// input.exr and the stage's other images, runner/export.h), runs the command with {input},
// {params}, {output} = OUT/cases/ID/candidate_output.exr and {id}, and reads what it wrote. A
// command that fails, times out or writes no image is an error for that case only.
class CandidateCommandEngine final : public Engine {
 public:
  CandidateCommandEngine(std::vector<std::string> argv, std::string out_dir, double timeout_s,
                         std::shared_ptr<DeclinedStages> declined = nullptr, bool sandbox = false)
      : argv_(std::move(argv)),
        out_dir_(std::move(out_dir)),
        timeout_s_(timeout_s),
        declined_(declined ? std::move(declined) : std::make_shared<DeclinedStages>()),
        sandbox_(sandbox) {}
  std::string name() const override { return "candidate-cmd"; }
  Status init() override;
  DeviceInfo device() const override;
  Result<Image> run(const ResolvedCase& c) override;
  std::string unsupported(const ResolvedCase& c) const override;

 private:
  Error decline(const ResolvedCase& c, int status, const std::string& said);
  std::vector<std::string> argv_;
  std::string out_dir_;
  double timeout_s_;
  std::shared_ptr<DeclinedStages> declined_;
  std::string declined_case_, declined_reason_;  // the last case this engine's command declined
  bool sandbox_ = false;
};

// verify --candidate-limits FILE: a port's declared deviations, in known_limits.json's form
// ({"limits": [{"cases": GLOB, "engine": "candidate-cmd" | "candidate-dir", "reason": TEXT}]}).
// Every problem is appended to `errors`, naming the file, the JSON pointer, the value and the
// valid choices. Each reason is prefixed so the verdict says who declared it.
std::vector<KnownLimit> load_candidate_limits(const std::string& path, std::vector<Error>* errors);

// The command that reruns one case as this run ran it, printed with every failing case (console
// and JUnit): "hdrconform run --filter '=ID' --out out/repro" plus the run's options that matter
// (RunReport::reproduce_args: --cases, --engine, --candidate-cmd ...).
std::string reproduce_command(const RunReport& r, const std::string& case_id);

struct SuiteOptions {
  std::string command = "run";  // "run" or "verify"
  std::string cases_dir;
  std::string out_dir = "out";
  int jobs = 0;              // 0: every core
  std::string shard;         // "K/N" or ""
  RunProvenance provenance;  // recorded in results.json (runner/provenance.h)
  // verify --candidate-dir: report absent images as MISSING.
  const CandidateDirEngine* candidate_dir = nullptr;
  bool require_all = false;         // verify --require-all: UNSUPPORTED fails the run
  std::string candidate_limits;     // verify --candidate-limits FILE ("": none)
  std::string candidate_engine;     // "candidate-cmd" / "candidate-dir" (which limits apply)
  std::string reference = "baked";  // verify --reference: "baked" (UE's LUT) or "analytic"
  std::string reproduce_args;       // the options a reproduce command repeats (shell-quoted)
  // --no-device-allowance clears it: a case within a device allowance only fails
  // (RunOptions::device_allowances).
  bool device_allowances = true;
  int max_fail = 0;  // --maxfail N: no case starts after N failures (RunOptions::max_fail)
  // --failed-first DIR: the cases DIR/results.json records as failed (selection.h:
  // failed_case_ids) run first, then the others, each group in case order; after --shard, so
  // the shards stay those of the plan.
  std::string failed_first_dir;
  std::set<std::string> failed_first;
  // --memory-budget in bytes (0: the machine's, runner/budget.h run_memory_budget): a case whose
  // estimate is over it is refused before any work (exit 2); RunOptions::memory_budget.
  double memory_budget = 0;
};

// The reference engine a suite run compares against: "baked" samples the LUT UE bakes (the
// default); "analytic" evaluates CombineLUTs per pixel, for ports that do not bake a LUT, judged
// with cases/tolerance_overlays_analytic.json applied over the usual tolerances.
inline constexpr const char* kReferenceModes = "baked, analytic";

// The part of `run`/`verify` after the cases are loaded: loads the tolerance overlays, applies
// --shard, runs with -j workers (Ctrl-C stops starting cases; the rest are NOT_RUN), prints a
// progress line per case (a progress bar on a terminal) and the summary, writes results.json,
// junit.xml, the case images and the report into out_dir. Returns the exit code.
int run_suite(std::vector<Case> cases, const std::vector<KnownLimit>& limits,
              const EngineFactory& candidate, const SuiteOptions& options);

}  // namespace hdrc
