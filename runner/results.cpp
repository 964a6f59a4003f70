#include "runner/results.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "core/atomic_file.h"
#include "core/utf8.h"
#include "report/assets.h"
#include "report/html_report.h"
#include "runner/export.h"
#include "runner/json_read.h"
#include "runner/json_schema.h"
#include "runner/verify.h"

namespace hdrc {

using json = nlohmann::ordered_json;

namespace {

constexpr double kBandEdges[kBandCount + 1] = {0, 0.1, 1, 10, 100, 1000, kNotJudged};

// JSON has no NaN or Inf: they are written as the strings "NaN", "Infinity", "-Infinity".
json number(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "Infinity" : "-Infinity";
  return v;
}

// A pixel's values to 9 significant digits: a float32 value exactly (the candidate's, the
// stimuli's), and the digits the report shows (report/html_report.cpp, "%.9g").
json pixel_value(double v) {
  if (!std::isfinite(v) || v == 0) return number(v);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return std::strtod(buf, nullptr);
}

json pixel(const PixelRef& p) {
  if (!p.valid()) return nullptr;
  json j = {{"x", p.x},
            {"y", p.y},
            {"channel", std::string(1, "RGBA"[p.channel])},
            {"input", pixel_value(p.input)},
            {"reference", pixel_value(p.reference)},
            {"candidate", pixel_value(p.candidate)}};
  j["band"] = p.band >= 0 ? json(band_name(p.band)) : json(nullptr);
  return j;
}

json device(const DeviceInfo& d) {
  json j = {{"engine", d.engine},
            {"device", d.device},
            {"driver", d.driver},
            {"api_version", d.api_version},
            {"float32_exact", d.precision.float32_exact}};
  // The precision properties the device allowances are derived from (docs/precision.md). The
  // reference engine has none: it is exact by definition.
  if (d.engine != "reference")
    j["precision"] = {{"sub_texel_precision_bits", d.precision.sub_texel_bits},
                      {"mipmap_precision_bits", d.precision.mipmap_bits},
                      {"rounding_rte_float16", d.precision.fp16_rte},
                      {"denorm_preserve_float32", d.precision.fp32_denorm},
                      {"device_model", d.precision.model.empty() ? "none" : d.precision.model}};
  return j;
}

// A descriptive statistic (mean, rms, percentiles, a fraction) to 5 significant digits: the
// report's 4 ("%.4g") and a guard digit; no reader judges by them (verdicts are the run's own, from
// the exact values). Maxima, compared with tolerances, keep every digit (a band's, compared with
// nothing, the pixel values' 9).
json statistic(double v) {
  if (!std::isfinite(v) || v == 0) return number(v);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.5g", v);
  return std::strtod(buf, nullptr);
}

// A metric's statistics; where its values are all equal on both sides (count > 0, max 0) only
// count and max: every other statistic is 0 and no pixel is worse than another
// (docs/results-schema.md). The fraction over is written only where a value is over (it is
// over / count, 0 where none is: issue 27 item 8).
// A band's have no worst pixel: the case's worst pixels are the overall ones (the report's
// worst-pixel table).
json metric_stats(const MetricStats& m, bool band) {
  if (m.count > 0 && m.max == 0 && m.over == 0) return {{"count", m.count}, {"max", 0}};
  json j = {{"count", m.count},
            {"max", band ? pixel_value(m.max) : number(m.max)},
            {"mean", statistic(m.mean)},
            {"rms", statistic(m.rms)},
            {"p99", statistic(m.p99)},
            {"p99_9", statistic(m.p999)},
            {"over", m.over}};
  if (m.over > 0) j["fraction_over"] = statistic(m.fraction_over);
  if (!band) j["worst"] = pixel(m.worst);
  return j;
}

json metrics_of(const std::array<MetricStats, kMetricCount>& ms) {
  json j = json::object();
  for (int m = 0; m < kMetricCount; ++m)
    j[metric_key(static_cast<Metric>(m))] = metric_stats(ms[m], false);
  return j;
}

// A band's statistics: of the metrics the case's tolerance judges only, and none where the band
// holds every pixel (they are the overall ones).
json band_metrics(const DiffStats& s, int b, const Tolerance& t) {
  json j = json::object();
  if (s.band_pixels[b] == s.pixels) return j;
  for (int m = 0; m < kMetricCount; ++m)
    if (t.judged(static_cast<Metric>(m)))
      j[metric_key(static_cast<Metric>(m))] = metric_stats(s.band[b][m], true);
  return j;
}

json census_side(const NonFiniteCensus::Side& s) {
  return {{"nan", s.nan}, {"pos_inf", s.pos_inf}, {"neg_inf", s.neg_inf}, {"negative", s.negative}};
}

json range_of_band(int b) {
  return {{"band", band_name(b)},
          {"min_nits", kBandEdges[b]},
          {"max_nits", kBandEdges[b + 1] < kNotJudged ? json(kBandEdges[b + 1]) : json(nullptr)}};
}

// The dither criterion's statistics (runner/dither.h); null for a case without one.
json dither_json(const CaseResult& c) {
  if (!c.has_dither) return nullptr;
  const DitherStats& d = c.dither;
  json channels = json::object();
  for (int i = 0; i < 3; ++i) {
    const DitherChannelStats& ch = d.channel[i];
    channels[std::string(1, "RGB"[i])] = {{"n", ch.n},
                                          {"blocks", ch.blocks},
                                          {"mean_z", statistic(ch.mean_z)},
                                          {"worst_block", ch.worst_block},
                                          {"mean_used", statistic(ch.mean_used)},
                                          {"judged", ch.judged},
                                          {"std_ratio", statistic(ch.std_ratio)},
                                          {"std_bound", statistic(ch.std_bound)},
                                          {"ks", statistic(ch.ks)},
                                          {"ks_bound", statistic(ch.ks_bound)}};
  }
  json worst = nullptr;
  if (d.worst_x >= 0)
    worst = {{"x", d.worst_x},
             {"y", d.worst_y},
             {"channel", std::string(1, "RGB"[d.worst_channel])},
             {"undithered", number(d.worst_undithered)},
             {"candidate", number(d.worst_candidate)}};
  return {{"amount", d.amount},
          {"values", d.values},
          {"over_amplitude", d.over_amplitude},
          {"max_amplitude", number(d.max_amplitude)},
          {"worst", worst},
          {"resolved", d.resolved},
          {"statistics", d.statistics},
          {"exact_pattern_judged", c.exact_pattern_judged},
          {"channels", channels}};
}

json case_json(const CaseResult& c) {
  json cvars = json::object();
  for (const auto& [k, v] : c.spec.cvars.explicit_values()) cvars[k] = v;
  json settings = json::object();
  for (const auto& [k, v] : c.spec.settings.explicit_values()) {
    const SettingInfo* info = find_setting(k);
    settings[k] = info && info->components == 1 ? json(v[0]) : json(v);
  }
  json stats = nullptr, nonfinite = nullptr, worst = nullptr;
  if (c.has_stats) {
    const DiffStats& s = c.stats;
    json bands = json::array();
    for (int b = 0; b < kBandCount; ++b) {
      // The band's range is the run's "bands" entry of the same name.
      json band = {{"band", band_name(b)}, {"pixels", s.band_pixels[b]}};
      // An empty band has no statistics to give (every one 0): its metrics are left out.
      if (s.band_pixels[b] > 0) band["metrics"] = band_metrics(s, b, c.tolerance);
      bands.push_back(band);
    }
    stats = {{"pixels", s.pixels},
             {"values", s.values},
             {"admissible", s.admissible},
             {"overall", metrics_of(s.metric)},
             {"bands", bands}};
    nonfinite = {{"reference", census_side(s.nonfinite.reference)},
                 {"candidate", census_side(s.nonfinite.candidate)},
                 {"consistent", s.nonfinite.consistent},
                 {"mismatch", s.nonfinite.mismatch},
                 {"first_mismatch", pixel(s.nonfinite.first_mismatch)},
                 {"sign_boundary", s.nonfinite.sign_boundary},
                 {"first_sign_boundary", pixel(s.nonfinite.first_sign_boundary)}};
    // The worst pixel is the first non-finite mismatch when there is one (it decided the
    // verdict), else the worst value of the metric using most of its budget.
    if (s.nonfinite.mismatch > 0) {
      worst = pixel(s.nonfinite.first_mismatch);
      worst["metric"] = "nonfinite";
    } else if (s.worst.valid()) {
      worst = pixel(s.worst);
      worst["metric"] = metric_key(s.worst_metric);
    }
  }
  json images = json::object();
  for (const auto& [k, v] : c.images) images[k] = v;
  json out = {
      {"id", c.spec.id},
      {"file", c.spec.file},
      {"pipeline", c.spec.stage ? std::string(c.spec.stage->pipeline) : std::string()},
      {"stage", c.spec.stage ? std::string(c.spec.stage->name) : std::string()},
      {"verdict", verdict_name(c.verdict)},
      {"reason", c.reason},
      {"warn", !c.warnings.empty()},
      {"warnings", c.warnings},
      {"could_be_tightened", c.could_be_tightened},
      {"budget_used", c.has_stats ? number(c.budget_used) : json(nullptr)},
      {"cvars", cvars},
      {"settings", settings},
      {"input", c.spec.input.describe()},
      {"encoding", c.encoding},
      {"tolerance", tolerance_json(c.tolerance)},
      {"nonfinite", nonfinite},
      {"stats", stats},
      {"dither", dither_json(c)},
      {"worst_pixel", worst},
      {"images", images},
      {"seconds",
       {{"reference", c.reference_seconds},
        {"candidate", c.candidate_seconds},
        {"diff", c.diff_seconds},
        {"total", c.seconds()}}},
      // No "device": every case of a run has the run's candidate device, its top-level
      // "candidate" (and merge takes shards of one device only): 310 bytes a case written once
      // (issue 27 item 8). Results from before 2026-11-27 carry it in each case.
      {"reference_values", c.reference_values},
      {"params", c.has_params
                     ? params_json(c.params, c.spec.stage ? c.spec.stage->pipeline : "ue55")
                     : json(nullptr)},
  };
  // A PASS within a device allowance only (docs/precision.md, "Device allowances").
  if (!c.device_allowances.empty())
    out["device_allowance"] = {
        {"classes", c.device_allowances},
        {"values", c.allowance_values},
        // A whole pixel (the diff counts values, not one channel).
        {"first", c.first_allowance.valid()
                      ? json{{"x", c.first_allowance.x}, {"y", c.first_allowance.y}}
                      : json(nullptr)},
        {"without_it", c.tight_reason}};
  // A FAIL's possible causes (runner/diagnosis.h; each also ends the reason).
  json hints = json::array();
  for (const Hint& h : c.hints)
    hints.push_back(
        {{"id", h.id}, {"message", h.message}, {"evidence", h.evidence}, {"docs", h.docs}});
  out["hints"] = hints;
  return out;
}

// verify's candidate protocol (runner/verify.h): which reference the candidate was judged
// against, whether UNSUPPORTED fails the run, and the deviations the candidate declared.
void add_candidate_protocol(json& doc, const RunReport& r) {
  json limits = json::array();
  for (const KnownLimit& k : r.candidate_limits)
    limits.push_back({{"cases", k.cases}, {"engine", k.engine}, {"reason", k.reason}});
  doc["reference_mode"] = r.reference_mode;
  doc["require_all"] = r.require_all;
  doc["candidate_limits"] = {
      {"file", r.candidate_limits_file.empty() ? json(nullptr) : json(r.candidate_limits_file)},
      {"limits", limits}};
}

}  // namespace

std::string results_json(const RunReport& r) {
  json cases = json::array();
  for (const auto& c : r.cases) {
    cases.push_back(case_json(c));
    // A failing case carries the command that reruns it alone (junit and the console print it).
    if (c.verdict == CaseVerdict::kFail || c.verdict == CaseVerdict::kError ||
        c.verdict == CaseVerdict::kMissing)
      cases.back()["reproduce"] = reproduce_command(r, c.spec.id);
  }
  json bands = json::array();
  for (int b = 0; b < kBandCount; ++b) bands.push_back(range_of_band(b));
  json metrics = json::array();
  for (int m = 0; m < kMetricCount; ++m) metrics.push_back(metric_key(static_cast<Metric>(m)));
  int tighten = 0;
  for (const auto& c : r.cases) tighten += c.could_be_tightened;
  json doc = {
      {"$schema", "results.schema.json"},
      {"tool", "hdrconform"},
      {"schema_version", 2},
      {"command", r.command},
      {"started_utc", r.started_utc},
      {"wall_seconds", r.wall_seconds},
      {"jobs", r.jobs},
      {"shard", r.shard.empty() ? json(nullptr) : json(r.shard)},
      {"interrupted", r.interrupted},
      {"max_fail", r.max_fail > 0 ? json{{"limit", r.max_fail}, {"stopped", r.stopped_by_max_fail}}
                                  : json(nullptr)},
      {"reference", device(r.reference_device)},
      {"candidate", device(r.candidate_device)},
      {"candidate_unavailable", r.candidate_unavailable},
      {"provenance",
       {{"commit", r.provenance.commit},
        {"command_line", r.provenance.command_line},
        {"reproduce", r.provenance.reproduce},
        {"cwd", r.provenance.cwd},
        {"hostname", r.provenance.hostname},
        {"shader_dir", r.provenance.shader_dir},
        {"shader_hash", r.provenance.shader_hash},
        {"build_type", r.provenance.build_type},
        {"compiler", r.provenance.compiler},
        {"tool_version", r.provenance.tool_version},
        {"suite_fingerprint", r.provenance.suite_fingerprint},
        {"suite_cases", r.provenance.suite_cases},
        {"shard_plan", r.provenance.shard_plan},
        {"images", r.provenance.images}}},
      {"metrics", metrics},
      {"bands", bands},
      {"summary",
       {{"total", r.cases.size()},
        {"pass", r.count(CaseVerdict::kPass)},
        {"fail", r.count(CaseVerdict::kFail)},
        {"error", r.count(CaseVerdict::kError)},
        {"skipped", r.count(CaseVerdict::kSkipped)},
        {"known_limit", r.count(CaseVerdict::kKnownLimit)},
        {"degenerate", r.count(CaseVerdict::kDegenerate)},
        {"missing", r.count(CaseVerdict::kMissing)},
        {"not_run", r.count(CaseVerdict::kNotRun)},
        {"unsupported", r.count(CaseVerdict::kUnsupported)},
        {"warned", r.warned()},
        {"could_be_tightened", tighten},
        {"exit_code", r.exit_code()}}},
      {"cases", cases},
  };
  add_candidate_protocol(doc, r);
  return dump_json(doc, -1) + "\n";
}

namespace {

std::string str_of(const json& j, const char* key) {
  auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
}
double num_of(const json& j, const char* key) {
  auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>() : 0.0;
}
// JUnit's time: seconds with at most 3 decimals (the xs:decimal of the common schemas: Ant's
// and Jenkins' junit-10.xsd, GitLab's parser).
std::string seconds_text(double s) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3f", std::isfinite(s) && s > 0 ? s : 0.0);
  return buf;
}

// The attributes every <testsuite> carries in those schemas beside its counts: when the run
// started (ISO 8601 without a time zone; results.json's started_utc is UTC) and the host.
std::string suite_stamp(const json& doc) {
  std::string started = str_of(doc, "started_utc");
  if (!started.empty() && started.back() == 'Z') started.pop_back();
  std::string host;
  if (auto p = doc.find("provenance"); p != doc.end() && p->is_object())
    host = str_of(*p, "hostname");
  return " timestamp=\"" + escape_markup(started) + "\" hostname=\"" +
         escape_markup(host.empty() ? "unknown" : host) + "\"";
}

// One <testcase>: its failure names the worst pixel (the reason) and links to the case page.
std::string junit_case(const json& c) {
  const std::string stage = str_of(c, "stage").empty() ? "unknown" : str_of(c, "stage");
  const std::string id = str_of(c, "id"), verdict = str_of(c, "verdict");
  const std::string reason = str_of(c, "reason");
  double seconds = 0;
  if (auto it = c.find("seconds"); it != c.end() && it->is_object()) seconds = num_of(*it, "total");
  std::string x = "  <testcase classname=\"hdrconform." + escape_markup(stage) + "\" name=\"" +
                  escape_markup(id) + "\" time=\"" + seconds_text(seconds) + "\"";
  const std::string page = "report/" + case_page_path(id);
  const std::string repro = str_of(c, "reproduce").empty()
                                ? ""
                                : "&#10;reproduce: " + escape_markup(str_of(c, "reproduce"));
  std::string body;
  if (verdict == "FAIL" || verdict == "MISSING") {
    const std::string msg = (verdict == "MISSING" ? "MISSING: " : "") + reason;
    std::string source;
    if (auto t = c.find("tolerance"); t != c.end() && t->is_object()) source = str_of(*t, "source");
    body = "    <failure message=\"" + escape_markup(msg) + "\">" + escape_markup(msg) +
           "&#10;tolerance: " + escape_markup(source) + "&#10;case page: " + escape_markup(page) +
           repro + "</failure>\n";
  } else if (verdict == "ERROR") {
    body = "    <error message=\"" + escape_markup(reason) + "\">" + escape_markup(reason) +
           "&#10;case page: " + escape_markup(page) + repro + "</error>\n";
  } else if (verdict != "PASS") {
    body = "    <skipped message=\"" + escape_markup(verdict) + ": " + escape_markup(reason) +
           "\"/>\n";
  }
  std::string w;
  if (auto ws = c.find("warnings"); ws != c.end() && ws->is_array())
    for (const auto& s : *ws)
      if (s.is_string()) w += "warning: " + s.get<std::string>() + "\n";
  if (!w.empty()) body += "    <system-out>" + escape_markup(w) + "</system-out>\n";
  return x + (body.empty() ? "/>\n" : ">\n" + body + "  </testcase>\n");
}

}  // namespace

