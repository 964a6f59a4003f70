#include "runner/tolerance.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "runner/case_loader.h"
#include "runner/json_read.h"

namespace hdrc {

std::string escape_pointer_token(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '~')
      out += "~0";
    else if (c == '/')
      out += "~1";
    else
      out += c;
  }
  return out;
}

using json = nlohmann::ordered_json;

namespace {

constexpr Metric kMetrics[kMetricCount] = {Metric::kLinearAbs, Metric::kLinearRel,
                                           Metric::kPqCode10, Metric::kPqCode12,
                                           Metric::kDeltaEItp};
constexpr const char* kLimitKeys = "max, allowed_fraction, hard, warn";

std::string show(const json& v) {
  std::string s = v.dump();
  return s.size() > 60 ? s.substr(0, 57) + "..." : s;
}

// A number as people write it: 1, 0.5, 1e-05.

// A number >= 0 (upper bound `hi`), or null when `null_ok` (returned as kNotJudged).
Result<double> limit_value(const json& v, const std::string& file, const std::string& pointer,
                           const std::string& key, bool null_ok, double hi = kNotJudged) {
  if (v.is_null() && null_ok) return kNotJudged;
  const std::string range =
      hi < kNotJudged ? "a number from 0 to " + format_number(hi) : std::string("a number >= 0");
  if (!v.is_number())
    return Error{file, pointer,
                 key + " must be a number, got " + std::string(v.type_name()) + " " + show(v),
                 null_ok ? range + " or null (not judged)" : range};
  const double x = v.get<double>();
  if (!(x >= 0)) return Error{file, pointer, key + " " + show(v) + " is negative", range};
  if (!(x <= hi))
    return Error{file, pointer, key + " " + show(v) + " is over " + format_number(hi), range};
  return x;
}

constexpr const char* kDitherKeys =
    "mean_sigmas, block_pixels, std_sigmas, ks_c, exact_pattern, reason";

// The "dither" criterion (core/case.h DitherCriterion) over `d`: null clears it, an object sets
// the keys it names (the others keep the layer below) and must say why.
Status parse_dither(const json& v, const std::string& file, const std::string& at,
                    DitherCriterion* d) {
  if (v.is_null()) {
    *d = DitherCriterion{};
    return {};
  }
  if (!v.is_object())
    return Error{
        file, at,
        "dither must be an object or null, got " + std::string(v.type_name()) + " " + show(v),
        std::string("{") + kDitherKeys + "} or null (not judged)"};
  DitherCriterion out = *d;
  out.judged = true;
  for (auto it = v.begin(); it != v.end(); ++it) {
    const std::string& k = it.key();
    const std::string kat = at + "/" + escape_pointer_token(k);
    if (k == "mean_sigmas" || k == "std_sigmas" || k == "ks_c") {
      Result<double> x = limit_value(it.value(), file, kat, k, false);
      if (!x) return x.error();
      if (!(*x > 0)) return Error{file, kat, k + " must be positive", "a number > 0"};
      (k == "mean_sigmas" ? out.mean_sigmas : k == "std_sigmas" ? out.std_sigmas : out.ks_c) = *x;
    } else if (k == "block_pixels") {
      const json& b = it.value();
      if (!b.is_number_integer() || b.get<long long>() < 1 || b.get<long long>() > (1 << 24))
        return Error{file, kat, "block_pixels must be a whole number, got " + show(b),
                     "an integer from 1 to 16777216"};
      out.block_pixels = b.get<int>();
    } else if (k == "exact_pattern") {
      const json& e = it.value();
      if (!e.is_string() || (e != "always" && e != "float32_exact" && e != "never"))
        return Error{file, kat, "exact_pattern " + show(e) + " is not a known choice",
                     "\"always\", \"float32_exact\" or \"never\""};
      out.exact_pattern = e.get<std::string>();
    } else if (k == "reason") {
      if (!it.value().is_string() || it.value().get<std::string>().empty())
        return Error{file, kat, "the dither criterion's reason must be a non-empty string",
                     "why these bounds (their derivation and the measured margin)"};
      out.reason = it.value().get<std::string>();
    } else {
      return Error{file, kat, "unknown key '" + k + "'", kDitherKeys};
    }
  }
  if (!v.contains("reason"))
    return Error{file, at + "/reason", "the dither criterion must say why (its derivation)",
                 "a non-empty string"};
  *d = std::move(out);
  return {};
}

bool glob_match(const std::string& glob, const std::string& s) {
  return matches_filter(s, glob);  // runner/case_loader.h: linear time on any pattern
}

}  // namespace

