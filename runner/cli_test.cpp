// The hdrconform binary end to end: help and exit codes, bad input, and a planted defect.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "core/image.h"
#include "core/pipeline.h"
#include "runner/test_support.h"

#ifndef HDRC_BINARY
#error "HDRC_BINARY must be defined"
#endif
#ifndef HDRC_EXAMPLE_CANDIDATE
#error "HDRC_EXAMPLE_CANDIDATE must be defined"
#endif

namespace fs = std::filesystem;
using namespace hdrc::test;  // runner/test_support.h

namespace {

TEST(Cli, HelpExplainsOptionsAndExitCodes) {
  for (const char* sub :
       {"", "run ", "list ", "devices ", "probe ", "cvars ", "export ", "verify "}) {
    const Ran r = run(std::string(sub) + "--help");
    EXPECT_EQ(r.code, 0) << sub;
    EXPECT_NE(r.out.find("Exit codes:"), std::string::npos) << sub;
    EXPECT_NE(r.out.find("3  engine unavailable"), std::string::npos) << sub;
    EXPECT_NE(r.out.find("4  pass with warnings"), std::string::npos) << sub;
    EXPECT_NE(r.out.find("130  interrupted"), std::string::npos) << sub;
  }
  EXPECT_NE(run("run --help").out.find("--shader-dir"), std::string::npos);
}

// The cvar table lists every cvar with its default and range (docs/spec/ue55.md §10 defaults).
TEST(Cli, CvarTableListsDefaultsAndRanges) {
  const Ran r = run("cvars");
  EXPECT_EQ(r.code, 0);
  for (const char* want :
       {"r.HDR.Display.OutputDevice", "r.HDR.UI.Luminance", "300",
        "r.HDR.Aces.SceneColorMultiplier", "1.5", "FilmSlope", "0.88", "ColorGammaHighlights"})
    EXPECT_NE(r.out.find(want), std::string::npos) << want;
}

TEST(Cli, UsageErrorIsExitCode2) {
  EXPECT_EQ(run("").code, 2);
  EXPECT_EQ(run("frobnicate").code, 2);
  EXPECT_EQ(run("run --engine metal").code, 2);
}

// A bad case file: one clear error, exit 2, and the previous results are left as they were.
TEST(Cli, BadCaseFileRunsNothingAndOverwritesNothing) {
  const fs::path cases = temp_dir("badcases");
  const fs::path out = temp_dir("badout");
  {
    std::ofstream f(cases / "a.json");
    f << R"({"stage": "shaper", "cvars": {"r.HDR.Display.OutputDevice": 12}, "input": {"stimulus": "log_ramp"}})";
  }
  std::ofstream(out / "results.json") << "previous results";
  const Ran r = run("run --cases " + cases.string() + " --out " + out.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find((cases / "a.json").string() +
                       ": /cvars/r.HDR.Display.OutputDevice: cvar r.HDR.Display.OutputDevice = 12 "
                       "is out of range; valid choices: 0 to 9"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(read(out / "results.json"), "previous results");
  EXPECT_FALSE(fs::exists(out / "junit.xml"));
  fs::remove_all(cases);
  fs::remove_all(out);
}

TEST(Cli, UnavailableDeviceSkipsAndExits3) {
  const fs::path out = temp_dir("nodevice");
  const Ran r =
      run("run --filter 'tonemap/shaper_pq/dev3_*' --device no-such-gpu --out " + out.string());
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("SKIP"), std::string::npos);
  EXPECT_NE(r.out.find("0 passed"), std::string::npos);
  EXPECT_NE(read(out / "junit.xml").find("<skipped"), std::string::npos);
  fs::remove_all(out);
}

// Usage errors name the cause and the fix, exit 2 and write nothing (issue 28, CLI polish): a
// misspelt command or option gets the nearest one; a word for a number says it is not one.
TEST(Cli, UsageErrorsNameTheNearestChoiceAndWriteNothing) {
  const fs::path out = temp_dir("usage") / "out";
  struct Row {
    std::string args, says;
  };
  const Row rows[] = {
      {"runn", "unknown command 'runn'; did you mean 'run'?"},
      {"run --filtr x", "unknown option '--filtr' for 'run'; did you mean '--filter'?"},
      {"run --pipe ue55", "did you mean '--pipeline'?"},
      {"verify --candidate-cm x",
       "unknown option '--candidate-cm' for 'verify'; did you mean "
       "'--candidate-cmd'?"},
      {"goldens update --bogus", "unknown option '--bogus' for 'update'; --help lists its options"},
      {"run -j two", "'two' is not a whole number"},
      {"run -j 2000", "'2000' is out of range: 0 (every core) to 1024"},
      {"report " + out.string() + " -j x", "'x' is not a whole number"},
  };
  for (const Row& r : rows) {
    const Ran ran = run(r.args + (r.args.rfind("report", 0) == 0 ? "" : " --out " + out.string()));
    EXPECT_EQ(ran.code, 2) << r.args << "\n" << ran.out;
    EXPECT_NE(ran.out.find(r.says), std::string::npos) << r.args << "\n" << ran.out;
    EXPECT_FALSE(fs::exists(out)) << r.args << " wrote " << out;
  }
  // The top-level help names every pipeline by its title, and probe's help by its name (a
  // pipeline added later is checked without editing this test).
  const Ran help = run("--help");
  const Ran probe_help = run("probe --help");
  for (const hdrc::Pipeline* p : hdrc::pipeline_table()) {
    EXPECT_NE(help.out.find(std::string(p->title)), std::string::npos) << p->title << "\n"
                                                                       << help.out;
    EXPECT_NE(probe_help.out.find(std::string(p->name)), std::string::npos) << p->name << "\n"
                                                                            << probe_help.out;
  }
}

// No Vulkan driver at all (an ICD list naming no file): unavailable with the reason, exit 3.
TEST(Cli, NoVulkanDriverSkipsAndExits3) {
  const fs::path out = temp_dir("noicd");
  const Ran r = run("run --filter 'tonemap/linear_dev8/*' --out " + out.string(),
                    "VK_ICD_FILENAMES=/nonexistent/icd.json ");
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("candidate unavailable: vulkan engine unavailable"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("40 skipped"), std::string::npos) << r.out;
  // The reason says what to check (the loader loaded no driver), not only the VkResult.
  EXPECT_NE(r.out.find("the Vulkan loader could load no driver"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("VK_LOADER_DEBUG=driver"), std::string::npos) << r.out;
  const Ran d = run("devices", "VK_ICD_FILENAMES=/nonexistent/icd.json ");
  EXPECT_EQ(d.code, 3) << d.out;
  EXPECT_NE(d.out.find("could load no driver"), std::string::npos) << d.out;
  fs::remove_all(out);
}

// probe: the README example; lines out match lines in; errors name the line.
TEST(Cli, ProbePrintsNineDigitsPerLine) {
  const fs::path in = temp_dir("probe") / "in.txt";
  std::ofstream(in) << "# scene grey and white\n0.18 0.18 0.18\n\n1 1 1\n";
  const Ran p =
      run("probe --set r.HDR.EnableHDROutput=1 --set r.HDR.Display.OutputDevice=3 "
          "--set r.HDR.Display.ColorGamut=4 --stage device < " +
          in.string());
  EXPECT_EQ(p.code, 0) << p.out;
  // Spec §13: PQ 0.378296436 for grey 0.18 and 0.552035909 for 1.0 (AP1 output: no gamut drift).
  std::istringstream lines(p.out);
  double a, b, c;
  ASSERT_TRUE(lines >> a >> b >> c);
  EXPECT_NEAR(b, 0.378296436, 2e-6);
  ASSERT_TRUE(lines >> a >> b >> c);
  EXPECT_NEAR(b, 0.552035909, 2e-6);
  EXPECT_FALSE(lines >> a);
  EXPECT_NE(p.out.find("0.378296"), std::string::npos);
  const Ran j =
      run("probe --json --stage aces_nits --set r.HDR.EnableHDROutput=1 --set "
          "r.HDR.Display.OutputDevice=3 < " +
          in.string());
  EXPECT_EQ(j.code, 0);
  EXPECT_NE(j.out.find("\"aces_nits\""), std::string::npos) << j.out;
  std::ofstream(in) << "0.18 x 0.18\n";
  const Ran bad = run("probe < " + in.string());
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.out.find("<stdin>: line 1: expected three numbers"), std::string::npos) << bad.out;
  const Ran bad_stage = run("probe --stage foo < " + in.string());
  EXPECT_EQ(bad_stage.code, 2);
  EXPECT_NE(bad_stage.out.find("valid choices: lattice, decoded"), std::string::npos);
  const Ran bad_cvar = run("probe --set r.HDR.Display.OutputDevice=12 < " + in.string());
  EXPECT_EQ(bad_cvar.code, 2);
  EXPECT_NE(bad_cvar.out.find("out of range; valid choices: 0 to 9"), std::string::npos);
  fs::remove_all(in.parent_path());
}

// probe's UI composite and VisualizeHDR false colour, against hand-derived values: an opaque white
// UI at r.HDR.UI.Luminance 300 is PQ(300 nits) = 0.6218628 up to the sRGB→Rec.2020 literal
// product's row sums (4e-10 with UE 5.5's 10-digit literals, 8.6e-6 with the pre-5.3 ones; the
// probe prints 9 digits); Colorize(0) is pure blue for a luminance below the histogram.
TEST(Cli, ProbeUiCompositeAndFalseColour) {
  const fs::path dir = temp_dir("probe_ui");
  std::ofstream(dir / "in.txt") << "0.5 0.5 0.5\n";
  const Ran ui =
      run("probe --set r.HDR.EnableHDROutput=1 --set r.HDR.Display.OutputDevice=3 "
          "--stage ui_composite --ui 1,1,1,1 < " +
          (dir / "in.txt").string());
  EXPECT_EQ(ui.code, 0) << ui.out;
  std::istringstream l(ui.out);
  double r, g, b;
  ASSERT_TRUE(l >> r >> g >> b);
  for (double v : {r, g, b}) EXPECT_NEAR(v, 0.621862837, 2e-9);
  const Ran sdr = run("probe --stage ui_composite < " + (dir / "in.txt").string());
  EXPECT_EQ(sdr.code, 2);
  EXPECT_NE(sdr.out.find("HDR back buffers only"), std::string::npos) << sdr.out;
  std::ofstream(dir / "in.txt") << "1e-6 1e-6 1e-6\n";
  const Ran fc = run("probe --stage visualize_false_colour < " + (dir / "in.txt").string());
  EXPECT_EQ(fc.code, 0);
  EXPECT_EQ(fc.out, "0 0 1\n");
  fs::remove_all(dir);
}

// Planted defect: one output pixel of the shaper stage altered by 0.1 %. The suite must fail,
// naming the case and locating the pixel and channel exactly. (A one-ULP change of PQ's m2 is
// below lavapipe's own float32 error here, see docs/precision.md.)
TEST(Cli, PlantedDefectOnePixelFailsAndIsLocated) {
  const fs::path shaders = temp_dir("defect_shaders");
  const fs::path out = temp_dir("defect_out");
  fs::copy(fs::path(HDRC_SOURCE_DIR) / "gpu/shaders", shaders, fs::copy_options::recursive);
  std::string text = read(shaders / "stages/shaper.comp");
  const std::string from = "  out_px[i] = vec4(rgb, px.a);";
  const size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, from.size(), "  if (i == 517u) rgb.g *= 1.001;\n" + from);
  std::ofstream(shaders / "stages/shaper.comp") << text;

  const Ran r = run("run --filter 'tonemap/shaper_pq/dev3_log_ramp' --shader-dir " +
                    shaders.string() + " --out " + out.string());
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("FAIL  tonemap/shaper_pq/dev3_log_ramp  linear_rel "), std::string::npos)
      << r.out;
  // Pixel 517 of the log ramp is 0.01104 scene-linear = 1.1 nits grey: band 1-10 nits.
  EXPECT_NE(r.out.find(": 1 of 12288 values over (0.00814 %, allowed 0 %) at (517, 0) G, 1-10 "
                       "nits: input 0.0110410592 reference 0.0110410592 candidate "),
            std::string::npos)
      << r.out;
  const auto results = nlohmann::json::parse(read(out / "results.json"));
  const auto& c = results["cases"][0];
  EXPECT_EQ(c["verdict"], "FAIL");
  const auto& w = c["worst_pixel"];
  EXPECT_EQ(w["x"], 517);
  EXPECT_EQ(w["y"], 0);
  EXPECT_EQ(w["channel"], "G");
  EXPECT_EQ(w["band"], "1-10");
  EXPECT_EQ(w["metric"], "linear_rel");
  // The values are the images' own: the input and reference as written, the candidate 0.1 % off
  // (plus lavapipe's float32 error, under the case's 2.5e-4); results.json keeps 9 significant
  // digits, each image's float32 value exactly.
  auto in = hdrc::read_image((out / "cases/tonemap/shaper_pq/dev3_log_ramp/input.exr").string());
  auto ref =
      hdrc::read_image((out / "cases/tonemap/shaper_pq/dev3_log_ramp/reference.exr").string());
  auto cand =
      hdrc::read_image((out / "cases/tonemap/shaper_pq/dev3_log_ramp/candidate.exr").string());
  ASSERT_TRUE(in.ok() && ref.ok() && cand.ok());
  EXPECT_EQ(static_cast<float>(w["input"].get<double>()), in->px(517, 0)[1]);
  EXPECT_EQ(static_cast<float>(w["reference"].get<double>()), ref->px(517, 0)[1]);
  EXPECT_EQ(static_cast<float>(w["candidate"].get<double>()), cand->px(517, 0)[1]);
  EXPECT_NEAR(w["candidate"].get<double>() / w["reference"].get<double>(), 1.001, 2.5e-4);
  EXPECT_EQ(c["stats"]["overall"]["linear_rel"]["over"], 1);
  EXPECT_EQ(c["stats"]["bands"][2]["metrics"]["linear_rel"]["over"], 1);
  EXPECT_EQ(c["nonfinite"]["mismatch"], 0);
  EXPECT_NE(read(out / "junit.xml").find("<failure message=\"linear_rel "), std::string::npos);
  EXPECT_NE(read(out / "junit.xml").find("at (517, 0) G, 1-10 nits"), std::string::npos);
  fs::remove_all(shaders);
  fs::remove_all(out);
}