std::string case_page_path(const std::string& case_id) {
  return "c/" + report::url_path_escape(report::case_slug(case_id)) + ".html";
}

std::string junit_from_results(const nlohmann::ordered_json& doc) {
  std::string x;
  const json empty = json::array();
  const json& cases = doc.contains("cases") && doc["cases"].is_array() ? doc["cases"] : empty;
  int failures = 0, errors = 0, skipped = 0;
  for (const auto& c : cases) {
    const std::string v = str_of(c, "verdict");
    failures += v == "FAIL" || v == "MISSING";
    errors += v == "ERROR";
    skipped += v != "FAIL" && v != "MISSING" && v != "ERROR" && v != "PASS";
  }
  std::string device;
  if (auto d = doc.find("candidate"); d != doc.end() && d->is_object())
    device = str_of(*d, "device") + " / " + str_of(*d, "driver");
  x += "<testsuite name=\"hdrconform\" tests=\"" + std::to_string(cases.size()) + "\" failures=\"" +
       std::to_string(failures) + "\" errors=\"" + std::to_string(errors) + "\" skipped=\"" +
       std::to_string(skipped) + "\" time=\"" + seconds_text(num_of(doc, "wall_seconds")) + "\"" +
       suite_stamp(doc) + ">\n";
  x += "  <properties><property name=\"candidate.device\" value=\"" + escape_markup(device) +
       "\"/></properties>\n";
  for (const auto& c : cases) x += junit_case(c);
  x += "</testsuite>\n";
  // The golden check of the reference (goldens.json, recorded by record_golden_results): one
  // test case per checked golden, a failure for each missing, stale or regressed one.
  int golden_tests = 0, golden_failures = 0;
  if (auto g = doc.find("goldens"); g != doc.end() && g->is_object()) {
    const json& gc = g->contains("cases") && (*g)["cases"].is_array() ? (*g)["cases"] : empty;
    int gf = 0;
    for (const auto& e : gc) gf += str_of(e, "outcome") != "match";
    golden_tests = static_cast<int>(gc.size());
    golden_failures = gf;
    x += "<testsuite name=\"hdrconform.goldens\" tests=\"" + std::to_string(gc.size()) +
         "\" failures=\"" + std::to_string(gf) + "\" errors=\"0\" skipped=\"0\" time=\"" +
         seconds_text(num_of(*g, "seconds")) + "\"" + suite_stamp(doc) + ">\n";
    for (const auto& e : gc) {
      const std::string outcome = str_of(e, "outcome");
      x += "  <testcase classname=\"hdrconform.goldens\" name=\"" + escape_markup(str_of(e, "id")) +
           "\"";
      if (outcome == "match") {
        x += "/>\n";
        continue;
      }
      const std::string msg = "golden " + outcome + ": " + str_of(e, "message");
      x += ">\n    <failure message=\"" + escape_markup(msg) + "\">" + escape_markup(msg) +
           "</failure>\n  </testcase>\n";
    }
    x += "</testsuite>\n";
  }
  // The totals over both suites, which a CI's headline shows: a golden regression is a failure
  // there too.
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"hdrconform\" tests=\"" +
         std::to_string(cases.size() + golden_tests) + "\" failures=\"" +
         std::to_string(failures + golden_failures) + "\" errors=\"" + std::to_string(errors) +
         "\" skipped=\"" + std::to_string(skipped) + "\" time=\"" +
         seconds_text(num_of(doc, "wall_seconds")) + "\">\n" + x + "</testsuites>\n";
}

