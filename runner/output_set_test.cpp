// The output folder as a whole (runner/output_set.h): kill -9 at random moments of a run leaves
// either the previous complete run or the new complete run; two runs into one folder are refused;
// the candidate's process group does not outlive its case; the helpers' own contracts.
#include "runner/output_set.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include "core/utf8.h"
#include "runner/json_read.h"
#include "runner/test_support.h"

#ifndef HDRC_BINARY
#error "HDRC_BINARY must be defined"
#endif

namespace fs = std::filesystem;
using namespace hdrc::test;  // runner/test_support.h

namespace {

// Every run here is bounded at 120 s: a hang fails the test instead of stalling CI.
Ran run(const std::string& args) {
  return hdrc::test::run(args, "", 120);
}

// Starts the binary with `args` (no shell), output to /dev/null; returns its pid.
pid_t spawn(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  std::string bin = HDRC_BINARY;
  argv.push_back(bin.data());
  std::vector<std::string> copy = args;
  for (auto& a : copy) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    freopen("/dev/null", "w", stdout);
    freopen("/dev/null", "w", stderr);
    unsetenv("CI");  // hermetic, as hdrc::test::run (runner/test_support.h)
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

int wait_code(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// A suite of `n` cases that takes a noticeable time on the reference engine.
void write_suite(const fs::path& cases, int n) {
  std::string values;
  for (int i = 0; i < n; ++i) {  // appended: GCC 12 -O3 -Wrestrict false positive (bug 105329)
    if (i) values += ',';
    values += std::to_string(0.3 + 0.05 * i);
  }
  write(cases / "k.json",
        R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 256, "height": 64},
            "matrix": {"settings": {"FilmSlope": [)" +
            values + "]}}}");
}

// No symbolic link anywhere under `dir` (GitLab's runner follows none for artifacts).
void expect_no_symlinks(const fs::path& dir) {
  size_t entries = 0;
  for (fs::recursive_directory_iterator it(dir), end; it != end; ++it) {
    ++entries;
    EXPECT_FALSE(it->is_symlink()) << it->path();
  }
  EXPECT_GT(entries, 0u) << dir;
}

// What a reader of OUT sees: the published run, complete, plain files only, every file of it
// from one run: junit.xml's timestamp and time and the report's "started"/"duration" rows are
// results.json's started_utc and wall_seconds.
// Returns the run's started_utc + wall_seconds (its identity), or "" with a failure recorded.
std::string check_complete(const fs::path& out, size_t cases) {
  expect_no_symlinks(out);
  auto doc = hdrc::read_json_file<nlohmann::json>((out / "results.json").string());
  EXPECT_TRUE(doc.ok()) << (doc ? "" : doc.error().to_string());
  if (!doc) return "";
  EXPECT_EQ((*doc)["cases"].size(), cases);
  for (const auto& c : (*doc)["cases"])
    for (const auto& [k, v] : c["images"].items())
      EXPECT_TRUE(fs::is_regular_file(out / v.get<std::string>())) << v;
  const std::string junit = read(out / "junit.xml");
  EXPECT_NE(junit.find("tests=\"" + std::to_string(cases) + "\""), std::string::npos);
  EXPECT_NE(junit.find("</testsuites>"), std::string::npos);
  std::string started = (*doc)["started_utc"].get<std::string>();
  const double wall = (*doc)["wall_seconds"].get<double>();
  if (!started.empty() && started.back() == 'Z') started.pop_back();  // JUnit: no time zone
  char time[64], duration[64];
  std::snprintf(time, sizeof time, "time=\"%.3f\"", wall);
  std::snprintf(duration, sizeof duration, "<td>%.2f</td>", wall);
  EXPECT_NE(junit.find("timestamp=\"" + started + "\""), std::string::npos) << junit;
  EXPECT_NE(junit.find(time), std::string::npos) << time;
  const std::string index = read(out / "report/index.html");
  EXPECT_NE(index.find(duration), std::string::npos) << duration;
  return (*doc)["started_utc"].dump() + (*doc)["wall_seconds"].dump();
}

// The folders beside `out` that are not `out` itself (staging folders left behind).
size_t siblings_of(const fs::path& out) {
  size_t n = 0;
  for (const auto& e : fs::directory_iterator(out.parent_path()))
    n += e.path().filename().string().rfind("." + out.filename().string() + ".hdrconform-", 0) == 0;
  return n;
}

TEST(OutputSet, KillNineAtRandomMomentsLeavesPreviousOrNewCompleteRun) {
  const fs::path t = temp_dir("kill");
  const int n = 12;
  write_suite(t / "cases", n);
  const std::vector<std::string> args = {
      "run",   "--engine",           "reference", "--cases", (t / "cases").string(),
      "--out", (t / "out").string(), "-j",        "1"};
  // The previous complete run, and how long a run takes.
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(wait_code(spawn(args)), 0);
  const double full_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::string previous = check_complete(t / "out", n);
  ASSERT_FALSE(previous.empty());

  std::mt19937 rng(12);
  std::uniform_real_distribution<double> when(0.0, full_ms * 1.1);
  int kept_previous = 0, got_new = 0;
  const int kills = 16;
  for (int i = 0; i < kills; ++i) {
    const pid_t pid = spawn(args);
    std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(when(rng)));
    kill(pid, SIGKILL);
    wait_code(pid);
    SCOPED_TRACE("kill " + std::to_string(i));
    const std::string seen = check_complete(t / "out", n);
    ASSERT_FALSE(seen.empty());
    if (seen == previous) {
      ++kept_previous;
    } else {
      ++got_new;
      previous = seen;
    }
  }
  std::printf(
      "kill -9 at %d random moments over %.0f ms runs: %d left the previous run, %d the "
      "new one; every time complete\n",
      kills, full_ms, kept_previous, got_new);
  EXPECT_GT(kept_previous, 0);  // some kills hit a run before it published
  // The next run cleans the killed runs' staging folders beside OUT: none remains.
  ASSERT_EQ(wait_code(spawn(args)), 0);
  check_complete(t / "out", n);
  EXPECT_EQ(siblings_of(t / "out"), 0u);
  if (!::testing::Test::HasFailure()) fs::remove_all(t);
}

// `merge` publishes as `run` does (runner/merge.h): kill -9 at moments spread over a merge's
// duration leaves OUT holding one complete merge, the previous one or the new one, never one
// merge's results.json beside another's report or images. Merges of two shard sets (the same
// suite run twice: different started_utc and wall_seconds) alternate, so every kill that lands
// after a publication shows as a change.
TEST(OutputSet, KillNineDuringMergeLeavesPreviousOrNewCompleteMerge) {
  const fs::path t = temp_dir("kill_merge");
  const int n = 12;
  write_suite(t / "cases", n);
  // Two runs of the suite, each as two shards.
  for (const char* set : {"a", "b"})
    for (const char* k : {"1", "2"}) {
      const fs::path dir = t / (std::string(set) + k);
      ASSERT_EQ(wait_code(spawn({"run", "--engine", "reference", "--cases", (t / "cases").string(),
                                 "--shard", std::string(k) + "/2", "--images", "all", "--out",
                                 dir.string(), "-j", "1"})),
                0);
    }
  auto merge_args = [&](const std::string& set) {
    return std::vector<std::string>{"merge", (t / "out").string(), (t / (set + "1")).string(),
                                    (t / (set + "2")).string()};
  };
  // The identity of a complete merge: its started_utc and wall_seconds, as check_complete reads
  // them, and its case images (the report's and results.json's) from the same shards.
  auto identity = [&](const std::string& seen) {
    const auto doc = nlohmann::json::parse(read(t / "out/results.json"));
    std::string set;
    for (const auto& from : doc["merged_from"]) set += from["dir"].get<std::string>() + ";";
    // Every image OUT shows is the shards' own file (a hard link: the same inode).
    for (const auto& c : doc["cases"])
      for (const auto& [name, rel] : c["images"].items()) {
        const std::string shard = set.find((t / "a1").string()) != std::string::npos ? "a" : "b";
        bool same = false;
        for (const char* k : {"1", "2"})
          same = same || fs::equivalent(t / "out" / rel.get<std::string>(),
                                        t / (shard + k) / rel.get<std::string>());
        EXPECT_TRUE(same) << rel << " is not from shard set " << shard;
      }
    // The report shows the same merge: its data names the shard folders results.json names.
    const std::string data = read(t / "out/report/index.html");
    EXPECT_NE(
        data.find(
            (t / (set.find((t / "a1").string()) != std::string::npos ? "a1" : "b1")).string()),
        std::string::npos)
        << "the report is not of the merge results.json holds";
    return seen + set;
  };
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(wait_code(spawn(merge_args("a"))), 0);
  const double full_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::string previous = identity(check_complete(t / "out", n));
  ASSERT_FALSE(previous.empty());

  // Moments spread evenly over 1.6 times a merge's duration (a merge under load takes longer
  // than the one timed), each jittered within its slot.
  std::mt19937 rng(29);
  const int kills = 16;
  int kept_previous = 0, got_new = 0;
  for (int i = 0; i < kills; ++i) {
    const double slot = full_ms * 1.6 / kills;
    const double at = slot * (i + std::uniform_real_distribution<double>(0.0, 1.0)(rng));
    const pid_t pid = spawn(merge_args(i % 2 ? "a" : "b"));
    std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(at));
    kill(pid, SIGKILL);
    wait_code(pid);
    SCOPED_TRACE("kill " + std::to_string(i) + " at " + std::to_string(at) + " ms");
    const std::string seen = identity(check_complete(t / "out", n));
    ASSERT_FALSE(seen.empty());
    if (seen == previous) {
      ++kept_previous;
    } else {
      ++got_new;
      previous = seen;
    }
  }
  std::printf(
      "merge: kill -9 at %d moments over %.0f ms merges: %d left the previous merge, %d the new "
      "one; every time complete\n",
      kills, full_ms, kept_previous, got_new);
  EXPECT_GT(kept_previous, 0);  // some kills hit a merge before it published
  // The next merge cleans the killed merges' staging folders: none is left beside OUT.
  ASSERT_EQ(wait_code(spawn(merge_args("b"))), 0);
  identity(check_complete(t / "out", n));
  EXPECT_EQ(siblings_of(t / "out"), 0u);
  if (!::testing::Test::HasFailure()) fs::remove_all(t);
}

// A finished merge's OUT holds exactly that merge's outputs: merging another suite's shards into
// it leaves none of the first merge's case images, and no run folder but its own.
TEST(OutputSet, MergeLeavesNothingOfTheMergeBefore) {
  const fs::path t = temp_dir("merge_again");
  write_suite(t / "big", 6);
  write(t / "small/s.json",
        R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 8, "height": 2}})");
  write(t / "small/u.json",
        R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 8, "height": 4}})");
  for (const char* suite : {"big", "small"})
    for (const char* k : {"1", "2"})
      ASSERT_EQ(wait_code(spawn({"run", "--engine", "reference", "--cases", (t / suite).string(),
                                 "--shard", std::string(k) + "/2", "--images", "all", "--out",
                                 (t / (std::string(suite) + k)).string()})),
                0);
  ASSERT_EQ(wait_code(spawn(
                {"merge", (t / "out").string(), (t / "big1").string(), (t / "big2").string()})),
            0);
  check_complete(t / "out", 6);
  ASSERT_EQ(wait_code(spawn(
                {"merge", (t / "out").string(), (t / "small1").string(), (t / "small2").string()})),
            0);
  check_complete(t / "out", 2);
  // The files OUT shows: exactly those of the second merge.
  std::set<std::string> shown;
  for (const auto& e : fs::recursive_directory_iterator(t / "out/cases"))
    if (e.is_regular_file()) shown.insert(fs::relative(e.path(), t / "out/cases").string());
  std::set<std::string> expected;
  const auto doc = nlohmann::json::parse(read(t / "out/results.json"));
  for (const auto& c : doc["cases"])
    for (const auto& [name, rel] : c["images"].items())
      expected.insert(fs::path(rel.get<std::string>()).lexically_relative("cases").string());
  EXPECT_EQ(shown, expected);
  EXPECT_EQ(siblings_of(t / "out"), 0u);
  if (!::testing::Test::HasFailure()) fs::remove_all(t);
}

