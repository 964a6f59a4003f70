#include "runner/merge.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "core/atomic_file.h"
#include "core/utf8.h"
#include "report/html_report.h"
#include "runner/output_set.h"
#include "runner/results.h"
#include "runner/run.h"
#include "runner/verify.h"

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

// A shard's image into the merged run: a hard link (or a copy) of a regular file inside the
// shard's run folder. A symlink or special file there (a FIFO, /dev/zero) is refused: a link
// would carry it into OUT, a copy would block or never end.
Status link_or_copy(const fs::path& from, const fs::path& to, const std::string& results,
                    const std::string& pointer) {
  std::error_code ec;
  const auto st = fs::symlink_status(from, ec);
  if (!fs::is_regular_file(st))
    return Error{results, pointer,
                 "names " + valid_utf8(from.string()) +
                     (fs::exists(st) ? ", which is not a regular file" : ", which does not exist"),
                 "the shard's own case images, as run --shard wrote them"};
  fs::create_directories(to.parent_path(), ec);
  fs::create_hard_link(from, to, ec);
  if (!ec) return {};
  ec.clear();
  fs::copy_file(from, to, fs::copy_options::overwrite_existing, ec);
  if (ec)
    return Error{valid_utf8(from.string()), "",
                 "cannot copy to " + valid_utf8(to.string()) + ": " + ec.message(), ""};
  return {};
}

int refuse(const std::string& msg) {
  std::fprintf(stderr, "error: merge: %s\n", msg.c_str());
  return kExitBadInput;
}

Error refusal(std::string msg) {
  return Error{"", "", std::move(msg), ""};
}

}  // namespace

bool safe_image_path(const std::string& rel) {
  if (rel.empty() || rel[0] == '/' || rel.find('\0') != std::string::npos) return false;
  for (const auto& part : fs::path(rel))
    if (part.empty() || part == ".." || part == ".") return false;
  return true;
}

std::vector<std::string> shard_input_folders(const json& doc) {
  const std::string line = field(doc, "/provenance/command_line");
  const std::string cwd = field(doc, "/provenance/cwd");
  if (line == "(absent)") return {};
  // The words of the command line as provenance.command_line writes them (shell_quote: bare words,
  // '...' with '\'' for a quote), split as verify splits a command template; a line that does not
  // split names no folder.
  auto split = split_command_template(line);
  if (!split) return {};
  const std::vector<std::string> words = std::move(*split);
  std::vector<std::string> out;
  for (size_t i = 0; i < words.size(); ++i)
    for (const std::string opt : {"--cases", "--goldens"}) {
      std::string value;
      if (words[i] == opt && i + 1 < words.size())
        value = words[i + 1];
      else if (words[i].rfind(opt + "=", 0) == 0)
        value = words[i].substr(opt.size() + 1);
      if (value.empty()) continue;
      const fs::path p(value);
      out.push_back(p.is_absolute() || cwd == "(absent)" ? value : (fs::path(cwd) / p).string());
    }
  return out;
}

Result<MergedRun> merge_results(const std::vector<json>& docs,
                                const std::vector<std::string>& shard_dirs) {
  if (docs.empty() || docs.size() != shard_dirs.size())
    return refusal("no shard directories given");
  // One run: the same suite, build, engine and plan everywhere.
  for (size_t i = 1; i < docs.size(); ++i)
    for (const Same& s : kSame)
      if (field(docs[i], s.pointer) != field(docs[0], s.pointer))
        return refusal("the shards differ in " + std::string(s.what) + ": " + shard_dirs[0] +
                       "/results.json " + s.pointer + " = " + field(docs[0], s.pointer) + ", " +
                       shard_dirs[i] + "/results.json = " + field(docs[i], s.pointer) +
                       "; merge only the shards of one run (one suite, one build)");
  // Every K of one N, once.
  int n = 0;
  std::map<int, std::string> ks;
  for (size_t i = 0; i < docs.size(); ++i) {
    if (!docs[i].is_object() || !docs[i].contains("cases") || !docs[i]["cases"].is_array())
      return refusal(shard_dirs[i] +
                     "/results.json: /cases: absent or not an array; merge takes "
                     "the outputs of run --shard K/N");
    const std::string shard = docs[i].value("shard", json()).is_string()
                                  ? docs[i]["shard"].get<std::string>()
                                  : std::string();
    auto sh = parse_shard(shard);
    if (!sh)
      return refusal(shard_dirs[i] + "/results.json: /shard: '" + shard +
                     "' is not K/N; merge takes the outputs of run --shard K/N");
    if (n && sh->n != n)
      return refusal(shard_dirs[i] + " is shard " + shard + ", " + shard_dirs[0] +
                     " of N = " + std::to_string(n) + "; every shard must have the same N");
    n = sh->n;
    if (ks.count(sh->k))
      return refusal("shard " + shard + " given twice: " + ks[sh->k] + " and " + shard_dirs[i]);
    ks[sh->k] = shard_dirs[i];
  }
  std::string missing;
  for (int k = 1; k <= n; ++k)
    if (!ks.count(k))
      missing += (missing.empty() ? "" : ", ") + std::to_string(k) + "/" + std::to_string(n);
  if (!missing.empty())
    return refusal("shard(s) " + missing + " missing; give every shard of the run");

  // Cases: disjoint, together the suite; in id order (the order of an unsharded run).
  MergedRun m;
  m.n = n;
  std::vector<std::pair<json, size_t>> cases;  // (case, shard index)
  std::map<std::string, size_t> seen;
  for (size_t i = 0; i < docs.size(); ++i)
    for (const auto& c : docs[i]["cases"]) {
      const std::string id = c.is_object() ? c.value("id", std::string()) : std::string();
      if (auto it = seen.find(id); it != seen.end())
        return refusal("case " + id + " is in two shards: " + shard_dirs[it->second] + " and " +
                       shard_dirs[i]);
      seen[id] = i;
      cases.push_back({c, i});
    }
  const json::json_pointer suite_cases("/provenance/suite_cases");
  if (docs[0].contains(suite_cases) && docs[0].at(suite_cases).is_number_unsigned() &&
      docs[0].at(suite_cases).get<size_t>() != cases.size())
    return refusal("the shards hold " + std::to_string(cases.size()) + " cases, the suite " +
                   docs[0].at(suite_cases).dump() + "; give every shard of the run");
  std::stable_sort(cases.begin(), cases.end(), [](const auto& a, const auto& b) {
    return a.first.value("id", std::string()) < b.first.value("id", std::string());
  });

  json doc = docs[0];
  doc["cases"] = json::array();
  for (auto& [c, i] : cases) {
    doc["cases"].push_back(std::move(c));
    m.shard_of.push_back(i);
  }
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
  m.exit_code = exit_code_of(doc);
  doc["summary"]["exit_code"] = m.exit_code;
  m.doc = std::move(doc);
  return m;
}

