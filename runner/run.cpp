#include "runner/run.h"

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "core/pipeline.h"
#include "runner/budget.h"
#include "runner/case_loader.h"
#include "runner/dither.h"
#include "runner/goldens.h"
#include "runner/json_read.h"
#include "runner/results.h"

namespace hdrc {

const char* verdict_name(CaseVerdict v) {
  switch (v) {
    case CaseVerdict::kPass:
      return "PASS";
    case CaseVerdict::kFail:
      return "FAIL";
    case CaseVerdict::kError:
      return "ERROR";
    case CaseVerdict::kSkipped:
      return "SKIP";
    case CaseVerdict::kKnownLimit:
      return "KNOWN_LIMIT";
    case CaseVerdict::kDegenerate:
      return "DEGENERATE";
    case CaseVerdict::kMissing:
      return "MISSING";
    case CaseVerdict::kNotRun:
      return "NOT_RUN";
    case CaseVerdict::kUnsupported:
      return "UNSUPPORTED";
  }
  return "?";
}

int RunReport::count(CaseVerdict v) const {
  int n = 0;
  for (const auto& c : cases) n += c.verdict == v;
  return n;
}

int RunReport::warned() const {
  int n = 0;
  for (const auto& c : cases) n += c.verdict == CaseVerdict::kPass && !c.warnings.empty();
  return n;
}

int RunReport::exit_code() const {
  if (interrupted) return kExitInterrupted;
  if (count(CaseVerdict::kFail) + count(CaseVerdict::kError) + count(CaseVerdict::kMissing) > 0)
    return kExitFail;
  if (require_all && count(CaseVerdict::kUnsupported) > 0) return kExitFail;
  if (count(CaseVerdict::kSkipped) > 0) return kExitEngineUnavailable;
  if (warned() > 0) return kExitPassWithWarnings;
  return kExitPass;
}

std::string case_image_dir(const std::string& case_id) {
  return "cases/" + case_id;
}

Result<Shard> parse_shard(const std::string& text) {
  Shard s;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%d/%d%c", &s.k, &s.n, &tail) != 2 || s.n < 1 || s.k < 1 ||
      s.k > s.n)
    return Error{"", "--shard", "invalid shard '" + text + "'", "K/N with 1 <= K <= N, e.g. 2/3"};
  return s;
}

namespace {

// The timings --shard balances with (use_shard_timings): case id → seconds, and where from.
struct ShardTimings {
  std::map<std::string, double> seconds;
  std::string description = "static";
};
ShardTimings& shard_timings() {
  static ShardTimings t;
  return t;
}

}  // namespace

double static_case_cost(const Case& c) {
  // The stage's measured cost (core/pipeline.h StageCost, declared beside each pipeline's stages
  // and fitted by bench/shard_balance.py): a fixed part, the image's pixels (a bake's N² x N
  // lattice) and the texels of a LUT baked before the pixel passes. The sizes are the host
  // derivation's (Pipeline::resolve, as the run does), so a LUT size set by a cvar or a setting of
  // any pipeline counts; a degenerate case is never evaluated and costs nothing.
  if (!c.stage) return 0;
  const StageCost k = stage_cost(*c.stage);
  const CaseCost size = case_cost(c);  // a file input's size from its header (runner/budget.h)
  const auto resolution = pipeline_of(*c.stage).resolve(c, size.width, size.height);
  if (!resolution) return k.us * 1e-6;  // reported at once as an error
  if (!resolution->degenerate.empty()) return 0;
  const double n = std::clamp(resolution->params.lut_size, 0, 256);
  const bool bakes =
      std::any_of(c.stage->passes.begin(), c.stage->passes.end(),
                  [](const StagePass& p) { return p.domain == Dispatch::kLutTexels; });
  const double pixels = c.stage->takes_input ? size.pixels : n * n * n;
  const double texels = bakes && c.stage->takes_input ? n * n * n : 0;
  return (k.us + k.us_per_pixel * pixels + k.us_per_lut_texel * texels) * 1e-6;
}

