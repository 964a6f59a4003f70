#include "runner/selection.h"

#include <algorithm>
#include <map>

#include "core/nearest.h"
#include "core/pipeline.h"
#include "runner/case_loader.h"
#include "runner/results.h"

namespace hdrc {

namespace {

bool is_glob(const std::string& p) {
  return p.find_first_of("*?[") != std::string::npos;
}

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

}  // namespace

std::vector<std::string> split_filter(const std::string& text) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : text + "\n") {
    if (c == '\n' || c == ',') {
      if (std::string t = trim(cur); !t.empty()) out.push_back(t);
      cur.clear();
    } else {
      cur += c;
    }
  }
  return out;
}

namespace {

// One pattern (without its '!'): =ID, a glob over the whole id (fnmatch's semantics in linear
// time, runner/case_loader.h), or a substring.
bool pattern_matches(const std::string& p, const std::string& id) {
  if (p[0] == '=') return id == p.substr(1);
  return is_glob(p) ? matches_filter(id, p) : id.find(p) != std::string::npos;
}

}  // namespace

bool CaseSelection::matches(const std::string& id) const {
  if (rerun_ids && !rerun_ids->count(id)) return false;
  // As gtest's --gtest_filter=POS-NEG and pytest's -k 'a and not b': an id is selected when an
  // inclusion pattern matches it (or there is none) and no exclusion pattern ('!...') does.
  bool any_inclusion = false, included = false;
  for (const auto& p : patterns) {
    if (p[0] == '!') {
      if (pattern_matches(p.substr(1), id)) return false;
      continue;
    }
    any_inclusion = true;
    included = included || pattern_matches(p, id);
  }
  return included || !any_inclusion;
}

bool CaseSelection::matches(const Case& c) const {
  if (!pipelines.empty() && (!c.stage || std::find(pipelines.begin(), pipelines.end(),
                                                   c.stage->pipeline) == pipelines.end()))
    return false;
  return matches(c.id);
}

std::string CaseSelection::describe() const {
  std::string s;
  if (!patterns.empty()) {
    std::string joined;
    for (const auto& p : patterns) joined += (joined.empty() ? "" : ",") + p;
    s = "--filter '" + joined + "'";
  }
  if (!pipelines.empty()) {
    std::string joined;
    // Appended piece by piece: GCC 12 -O3 -Wrestrict false positive (bug 105329).
    for (const auto& p : pipelines) {
      if (!joined.empty()) joined += ',';
      joined += p;
    }
    if (!s.empty()) s += ' ';
    s += "--pipeline ";
    s += joined;
  }
  if (!rerun_dir.empty()) s += (s.empty() ? "" : " ") + std::string("--rerun-failed ") + rerun_dir;
  return s.empty() ? "(every case)" : s;
}

Result<std::set<std::string>> failed_case_ids(const std::string& results_dir) {
  // Checked against runner/results.schema.json: a field of another type is an error naming it.
  auto doc = read_given_results_json(results_dir + "/results.json");
  if (!doc) return doc.error();
  std::set<std::string> ids;
  for (const auto& c : (*doc)["cases"]) {
    if (!c.is_object() || !c.contains("id") || !c["id"].is_string()) continue;
    const std::string v = c.value("verdict", std::string());
    if (v == "FAIL" || v == "ERROR" || v == "MISSING") ids.insert(c["id"].get<std::string>());
  }
  if (doc->contains("goldens") && (*doc)["goldens"].is_object() &&
      (*doc)["goldens"].contains("cases") && (*doc)["goldens"]["cases"].is_array())
    for (const auto& g : (*doc)["goldens"]["cases"])
      if (g.is_object() && g.value("outcome", std::string("match")) != "match" &&
          g.contains("id") && g["id"].is_string())
        ids.insert(g["id"].get<std::string>());
  return ids;
}

Result<CaseSelection> make_selection(const std::string& filter_text, const std::string& rerun_dir,
                                     const std::string& pipeline_text) {
  CaseSelection sel;
  sel.patterns = split_filter(filter_text);
  for (const std::string& p : sel.patterns)
    if (p == "!" || p == "=" || p == "!=")
      return Error{"--filter", "", "the pattern '" + p + "' names no case",
                   "PATTERN (a glob with * ? [, =ID, or a substring), or !PATTERN to exclude"};
  sel.rerun_dir = rerun_dir;
  for (const std::string& name : split_filter(pipeline_text)) {
    if (!find_pipeline(name))
      return Error{"--pipeline", "", "unknown pipeline '" + name + "'", pipeline_names()};
    sel.pipelines.push_back(name);
  }
  if (!rerun_dir.empty()) {
    auto ids = failed_case_ids(rerun_dir);
    if (!ids) return ids.error();
    sel.rerun_ids = std::move(*ids);
  }
  return sel;
}

std::string no_match_message(const CaseSelection& sel, const std::vector<Case>& all,
                             const std::string& cases_dir) {
  std::string msg = "no case matches " + sel.describe() + " in " + cases_dir;
  if (sel.rerun_ids && sel.rerun_ids->empty())
    return msg + " (" + sel.rerun_dir + "/results.json lists no failed case)";
  // Did you mean: the closest ids and '/'-separated components of ids, per pattern.
  std::set<std::string> parts;
  std::vector<std::string> ids;
  for (const auto& c : all) {
    ids.push_back(c.id);
    size_t start = 0;
    for (size_t i = 0; i <= c.id.size() && parts.size() < 20000; ++i)
      if (i == c.id.size() || c.id[i] == '/' || c.id[i] == '_') {
        if (i > start) parts.insert(c.id.substr(start, i - start));
        start = i + 1;
      }
  }
  const std::vector<std::string> part_list(parts.begin(), parts.end());
  std::string hints;
  for (const auto& p : sel.patterns) {
    if (is_glob(p) || p[0] == '=' || p[0] == '!') continue;
    for (const auto& n : nearest_names(p, part_list, 3))
      if (edit_distance(p, n) <= std::max<size_t>(2, p.size() / 3))
        hints += (hints.empty() ? "" : ", ") + n;
  }
  if (!hints.empty()) msg += "; did you mean " + hints + "?";
  msg +=
      "\nhint: a pattern with * ? [ matches the whole id (e.g. 'tonemap/*'), =ID exactly one "
      "id, any other is a substring (e.g. lut); several patterns (--filter a,b or --filter a "
      "--filter b) select "
      "the cases any of them matches, less those a !PATTERN matches; `hdrconform list` prints "
      "every id";
  return msg;
}

std::string closest_command(const std::string& typed, const std::vector<std::string>& commands) {
  if (typed.empty() || typed[0] == '-') return "";
  for (const auto& c : commands)
    if (c.size() > typed.size() && c.compare(0, typed.size(), typed) == 0 && typed.size() >= 2)
      return c;
  const auto near = nearest_names(typed, commands, 1);
  if (near.empty() || edit_distance(typed, near[0]) > 3 ||
      edit_distance(typed, near[0]) >= std::max(typed.size(), near[0].size()))
    return "";
  return near[0];
}

}  // namespace hdrc
