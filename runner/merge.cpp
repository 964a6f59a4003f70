#include "runner/merge.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "core/atomic_file.h"
#include "report/html_report.h"
#include "runner/output_set.h"
#include "runner/results.h"

namespace hdrc {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace {

std::string field(const json& doc, const std::string& pointer) {
  const json::json_pointer p(pointer);
  if (!doc.contains(p)) return "(absent)";
  const json& v = doc.at(p);
  return v.is_string() ? v.get<std::string>() : v.dump();
}

// Fields every shard of one run shares, with what a difference means.
struct Same {
  const char* pointer;
  const char* what;
};
constexpr Same kSame[] = {
    {"/tool", "tool"},
    {"/schema_version", "results.json schema version"},
    {"/command", "command (run or verify)"},
    {"/provenance/suite_fingerprint", "suite (the selected cases and their definitions)"},
    {"/provenance/suite_cases", "suite size"},
    {"/provenance/commit", "build: source commit"},
    {"/provenance/build_type", "build: build type"},
    {"/provenance/compiler", "build: compiler"},
    {"/provenance/tool_version", "build: tool version"},
    {"/provenance/shader_hash", "build: shader directory content"},
    {"/provenance/shard_plan", "shard plan (the timings --shard balanced with)"},
    {"/candidate/engine", "candidate engine"},
    {"/candidate/device", "candidate device"},
    {"/reference/device", "reference engine"},
};

Status link_or_copy(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  fs::create_directories(to.parent_path(), ec);
  fs::remove(to, ec);
  fs::create_hard_link(from, to, ec);
  if (!ec) return {};
  ec.clear();
  fs::copy_file(from, to, fs::copy_options::overwrite_existing, ec);
  if (ec)
    return Error{from.string(), "", "cannot copy to " + to.string() + ": " + ec.message(), ""};
  return {};
}

int refuse(const std::string& msg) {
  std::fprintf(stderr, "error: merge: %s\n", msg.c_str());
  return kExitBadInput;
}

}  // namespace

int merge_runs(const std::string& out_dir, const std::vector<std::string>& shard_dirs) {
  if (shard_dirs.empty()) return refuse("no shard directories given");
  std::error_code ec;
  std::vector<json> docs;
  for (const auto& d : shard_dirs) {
    if (fs::exists(out_dir) && fs::equivalent(out_dir, d, ec))
      return refuse("OUT " + out_dir + " is also a shard directory; merge into a new directory");
    auto doc = read_given_results_json(d + "/results.json");  // schema-checked: typed below
    if (!doc) return refuse(doc.error().to_string());
    docs.push_back(std::move(*doc));
  }
  // One run: the same suite, build, engine and plan everywhere.
  for (size_t i = 1; i < docs.size(); ++i)
    for (const Same& s : kSame)
      if (field(docs[i], s.pointer) != field(docs[0], s.pointer))
        return refuse("the shards differ in " + std::string(s.what) + ": " + shard_dirs[0] +
                      "/results.json " + s.pointer + " = " + field(docs[0], s.pointer) + ", " +
                      shard_dirs[i] + "/results.json = " + field(docs[i], s.pointer) +
                      "; merge only the shards of one run (one suite, one build)");
  // Every K of one N, once.
  int n = 0;
  std::map<int, std::string> ks;
  for (size_t i = 0; i < docs.size(); ++i) {
    const std::string shard = docs[i].value("shard", json()).is_string()
                                  ? docs[i]["shard"].get<std::string>()
                                  : std::string();
    auto sh = parse_shard(shard);
    if (!sh)
      return refuse(shard_dirs[i] + "/results.json: /shard: '" + shard +
                    "' is not K/N; merge takes the outputs of run --shard K/N");
    if (n && sh->n != n)
      return refuse(shard_dirs[i] + " is shard " + shard + ", " + shard_dirs[0] +
                    " of N = " + std::to_string(n) + "; every shard must have the same N");
    n = sh->n;
    if (ks.count(sh->k))
      return refuse("shard " + shard + " given twice: " + ks[sh->k] + " and " + shard_dirs[i]);
    ks[sh->k] = shard_dirs[i];
  }
  std::string missing;
  for (int k = 1; k <= n; ++k)
    if (!ks.count(k))
      missing += (missing.empty() ? "" : ", ") + std::to_string(k) + "/" + std::to_string(n);
  if (!missing.empty())
    return refuse("shard(s) " + missing + " missing; give every shard of the run");

  // Cases: disjoint, together the suite; in id order (the order of an unsharded run).
  std::vector<std::pair<std::string, size_t>> where;  // id → shard index
  std::vector<json> cases;
  std::map<std::string, size_t> seen;
  for (size_t i = 0; i < docs.size(); ++i)
    for (auto& c : docs[i]["cases"]) {
      const std::string id = c.value("id", std::string());
      if (auto it = seen.find(id); it != seen.end())
        return refuse("case " + id + " is in two shards: " + shard_dirs[it->second] + " and " +
                      shard_dirs[i]);
      seen[id] = i;
      cases.push_back(c);
    }
  const json::json_pointer suite_cases("/provenance/suite_cases");
  if (docs[0].contains(suite_cases) && docs[0].at(suite_cases).is_number_unsigned() &&
      docs[0].at(suite_cases).get<size_t>() != cases.size())
    return refuse("the shards hold " + std::to_string(cases.size()) + " cases, the suite " +
                  docs[0].at(suite_cases).dump() + "; give every shard of the run");
  std::stable_sort(cases.begin(), cases.end(), [](const json& a, const json& b) {
    return a.value("id", std::string()) < b.value("id", std::string());
  });

  // Written like a run (runner/output_set.h): into a staging folder, swapped in whole.
  auto set = OutputSet::open(out_dir, {}, "OUT");
  if (!set) return refuse(set.error().to_string());
  const std::string staging = (*set)->staging();
  // Images: hard links (or copies) of the shards' files, at the same relative paths.
  for (const auto& c : cases) {
    auto im = c.find("images");
    if (im == c.end() || !im->is_object()) continue;
    const std::string& src = shard_dirs[seen[c.value("id", std::string())]];
    for (auto it = im->begin(); it != im->end(); ++it) {
      if (!it->is_string()) continue;
      const std::string rel = it->get<std::string>();
      if (rel.find("..") != std::string::npos || rel.empty() || rel[0] == '/') continue;
      if (Status s = link_or_copy(fs::path(src) / rel, fs::path(staging) / rel); !s)
        return refuse(s.error().to_string());
    }
  }

  json doc = docs[0];
  doc["cases"] = cases;
  doc["shard"] = nullptr;
  json from = json::array();
  double wall = 0;
  std::string started = doc.value("started_utc", std::string());
  bool interrupted = false;
  for (size_t i = 0; i < docs.size(); ++i) {
    const double w = docs[i].value("wall_seconds", 0.0);
    wall = std::max(wall, w);
    const std::string s = docs[i].value("started_utc", std::string());
    if (!s.empty() && (started.empty() || s < started)) started = s;
    interrupted = interrupted || docs[i].value("interrupted", false);
    from.push_back({{"dir", shard_dirs[i]},
                    {"shard", docs[i]["shard"]},
                    {"wall_seconds", w},
                    {"jobs", docs[i].value("jobs", 0)},
                    {"cases", docs[i]["cases"].size()},
                    {"command_line", field(docs[i], "/provenance/command_line")}});
    if (doc.value("candidate_unavailable", std::string()).empty())
      doc["candidate_unavailable"] = docs[i].value("candidate_unavailable", std::string());
  }
  doc["started_utc"] = started;
  doc["wall_seconds"] = wall;  // the shards ran side by side
  doc["interrupted"] = interrupted;
  doc["merged_from"] = from;
  // JUnit's hostname: the shards' hosts, each once.
  std::vector<std::string> hosts;
  for (const auto& d : docs) {
    const std::string h = field(d, "/provenance/hostname");
    if (h != "(absent)" && std::find(hosts.begin(), hosts.end(), h) == hosts.end())
      hosts.push_back(h);
  }
  std::string host_list;
  for (const auto& h : hosts) host_list += (host_list.empty() ? "" : ",") + h;
  if (doc.contains("provenance") && doc["provenance"].is_object())
    doc["provenance"]["hostname"] = host_list;
  // Counts: every integer of the shards' summaries adds up (exit_code is recomputed).
  json summary = json::object();
  for (const auto& d : docs)
    if (d.contains("summary") && d["summary"].is_object())
      for (auto it = d["summary"].begin(); it != d["summary"].end(); ++it)
        if (it.key() != "exit_code" && it->is_number_integer())
          summary[it.key()] = summary.value(it.key(), 0) + it->get<long long>();
  // Goldens: counts summed, entries joined in id order.
  bool any_goldens = false;
  json goldens = json::object();
  json gcases = json::array();
  for (const auto& d : docs) {
    if (!d.contains("goldens") || !d["goldens"].is_object()) continue;
    const json& g = d["goldens"];
    if (!any_goldens)
      goldens = g;
    else {
      for (const char* k : {"checked", "match", "missing", "stale", "regression", "failed"})
        goldens[k] = goldens.value(k, 0) + g.value(k, 0);
      goldens["seconds"] = std::max(goldens.value("seconds", 0.0), g.value("seconds", 0.0));
    }
    any_goldens = true;
    if (g.contains("cases") && g["cases"].is_array())
      for (const auto& e : g["cases"]) gcases.push_back(e);
  }
  if (any_goldens) {
    std::stable_sort(gcases.begin(), gcases.end(), [](const json& a, const json& b) {
      return a.value("id", std::string()) < b.value("id", std::string());
    });
    goldens["cases"] = gcases;
    doc["goldens"] = goldens;
  }
  doc["summary"] = summary;
  const int code = exit_code_of(doc);
  doc["summary"]["exit_code"] = code;

  Status st = write_file_atomic(staging + "/results.json", doc.dump() + "\n");
  if (st) st = write_file_atomic(staging + "/junit.xml", junit_from_results(doc));
  if (!st) return refuse(st.error().to_string());
  auto report = write_report(staging);
  if (!report) return refuse(report.error().to_string());
  if (Status p = (*set)->publish(); !p) {
    std::fprintf(stderr, "error: merge: %s\n", p.error().to_string().c_str());
    return kExitFail;
  }
  std::printf("merged %zu shards (%d/%d .. %d/%d): %zu cases, exit code %d\n%s\nreport: %s\n",
              docs.size(), 1, n, n, n, cases.size(), code, headline_of(doc).c_str(),
              (fs::absolute(out_dir, ec).lexically_normal() / "report/index.html").c_str());
  return code;
}

}  // namespace hdrc
