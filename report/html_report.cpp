#include "report/html_report.h"

#include <cstdio>

namespace hdrc {

std::string html_escape(const std::string& s) {
  std::string out;
  out.reserve(s.size());
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
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

namespace {
std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}
const char* css_class(CaseVerdict v) {
  switch (v) {
    case CaseVerdict::kPass:
      return "pass";
    case CaseVerdict::kFail:
      return "fail";
    case CaseVerdict::kError:
      return "error";
    case CaseVerdict::kSkipped:
    case CaseVerdict::kKnownLimit:
    case CaseVerdict::kDegenerate:
      return "skip";
  }
  return "";
}
}  // namespace

std::string html_report(const RunReport& r) {
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n";
  h += "<title>hdrconform report</title>\n<style>\n";
  h += "body{font:14px system-ui,sans-serif;margin:1.5em;color:#222}"
       "table{border-collapse:collapse;width:100%}th,td{border:1px solid #ccc;padding:3px 6px;"
       "text-align:left;vertical-align:top}th{background:#f0f0f0}td.num{text-align:right;"
       "font-variant-numeric:tabular-nums}.pass{color:#11772d}.fail{color:#b00020;font-weight:bold}"
       ".error{color:#b35c00;font-weight:bold}.skip{color:#666}code{font-size:12px}"
       ".summary span{margin-right:1.5em}\n";
  h += "</style></head><body>\n<h1>hdrconform report</h1>\n";
  h += "<p class=\"summary\"><span>total " + std::to_string(r.cases.size()) + "</span>";
  h += "<span class=\"pass\">pass " + std::to_string(r.count(CaseVerdict::kPass)) + "</span>";
  h += "<span class=\"fail\">fail " + std::to_string(r.count(CaseVerdict::kFail)) + "</span>";
  h += "<span class=\"error\">error " + std::to_string(r.count(CaseVerdict::kError)) + "</span>";
  h += "<span class=\"skip\">skipped " + std::to_string(r.count(CaseVerdict::kSkipped)) + "</span>";
  h += "<span class=\"skip\">known limits " + std::to_string(r.count(CaseVerdict::kKnownLimit)) +
       "</span>";
  h += "<span class=\"skip\">degenerate " + std::to_string(r.count(CaseVerdict::kDegenerate)) +
       "</span></p>\n";
  h += "<p>Started " + html_escape(r.started_utc) + ", " + num(r.wall_seconds) +
       " s. Reference: " + html_escape(r.reference_device.device) +
       ". Candidate: " + html_escape(r.candidate_device.engine) + " on " +
       html_escape(r.candidate_device.device) + " (" + html_escape(r.candidate_device.driver) +
       ", Vulkan " + html_escape(r.candidate_device.api_version) + ").</p>\n";
  if (!r.candidate_unavailable.empty())
    h += "<p class=\"skip\">" + html_escape(r.candidate_unavailable) + "</p>\n";
  h += "<p><a href=\"../results.json\">results.json</a> · <a "
       "href=\"../junit.xml\">junit.xml</a></p>\n";
  h += "<table id=\"cases\"><thead><tr><th>verdict</th><th>case</th><th>stage</th><th>input</th>"
       "<th>max rel</th><th>max PQ (10-bit codes)</th><th>tolerance</th><th>worst pixel / reason"
       "</th></tr></thead><tbody>\n";
  for (const auto& c : r.cases) {
    const auto& s = c.stats;
    const auto& t = c.spec.tolerance;
    h += "<tr class=\"case\"><td class=\"" + std::string(css_class(c.verdict)) + "\">" +
         verdict_name(c.verdict) + "</td><td><code>" + html_escape(c.spec.id) + "</code></td><td>" +
         html_escape(std::string(c.spec.stage->name)) + "</td><td>" +
         html_escape(c.spec.input.describe()) + "</td><td class=\"num\">" + num(s.max_rel) +
         "</td><td class=\"num\">" + num(s.max_pq10) + "</td><td>rel " + num(t.linear_rel) +
         " (floor " + num(t.rel_floor) + "), pq10 " + num(t.pq_code10) + "<br><small>" +
         html_escape(t.source) + "</small></td><td>" + html_escape(c.reason);
    if ((c.verdict == CaseVerdict::kPass || c.verdict == CaseVerdict::kFail) && s.worst_rel.valid())
      h += "<br><small>worst rel at " + html_escape(describe_pixel(s.worst_rel)) + "</small>";
    h += "</td></tr>\n";
  }
  h += "</tbody></table>\n</body></html>\n";
  return h;
}

}  // namespace hdrc