TEST(OutputSet, ConcurrentRunsIntoOneFolderAreRefused) {
  const fs::path t = temp_dir("lock");
  write(t / "cases/a.json",
        R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 8, "height": 2}})");
  write(t / "slow.sh", "#!/bin/sh\nsleep 10\nexit 1\n");
  const pid_t first =
      spawn({"verify", "--cases", (t / "cases").string(), "--out", (t / "out").string(),
             "--candidate-cmd", "sh " + (t / "slow.sh").string() + " {output}"});
  // Wait until the first run holds the lock.
  for (int i = 0; i < 200 && !fs::exists(t / "out/.lock"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const Ran second = run("run --engine reference --cases " + (t / "cases").string() + " --out " +
                         (t / "out").string());
  EXPECT_EQ(second.code, 2) << second.out;
  EXPECT_NE(second.out.find("another hdrconform run (pid " + std::to_string(first) +
                            ") is writing to this output folder"),
            std::string::npos)
      << second.out;
  const Ran report = run("report " + (t / "out").string());
  EXPECT_EQ(report.code, 2) << report.out;
  EXPECT_EQ(wait_code(first), 1);  // the first run finished undisturbed (its candidate fails)
  check_complete(t / "out", 1);
  // Free again: a run now works.
  EXPECT_EQ(run("run --engine reference --cases " + (t / "cases").string() + " --out " +
                (t / "out").string())
                .code,
            0);
  if (!::testing::Test::HasFailure()) fs::remove_all(t);
}

// run, merge and report publish plain files and folders: no symlink anywhere in an output
// folder (GitLab's artifacts and reports:junit follow none), none left beside it; an output
// folder of the layout before (symlinks into .runs/) is replaced by plain files.
TEST(OutputSet, NoSymlinkInAnOutputFolderAfterRunMergeOrReport) {
  const fs::path t = temp_dir("nolinks");
  write_suite(t / "cases", 4);
  const std::string common = "--engine reference --cases " + (t / "cases").string() + " -j 1 ";
  // The layout of before: results.json etc. as symlinks through current -> .runs/<run>.
  write(t / "s1/.runs/run-old/results.json",
        "{\"tool\": \"hdrconform\", \"shard\": \"1/2\", \"cases\": []}");
  fs::create_directory_symlink(".runs/run-old", t / "s1/current");
  fs::create_symlink("current/results.json", t / "s1/results.json");
  for (const char* shard : {"1/2", "2/2"}) {
    const fs::path out = t / (std::string("s") + shard[0]);
    const Ran r = run("run " + common + "--shard " + shard + " --out " + out.string());
    ASSERT_EQ(r.code, 0) << r.out;
    expect_no_symlinks(out);
    EXPECT_FALSE(fs::exists(out / ".runs"));
    EXPECT_FALSE(fs::exists(out / "current"));
  }
  const Ran m =
      run("merge " + (t / "m").string() + " " + (t / "s1").string() + " " + (t / "s2").string());
  ASSERT_EQ(m.code, 0) << m.out;
  check_complete(t / "m", 4);
  // A second merge into the same folder replaces it whole.
  ASSERT_EQ(
      run("merge " + (t / "m").string() + " " + (t / "s1").string() + " " + (t / "s2").string())
          .code,
      0);
  check_complete(t / "m", 4);
  const Ran rep = run("report " + (t / "m").string());
  ASSERT_EQ(rep.code, 0) << rep.out;
  check_complete(t / "m", 4);
  for (const char* d : {"s1", "s2", "m"}) EXPECT_EQ(siblings_of(t / d), 0u) << d;
  // A folder holding anything else is refused, untouched: a run replaces the folder whole.
  write(t / "other/keep.txt", "precious");
  const Ran other = run("run " + common + "--out " + (t / "other").string());
  EXPECT_EQ(other.code, 2) << other.out;
  EXPECT_NE(other.out.find("holds keep.txt, not written by hdrconform"), std::string::npos)
      << other.out;
  EXPECT_EQ(read(t / "other/keep.txt"), "precious");
  if (!::testing::Test::HasFailure()) fs::remove_all(t);
}

TEST(OutputSet, CandidateProcessGroupIsKilledWhenTheCommandEnds) {
  const fs::path t = temp_dir("pgroup");
  write(t / "cases/a.json",
        R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 8, "height": 2}})");
  // Leaves a child behind and exits at once (normal exit, status 1).
  write(t / "cand.sh",
        "#!/bin/sh\nsleep 300 &\necho $! > " + (t / "child.pid").string() + "\nexit 1\n");
  const Ran r = run("verify --cases " + (t / "cases").string() + " --out " + (t / "out").string() +
                    " --candidate-cmd 'sh " + (t / "cand.sh").string() + " {output}'");
  EXPECT_EQ(r.code, 1) << r.out;
  const pid_t child = std::stoi(read(t / "child.pid"));
  ASSERT_GT(child, 1);
  bool gone = false;
  for (int i = 0; i < 100 && !gone; ++i) {
    gone = kill(child, 0) != 0 && errno == ESRCH;
    if (!gone) {
      // A zombie reparented to a reaper that has not reaped yet counts as gone.
      const std::string stat = read("/proc/" + std::to_string(child) + "/stat");
      gone = stat.find(") Z ") != std::string::npos;
    }
    if (!gone) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_TRUE(gone) << "the candidate's child " << child << " outlived it";
  if (!gone) kill(child, SIGKILL);
  if (!::testing::Test::HasFailure()) fs::remove_all(t);
}

