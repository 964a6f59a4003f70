// verify's candidate protocol end to end (declining a case or a stage, UNSUPPORTED, --require-all,
// --candidate-limits, reproduce commands), the standalone example, `--reference analytic`, and the
// messages that point at a cause (lattice point, RGB triplet, ΔE_ITP, the rule behind a NaN).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/pipeline.h"
#include "runner/diff.h"
#include "runner/json_schema.h"
#include "runner/test_support.h"

#ifndef HDRC_BINARY
#error "HDRC_BINARY must be defined"
#endif

namespace fs = std::filesystem;
using namespace hdrc::test;  // runner/test_support.h

namespace {

nlohmann::ordered_json results(const fs::path& out) {
  return nlohmann::ordered_json::parse(read(out / "results.json"));
}

int count_verdict(const nlohmann::ordered_json& r, const std::string& v) {
  int n = 0;
  for (const auto& c : r["cases"]) n += c["verdict"] == v;
  return n;
}

const std::string kShaperPq = "'tonemap/shaper_pq/*'";

// A candidate that declines every case (exit 77) with a reason: UNSUPPORTED, never a pass; the run
// exits 0 without --require-all and 1 with it; JUnit reports them as skipped.
TEST(CandidateProtocol, DeclinedCaseIsUnsupportedAndOnlyFailsUnderRequireAll) {
  const fs::path out = temp_dir("decline_case");
  const std::string cmd =
      "--candidate-cmd \"sh -c 'echo not my device; exit 77' {output}\" --filter "
      "'tonemap/shaper_pq/dev3_*' -j 1 --out " +
      out.string();
  Ran r = run("verify " + cmd);
  EXPECT_EQ(r.code, 0) << r.out;
  auto j = results(out);
  const int n = static_cast<int>(j["cases"].size());
  ASSERT_GT(n, 1);
  EXPECT_EQ(count_verdict(j, "UNSUPPORTED"), n);
  EXPECT_EQ(j["summary"]["unsupported"], n);
  EXPECT_EQ(j["summary"]["pass"], 0);
  EXPECT_EQ(j["cases"][0]["reason"], "the candidate declined this case (exit 77): not my device");
  EXPECT_NE(r.out.find(std::to_string(n) + " unsupported"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("UNSUPPORTED (never a pass):"), std::string::npos) << r.out;
  const std::string junit = read(out / "junit.xml");
  EXPECT_NE(junit.find("skipped=\"" + std::to_string(n) + "\""), std::string::npos) << junit;
  EXPECT_NE(junit.find("<skipped message=\"UNSUPPORTED: the candidate declined this case"),
            std::string::npos);
  r = run("verify --require-all " + cmd);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_EQ(results(out)["require_all"], true);
  fs::remove_all(out);
}

// Exit 78 declines the stage: the first case runs the command, every later case of that stage is
// UNSUPPORTED without the command being started again (the command logs each start).
TEST(CandidateProtocol, DeclinedStageStartsNoLaterCaseOfIt) {
  const fs::path out = temp_dir("decline_stage");
  // Beside OUT, not in it: a run replaces OUT whole when it publishes (runner/output_set.h).
  const fs::path log = temp_dir("decline_stage_log") / "starts.log";
  const Ran r = run("verify --candidate-cmd \"sh -c 'echo {id} >> " + log.string() +
                    "; echo no shaper here; exit 78' {output}\" --filter " + kShaperPq +
                    " -j 2 --out " + out.string());
  EXPECT_EQ(r.code, 0) << r.out;
  auto j = results(out);
  const int n = static_cast<int>(j["cases"].size());
  ASSERT_GT(n, 10);
  EXPECT_EQ(count_verdict(j, "UNSUPPORTED"), n);
  std::istringstream starts(read(log));
  int lines = 0;
  for (std::string l; std::getline(starts, l);) ++lines;
  // -j 2: each worker may have started one case before the other's decline was recorded.
  EXPECT_GE(lines, 1);
  EXPECT_LE(lines, 2) << read(log);
  EXPECT_NE(j["cases"][n - 1]["reason"].get<std::string>().find(
                "the candidate declined stage shaper (exit 78 on tonemap/shaper_pq/"),
            std::string::npos)
      << j["cases"][n - 1]["reason"];
  EXPECT_NE(r.out.find(std::to_string(n) + " case(s): the candidate declined stage shaper"),
            std::string::npos)
      << r.out;
  fs::remove_all(out);
  fs::remove_all(log.parent_path());
}

#ifdef HDRC_STANDALONE_CANDIDATE
// The acceptance test: a renderer that implements only devices 3 and 4 (the standalone example
// with --devices 3,4: the shaper and linear_device stages, declining other devices per case and
// other stages whole) runs verify over the whole suite. Its declined cases are UNSUPPORTED; its
// implemented ones pass; the run exits 0 without --require-all and 1 with it.
TEST(CandidateProtocol, DevicesThreeAndFourOnlyOverTheWholeSuite) {
  const fs::path out = temp_dir("dev34");
  const std::string cmd = "--candidate-cmd '" + std::string(HDRC_STANDALONE_CANDIDATE) +
                          " --params {params} --output {output} --devices 3,4' -j 2 --out " +
                          out.string();
  Ran r = run("verify " + cmd);
  EXPECT_EQ(r.code, 0) << r.out.substr(r.out.size() > 4000 ? r.out.size() - 4000 : 0);
  const auto j = results(out);
  const int total = static_cast<int>(j["cases"].size());
  const int pass = count_verdict(j, "PASS"), unsupported = count_verdict(j, "UNSUPPORTED");
  const int degenerate = count_verdict(j, "DEGENERATE");
  EXPECT_GT(total, 500);
  EXPECT_GT(pass, 0);
  EXPECT_EQ(pass + unsupported + degenerate, total);
  for (const auto& c : j["cases"]) {
    if (c["verdict"] != "PASS") continue;
    EXPECT_EQ(c["stage"], "shaper") << c["id"];
    const int device = c["params"]["output_device"];
    EXPECT_TRUE(device == 3 || device == 4) << c["id"];
  }
  RecordProperty("cases", std::to_string(total));
  RecordProperty("pass", std::to_string(pass));
  RecordProperty("unsupported", std::to_string(unsupported));
  // --require-all on the shaper cases alone, which hold both kinds (devices 3 and 4 pass, the
  // others are declined per case): the whole suite's outcome was checked above, and a second
  // whole-suite replay only to read an exit code cost half this test (measured: 150 s of 298 s).
  r = run("verify --require-all " + cmd + " --filter 'tonemap/shaper*'");
  EXPECT_EQ(r.code, 1) << r.out.substr(r.out.size() > 2000 ? r.out.size() - 2000 : 0);
  EXPECT_NE(r.out.find("--require-all: they fail the run"), std::string::npos);
  fs::remove_all(out);
}
#endif

// --candidate-limits: the port's declared deviations in known_limits.json's form; bad files are
// rejected before anything runs, with the file, pointer, value and valid choices; matching cases
// are KNOWN_LIMIT with the declared reason, and results.json (hence the report) lists them.
TEST(CandidateProtocol, CandidateLimitsAreValidatedAndShown) {
  const fs::path out = temp_dir("limits");
  const fs::path bad = out / "bad.json", good = out / "limits.json";
  std::ofstream(bad) << R"({"limits": [{"cases": "x/*", "engine": "vulkan", "reason": "r"},
                                        {"cases": "", "engine": "candidate-cmd"}]})";
  const std::string base = "verify --candidate-cmd \"sh -c 'exit 1' {output}\" --filter " +
                           kShaperPq + " -j 1 --out " + (out / "run").string();
  Ran r = run(base + " --candidate-limits " + bad.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(bad.string() + ": /limits/0/engine: unknown engine \"vulkan\"; valid "
                                      "choices: candidate-cmd, candidate-dir"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find(bad.string() + ": /limits/1/cases: missing cases, got \"\""),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find(bad.string() + ": /limits/1/reason: missing reason"), std::string::npos);
  EXPECT_FALSE(fs::exists(out / "run" / "results.json"));

  std::ofstream(good) << R"J({"limits": [{"cases": "tonemap/shaper_pq/*", "engine": "candidate-cmd",
                                          "reason": "our PQ uses a 4096-entry table (issue 7)"}]})J";
  r = run(base + " --candidate-limits " + good.string());
  EXPECT_EQ(r.code, 0) << r.out;
  const auto j = results(out / "run");
  EXPECT_EQ(count_verdict(j, "KNOWN_LIMIT"), static_cast<int>(j["cases"].size()));
  EXPECT_EQ(j["cases"][0]["reason"], "known limit of candidate-cmd: declared by the candidate (" +
                                         good.string() +
                                         "): our PQ uses a 4096-entry table (issue 7)");
  EXPECT_EQ(j["candidate_limits"]["file"], good.string());
  EXPECT_EQ(j["candidate_limits"]["limits"][0]["reason"],
            "our PQ uses a 4096-entry table (issue 7)");
  EXPECT_NE(r.out.find("1 deviation(s) declared by the candidate in " + good.string()),
            std::string::npos);
  // The report page carries them.
  EXPECT_NE(read(out / "run/report/index.html").find("our PQ uses a 4096-entry table"),
            std::string::npos);
  fs::remove_all(out);
}

// A failing case prints the command that reruns it, on the console and in JUnit; results.json
// (UNSUPPORTED and the protocol fields included) is valid under runner/results.schema.json.
TEST(CandidateProtocol, FailuresPrintAReproduceCommandAndResultsMatchTheSchema) {
  const fs::path out = temp_dir("repro");
  const Ran r =
      run("verify --candidate-cmd \"sh -c 'exit 3' {output}\" --filter "
          "'tonemap/shaper_pq/dev3_log_ramp' --out " +
          out.string());
  EXPECT_EQ(r.code, 1) << r.out;
  const std::string repro =
      "reproduce: hdrconform verify --filter =tonemap/shaper_pq/dev3_log_ramp --out out/repro "
      "--candidate-cmd 'sh -c '\\''exit 3'\\'' {output}'";
  EXPECT_NE(r.out.find(repro), std::string::npos) << r.out;
  const std::string junit = read(out / "junit.xml");
  EXPECT_NE(junit.find("reproduce: hdrconform verify --filter =tonemap/shaper_pq/"
                       "dev3_log_ramp --out"),
            std::string::npos)
      << junit;
  std::ifstream f(std::string(HDRC_SOURCE_DIR) + "/runner/results.schema.json");
  const auto schema = nlohmann::ordered_json::parse(f);
  for (const auto& e : hdrc::validate_json(results(out), schema, "results.json"))
    ADD_FAILURE() << e.to_string();
  fs::remove_all(out);
}

// The reference knows why it is NaN: the PQ shaper of a negative input is pow of a negative base.
TEST(Messages, NonFiniteMismatchNamesTheRule) {
  hdrc::Image input(2, 1), reference(2, 1), candidate(2, 1);
  for (int x = 0; x < 2; ++x)
    for (int c = 0; c < 4; ++c)
      input.px(x, 0)[c] = reference.px(x, 0)[c] = candidate.px(x, 0)[c] = 0.5;
  input.px(1, 0)[0] = -0.25;
  reference.px(1, 0)[0] = std::nan("");
  candidate.px(1, 0)[0] = 0.0;  // a port that clamps before the PQ encode
  hdrc::ParamBlock p;
  p.output_device = 3;
  hdrc::Tolerance tol;
  tol.linear_abs = 1e-6;
  const auto enc = hdrc::output_encoding(*hdrc::find_stage("shaper"), p);
  const auto v = hdrc::judge(hdrc::diff_images(input, reference, candidate, enc, tol), tol);
  EXPECT_FALSE(v.pass);
  EXPECT_NE(v.reason.find("1 non-finite mismatch(es); first at (1, 0) R: input -0.25 reference nan "
                          "candidate 0; pixel RGB input (-0.25, 0.5, 0.5)"),
            std::string::npos)
      << v.reason;
  EXPECT_NE(v.reason.find("the reference's value comes from LinearToST2084 of a negative value "
                          "(-0.25 x 100 nits): pow of a negative base is NaN"),
            std::string::npos)
      << v.reason;
}

// A planted per-channel LUT defect: one texel's G raised by 0.01 in the project's own
// combine_luts.comp. The message names the lattice point (r, g, b), the pixel's full RGB triplet
// on each side, and the pixel's ΔE_ITP (a 10-bit volume LUT, device 3: texel (6, 0, 1) of 16³).
TEST(Messages, PlantedLutDefectNamesLatticeTripletAndDeltaE) {
  const fs::path shaders = temp_dir("lut_shaders");
  const fs::path out = temp_dir("lut_out");
  fs::copy(fs::path(HDRC_SOURCE_DIR) / "gpu/shaders", shaders, fs::copy_options::recursive);
  std::string text = read(shaders / "stages/combine_luts.comp");
  const std::string from = "  if (P.lut_layout == 0) {";
  const size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, from.size(), "  if (texel == ivec3(6, 0, 1)) stored.g += 0.01;\n" + from);
  std::ofstream(shaders / "stages/combine_luts.comp") << text;
  const std::string id = "lut/devices/dev3_gamut2";
  const Ran r = run("run --no-goldens --filter '" + id + "' --shader-dir " + shaders.string() +
                    " --out " + out.string());
  EXPECT_EQ(r.code, 1) << r.out;
  // Lattice point (6, 0, 1) of a 16³ LUT is pixel (6 + 16·1, 0) = (22, 0).
  EXPECT_NE(r.out.find("at lattice (r 6, g 0, b 1) = pixel (22, 0) G"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("; pixel RGB input (0.400000006, 0, 0.0666666701) reference ("),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("), pixel ΔE_ITP "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("reproduce: hdrconform run --filter =" + id + " --out out/repro"),
            std::string::npos)
      << r.out;
  fs::remove_all(shaders);
  fs::remove_all(out);
}

}  // namespace

namespace {

// An HLSL port: examples/hlsl_shaders/stages/shaper.hlsl, compiled by glslang's HLSL front end in
// place of stages/shaper.comp, passes every shaper case (log and PQ shapers, all ten devices).
TEST(HlslPort, ShaperStageInHlslPassesItsCases) {
  const fs::path out = temp_dir("hlsl");
  const Ran r = run("run --no-goldens --filter 'tonemap/shaper_*' --shader-dir " +
                    std::string(HDRC_SOURCE_DIR) + "/examples/hlsl_shaders --out " + out.string());
  ASSERT_NE(r.code, 3) << "no Vulkan device: " << r.out;
  EXPECT_EQ(r.code, 0) << r.out;
  const auto j = results(out);
  EXPECT_GT(j["cases"].size(), 20u);
  EXPECT_EQ(count_verdict(j, "PASS"), static_cast<int>(j["cases"].size()));
  fs::remove_all(out);
}

}  // namespace

namespace {

// --reference analytic: a port that evaluates the pipeline per pixel without a LUT
// (examples/per_pixel_shaders: the project's shaders with the LUT lookup replaced by CombineLUTs
// at the pixel's coordinate) passes the tonemap cases against the analytic reference, and fails
// them against the baked reference by the LUT's interpolation error alone, as before.
TEST(AnalyticReference, PerPixelPortPassesAnalyticAndFailsBaked) {
  const std::string src = HDRC_SOURCE_DIR;
  const fs::path out = temp_dir("analytic");
  const std::string filter = " --filter 'tonemap/tonemap/*' -j 2 ";
  const Ran a = run("verify --reference analytic --candidate-limits " + src +
                    "/examples/per_pixel_shaders/candidate_limits.json" + filter + "--out " +
                    (out / "analytic").string() + " --candidate-cmd '" + HDRC_EXAMPLE_CANDIDATE +
                    " --params {params} --output {output} --shader-dir " + src +
                    "/examples/per_pixel_shaders'");
  EXPECT_EQ(a.code, 0) << a.out;
  const auto ja = results(out / "analytic");
  const int n = static_cast<int>(ja["cases"].size());
  EXPECT_EQ(n, 20);
  EXPECT_EQ(ja["reference_mode"], "analytic");
  // The two declared limits: 4 values each where the double reference is NaN (PQ of a value a few
  // ulps below zero) and float32 lands a few ulps above it (candidate_limits.json).
  EXPECT_EQ(count_verdict(ja, "PASS"), n - 2);
  EXPECT_EQ(count_verdict(ja, "KNOWN_LIMIT"), 2);
  double worst_pq = 0;
  for (const auto& c : ja["cases"])
    if (c["verdict"] == "PASS")
      worst_pq = std::max(worst_pq, c["stats"]["overall"]["pq_code10"]["max"].get<double>());
  RecordProperty("analytic_max_pq_code10", std::to_string(worst_pq));

  // The same shaders against the baked reference (in process: the same engine and shaders).
  const Ran b = run("run --no-goldens --shader-dir " + src + "/examples/per_pixel_shaders" +
                    filter + "--out " + (out / "baked").string());
  EXPECT_EQ(b.code, 1) << b.out;
  const auto jb = results(out / "baked");
  // Measured: 17 of the 20 fail (up to 131 10-bit PQ codes on device 0, 35 on scRGB); the three
  // special_ramp cases of devices 5-7 hold too few values in range to show the LUT's error.
  // Every log ramp (1024 values from 1e-4 to 1e4 nits) fails.
  EXPECT_GE(count_verdict(jb, "FAIL"), 17) << b.out;
  for (const auto& c : jb["cases"]) {
    if (c["id"].get<std::string>().find("log_ramp") != std::string::npos) {
      EXPECT_EQ(c["verdict"], "FAIL") << c["id"];
    }
  }
  fs::remove_all(out);
}

}  // namespace
