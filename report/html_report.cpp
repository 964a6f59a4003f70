#include "report/html_report.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <list>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <thread>
#include <tuple>

#include "color/st2084.h"
#include "core/cvars.h"
#include "core/pipeline.h"
#include "core/settings.h"
#include "core/stage.h"
#include "core/utf8.h"
#include "reference/ue/visualize/histogram.h"
#include "report/assets.h"
#include "report/images.h"
#include "runner/diff.h"
#include "runner/json_read.h"

namespace hdrc {

namespace fs = std::filesystem;
using json = nlohmann::json;

std::string html_escape(const std::string& s) {
  return escape_markup(s);
}

namespace report {

std::string url_path_escape(const std::string& path) {
  static const char* kHex = "0123456789ABCDEF";
  std::string out;
  for (unsigned char c : path) {
    if (std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~' || c == '/') {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

std::string case_slug(const std::string& id) {
  std::string out;
  for (unsigned char c : id) {
    if (std::isalnum(c) || c == '-' || c == '.' || c == '_')
      out += static_cast<char>(c);
    else if (c == '/')
      out += "__";
    else
      out += '_';
  }
  if (out.empty() || out[0] == '.') out = "_" + out;  // no hidden files, no "." or ".."
  if (out.size() > 120) out.resize(120);
  return out;
}

std::string script_safe_json(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '<')
      out += "\\u003c";
    else if (c == '>')
      out += "\\u003e";
    else if (c == '&')
      out += "\\u0026";
    else if (c == '\xE2' && i + 2 < text.size() && text[i + 1] == '\x80' &&
             (text[i + 2] == '\xA8' || text[i + 2] == '\xA9')) {
      out += text[i + 2] == '\xA8' ? "\\u2028" : "\\u2029";
      i += 2;
    } else {
      out += c;
    }
  }
  return out;
}

namespace {

// ---------------------------------------------------------------------------------------------
// Reading results.json defensively: every accessor tolerates a missing or differently typed field.

const json* get(const json& j, std::initializer_list<std::string_view> path) {
  const json* cur = &j;
  for (std::string_view key : path) {
    if (!cur->is_object()) return nullptr;
    auto it = cur->find(std::string(key));
    if (it == cur->end()) return nullptr;
    cur = &*it;
  }
  return cur;
}

// Numbers; results.json writes non-finite values as the strings "NaN", "Infinity", "-Infinity".
std::optional<double> num(const json* v) {
  if (!v) return std::nullopt;
  if (v->is_number()) return v->get<double>();
  if (v->is_string()) {
    const auto& s = v->get_ref<const std::string&>();
    if (s == "NaN") return std::nan("");
    if (s == "Infinity") return INFINITY;
    if (s == "-Infinity") return -INFINITY;
  }
  return std::nullopt;
}

std::string fmt(std::optional<double> v, const char* f = "%.4g") {
  if (!v) return "—";
  if (std::isnan(*v)) return "NaN";
  if (std::isinf(*v)) return *v > 0 ? "+Inf" : "−Inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, f, *v);
  return buf;
}

// An array or object as JSON text with its floating-point numbers to the 9 significant digits
// text() shows of a single number (a float32 value exactly), not a round trip's 17.
std::string dump_9g(const json& v) {
  if (v.is_number_float() && std::isfinite(v.get<double>())) return fmt(v.get<double>(), "%.9g");
  std::string s;
  if (v.is_array()) {
    for (const auto& e : v) s += (s.empty() ? "" : ",") + dump_9g(e);
    return "[" + s + "]";
  }
  if (v.is_object()) {
    for (const auto& [k, e] : v.items())
      s += (s.empty() ? "" : ",") + json(k).dump() + ":" + dump_9g(e);
    return "{" + s + "}";
  }
  return v.dump();
}

// Any JSON value as display text (not escaped).
std::string text(const json* v) {
  if (!v || v->is_null()) return "—";
  if (v->is_string()) return v->get<std::string>();
  if (v->is_boolean()) return v->get<bool>() ? "yes" : "no";
  if (v->is_number_integer() || v->is_number_unsigned()) return v->dump();
  if (v->is_number()) return fmt(v->get<double>(), "%.9g");
  return dump_9g(*v);
}

std::string esc_text(const json* v) {
  return html_escape(text(v));
}

// The tolerance as the report reads it: each metric's max (absent or null: not judged).
struct TolView {
  std::map<std::string, double> max;  // metric key → max
  double rel_floor = 0;
};
const char* const kMetricKeys[] = {"linear_abs", "linear_rel", "pq_code10", "pq_code12",
                                   "delta_e_itp"};

TolView tolerance_of(const json& c) {
  TolView t;
  const json* tj = get(c, {"tolerance"});
  if (!tj || !tj->is_object()) return t;
  for (const char* k : kMetricKeys) {
    const json* m = get(*tj, {k});
    std::optional<double> v = num(m);
    if (!v && m && m->is_object()) v = num(get(*m, {"max"}));
    if (v && std::isfinite(*v)) t.max[k] = *v;
  }
  if (auto f = num(get(*tj, {"rel_floor"}))) t.rel_floor = *f;
  return t;
}

// A metric's overall statistics object, wherever this version of results.json keeps it.
const json* metric_stats(const json& c, const std::string& key) {
  for (const json* base : {get(c, {"stats", "overall"}), get(c, {"metrics", "overall"}),
                           get(c, {"stats"}), get(c, {"metrics"})}) {
    if (base && base->is_object()) {
      if (const json* m = get(*base, {key}); m && m->is_object()) return m;
    }
  }
  return nullptr;
}

// The share of the budget used, as the runner computed it (results.json's budget_used,
// runner/diff.h: budget_used): the report only displays it, so allowed fractions and hard caps
// count exactly as they did for the verdict. Absent (null) when the case was not diffed.
std::optional<double> budget_used(const json& c) {
  return num(get(c, {"budget_used"}));
}

// The warnings list; a bare `warn` flag or string when there is none.
std::vector<std::string> warnings_of(const json& c) {
  std::vector<std::string> w;
  if (const json* v = get(c, {"warnings"}); v && v->is_array())
    for (const auto& e : *v) w.push_back(e.is_string() ? e.get<std::string>() : e.dump());
  if (!w.empty()) return w;
  if (const json* v = get(c, {"warn"})) {
    if (v->is_string() && !v->get<std::string>().empty()) w.push_back(v->get<std::string>());
    if (v->is_boolean() && v->get<bool>()) w.push_back("over a warn level");
  }
  return w;
}

// A FAIL's possible causes (results.json "hints", runner/diagnosis.h), as the reason words them.
std::vector<std::string> hints_of(const json& c) {
  std::vector<std::string> h;
  if (const json* v = get(c, {"hints"}); v && v->is_array())
    for (const auto& e : *v)
      if (e.is_object())
        h.push_back("possible cause: " + text(get(e, {"message"})) + " (" +
                    text(get(e, {"evidence"})) + "; see " + text(get(e, {"docs"})) + ")");
  return h;
}

bool truthy(const json* v) {
  if (!v || v->is_null()) return false;
  if (v->is_boolean()) return v->get<bool>();
  if (v->is_string()) return !v->get<std::string>().empty();
  if (v->is_object() || v->is_array()) return !v->empty();
  return true;
}

// Near miss: passed with more than this share of the budget used.
constexpr double kNearMiss = 0.5;

// ---------------------------------------------------------------------------------------------
// One case as the report sees it.

struct CaseView {
  const json* j = nullptr;
  size_t index = 0;
  std::string id, slug, pipeline, stage, verdict, reason;
  std::vector<std::string> warnings;
  std::vector<std::string> hints;  // "possible cause: ..." (results.json "hints")
  bool tighten = false, near_miss = false;
  std::optional<double> budget;
  TolView tol;
  int width = 0, height = 0;
  bool has[3] = {false, false, false};  // input, reference, candidate EXR read
  bool heat = false;                    // heat/mask maps written
  size_t over_pixels = 0, mismatch_pixels = 0;
  bool px = false;      // float data written
  std::string px_json;  // the float data for the case page (script-safe JSON), until it is written
  std::string error;    // why images are missing, if they are
  int lut_size = 0;
  json meta;  // what the case page's script needs
  // Where each picture of the case lies in its one PNG, c/<slug>.png (see case_images): input,
  // reference, candidate (SDR previews), heat, heat_itp, mask.
  struct Rect {
    int x = 0, y = 0, w = 0, h = 0;
  };
  std::map<std::string, Rect> sprite;
  std::string sprite_png;  // that PNG's bytes, until the page (which carries it) is written
  // The list pages' thumbnails (the main preview, the heatmap), and where write_report put them
  // in the thumbnail atlases: t/<atlas>.png at (0, y).
  Rgb8 thumb[2];
  int thumb_atlas = -1, thumb_y[2] = {0, 0};
};

const char* const kImageNames[3] = {"input", "reference", "candidate"};

std::string verdict_class(const std::string& v) {
  if (v == "PASS") return "pass";
  if (v == "FAIL" || v == "MISSING") return "fail";
  if (v == "ERROR") return "error";
  return "skip";
}

// The case's output encoding: stage from the case, device and gamut resolved from its cvars and
// settings exactly as the runner resolves them (its pipeline's host derivation).
Result<OutputEncoding> encoding_of(const json& c, int width, int height) {
  Case spec;
  const std::string stage = text(get(c, {"stage"}));
  spec.stage = find_stage(stage);
  if (!spec.stage) return Error{"results.json", "/stage", "unknown stage '" + stage + "'", ""};
  const Pipeline& pipeline = pipeline_of(*spec.stage);
  spec.settings = pipeline.new_settings();
  if (const json* cv = get(c, {"cvars"}); cv && cv->is_object())
    for (const auto& [k, v] : cv->items())
      if (auto d = num(&v)) (void)spec.cvars.set(k, *d);
  if (const json* st = get(c, {"settings"}); st && st->is_object())
    for (const auto& [k, v] : st->items()) {
      const SettingInfo* info = find_setting(spec.settings.table(), k);
      if (!info) continue;
      Vec4d v4{0, 0, 0, 0};
      if (auto d = num(&v)) v4[0] = *d;
      if (v.is_array())
        for (size_t i = 0; i < v.size() && i < 4; ++i) v4[i] = num(&v[i]).value_or(0);
      (void)spec.settings.set(k, v4, info->components);
    }
  auto r = pipeline.resolve(spec, std::max(1, width), std::max(1, height));
  if (!r) return r.error();
  return output_encoding(*spec.stage, r->params);
}

// OutputEncoding::to_nits as data for the page's script (assets/report.js toNits): nits =
// transfer(pre_scale · v) · nits_scale.
json encoding_json(const OutputEncoding& e) {
  using T = OutputEncoding::Transfer;
  const T kinds[] = {T::kLinear, T::kPq, T::kSrgb, T::kRec709, T::kGamma};
  const char* const names[] = {"linear", "pq", "srgb", "rec709", "gamma"};
  const char* t = "linear";
  for (int k = 0; k < 5; ++k)
    if (e.transfer == kinds[k]) t = names[k];
  return {{"transfer", t},
          {"pre_scale", e.pre_scale},
          {"nits_scale", e.nits_scale},
          {"gamma", e.gamma}};
}

// Writes a file (the whole report is built in a fresh folder, swapped in at the end).
Status write_text(const fs::path& p, const std::string& s) {
  std::ofstream f(p, std::ios::binary);
  f << s;
  f.close();
  if (!f) return Error{p.string(), "", "cannot write", ""};
  return {};
}

// ---------------------------------------------------------------------------------------------
// HTML pieces.

std::string page_head(const std::string& title, const std::string& root, const std::string& page) {
  std::string h = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n";
  h += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  // Everything is local: no request leaves the report folder (and results dir for the EXRs).
  h += "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'self' file: data:; "
       "img-src 'self' file: data: blob:; script-src 'self' file:; style-src 'self' file: "
       "'unsafe-inline'\">\n";
  h += "<title>" + html_escape(title) + "</title>\n";
  h += "<link rel=\"stylesheet\" href=\"" + root + "assets/report.css\">\n";
  h += "</head><body data-page=\"" + page + "\">\n";
  h += "<nav class=\"top\"><a href=\"" + root + "index.html\"" +
       (page == "summary" ? " class=\"here\"" : "") + ">Summary</a><a href=\"" + root +
       "matrix.html\"" + (page == "matrix" ? " class=\"here\"" : "") +
       ">Cvar matrix</a><a href=\"" + root + "cases.html\"" +
       (page == "cases" ? " class=\"here\"" : "") +
       ">Cases</a><span class=\"brand\">hdrconform report</span></nav>\n<main>\n";
  return h;
}

std::string page_tail(const std::string& root, const std::vector<std::string>& scripts) {
  // report.js first: the data scripts after it hand their data to HDRC.data / HDRC.pixels; the
  // page is set up on DOMContentLoaded, when every one of them has run.
  std::string h = "</main>\n<script src=\"" + root + "assets/report.js\"></script>\n";
  for (const auto& s : scripts) h += "<script src=\"" + s + "\"></script>\n";
  return h + "</body></html>\n";
}

// "12px": a CSS length in pixels, to 4 decimals (thumbnail scale factors are not integers).
std::string css_px(double v) {
  return fmt(v, "%.4g") + "px";
}

// A list page's thumbnail of a case (`which`: 0 its main preview, 1 its heatmap), nearest
// neighbour at most 160 pixels wide and [12, 40] high (report/images.h thumbnail). Thumbnails
// are not files of their own: every case's sit stacked in a few atlas PNGs, t/<n>.png (written
// by write_report), and a thumbnail is its atlas offset in a box of its size (no script needed).
std::string thumb_img(const CaseView& c, int which, bool lazy) {
  const Rgb8& t = c.thumb[which];
  if (c.thumb_atlas < 0 || t.width <= 0 || t.height <= 0) return "";
  return "<span class=\"thumb\" data-key=\"" + std::string(which ? "heat" : "main") +
         "\" style=\"width:" + css_px(t.width) + ";height:" + css_px(t.height) + "\"><img" +
         (lazy ? " loading=\"lazy\"" : "") + " alt=\"\" src=\"t/" + std::to_string(c.thumb_atlas) +
         ".png\" style=\"margin-top:" + css_px(-c.thumb_y[which]) + "\"></span>";
}

// The list pages' case cell: the case's id, shortened to fit a line (short_case_id; the full id
// in the link's title), and beneath it the reason, cut to two lines by the
// stylesheet (a click on it shows it all, assets/report.js; no copy in a title: a list of 1408
// cases carries its reasons once).
constexpr size_t kShortIdChars = 64;
std::string case_cell(const CaseView& c) {
  const std::string shown = report::short_case_id(c.id, kShortIdChars);
  std::string h = "<a class=\"case-link\" href=\"c/" + url_path_escape(c.slug) +
                  ".html\" title=\"" + html_escape(c.id) + "\"><code>" + html_escape(shown) +
                  "</code></a>";
  if (!c.reason.empty()) h += "<div class=\"reason\">" + html_escape(c.reason) + "</div>";
  return h;
}

std::string badge(const std::string& verdict) {
  return "<span class=\"badge v-" + verdict_class(verdict) + "\">" + html_escape(verdict) +
         "</span>";
}

std::string markers(const CaseView& c) {
  std::string h;
  if (!c.warnings.empty())
    h += " <span class=\"marker warn\" title=\"passed with a warning\">WARN</span>";
  if (c.near_miss)
    h += " <span class=\"marker near\" title=\"passed with more than half the budget used\">near "
         "miss</span>";
  if (c.tighten)
    h += " <span class=\"marker tighten\" title=\"every metric under 10 % of its budget\">could be "
         "tightened</span>";
  return h;
}

// The case pages' table rows leave out the end tags of their cells and rows, and put no line
// break between rows (a break would end up in the last cell's text): HTML's optional tags
// (WHATWG HTML, 13.1.2.4 "Optional tags": a td's or th's end tag may be omitted when a td or
// th follows or the row ends; a tr's when a tr follows or the table section ends), which parse
// to the same tables. These tables are most of a case page's bytes: 5 bytes a cell, 2.3 MB of
// the 1655 case pages of the default run (issue 27 item 8).

// A key → value table of a JSON object (values shown as text; nested values as JSON).
std::string kv_table(const json* obj, const std::string& id, const std::string& empty) {
  if (!obj || !obj->is_object() || obj->empty()) return "<p class=\"muted\">" + empty + "</p>\n";
  std::string h = "<table class=\"kv\" id=\"" + id + "\"><tbody>";
  for (const auto& [k, v] : obj->items()) h += "<tr><th>" + html_escape(k) + "<td>" + esc_text(&v);
  return h + "</tbody></table>\n";
}

// A table of statistics: rows are the keys of `obj` (metrics or bands), columns the union of the
// numeric fields of the row objects (nested one level: "rel.max").
// Pixel objects ("worst") are left out: the worst-pixel table shows them.
void flatten(const json& j, const std::string& prefix,
             std::vector<std::pair<std::string, const json*>>* out) {
  if (j.is_object()) {
    for (const auto& [k, v] : j.items())
      if (k != "worst" && k != "first_mismatch")
        flatten(v, prefix.empty() ? k : prefix + "." + k, out);
  } else {
    out->push_back({prefix, &j});
  }
}

// A metric's statistics with what results.json leaves out (runner/results.cpp) filled in: where
// every value is equal on both sides (count and max 0 only) each statistic 0; the fraction over
// where no value is over (over 0) 0.
json full_metric_stats(const json& m) {
  const json* max = get(m, {"max"});
  if (!m.is_object()) return m;
  if (m.contains("mean") || !max || !max->is_number() || max->get<double>() != 0) {
    const auto over = num(get(m, {"over"}));
    if (m.contains("fraction_over") || !over || *over != 0) return m;
    json out = m;
    out["fraction_over"] = 0;
    return out;
  }
  json out = m;
  for (const char* k : {"mean", "rms", "p99", "p99_9", "over", "fraction_over"}) out[k] = 0;
  return out;
}

std::string stats_table(const json* obj, const std::string& id, const std::string& row_head) {
  if (!obj || (!obj->is_object() && !obj->is_array()) || obj->empty()) return "";
  std::vector<std::pair<std::string, std::vector<std::pair<std::string, const json*>>>> rows;
  std::vector<std::string> cols;
  std::set<std::string> seen;
  std::list<json> filled;  // full_metric_stats's copies, alive while the table is written
  auto add_row = [&](const std::string& name, const json& row) {
    const json& v = filled.emplace_back(full_metric_stats(row));
    std::vector<std::pair<std::string, const json*>> cells;
    if (v.is_object())
      flatten(v, "", &cells);
    else
      cells.push_back({"value", &v});
    for (const auto& [k, _] : cells)
      if (seen.insert(k).second) cols.push_back(k);
    rows.push_back({name, std::move(cells)});
  };
  if (obj->is_object()) {
    for (const auto& [k, v] : obj->items()) add_row(k, v);
  } else {
    for (const auto& v : *obj) {
      std::string name = "—";
      for (const char* key : {"band", "name", "metric", "range"})
        if (const json* n = get(v, {key})) {
          name = text(n);
          break;
        }
      add_row(name, v);
    }
  }
  std::string h = "<div class=\"scroll\"><table class=\"stats\" id=\"" + id + "\"><thead><tr><th>" +
                  row_head + "</th>";
  for (const auto& c : cols) h += "<th>" + html_escape(c) + "</th>";
  h += "</tr></thead><tbody>";
  for (const auto& [name, cells] : rows) {
    h += "<tr><th>" + html_escape(name);
    for (const auto& c : cols) {
      const json* v = nullptr;
      for (const auto& [k, p] : cells)
        if (k == c) v = p;
      const auto n = num(v);
      // Numbers right-aligned by the stylesheet (table.stats td): no class per cell, as these
      // tables are most of a case page's bytes (and no end tags: kv_table).
      h += "<td>" + (n ? fmt(n) : esc_text(v));
    }
  }
  return h + "</tbody></table></div>\n";
}

// The per-band statistics of results.json (runner/results.cpp: a band lists its judged metrics,
// none where it holds every pixel) as one table, a row per band and metric, and a line of each
// band's pixels. Columns: the union of the rows' statistics, in the order first seen.
std::string band_table(const json& bands, std::optional<double> case_pixels) {
  std::vector<std::string> cols;
  std::set<std::string> seen;
  std::list<json> filled;
  std::vector<
      std::tuple<std::string, std::string, std::vector<std::pair<std::string, const json*>>>>
      rows;
  std::string counts, notes;
  for (const auto& b : bands) {
    const std::string name = text(get(b, {"band"}));
    const auto pixels = num(get(b, {"pixels"}));
    counts += (counts.empty() ? "" : ", ") + html_escape(name) + ": " + fmt(pixels, "%.0f");
    const json* m = get(b, {"metrics"});
    if (pixels && *pixels > 0 && m && m->is_object() && m->empty())
      notes = case_pixels && *pixels == *case_pixels
                  ? " (one band holds every pixel: its statistics are the overall ones)"
                  : " (no metric is judged)";
    if (!m || !m->is_object()) continue;
    for (const auto& [metric, stats] : m->items()) {
      const json& v = filled.emplace_back(full_metric_stats(stats));
      std::vector<std::pair<std::string, const json*>> cells;
      flatten(v, "", &cells);
      for (const auto& [k, _] : cells)
        if (seen.insert(k).second) cols.push_back(k);
      rows.push_back({name, metric, std::move(cells)});
    }
  }
  std::string h;
  if (!rows.empty()) {
    h = "<div class=\"scroll\"><table class=\"stats\" id=\"stats-bands\"><thead><tr><th>band"
        "</th><th>metric</th>";
    for (const auto& c : cols) h += "<th>" + html_escape(c) + "</th>";
    h += "</tr></thead><tbody>";
    for (const auto& [band, metric, cells] : rows) {
      h += "<tr><th>" + html_escape(band) + "<th>" + html_escape(metric);
      for (const auto& c : cols) {
        const json* v = nullptr;
        for (const auto& [k, p] : cells)
          if (k == c) v = p;
        const auto n = num(v);
        h += "<td>" + (n ? fmt(n) : esc_text(v));
      }
    }
    h += "</tbody></table></div>\n";
  }
  return h + "<p>Pixels per band: " + counts + notes + ".</p>\n";
}

// `probe`: the page has float data, so each row gets a button that shows its pixel in the probe.
std::string pixel_rows(const json& c, bool probe) {
  // Every worst/first pixel object the case has: worst, worst_rel, worst_pq, per-metric worst,
  // nonfinite.first_mismatch.
  std::vector<std::pair<std::string, const json*>> px;
  for (const char* k : {"worst_pixel", "worst", "worst_rel", "worst_pq"})
    if (const json* p = get(c, {k}); p && p->is_object()) {
      const json* m = get(*p, {"metric"});
      px.push_back({m ? "worst (" + text(m) + ")" : std::string(k), p});
    }
  // A metric's worst value that is the case's worst pixel (the same value) is its row already.
  const json* case_worst = get(c, {"worst_pixel"});
  auto same = [&](const json* w, const char* metric) {
    if (!case_worst || !case_worst->is_object() || text(get(*case_worst, {"metric"})) != metric)
      return false;
    for (const char* f : {"x", "y", "channel"})
      if (text(get(*case_worst, {f})) != text(get(*w, {f}))) return false;
    return true;
  };
  for (const char* k : kMetricKeys)
    if (const json* m = metric_stats(c, k))
      if (const json* w = get(*m, {"worst"}); w && w->is_object() && !same(w, k))
        px.push_back({std::string(k) + " max", w});
  if (const json* p = get(c, {"nonfinite", "first_mismatch"}); p && p->is_object())
    px.push_back({"first non-finite mismatch", p});
  // Entries of one pixel and channel (most metrics' worst values are the same pixel) are one row
  // that names them all, in this order.
  std::vector<std::pair<std::string, const json*>> rows;
  for (const auto& entry : px) {
    // Named copies, not a structured binding: clang 14 (the sanitizer build) cannot capture one.
    const std::string& label = entry.first;
    const json* p = entry.second;
    auto same_pixel = [&](const auto& row) {
      for (const char* f : {"x", "y", "channel", "input", "reference", "candidate"})
        if (text(get(*row.second, {f})) != text(get(*p, {f}))) return false;
      return true;
    };
    if (auto it = std::find_if(rows.begin(), rows.end(), same_pixel); it != rows.end())
      it->first += "; " + label;
    else
      rows.push_back({label, p});
  }
  std::string h;  // no end tags (kv_table)
  for (const auto& [label, p] : rows) {
    h += "<tr data-x=\"" + esc_text(get(*p, {"x"})) + "\" data-y=\"" + esc_text(get(*p, {"y"})) +
         "\"><th>" + html_escape(label);
    for (const char* f : {"x", "y", "channel", "band"}) h += "<td>" + esc_text(get(*p, {f}));
    // The values in the monospace font of the stylesheet's #worst-pixel rule.
    for (const char* f : {"input", "reference", "candidate"}) {
      const auto v = num(get(*p, {f}));
      h += "<td>" + (v ? fmt(v, "%.9g") : esc_text(get(*p, {f})));
    }
    if (probe) h += "<td><button type=\"button\" class=\"goto\">probe</button>";
  }
  return h;
}

// The cvars with UE's names beside the device and gamut numbers (HDRHelper.h:
// EDisplayOutputFormat, EDisplayColorGamut); mirrored in assets/report.js (VALUE_NAMES).
json named_cvars(const json* cvars) {
  static const std::map<std::string, std::vector<const char*>> kNames = {
      {"r.HDR.Display.OutputDevice",
       {"SDR sRGB", "SDR Rec.709", "SDR explicit gamma", "HDR ACES 1000-nit ST 2084",
        "HDR ACES 2000-nit ST 2084", "HDR ACES 1000-nit scRGB", "HDR ACES 2000-nit scRGB",
        "HDR LinearEXR", "HDR LinearNoToneCurve", "HDR LinearWithToneCurve"}},
      {"r.HDR.Display.ColorGamut",
       {"Rec.709 / sRGB D65", "DCI-P3 D65", "Rec.2020 D65", "ACES AP0 D60", "ACEScg AP1 D60"}}};
  if (!cvars || !cvars->is_object()) return json();
  json out = *cvars;
  for (const auto& [k, names] : kNames) {
    auto v = num(get(*cvars, {k}));
    if (v && *v >= 0 && *v < static_cast<double>(names.size()) && *v == std::floor(*v))
      out[k] = text(get(*cvars, {k})) + " (" + names[static_cast<size_t>(*v)] + ")";
  }
  return out;
}

std::string case_image_dir_of(const std::string& id) {
  return "cases/" + id;
}

// A command that runs this one case again as the run did: the recorded command line without
// the options that pick cases or outputs, then --filter '=<id>' (exact) and a fresh --out.
std::string reproduce_command(const json& doc, const std::string& id) {
  const json* prov = get(doc, {"provenance"});
  std::string base = prov ? text(get(*prov, {"reproduce"})) : "—";
  if (base == "—" || base.empty()) base = "hdrconform " + text(get(doc, {"command"}));
  std::string q = "'";
  for (char ch : "=" + id) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return base + " --filter " + q + "' --out repro";
}

// A tolerance reason's lead: its first sentence (to the first ". " or ": "), at most 160 bytes
// (cut at a space, never inside a UTF-8 sequence).
std::string reason_lead(const std::string& r) {
  size_t end = std::min(r.find(". "), r.find(": "));
  if (end == std::string::npos || end > 160) {
    end = std::min<size_t>(r.size(), 160);
    if (end < r.size()) {
      const size_t space = r.rfind(' ', end);
      end = space != std::string::npos && space > 0 ? space : end;
      while (end > 0 && (static_cast<unsigned char>(r[end]) & 0xC0) == 0x80) --end;
    }
  }
  return end < r.size() ? r.substr(0, end) + " …" : r;
}

// A tolerance reason's parts: the tolerance's own and each overlay's, which
// runner/tolerance.cpp apply_overlays joins with "; overlay: " (an overlay measured per case
// makes each case's whole reason its own, while its parts are shared).
std::vector<std::string> reason_parts(const std::string& r) {
  static const std::string kJoin = "; overlay: ";
  std::vector<std::string> out;
  size_t from = 0;
  for (size_t at; (at = r.find(kJoin, from)) != std::string::npos; from = at + kJoin.size())
    out.push_back(r.substr(from, at - from));
  out.push_back(r.substr(from));
  return out;
}

std::string metadata_table(const json& doc) {
  std::string h = "<table class=\"kv\" id=\"run-meta\"><tbody>\n";
  auto row = [&](const std::string& k, const std::string& v) {
    h += "<tr><th>" + html_escape(k) + "</th><td>" + html_escape(v) + "</td></tr>\n";
  };
  const json* prov = get(doc, {"provenance"});
  auto p = [&](const char* k) { return text(prov ? get(*prov, {k}) : nullptr); };
  row("commit", p("commit"));
  row("command line", p("command_line"));
  row("working directory", p("cwd"));
  row("shader directory",
      p("shader_dir") + (p("shader_hash").size() > 12
                             ? " (sha256 " + p("shader_hash").substr(0, 16) + "…)"
                             : ""));
  row("build", p("build_type") + ", " + p("compiler"));
  row("suite", p("suite_cases") + " cases, fingerprint " + p("suite_fingerprint").substr(0, 16));
  row("shard plan", p("shard_plan"));
  row("images kept", p("images"));
  row("candidate engine", text(get(doc, {"candidate", "engine"})));
  row("candidate device", text(get(doc, {"candidate", "device"})));
  row("driver", text(get(doc, {"candidate", "driver"})));
  row("Vulkan", text(get(doc, {"candidate", "api_version"})));
  if (const json* pr = get(doc, {"candidate", "precision"}); pr && pr->is_object())
    row("device precision", "sub-texel " + text(get(*pr, {"sub_texel_precision_bits"})) +
                                " bits, mipmap " + text(get(*pr, {"mipmap_precision_bits"})) +
                                " bits, float16 RTE " + text(get(*pr, {"rounding_rte_float16"})) +
                                ", device model " + text(get(*pr, {"device_model"})));
  row("reference", text(get(doc, {"reference", "device"})));
  row("started (UTC)", text(get(doc, {"started_utc"})));
  row("duration (s)", fmt(num(get(doc, {"wall_seconds"})), "%.2f"));
  row("command", text(get(doc, {"command"})));
  row("jobs", text(get(doc, {"jobs"})));
  row("shard", text(get(doc, {"shard"})));
  if (const json* m = get(doc, {"merged_from"}); m && m->is_array()) {
    std::string shards;
    for (const auto& e : *m)
      shards += (shards.empty() ? "" : "; ") + text(get(e, {"shard"})) + " " +
                text(get(e, {"dir"})) + " (" + fmt(num(get(e, {"wall_seconds"})), "%.1f") + " s)";
    row("merged from", shards);
  }
  if (truthy(get(doc, {"interrupted"}))) row("interrupted", "yes: cases not started are NOT_RUN");
  if (truthy(get(doc, {"candidate_unavailable"})))
    row("candidate unavailable", text(get(doc, {"candidate_unavailable"})));
  // verify's candidate protocol (runner/verify.h): the reference mode, declined cases and the
  // deviations the candidate declared.
  if (text(get(doc, {"reference_mode"})) == "analytic")
    row("reference mode", "analytic: CombineLUTs per pixel, no baked LUT (verify --reference)");
  if (const auto n = num(get(doc, {"summary", "unsupported"})); n && *n > 0)
    row("UNSUPPORTED",
        fmt(*n, "%.0f") + " case(s) declined by the candidate: never a pass" +
            (truthy(get(doc, {"require_all"})) ? "; --require-all fails the run" : ""));
  if (const json* limits = get(doc, {"candidate_limits", "limits"}); limits && limits->is_array())
    for (const json& l : *limits)
      row("declared by the candidate (" + text(get(doc, {"candidate_limits", "file"})) + ")",
          text(get(l, {"cases"})) + ": " + text(get(l, {"reason"})));
  return h + "</tbody></table>\n";
}

// The golden check of the reference (results.json "goldens", runner/results.h:
// record_golden_results): counts, and every missing, stale or regressed golden with its message.
std::string goldens_section(const json& doc) {
  const json* g = get(doc, {"goldens"});
  if (!g || !g->is_object()) return "";
  const auto failed = num(get(*g, {"failed"})).value_or(0);
  std::string h =
      "<h2 id=\"goldens\">Goldens</h2>\n<p id=\"goldens-summary\" class=\"" +
      std::string(failed > 0 ? "warning" : "muted") + "\">The reference's outputs against " +
      esc_text(get(*g, {"dir"})) + " (reference " + esc_text(get(*g, {"reference_version"})) +
      "): " + esc_text(get(*g, {"checked"})) + " checked, " + esc_text(get(*g, {"match"})) +
      " match, " + esc_text(get(*g, {"missing"})) + " missing, " + esc_text(get(*g, {"stale"})) +
      " stale, " + esc_text(get(*g, {"regression"})) + " regressions.</p>\n";
  std::string rows;
  if (const json* cs = get(*g, {"cases"}); cs && cs->is_array())
    for (const auto& e : *cs) {
      if (text(get(e, {"outcome"})) == "match") continue;
      rows += "<tr><td><span class=\"badge v-fail\">GOLDEN " + esc_text(get(e, {"outcome"})) +
              "</span></td><td><code>" + esc_text(get(e, {"id"})) +
              "</code></td><td class=\"reason\">" + esc_text(get(e, {"message"})) + "</td></tr>\n";
    }
  if (!rows.empty())
    h += "<table class=\"cases\" id=\"golden-failures\"><thead><tr><th>outcome</th><th>case</th>"
         "<th>what differs, and the command if intended</th></tr></thead><tbody>\n" +
         rows + "</tbody></table>\n";
  return h;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// The list pages' short ids, the metrics a case is judged on, and the class of a failure.

namespace {

// The code points of UTF-8 text (a lead byte and its continuation bytes each).
std::vector<std::string> code_points(const std::string& s) {
  std::vector<std::string> out;
  for (size_t i = 0; i < s.size(); ++i) {
    if ((static_cast<unsigned char>(s[i]) & 0xC0) == 0x80 && !out.empty())
      out.back() += s[i];
    else
      out.emplace_back(1, s[i]);
  }
  return out;
}

std::string joined(const std::vector<std::string>& cps, size_t from, size_t to) {
  std::string s;
  for (size_t i = from; i < to && i < cps.size(); ++i) s += cps[i];
  return s;
}

}  // namespace

std::string short_case_id(const std::string& id, size_t max_chars) {
  const std::vector<std::string> cps = code_points(id);
  if (cps.size() <= max_chars || max_chars < 8) return id;
  // The first segment (the suite, up to its '/') when it takes at most a third of the room.
  size_t head = 0;
  while (head < cps.size() && cps[head] != "/") ++head;
  if (head >= cps.size() || head + 3 > max_chars / 3) head = 0;
  const std::string prefix = head ? joined(cps, 0, head) + "/…" : "…";
  const size_t room = max_chars - (head ? head + 2 : 1);  // for the end of the id
  // The end of the id, from a separator ('/' kept, after a '_') when one lies in the first
  // quarter of the room (no word cut there), else its last `room` code points.
  size_t from = cps.size() - room;
  for (size_t i = from + 1; i <= from + room / 4 && i < cps.size(); ++i)
    if (cps[i - 1] == "/" || cps[i - 1] == "_") {
      from = cps[i - 1] == "/" ? i - 1 : i;
      break;
    }
  return prefix + joined(cps, from, cps.size());
}

std::vector<std::string> judged_metrics(const json& c) {
  std::vector<std::string> out;
  const json* t = get(c, {"tolerance"});
  if (!t || !t->is_object()) return out;
  // Metric entries: an object (max, allowed_fraction, hard, warn) or, in older results, a number;
  // the dither criterion an object; rel_floor, reason and source are not metrics. The diff's
  // metrics first, in the runner's order (core/case.h Metric, the order judge() decides in),
  // then any other (a metric this report does not know yet), then dither.
  auto judged = [&](const std::string& k) {
    const json* v = get(*t, {k});
    return v && (v->is_object() || (v->is_number() && k != "rel_floor"));
  };
  for (const char* k : kMetricKeys)
    if (judged(k)) out.push_back(k);
  for (const auto& [k, v] : t->items())
    if (k != "dither" && std::find(out.begin(), out.end(), k) == out.end() && judged(k))
      out.push_back(k);
  if (judged("dither")) out.push_back("dither");
  return out;
}

std::string FailureClass::label() const {
  return metric.empty() || kind.rfind(metric, 0) == 0 ? kind : metric + " " + kind;
}

FailureClass failure_class(const json& c) {
  const std::string verdict = text(get(c, {"verdict"}));
  std::string lower;
  for (char ch : verdict) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (verdict != "FAIL") return {"", lower};
  if (num(get(c, {"nonfinite", "mismatch"})).value_or(0) > 0)
    return {"non-finite", "non-finite mismatch"};
  // A dither criterion: runner/dither.cpp names it first in the reason ("dither mean: ...",
  // "exact pattern (...)").
  const std::string reason = text(get(c, {"reason"}));
  if (truthy(get(c, {"dither"}))) {
    if (reason.rfind("dither ", 0) == 0 && reason.find(':') != std::string::npos)
      return {reason.substr(0, reason.find(':')), "over tolerance"};
    if (reason.rfind("exact pattern", 0) == 0) return {"dither exact pattern", "over tolerance"};
  }
  // The metrics in the tolerance's order (runner/diff.cpp judge: hard cap, then max or allowed
  // fraction, metric by metric; the first over decides).
  const json* t = get(c, {"tolerance"});
  for (const std::string& k : judged_metrics(c)) {
    if (k == "dither") continue;
    const json* st = metric_stats(c, k);
    const json* tk = get(*t, {k});
    if (!st || !tk) continue;
    const auto max = num(get(*st, {"max"}));
    if (!max) continue;
    const auto limit = tk->is_number() ? num(tk) : num(get(*tk, {"max"}));
    const auto hard = num(get(*tk, {"hard"}));
    const double fraction = num(get(*tk, {"allowed_fraction"})).value_or(0);
    if (hard && !(*max <= *hard)) return {k, "over hard cap"};
    const bool over = fraction > 0 ? !(num(get(*st, {"fraction_over"})).value_or(0) <= fraction)
                                   : limit && !(*max <= *limit);
    if (over) return {k, "over tolerance"};
  }
  return {"", "fail"};
}

namespace {

struct Builder {
  fs::path results_dir, out;  // out: the new report folder
  json doc;
  std::vector<CaseView> cases;
  // Tolerance reasons that several cases share (most cases of a stage share their defaults'):
  // each is written once, in tolerances.html, and a case page links to it (share_reasons).
  struct SharedReason {
    int id = 0, cases = 0;
  };
  std::map<std::string, SharedReason> reasons;
  std::atomic<size_t> files{0};

  Status put(const fs::path& rel, const std::string& s) {
    ++files;
    return write_text(out / rel, s);
  }
  Status put_png(const fs::path& rel, const Rgb8& img) {
    ++files;
    return write_png((out / rel).string(), img);
  }

  // Images and float data of one case; a missing or unreadable EXR is noted, never fatal.
  Status case_images(CaseView& c) {
    Image img[3];
    fs::path path[3];
    const fs::path case_dir = results_dir / "cases" / fs::path(c.id);
    // Ids are data: refuse any that would leave the results directory.
    const bool safe = c.id.find("..") == std::string::npos && !c.id.empty() && c.id[0] != '/';
    for (int i = 0; i < 3 && safe; ++i) {
      fs::path p = case_dir / (std::string(kImageNames[i]) + ".exr");
      if (const json* given = get(*c.j, {"images", kImageNames[i]}); given && given->is_string()) {
        const std::string g = given->get<std::string>();
        if (g.find("..") == std::string::npos && !g.empty() && g[0] != '/') p = results_dir / g;
      }
      std::error_code ec;
      if (!fs::exists(p, ec)) continue;
      // What the run just wrote, from memory when it kept it (core/image.h written_images).
      std::optional<Image> kept = written_images::take(p.string());
      auto r = kept ? Result<Image>(std::move(*kept)) : read_image(p.string());
      if (!r) {
        c.error += r.error().to_string() + "\n";
        continue;
      }
      img[i] = std::move(*r);
      path[i] = p;
      c.has[i] = true;
    }
    const Image* shape = c.has[1] ? &img[1] : c.has[2] ? &img[2] : c.has[0] ? &img[0] : nullptr;
    if (!shape) return {};
    c.width = shape->width;
    c.height = shape->height;
    for (int i = 0; i < 3; ++i)
      if (c.has[i] && (img[i].width != c.width || img[i].height != c.height) && i != 0) {
        c.error += std::string(kImageNames[i]) + " has a different size; not shown\n";
        c.has[i] = false;
      }
    auto enc = encoding_of(*c.j, c.width, c.height);
    if (!enc) {
      c.error += enc.error().to_string() + "\n";
      return {};
    }
    const bool input_scene_linear = enc->stage != StageId::kUiComposite;
    OutputEncoding scene;  // scene-linear × 100 nits: how inputs are read (shaper's encoding)
    scene.stage = StageId::kShaper;
    // Images up to 4 Mpixel (every case of the suites) go into the case page as float data, and
    // the page's script draws their previews, heatmaps and mask from it (assets/report.js:
    // previewData, pixelError, maskData): here only the list pages' thumbnails are made, from
    // the pixels a thumbnail shows (sample_nearest, the sampling of thumbnail()), which are the
    // same bytes as thumbnails of the full pictures without making those. Larger images get no
    // float data; their pictures are made here, into one PNG the page carries.
    const size_t kMaxPxData = size_t{1} << 22;
    const bool script_draws = c.width * static_cast<size_t>(c.height) <= kMaxPxData;
    const int main = c.has[2] ? 2 : c.has[1] ? 1 : 0;
    const bool compared = c.has[1] && c.has[2];
    Image sampled[3];
    const Image* src[3] = {&img[0], &img[1], &img[2]};
    Tolerance tol;  // only the limits the mask judges, from results.json
    tol.rel_floor = c.tol.rel_floor;
    for (int m = 0; m < kMetricCount; ++m)
      if (auto it = c.tol.max.find(kMetricKeys[m]); it != c.tol.max.end())
        tol.max(static_cast<Metric>(m)) = it->second;
    if (!script_draws) {
      // The mask's counts of every pixel, then the pictures from a sample of at most
      // kMaxPicturePixels (report/images.h picture_size), each full image freed once sampled:
      // a 4096x4096 case's report held its three images, their nits and six full-size pictures
      // (5.4 GB with the run, issue 29).
      if (compared) {
        const ErrorMaps counts = error_counts(img[1], img[2], *enc, tol);
        c.over_pixels = counts.over;
        c.mismatch_pixels = counts.mismatch;
      }
      for (int i = 0; i < 3; ++i) {
        if (!c.has[i]) continue;
        const auto [pw, ph] = picture_size(img[i].width, img[i].height);
        if (pw == img[i].width && ph == img[i].height) continue;
        sampled[i] = sample_nearest(img[i], pw, ph);
        img[i] = Image();
        src[i] = &sampled[i];
      }
    }
    if (script_draws) {
      const auto [tw, th] = thumbnail_size(c.width, c.height, 160, 12, 40);
      for (int i = 0; i < 3; ++i)
        if (c.has[i] && (i == main || (compared && i > 0))) {
          sampled[i] = sample_nearest(img[i], tw, th);
          src[i] = &sampled[i];
        }
    }
    auto wanted = [&](int i) {
      return c.has[i] && (!script_draws || i == main || (compared && i > 0));
    };
    // Each image decoded to nits once, for its preview and the error maps; the candidate reuses
    // the reference's nits where its values are the same bits.
    Image nits[3];
    for (int i : {0, 1, 2}) {
      if (!wanted(i)) continue;
      const OutputEncoding& e = (i == 0 && input_scene_linear) ? scene : *enc;
      nits[i] =
          i == 2 && c.has[1] ? nits_image(*src[2], e, src[1], &nits[1]) : nits_image(*src[i], e);
    }
    Rgb8 prev[3];
    for (int i = 0; i < 3; ++i) {
      if (!wanted(i) || (script_draws && i != main && i != 1)) continue;
      // Outputs in their gamut, converted to the display's; the input (working colour space,
      // Rec.709 primaries by default) as it is.
      const ref::Mat3 to_display = output_to_display(*enc);
      prev[i] = preview_of_nits(*src[i], nits[i], 0,
                                i == 0 && input_scene_linear ? nullptr : &to_display);
    }
    ErrorMaps maps;
    if (compared) {
      // Script-drawn pages: the script counts the mask where it draws it; the others were
      // counted above, over every pixel.
      maps = error_maps(*src[1], *src[2], nits[1], nits[2], *enc, tol, prev[1]);
      c.heat = true;
    }
    c.thumb[0] = thumbnail(prev[main], 160, 12, 40);  // script_draws: already that size
    if (c.heat) c.thumb[1] = thumbnail(maps.heat, 160, 12, 40);
    if (!script_draws) {
      // Every picture of the case in one PNG, stacked top to bottom in this order
      // (CaseView::sprite says where), carried by the case page itself (a data: URL).
      std::vector<std::pair<std::string, const Rgb8*>> pictures;
      for (int i = 0; i < 3; ++i)
        if (c.has[i]) pictures.emplace_back(kImageNames[i], &prev[i]);
      if (c.heat) {
        pictures.emplace_back("heat", &maps.heat);
        pictures.emplace_back("heat_itp", &maps.heat_itp);
        pictures.emplace_back("mask", &maps.mask);
      }
      int sprite_w = 0, sprite_h = 0;
      for (const auto& [key, pic] : pictures) {
        c.sprite[key] = {0, sprite_h, pic->width, pic->height};
        sprite_w = std::max(sprite_w, pic->width);
        sprite_h += pic->height;
      }
      Rgb8 sprite(sprite_w, sprite_h);  // black where a narrower picture leaves room
      for (const auto& [key, pic] : pictures)
        for (int y = 0; y < pic->height; ++y)
          std::memcpy(sprite.px(0, c.sprite[key].y + y),
                      &pic->data[static_cast<size_t>(y) * pic->width * 3],
                      static_cast<size_t>(pic->width) * 3);
      c.sprite_png = png_bytes(sprite);
      if (c.sprite_png.empty())
        return Error{(out / "c" / (c.slug + ".html")).string(), "", "cannot encode the case's PNG",
                     ""};
    } else {
      // Float data for the previews, heatmaps, mask, exposure control, probe and LUT view.
      // The JSON is written out here rather than through json::dump and script_safe_json: the
      // values are megabytes of base64, whose alphabet needs no escaping in JSON or in a
      // <script> element, and the rest are numbers and fixed keys.
      std::string px = "{\"w\":" + std::to_string(c.width) + ",\"h\":" + std::to_string(c.height) +
                       ",\"packing\":\"exr: the OpenEXR file; v: float32 byte planes, deflate; "
                       "base64\",\"images\":{";
      bool first = true;
      for (int i = 0; i < 3; ++i) {
        if (!c.has[i]) continue;
        const OutputEncoding& e = (i == 0 && input_scene_linear) ? scene : *enc;
        px += std::string(first ? "" : ",") + "\"" + kImageNames[i] + "\":{";
        first = false;
        // The EXR itself when the script can decode it (report.js decodeExr): what the run
        // wrote, no repacking; else its float32 values packed.
        std::string file;
        if (img[i].width == c.width && img[i].height == c.height)
          if (auto f = read_bounded_file(path[i].string(), kMaxImageFileBytes, "case image"))
            file = std::move(*f);
        if (!file.empty() && exr_embeddable(file, c.width, c.height)) {
          px += "\"exr\":\"" +
                base64_of(reinterpret_cast<const uint8_t*>(file.data()), file.size()) + "\"";
        } else {
          double a = 0;
          const bool const_a = constant_alpha(img[i], &a);
          px += "\"ch\":" + std::to_string(const_a ? 3 : 4);
          if (const_a) px += ",\"alpha\":" + json(a).dump();
          px += ",\"v\":\"" + float32_packed_base64(img[i], const_a ? 3 : 4) + "\"";
        }
        // How the script decodes a value to nits: OutputEncoding::to_nits, as parameters.
        px += ",\"enc\":" + encoding_json(e).dump() + "}";
      }
      // In the case page, as data (CSP: no inline script runs), not a px.js beside it: one file
      // fewer per case.
      c.px = true;
      c.px_json = px + "}}";
    }
    c.meta["encoding"] = enc->describe();
    c.meta["gamut"] = enc->gamut;
    json m = json::array();
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) m.push_back(enc->to_rec2020(r, k));
    c.meta["to_rec2020"] = m;
    const ref::Mat3 disp = output_to_display(*enc);
    c.meta["to_display"] = json(disp.m);
    // VisualizeHDR's false colour (reference/ue/visualize/histogram.h): Colorize of the histogram
    // position of log2(max(mean RGB, LuminanceMin)), default eye adaptation (extended range).
    const auto eye =
        ref::visualize::compute_eye_adaptation_parameters(ref::visualize::default_settings(true));
    c.meta["false_colour"] = {{"scale", eye.histogram_scale},
                              {"bias", eye.histogram_bias},
                              {"luminance_min", eye.luminance_min}};
    c.meta["input_encoding"] = input_scene_linear ? "scene-linear x 100 nits" : enc->describe();
    if (enc->stage == StageId::kCombineLuts && c.height > 0 && c.width == c.height * c.height)
      c.lut_size = c.height;
    return {};
  }

  // One case: its images, float data and page.
  Status case_outputs(CaseView& c) {
    if (Status s = case_images(c); !s) return s;
    c.meta["id"] = c.id;
    c.meta["verdict"] = c.verdict;
    c.meta["w"] = c.width;
    c.meta["h"] = c.height;
    c.meta["has"] = {
        {"input", c.has[0]}, {"reference", c.has[1]}, {"candidate", c.has[2]}, {"heat", c.heat}};
    json tol = json::object();
    for (const auto& [k, v] : c.tol.max) tol[k] = v;
    tol["rel_floor"] = c.tol.rel_floor;
    c.meta["tol"] = tol;
    c.meta["lut_size"] = c.lut_size;
    if (const json* wp = get(*c.j, {"worst_pixel"}); wp && wp->is_object()) {
      auto x = num(get(*wp, {"x"})), y = num(get(*wp, {"y"}));
      if (x && y) c.meta["worst"] = {{"x", *x}, {"y", *y}};
    }
    c.meta["input"] = text(get(*c.j, {"input"}));
    c.meta["px"] = c.px;
    if (!c.sprite.empty()) {
      json panels = json::object();
      for (const auto& [key, r] : c.sprite) panels[key] = {r.x, r.y, r.w, r.h};
      c.meta["sprite"] = {{"panels", panels}};
    }
    Status s = put(fs::path("c") / (c.slug + ".html"), case_page(c));
    c.px_json = std::string();  // written: free it
    c.sprite_png = std::string();
    return s;
  }

  std::string case_page(const CaseView& c) {
    const json& j = *c.j;
    const std::string root = "../";
    std::string h = page_head(c.id + " — hdrconform", root, "case");
    h += "<h1 class=\"case-id\"><code id=\"case-id\">" + html_escape(c.id) + "</code></h1>\n";
    // The hints end the reason ("; possible cause: ..."): shown as a list of their own.
    std::string reason = c.reason;
    if (!c.hints.empty())
      if (const size_t at = reason.find("; " + c.hints.front()); at != std::string::npos)
        reason.resize(at);
    h += "<p class=\"verdict-line\">" + badge(c.verdict) + markers(c) + " <span id=\"reason\">" +
         html_escape(reason) + "</span></p>\n";
    if (!c.hints.empty()) {
      h += "<ul id=\"hints\" class=\"hints\">\n";
      for (const auto& hint : c.hints) h += "<li>" + html_escape(hint) + "</li>\n";
      h += "</ul>\n";
    }
    for (const auto& w : c.warnings)
      h += "<p class=\"warning\">warning: " + html_escape(w) + "</p>\n";
    if (c.budget)
      h += "<p>Budget used: <b id=\"budget\">" + fmt(*c.budget * 100.0, "%.3g") +
           " %</b> of the tolerance (the runner's figure: the largest share any limit uses).</p>\n";
    h += "<p class=\"repro\">Reproduce: <code id=\"repro-cmd\">" +
         html_escape(reproduce_command(doc, c.id)) +
         "</code> <button type=\"button\" id=\"repro-copy\">copy</button></p>\n";

    h += "<section id=\"images\"><h2>Images</h2>\n";
    if (!c.has[0] && !c.has[1] && !c.has[2]) {
      h += "<p class=\"muted\">No images were written for this case.</p>\n";
    } else {
      h += "<div class=\"toolbar\">"
           "<label>View <select id=\"view-mode\"><option value=\"side\">side by side</option>"
           "<option value=\"flip\">A/B flip</option><option value=\"slider\">slider</option>"
           "<option value=\"diff\">diff</option></select></label>"
           "<label>Display <select id=\"display-mode\"><option value=\"clip\">clip</option>"
           "<option value=\"tonemap\">tone map</option><option value=\"falsecolour\">"
           "VisualizeHDR false colour</option><option value=\"pq\">PQ signal</option>"
           "<option value=\"hdr\">HDR (PQ)</option></select></label>"
           "<label>A <select id=\"view-a\"></select></label><label>B <select id=\"view-b\">"
           "</select></label>"
           "<label>Exposure <input type=\"range\" id=\"exposure\" min=\"-12\" max=\"12\" "
           "step=\"0.5\" value=\"0\"> <output id=\"exposure-value\">0 EV</output></label>"
           "<button type=\"button\" id=\"exposure-reset\">0 EV</button>"
           "<label>Heatmap <select id=\"heat-metric\"><option value=\"pq10\">PQ 10-bit codes"
           "</option><option value=\"itp\">ΔE_ITP</option></select></label>"
           "<label>Zoom <select id=\"zoom\"><option value=\"0\">fit</option><option value=\"1\">1×"
           "</option><option value=\"2\">2×</option><option value=\"4\">4×</option><option "
           "value=\"8\">8×</option></select></label></div>\n";
      h += "<p class=\"mapping\" id=\"hdr-status\"></p>\n";
      h += "<p class=\"mapping\">SDR preview: each value decoded to nits (output: " +
           html_escape(c.meta.value("encoding", std::string("—"))) +
           "; input: " + html_escape(c.meta.value("input_encoding", std::string("—"))) +
           "), converted from the output gamut (" +
           html_escape(c.meta.value("gamut", std::string("—"))) +
           ") to the display's sRGB primaries, shown as sRGB(clamp(nits / 100 · 2<sup>EV</sup>, 0, "
           "1)) (clip): 100 nits is SDR white at 0 EV; tone map: x / (1 + x); false colour: "
           "VisualizeHDR's Colorize of the histogram position; PQ signal: ST 2084 codes as grey. "
           "NaN pixels magenta, infinite pixels cyan.</p>\n";
      h += "<div id=\"panels\" class=\"panels\">\n";
      // Each panel shows its picture of the case's PNG at 1:1 without the script (a box of the
      // picture's size over the PNG, offset); the script redraws the panels.
      // With float data the script draws every panel (an empty frame until then).
      auto panel = [&](const std::string& key, const std::string& label, bool present) {
        if (!present) return;
        h += "<figure class=\"panel\" data-key=\"" + key + "\"><figcaption>" + label +
             "</figcaption><div class=\"frame\">";
        if (const auto it = c.sprite.find(key); it != c.sprite.end()) {
          const CaseView::Rect& r = it->second;
          h += "<span class=\"sprite\" role=\"img\" aria-label=\"" + label +
               "\" style=\"width:" + css_px(r.w) + ";height:" + css_px(r.h) +
               ";background-position:" + css_px(-r.x) + " " + css_px(-r.y) + "\"></span>";
        }
        h += "</div></figure>\n";
      };
      if (c.px)
        h += "<noscript><p class=\"warning\">The pictures of this case are drawn by the page's "
             "script from its float data: they need JavaScript.</p></noscript>\n";
      // The case's PNG, once: the panels' background (shown without the script too) and what
      // the script draws its canvases from (report.js initCase). Base64 needs no escaping in CSS.
      if (!c.sprite_png.empty())
        h += "<style id=\"case-sprite\">#images .sprite { background-image: "
             "url(\"data:image/png;base64," +
             base64_of(reinterpret_cast<const uint8_t*>(c.sprite_png.data()), c.sprite_png.size()) +
             "\"); }</style>\n";
      panel("input", "input", c.has[0]);
      panel("reference", "reference", c.has[1]);
      panel("candidate", "candidate", c.has[2]);
      panel("heat", "error heatmap", c.heat);
      panel("mask", "over tolerance", c.heat);
      h += "</div>\n<div id=\"compare\" class=\"compare\" hidden></div>\n";
      if (c.heat) {
        h += "<div class=\"legend\" id=\"heat-legend\"><canvas id=\"legend-bar\" width=\"400\" "
             "height=\"14\"></canvas><div id=\"legend-ticks\" class=\"ticks\"></div><p>Heatmap: "
             "per pixel the largest error of its colour channels (<span "
             "id=\"legend-unit\">PQ 10-bit code values</span>), VisualizeHDR's Colorize ramp on a "
             "log scale; black = exact, white = non-finite mismatch; ▲ = the tolerance. Mask: "
             "<span class=\"sw over\"></span> a value over its metric's max (<span "
             "id=\"mask-over\">" +
             (c.px ? std::string("…") : std::to_string(c.over_pixels)) +
             "</span> pixels), <span class=\"sw nan\"></span> non-finite mismatch (<span "
             "id=\"mask-mismatch\">" +
             (c.px ? std::string("…") : std::to_string(c.mismatch_pixels)) +
             "</span> pixels), grey: within tolerance (dimmed reference).</p></div>\n";
      }
      h += "<div id=\"probe\" class=\"probe\"><p id=\"probe-hint\">" +
           std::string(c.px ? "Hover over an image for the pixel probe; click to pin."
                            : "The pixel probe needs the float data, not written for this case.") +
           "</p><table id=\"probe-table\" hidden><thead><tr><th id=\"probe-xy\"></th><th>R</th><th>"
           "G</th><th>B</th><th>A</th></tr></thead><tbody></tbody></table></div>\n";
      // The report links nothing outside report/ (it is uploaded alone); the EXRs are named.
      h += "<p class=\"links\">Full-precision EXRs in the run's output folder (beside report/): ";
      for (int i = 0; i < 3; ++i)
        if (c.has[i])
          h += "<code>" + html_escape(case_image_dir_of(c.id)) + "/" + kImageNames[i] +
               ".exr</code> ";
      h += "</p>\n";
    }
    if (!c.error.empty()) h += "<pre class=\"warning\">" + html_escape(c.error) + "</pre>\n";
    h += "</section>\n";

    if (c.px)
      h += "<section id=\"plots\"><h2>Plots</h2><div class=\"toolbar\"><label>ramp row <select "
           "id=\"plot-row\"></select></label></div><div id=\"plots-body\"></div></section>\n";
    if (c.lut_size > 0)
      h += "<section id=\"lut\"><h2>LUT slices</h2><p>The " + std::to_string(c.lut_size) +
           "³ LUT, one blue slice at a time (r across, g down), and the error per lattice point "
           "(heatmap scale above). Hover for the lattice point's values.</p><div class=\"toolbar\">"
           "<label>blue slice <input type=\"range\" id=\"lut-slice\" min=\"0\" max=\"" +
           std::to_string(c.lut_size - 1) +
           "\" value=\"0\"> <output id=\"lut-slice-value\">0</output></label></div>"
           "<div id=\"lut-panels\" class=\"panels\"></div><p id=\"lut-probe\" class=\"mono\"></p>"
           "<div id=\"lut-worst\"></div></section>\n";

    h += "<section id=\"worst\"><h2>Worst pixels</h2>";
    const std::string rows = pixel_rows(j, c.px);
    if (rows.empty())
      h += "<p class=\"muted\">—</p>";
    else
      h += "<table class=\"stats\" id=\"worst-pixel\"><thead><tr><th></th><th>x</th><th>y</th><th>"
           "channel</th><th>band</th><th>input</th><th>reference</th><th>candidate</th>" +
           std::string(c.px ? "<th></th>" : "") + "</tr></thead><tbody>" + rows +
           "</tbody></table>\n";
    h += "</section>\n";

    h += "<section id=\"tolerance\"><h2>Tolerance</h2>";
    const json* tj = get(j, {"tolerance"});
    std::string tol_rows, not_judged;
    if (tj && tj->is_object()) {
      for (const auto& [k, v] : tj->items()) {
        if (k == "reason" || k == "source") continue;
        // The metrics the tolerance does not judge (null) are one row, not a row of "—" each;
        // a metric's limits as "max 0.00033, allowed_fraction 0, hard —, warn —".
        if (v.is_null()) {
          not_judged += (not_judged.empty() ? "" : ", ") + html_escape(k);
          continue;
        }
        std::string limits;
        if (v.is_object())
          for (const auto& [f, x] : v.items())
            limits += (limits.empty() ? "" : ", ") + html_escape(f) + " " + esc_text(&x);
        tol_rows += "<tr><th>" + html_escape(k) + "<td class=\"mono\">" +
                    (v.is_object() ? limits : esc_text(&v));
      }
      if (!not_judged.empty()) tol_rows += "<tr><th>not judged<td>" + not_judged;
    }
    h += tol_rows.empty()
             ? "<p class=\"muted\">—</p>"
             : "<table class=\"kv\" id=\"tolerance-table\"><tbody>" + tol_rows + "</tbody></table>";
    // The reason and each overlay's (runner/tolerance.cpp apply_overlays joins them with
    // "; overlay: "): a part several cases give as its first sentence and a link to it in
    // tolerances.html, any other as it is.
    const std::string tol_reason = text(tj ? get(*tj, {"reason"}) : nullptr);
    h += "<p><b>Reason:</b> ";
    bool linked = false;
    const std::vector<std::string> parts = reason_parts(tol_reason);
    for (size_t i = 0; i < parts.size(); ++i) {
      const std::string& part = parts[i];
      if (i > 0) h += "; overlay: ";
      if (const auto it = reasons.find(part); it != reasons.end()) {
        h += html_escape(reason_lead(part)) + " <a href=\"" + root + "tolerances.html#r" +
             std::to_string(it->second.id) + "\"" + (linked ? "" : " id=\"tolerance-reason\"") +
             ">(the whole reason; " + std::to_string(it->second.cases) + " cases share it)</a>";
        linked = true;
      } else {
        h += html_escape(part);
      }
    }
    h += "</p>";
    h += "<p><b>Source:</b> <span id=\"tolerance-source\">" +
         esc_text(tj ? get(*tj, {"source"}) : nullptr) + "</span></p></section>\n";

    h += "<section id=\"stats\"><h2>Statistics</h2>";
    const json* overall = get(j, {"stats", "overall"});
    if (!overall) overall = get(j, {"metrics"});
    if (!overall) overall = get(j, {"stats"});
    std::string st = stats_table(overall, "stats-overall", "metric");
    if (const json* px = get(j, {"stats", "pixels"}))
      st = "<p>" + esc_text(px) + " pixels, " + esc_text(get(j, {"stats", "values"})) +
           " colour values finite on both sides.</p>" + st;
    h += st.empty() ? "<p class=\"muted\">—</p>" : st;
    const json* bands = get(j, {"stats", "bands"});
    if (!bands) bands = get(j, {"bands"});
    if (bands && bands->is_array()) {
      // [{band, pixels, metrics: {metric: stats}}]: one table, a row per band and metric (one
      // header for every band), then each band's pixels.
      h += "<h3>Per luminance band (the reference pixel's luminance, nits; the judged "
           "metrics)</h3>\n" +
           band_table(*bands, num(get(j, {"stats", "pixels"})));
    } else if (bands) {
      h += "<h3>Per luminance band</h3>" + stats_table(bands, "stats-bands", "band");
    }
    h += "</section>\n";

    h += "<section id=\"census\"><h2>Non-finite census</h2>";
    const json* nf = get(j, {"nonfinite"});
    if (!nf) nf = get(j, {"census"});
    if (nf && nf->is_object()) {
      json flat = json::object();
      std::vector<std::pair<std::string, const json*>> cells;
      flatten(*nf, "", &cells);
      bool none = true;  // every count 0: one line, not a table of zeros (most cases)
      for (const auto& [k, v] : cells)
        if (k.rfind("first_mismatch", 0) != 0) {
          flat[k] = *v;
          none = none && (v->is_null() || (v->is_number() && v->get<double>() == 0));
        }
      h += none ? "<p id=\"census-table\">None: no NaN, +Inf, −Inf or negative value on either "
                  "side (every count 0).</p>\n"
                : kv_table(&flat, "census-table", "—");
    } else {
      h += "<p class=\"muted\">—</p>";
    }
    h += "</section>\n";

    h += "<section id=\"params\"><h2>Parameters</h2><table class=\"kv\" id=\"case-info\"><tbody>";
    for (const char* k : {"stage", "input", "file", "verdict", "encoding"})
      h += "<tr><th>" + std::string(k) + "<td>" + esc_text(get(j, {k}));
    h += "<tr><th>output encoding<td>" + html_escape(c.meta.value("encoding", std::string("—"))) +
         ", " + html_escape(c.meta.value("gamut", std::string("—")));
    h += "<tr><th>size<td>" +
         (c.width ? std::to_string(c.width) + " × " + std::to_string(c.height) : "—") +
         "</tbody></table>\n";
    const json named = named_cvars(get(j, {"cvars"}));
    h += "<h3>Cvars</h3>" + kv_table(&named, "cvars", "none set (UE defaults)");
    h += "<h3>Settings</h3>" + kv_table(get(j, {"settings"}), "settings", "none set (UE defaults)");
    const json* resolved = get(j, {"resolved"});
    if (!resolved) resolved = get(j, {"params"});
    h += "<details><summary>Resolved parameters (what both engines received)</summary>" +
         kv_table(resolved, "resolved", "—") + "</details>";
    if (const json* rv = get(j, {"reference_values"}); rv && !rv->empty())
      h += "<h3>Named values (reference)</h3>" + kv_table(rv, "named-values", "—");
    // The device every case of a run shares (the run's candidate) is in the summary's run table,
    // once; a case page names it and links there. results.json names it per case no more
    // (runner/results.cpp case_json); older files do.
    const json* run_dev = get(doc, {"candidate"});
    const json* dev = get(j, {"device"});
    if (!dev) dev = run_dev;
    h += "<h3>Timings and device</h3>" + kv_table(get(j, {"seconds"}), "timings", "—") +
         (dev && run_dev && *dev == *run_dev
              ? "<p id=\"device\">" + esc_text(get(*dev, {"device"})) +
                    ", the run's candidate device (<a href=\"" + root +
                    "index.html#run-meta\">run</a>)</p>\n"
              : kv_table(dev, "device", "—"));
    h += "</section>\n";

    // What the page's script reads (report.js initCase): everything for the image views; the
    // id and verdict alone where the case has no images (a passing case of a run that keeps
    // failing cases' images: CI's artifact, issue 27 item 8).
    const bool images = c.has[0] || c.has[1] || c.has[2];
    const json meta = images ? c.meta : json{{"id", c.id}, {"verdict", c.verdict}};
    h += "<script type=\"application/json\" id=\"case-meta\">" + script_safe_json(meta.dump()) +
         "</script>\n";
    if (c.px) h += "<script type=\"application/json\" id=\"case-px\">" + c.px_json + "</script>\n";
    return h + page_tail(root, {});
  }

  // The run by pipeline (core/pipeline.h): each pipeline's cases and verdicts, each linked to
  // the case list filtered by its id prefix.
  std::string pipelines_section() const {
    std::map<std::string, std::map<std::string, int>> by;
    for (const auto& c : cases) ++by[c.pipeline.empty() ? "?" : c.pipeline][c.verdict];
    std::string rows;
    for (const auto& [pipeline, verdicts] : by) {
      int total = 0;
      std::string counts;
      for (const auto& [v, n] : verdicts) {
        total += n;
        counts += (counts.empty() ? "" : ", ") + std::to_string(n) + " " + html_escape(v);
      }
      const Pipeline* info = find_pipeline(pipeline);
      rows += "<tr><td><b>" + html_escape(pipeline) + "</b></td><td>" +
              html_escape(info ? std::string(info->title) : "") + "</td><td>" +
              std::to_string(total) + "</td><td>" + counts + "</td></tr>\n";
    }
    return "<h2>Pipelines</h2>\n<table id=\"pipelines\"><thead><tr><th>pipeline</th><th></th>"
           "<th>cases</th><th>verdicts</th></tr></thead><tbody>\n" +
           rows + "</tbody></table>\n";
  }

  std::string summary_page() {
    std::string h = page_head("hdrconform report", "", "summary");
    h += "<h1>hdrconform report</h1>\n";
    std::map<std::string, int> counts;
    int warned = 0, near = 0, tighten = 0;
    for (const auto& c : cases) {
      ++counts[c.verdict];
      warned += !c.warnings.empty();
      near += c.near_miss;
      tighten += c.tighten;
    }
    h += "<div class=\"counts\" id=\"counts\">";
    h += "<a class=\"count total\" href=\"cases.html\"><b id=\"count-total\">" +
         std::to_string(cases.size()) + "</b> cases</a>";
    std::vector<std::string> order = {"PASS", "FAIL", "ERROR", "SKIP", "KNOWN_LIMIT", "DEGENERATE"};
    for (const auto& [v, n] : counts)
      if (std::find(order.begin(), order.end(), v) == order.end()) order.push_back(v);
    for (const auto& v : order) {
      const int n = counts.count(v) ? counts[v] : 0;
      h += "<a class=\"count v-" + verdict_class(v) +
           "\" href=\"cases.html#verdict=" + url_path_escape(v) + "\"><b id=\"count-" +
           html_escape(case_slug(v)) + "\">" + std::to_string(n) + "</b> " + html_escape(v) +
           "</a>";
      // The failed goldens (missing, stale, regressed) fail the run as a FAIL does: their card
      // follows FAIL's and leads to the Goldens section.
      if (const json* g = get(doc, {"goldens"}); v == "FAIL" && g && g->is_object()) {
        const double gf = num(get(*g, {"failed"})).value_or(0);
        h += "<a class=\"count v-" + std::string(gf > 0 ? "fail" : "pass") +
             "\" href=\"#goldens\"><b id=\"count-GOLDEN_FAILED\">" + fmt(gf, "%.0f") +
             "</b> golden failures</a>";
      }
    }
    h += "<a class=\"count warn\" href=\"cases.html#verdict=WARN\"><b id=\"count-WARN\">" +
         std::to_string(warned) + "</b> warned</a>";
    h +=
        "<a class=\"count near\" href=\"cases.html#verdict=NEAR_MISS\"><b id=\"count-NEAR_MISS\">" +
        std::to_string(near) + "</b> near misses</a>";
    h += "<a class=\"count tighten\" href=\"cases.html#verdict=TIGHTEN\"><b id=\"count-TIGHTEN\">" +
         std::to_string(tighten) + "</b> could be tightened</a></div>\n";

    h += pipelines_section();
    h += goldens_section(doc);

    // Worst cases, grouped by the class of their failure (failure_class: the metric and the
    // kind), the class holding most failures first; in a class, the cases by budget used. Then
    // the passing cases that used most of their budget.
    const auto by_budget = [](const CaseView* a, const CaseView* b) {
      const double ba = a->budget.value_or(-1), bb = b->budget.value_or(-1);
      return ba > bb || (std::isnan(ba) && !std::isnan(bb));
    };
    std::map<std::string, std::vector<const CaseView*>> classes;
    std::vector<const CaseView*> passed;
    for (const auto& c : cases) {
      if (c.verdict == "FAIL" || c.verdict == "MISSING" || c.verdict == "ERROR")
        classes[failure_class(*c.j).label()].push_back(&c);
      else if (c.verdict == "PASS" && c.budget && *c.budget > 0)
        passed.push_back(&c);
    }
    std::vector<std::pair<std::string, std::vector<const CaseView*>>> groups(classes.begin(),
                                                                             classes.end());
    std::stable_sort(groups.begin(), groups.end(), [](const auto& a, const auto& b) {
      return a.second.size() > b.second.size();
    });
    for (auto& [label, members] : groups)
      std::stable_sort(members.begin(), members.end(), by_budget);
    std::stable_sort(passed.begin(), passed.end(), by_budget);
    constexpr size_t kPerGroup = 5;
    h += "<h2>Worst cases</h2>\n";
    if (groups.empty() && passed.empty()) {
      h += "<p class=\"muted\">No case was evaluated with an error.</p>\n";
    } else {
      h += "<p class=\"muted\">Failures by class (the metric and the kind of failure), the class "
           "with most failures first; in a class, the " +
           std::to_string(kPerGroup) +
           " that used most of their budget.</p>\n<table class=\"cases\" id=\"worst-cases\">"
           "<thead><tr><th class=\"verdict\">verdict</th><th>case and reason</th><th "
           "class=\"num budget\">budget used</th><th class=\"images\"></th></tr></thead>\n";
      auto group = [&](const std::string& label, const std::string& count,
                       const std::vector<const CaseView*>& members) {
        h += "<tbody class=\"class-group\" data-class=\"" + html_escape(label) +
             "\"><tr class=\"group\"><th colspan=\"4\"><span class=\"class-label\">" +
             html_escape(label) + "</span>: <span class=\"class-count\">" + count + "</span>" +
             (members.size() > kPerGroup
                  ? " (the " + std::to_string(kPerGroup) + " that used most of their budget)"
                  : "") +
             "</th></tr>\n";
        for (size_t k = 0; k < members.size() && k < kPerGroup; ++k) {
          const CaseView* c = members[k];
          h += "<tr class=\"case\" data-id=\"" + html_escape(c->id) + "\"><td>" +
               badge(c->verdict) + markers(*c) + "</td><td>" + case_cell(*c) +
               "</td><td class=\"num\">" +
               (c->budget ? fmt(*c->budget * 100, "%.3g") + " %" : "—") + "</td><td>" +
               (c->heat ? thumb_img(*c, 1, false) : "") + "</td></tr>\n";
        }
        h += "</tbody>\n";
      };
      for (const auto& [label, members] : groups)
        group(label, std::to_string(members.size()) + " case" + (members.size() == 1 ? "" : "s"),
              members);
      if (!passed.empty())
        group("passed, most budget used", std::to_string(passed.size()) + " cases", passed);
      h += "</table>\n";
    }
    auto list = [&](const std::string& title, const std::string& id, auto pred) {
      std::string rows;
      for (const auto& c : cases)
        if (pred(c))
          rows += "<li><a href=\"c/" + url_path_escape(c.slug) + ".html\"><code>" +
                  html_escape(c.id) + "</code></a> " +
                  (c.budget ? fmt(*c.budget * 100, "%.3g") + " %" : "") + markers(c) + "</li>\n";
      if (!rows.empty()) h += "<h2>" + title + "</h2><ul id=\"" + id + "\">" + rows + "</ul>\n";
    };
    list("Warnings", "warned", [](const CaseView& c) { return !c.warnings.empty(); });
    list("Near misses (passed, over half the budget used)", "near-misses",
         [](const CaseView& c) { return c.near_miss; });
    list("Could be tightened", "could-be-tightened", [](const CaseView& c) { return c.tighten; });
    h += "<h2>Run</h2>\n" + metadata_table(doc);
    h += "<p class=\"links\"><a href=\"matrix.html\">cvar matrix</a> · <a "
         "href=\"cases.html\">all cases</a> · <a href=\"tolerances.html\">tolerance reasons</a> · "
         "results.json and junit.xml are beside report/ in the "
         "run's output folder</p>\n";
    return h + page_tail("", {});
  }

  std::string cases_page() {
    std::string h = page_head("Cases — hdrconform", "", "cases");
    h += "<h1>Cases</h1>\n<form id=\"filters\" class=\"toolbar\" autocomplete=\"off\">"
         "<label>pipeline <select id=\"f-pipeline\"><option value=\"\">all</option></select>"
         "</label>"
         "<label>stage <select id=\"f-stage\"><option value=\"\">all</option></select></label>"
         "<label>verdict <select id=\"f-verdict\"><option value=\"\">all</option></select></label>"
         "<label>cvar <select id=\"f-cvar\"><option value=\"\">—</option></select></label>"
         "<label>= <select id=\"f-cvar-value\"><option value=\"\">any</option></select></label>"
         "<label>text <input type=\"search\" id=\"f-text\" placeholder=\"id, input, reason\">"
         "</label><label>metric column <select id=\"f-metric\"></select></label>"
         "<span id=\"shown\"></span></form>\n";
    // The table is written here in full (readable without scripts); the script filters and sorts.
    // Fixed column widths but the case's (report.css table.cases.list): the reason sits under
    // the id, so a row keeps to a few lines at any common width.
    h += "<table class=\"cases list\" id=\"case-table\"><thead><tr><th data-sort=\"verdict\" "
         "class=\"verdict\">verdict</th><th data-sort=\"id\" class=\"case\">case and reason</th>"
         "<th data-sort=\"stage\" class=\"stage\">stage</th><th data-sort=\"input\" "
         "class=\"input\">input</th><th data-sort=\"budget\" class=\"num budget\">budget "
         "used</th><th data-sort=\"metric\" class=\"num metric\" id=\"metric-head\">metric</th>"
         "<th class=\"images\">images</th></tr></thead><tbody>\n";
    for (const auto& c : cases) {
      const std::string input = text(get(*c.j, {"input"}));
      h += "<tr data-i=\"" + std::to_string(c.index) + "\"><td>" + badge(c.verdict) + markers(c) +
           "</td><td>" + case_cell(c) + "</td><td class=\"stage\" title=\"" +
           html_escape(c.pipeline) + " / " + html_escape(c.stage) + "\">" + html_escape(c.stage) +
           "</td><td class=\"input\" title=\"" + html_escape(input) + "\">" + html_escape(input) +
           "</td><td class=\"num\">" + (c.budget ? fmt(*c.budget * 100, "%.3g") + " %" : "—") +
           "</td><td class=\"num metric\">—</td><td class=\"images\">";
      if (c.has[0] || c.has[1] || c.has[2]) h += thumb_img(c, 0, true);
      if (c.heat) h += thumb_img(c, 1, true);
      h += "</td></tr>\n";
    }
    h += "</tbody></table>\n";
    return h + page_tail("", {"data.js"});
  }

  // Which tolerance reasons are shared: a reason longer than its lead (reason_lead) that more
  // than one case gives, numbered in the order of the cases.
  // A reason's parts count each (reason_parts): the tolerance's own and each overlay's.
  void share_reasons() {
    std::map<std::string, int> count;
    for (const CaseView& c : cases)
      for (const std::string& r : reason_parts(text(get(*c.j, {"tolerance", "reason"}))))
        ++count[r];
    for (const CaseView& c : cases)
      for (const std::string& r : reason_parts(text(get(*c.j, {"tolerance", "reason"}))))
        if (count[r] > 1 && reason_lead(r).size() < r.size() && !reasons.count(r))
          reasons[r] = {static_cast<int>(reasons.size()) + 1, count[r]};
  }

  std::string tolerances_page() const {
    std::vector<std::pair<int, const std::string*>> order;
    for (const auto& [r, s] : reasons) order.push_back({s.id, &r});
    std::sort(order.begin(), order.end());
    std::string h = page_head("Tolerance reasons — hdrconform", "", "tolerances");
    h += "<h1>Tolerance reasons</h1>\n<p>The reasons several cases' tolerances give, once each "
         "(each case page links to its own), a tolerance's and each overlay's apart.</p>\n";
    for (const auto& [id, r] : order)
      h += "<section id=\"r" + std::to_string(id) + "\"><h2>Reason " + std::to_string(id) + " (" +
           std::to_string(reasons.at(*r).cases) + " cases)</h2><p>" + html_escape(*r) +
           "</p></section>\n";
    return h + page_tail("", {});
  }

  std::string matrix_page() {
    std::string h = page_head("Cvar matrix — hdrconform", "", "matrix");
    h += "<h1>Cvar matrix</h1>\n<form class=\"toolbar\" id=\"matrix-form\" autocomplete=\"off\">"
         "<label>stage <select id=\"m-stage\"><option value=\"\">all</option></select></label>"
         "<label>rows <select id=\"m-rows\"></select></label>"
         "<label>columns <select id=\"m-cols\"></select></label>"
         "<label>show <select id=\"m-show\"><option value=\"verdict\">verdict</option></select>"
         "</label></form>\n<div id=\"matrix\" class=\"scroll\"></div>\n"
         "<div class=\"legend\" id=\"matrix-legend\"></div>\n"
         "<h2 id=\"cell-title\"></h2><div id=\"cell-cases\"></div>\n"
         "<noscript><p>The matrix needs JavaScript; <a href=\"cases.html\">the case list</a> "
         "does not.</p></noscript>\n";
    return h + page_tail("", {"data.js"});
  }

  // The case table the matrix and list scripts read. A case's overall statistics are one array
  // in the order of the run's "metric_keys" (each key written once, not once a case: 1.8 KB a
  // case of 5 metrics x 8 statistics, issue 27 item 8), null where the case has none; numbers
  // to the 9 significant digits the case pages show (dump_9g). report.js HDRC.data turns them
  // back into each case's `metrics` object.
  std::string data_js() {
    json list = json::array();
    std::vector<json> case_metrics;
    std::set<std::string> metric_keys;
    for (const auto& c : cases) {
      json metrics = json::object();
      std::vector<std::pair<std::string, const json*>> cells;
      // Overall statistics as "pq_code10.max", "linear_rel.p99", ... (older results: metrics.*).
      const json* base = get(*c.j, {"stats", "overall"});
      if (!base) base = get(*c.j, {"metrics"});
      json full = json::object();  // compact statistics (all 0) as the statistics they imply
      if (base && base->is_object())
        for (const auto& [k, v] : base->items()) full[k] = full_metric_stats(v);
      flatten(full, "", &cells);
      for (const auto& [k, v] : cells)
        if (auto n = num(v); n && k.find("worst") == std::string::npos)
          metrics[k] = std::isfinite(*n) ? json(*n) : json(fmt(n));
      json cv = get(*c.j, {"cvars"}) && get(*c.j, {"cvars"})->is_object() ? *get(*c.j, {"cvars"})
                                                                          : json::object();
      json st = get(*c.j, {"settings"}) && get(*c.j, {"settings"})->is_object()
                    ? *get(*c.j, {"settings"})
                    : json::object();
      for (auto& [k, v] : st.items())
        if (!v.is_number() && !v.is_string()) v = v.dump();
      list.push_back({{"i", c.index},
                      {"id", c.id},
                      {"slug", c.slug},
                      {"pipeline", c.pipeline},
                      {"stage", c.stage},
                      {"verdict", c.verdict},
                      {"warn", !c.warnings.empty()},
                      {"near", c.near_miss},
                      {"tighten", c.tighten},
                      {"budget", c.budget && std::isfinite(*c.budget) ? json(*c.budget)
                                 : c.budget                           ? json("Infinity")
                                                                      : json(nullptr)},
                      {"input", text(get(*c.j, {"input"}))},
                      {"reason", c.reason},
                      {"cvars", cv},
                      {"settings", st},
                      // The metrics the case's tolerance judges: the matrix shows a metric's
                      // value only for these (a metric of stats.overall that is not judged).
                      {"judged", judged_metrics(*c.j)},
                      {"heat", c.heat}});
      for (const auto& [k, _] : metrics.items()) metric_keys.insert(k);
      case_metrics.push_back(std::move(metrics));
    }
    const json keys(metric_keys);
    for (size_t i = 0; i < list.size(); ++i) {
      json m = json::array();
      for (const auto& k : metric_keys) {
        const auto it = case_metrics[i].find(k);
        m.push_back(it == case_metrics[i].end() ? json(nullptr) : *it);
      }
      list[i]["m"] = std::move(m);
    }
    return "HDRC.data(" + script_safe_json(dump_9g(json{{"metric_keys", keys}, {"cases", list}})) +
           ");\n";
  }
};

Result<size_t> folder_size(const fs::path& p, size_t* files) {
  size_t bytes = 0;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(p, ec); !ec && it != fs::end(it);
       it.increment(ec))
    if (it->is_regular_file(ec)) {
      bytes += it->file_size(ec);
      ++*files;
    }
  if (ec) return Error{p.string(), "", "cannot list: " + ec.message(), ""};
  return bytes;
}

}  // namespace

}  // namespace report

Result<report::ReportInfo> write_report(const std::string& results_dir, int jobs) {
  using namespace report;
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t cpu0 = std::clock();  // process CPU time, all threads (POSIX clock())
  Builder b;
  b.results_dir = results_dir;
  const fs::path results = b.results_dir / "results.json";
  {
    auto doc = read_json_file<json>(results.string(), "results file (run `hdrconform run` first)",
                                    kMaxResultsFileBytes);
    if (!doc) return doc.error();
    b.doc = std::move(*doc);
  }
  const json* cases = get(b.doc, {"cases"});
  if (!cases || !cases->is_array())
    return Error{results.string(), "/cases", "missing or not an array", ""};

  const fs::path final_dir = b.results_dir / "report";
  b.out = b.results_dir / ".report.new";
  std::error_code ec;
  fs::remove_all(b.out, ec);
  fs::create_directories(b.out / "assets", ec);
  fs::create_directories(b.out / "c", ec);
  if (ec) return Error{b.out.string(), "", "cannot create: " + ec.message(), ""};

  std::set<std::string> slugs;
  for (size_t i = 0; i < cases->size(); ++i) {
    const json& j = (*cases)[i];
    CaseView c;
    c.j = &j;
    c.index = i;
    c.id = text(get(j, {"id"}));
    c.stage = text(get(j, {"stage"}));
    // results.json written before pipelines has no "pipeline": its stage names it.
    c.pipeline = text(get(j, {"pipeline"}));
    if (const StageInfo* info = find_stage(c.stage); c.pipeline.empty() && info)
      c.pipeline = std::string(info->pipeline);
    c.verdict = text(get(j, {"verdict"}));
    c.reason = get(j, {"reason"}) ? text(get(j, {"reason"})) : "";
    c.warnings = warnings_of(j);
    c.hints = hints_of(j);
    c.tighten = truthy(get(j, {"could_be_tightened"}));
    c.tol = tolerance_of(j);
    c.budget = budget_used(j);
    const json* nm = get(j, {"near_miss"});
    c.near_miss = nm ? truthy(nm)
                     : c.verdict == "PASS" && c.budget && *c.budget > kNearMiss && *c.budget <= 1;
    std::string slug = case_slug(c.id);
    for (int n = 2; !slugs.insert(slug).second; ++n)
      slug = case_slug(c.id) + "-" + std::to_string(n);
    c.slug = slug;
    b.cases.push_back(std::move(c));
  }
  b.share_reasons();
  // The cases' images and pages, on `jobs` threads (each case writes only its own files and
  // fields); the list pages after, from every case in order.
  const size_t n = b.cases.size();
  const size_t threads = std::clamp<size_t>(
      jobs > 0 ? static_cast<size_t>(jobs) : std::max(1u, std::thread::hardware_concurrency()), 1,
      std::max<size_t>(1, n));
  std::vector<Status> done(n);
  std::atomic<size_t> next{0};
  std::atomic<bool> failed{false};
  auto work = [&] {
    for (size_t i; !failed && (i = next++) < n;)
      if (!(done[i] = b.case_outputs(b.cases[i]))) failed = true;
  };
  std::vector<std::thread> pool;
  for (size_t t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  for (const Status& s : done)
    if (!s) return s.error();
  // The thumbnail atlases: the cases' thumbnails in order, stacked, 64 cases an atlas (a list
  // page loads only the atlases of the rows it shows: <img loading="lazy">).
  {
    constexpr size_t kCasesPerAtlas = 64;
    std::vector<CaseView*> with;
    for (auto& c : b.cases)
      if (c.thumb[0].width > 0 || c.thumb[1].width > 0) with.push_back(&c);
    if (!with.empty()) fs::create_directories(b.out / "t", ec);
    for (size_t first = 0, atlas = 0; first < with.size(); first += kCasesPerAtlas, ++atlas) {
      const size_t last = std::min(with.size(), first + kCasesPerAtlas);
      int w = 1, h = 0;
      for (size_t i = first; i < last; ++i)
        for (const Rgb8& t : with[i]->thumb) {
          w = std::max(w, t.width);
          h += t.height;
        }
      Rgb8 sheet(w, std::max(h, 1));
      int y = 0;
      for (size_t i = first; i < last; ++i) {
        CaseView& c = *with[i];
        c.thumb_atlas = static_cast<int>(atlas);
        for (int k = 0; k < 2; ++k) {
          const Rgb8& t = c.thumb[k];
          c.thumb_y[k] = y;
          for (int row = 0; row < t.height; ++row, ++y)
            std::memcpy(sheet.px(0, y), &t.data[static_cast<size_t>(row) * t.width * 3],
                        static_cast<size_t>(t.width) * 3);
        }
      }
      if (Status s = b.put_png(fs::path("t") / (std::to_string(atlas) + ".png"), sheet); !s)
        return s.error();
    }
  }
  for (const Asset& a : assets())
    if (Status s = b.put(fs::path("assets") / std::string(a.name), std::string(a.contents)); !s)
      return s.error();
  for (const auto& [name, page] :
       {std::pair<const char*, std::string>{"index.html", b.summary_page()},
        {"cases.html", b.cases_page()},
        {"matrix.html", b.matrix_page()},
        {"tolerances.html", b.tolerances_page()},
        {"data.js", b.data_js()}})
    if (Status s = b.put(name, page); !s) return s.error();

  // Swap the new folder in.
  const fs::path old = b.results_dir / ".report.old";
  fs::remove_all(old, ec);
  if (fs::exists(final_dir)) fs::rename(final_dir, old, ec);
  if (ec) return Error{final_dir.string(), "", "cannot replace: " + ec.message(), ""};
  fs::rename(b.out, final_dir, ec);
  if (ec)
    return Error{final_dir.string(), "", "cannot move the new report in: " + ec.message(), ""};
  fs::remove_all(old, ec);

  ReportInfo info;
  info.index_path = (final_dir / "index.html").string();
  info.cases = b.cases.size();
  auto bytes = folder_size(final_dir, &info.files);
  if (!bytes) return bytes.error();
  info.bytes = *bytes;
  info.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  info.cpu_seconds = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
  return info;
}

}  // namespace hdrc
