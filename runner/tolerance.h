// The tolerance policy as data (docs/tolerances.md): the JSON form of a case's `tolerance`, the
// project default, and the overlays of cases/tolerance_overlays.json that adjust tolerances per
// stage, per case glob or per backend (engine and device), each with a written reason.
//
// Layers, later over earlier, each naming where it came from in Tolerance::source:
//   1. the project default (default_tolerance_policy());
//   2. the case file's `/tolerance` (one per file; every case its matrix expands shares it);
//   3. every matching overlay of cases/tolerance_overlays.json, in file order.
//
// A tolerance object:
//   {"linear_rel": 2.5e-4,                       a number: that metric's max
//    "pq_code10": {"max": 0.025, "allowed_fraction": 0.001, "hard": 0.5, "warn": 0.02},
//    "delta_e_itp": null,                        null: that metric is not judged
//    "rel_floor": 1e-4,
//    "dither": {"mean_sigmas": 5.5, ..., "reason": "..."},  the dither stage's properties
//                                                (core/case.h DitherCriterion; null: none)
//    "reason": "measured ... because ..."}       required, non-empty
// Metric keys: linear_abs, linear_rel, pq_code10, pq_code12, delta_e_itp. A key left out keeps
// the value of the layer below.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/case.h"
#include "core/result.h"

namespace hdrc {

// One JSON-pointer reference token, escaped as RFC 6901 says ('~' → "~0", '/' → "~1").
std::string escape_pointer_token(const std::string& s);

// The JSON key of a metric ("linear_rel", "pq_code10", ...), used in tolerances and results.
const char* metric_key(Metric m);
// "linear_abs, linear_rel, pq_code10, pq_code12, delta_e_itp"
std::string metric_keys();
// The keys a tolerance object may have, comma-separated.
std::string tolerance_keys();

// The project default (docs/tolerances.md): float32 evaluation of a well-conditioned formula.
Tolerance default_tolerance_policy();

// Parses the tolerance object `j` found at `pointer` of `file` over `base`. Errors name the
// file, the pointer of the offending key, its value and the valid choices. The result's source
// is "FILE: POINTER".
Result<Tolerance> parse_tolerance(const nlohmann::ordered_json& j, const std::string& file,
                                  const std::string& pointer, const Tolerance& base);
// The same over default_tolerance_policy().
Result<Tolerance> parse_tolerance(const nlohmann::ordered_json& j, const std::string& file,
                                  const std::string& pointer);

// One entry of cases/tolerance_overlays.json: a tolerance patch for the cases its selectors
// match. Every selector left out matches everything; at least one must be given.
struct ToleranceOverlay {
  std::string file,
      pointer;         // where it is written ("cases/tolerance_overlays.json", "/overlays/0")
  std::string stage;   // a stage name
  std::string cases;   // a glob over case ids
  std::string engine;  // a candidate engine name ("vulkan", "candidate-dir", ...)
  std::string device;  // a glob over the candidate device's name ("*NVIDIA*")
  nlohmann::ordered_json tolerance;  // the patch, validated on load; its reason is required
};

// Reads `cases_dir`/tolerance_overlays.json (absent: none). Every error is appended to `errors`.
std::vector<ToleranceOverlay> load_tolerance_overlays(const std::string& cases_dir,
                                                      std::vector<Error>* errors);
// Parses the text of an overlay file (exposed for tests).
std::vector<ToleranceOverlay> parse_tolerance_overlays(const std::string& file,
                                                       const std::string& text,
                                                       std::vector<Error>* errors);

bool overlay_matches(const ToleranceOverlay& o, const Case& c, const std::string& engine,
                     const std::string& device);

// `c.tolerance` with every matching overlay applied in order; the source lists each layer and
// the reason gains each overlay's reason.
Result<Tolerance> apply_overlays(const Case& c, const std::string& engine,
                                 const std::string& device,
                                 const std::vector<ToleranceOverlay>& overlays);

// The tolerance as JSON (every criterion, null where not judged), the form results.json uses.
nlohmann::ordered_json tolerance_json(const Tolerance& t);

}  // namespace hdrc
