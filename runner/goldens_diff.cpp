#include "runner/goldens_diff.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <map>
#include <set>

#include "core/atomic_file.h"
#include "core/output_encoding.h"
#include "core/pipeline.h"
#include "core/utf8.h"
#include "report/html_report.h"
#include "runner/case_loader.h"
#include "runner/goldens.h"
#include "runner/json_read.h"
#include "runner/results.h"
#include "runner/run.h"
#include "runner/verify.h"

namespace hdrc {

namespace fs = std::filesystem;

bool same_pixels(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height || a.data.size() != b.data.size()) return false;
  for (size_t i = 0; i < a.data.size(); ++i) {
    const float x = static_cast<float>(a.data[i]), y = static_cast<float>(b.data[i]);
    if (std::memcmp(&x, &y, sizeof x) != 0) return false;
  }
  return true;
}

GoldenMove golden_move(const Case& c, const ResolvedCase& resolved, const Image& before,
                       const Image& now, DiffStats* stats) {
  GoldenMove m;
  if (before.width != now.width || before.height != now.height ||
      before.data.size() != now.data.size()) {
    m.resized = true;
    return m;
  }
  for (size_t i = 0; i < before.data.size(); ++i) {
    const float x = static_cast<float>(before.data[i]), y = static_cast<float>(now.data[i]);
    if (std::memcmp(&x, &y, sizeof x) != 0) ++m.values_changed;
  }
  // The metrics of run and verify (runner/diff.h), the old golden as the reference; both as the
  // golden stores them, float32 (the reference's own output is double until written).
  auto as_float = [](const Image& img) {
    Image f = img;
    for (double& v : f.data) v = static_cast<float>(v);
    return f;
  };
  const OutputEncoding enc = output_encoding(*c.stage, resolved.params);
  const DiffStats s =
      diff_images(resolved.input, as_float(before), as_float(now), enc, c.tolerance);
  m.nonfinite_mismatch = s.nonfinite.mismatch;
  m.pq10_max = s[Metric::kPqCode10].max;
  m.pq10_p99 = s[Metric::kPqCode10].p99;
  m.itp_max = s[Metric::kDeltaEItp].max;
  m.itp_p99 = s[Metric::kDeltaEItp].p99;
  m.linear_max = s[Metric::kLinearAbs].max;
  if (stats) *stats = s;
  return m;
}

std::string describe_move(const GoldenMove& m) {
  if (m.resized) return "the image's size changed";
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "PQ max %.3g p99 %.3g (10-bit codes), ΔE_ITP max %.3g p99 %.3g, linear max %.3g; "
                "%zu value(s) changed",
                m.pq10_max, m.pq10_p99, m.itp_max, m.itp_p99, m.linear_max, m.values_changed);
  std::string out = buf;
  if (m.nonfinite_mismatch)
    out += ", " + std::to_string(m.nonfinite_mismatch) + " non-finite value(s) mismatched";
  return out;
}

namespace {

// A golden's id from its path relative to the goldens folder ("tonemap/x.exr" → "tonemap/x"),
// or "" when the path could leave the folder (absolute, "..") or is no golden file.
std::string golden_id(const std::string& rel) {
  const fs::path p(rel);
  if (p.is_absolute() || (p.extension() != ".exr" && p.extension() != ".json")) return "";
  for (const auto& part : p)
    if (part == ".." || part == ".") return "";
  if (p.filename() == "README.md") return "";
  return fs::path(p).replace_extension().generic_string();
}

// The golden ids under `dir` (its .exr and .json files), a bounded walk.
std::set<std::string> golden_ids_in(const std::string& dir) {
  std::set<std::string> ids;
  std::error_code ec;
  size_t visited = 0;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (++visited > 1000000) break;
    if (it->symlink_status(ec).type() != fs::file_type::regular) continue;
    const std::string id = golden_id(it->path().lexically_relative(dir).generic_string());
    if (!id.empty()) ids.insert(id);
  }
  return ids;
}

constexpr double kGitTimeoutSeconds = 120;

// git with `args` in `dir` (argv, no shell); its output (stdout and stderr) bounded by `max`.
Result<std::string> git_text(const std::string& dir, const std::vector<std::string>& args,
                             size_t max = size_t{16} << 20) {
  std::vector<std::string> argv = {"git", "-C", dir};
  argv.insert(argv.end(), args.begin(), args.end());
  CommandLimits limits;
  limits.max_log_bytes = max;
  const CommandResult r = run_command(argv, "", kGitTimeoutSeconds, limits);
  std::string shown = "git";
  for (size_t i = 1; i < argv.size(); ++i) shown += " " + argv[i];
  if (!r.error.empty()) return Error{shown, "", "cannot run git: " + r.error, "git on PATH"};
  if (r.exit_status != 0 || r.output_dropped)
    return Error{shown, "",
                 r.output_dropped ? "more output than " + std::to_string(max) + " bytes"
                                  : "exit status " + std::to_string(r.exit_status) + ": " +
                                        r.output.substr(0, 400),
                 ""};
  return r.output;
}