std::string junit_xml(const RunReport& r) {
  return junit_from_results(json::parse(results_json(r)));
}

Result<nlohmann::ordered_json> read_results_json(const std::string& path) {
  // Bounded like every JSON input (runner/json_read.h): size and nesting before parsing.
  auto doc = read_json_file<json>(path, "results file (a results.json written by `hdrconform run`)",
                                  kMaxResultsFileBytes);
  if (!doc) return doc.error();
  if (!doc->is_object() || !doc->contains("cases") || !(*doc)["cases"].is_array())
    return Error{path, "/cases", "missing or not an array", "a results.json (results.schema.json)"};
  return std::move(*doc);
}

Status check_results_schema(const nlohmann::ordered_json& doc, const std::string& file) {
  static const json schema = [] {
    for (const report::Asset& a : report::schemas())
      if (a.name == "results.schema.json") return json::parse(a.contents);
    return json();
  }();
  // Every value present is checked; a missing one is its reader's default (a results.json of
  // an older build, or one written by hand, may leave fields out).
  const std::vector<Error> errors = validate_json(doc, schema, file, /*check_required=*/false);
  if (errors.empty()) return {};
  Error e = errors.front();
  e.message += " (a results.json's values are as runner/results.schema.json describes them";
  if (errors.size() > 1)
    e.message += "; " + std::to_string(errors.size() - 1) + " more error" +
                 (errors.size() > 2 ? "s" : "") + " after this one";
  e.message += ")";
  return e;
}

