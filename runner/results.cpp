#include "runner/results.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "report/html_report.h"

namespace hdrc {

using json = nlohmann::json;

namespace {
json number(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "Infinity" : "-Infinity";
  return v;
}
json pixel(const PixelRef& p) {
  if (!p.valid()) return nullptr;
  return {{"x", p.x},
          {"y", p.y},
          {"channel", std::string(1, "RGBA"[p.channel])},
          {"input", number(p.input)},
          {"reference", number(p.reference)},
          {"candidate", number(p.candidate)}};
}
json device(const DeviceInfo& d) {
  return {{"engine", d.engine},
          {"device", d.device},
          {"driver", d.driver},
          {"api_version", d.api_version}};
}
std::string xml_escape(const std::string& s) {
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
      default:
        out += c;
    }
  }
  return out;
}
}  // namespace

std::string results_json(const RunReport& r) {
  json cases = json::array();
  for (const auto& c : r.cases) {
    json cvars = json::object();
    for (const auto& [k, v] : c.spec.cvars.explicit_values()) cvars[k] = v;
    const Tolerance& t = c.spec.tolerance;
    const DiffStats& s = c.stats;
    cases.push_back({
        {"id", c.spec.id},
        {"file", c.spec.file},
        {"stage", std::string(c.spec.stage->name)},
        {"cvars", cvars},
        {"input", c.spec.input.describe()},
        {"verdict", verdict_name(c.verdict)},
        {"reason", c.reason},
        {"tolerance",
         {{"linear_rel", t.linear_rel},
          {"rel_floor", t.rel_floor},
          {"pq_code10", t.pq_code10},
          {"reason", t.reason},
          {"source", t.source}}},
        {"metrics",
         {{"values", s.values},
          {"max_abs", number(s.max_abs)},
          {"mean_abs", number(s.mean_abs)},
          {"max_rel", number(s.max_rel)},
          {"mean_rel", number(s.mean_rel)},
          {"max_pq10", number(s.max_pq10)},
          {"max_pq12", number(s.max_pq12)},
          {"mean_pq10", number(s.mean_pq10)},
          {"over_rel", s.over_rel},
          {"over_pq10", s.over_pq10}}},
        {"nonfinite",
         {{"reference", s.nonfinite_ref},
          {"consistent", s.nonfinite_consistent},
          {"mismatch", s.nonfinite_mismatch},
          {"first_mismatch", pixel(s.first_mismatch)}}},
        {"worst_rel", pixel(s.worst_rel)},
        {"worst_pq", pixel(s.worst_pq)},
        {"seconds", {{"reference", c.reference_seconds}, {"candidate", c.candidate_seconds}}},
        {"device", device(r.candidate_device)},
        {"reference_values", c.reference_values},
    });
  }
  json doc = {
      {"tool", "hdrconform"},
      {"started_utc", r.started_utc},
      {"wall_seconds", r.wall_seconds},
      {"reference", device(r.reference_device)},
      {"candidate", device(r.candidate_device)},
      {"candidate_unavailable", r.candidate_unavailable},
      {"summary",
       {{"total", r.cases.size()},
        {"pass", r.count(CaseVerdict::kPass)},
        {"fail", r.count(CaseVerdict::kFail)},
        {"error", r.count(CaseVerdict::kError)},
        {"skipped", r.count(CaseVerdict::kSkipped)},
        {"known_limit", r.count(CaseVerdict::kKnownLimit)},
        {"degenerate", r.count(CaseVerdict::kDegenerate)},
        {"exit_code", r.exit_code()}}},
      {"cases", cases},
  };
  return doc.dump(2) + "\n";
}

std::string junit_xml(const RunReport& r) {
  std::string x = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  const int failures = r.count(CaseVerdict::kFail);
  const int errors = r.count(CaseVerdict::kError);
  const int skipped = r.count(CaseVerdict::kSkipped) + r.count(CaseVerdict::kKnownLimit) +
                      r.count(CaseVerdict::kDegenerate);
  x += "<testsuites>\n<testsuite name=\"hdrconform\" tests=\"" + std::to_string(r.cases.size()) +
       "\" failures=\"" + std::to_string(failures) + "\" errors=\"" + std::to_string(errors) +
       "\" skipped=\"" + std::to_string(skipped) + "\" time=\"" + std::to_string(r.wall_seconds) +
       "\">\n";
  x += "  <properties><property name=\"candidate.device\" value=\"" +
       xml_escape(r.candidate_device.device + " / " + r.candidate_device.driver) +
       "\"/></properties>\n";
  for (const auto& c : r.cases) {
    x += "  <testcase classname=\"hdrconform." + xml_escape(std::string(c.spec.stage->name)) +
         "\" name=\"" + xml_escape(c.spec.id) + "\" time=\"" +
         std::to_string(c.reference_seconds + c.candidate_seconds) + "\"";
    switch (c.verdict) {
      case CaseVerdict::kPass:
        x += "/>\n";
        break;
      case CaseVerdict::kFail:
        x += ">\n    <failure message=\"" + xml_escape(c.reason) + "\">" + xml_escape(c.reason) +
             "\ntolerance: " + xml_escape(c.spec.tolerance.source) + "</failure>\n  </testcase>\n";
        break;
      case CaseVerdict::kError:
        x += ">\n    <error message=\"" + xml_escape(c.reason) + "\"/>\n  </testcase>\n";
        break;
      case CaseVerdict::kSkipped:
      case CaseVerdict::kKnownLimit:
      case CaseVerdict::kDegenerate:
        x += ">\n    <skipped message=\"" + std::string(verdict_name(c.verdict)) + ": " +
             xml_escape(c.reason) + "\"/>\n  </testcase>\n";
        break;
    }
  }
  x += "</testsuite>\n</testsuites>\n";
  return x;
}

Status write_run_outputs(const RunReport& r, const std::string& out_dir) {
  if (Status s = write_file_atomic(out_dir + "/results.json", results_json(r)); !s) return s;
  if (Status s = write_file_atomic(out_dir + "/junit.xml", junit_xml(r)); !s) return s;
  return write_file_atomic(out_dir + "/report/index.html", html_report(r));
}

}  // namespace hdrc