const char* metric_key(Metric m) {
  switch (m) {
    case Metric::kLinearAbs:
      return "linear_abs";
    case Metric::kLinearRel:
      return "linear_rel";
    case Metric::kPqCode10:
      return "pq_code10";
    case Metric::kPqCode12:
      return "pq_code12";
    case Metric::kDeltaEItp:
      return "delta_e_itp";
  }
  return "?";
}

std::string metric_keys() {
  std::string s;
  for (Metric m : kMetrics) s += (s.empty() ? "" : ", ") + std::string(metric_key(m));
  return s;
}

std::string tolerance_keys() {
  return metric_keys() + ", dither, rel_floor, pq_near_black, reason";
}

Tolerance default_tolerance_policy() {
  Tolerance t;
  t.linear_rel = 1e-5;
  t.rel_floor = 1e-6;
  t.pq_code10 = 0.05;
  t.reason = "project default (docs/tolerances.md): float32 evaluation of double formulas";
  t.source = "default";
  return t;
}

Result<Tolerance> parse_tolerance(const json& j, const std::string& file,
                                  const std::string& pointer, const Tolerance& base) {
  if (!j.is_object())
    return Error{file, pointer,
                 "a tolerance is an object, got " + std::string(j.type_name()) + " " + show(j),
                 "an object with keys " + tolerance_keys()};
  Tolerance t = base;
  const std::string keys = tolerance_keys();
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string& key = it.key();
    const std::string at = pointer + "/" + escape_pointer_token(key);
    bool known = key == "rel_floor" || key == "pq_near_black" || key == "reason" || key == "dither";
    for (Metric m : kMetrics) known = known || key == metric_key(m);
    if (!known) return Error{file, at, "unknown key '" + key + "'", keys};
  }
  for (Metric m : kMetrics) {
    const std::string key = metric_key(m);
    if (!j.contains(key)) continue;
    const json& v = j[key];
    const std::string at = pointer + "/" + key;
    const int i = static_cast<int>(m);
    if (v.is_null()) {  // not judged
      t.max(m) = kNotJudged;
      t.allowed_fraction[i] = 0;
      t.hard[i] = kNotJudged;
      t.warn[i] = kNotJudged;
    } else if (v.is_object()) {
      for (auto it = v.begin(); it != v.end(); ++it) {
        const std::string& k = it.key();
        const std::string kat = at + "/" + escape_pointer_token(k);
        Result<double> x = k == "allowed_fraction"
                               ? limit_value(it.value(), file, kat, k, false, 1.0)
                               : limit_value(it.value(), file, kat, k, true);
        if (k != "max" && k != "allowed_fraction" && k != "hard" && k != "warn")
          return Error{file, kat, "unknown key '" + k + "'", kLimitKeys};
        if (!x) return x.error();
        if (k == "max") t.max(m) = *x;
        if (k == "allowed_fraction") t.allowed_fraction[i] = *x;
        if (k == "hard") t.hard[i] = *x;
        if (k == "warn") t.warn[i] = *x;
      }
    } else if (v.is_number()) {
      Result<double> x = limit_value(v, file, at, key, true);
      if (!x) return x.error();
      t.max(m) = *x;
    } else {
      return Error{
          file, at,
          key + " must be a number, null or an object, got " + std::string(v.type_name()) + " " +
              show(v),
          "a number >= 0 (the max), null (not judged) or {" + std::string(kLimitKeys) + "}"};
    }
    // The criteria of one metric must make sense together.
    if (t.allowed_fraction[i] > 0 && !(t.hard[i] < kNotJudged))
      return Error{file, at,
                   key + ": allowed_fraction " + format_number(t.allowed_fraction[i]) +
                       " needs a hard cap, or the allowed values could be off by any amount",
                   "add \"hard\": a number >= max"};
    if (t.hard[i] < t.max(m))
      return Error{
          file, at,
          key + ": hard " + format_number(t.hard[i]) + " is below max " + format_number(t.max(m)),
          "hard >= max"};
    if (t.warn[i] < kNotJudged && t.max(m) < kNotJudged && t.warn[i] > t.max(m))
      return Error{file, at,
                   key + ": warn " + format_number(t.warn[i]) + " is above max " +
                       format_number(t.max(m)) + "; a warn level sits below the fail limit",
                   "warn <= max"};
  }
  if (j.contains("dither")) {
    Status st = parse_dither(j["dither"], file, pointer + "/dither", &t.dither);
    if (!st) return st.error();
  }
  if (j.contains("rel_floor")) {
    Result<double> x =
        limit_value(j["rel_floor"], file, pointer + "/rel_floor", "rel_floor", false);
    if (!x) return x.error();
    t.rel_floor = *x;
  }
  if (j.contains("pq_near_black")) {
    const std::string at = pointer + "/pq_near_black";
    if (j["pq_near_black"].is_null()) {
      t.pq_near_black = 0;
    } else {
      Result<double> x = limit_value(j["pq_near_black"], file, at, "pq_near_black", false);
      if (!x) return x.error();
      t.pq_near_black = *x;
    }
  }
  // The near-black floor stands on the other metrics' agreement: both must be judged.
  if (t.pq_near_black > 0 &&
      (!(t.delta_e_itp < kNotJudged) || !(t.linear_rel < kNotJudged || t.linear_abs < kNotJudged)))
    return Error{file, pointer + "/pq_near_black",
                 "pq_near_black " + format_number(t.pq_near_black) +
                     " needs delta_e_itp and linear_rel (or linear_abs) judged with a max: the "
                     "floor applies where they agree that a pixel is right",
                 "set delta_e_itp and linear_rel, or \"pq_near_black\": null"};
  if (!j.contains("reason") || !j["reason"].is_string() || j["reason"].get<std::string>().empty())
    return Error{file, pointer + "/reason",
                 "a tolerance must say why (measured error and its cause)", "a non-empty string"};
  t.reason = j["reason"].get<std::string>();
  t.source = file + ": " + pointer;
  return t;
}