TEST(OutputSet, ValidateRefusesProtectedFoldersWithReasons) {
  const fs::path t = temp_dir("validate");
  fs::create_directories(t / "cases");
  const std::vector<std::string> prot = {(t / "cases").string()};
  EXPECT_FALSE(hdrc::validate_output_dir("", "--out", prot));
  EXPECT_FALSE(hdrc::validate_output_dir((t / "cases").string(), "--out", prot));
  EXPECT_FALSE(hdrc::validate_output_dir((t / "cases/x").string(), "--out", prot));
  EXPECT_FALSE(hdrc::validate_output_dir(t.string(), "--out", prot));
  fs::create_directory_symlink(t / "cases", t / "l");
  auto e = hdrc::validate_output_dir((t / "l").string(), "--out", prot);
  ASSERT_FALSE(e);
  EXPECT_NE(e.error().message.find("itself"), std::string::npos);
  EXPECT_TRUE(hdrc::validate_output_dir((t / "out").string(), "--out", prot));
  EXPECT_TRUE(fs::is_directory(t / "out"));
  EXPECT_TRUE(fs::is_empty(t / "out"));  // the probe file is gone
  write(t / "file", "x");
  e = hdrc::validate_output_dir((t / "file").string(), "--out", prot);
  ASSERT_FALSE(e);
  EXPECT_NE(e.error().message.find("not a folder"), std::string::npos);
  fs::remove_all(t);
}