Result<nlohmann::ordered_json> read_given_results_json(const std::string& path) {
  auto doc = read_results_json(path);
  if (!doc) return doc.error();
  if (Status st = check_results_schema(*doc, path); !st) return st.error();
  return doc;
}

Status record_goldens(nlohmann::ordered_json& doc, const std::string& out_dir) {
  json g = json::object();
  std::error_code ec;
  if (std::filesystem::exists(std::filesystem::symlink_status(out_dir + "/goldens.json", ec))) {
    // Bounded like every JSON input (runner/json_read.h), although this run wrote it.
    auto read = read_json_file<json>(out_dir + "/goldens.json", "golden check (goldens.json)");
    if (!read) return read.error();
    g = std::move(*read);
    if (!g.is_object())
      return Error{out_dir + "/goldens.json", "",
                   "not a JSON object, got " + std::string(g.type_name()), ""};
  }
  json summary = {{"checked", 0}, {"match", 0}, {"missing", 0}, {"stale", 0}, {"regression", 0}};
  json cases = json::array();
  if (auto it = g.find("cases"); it != g.end() && it->is_array())
    for (const auto& e : *it) {
      const std::string outcome = str_of(e, "outcome");
      if (!summary.contains(outcome)) continue;
      summary["checked"] = summary["checked"].get<int>() + 1;
      summary[outcome] = summary[outcome].get<int>() + 1;
      cases.push_back(
          {{"id", str_of(e, "id")}, {"outcome", outcome}, {"message", str_of(e, "message")}});
    }
  json goldens = {{"dir", str_of(g, "goldens_dir")},
                  {"reference_version", str_of(g, "reference_version")}};
  goldens.update(summary);
  goldens["failed"] = summary["missing"].get<int>() + summary["stale"].get<int>() +
                      summary["regression"].get<int>();
  goldens["seconds"] = num_of(g, "seconds");
  goldens["cases"] = cases;
  doc["goldens"] = goldens;
  doc["summary"]["golden_failed"] = goldens["failed"];
  return {};
}