// ---- issue 5: sharding, parallelism, interruption, export/verify, warnings --------------------

std::vector<std::string> listed_ids(const std::string& args) {
  const Ran r = run("list " + args);
  EXPECT_EQ(r.code, 0) << r.out;
  std::vector<std::string> ids;
  std::istringstream lines(r.out);
  for (std::string line; std::getline(lines, line);)
    if (!line.empty()) ids.push_back(line.substr(0, line.find("  (")));
  return ids;
}

// --shard K/N over N = 1, 2, 3, 7: the shards are disjoint and together the unsharded list.
TEST(Cli, ShardsPartitionTheCaseList) {
  const std::vector<std::string> all = listed_ids("");
  ASSERT_GT(all.size(), 20u);
  for (int n : {1, 2, 3, 7}) {
    std::multiset<std::string> seen;
    for (int k = 1; k <= n; ++k) {
      const auto part = listed_ids("--shard " + std::to_string(k) + "/" + std::to_string(n));
      // Balanced by cost (runner/run.h: select_shard; cli_report_test.cpp checks the balance).
      EXPECT_FALSE(part.empty()) << k << "/" << n;
      seen.insert(part.begin(), part.end());
    }
    EXPECT_EQ(seen, std::multiset<std::string>(all.begin(), all.end())) << "N = " << n;
  }
  // run --shard runs exactly the cases list --shard names.
  const fs::path out = temp_dir("shard_run");
  const Ran r = run("run --engine reference --filter 'tonemap/shaper_pq/*' --shard 2/3 --out " +
                    out.string());
  EXPECT_EQ(r.code, 0) << r.out;
  const auto results = nlohmann::json::parse(read(out / "results.json"));
  std::vector<std::string> ran;
  for (const auto& c : results["cases"]) ran.push_back(c["id"]);
  EXPECT_EQ(ran, listed_ids("--filter 'tonemap/shaper_pq/*' --shard 2/3"));
  EXPECT_EQ(results["shard"], "2/3");
  EXPECT_EQ(run("list --shard 4/3").code, 2);
  EXPECT_EQ(run("list --shard x").code, 2);
  fs::remove_all(out);
}