TEST(OutputSet, TreeDigestSeesEveryChange) {
  const fs::path t = temp_dir("digest");
  write(t / "a/b.json", "1");
  const auto d0 = hdrc::tree_digest(t.string());
  write(t / "a/b.json", "2");
  auto d1 = hdrc::tree_digest(t.string());
  EXPECT_EQ(hdrc::digest_changes(d0, d1), std::vector<std::string>{"a/b.json (changed)"});
  write(t / "c", "");
  fs::create_symlink("x", t / "s");
  const auto d2 = hdrc::tree_digest(t.string());
  EXPECT_EQ(hdrc::digest_changes(d1, d2), (std::vector<std::string>{"c (added)", "s (added)"}));
  fs::remove_all(t);
}

TEST(JsonRead, NestingAndOverflowAreErrorsNamingTheFile) {
  auto deep = hdrc::parse_json_text<nlohmann::json>("f.json", std::string(200000, '['));
  ASSERT_FALSE(deep);
  EXPECT_EQ(deep.error().file, "f.json");
  EXPECT_EQ(deep.error().pointer, "line 1");
  auto ok = hdrc::parse_json_text<nlohmann::json>("f.json",
                                                  std::string(100, '[') + std::string(100, ']'));
  EXPECT_TRUE(ok);
  auto big = hdrc::parse_json_text<nlohmann::json>("f.json", "[1e999]");
  ASSERT_FALSE(big);
  EXPECT_NE(big.error().message.find("number overflow"), std::string::npos);
  auto bad = hdrc::parse_json_text<nlohmann::json>("f.json", "\"\xff\"");
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().file, "f.json");
  // Brackets inside strings do not count.
  EXPECT_TRUE(
      hdrc::parse_json_text<nlohmann::json>("f.json", "\"" + std::string(500, '[') + "\\\"\""));
}