int merge_runs(const std::string& out_dir, const std::vector<std::string>& shard_dirs,
               const std::vector<std::string>& protected_dirs) {
  if (shard_dirs.empty()) return refuse("no shard directories given");
  // Each shard's output folder holds its published run as plain files (runner/output_set.h).
  std::vector<std::string> runs;
  std::vector<json> docs;
  std::vector<std::string> watched = protected_dirs;
  for (const auto& d : shard_dirs) {
    runs.push_back(d);
    auto doc = read_given_results_json(d + "/results.json");  // schema-checked: typed below
    if (!doc) return refuse(doc.error().to_string());
    for (const std::string& f : shard_input_folders(*doc)) watched.push_back(f);
    docs.push_back(std::move(*doc));
    watched.push_back(d);
  }
  // OUT as run's --out (runner/output_set.h): not a shard, nor the folders the shards ran on, nor
  // the default cases and goldens folders, nor inside or around one. Checked before the shards'
  // contents, so that a shard that is OUT (a symlink to it) is named as such.
  if (Status st = validate_output_dir(out_dir, "OUT", watched); !st)
    return refuse(st.error().to_string());
  auto merged = merge_results(docs, shard_dirs);
  if (!merged) return refuse(merged.error().to_string());
  json& doc = merged->doc;

  // Locked, written into a staging folder of its own and published as a whole, as run's --out;
  // the protected folders are hashed now and again before publishing, as run's cases and goldens.
  auto set = OutputSet::open(out_dir, watched, "OUT");
  if (!set) return refuse(set.error().to_string());
  const std::string staging = (*set)->staging();
  // Images: hard links (or copies) of the shards' files, at the same relative paths.
  const json& cases = doc["cases"];
  for (size_t ci = 0; ci < cases.size(); ++ci) {
    const json& c = cases[ci];
    auto im = c.find("images");
    if (im == c.end() || !im->is_object()) continue;
    const size_t s = merged->shard_of[ci];
    for (auto it = im->begin(); it != im->end(); ++it) {
      if (!it->is_string()) continue;
      const std::string rel = it->get<std::string>();
      const std::string results = shard_dirs[s] + "/results.json";
      // The pointer as the shard's results.json has it (the case's index there).
      std::string pointer = "/cases/?/images/" + it.key();
      for (size_t k = 0; k < docs[s]["cases"].size(); ++k)
        if (docs[s]["cases"][k].value("id", std::string()) == c.value("id", std::string()))
          pointer = "/cases/" + std::to_string(k) + "/images/" + it.key();
      if (!safe_image_path(rel))
        return refuse(Error{results, pointer,
                            "'" + valid_utf8(rel) + "' is not a path inside the run folder",
                            "cases/<case id>/<name>.exr"}
                          .to_string());
      if (Status st =
              link_or_copy(fs::path(runs[s]) / rel, fs::path(staging) / rel, results, pointer);
          !st)
        return refuse(st.error().to_string());
    }
  }

  Status st = write_file_atomic(staging + "/results.json", doc.dump() + "\n");
  if (st) st = write_file_atomic(staging + "/junit.xml", junit_from_results(doc));
  if (!st) return refuse(st.error().to_string());
  auto report = write_report(staging);
  if (!report) return refuse(report.error().to_string());
  const int code = publish_run(set->get(), merged->exit_code);  // run's own publication
  if (!(*set)->published()) return code;                        // the reason is printed
  std::error_code ec;
  std::printf("merged %zu shards (%d/%d .. %d/%d): %zu cases, exit code %d\n%s\nreport: %s\n",
              docs.size(), 1, merged->n, merged->n, merged->n, cases.size(), code,
              headline_of(doc).c_str(),
              fs::absolute(fs::path(out_dir) / "report/index.html", ec).lexically_normal().c_str());
  return code;
}

}  // namespace hdrc