// -j N: each worker has its own engines; the output is in case order whatever the scheduling.
TEST(Cli, ParallelRunsGiveTheSameOutputInTheSameOrder) {
  const fs::path a = temp_dir("j1"), b = temp_dir("j4");
  const std::string filter = "--engine reference --filter 'tonemap/shaper_*' ";
  const Ran r1 = run("run -j 1 " + filter + "--out " + a.string());
  const Ran r4 = run("run -j 4 " + filter + "--out " + b.string());
  EXPECT_EQ(r1.code, 0) << r1.out;
  EXPECT_EQ(r4.code, 0) << r4.out;
  auto case_lines = [](const std::string& out) {
    std::string lines;
    std::istringstream in(out);
    for (std::string l; std::getline(in, l);)
      if (l.rfind("[", 0) == 0) lines += l + "\n";
    return lines;
  };
  EXPECT_EQ(case_lines(r1.out), case_lines(r4.out));
  EXPECT_FALSE(case_lines(r1.out).empty());
  auto ja = nlohmann::json::parse(read(a / "results.json"));
  auto jb = nlohmann::json::parse(read(b / "results.json"));
  EXPECT_EQ(jb["jobs"], 4);
  ASSERT_EQ(ja["cases"].size(), jb["cases"].size());
  for (size_t i = 0; i < ja["cases"].size(); ++i) {
    EXPECT_EQ(ja["cases"][i]["id"], jb["cases"][i]["id"]);
    EXPECT_EQ(ja["cases"][i]["stats"], jb["cases"][i]["stats"]);
  }
  fs::remove_all(a);
  fs::remove_all(b);
}

