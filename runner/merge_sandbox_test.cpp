// Hostile input to `merge` and to `verify --sandbox`, table-driven (issue 29, items 2 and 4), as
// runner/hostile_input_test.cpp: every row builds a small suite in a fresh folder T and, for merge,
// two shards of it made by `run --shard K/2` (T/s1, T/s2); plants one bad input; runs the binary
// under a hard time limit; and asserts the exit code, the key parts of the message (file, field,
// value, valid choices), that the output is valid UTF-8 with no crash and no hang, and that nothing
// outside the folder the command may write (T/out unless the row says otherwise) changed, nor the
// repository's cases and goldens folders. Sandbox rows also assert that no process the candidate
// started outlived the case.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "core/utf8.h"
#include "runner/output_set.h"
#include "runner/test_support.h"

#ifndef HDRC_BINARY
#error "HDRC_BINARY must be defined"
#endif
#ifndef HDRC_SOURCE_DIR
#error "HDRC_SOURCE_DIR must be defined"
#endif

namespace fs = std::filesystem;
using json = nlohmann::json;
using namespace hdrc::test;  // runner/test_support.h

namespace {

// Two small cases, so that `--shard K/2` gives each shard one: the shaper on 8x2 log ramps.
const char* kCaseA =
    R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 8, "height": 2}})";
const char* kCaseB =
    R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 8, "height": 4}})";

std::string subst(std::string s, const fs::path& t) {
  for (size_t at; (at = s.find("{T}")) != std::string::npos;) s.replace(at, 3, t.string());
  for (size_t at; (at = s.find("{S}")) != std::string::npos;) s.replace(at, 3, HDRC_SOURCE_DIR);
  return s;
}

// `run --shard K/N` (K/N "": an unsharded run) of T's suite (or `cases`) into T/<dir>; `extra` adds
// options. A failure is recorded (the row then fails).
void shard(const fs::path& t, const std::string& dir, const std::string& k_of_n,
           const std::string& extra = "", const std::string& cases = "cases") {
  const Ran r = run("run --engine reference --images all --cases " + (t / cases).string() +
                        (k_of_n.empty() ? "" : " --shard " + k_of_n) + " --out " +
                        (t / dir).string() + " " + extra,
                    "", 60);
  EXPECT_LE(r.code, 1) << r.out;  // 1: a golden check of --goldens that has no goldens
}
void shards(const fs::path& t, const std::string& extra = "") {
  shard(t, "s1", "1/2", extra);
  shard(t, "s2", "2/2", extra);
}

// A shard's results.json, edited by `edit` (the file, not the symlink to it, is rewritten).
void edit_results(const fs::path& shard_dir, const std::function<void(json&)>& edit) {
  const fs::path file = fs::canonical(shard_dir / "results.json");
  json doc = json::parse(read(file));
  edit(doc);
  fs::remove(file);
  write(file, doc.dump(1));
}
void replace_results(const fs::path& shard_dir, const std::string& text) {
  const fs::path file = fs::canonical(shard_dir / "results.json");
  fs::remove(file);
  write(file, text);
}
// The first image of the shard's first case: its path in the run folder.
fs::path first_image(const fs::path& shard_dir) {
  const json doc = json::parse(read(shard_dir / "results.json"));
  return shard_dir / doc["cases"][0]["images"].begin()->get<std::string>();
}

// The files of T except those under `writable` (relative; "" for none), with their digests.
std::map<std::string, std::string> snapshot(const fs::path& t, const std::string& writable) {
  auto all = hdrc::tree_digest(t.string());
  std::map<std::string, std::string> out;
  for (auto& [k, v] : all)
    if (writable.empty() || (k != writable && k.rfind(writable + "/", 0) != 0)) out[k] = v;
  return out;
}