// The blob `rev`:./`rel` (relative to `dir`) written to `path`; false when the revision has no
// such file. Its size is asked first and bounded (kMaxImageFileBytes), and the written file must
// have exactly that size (git wrote nothing else to the pipe).
Result<bool> git_blob_to(const std::string& dir, const std::string& rev, const std::string& rel,
                         const std::string& path) {
  const std::string object = rev + ":./" + rel;
  std::vector<std::string> argv = {"git", "-C", dir, "cat-file", "-s", object};
  CommandResult r = run_command(argv, "", kGitTimeoutSeconds);
  if (!r.error.empty()) return Error{object, "", "cannot run git: " + r.error, "git on PATH"};
  if (r.exit_status != 0) return false;  // not in that revision: an added golden
  char* end = nullptr;
  const unsigned long long size = std::strtoull(r.output.c_str(), &end, 10);
  if (end == r.output.c_str() || size > kMaxImageFileBytes)
    return Error{object, "", "size " + r.output.substr(0, 40) + " from git cat-file -s",
                 "at most " + std::to_string(kMaxImageFileBytes) + " bytes"};
  std::error_code ec;
  fs::create_directories(fs::path(path).parent_path(), ec);
  argv = {"git", "-C", dir, "cat-file", "blob", object};
  CommandLimits limits;
  limits.max_log_bytes = static_cast<size_t>(size) + 1;
  r = run_command(argv, path, kGitTimeoutSeconds, limits);
  if (!r.error.empty() || r.exit_status != 0 || r.output_dropped ||
      fs::file_size(path, ec) != size) {
    fs::remove(path, ec);
    return Error{object, "",
                 "git cat-file blob failed (exit status " + std::to_string(r.exit_status) + ")",
                 ""};
  }
  return true;
}

// git's paths, one a line (core.quotePath off; a path git still quotes names no golden file,
// and is skipped as one that exists on neither side) → golden ids.
void add_ids(const std::string& lines, std::set<std::string>* ids) {
  size_t at = 0;
  while (at < lines.size()) {
    size_t end = lines.find('\n', at);
    if (end == std::string::npos) end = lines.size();
    const std::string id = golden_id(lines.substr(at, end - at));
    if (!id.empty()) ids->insert(id);
    at = end + 1;
  }
}

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

std::string utc_now() {
  char buf[32];
  const std::time_t t = std::time(nullptr);
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

struct Row {
  std::string id, what, stage, verdict, page;
  GoldenMove move;
  bool has_move = false;
};

// OUT/review.html: one table of every golden that differs, each changed one linked to its case
// page. Static HTML, no script: every string escaped (html_escape, url_path_escape).
std::string review_html(const std::vector<Row>& rows, const std::string& old_label,
                        const std::string& new_label, const std::string& command_line) {
  std::string h =
      "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>Golden changes"
      "</title>\n<style>body{font:14px/1.4 system-ui,sans-serif;margin:1.5em;color:#222}"
      "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:3px 8px;text-align:"
      "left}td:first-child{max-width:36em;overflow-wrap:anywhere}td.n{text-align:right;font-"
      "variant-numeric:tabular-nums}th{background:#f3f3f3}"
      ".FAIL{color:#b00;font-weight:600}.PASS{color:#080}code{background:#f6f6f6}</style>"
      "</head>\n<body>\n<h1>Golden changes</h1>\n<p>Old: <code>" +
      html_escape(old_label) + "</code> (shown as the <em>reference</em>); new: <code>" +
      html_escape(new_label) +
      "</code> (shown as the <em>candidate</em>). The numbers are the run's metrics "
      "(docs/diff-metrics.md) of the new golden against the old one; the verdict applies the "
      "case's tolerance: FAIL means a port that matched the old golden would no longer pass.</p>"
      "\n<p>Command: <code>" +
      html_escape(command_line) + "</code></p>\n";
  size_t changed = 0;
  for (const Row& r : rows) changed += r.has_move;
  h += "<p id=\"summary\">" + std::to_string(rows.size()) + " golden(s) differ, " +
       std::to_string(changed) +
       " with views. <a href=\"report/index.html\">The report of the changed goldens</a>.</p>\n";
  if (rows.empty()) return h + "<p>No golden differs.</p>\n</body></html>\n";
  h += "<table id=\"changes\"><thead><tr><th>golden</th><th>change</th><th>stage</th>"
       "<th>PQ max</th><th>PQ p99</th><th>ΔE<sub>ITP</sub> max</th><th>ΔE<sub>ITP</sub> p99"
       "</th><th>linear max</th><th>values changed</th><th>case tolerance</th></tr></thead>"
       "<tbody>\n";
  for (const Row& r : rows) {
    h += "<tr><td>";
    if (!r.page.empty())
      h += "<a href=\"report/" + html_escape(report::url_path_escape(r.page)) + "\">" +
           html_escape(r.id) + "</a>";
    else
      h += html_escape(r.id);
    h += "</td><td>" + html_escape(r.what) + "</td><td>" + html_escape(r.stage) + "</td>";
    if (r.has_move && !r.move.resized)
      h += "<td class=\"n\">" + fmt(r.move.pq10_max) + "</td><td class=\"n\">" +
           fmt(r.move.pq10_p99) + "</td><td class=\"n\">" + fmt(r.move.itp_max) +
           "</td><td class=\"n\">" + fmt(r.move.itp_p99) + "</td><td class=\"n\">" +
           fmt(r.move.linear_max) + "</td><td class=\"n\">" +
           std::to_string(r.move.values_changed) + "</td>";
    else
      h += "<td colspan=\"6\">—</td>";
    h += "<td class=\"" + html_escape(r.verdict) + "\">" +
         html_escape(r.verdict.empty() ? "—" : r.verdict) + "</td></tr>\n";
  }
  h += "</tbody></table>\n<p>PQ: 10-bit code values per colour value; ΔE<sub>ITP</sub>: "
       "ITU-R BT.2124 per pixel; linear: the output's own units.</p>\n</body></html>\n";
  return h;
}

}  // namespace