// Ctrl-C: the cases already finished are written and readable, the rest are NOT_RUN, exit 130.
TEST(Cli, InterruptWritesFinishedCasesAndMarksTheRestNotRun) {
  const fs::path out = temp_dir("sigint");
  int pipefd[2];
  ASSERT_EQ(pipe(pipefd), 0);
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    dup2(pipefd[1], 1);
    close(pipefd[0]);
    execl(HDRC_BINARY, HDRC_BINARY, "run", "--engine", "reference", "-j", "1", "--out", out.c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  close(pipefd[1]);
  FILE* child_out = fdopen(pipefd[0], "r");
  std::string text;
  int lines = 0;
  char buf[4096];
  while (lines < 3 && fgets(buf, sizeof buf, child_out)) {
    text += buf;
    lines += buf[0] == '[';
  }
  ASSERT_EQ(lines, 3) << text;
  kill(pid, SIGINT);
  while (fgets(buf, sizeof buf, child_out)) text += buf;
  fclose(child_out);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << text;
  EXPECT_EQ(WEXITSTATUS(status), 130) << text;
  const auto results = nlohmann::json::parse(read(out / "results.json"));
  EXPECT_TRUE(results["interrupted"].get<bool>());
  EXPECT_EQ(results["summary"]["exit_code"], 130);
  EXPECT_EQ(results["cases"].size(), listed_ids("").size());  // every case is listed
  int finished = 0, not_run = 0;
  for (const auto& c : results["cases"]) {
    if (c["verdict"] == "NOT_RUN") {
      ++not_run;
    } else {
      ++finished;
      for (const auto& [name, path] : c["images"].items())
        EXPECT_TRUE(hdrc::read_image((out / path.get<std::string>()).string()).ok()) << path;
    }
  }
  EXPECT_GE(finished, 3);
  EXPECT_GT(not_run, 0);
  EXPECT_NE(read(out / "junit.xml").find("NOT_RUN: not run: the run was interrupted"),
            std::string::npos);
  fs::remove_all(out);
}

// Six one-case files a..f and a candidate command that always fails (exit 1: an ERROR).
std::vector<std::string> write_six_cases(const fs::path& t) {
  std::vector<std::string> ids;
  for (const char* name : {"a", "b", "c", "d", "e", "f"}) {
    write(t / "cases" / (std::string(name) + ".json"),
          R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 8, "height": 2}})");
    ids.push_back(std::string(name) + "/log_ramp");
  }
  write(t / "fail.sh", "#!/bin/sh\nexit 1\n");
  return ids;
}

std::vector<std::string> result_ids(const fs::path& out) {
  std::vector<std::string> ids;
  const auto doc = nlohmann::json::parse(read(out / "results.json"));
  for (const auto& c : doc["cases"]) ids.push_back(c["id"].get<std::string>());
  return ids;
}

// --filter '!PATTERN' excludes, whatever its place among the patterns (gtest's POS-NEG,
// pytest's "not"); exclusions alone start from every case; a bare '!' is an error.
TEST(Cli, FilterExclusionPatterns) {
  const auto all = listed_ids("");
  const auto shaper = listed_ids("--filter 'tonemap/shaper_pq/*'");
  const auto dev3 = listed_ids("--filter 'tonemap/shaper_pq/dev3_*'");
  ASSERT_GT(dev3.size(), 1u);
  ASSERT_GT(shaper.size(), dev3.size());
  std::vector<std::string> want;
  for (const auto& id : shaper)
    if (std::find(dev3.begin(), dev3.end(), id) == dev3.end()) want.push_back(id);
  EXPECT_EQ(listed_ids("--filter 'tonemap/shaper_pq/*,!tonemap/shaper_pq/dev3_*'"), want);
  EXPECT_EQ(listed_ids("--filter '!shaper_pq/dev3_' --filter 'tonemap/shaper_pq/*'"), want);
  EXPECT_EQ(listed_ids("--filter '!tonemap/shaper_pq/*'").size(), all.size() - shaper.size());
  EXPECT_EQ(listed_ids("--filter '!=" + dev3[0] + "'").size(), all.size() - 1);
  const Ran bare = run("list --filter 'lut,!'");
  EXPECT_EQ(bare.code, 2) << bare.out;
  EXPECT_NE(bare.out.find("--filter: the pattern '!' names no case"), std::string::npos)
      << bare.out;
  const Ran none = run("list --filter '!tonemap,tonemap/shaper_pq/*'");
  EXPECT_EQ(none.code, 2) << none.out;
  EXPECT_NE(none.out.find("no case matches --filter '!tonemap,tonemap/shaper_pq/*'"),
            std::string::npos)
      << none.out;
}