// Processes whose command line holds `needle` (this test's own marker programs).
std::vector<pid_t> processes_with(const std::string& needle) {
  std::vector<pid_t> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator("/proc", ec)) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::string cmd = read(e.path() / "cmdline");
    for (char& c : cmd)
      if (c == '\0') c = ' ';
    const std::string stat = read(e.path() / "stat");
    if (cmd.find(needle) != std::string::npos && stat.find(") Z ") == std::string::npos)
      out.push_back(std::stoi(name));
  }
  return out;
}

// bwrap can create the namespaces --sandbox needs here ("" if so, else why not).
std::string sandbox_unavailable() {
  static const std::string why = [] {
    const int rc =
        std::system("bwrap --unshare-pid --die-with-parent --ro-bind / / true >/dev/null 2>&1");
    return rc == 0 ? std::string()
                   : std::string(
                         "bwrap cannot create a PID namespace on this machine "
                         "(`bwrap --unshare-pid --die-with-parent --ro-bind / / true` "
                         "failed); the sandbox rows need it");
  }();
  return why;
}

struct Row {
  std::string name;
  std::function<void(const fs::path& t)> setup;  // plants the bad input (may be empty)
  std::string args;                              // {T}: the row's folder; {S}: the source tree
  int code;
  std::vector<std::string> expect;  // substrings of the combined output ({T}, {S} replaced)
  // The folder of T the command may change ("": none; "out/.lock": only the lock, which a
  // refused OUT gets as run's does, taken before its content is judged).
  std::string writable = "out";
  bool sandbox = false;  // needs bwrap's namespaces; checks for surviving processes
  std::string env = "";  // "VAR=value ..." for the command
};

const std::string kMerge = "merge {T}/out {T}/s1 {T}/s2";
const std::string kSandbox =
    "verify --sandbox --cases {T}/cases --out {T}/out --candidate-cmd "
    "'sh {T}/cand.sh {output} {input} {params}'";

std::string ref_image() {
  return (fs::temp_directory_path() / ("hdrc_merge_sandbox_ref_" + std::to_string(::getpid())) /
          "ref.exr")
      .string();
}

// The candidate: copies the reference's own image of case `base/log_ramp` to {output}, after
// `before` (a shell fragment; {T} replaced).
std::function<void(const fs::path&)> candidate(const std::string& before) {
  return [before](const fs::path& t) {
    write(t / "cand.sh", "#!/bin/sh\n" + subst(before, t) +
                             "\ntest -f \"$2\" && test -f \"$3\" || exit 5\ncp " + ref_image() +
                             " \"$1\"\n");
    // A copy of sleep at a path of this row: its processes are found by their command line.
    fs::copy_file("/bin/sleep", t / "marker_sleep");
    fs::remove(t / "cases/more.json");  // one case, whose reference image the candidate copies
  };
}