Status use_shard_timings(const std::string& path, const std::string& out_dir) {
  namespace fs = std::filesystem;
  std::string file = path;
  std::error_code ec;
  if (file.empty() && !out_dir.empty() && fs::exists(out_dir + "/results.json", ec))
    file = out_dir + "/results.json";
  ShardTimings t;
  if (!file.empty()) {
    // Bounded like every JSON input (runner/json_read.h): size and nesting checked before parsing.
    auto text = read_bounded_file(file, kMaxResultsFileBytes, "timings (a results.json)");
    if (!text) {
      if (!path.empty()) return text.error();
      return {};  // an unreadable results.json left in --out: static costs
    }
    auto parsed = parse_json_text<nlohmann::ordered_json>(file, *text);
    if (!parsed && !path.empty()) return parsed.error();
    const nlohmann::ordered_json doc = parsed ? std::move(*parsed) : nlohmann::ordered_json();
    if (!doc.is_object() || !doc.contains("cases") || !doc["cases"].is_array()) {
      if (!path.empty()) return Error{file, "/cases", "not a results.json with a cases array", ""};
      return {};  // a broken results.json left in --out: static costs
    }
    // --timings FILE is checked against runner/results.schema.json, as every results.json named
    // on the command line; one left in --out is only read where its types fit.
    if (!path.empty())
      if (Status st = check_results_schema(doc, file); !st) return st.error();
    // --out's own results only when they are a whole run: a shard's would balance by its cases
    // alone, and the other shards (with other --out folders) would plan differently.
    if (path.empty() && doc.contains("shard") && !doc["shard"].is_null()) {
      shard_timings() = ShardTimings{};
      return {};
    }
    for (const auto& c : doc["cases"]) {
      if (!c.is_object() || !c.contains("id") || !c["id"].is_string()) continue;
      const auto sec = c.find("seconds");
      if (sec == c.end() || !sec->is_object() || !sec->contains("total") ||
          !(*sec)["total"].is_number())
        continue;
      const double v = (*sec)["total"].get<double>();
      if (v > 0 && std::isfinite(v)) t.seconds[c["id"].get<std::string>()] = v;
    }
    // The plan depends on the file's content only: shards that read the same timings from
    // different paths (each CI job's own workspace) plan alike, and merge accepts them.
    t.description = "timings sha256 " + sha256_hex(*text).substr(0, 12) + " (" +
                    std::to_string(t.seconds.size()) + " cases timed)";
  }
  shard_timings() = std::move(t);
  return {};
}

std::string shard_plan_description() {
  return shard_timings().description;
}

namespace {
// A case's cost for the balance: its recorded seconds, at most kOneTimeClip times the static
// model's estimate. A run's recorded seconds include costs paid once per process, by whichever
// case came first: compiling a stage's shaders, creating its pipelines, baking a LUT that later
// cases share. In another split they fall on another case in every shard, so an uncapped
// timing piles one-time costs on one case (measured on the default suite, 3 shards run one after
// another on 2 cores: the slowest shard 21 % over the fastest uncapped, 15 % capped, 10 % with
// the static model alone; docs/performance-notes.md).
constexpr double kOneTimeClip = 3.0;
// A case no timings list costs the model's estimate scaled to the timings' seconds (`scale`: the
// median of seconds / static_case_cost over the timed cases of the selection, the static model in
// this machine's seconds).
double shard_cost(const Case& c, double model, const ShardTimings& t, double scale) {
  const auto it = t.seconds.find(c.id);
  return it == t.seconds.end() ? model * scale : std::min(it->second, kOneTimeClip * scale * model);
}
}  // namespace

std::vector<int> plan_shards(const std::vector<double>& costs, const std::vector<std::string>& ids,
                             int n) {
  std::vector<size_t> order(costs.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    if (costs[a] != costs[b]) return costs[a] > costs[b];
    return ids[a] < ids[b];
  });
  std::vector<double> load(static_cast<size_t>(std::max(n, 1)), 0.0);
  std::vector<int> shard(costs.size(), 0);
  for (const size_t i : order) {
    const size_t k = static_cast<size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    load[k] += costs[i];
    shard[i] = static_cast<int>(k);
  }
  return shard;
}