// --maxfail N: after N failures no case starts; the output is complete and consistent (every
// case listed, the rest NOT_RUN and counted, junit and report written), exit 1.
TEST(Cli, MaxfailStopsAfterNFailuresAndPublishesACompleteRun) {
  const fs::path t = temp_dir("maxfail");
  const auto ids = write_six_cases(t);
  const Ran r =
      run("verify -j 1 --maxfail 2 --cases " + (t / "cases").string() + " --out " +
          (t / "out").string() + " --candidate-cmd 'sh " + (t / "fail.sh").string() + " {output}'");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("stopped: --maxfail 2: 2 cases failed; 4 cases not run (NOT_RUN)"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find(", 4 not run in "), std::string::npos) << r.out;  // the headline
  const auto doc = nlohmann::json::parse(read(t / "out/results.json"));
  EXPECT_EQ(result_ids(t / "out"), ids);  // every case, in case order
  EXPECT_EQ(doc["summary"]["error"], 2);
  EXPECT_EQ(doc["summary"]["not_run"], 4);
  EXPECT_EQ(doc["summary"]["exit_code"], 1);
  EXPECT_EQ(doc["max_fail"]["limit"], 2);
  EXPECT_EQ(doc["max_fail"]["stopped"], true);
  EXPECT_FALSE(doc["interrupted"].get<bool>());  // not a Ctrl-C: exit 1, not 130
  for (size_t i = 2; i < ids.size(); ++i) {
    EXPECT_EQ(doc["cases"][i]["verdict"], "NOT_RUN") << ids[i];
    EXPECT_EQ(doc["cases"][i]["reason"], "not run: --maxfail 2 cases had failed") << ids[i];
  }
  const std::string junit = read(t / "out/junit.xml");
  EXPECT_NE(junit.find("tests=\"6\" failures=\"0\" errors=\"2\" skipped=\"4\""), std::string::npos)
      << junit;
  EXPECT_TRUE(fs::is_regular_file(t / "out/report/index.html"));
  // Without --maxfail every case runs; --maxfail 0 is a usage error.
  const Ran all =
      run("verify -j 1 --cases " + (t / "cases").string() + " --out " + (t / "all").string() +
          " --candidate-cmd 'sh " + (t / "fail.sh").string() + " {output}'");
  EXPECT_EQ(all.code, 1);
  EXPECT_EQ(nlohmann::json::parse(read(t / "all/results.json"))["summary"]["error"], 6);
  EXPECT_EQ(nlohmann::json::parse(read(t / "all/results.json"))["max_fail"], nullptr);
  EXPECT_EQ(run("run --engine reference --maxfail 0 --cases " + (t / "cases").string()).code, 2);
  fs::remove_all(t);
}