std::vector<Row> rows() {
  std::vector<Row> r;
  auto add = [&](Row row) { r.push_back(std::move(row)); };
  auto with_shards = [](std::function<void(const fs::path&)> more = nullptr) {
    return [more](const fs::path& t) {
      shards(t);
      if (more) more(t);
    };
  };
  // ---- merge: OUT -----------------------------------------------------------------------------
  add({"merge_ok", with_shards(), kMerge, 0, {"merged 2 shards", "2 cases", "exit code 0"}});
  add({"merge_ok_over_previous_run",
       with_shards([](const fs::path& t) { shard(t, "out", "1/1"); }),
       kMerge,
       0,
       {"merged 2 shards"}});
  add({"merge_out_is_shards_cases",
       with_shards(),
       "merge {T}/cases {T}/s1 {T}/s2",
       2,
       {"{T}/cases", "OUT", "is the folder", "must not write into",
        "a folder of its own, outside the cases and goldens folders"},
       ""});
  add({"merge_out_inside_shards_cases",
       with_shards(),
       "merge {T}/cases/sub {T}/s1 {T}/s2",
       2,
       {"{T}/cases/sub", "is inside", "{T}/cases"},
       ""});
  add({"merge_out_holds_shards_cases",
       with_shards(),
       "merge {T} {T}/s1 {T}/s2",
       2,
       {"holds", "must not write into"},
       ""});
  add({"merge_out_is_shards_goldens",
       [](const fs::path& t) { shards(t, "--goldens " + (t / "goldens").string()); },
       "merge {T}/goldens {T}/s1 {T}/s2",
       2,
       {"{T}/goldens", "is the folder", "must not write into"},
       ""});
  add({"merge_out_is_repo_cases",
       with_shards(),
       "merge {S}/cases {T}/s1 {T}/s2",
       2,
       {"{S}/cases", "is the folder", "must not write into"},
       ""});
  add({"merge_out_inside_repo_cases",
       with_shards(),
       "merge {S}/cases/tonemap {T}/s1 {T}/s2",
       2,
       {"{S}/cases/tonemap", "is inside"},
       ""});
  add({"merge_out_is_repo_goldens",
       with_shards(),
       "merge {S}/goldens {T}/s1 {T}/s2",
       2,
       {"{S}/goldens", "is the folder", "must not write into"},
       ""});
  add({"merge_out_is_shard",
       with_shards(),
       "merge {T}/s1 {T}/s1 {T}/s2",
       2,
       {"{T}/s1", "is the folder", "must not write into"},
       ""});
  add({"merge_out_is_shard_via_dotdot",
       with_shards(),
       "merge {T}/s2/../s1 {T}/s1 {T}/s2",
       2,
       {"is the folder", "{T}/s1"},
       ""});
  add({"merge_out_inside_shard",
       with_shards(),
       "merge {T}/s1/merged {T}/s1 {T}/s2",
       2,
       {"{T}/s1/merged", "is inside", "{T}/s1"},
       ""});
  add({"merge_out_inside_shard_run_folder",
       with_shards(),
       "merge {T}/s1/cases {T}/s1 {T}/s2",
       2,
       {"is inside", "{T}/s1"},
       ""});
  add({"merge_out_holds_shards",
       [](const fs::path& t) {
         shard(t, "wrap/s1", "1/2");
         shard(t, "wrap/s2", "2/2");
       },
       "merge {T}/wrap {T}/wrap/s1 {T}/wrap/s2",
       2,
       {"{T}/wrap", "holds", "{T}/wrap/s1"},
       ""});
  add({"merge_out_symlink_to_shard",
       with_shards([](const fs::path& t) { fs::create_directory_symlink(t / "s2", t / "out"); }),
       kMerge,
       2,
       {"{T}/out", "is the folder", "{T}/s2"},
       ""});
  add({"merge_shard_symlink_to_out",
       with_shards([](const fs::path& t) {
         ASSERT_EQ(run("merge " + (t / "out").string() + " " + (t / "s1").string() + " " +
                           (t / "s2").string(),
                       "", 60)
                       .code,
                   0);
         fs::create_directory_symlink(t / "out", t / "s2link");
       }),
       "merge {T}/out {T}/s1 {T}/s2link",
       2,
       {"{T}/out", "is the folder", "must not write into"},
       ""});
  add({"merge_out_foreign_results",
       with_shards([](const fs::path& t) { write(t / "out/results.json", "{\"mine\": 1}\n"); }),
       kMerge,
       2,
       {"{T}/out", "not written by hdrconform", "no results.json of a run",
        "an empty folder or one written by hdrconform run/verify"},
       "out/.lock"});
  add({"merge_out_foreign_report",
       with_shards([](const fs::path& t) { write(t / "out/report/index.html", "<p>mine</p>"); }),
       kMerge,
       2,
       {"{T}/out", "not written by hdrconform"},
       "out/.lock"});
  add({"merge_out_foreign_junit_beside_run",
       with_shards([](const fs::path& t) {
         write(t / "out/junit.xml", "<mine/>");
         write(t / "out/results.json", "{\"tool\": \"other\"}");
       }),
       kMerge,
       2,
       {"not written by hdrconform"},
       "out/.lock"});
  add({"merge_out_is_file",
       with_shards([](const fs::path& t) { write(t / "out", "a file"); }),
       kMerge,
       2,
       {"{T}/out", "OUT", "exists and is not a folder", "a folder path"},
       ""});
  add({"merge_out_runs_is_symlink",
       with_shards([](const fs::path& t) {
         write(t / "victim/keep.txt", "precious");
         fs::create_directories(t / "out");
         fs::create_directory_symlink(t / "victim", t / "out/.runs");
       }),
       kMerge,
       2,
       {"{T}/out", "not written by hdrconform", "replaces the output folder whole"},
       "out/.lock"});
  add({"merge_out_current_is_folder",
       with_shards([](const fs::path& t) { fs::create_directories(t / "out/current"); }),
       kMerge,
       2,
       {"not written by hdrconform"},
       "out/.lock"});
  add({"merge_out_empty_name",
       with_shards(),
       "merge '' {T}/s1 {T}/s2",
       2,
       {"OUT", "the folder is empty"},
       ""});
  // ---- merge: the shards ------------------------------------------------------------------------
  add({"merge_shard_missing",
       with_shards(),
       "merge {T}/out {T}/s1 {T}/nope",
       2,
       {"{T}/nope/results.json"},
       ""});
  add({"merge_shard_empty_folder",
       with_shards([](const fs::path& t) { fs::create_directories(t / "empty"); }),
       "merge {T}/out {T}/s1 {T}/empty",
       2,
       {"{T}/empty/results.json"},
       ""});
  add({"merge_shard_not_a_run",
       with_shards(),
       "merge {T}/out {T}/s1 {T}/cases",
       2,
       {"{T}/cases/results.json"},
       ""});
  add({"merge_shard_is_dev_zero",
       with_shards(),
       "merge {T}/out {T}/s1 /dev/zero",
       2,
       {"/dev/zero/results.json"},
       ""});
  add({"merge_shard_results_fifo",
       with_shards([](const fs::path& t) {
         fs::create_directories(t / "fifo");
         ASSERT_EQ(::mkfifo((t / "fifo/results.json").c_str(), 0644), 0);
       }),
       "merge {T}/out {T}/s1 {T}/fifo",
       2,
       {"{T}/fifo/results.json", "not a regular file"},
       ""});
  add({"merge_shard_results_dev_zero",
       with_shards([](const fs::path& t) {
         fs::create_directories(t / "z");
         fs::create_symlink("/dev/zero", t / "z/results.json");
       }),
       "merge {T}/out {T}/s1 {T}/z",
       2,
       {"{T}/z/results.json", "not a regular file"},
       ""});
  add({"merge_shard_results_deep_nesting",
       with_shards([](const fs::path& t) {
         replace_results(t / "s2", std::string(5000, '[') + std::string(5000, ']'));
       }),
       kMerge,
       2,
       {"{T}/s2/results.json", "nest"},
       ""});
  add({"merge_shard_results_1e999",
       with_shards([](const fs::path& t) {
         std::string text = read(t / "s2/results.json");
         const size_t at = text.find(':', text.find("\"wall_seconds\""));
         ASSERT_NE(at, std::string::npos);
         text.insert(at + 1, "1e999, \"x\": ");
         replace_results(t / "s2", text);
       }),
       kMerge,
       2,
       {"{T}/s2/results.json", "1e999"},
       ""});
  add({"merge_shard_results_non_utf8",
       with_shards([](const fs::path& t) {
         std::string text = read(t / "s2/results.json");
         const size_t at = text.find('"', text.find(':', text.find("\"started_utc\"")));
         ASSERT_NE(at, std::string::npos);
         text.insert(at + 1, "\xff\xfe");
         replace_results(t / "s2", text);
       }),
       kMerge,
       2,
       {"{T}/s2/results.json"},
       ""});
  add({"merge_shard_results_not_json",
       with_shards([](const fs::path& t) { replace_results(t / "s2", "hello"); }),
       kMerge,
       2,
       {"{T}/s2/results.json"},
       ""});
  add({"merge_shard_results_cases_wrong_type",
       with_shards(
           [](const fs::path& t) { edit_results(t / "s2", [](json& d) { d["cases"] = 5; }); }),
       kMerge,
       2,
       {"{T}/s2/results.json", "/cases", "not an array", "results.schema.json"},
       ""});
  add({"merge_shard_other_suite",
       with_shards([](const fs::path& t) {
         write(t / "other/a.json", kCaseA);
         write(
             t / "other/c.json",
             R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 4, "height": 2}})");
         shard(t, "s2other", "2/2", "", "other");
       }),
       "merge {T}/out {T}/s1 {T}/s2other",
       2,
       {"differ in suite", "{T}/s1/results.json", "/provenance/suite_fingerprint",
        "{T}/s2other/results.json", "merge only the shards of one run"},
       ""});
  add({"merge_shard_conflicting_case_ids",
       with_shards([](const fs::path& t) {
         const json one = json::parse(read(t / "s1/results.json"));
         edit_results(t / "s2", [&](json& d) { d["cases"][0]["id"] = one["cases"][0]["id"]; });
       }),
       kMerge,
       2,
       {"is in two shards", "{T}/s1", "{T}/s2"},
       ""});
  add({"merge_shard_duplicated",
       with_shards(),
       "merge {T}/out {T}/s1 {T}/s1",
       2,
       {"shard 1/2 given twice", "{T}/s1"},
       ""});
  add({"merge_shard_k_missing",
       with_shards(),
       "merge {T}/out {T}/s1",
       2,
       {"shard(s) 2/2 missing", "give every shard"},
       ""});
  add({"merge_shard_not_sharded",
       with_shards([](const fs::path& t) { shard(t, "whole", ""); }),
       "merge {T}/out {T}/s1 {T}/whole",
       2,
       {"{T}/whole/results.json", "/shard", "is not K/N", "run --shard K/N"},
       ""});
  add({"merge_shard_unsharded_run",
       with_shards([](const fs::path& t) {
         edit_results(t / "s2", [](json& d) { d["shard"] = nullptr; });
       }),
       kMerge,
       2,
       {"{T}/s2/results.json", "/shard", "is not K/N"},
       ""});
  add({"merge_shard_different_n",
       with_shards([](const fs::path& t) { shard(t, "s3", "2/3"); }),
       "merge {T}/out {T}/s1 {T}/s3",
       2,
       {"every shard must have the same N", "{T}/s3"},
       ""});
  add({"merge_shard_image_escapes",
       with_shards([](const fs::path& t) {
         edit_results(t / "s2", [](json& d) {
           d["cases"][0]["images"]["input"] = "../../../../../../etc/passwd";
         });
       }),
       kMerge,
       2,
       {"{T}/s2/results.json", "/cases/0/images/input", "../../../../../../etc/passwd",
        "not a path inside the run folder", "cases/<case id>/<name>.exr"}});
  add({"merge_shard_image_absolute",
       with_shards([](const fs::path& t) {
         edit_results(t / "s2",
                      [](json& d) { d["cases"][0]["images"]["reference"] = "/etc/passwd"; });
       }),
       kMerge,
       2,
       {"{T}/s2/results.json", "/cases/0/images/reference", "'/etc/passwd'",
        "not a path inside the run folder"}});
  add({"merge_shard_image_fifo",
       with_shards([](const fs::path& t) {
         const fs::path img = first_image(t / "s2");
         fs::remove(img);
         ASSERT_EQ(::mkfifo(img.c_str(), 0644), 0);
       }),
       kMerge,
       2,
       {"{T}/s2/results.json", "/cases/0/images/", "not a regular file"}});
  add({"merge_shard_image_symlink_outside",
       with_shards([](const fs::path& t) {
         write(t / "secret.txt", "secret");
         const fs::path img = first_image(t / "s2");
         fs::remove(img);
         fs::create_symlink(t / "secret.txt", img);
       }),
       kMerge,
       2,
       {"{T}/s2/results.json", "not a regular file", "the shard's own case images"}});
  add({"merge_shard_image_missing",
       with_shards([](const fs::path& t) { fs::remove(first_image(t / "s2")); }),
       kMerge,
       2,
       {"{T}/s2/results.json", "does not exist"}});
  // ---- verify --sandbox ----------------------------------------------------------------------
  // A relative --out: {output} and the other paths are absolute inside the sandbox, whose
  // working folder is the case folder.
  add({"sandbox_relative_out",
       candidate(""),
       "verify --sandbox --cases {T}/cases --out \"$(realpath -m --relative-to=. {T}/out)\" "
       "--candidate-cmd 'sh {T}/cand.sh {output} {input} {params}'",
       0,
       {"1 passed"},
       "out",
       true});
  add({"sandbox_relative_out_dotdot",
       candidate(""),
       "verify --sandbox --cases {T}/cases --out \"$(realpath -m --relative-to=. {T}/out)/../out\" "
       "--candidate-cmd 'sh {T}/cand.sh {output} {input} {params}'",
       0,
       {"1 passed"},
       "out",
       true});
  add({"sandbox_background_child_killed_at_case_end",
       candidate("{T}/marker_sleep 300 &"),
       kSandbox,
       0,
       {"1 passed"},
       "out",
       true});
  add({"sandbox_setsid_child_killed_at_case_end",
       candidate("setsid {T}/marker_sleep 300 </dev/null >/dev/null 2>&1 &"),
       kSandbox,
       0,
       {"1 passed"},
       "out",
       true});
  add({"sandbox_double_fork_child_killed_at_case_end",
       candidate("( ( {T}/marker_sleep 300 </dev/null >/dev/null 2>&1 & ) & )"),
       kSandbox,
       0,
       {"1 passed"},
       "out",
       true});
  add({"sandbox_child_killed_at_timeout",
       candidate("{T}/marker_sleep 300 & {T}/marker_sleep 30"),
       kSandbox + " --timeout 1",
       1,
       {"timed out after 1 s", "killed with every process it started"},
       "out",
       true});
  add({"sandbox_unknown_placeholder",
       candidate(""),
       "verify --sandbox --cases {T}/cases --out {T}/out --candidate-cmd "
       "'sh {T}/cand.sh {outptu} {output}'",
       2,
       {"--candidate-cmd", "unknown placeholder {outptu}",
        "valid placeholders: {input} {params} {output} {id}"},
       "out"});
  add({"cmd_unknown_placeholder",
       candidate(""),
       "verify --cases {T}/cases --out {T}/out --candidate-cmd 'sh {T}/cand.sh {output} {Id} "
       "{ids}'",
       2,
       {"unknown placeholder {ids}", "valid placeholders"},
       "out"});
  add({"sandbox_missing_bwrap",
       [](const fs::path& t) {
         candidate("")(t);
         fs::create_directories(t / "bin");
         fs::create_symlink("/usr/bin/timeout", t / "bin/timeout");
       },
       kSandbox,
       3,
       {"--sandbox", "bubblewrap (bwrap) is not installed", "not found on PATH {T}/bin",
        "install Debian's package bubblewrap, or run without --sandbox"},
       "out",
       false,
       "PATH={T}/bin"});
  return r;
}