Status write_run_outputs(const RunReport& r, const std::string& out_dir) {
  if (Status s = write_file_atomic(out_dir + "/results.json", results_json(r)); !s) return s;
  if (Status s = write_file_atomic(out_dir + "/junit.xml", junit_xml(r)); !s) return s;
  // `hdrconform run/verify` build the report once, at the end (finish_run_outputs); other
  // callers (the report fixture) get it here.
  if (r.provenance.command_line.empty()) {
    auto report = write_report(out_dir);
    if (!report) return report.error();
  }
  return {};
}

namespace {

bool keeps_images(const json& c, const std::set<std::string>& golden_failed,
                  const std::string& policy) {
  if (policy == "all") return true;
  if (policy == "none") return false;
  const std::string v = str_of(c, "verdict");
  return v == "FAIL" || v == "ERROR" || v == "MISSING" || golden_failed.count(str_of(c, "id"));
}

}  // namespace

Status apply_image_policy(nlohmann::ordered_json& doc, const std::string& out_dir,
                          const std::string& policy) {
  namespace fs = std::filesystem;
  std::set<std::string> golden_failed;
  if (auto g = doc.find("goldens"); g != doc.end() && g->is_object() && g->contains("cases"))
    for (const auto& e : (*g)["cases"])
      if (str_of(e, "outcome") != "match") golden_failed.insert(str_of(e, "id"));
  std::error_code ec;
  for (auto& c : doc["cases"]) {
    if (!c.is_object() || keeps_images(c, golden_failed, policy)) continue;
    auto im = c.find("images");
    if (im == c.end() || !im->is_object()) continue;
    for (auto it = im->begin(); it != im->end(); ++it) {
      if (!it->is_string()) continue;
      const std::string rel = it->get<std::string>();
      // Only files this run wrote under OUT/cases/ (results.json is data: never a path out).
      if (rel.rfind("cases/", 0) != 0 || rel.find("..") != std::string::npos) continue;
      const fs::path p = fs::path(out_dir) / rel;
      fs::remove(p, ec);
      written_images::forget(p.string());
      // The case's folder and its parents up to OUT/cases, when that leaves them empty.
      for (fs::path d = p.parent_path(); d.filename() != "cases" && fs::is_empty(d, ec) && !ec;
           d = d.parent_path())
        fs::remove(d, ec);
    }
    c["images"] = json::object();
    // The resolved parameters go with the images: 3.8 KB a case in results.json and 5.5 KB in
    // its report page, the largest part of a passing run's output. `hdrconform export --filter
    // =ID` writes them again for any case.
    c["params"] = nullptr;
  }
  doc["images_policy"] = policy;
  return {};
}