// --failed-first PREV: PREV's failed cases run first, the rest after, each in case order; PREV's
// results.json is read like --rerun-failed's (a missing one is bad input, exit 2, naming it).
TEST(Cli, FailedFirstRunsThePreviousFailuresFirst) {
  const fs::path t = temp_dir("failed_first");
  const auto ids = write_six_cases(t);  // a b c d e f
  const std::string cases = " --cases " + (t / "cases").string();
  // PREV: d and f errored (the failing candidate ran only them).
  const Ran prev = run("verify -j 1 --filter '=" + ids[3] + ",=" + ids[5] + "'" + cases +
                       " --out " + (t / "prev").string() + " --candidate-cmd 'sh " +
                       (t / "fail.sh").string() + " {output}'");
  ASSERT_EQ(prev.code, 1) << prev.out;
  const Ran r = run("run --engine reference -j 2 --failed-first " + (t / "prev").string() + cases +
                    " --out " + (t / "out").string());
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("failed first: 2 case(s) that failed in " + (t / "prev").string() +
                       "/results.json run first"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(result_ids(t / "out"),
            (std::vector<std::string>{ids[3], ids[5], ids[0], ids[1], ids[2], ids[4]}));
  // The reproduce command does not repeat it (it chooses the order, not what a case computes).
  const auto doc = nlohmann::json::parse(read(t / "out/results.json"));
  EXPECT_EQ(doc["provenance"]["reproduce"].get<std::string>().find("--failed-first"),
            std::string::npos);
  const Ran missing = run("run --engine reference --failed-first " + (t / "nope").string() + cases +
                          " --out " + (t / "out2").string());
  EXPECT_EQ(missing.code, 2) << missing.out;
  EXPECT_NE(missing.out.find("--failed-first: " + (t / "nope/results.json").string()),
            std::string::npos)
      << missing.out;
  EXPECT_FALSE(fs::exists(t / "out2/results.json"));
  fs::remove_all(t);
}

bool vulkan_available() {
  return run("devices").code == 0;
}

// A test that needs a Vulkan device fails without one (a green run must have checked the GPU
// path), unless HDRC_ALLOW_NO_VULKAN=1 says the machine has none: then it is skipped.
#define HDRC_REQUIRE_VULKAN()                                                                      \
  do {                                                                                             \
    if (!vulkan_available()) {                                                                     \
      if (hdrc::test::vulkan_optional())                                                           \
        GTEST_SKIP() << "no Vulkan device (HDRC_ALLOW_NO_VULKAN)";                                 \
      FAIL() << "no Vulkan device; on a machine without Vulkan HDRC_ALLOW_NO_VULKAN=1 skips this"; \
    }                                                                                              \
  } while (0)

// export, then a port (examples/vulkan_candidate, hdrconform's own GPU engine reading only the
// exported files) renders each case into DIR/<id>.exr, then verify --candidate-dir: the same
// verdicts and statistics as `run`.
TEST(Cli, ExportThenVerifyCandidateDirMatchesRun) {
  HDRC_REQUIRE_VULKAN();
  // Gamuts 2 and 3: gamut 0's ramps are known limits of the vulkan engine (cases/known_limits.json,
  // sign-boundary NaN), which `verify` of a candidate directory does not apply.
  const std::string filter = "--filter 'tonemap/linear_dev7/gamut[23]_[ls]*_ramp' ";
  const fs::path exported = temp_dir("export"), cand = temp_dir("cand"), ran = temp_dir("ran"),
                 verified = temp_dir("verified");
  const Ran e = run("export " + filter + "--out " + exported.string());
  ASSERT_EQ(e.code, 0) << e.out;
  const auto manifest = nlohmann::json::parse(read(exported / "manifest.json"));
  ASSERT_GE(manifest["cases"].size(), 2u);  // log and special ramps of gamuts 2 and 3
  ASSERT_LE(manifest["cases"].size(), 8u);
  for (const auto& c : manifest["cases"]) {
    const std::string id = c["id"];
    fs::create_directories((cand / id).parent_path());
    const std::string cmd = std::string(HDRC_EXAMPLE_CANDIDATE) + " --params " +
                            (exported / c["dir"].get<std::string>() / "params.json").string() +
                            " --output " + (cand / (id + ".exr")).string();
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  }
  const Ran r = run("run " + filter + "--out " + ran.string());
  const Ran v =
      run("verify " + filter + "--candidate-dir " + cand.string() + " --out " + verified.string());
  EXPECT_EQ(r.code, v.code) << r.out << v.out;
  const auto jr = nlohmann::json::parse(read(ran / "results.json"));
  const auto jv = nlohmann::json::parse(read(verified / "results.json"));
  EXPECT_EQ(jv["command"], "verify");
  ASSERT_EQ(jr["cases"].size(), jv["cases"].size());
  for (size_t i = 0; i < jr["cases"].size(); ++i) {
    EXPECT_EQ(jr["cases"][i]["id"], jv["cases"][i]["id"]);
    EXPECT_EQ(jr["cases"][i]["verdict"], jv["cases"][i]["verdict"]);
    EXPECT_EQ(jr["cases"][i]["stats"], jv["cases"][i]["stats"]) << jr["cases"][i]["id"];
  }
  for (const auto& p : {exported, cand, ran, verified}) fs::remove_all(p);
}

// Missing and corrupted candidate images: each case says what is wrong, the others still run.
TEST(Cli, VerifyReportsMissingAndCorruptCandidatesPerCase) {
  const fs::path cand = temp_dir("badcand"), out = temp_dir("badcand_out");
  const auto ids = listed_ids("--filter 'tonemap/linear_dev8/gamut[0-4]_log_ramp'");
  ASSERT_EQ(ids.size(), 5u);
  // A good image (the reference's own output), then damaged copies.
  const fs::path ref_out = temp_dir("badcand_ref");
  ASSERT_EQ(run("run --engine reference --filter '" + ids[0] + "' --out " + ref_out.string()).code,
            0);
  const fs::path good = ref_out / "cases" / ids[0] / "reference.exr";
  auto place = [&](const std::string& id) {
    fs::create_directories((cand / id).parent_path());
    return cand / (id + ".exr");
  };
  fs::copy_file(good, place(ids[0]));  // 0: good
  // 1: missing. 2: truncated to half its bytes.
  fs::copy_file(good, place(ids[2]));
  fs::resize_file(place(ids[2]), fs::file_size(good) / 2);
  // 3: wrong size.
  ASSERT_TRUE(hdrc::write_exr(place(ids[3]).string(), hdrc::Image(10, 1)).ok());
  // 4: two channels.
  {
    OIIO::ImageSpec spec(1024, 4, 2, OIIO::TypeDesc::FLOAT);
    std::vector<float> px(1024 * 4 * 2, 0.5f);
    auto o = OIIO::ImageOutput::create(place(ids[4]).string());
    ASSERT_TRUE(o && o->open(place(ids[4]).string(), spec) &&
                o->write_image(OIIO::TypeDesc::FLOAT, px.data()) && o->close());
  }
  const Ran v = run("verify --filter 'tonemap/linear_dev8/gamut[0-4]_log_ramp' --candidate-dir " +
                    cand.string() + " --out " + out.string());
  EXPECT_EQ(v.code, 1) << v.out;
  const auto results = nlohmann::json::parse(read(out / "results.json"));
  std::map<std::string, nlohmann::json> by_id;
  for (const auto& c : results["cases"]) by_id[c["id"]] = c;
  EXPECT_EQ(by_id[ids[0]]["verdict"], "PASS") << by_id[ids[0]]["reason"];
  EXPECT_EQ(by_id[ids[1]]["verdict"], "MISSING");
  EXPECT_EQ(by_id[ids[1]]["reason"], "missing candidate image " + place(ids[1]).string());
  auto reason = [&](int i) { return by_id[ids[i]]["reason"].get<std::string>(); };
  EXPECT_EQ(by_id[ids[2]]["verdict"], "ERROR");
  EXPECT_NE(reason(2).find(place(ids[2]).string() + ": bad candidate image: cannot"),
            std::string::npos)
      << reason(2);
  EXPECT_EQ(by_id[ids[3]]["verdict"], "ERROR");
  EXPECT_EQ(reason(3), "candidate-dir: the candidate image is 10x1, the reference 1024x4");
  EXPECT_EQ(by_id[ids[4]]["verdict"], "ERROR");
  EXPECT_EQ(reason(4), "candidate-dir: " + place(ids[4]).string() +
                           ": bad candidate image: image has 2 channel(s); valid choices: 3 (RGB) "
                           "or 4 (RGBA) channels");
  EXPECT_EQ(results["summary"]["missing"], 1);
  EXPECT_NE(read(out / "junit.xml").find("<failure message=\"MISSING: missing candidate image"),
            std::string::npos);
  // Not a directory: bad input, nothing run.
  EXPECT_EQ(run("verify --candidate-dir /nonexistent/dir --out " + out.string()).code, 2);
  EXPECT_EQ(run("verify --out " + out.string()).code, 2);
  for (const auto& p : {cand, out, ref_out}) fs::remove_all(p);
}

// verify --candidate-cmd with the example candidate in examples/: the way to verify a port.
TEST(Cli, VerifyCandidateCmdWithTheExampleCandidate) {
  HDRC_REQUIRE_VULKAN();
  const fs::path out = temp_dir("cmd");
  const Ran v = run("verify --filter 'tonemap/shaper_pq/dev3_[ls]*_ramp' -j 2 --candidate-cmd '" +
                    std::string(HDRC_EXAMPLE_CANDIDATE) +
                    " --params {params} --output {output}' --out " + out.string());
  EXPECT_EQ(v.code, 0) << v.out;
  EXPECT_NE(v.out.find("2 passed"), std::string::npos) << v.out;
  const fs::path dir = out / "cases/tonemap/shaper_pq/dev3_log_ramp";
  EXPECT_TRUE(fs::exists(dir / "params.json"));
  EXPECT_TRUE(hdrc::read_image((dir / "candidate.exr").string()).ok());
  fs::remove_all(out);
}

// A command that fails or hangs is an error for its case; the run goes on. Case data is never
// interpreted by a shell: {id} holds '/' and the template's quotes group words.
TEST(Cli, VerifyCandidateCmdFailureAndTimeoutArePerCaseErrors) {
  const fs::path out = temp_dir("cmdfail");
  const std::string filter = "--filter 'tonemap/linear_dev8/gamut[01]_log_ramp' ";
  Ran v = run("verify " + filter +
              "--candidate-cmd 'sh -c \"echo no GPU for $0 >&2; exit 3\" {id} {output}' --out " +
              out.string());
  EXPECT_EQ(v.code, 1) << v.out;
  auto results = nlohmann::json::parse(read(out / "results.json"));
  ASSERT_EQ(results["cases"].size(), 2u);
  for (const auto& c : results["cases"]) {
    EXPECT_EQ(c["verdict"], "ERROR");
    EXPECT_NE(c["reason"].get<std::string>().find(
                  "candidate command exited with status 3; output: no GPU for " +
                  c["id"].get<std::string>()),
              std::string::npos)
        << c["reason"];
  }
  v = run("verify " + filter +
          "-j 2 --timeout 0.5 --candidate-cmd 'sh -c \"sleep 30\" {output}' --out " + out.string());
  EXPECT_EQ(v.code, 1) << v.out;
  results = nlohmann::json::parse(read(out / "results.json"));
  for (const auto& c : results["cases"])
    EXPECT_NE(c["reason"].get<std::string>().find(
                  "timed out after 0.5 s (killed with every process it started); a slower port "),
              std::string::npos)
        << c["reason"];
  EXPECT_LT(results["wall_seconds"].get<double>(), 10);
  v = run("verify " + filter + "--candidate-cmd 'true {output}' --out " + out.string());
  EXPECT_NE(v.out.find("candidate command exited 0 but wrote no image"), std::string::npos)
      << v.out;
  EXPECT_EQ(run("verify --candidate-cmd 'convert {input}' --out " + out.string()).code, 2);
  EXPECT_EQ(run("verify --candidate-cmd 'x \"unterminated {output}' --out " + out.string()).code,
            2);
  fs::remove_all(out);
}

// A warn level: every case passes but one is over its warn level: exit 4. A per-backend overlay
// (cases/tolerance_overlays.json) tightens it into a failure, naming the overlay as the source.
TEST(Cli, WarnLevelGivesExitCode4AndOverlaysApply) {
  const fs::path cases = temp_dir("warn_cases"), ref_out = temp_dir("warn_ref"),
                 cand = temp_dir("warn_cand"), out = temp_dir("warn_out");
  std::ofstream(cases / "w.json") << R"({"stage": "shaper", "input": {"stimulus": "log_ramp"},
    "tolerance": {"linear_rel": {"max": 1e-2, "warn": 1e-4}, "rel_floor": 1e-6,
                  "pq_code10": null, "reason": "test"}})";
  ASSERT_EQ(
      run("run --engine reference --cases " + cases.string() + " --out " + ref_out.string()).code,
      0);
  auto img = hdrc::read_image((ref_out / "cases/w/log_ramp/reference.exr").string());
  ASSERT_TRUE(img.ok());
  for (double& v : img->data) v *= 1.001;
  ASSERT_TRUE(hdrc::write_exr((cand / "w/log_ramp.exr").string(), *img).ok());
  const std::string verify =
      "verify --cases " + cases.string() + " --candidate-dir " + cand.string() + " --out ";
  Ran v = run(verify + out.string());
  EXPECT_EQ(v.code, 4) << v.out;
  EXPECT_NE(v.out.find("warning: linear_rel 0.001 over its warn level 0.0001"), std::string::npos)
      << v.out;
  auto results = nlohmann::json::parse(read(out / "results.json"));
  EXPECT_EQ(results["cases"][0]["verdict"], "PASS");
  EXPECT_TRUE(results["cases"][0]["warn"].get<bool>());
  EXPECT_EQ(results["summary"]["warned"], 1);
  EXPECT_NE(read(out / "junit.xml").find("<system-out>warning: linear_rel"), std::string::npos);

  std::ofstream(cases / "tolerance_overlays.json") << R"({"overlays": [
    {"engine": "candidate-dir", "cases": "w/*",
     "tolerance": {"linear_rel": 1e-4, "reason": "this backend must be exact"}}]})";
  v = run(verify + out.string());
  EXPECT_EQ(v.code, 1) << v.out;
  results = nlohmann::json::parse(read(out / "results.json"));
  EXPECT_EQ(results["cases"][0]["verdict"], "FAIL");
  EXPECT_EQ(results["cases"][0]["tolerance"]["source"],
            (cases / "w.json").string() + ": /tolerance + overlay " +
                (cases / "tolerance_overlays.json").string() + ": /overlays/0/tolerance");
  // An overlay without a reason is bad input: nothing runs.
  std::ofstream(cases / "tolerance_overlays.json")
      << R"({"overlays": [{"engine": "candidate-dir", "tolerance": {"linear_rel": 1e-4}}]})";
  v = run(verify + out.string());
  EXPECT_EQ(v.code, 2) << v.out;
  EXPECT_NE(v.out.find("/overlays/0/tolerance/reason: a tolerance must say why"), std::string::npos)
      << v.out;
  for (const auto& p : {cases, ref_out, cand, out}) fs::remove_all(p);
}

}  // namespace