TEST(Utf8, ValidatesAndReplacesLikeRfc3629) {
  EXPECT_TRUE(hdrc::is_valid_utf8("plain"));
  EXPECT_TRUE(hdrc::is_valid_utf8("\xC3\xA9\xE2\x82\xAC\xF0\x9F\x98\x80"));  // é € 😀
  EXPECT_FALSE(hdrc::is_valid_utf8("\xC0\xAF"));                             // overlong '/'
  EXPECT_FALSE(hdrc::is_valid_utf8("\xED\xA0\x80"));                         // a UTF-16 surrogate
  EXPECT_FALSE(hdrc::is_valid_utf8("\xF4\x90\x80\x80"));                     // over U+10FFFF
  EXPECT_FALSE(hdrc::is_valid_utf8("\xE2\x82"));                             // truncated
  EXPECT_EQ(hdrc::valid_utf8("a\xff"
                             "b"),
            "a\xEF\xBF\xBD"
            "b");
  EXPECT_EQ(hdrc::valid_utf8("\xC3\xA9"), "\xC3\xA9");
  EXPECT_EQ(hdrc::valid_utf8(std::string("a\0b", 3)),
            "a\xEF\xBF\xBD"
            "b");
  // The result always dumps as JSON.
  nlohmann::json j = hdrc::valid_utf8("\xfe\xff\xC3");
  EXPECT_NO_THROW((void)j.dump());
}

}  // namespace