Result<Tolerance> parse_tolerance(const json& j, const std::string& file,
                                  const std::string& pointer) {
  return parse_tolerance(j, file, pointer, default_tolerance_policy());
}

std::vector<ToleranceOverlay> parse_tolerance_overlays(const std::string& file,
                                                       const std::string& text,
                                                       std::vector<Error>* errors) {
  std::vector<ToleranceOverlay> out;
  auto parsed = parse_json_text<json>(file, text);
  if (!parsed) {
    errors->push_back(parsed.error());
    return out;
  }
  json doc = std::move(*parsed);
  if (!doc.is_object()) {
    errors->push_back(Error{file, "", "an overlay file is a JSON object, got " + show(doc),
                            "{\"overlays\": [...]}"});
    return out;
  }
  for (auto it = doc.begin(); it != doc.end(); ++it)
    if (it.key() != "overlays" && it.key() != "description" && it.key() != "$schema")
      errors->push_back(Error{file, "/" + escape_pointer_token(it.key()),
                              "unknown key '" + it.key() + "'", "$schema, description, overlays"});
  if (!doc.contains("overlays")) return out;
  if (!doc["overlays"].is_array()) {
    errors->push_back(Error{file, "/overlays", "expected an array, got " + show(doc["overlays"]),
                            "an array of overlay objects"});
    return out;
  }
  const char* kKeys = "stage, cases, engine, device, tolerance";
  for (size_t i = 0; i < doc["overlays"].size(); ++i) {
    const json& o = doc["overlays"][i];
    const std::string at = "/overlays/" + std::to_string(i);
    if (!o.is_object()) {
      errors->push_back(Error{file, at, "expected an object, got " + show(o), kKeys});
      continue;
    }
    ToleranceOverlay ov;
    ov.file = file;
    ov.pointer = at;
    bool ok = true, any_selector = false;
    for (auto it = o.begin(); it != o.end(); ++it) {
      const std::string& k = it.key();
      const std::string kat = at + "/" + escape_pointer_token(k);
      if (k == "tolerance") continue;
      if (k != "stage" && k != "cases" && k != "engine" && k != "device") {
        errors->push_back(Error{file, kat, "unknown key '" + k + "'", kKeys});
        ok = false;
        continue;
      }
      if (!it.value().is_string() || it.value().get<std::string>().empty()) {
        errors->push_back(
            Error{file, kat, k + " must be a non-empty string, got " + show(it.value()), ""});
        ok = false;
        continue;
      }
      const std::string v = it.value().get<std::string>();
      any_selector = true;
      if (k == "stage") {
        if (!find_stage(v)) {
          errors->push_back(Error{file, kat, "unknown stage " + show(it.value()), stage_names()});
          ok = false;
        }
        ov.stage = v;
      }
      if (k == "cases") ov.cases = v;
      if (k == "engine") ov.engine = v;
      if (k == "device") ov.device = v;
    }
    if (!any_selector) {
      errors->push_back(Error{file, at,
                              "an overlay must select what it applies to (it would change every "
                              "tolerance of the suite)",
                              "one or more of stage, cases, engine, device"});
      ok = false;
    }
    if (!o.contains("tolerance")) {
      errors->push_back(Error{file, at + "/tolerance", "missing tolerance",
                              "an object with keys " + tolerance_keys()});
      continue;
    }
    // Validated here against an empty base, so every error is found on load, not mid-run.
    Result<Tolerance> t = parse_tolerance(o["tolerance"], file, at + "/tolerance", Tolerance{});
    if (!t) {
      errors->push_back(t.error());
      continue;
    }
    ov.tolerance = o["tolerance"];
    if (ok) out.push_back(std::move(ov));
  }
  return out;
}