std::vector<Case> select_shard(const std::vector<Case>& cases, const Shard& shard) {
  const ShardTimings& t = shard_timings();
  std::vector<double> model(cases.size());
  for (size_t i = 0; i < cases.size(); ++i) model[i] = static_case_cost(cases[i]);
  double scale = 1.0;
  std::vector<double> ratios;
  for (size_t i = 0; i < cases.size(); ++i)
    if (auto it = t.seconds.find(cases[i].id); it != t.seconds.end() && model[i] > 0)
      ratios.push_back(it->second / model[i]);
  if (!ratios.empty()) {
    std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
    scale = ratios[ratios.size() / 2];
  }
  std::vector<double> costs(cases.size());
  std::vector<std::string> ids(cases.size());
  for (size_t i = 0; i < cases.size(); ++i) {
    costs[i] = shard_cost(cases[i], model[i], t, scale);
    ids[i] = cases[i].id;
  }
  const std::vector<int> plan = plan_shards(costs, ids, shard.n);
  std::vector<Case> out;
  for (size_t i = 0; i < cases.size(); ++i)
    if (plan[i] == shard.k - 1) out.push_back(cases[i]);
  return out;
}

namespace {

std::string utc_now() {
  char buf[32];
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The name known limits select a device by: the device's own, with ", worst-case device model"
// appended when the candidate ran as the worst-case conformant device (--device-model worst).
std::string known_limit_device_name(const DeviceInfo& d) {
  return d.device + (d.precision.model == "worst" ? ", worst-case device model" : "");
}

struct Worker {
  std::unique_ptr<Engine> reference, candidate;
};

// RunOptions::memory_budget: case i starts when every case before it has started and its
// estimate fits beside the estimates of the cases running (or none is running).
class MemoryGate {
 public:
  MemoryGate(double budget, const std::atomic<bool>* interrupt)
      : budget_(budget), interrupt_(interrupt) {}
  // False when the run was interrupted while waiting (the case is not started).
  bool enter(size_t index, double bytes) {
    std::unique_lock<std::mutex> lock(mu_);
    for (;;) {
      if (interrupt_ && interrupt_->load()) return false;
      if (index == next_ && (budget_ <= 0 || running_ == 0 || in_use_ + bytes <= budget_)) break;
      // Polled too: a SIGINT handler sets the flag without notifying.
      cv_.wait_for(lock, std::chrono::milliseconds(100));
    }
    ++next_;
    ++running_;
    in_use_ += bytes;
    cv_.notify_all();
    return true;
  }
  void leave(double bytes) {
    std::lock_guard<std::mutex> lock(mu_);
    --running_;
    in_use_ -= bytes;
    cv_.notify_all();
  }

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  const double budget_;
  const std::atomic<bool>* interrupt_;
  size_t next_ = 0;  // the next case to start
  int running_ = 0;
  double in_use_ = 0;
};

class Executor {
 public:
  Executor(const RunOptions& o, const RunReport& report) : opt_(o), report_(report) {}

  CaseResult run_one(const Case& c, Worker& w) {
    CaseResult r;
    r.spec = c;
    r.tolerance = c.tolerance;
    const KnownLimit* limit = nullptr;
    for (const KnownLimit& k : opt_.known_limits)
      if (k.engine == w.candidate->name() && matches_filter(c.id, k.cases) &&
          matches_filter(known_limit_device_name(report_.candidate_device), k.device))
        limit = &k;
    auto resolved = resolve_case(c);
    if (!resolved) return error(std::move(r), resolved.error().to_string());
    r.has_params = true;
    r.params = resolved->params;
    if (!resolved->degenerate.empty()) {
      r.verdict = CaseVerdict::kDegenerate;
      r.reason = resolved->degenerate;
      return r;
    }
    auto tol =
        apply_overlays(c, w.candidate->name(), report_.candidate_device.device, opt_.overlays);
    if (!tol) return error(std::move(r), tol.error().to_string());
    r.tolerance = *tol;
    const OutputEncoding enc = output_encoding(*c.stage, resolved->params);
    r.encoding = enc.describe();
    if (!save(r, "input", resolved->input)) return r;
    if (!report_.candidate_unavailable.empty() && !limit) {
      r.verdict = CaseVerdict::kSkipped;
      r.reason = report_.candidate_unavailable;
      return r;
    }
    // A stage the candidate declined earlier: its later cases are not even started.
    if (!limit) {
      if (std::string why = w.candidate->unsupported(*resolved); !why.empty())
        return unsupported(std::move(r), std::move(why));
    }
    // The reference runs for every evaluated case, known limits and missing candidates included,
    // so its outputs (and any error of its own) are part of every run.
    auto t0 = std::chrono::steady_clock::now();
    auto ref_img = w.reference->run(*resolved);
    r.reference_seconds = seconds_since(t0);
    if (!ref_img) return error(std::move(r), "reference: " + ref_img.error().to_string());
    r.reference_values = ref_img->values;
    if (!save(r, "reference", *ref_img)) return r;
    if (limit) {
      r.verdict = CaseVerdict::kKnownLimit;
      r.reason = "known limit of " + limit->engine + ": " + limit->reason;
      return r;
    }
    if (opt_.missing_candidate) {
      if (std::string why = opt_.missing_candidate(c); !why.empty()) {
        r.verdict = CaseVerdict::kMissing;
        r.reason = why;
        return r;
      }
    }
    t0 = std::chrono::steady_clock::now();
    auto cand_img = w.candidate->run(*resolved);
    r.candidate_seconds = seconds_since(t0);
    if (!cand_img) {
      if (std::string why = w.candidate->unsupported(*resolved); !why.empty())
        return unsupported(std::move(r), std::move(why));
      return error(std::move(r), w.candidate->name() + ": " + cand_img.error().to_string());
    }
    if (cand_img->width != ref_img->width || cand_img->height != ref_img->height)
      return error(std::move(r), w.candidate->name() + ": the candidate image is " +
                                     std::to_string(cand_img->width) + "x" +
                                     std::to_string(cand_img->height) + ", the reference " +
                                     std::to_string(ref_img->width) + "x" +
                                     std::to_string(ref_img->height));
    if (!save(r, "candidate", *cand_img)) return r;
    t0 = std::chrono::steady_clock::now();
    r.stats = diff_images(resolved->input, *ref_img, *cand_img, enc, r.tolerance);
    Verdict v;
    if (r.tolerance.dither.judged) {
      // The dither's properties against the undithered image (the stage's input) and the case's
      // amount (runner/dither.h); the exact pattern only where the device makes it deterministic.
      if (c.stage->id != StageId::kDither)
        return error(std::move(r),
                     "the tolerance's dither criterion needs the dither stage, whose "
                     "input is the undithered image; this case's stage is " +
                         std::string(c.stage->name));
      r.dither = dither_stats(resolved->input, *cand_img, resolved->params.dither_amount,
                              r.tolerance.dither);
      r.has_dither = true;
      r.exact_pattern_judged = exact_pattern_judged(r.tolerance.dither, report_.candidate_device);
      v = judge_dither(r.stats, r.dither, r.tolerance, r.exact_pattern_judged,
                       !c.pins_nonfinite.empty());
    } else {
      v = judge(r.stats, r.tolerance, !c.pins_nonfinite.empty());
    }
    r.diff_seconds = seconds_since(t0);
    r.has_stats = true;
    r.verdict = v.pass ? CaseVerdict::kPass : (v.error ? CaseVerdict::kError : CaseVerdict::kFail);
    r.reason = v.reason;
    r.warnings = v.warnings;
    r.could_be_tightened = v.could_be_tightened;
    r.budget_used = v.budget_used;
    // A float32-exact device (lavapipe as it is, the reference) needs no allowance: its results
    // are judged by the tight bounds alone (runner/dither.h float32_exact_device).
    if (r.verdict == CaseVerdict::kFail && opt_.device_allowances &&
        !float32_exact_device(report_.candidate_device))
      judge_with_device_allowances(r, *resolved, *cand_img, enc, w);
    // A failing case's possible causes (docs/diagnosis.md): failing cases only, so a passing one
    // costs nothing. A dither's error is grain, judged by its statistics: not diagnosed.
    if (r.verdict == CaseVerdict::kFail && !r.tolerance.dither.judged) {
      const auto t1 = std::chrono::steady_clock::now();
      if (const auto& signatures = builtin_signatures(); signatures) {
        DiagnosisInput in;
        in.input = &resolved->input;
        in.reference = &*ref_img;
        in.candidate = &*cand_img;
        in.encoding = &enc;
        in.resolved = &*resolved;
        in.reference_of = [&w](const ResolvedCase& v) { return w.reference->run(v); };
        r.hints = diagnose(*signatures, in);
      }
      for (const Hint& h : r.hints) r.reason += "; " + h.text();
      r.diff_seconds += seconds_since(t1);
    }
    return r;
  }

 private:
  // A case that failed the tight bounds, judged again against the device ranges its reference
  // derives from the candidate device's precision (the reference runs again, asked for them: the
  // tight pass pays nothing for them). Within them: a PASS with the allowance named; else the
  // FAIL stands, with the device judgement's reason (the candidate is outside what any
  // conformant device may produce).
  void judge_with_device_allowances(CaseResult& r, ResolvedCase resolved, const Image& candidate,
                                    const OutputEncoding& enc, Worker& w) {
    resolved.device = report_.candidate_device.precision;
    resolved.device_allowances = true;
    const auto t0 = std::chrono::steady_clock::now();
    auto ref = w.reference->run(resolved);
    if (!ref || ref->device_admissible.empty()) return;
    ref->admissible = std::move(ref->device_admissible);
    const DiffStats s = diff_images(resolved.input, *ref, candidate, enc, r.tolerance);
    const Verdict v = judge(s, r.tolerance, !r.spec.pins_nonfinite.empty());
    r.diff_seconds += seconds_since(t0);
    if (!v.pass) {
      r.reason += "; outside the device allowances too (" + v.reason + ")";
      return;
    }
    r.tight_reason = r.reason;
    r.stats = s;
    r.verdict = CaseVerdict::kPass;
    r.device_allowances = ref->device_allowances;
    r.allowance_values = s.admissible;
    r.first_allowance = s.first_admissible;
    std::string classes;
    for (const std::string& a : r.device_allowances) classes += (classes.empty() ? "" : ", ") + a;
    r.reason = "with a device allowance (" + classes + "; " + std::to_string(s.admissible) +
               " values outside the float32-exact bounds): " + v.reason;
    r.warnings = v.warnings;
    r.could_be_tightened = false;
    r.budget_used = v.budget_used;
  }

  static CaseResult error(CaseResult r, std::string reason) {
    r.verdict = CaseVerdict::kError;
    r.reason = std::move(reason);
    return r;
  }

  static CaseResult unsupported(CaseResult r, std::string reason) {
    r.verdict = CaseVerdict::kUnsupported;
    r.reason = std::move(reason);
    return r;
  }

  // Writes one image of the case (atomically); false (and the case an ERROR) when it fails.
  bool save(CaseResult& r, const std::string& name, const Image& img) {
    if (opt_.image_dir.empty()) return true;
    const std::string rel = case_image_dir(r.spec.id) + "/" + name + ".exr";
    // zlib level 1: these are the run's own images, written for every case (the report reads
    // them back once; --images may delete them).
    const std::string path = opt_.image_dir + "/" + rel;
    if (Status st = write_exr(path, img, /*zip_level=*/1); !st) {
      r = error(std::move(r), "cannot write " + name + " image: " + st.error().to_string());
      return false;
    }
    written_images::keep(path, img);  // for the report at the run's end (when enabled)
    r.images[name] = rel;
    return true;
  }

  const RunOptions& opt_;
  const RunReport& report_;
};

}  // namespace

RunReport run_cases(const std::vector<Case>& cases, const EngineFactory& reference,
                    const EngineFactory& candidate, const RunOptions& opt) {
  RunReport report;
  report.started_utc = utc_now();
  const auto t_run = std::chrono::steady_clock::now();
  size_t jobs = opt.jobs > 0 ? static_cast<size_t>(opt.jobs)
                             : std::max(1u, std::thread::hardware_concurrency());
  jobs = std::max<size_t>(1, std::min(jobs, cases.size()));
  report.jobs = static_cast<int>(jobs);

  // The first worker's engines start here, so availability and device names are known (and the
  // same for every case) before any case runs.
  std::vector<Worker> workers(jobs);
  workers[0].reference = reference();
  workers[0].candidate = candidate();
  if (Status st = workers[0].reference->init(); !st)
    report.candidate_unavailable = "reference engine failed to start: " + st.error().to_string();
  report.reference_device = workers[0].reference->device();
  if (report.candidate_unavailable.empty()) {
    if (Status st = workers[0].candidate->init(); !st)
      report.candidate_unavailable =
          workers[0].candidate->name() + " engine unavailable: " + st.error().to_string();
  }
  report.candidate_device = workers[0].candidate->device();
  report.candidate_device.precision.float32_exact = float32_exact_device(report.candidate_device);
  report.reference_device.precision.float32_exact = float32_exact_device(report.reference_device);

  const size_t n = cases.size();
  report.cases.resize(n);
  std::vector<char> done(n, 0);
  std::atomic<size_t> next{0};
  std::mutex mu;
  size_t emitted = 0;
  Executor exec(opt, report);
  // The process's own part is not the cases' (runner/budget.h kProcessFixedBytes).
  MemoryGate gate(opt.memory_budget > 0 ? std::max(1.0, opt.memory_budget - kProcessFixedBytes) : 0,
                  opt.interrupt);
  auto interrupted = [&] { return opt.interrupt && opt.interrupt->load(); };
  std::atomic<int> failed{0};
  auto max_failed = [&] { return opt.max_fail > 0 && failed.load() >= opt.max_fail; };

  auto work = [&](size_t w) {
    Worker& me = workers[w];
    if (w > 0) {
      // Each worker owns its engines. One that cannot start leaves its share to the others.
      me.reference = reference();
      me.candidate = candidate();
      if (!me.reference->init()) return;
      if (report.candidate_unavailable.empty() && !me.candidate->init()) return;
    }
    for (;;) {
      if (interrupted() || max_failed()) return;
      const size_t i = next.fetch_add(1);
      if (i >= n) return;
      const double bytes = case_cost(cases[i]).bytes;
      if (!gate.enter(i, bytes)) return;
      CaseResult r = exec.run_one(cases[i], me);
      gate.leave(bytes);
      failed += r.verdict == CaseVerdict::kFail || r.verdict == CaseVerdict::kError ||
                r.verdict == CaseVerdict::kMissing;
      if (interrupted() && r.verdict == CaseVerdict::kError) {
        r.verdict = CaseVerdict::kNotRun;
        r.reason = "interrupted while running: " + r.reason;
      }
      std::lock_guard<std::mutex> lock(mu);
      report.cases[i] = std::move(r);
      done[i] = 1;
      while (emitted < n && done[emitted]) {
        if (opt.on_case) opt.on_case(report.cases[emitted], emitted, n);
        ++emitted;
      }
    }
  };
  std::vector<std::thread> threads;
  for (size_t w = 1; w < jobs; ++w) threads.emplace_back(work, w);
  work(0);
  for (auto& t : threads) t.join();

  report.interrupted = false;
  report.max_fail = opt.max_fail;
  for (size_t i = 0; i < n; ++i) {
    if (done[i] && report.cases[i].verdict != CaseVerdict::kNotRun) continue;
    report.interrupted = interrupted();
    if (done[i]) continue;
    report.stopped_by_max_fail = !report.interrupted && max_failed();
    CaseResult& r = report.cases[i];
    r.spec = cases[i];
    r.tolerance = cases[i].tolerance;
    r.verdict = CaseVerdict::kNotRun;
    r.reason = report.interrupted ? "not run: the run was interrupted (SIGINT)"
               : report.stopped_by_max_fail
                   ? "not run: --maxfail " + std::to_string(opt.max_fail) + " cases had failed"
                   : "not run: no worker could start its engines";
  }
  for (; emitted < n; ++emitted)
    if (opt.on_case) opt.on_case(report.cases[emitted], emitted, n);
  report.wall_seconds = seconds_since(t_run);
  return report;
}

}  // namespace hdrc