void PrintTo(const Row& row, std::ostream* os) {
  *os << row.name;
}

class MergeSandboxInput : public ::testing::TestWithParam<Row> {
 protected:
  // The reference's own image of `base/log_ramp`, for candidates that pass (made once).
  static void SetUpTestSuite() {
    setup_error() = "";
    const fs::path dir = fs::path(ref_image()).parent_path();
    fs::remove_all(dir);
    write(dir / "cases/base.json", kCaseA);
    const Ran r = run("run --engine reference --images all --cases " + (dir / "cases").string() +
                          " --out " + (dir / "out").string(),
                      "", 60);
    std::error_code ec;
    if (r.code != 0)
      setup_error() = "the reference run exited " + std::to_string(r.code) + ": " + r.out;
    else if (!fs::copy_file(dir / "out/cases/base/log_ramp/reference.exr", ref_image(), ec))
      setup_error() = "cannot copy the reference image: " + ec.message();
  }
  void SetUp() override { ASSERT_EQ(setup_error(), "") << "suite set-up failed"; }
  static std::string& setup_error() {
    static std::string e;
    return e;
  }
};

TEST_P(MergeSandboxInput, ClearErrorNoCrashNoHangNothingOutsideChanged) {
  const Row& row = GetParam();
  if (row.sandbox && !sandbox_unavailable().empty()) GTEST_SKIP() << sandbox_unavailable();
  const fs::path t =
      fs::temp_directory_path() / ("hdrc_merge_sandbox_" + std::to_string(::getpid())) / row.name;
  fs::remove_all(t);
  write(t / "cases/base.json", kCaseA);
  write(t / "cases/more.json", kCaseB);
  if (row.setup) row.setup(t);
  ASSERT_FALSE(::testing::Test::HasFailure()) << "the row's set-up failed";
  const bool touches_repo = row.args.find("{S}") != std::string::npos;
  const auto repo_cases = hdrc::tree_digest(std::string(HDRC_SOURCE_DIR) + "/cases");
  const auto repo_goldens = touches_repo
                                ? hdrc::tree_digest(std::string(HDRC_SOURCE_DIR) + "/goldens")
                                : std::map<std::string, std::string>();
  const auto before = snapshot(t, row.writable);
  const Ran r = hdrc::test::run(subst(row.args, t), subst(row.env, t), 60);
  SCOPED_TRACE(r.out.substr(0, 3000));
  EXPECT_NE(r.code, 137) << "hang: killed after the time limit";
  EXPECT_LT(r.code, 128) << "crash: killed by a signal";
  EXPECT_EQ(r.code, row.code);
  for (const auto& want : row.expect)
    EXPECT_NE(r.out.find(subst(want, t)), std::string::npos) << "missing: " << subst(want, t);
  EXPECT_TRUE(hdrc::is_valid_utf8(r.out)) << "the messages are not valid UTF-8";
  const auto changes = hdrc::digest_changes(before, snapshot(t, row.writable), 20);
  EXPECT_TRUE(changes.empty()) << "changed outside "
                               << (row.writable.empty() ? "(none)" : row.writable) << ": "
                               << ::testing::PrintToString(changes);
  EXPECT_EQ(hdrc::tree_digest(std::string(HDRC_SOURCE_DIR) + "/cases"), repo_cases);
  if (touches_repo) {
    EXPECT_EQ(hdrc::tree_digest(std::string(HDRC_SOURCE_DIR) + "/goldens"), repo_goldens);
  }
  // A published output is complete; a refused merge published nothing new.
  if (r.code != 2 && row.writable == "out") {
    EXPECT_TRUE(nlohmann::json::accept(read(t / "out/results.json")));
    EXPECT_TRUE(fs::exists(t / "out/report/index.html"));
  }
  if (row.sandbox) {
    // No process the candidate started is left (its marker program runs from T).
    std::vector<pid_t> left;
    for (int i = 0; i < 50; ++i) {
      left = processes_with((t / "marker_sleep").string());
      if (left.empty()) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    EXPECT_TRUE(left.empty()) << left.size() << " of the candidate's processes outlived the case, "
                              << "e.g. pid " << (left.empty() ? 0 : left[0]);
    for (pid_t p : left) ::kill(p, SIGKILL);
  }
  if (!::testing::Test::HasFailure()) fs::remove_all(t);
}

INSTANTIATE_TEST_SUITE_P(Table, MergeSandboxInput, ::testing::ValuesIn(rows()),
                         [](const auto& info) {
                           return hdrc::test::gtest_param_name(info.param.name);
                         });

// A sandboxed command's child that leaves its session and clears its environment (so neither
// the process-group kill nor the token search of runner/descendants.h finds it) is gone when its
// case ends, not only when the run is published: observed while the next case runs. `timeout`:
// case a/log_ramp's command outlives --timeout (and is killed) instead of exiting.
void sandboxed_child_is_gone_at_case_end(bool timeout) {
  if (!sandbox_unavailable().empty()) GTEST_SKIP() << sandbox_unavailable();
  const fs::path t = temp_dir(timeout ? "sandbox_timeout" : "sandbox_case_end");
  write(t / "refcases/a.json", kCaseA);
  ASSERT_EQ(run("run --engine reference --images all --cases " + (t / "refcases").string() +
                    " --out " + (t / "ref").string(),
                "", 60)
                .code,
            0);
  write(t / "cases/a.json", kCaseA);
  write(t / "cases/b.json", kCaseA);
  fs::copy_file("/bin/sleep", t / "marker_sleep");
  // Case a/log_ramp leaves the child (and waits until it has exec'd, its environment cleared;
  // or past --timeout 2); case b/log_ramp takes 1.8 s, while this test looks. Without the timeout
  // under test, --timeout is far above what the cases take, also on a loaded or sanitized build.
  // The child is orphaned at once (a double fork): no longer below the command's process.
  write(t / "cand.sh", "#!/bin/sh\nif [ \"$2\" = a/log_ramp ]; then (setsid env -i " +
                           (t / "marker_sleep").string() +
                           " 300 </dev/null >/dev/null 2>&1 &); sleep " + (timeout ? "30" : "1") +
                           "; else sleep 1.8; fi\ncp " +
                           (t / "ref/cases/a/log_ramp/reference.exr").string() + " \"$1\"\n");
  const std::string cmd = "env -u CI timeout -s KILL 60 " + std::string(HDRC_BINARY) +
                          " verify --sandbox -j 1 --timeout " + (timeout ? "2" : "30") +
                          " --cases " + (t / "cases").string() + " --out " + (t / "out").string() +
                          " --candidate-cmd 'sh " + (t / "cand.sh").string() + " {output} {id}' >" +
                          (t / "log.txt").string() + " 2>&1 </dev/null";
  std::FILE* p = popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  // Case b has started (its folder exists) once case a has ended.
  bool b_started = false;
  for (int i = 0; i < 1000 && !b_started; ++i) {
    std::error_code ec;
    // The run writes into its staging folder beside OUT (runner/output_set.cpp).
    for (const auto& e : fs::directory_iterator(t, ec))
      if (e.path().filename().string().rfind(".out.hdrconform-", 0) == 0)
        b_started = b_started || fs::exists(e.path() / "cases/b/log_ramp/params.json", ec);
    if (!b_started) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_TRUE(b_started) << "case b/log_ramp never started";
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const std::vector<pid_t> left = processes_with((t / "marker_sleep").string());
  EXPECT_TRUE(left.empty()) << "case a/log_ramp's sandboxed child outlived its case: pid "
                            << (left.empty() ? 0 : left[0]);
  const int status = pclose(p);
  const std::string log = read(t / "log.txt");
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, timeout ? 1 : 0) << log;
  if (timeout) {
    EXPECT_NE(log.find("timed out after 2 s (killed with every process it started)"),
              std::string::npos)
        << log;
  }
  for (pid_t q : processes_with((t / "marker_sleep").string())) ::kill(q, SIGKILL);
  if (!::testing::Test::HasFailure()) fs::remove_all(t);
}

TEST(MergeSandboxInput, SandboxedChildWithoutTokenIsGoneAtTheCaseEnd) {
  sandboxed_child_is_gone_at_case_end(false);
}

TEST(MergeSandboxInput, SandboxedChildWithoutTokenIsGoneAfterTimeout) {
  sandboxed_child_is_gone_at_case_end(true);
}

TEST(MergeSandboxInput, TableHasAtLeast40Rows) {
  EXPECT_GE(rows().size(), 40u);
}

}  // namespace