Result<GoldensDiffReport> goldens_diff(const std::vector<Case>& cases,
                                       const GoldensDiffOptions& opt, const std::string& staging) {
  GoldensDiffReport rep;
  std::error_code ec;
  if (!fs::is_directory(opt.goldens_dir, ec))
    return Error{opt.goldens_dir, "--goldens", "not a folder", "the goldens folder"};
  const bool from_git = opt.old_dir.empty();
  std::set<std::string> ids;
  std::string old_label;
  if (from_git) {
    // The revision must name a commit; the changed paths are git's, relative to the folder.
    if (opt.since.empty() || opt.since[0] == '-')
      return Error{"--since", "", "'" + opt.since + "' is not a revision",
                   "a commit, branch or tag (default HEAD)"};
    auto commit = git_text(opt.goldens_dir, {"rev-parse", "--verify", "--quiet", "--end-of-options",
                                             opt.since + "^{commit}"});
    if (!commit)
      return Error{"--since", opt.since,
                   "not a commit of the git checkout holding " + opt.goldens_dir + " (" +
                       commit.error().message + ")",
                   "a commit, branch or tag; or --old DIR for goldens outside git"};
    old_label = opt.since + " (" + commit->substr(0, 12) + ")";
    auto changed = git_text(opt.goldens_dir,
                            {"-c", "core.quotePath=false", "diff", "--name-only", "--no-renames",
                             "--relative", "--end-of-options", opt.since, "--", "."});
    if (!changed) return changed.error();
    add_ids(*changed, &ids);
    auto added = git_text(opt.goldens_dir, {"-c", "core.quotePath=false", "ls-files", "--others",
                                            "--exclude-standard", "--", "."});
    if (!added) return added.error();
    add_ids(*added, &ids);
  } else {
    if (!fs::is_directory(opt.old_dir, ec))
      return Error{opt.old_dir, "--old", "not a folder", "a folder of goldens"};
    old_label = opt.old_dir;
    ids = golden_ids_in(opt.old_dir);
    for (const std::string& id : golden_ids_in(opt.goldens_dir)) ids.insert(id);
  }

  std::map<std::string, const Case*> by_id;
  for (const Case& c : cases) by_id[c.id] = &c;
  RunReport run;
  run.command = "run";
  run.started_utc = utc_now();
  run.reference_device.engine = "golden";
  run.reference_device.device = "old goldens: " + old_label;
  run.candidate_device.engine = "golden";
  run.candidate_device.device = "new goldens: " + opt.goldens_dir;
  run.provenance.command_line = opt.command_line;
  std::vector<Row> rows;
  const std::string fetched = staging + "/.old";
  for (const std::string& id : ids) {
    const GoldenPaths now = golden_paths(opt.goldens_dir, id);
    std::string old_exr;
    bool had_old = false;
    if (from_git) {
      old_exr = fetched + "/" + id + ".exr";
      auto got = git_blob_to(opt.goldens_dir, opt.since, id + ".exr", old_exr);
      if (!got) return got.error();
      had_old = *got;
    } else {
      old_exr = golden_paths(opt.old_dir, id).exr;
      had_old = fs::is_regular_file(old_exr, ec);
    }
    const bool has_new = fs::is_regular_file(now.exr, ec);
    Row row;
    row.id = id;
    auto c = by_id.find(id);
    if (c != by_id.end()) row.stage = std::string(c->second->stage->name);
    if (!had_old && !has_new) continue;  // a sidecar alone changed, without an image
    if (!had_old || !has_new) {
      row.what = had_old ? "removed" : "added";
      ++(had_old ? rep.removed : rep.added);
      rep.lines.push_back(row.what + " " + id);
      rows.push_back(row);
      continue;
    }
    auto before = read_image(old_exr);
    if (!before) return before.error();
    auto after = read_image(now.exr);
    if (!after) return after.error();
    if (same_pixels(*before, *after)) {
      // The bytes (or the sidecar) differ, not the values: nothing to view.
      bool same_bytes = false;
      if (!from_git) {
        auto a = read_bounded_file(old_exr, kMaxImageFileBytes, "old golden");
        auto b = read_bounded_file(now.exr, kMaxImageFileBytes, "golden");
        same_bytes = a && b && *a == *b;
      }
      if (from_git || !same_bytes) {
        ++rep.bytes_only;
        row.what = "same pixels (file bytes or sidecar differ)";
        rep.lines.push_back("same pixels " + id);
        rows.push_back(row);
      }
      continue;
    }
    if (c == by_id.end()) {
      ++rep.no_case;
      row.what = "changed (no case of that id in the cases: no views)";
      rep.lines.push_back("changed " + id + ": no case of that id, no views");
      rows.push_back(row);
      continue;
    }
    const Case& spec = *c->second;
    auto resolved = resolve_case(spec);
    if (!resolved) return resolved.error();
    CaseResult r;
    r.spec = spec;
    r.tolerance = spec.tolerance;
    r.has_params = true;
    r.params = resolved->params;
    r.encoding = output_encoding(*spec.stage, resolved->params).describe();
    row.move = golden_move(spec, *resolved, *before, *after, &r.stats);
    row.has_move = true;
    row.what = "changed";
    ++rep.changed;
    rep.lines.push_back("changed " + id + ": " + describe_move(row.move));
    if (row.move.resized) {
      r.verdict = CaseVerdict::kError;
      r.reason = "the golden's size changed: " + std::to_string(before->width) + "x" +
                 std::to_string(before->height) + " → " + std::to_string(after->width) + "x" +
                 std::to_string(after->height);
    } else {
      r.has_stats = true;
      const Verdict v = judge(r.stats, r.tolerance, !spec.pins_nonfinite.empty());
      r.verdict = v.error ? CaseVerdict::kError : v.pass ? CaseVerdict::kPass : CaseVerdict::kFail;
      r.reason = v.reason;
      r.warnings = v.warnings;
      r.budget_used = v.budget_used;
    }
    row.verdict = verdict_name(r.verdict);
    const std::string dir = case_image_dir(id);
    // The images as the report reads them: the old golden's file itself, the new one's, and the
    // case's input (the ramp plot's x axis).
    fs::create_directories(staging + "/" + dir, ec);
    Status st = write_exr(staging + "/" + dir + "/input.exr", resolved->input, 1);
    if (st) {
      fs::copy_file(old_exr, staging + "/" + dir + "/reference.exr",
                    fs::copy_options::overwrite_existing, ec);
      if (!ec)
        fs::copy_file(now.exr, staging + "/" + dir + "/candidate.exr",
                      fs::copy_options::overwrite_existing, ec);
      if (ec) st = Error{staging + "/" + dir, "", "cannot copy a golden: " + ec.message(), ""};
    }
    if (!st) return st.error();
    r.images = {{"input", dir + "/input.exr"},
                {"reference", dir + "/reference.exr"},
                {"candidate", dir + "/candidate.exr"}};
    row.page = case_page_path(id);
    rows.push_back(row);
    run.cases.push_back(std::move(r));
  }
  fs::remove_all(fetched, ec);
  // results.json and junit.xml as a run writes them (one test case per changed golden, judged
  // by the case's tolerance), so that OUT is a results folder like any other.
  if (Status st = write_file_atomic(staging + "/results.json", results_json(run)); !st)
    return st.error();
  if (Status st = write_file_atomic(staging + "/junit.xml", junit_xml(run)); !st) return st.error();
  auto info = write_report(staging, opt.jobs);
  if (!info) return info.error();
  rep.review_page = "review.html";
  if (Status st =
          write_file_atomic(staging + "/" + rep.review_page,
                            review_html(rows, old_label, opt.goldens_dir, opt.command_line));
      !st)
    return st.error();
  return rep;
}

}  // namespace hdrc
