#include "runner/results.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/utf8.h"
#include "report/html_report.h"
#include "runner/export.h"
#include "runner/json_read.h"

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

json pixel(const PixelRef& p) {
  if (!p.valid()) return nullptr;
  json j = {{"x", p.x},
            {"y", p.y},
            {"channel", std::string(1, "RGBA"[p.channel])},
            {"input", number(p.input)},
            {"reference", number(p.reference)},
            {"candidate", number(p.candidate)}};
  j["band"] = p.band >= 0 ? json(band_name(p.band)) : json(nullptr);
  return j;
}

json device(const DeviceInfo& d) {
  return {{"engine", d.engine},
          {"device", d.device},
          {"driver", d.driver},
          {"api_version", d.api_version}};
}

json metric_stats(const MetricStats& m) {
  return {{"count", m.count},       {"max", number(m.max)},
          {"mean", number(m.mean)}, {"rms", number(m.rms)},
          {"p99", number(m.p99)},   {"p99_9", number(m.p999)},
          {"over", m.over},         {"fraction_over", number(m.fraction_over)},
          {"worst", pixel(m.worst)}};
}

json metrics_of(const std::array<MetricStats, kMetricCount>& ms) {
  json j = json::object();
  for (int m = 0; m < kMetricCount; ++m)
    j[metric_key(static_cast<Metric>(m))] = metric_stats(ms[m]);
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

json case_json(const CaseResult& c, const RunReport& r) {
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
      json band = range_of_band(b);
      band["pixels"] = s.band_pixels[b];
      band["metrics"] = metrics_of(s.band[b]);
      bands.push_back(band);
    }
    stats = {{"pixels", s.pixels},
             {"values", s.values},
             {"overall", metrics_of(s.metric)},
             {"bands", bands}};
    nonfinite = {{"reference", census_side(s.nonfinite.reference)},
                 {"candidate", census_side(s.nonfinite.candidate)},
                 {"consistent", s.nonfinite.consistent},
                 {"mismatch", s.nonfinite.mismatch},
                 {"first_mismatch", pixel(s.nonfinite.first_mismatch)}};
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
  return {
      {"id", c.spec.id},
      {"file", c.spec.file},
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
      {"worst_pixel", worst},
      {"images", images},
      {"seconds",
       {{"reference", c.reference_seconds},
        {"candidate", c.candidate_seconds},
        {"diff", c.diff_seconds},
        {"total", c.seconds()}}},
      {"device", device(r.candidate_device)},
      {"reference_values", c.reference_values},
      {"params", c.has_params ? params_json(c.params) : json(nullptr)},
  };
}

std::string xml_escape(const std::string& text) {
  const std::string s = valid_utf8(text);  // XML text is well-formed UTF-8 or unreadable
  std::string out;
  for (char c : s) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      case '\n':
        out += "&#10;";
        break;
      default:
        // XML 1.0 allows no other control characters.
        if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\r')
          out += ' ';
        else
          out += c;
    }
  }
  return out;
}

}  // namespace

std::string results_json(const RunReport& r) {
  json cases = json::array();
  for (const auto& c : r.cases) cases.push_back(case_json(c, r));
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
      {"reference", device(r.reference_device)},
      {"candidate", device(r.candidate_device)},
      {"candidate_unavailable", r.candidate_unavailable},
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
        {"warned", r.warned()},
        {"could_be_tightened", tighten},
        {"exit_code", r.exit_code()}}},
      {"cases", cases},
  };
  return dump_json(doc, 2) + "\n";
}

std::string junit_xml(const RunReport& r) {
  std::string x = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  const int failures = r.count(CaseVerdict::kFail) + r.count(CaseVerdict::kMissing);
  const int errors = r.count(CaseVerdict::kError);
  const int skipped = r.count(CaseVerdict::kSkipped) + r.count(CaseVerdict::kKnownLimit) +
                      r.count(CaseVerdict::kDegenerate) + r.count(CaseVerdict::kNotRun);
  x += "<testsuites>\n<testsuite name=\"hdrconform\" tests=\"" + std::to_string(r.cases.size()) +
       "\" failures=\"" + std::to_string(failures) + "\" errors=\"" + std::to_string(errors) +
       "\" skipped=\"" + std::to_string(skipped) + "\" time=\"" + std::to_string(r.wall_seconds) +
       "\">\n";
  x += "  <properties><property name=\"candidate.device\" value=\"" +
       xml_escape(r.candidate_device.device + " / " + r.candidate_device.driver) +
       "\"/></properties>\n";
  for (const auto& c : r.cases) {
    const std::string stage = c.spec.stage ? std::string(c.spec.stage->name) : "unknown";
    x += "  <testcase classname=\"hdrconform." + xml_escape(stage) + "\" name=\"" +
         xml_escape(c.spec.id) + "\" time=\"" + std::to_string(c.seconds()) + "\"";
    std::string body;
    switch (c.verdict) {
      case CaseVerdict::kPass:
        break;
      case CaseVerdict::kFail:
      case CaseVerdict::kMissing: {
        // The reason names the worst pixel (or the first non-finite mismatch).
        const std::string msg = (c.verdict == CaseVerdict::kMissing ? "MISSING: " : "") + c.reason;
        body = "    <failure message=\"" + xml_escape(msg) + "\">" + xml_escape(msg) +
               "&#10;tolerance: " + xml_escape(c.tolerance.source) + "</failure>\n";
        break;
      }
      case CaseVerdict::kError:
        body = "    <error message=\"" + xml_escape(c.reason) + "\"/>\n";
        break;
      case CaseVerdict::kSkipped:
      case CaseVerdict::kKnownLimit:
      case CaseVerdict::kDegenerate:
      case CaseVerdict::kNotRun:
        body = "    <skipped message=\"" + std::string(verdict_name(c.verdict)) + ": " +
               xml_escape(c.reason) + "\"/>\n";
        break;
    }
    if (!c.warnings.empty()) {
      std::string w;
      for (const auto& s : c.warnings) w += "warning: " + s + "\n";
      body += "    <system-out>" + xml_escape(w) + "</system-out>\n";
    }
    x += body.empty() ? "/>\n" : ">\n" + body + "  </testcase>\n";
  }
  x += "</testsuite>\n</testsuites>\n";
  return x;
}

Status write_run_outputs(const RunReport& r, const std::string& out_dir) {
  if (Status s = write_file_atomic(out_dir + "/results.json", results_json(r)); !s) return s;
  if (Status s = write_file_atomic(out_dir + "/junit.xml", junit_xml(r)); !s) return s;
  auto report = write_report(out_dir);
  if (!report) return report.error();
  return {};
}

}  // namespace hdrc