int exit_code_of(const nlohmann::ordered_json& doc) {
  if (doc.value("interrupted", false)) return kExitInterrupted;
  int fail = 0, skipped = 0, warned = 0;
  for (const auto& c : doc["cases"]) {
    const std::string v = str_of(c, "verdict");
    fail += v == "FAIL" || v == "ERROR" || v == "MISSING";
    skipped += v == "SKIP";
    warned += v == "PASS" && c.value("warn", false);
  }
  if (auto g = doc.find("goldens"); g != doc.end() && g->is_object()) fail += g->value("failed", 0);
  if (fail) return kExitFail;
  if (skipped) return kExitEngineUnavailable;
  if (warned) return kExitPassWithWarnings;
  return kExitPass;
}

std::string headline_of(const nlohmann::ordered_json& doc) {
  const json empty = json::object();
  const json& s = doc.contains("summary") && doc["summary"].is_object() ? doc["summary"] : empty;
  const auto n = [&](const json& j, const char* key) {
    auto it = j.find(key);
    return it != j.end() && it->is_number_integer() ? it->get<long long>() : 0LL;
  };
  const json& g = doc.contains("goldens") && doc["goldens"].is_object() ? doc["goldens"] : empty;
  const long long golden_failed = n(g, "missing") + n(g, "stale") + n(g, "regression");
  std::string goldens;
  if (golden_failed > 0) {
    for (const auto& [key, what] : {std::pair{"regression", "regressions"},
                                    std::pair{"missing", "missing"}, std::pair{"stale", "stale"}})
      if (n(g, key) > 0)
        goldens += (goldens.empty() ? "" : ", ") + std::to_string(n(g, key)) + " " + what;
    goldens = " (" +
              std::string(n(s, "fail") > 0 ? std::to_string(n(s, "fail")) + " cases, " : "") +
              "goldens: " + goldens + ")";
  }
  const json& cand =
      doc.contains("candidate") && doc["candidate"].is_object() ? doc["candidate"] : empty;
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                "hdrconform: %zu cases: %lld passed, %lld failed%s, %lld errors, %lld "
                "unsupported, %lld skipped, %lld known limits, %lld degenerate, %lld missing, "
                "%lld not run in %.1f s on %s (%s), -j %lld",
                doc.contains("cases") && doc["cases"].is_array() ? doc["cases"].size() : size_t{0},
                n(s, "pass"), n(s, "fail") + golden_failed, goldens.c_str(), n(s, "error"),
                n(s, "unsupported"), n(s, "skipped"), n(s, "known_limit"), n(s, "degenerate"),
                n(s, "missing"), n(s, "not_run"), num_of(doc, "wall_seconds"),
                str_of(cand, "device").c_str(), str_of(cand, "driver").c_str(), n(doc, "jobs"));
  std::string line = buf;
  if (!str_of(doc, "shard").empty()) line += ", shard " + str_of(doc, "shard");
  if (doc.contains("merged_from") && doc["merged_from"].is_array())
    line += ", merged from " + std::to_string(doc["merged_from"].size()) + " shards";
  return line;
}