std::vector<ToleranceOverlay> load_tolerance_overlays(const std::string& cases_dir,
                                                      std::vector<Error>* errors) {
  const std::string path = cases_dir + "/tolerance_overlays.json";
  std::error_code ec;
  if (std::filesystem::symlink_status(path, ec).type() == std::filesystem::file_type::not_found)
    return {};
  auto text = read_bounded_file(path, kMaxJsonFileBytes, "tolerance overlay file");
  if (!text) {
    errors->push_back(text.error());
    return {};
  }
  return parse_tolerance_overlays(path, *text, errors);
}

bool overlay_matches(const ToleranceOverlay& o, const Case& c, const std::string& engine,
                     const std::string& device) {
  if (!o.stage.empty() && (!c.stage || o.stage != c.stage->name)) return false;
  return glob_match(o.cases, c.id) && (o.engine.empty() || o.engine == engine) &&
         glob_match(o.device, device);
}

Result<Tolerance> apply_overlays(const Case& c, const std::string& engine,
                                 const std::string& device,
                                 const std::vector<ToleranceOverlay>& overlays) {
  Tolerance t = c.tolerance;
  for (const ToleranceOverlay& o : overlays) {
    if (!overlay_matches(o, c, engine, device)) continue;
    Result<Tolerance> next = parse_tolerance(o.tolerance, o.file, o.pointer + "/tolerance", t);
    if (!next) return next.error();
    next->source = t.source + " + overlay " + next->source;
    next->reason = t.reason + "; overlay: " + next->reason;
    t = std::move(*next);
  }
  return t;
}

json tolerance_json(const Tolerance& t) {
  auto num = [](double v) -> json {
    if (!(v < kNotJudged)) return nullptr;
    return v;
  };
  json j = json::object();
  for (Metric m : kMetrics) {
    const int i = static_cast<int>(m);
    if (!t.judged(m)) {
      j[metric_key(m)] = nullptr;
      continue;
    }
    j[metric_key(m)] = {{"max", num(t.max(m))},
                        {"allowed_fraction", t.allowed_fraction[i]},
                        {"hard", num(t.hard[i])},
                        {"warn", num(t.warn[i])}};
  }
  if (t.dither.judged)
    j["dither"] = {
        {"mean_sigmas", t.dither.mean_sigmas},     {"block_pixels", t.dither.block_pixels},
        {"std_sigmas", t.dither.std_sigmas},       {"ks_c", t.dither.ks_c},
        {"exact_pattern", t.dither.exact_pattern}, {"reason", t.dither.reason}};
  else
    j["dither"] = nullptr;
  j["rel_floor"] = t.rel_floor;
  j["pq_near_black"] = t.pq_near_black > 0 ? json(t.pq_near_black) : json(nullptr);
  j["reason"] = t.reason;
  j["source"] = t.source;
  return j;
}

}  // namespace hdrc