#include <fnmatch.h>

#include "runner/case_loader.h"

namespace {

// The linear-time glob agrees with fnmatch(3) (flags 0), and stays fast where glibc backtracks.
TEST(Glob, AgreesWithFnmatchAndIsLinear) {
  const std::vector<std::string> ids = {
      "tonemap/display/hdr1_dev5",      "a", "", "abc", "a*b", "x/y/z", "[a]", "a\\b", "ab]c",
      "tonemap/shaper_pq/dev3_log_ramp"};
  const std::vector<std::string> globs = {"",           "*",
                                          "a",          "?",
                                          "a*",         "*b*",
                                          "*/*",        "tonemap/*",
                                          "[ab]*",      "[!a]*",
                                          "[^a]*",      "[a-c]bc",
                                          "a\\*b",      "\\[a]",
                                          "[]]",        "ab[]]c",
                                          "[",          "a[",
                                          "*[",         "**",
                                          "*?*",        "t*/d*/h*_d?v5",
                                          "*_log_ramp", "tonemap/shaper_pq/dev3_[ls]*_ramp",
                                          "[!]]*"};
  for (const auto& id : ids)
    for (const auto& g : globs)
      if (!g.empty()) {
        EXPECT_EQ(hdrc::matches_filter(id, g), fnmatch(g.c_str(), id.c_str(), 0) == 0)
            << "id '" << id << "' glob '" << g << "'";
      }
  const std::string id(160, 'a');
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_FALSE(hdrc::matches_filter(id, "*a*a*a*a*a*a*a*a*a*a*a*a*a*a*a*a*a*a*b"));
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0);
}

}  // namespace