// ---- issue 6: planted constant defects in a copy of the suite's shaders ----------------------

// Runs lut/devices/* with one constant of a copied shader library changed and returns the ids of
// the failing cases (results.json) and the console output.
std::vector<std::string> failing_with_planted_constant(const std::string& lib_file,
                                                       const std::string& from,
                                                       const std::string& to, std::string* out) {
  return planted_shader_failures("lib/" + lib_file, from, to, "--filter 'lut/devices/*'", out);
}

// One ACES matrix entry changed in its 4th decimal (AP0_2_AP1_MAT row 2, 1.1762296998 →
// 1.1763296998, where the RRT reads it; the literal itself comes from the generated interface):
// the HDR10/ACES devices 3 and 4 fail in the narrow output gamuts (sRGB, P3), where the change
// moves stored texels by 8 and 23 10-bit codes; the located texel is named. A 5th-decimal change
// (8.5e-6 relative) is below the float32 noise a dark channel of a bright texel carries into PQ
// (kShaderNoise, 2^-15 of the texel's largest channel: lavapipe itself moves such channels by 2
// codes), so the stored LUT cannot tell it from noise there; it is caught per pixel against the
// reference by gpu/aces_shader_test.cpp (PlantedDefectsAreCaughtAndLocated).
TEST(Cli, PlantedAcesMatrixEntryFailsTheAcesDevices) {
  std::string out;
  const auto failing = failing_with_planted_constant(
      "aces_rrt.glsl", "aces_mul(AP0_2_AP1_MAT, aces)",
      "aces_mul(AP0_2_AP1_MAT + mat3(0.0, 0.0, 0.0, 0.0, 1e-4, 0.0, 0.0, 0.0, 0.0), aces)", &out);
  const std::vector<std::string> want = {"lut/devices/dev3_gamut0", "lut/devices/dev3_gamut1",
                                         "lut/devices/dev4_gamut0", "lut/devices/dev4_gamut1"};
  EXPECT_EQ(failing, want) << out;
  EXPECT_NE(out.find("FAIL  lut/devices/dev3_gamut0  linear_abs 0.00782 over its hard cap 0.00098 "
                     "at lattice (r 11, g 3, b 13) = pixel (219, 3) G"),
            std::string::npos)
      << out;
}

// FilmToneMap's grey match point 0.18 → 0.1801 (4th decimal): every device on the film path
// fails, in every gamut (SDR 0-2 and 9, the film colour without gamma), and no ACES or linear
// device does (3-8 do not read it). A 5th-decimal
// change is below one 10-bit storage step here and is caught by the texel-level probe test
// (gpu/grading_shader_test.cpp).
TEST(Cli, PlantedFilmToneMapConstantFailsTheFilmPathDevices) {
  std::string out;
  const auto failing =
      failing_with_planted_constant("film_tonemap.glsl", "const float FILM_MATCH = 0.18;",
                                    "const float FILM_MATCH = 0.1801;", &out);
  std::vector<std::string> want;
  for (int device : {0, 1, 2, 9})
    for (int gamut = 0; gamut < 5; ++gamut)
      want.push_back("lut/devices/dev" + std::to_string(device) + "_gamut" + std::to_string(gamut));
  EXPECT_EQ(failing, want) << out;
}
