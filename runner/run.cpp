#include "runner/run.h"

#include <ctime>

#include "runner/case_loader.h"

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
  }
  return "?";
}

int RunReport::count(CaseVerdict v) const {
  int n = 0;
  for (const auto& c : cases) n += c.verdict == v;
  return n;
}

int RunReport::exit_code() const {
  if (count(CaseVerdict::kFail) + count(CaseVerdict::kError) > 0) return kExitFail;
  if (count(CaseVerdict::kSkipped) > 0) return kExitEngineUnavailable;
  return kExitPass;
}

namespace {
std::string utc_now() {
  char buf[32];
  const std::time_t t = std::time(nullptr);
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

RunReport run_cases(const std::vector<Case>& cases, Engine& reference, Engine& candidate,
                    const std::vector<KnownLimit>& known_limits,
                    void (*on_case)(const CaseResult&, size_t, size_t)) {
  RunReport report;
  report.started_utc = utc_now();
  const auto t_run = std::chrono::steady_clock::now();
  if (Status st = reference.init(); !st) {
    report.candidate_unavailable = "reference engine failed to start: " + st.error().to_string();
  }
  report.reference_device = reference.device();
  if (Status st = candidate.init(); !st) {
    report.candidate_unavailable =
        candidate.name() + " engine unavailable: " + st.error().to_string();
  }
  report.candidate_device = candidate.device();

  for (size_t i = 0; i < cases.size(); ++i) {
    CaseResult r;
    r.spec = cases[i];
    const KnownLimit* limit = nullptr;
    for (const KnownLimit& k : known_limits)
      if (k.engine == candidate.name() && matches_filter(cases[i].id, k.cases)) limit = &k;
    auto resolved = resolve_case(cases[i]);
    if (!resolved) {
      r.verdict = CaseVerdict::kError;
      r.reason = resolved.error().to_string();
    } else if (!resolved->degenerate.empty()) {
      r.verdict = CaseVerdict::kDegenerate;
      r.reason = resolved->degenerate;
    } else if (limit) {
      // The candidate is not run; the reference still is, so its outputs (and any error of its
      // own) are part of every run.
      const auto t0 = std::chrono::steady_clock::now();
      auto ref_img = reference.run(*resolved);
      r.reference_seconds = seconds_since(t0);
      if (!ref_img) {
        r.verdict = CaseVerdict::kError;
        r.reason = "reference: " + ref_img.error().to_string();
      } else {
        r.reference_values = ref_img->values;
        r.verdict = CaseVerdict::kKnownLimit;
        r.reason = "known limit of " + limit->engine + ": " + limit->reason;
      }
    } else if (!report.candidate_unavailable.empty()) {
      r.verdict = CaseVerdict::kSkipped;
      r.reason = report.candidate_unavailable;
    } else {
      auto t0 = std::chrono::steady_clock::now();
      auto ref_img = reference.run(*resolved);
      r.reference_seconds = seconds_since(t0);
      t0 = std::chrono::steady_clock::now();
      auto cand_img = candidate.run(*resolved);
      r.candidate_seconds = seconds_since(t0);
      if (ref_img) r.reference_values = ref_img->values;
      if (!ref_img) {
        r.verdict = CaseVerdict::kError;
        r.reason = "reference: " + ref_img.error().to_string();
      } else if (!cand_img) {
        r.verdict = CaseVerdict::kError;
        r.reason = candidate.name() + ": " + cand_img.error().to_string();
      } else {
        const OutputEncoding enc{cases[i].stage->id, resolved->params.output_device,
                                 resolved->params.inverse_gamma[2]};
        r.stats = diff_images(resolved->input, *ref_img, *cand_img, enc, cases[i].tolerance);
        const Verdict v = judge(r.stats, cases[i].tolerance);
        r.verdict = v.pass ? CaseVerdict::kPass : CaseVerdict::kFail;
        r.reason = v.reason;
      }
    }
    report.cases.push_back(std::move(r));
    if (on_case) on_case(report.cases.back(), i, cases.size());
  }
  report.wall_seconds = seconds_since(t_run);
  return report;
}

}  // namespace hdrc