int finish_run_outputs(const std::string& out_dir, int code, bool goldens_checked,
                       const std::string& images, int jobs, report::ReportInfo* report_info) {
  if (code == kExitBadInput) return code;
  auto doc = read_results_json(out_dir + "/results.json");
  if (!doc) return code;  // nothing was written (the run failed before its outputs)
  if (goldens_checked)
    if (Status s = record_goldens(*doc, out_dir); !s) {
      std::fprintf(stderr, "error: %s\n", s.error().to_string().c_str());
      code = kExitFail;
    }
  (*doc)["summary"]["exit_code"] = code;
  Status s = apply_image_policy(*doc, out_dir, images);
  if (s) s = write_file_atomic(out_dir + "/results.json", dump_json(*doc, -1) + "\n");
  if (s) s = write_file_atomic(out_dir + "/junit.xml", junit_from_results(*doc));
  if (s) {
    auto report = write_report(out_dir, jobs);
    if (!report)
      s = report.error();
    else if (report_info)
      *report_info = *report;
  }
  if (!s) {
    std::fprintf(stderr, "error: %s\n", s.error().to_string().c_str());
    return code == kExitInterrupted ? code : kExitFail;
  }
  std::printf("%s\n", headline_of(*doc).c_str());
  return code;
}

}  // namespace hdrc
