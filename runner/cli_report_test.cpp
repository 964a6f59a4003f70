// The command line of issue 14 end to end: merge of shards, cost-balanced shards, --filter
// patterns, --rerun-failed, did-you-mean, bare `list`, --images, and golden failures recorded as
// test results.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>

#include "core/image.h"
#include "runner/goldens.h"
#include "runner/test_support.h"

#ifndef HDRC_BINARY
#error "HDRC_BINARY must be defined"
#endif

namespace fs = std::filesystem;
using namespace hdrc::test;  // runner/test_support.h
using json = nlohmann::json;

namespace {

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);)
    if (!l.empty()) out.push_back(l);
  return out;
}

// The report minus what legitimately differs between runs: timings, the run's metadata table.
std::string stable_page(std::string html) {
  html =
      std::regex_replace(html, std::regex("<h3>Timings and device</h3>[\\s\\S]*?</section>"), "");
  html = std::regex_replace(
      html, std::regex("<table class=\"kv\" id=\"run-meta\">[\\s\\S]*?</table>"), "");
  // A case page carries its EXR files (the float data, base64), whose bytes are compared out of
  // the page (EXRs written before core/image.cpp left DateTime empty carried their time, capDate).
  html = std::regex_replace(html, std::regex("\"exr\":\"[A-Za-z0-9+/=]*\""), "\"exr\":\"\"");
  return html;
}

// Three shards merged give the same verdicts, counts, junit test cases and report as one
// unsharded run (issue 14, acceptance 2).
TEST(CliMerge, ThreeShardsMergedEqualOneUnshardedRun) {
  const fs::path root = temp_dir("merge");
  const std::string sel = "--engine reference --filter 'tonemap/shaper_pq/*,tonemap/dither' ";
  const Ran whole = run("run " + sel + "--out " + (root / "whole").string());
  ASSERT_TRUE(whole.code == 0 || whole.code == 4) << whole.out;
  std::vector<std::string> dirs;
  for (int k = 1; k <= 3; ++k) {
    const fs::path d = root / ("shard" + std::to_string(k));
    const Ran r = run("run " + sel + "--shard " + std::to_string(k) + "/3 --out " + d.string());
    ASSERT_TRUE(r.code == 0 || r.code == 4) << r.out;
    dirs.push_back(d.string());
  }
  const fs::path merged = root / "merged";
  const Ran m = run("merge " + merged.string() + " " + dirs[2] + " " + dirs[0] + " " + dirs[1]);
  ASSERT_EQ(m.code, whole.code) << m.out;
  const json a = json::parse(read(root / "whole" / "results.json"));
  const json b = json::parse(read(merged / "results.json"));
  ASSERT_EQ(a["cases"].size(), b["cases"].size());
  ASSERT_GT(a["cases"].size(), 10u);
  for (size_t i = 0; i < a["cases"].size(); ++i) {
    EXPECT_EQ(a["cases"][i]["id"], b["cases"][i]["id"]);
    EXPECT_EQ(a["cases"][i]["verdict"], b["cases"][i]["verdict"]);
    EXPECT_EQ(a["cases"][i]["reason"], b["cases"][i]["reason"]);
    EXPECT_EQ(a["cases"][i]["budget_used"], b["cases"][i]["budget_used"]);
  }
  EXPECT_EQ(a["summary"], b["summary"]);
  EXPECT_EQ(a["goldens"]["checked"], b["goldens"]["checked"]);
  EXPECT_EQ(a["goldens"]["cases"], b["goldens"]["cases"]);
  EXPECT_EQ(b["merged_from"].size(), 3u);
  auto testcases = [](const std::string& x) {  // but for timings and when the run started
    return std::regex_replace(x, std::regex(" (time|timestamp)=\"[0-9.:T-]+\""), "");
  };
  EXPECT_EQ(testcases(read(root / "whole" / "junit.xml")), testcases(read(merged / "junit.xml")));
  // The report: the same files, the same case table, the same pages (but for timings and the
  // run's metadata).
  std::set<std::string> fa, fb;
  for (const auto& e : fs::recursive_directory_iterator(root / "whole" / "report"))
    fa.insert(fs::relative(e.path(), root / "whole" / "report").string());
  for (const auto& e : fs::recursive_directory_iterator(merged / "report"))
    fb.insert(fs::relative(e.path(), merged / "report").string());
  EXPECT_EQ(fa, fb);
  EXPECT_EQ(read(root / "whole" / "report" / "data.js"), read(merged / "report" / "data.js"));
  for (const auto& f : fa) {
    if (f.size() > 5 && f.substr(f.size() - 5) == ".html") {
      EXPECT_EQ(stable_page(read(root / "whole" / "report" / f)),
                stable_page(read(merged / "report" / f)))
          << f;
    }
  }
  // The case EXRs the pages carry: the same pixels (their bytes differ in the write time).
  size_t exrs = 0;
  const fs::path whole_cases = fs::canonical(root / "whole" / "cases");  // via the run's link
  for (const auto& e : fs::recursive_directory_iterator(whole_cases)) {
    if (e.path().extension() != ".exr") continue;
    const auto a_img = hdrc::read_image(e.path().string());
    const auto b_img =
        hdrc::read_image((merged / "cases" / fs::relative(e.path(), whole_cases)).string());
    ASSERT_TRUE(a_img && b_img) << e.path();
    EXPECT_EQ(
        0, std::memcmp(a_img->data.data(), b_img->data.data(), a_img->data.size() * sizeof(double)))
        << e.path();
    ++exrs;
  }
  EXPECT_GT(exrs, 0u);

  // Refused: a shard missing, a shard twice, shards of another suite.
  Ran bad = run("merge " + (root / "m2").string() + " " + dirs[0] + " " + dirs[1]);
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.out.find("shard(s) 3/3 missing"), std::string::npos) << bad.out;
  bad = run("merge " + (root / "m3").string() + " " + dirs[0] + " " + dirs[0] + " " + dirs[1]);
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.out.find("given twice"), std::string::npos) << bad.out;
  const fs::path other = root / "other";
  ASSERT_LE(run("run --engine reference --filter 'tonemap/shaper_log/*' --shard 3/3 --out " +
                other.string())
                .code,
            4);
  bad =
      run("merge " + (root / "m4").string() + " " + dirs[0] + " " + dirs[1] + " " + other.string());
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.out.find("differ in suite"), std::string::npos) << bad.out;
  EXPECT_FALSE(fs::exists(root / "m4" / "results.json"));
  fs::remove_all(root);
}

// Shards balance cost, not count: with the last run's timings (--timings), every shard's summed
// seconds is within the largest single case of the others' (greedy bound), and the plan is
// recorded so shards of different plans are never merged.
TEST(CliShard, TimingsBalanceTheShards) {
  const fs::path root = temp_dir("timings");
  const auto all = lines(run("list --filter tonemap/shaper_pq").out);
  ASSERT_GT(all.size(), 6u);
  // The shards' loads under `timings`, a results.json giving case 0 `first` seconds and every
  // other case 1 s; each case counted at `counted(its seconds)`.
  auto loads = [&](double first, const std::function<double(double)>& counted) {
    json t = {{"cases", json::array()}};
    for (size_t i = 0; i < all.size(); ++i)
      t["cases"].push_back({{"id", all[i]}, {"seconds", {{"total", i == 0 ? first : 1.0}}}});
    std::ofstream(root / "t.json") << t.dump();
    std::vector<double> load;
    std::multiset<std::string> seen;
    for (int k = 1; k <= 3; ++k) {
      const Ran r = run("list --filter tonemap/shaper_pq --shard " + std::to_string(k) +
                        "/3 --timings " + (root / "t.json").string());
      EXPECT_EQ(r.code, 0) << r.out;
      double sum = 0;
      for (const auto& id : lines(r.out)) {
        sum += counted(id == all[0] ? first : 1.0);
        seen.insert(id);
      }
      load.push_back(sum);
    }
    EXPECT_EQ(seen, std::multiset<std::string>(all.begin(), all.end()));
    return load;
  };
  auto spread = [](const std::vector<double>& l) {
    return *std::max_element(l.begin(), l.end()) - *std::min_element(l.begin(), l.end());
  };
  // Greedy: the 2.5 s case first, the 1 s cases after it each to the least loaded shard, so the
  // loads end within one 1 s case of each other (an index split leaves the slow case's shard
  // 1.5 s over the others).
  auto l = loads(2.5, [](double s) { return s; });
  EXPECT_LE(spread(l), 1.0 + 1e-9) << l[0] << " " << l[1] << " " << l[2];
  // A recorded time far over the others of its kind (here 100x: one-time costs such as shader
  // compilation fall on one case) counts at most 3x the typical seconds of the static model's
  // estimate (runner/run.cpp, shard_cost): its shard still gets its share of the other cases.
  l = loads(100.0, [](double s) { return std::min(s, 3.0); });
  EXPECT_LE(spread(l), 1.0 + 1e-9) << l[0] << " " << l[1] << " " << l[2];
  EXPECT_EQ(run("list --shard 1/3 --timings " + (root / "nope.json").string()).code, 2);
  fs::remove_all(root);
}

TEST(CliSelection, FilterPatternsListAndHints) {
  // list prints bare ids; --long adds the stage and input.
  const Ran l = run("list --filter lut");
  ASSERT_EQ(l.code, 0) << l.out;
  const auto ids = lines(l.out);
  ASSERT_GT(ids.size(), 5u);
  for (const auto& id : ids) {
    EXPECT_EQ(id.find(' '), std::string::npos) << id;
    EXPECT_NE(id.find("lut"), std::string::npos) << id;  // a substring pattern
  }
  const Ran longer = run("list --long --filter lut");
  EXPECT_NE(longer.out.find("  (combine_luts, "), std::string::npos) << longer.out;
  // Several patterns: the union.
  const size_t a = lines(run("list --filter tonemap/shaper_pq").out).size();
  const size_t b = lines(run("list --filter tonemap/dither").out).size();
  EXPECT_EQ(lines(run("list --filter tonemap/shaper_pq,tonemap/dither").out).size(), a + b);
  EXPECT_EQ(lines(run("list --filter tonemap/shaper_pq --filter tonemap/dither").out).size(),
            a + b);
  // Nothing matches: exit 2 with a hint.
  const Ran none = run("list --filter tonemapp/shaper");
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.out.find("hint:"), std::string::npos) << none.out;
  // A mistyped command: did you mean.
  const Ran typo = run("lsit");
  EXPECT_EQ(typo.code, 2);
  EXPECT_NE(typo.out.find("did you mean 'list'?"), std::string::npos) << typo.out;
}

// Golden failures fail the run, and results.json, junit.xml and the report say so; --rerun-failed
// then runs exactly the failed cases; --images failing keeps only their images.
TEST(CliGoldens, GoldenFailuresAreRecordedAndRerun) {
  const fs::path root = temp_dir("goldens");
  fs::create_directories(root / "empty_goldens");
  const Ran r = run("run --engine reference --filter 'tonemap/shaper_pq/*' --goldens " +
                    (root / "empty_goldens").string() + " --out " + (root / "out").string());
  ASSERT_EQ(r.code, 1) << r.out;
  const json doc = json::parse(read(root / "out" / "results.json"));
  EXPECT_EQ(doc["summary"]["exit_code"], 1);
  EXPECT_EQ(doc["summary"]["fail"], 0);
  EXPECT_GT(doc["goldens"]["missing"].get<int>(), 0);
  const std::string junit = read(root / "out" / "junit.xml");
  EXPECT_NE(junit.find("<testsuite name=\"hdrconform.goldens\""), std::string::npos);
  EXPECT_NE(junit.find("<failure message=\"golden missing: "), std::string::npos);
  EXPECT_NE(read(root / "out" / "report" / "index.html").find("id=\"golden-failures\""),
            std::string::npos);
  // Rerun the failed ones (here: every case, by its golden) with the real goldens: they pass.
  const Ran again = run("run --engine reference --rerun-failed " + (root / "out").string() +
                        " --images failing --out " + (root / "again").string());
  EXPECT_EQ(again.code, 0) << again.out;
  const json doc2 = json::parse(read(root / "again" / "results.json"));
  EXPECT_EQ(doc2["cases"].size(), doc["cases"].size());
  EXPECT_FALSE(fs::exists(root / "again" / "cases" / "tonemap"));  // nothing failed: no images
  EXPECT_EQ(doc2["images_policy"], "failing");
  // Nothing failed there: nothing to rerun, exit 0.
  const Ran nothing = run("run --engine reference --rerun-failed " + (root / "again").string() +
                          " --out " + (root / "third").string());
  EXPECT_EQ(nothing.code, 0) << nothing.out;
  EXPECT_NE(nothing.out.find("nothing to rerun"), std::string::npos) << nothing.out;
  fs::remove_all(root);
}

// Two golden regressions with every case passing (issue 27): the run exits 1, and every place
// that gives the run's verdict at a glance says so: results.json's summary, the console's
// `hdrconform:` line, JUnit's <testsuites> totals and the report's count cards.
TEST(CliGoldens, GoldenRegressionsCountInEveryHeadline) {
  const fs::path root = temp_dir("golden_headline");
  const fs::path goldens = root / "goldens";
  fs::create_directories(goldens / "tonemap");
  fs::copy(fs::path(HDRC_SOURCE_DIR) / "goldens/tonemap/shaper_pq", goldens / "tonemap/shaper_pq");
  // Two goldens as a changed reference would leave them (goldens_test.cpp does one): one pixel
  // 0.1 % off, the sidecar's hash matching the altered image, another reference version.
  for (const char* id : {"tonemap/shaper_pq/dev3_log_ramp", "tonemap/shaper_pq/dev5_log_ramp"}) {
    const fs::path exr = goldens / (std::string(id) + ".exr");
    const fs::path side = goldens / (std::string(id) + ".json");
    auto img = hdrc::read_image(exr.string());
    ASSERT_TRUE(img.ok()) << exr;
    img->px(3, 0)[1] = img->px(3, 0)[1] * 1.001 + 1e-3;
    ASSERT_TRUE(hdrc::write_exr(exr.string(), *img).ok());
    json sidecar = json::parse(read(side));
    sidecar["reference_version"] = "0/000000000000";
    sidecar["output_hash"] = hdrc::sha256_hex(hdrc::image_bytes(*img));
    std::ofstream(side) << sidecar.dump(2);
  }
  const Ran r = run("run --engine reference --filter 'tonemap/shaper_pq/*' --goldens " +
                    goldens.string() + " --out " + (root / "out").string());
  ASSERT_EQ(r.code, 1) << r.out;
  const json doc = json::parse(read(root / "out/results.json"));
  const int cases = static_cast<int>(doc["cases"].size());
  ASSERT_GT(cases, 2);
  EXPECT_EQ(doc["summary"]["fail"], 0);  // every case passed; only the goldens failed
  EXPECT_EQ(doc["goldens"]["regression"], 2);
  EXPECT_EQ(doc["summary"]["golden_failed"], 2);
  EXPECT_EQ(doc["summary"]["exit_code"], 1);
  // The console: "2 failed" where it said "0 failed", with the kind.
  const std::string want_line = "hdrconform: " + std::to_string(cases) +
                                " cases: " + std::to_string(doc["summary"]["pass"].get<int>()) +
                                " passed, 2 failed (goldens: 2 regressions), 0 errors";
  EXPECT_NE(r.out.find(want_line), std::string::npos) << want_line << "\n" << r.out;
  // JUnit: the totals count them as failures.
  const std::string junit = read(root / "out/junit.xml");
  EXPECT_NE(junit.find("<testsuites name=\"hdrconform\" tests=\"" + std::to_string(2 * cases) +
                       "\" failures=\"2\" errors=\"0\""),
            std::string::npos)
      << junit.substr(0, 400);
  EXPECT_NE(junit.find("<testsuite name=\"hdrconform.goldens\" tests=\"" + std::to_string(cases) +
                       "\" failures=\"2\""),
            std::string::npos);
  // The report's cards: FAIL 0, golden failures 2, leading to the Goldens section.
  const std::string index = read(root / "out/report/index.html");
  EXPECT_NE(index.find("id=\"count-FAIL\">0<"), std::string::npos);
  EXPECT_NE(index.find("href=\"#goldens\"><b id=\"count-GOLDEN_FAILED\">2</b> golden failures"),
            std::string::npos);
  EXPECT_NE(index.find("id=\"goldens\""), std::string::npos);
  fs::remove_all(root);
}

// The CI environment variable changes one default: only failing cases keep their images; an
// explicit --images wins, and CI=false / CI=0 mean not CI. (Every other test runs with CI unset:
// runner/test_support.h.)
TEST(CliImages, CiKeepsOnlyFailingImagesByDefault) {
  const fs::path root = temp_dir("ci_images");
  const std::string args = "run --engine reference --filter 'tonemap/shaper_pq/dev3_log_ramp' ";
  const fs::path image = "cases/tonemap/shaper_pq/dev3_log_ramp/reference.exr";
  struct Want {
    std::string env, flag, policy;
  };
  for (const Want& w :
       {Want{"CI=true", "", "failing"}, Want{"CI=1", "--images all", "all"},
        Want{"CI=false", "", "all"}, Want{"CI=0", "", "all"}, Want{"", "", "all"}}) {
    const fs::path out = root / ("out" + w.env + w.flag);
    const Ran r = run(args + w.flag + " --out '" + out.string() + "'", w.env);
    ASSERT_EQ(r.code, 0) << w.env << " " << r.out;
    EXPECT_EQ(json::parse(read(out / "results.json"))["images_policy"], w.policy) << w.env;
    EXPECT_EQ(fs::exists(out / image), w.policy == "all") << w.env << " " << w.flag;
  }
  fs::remove_all(root);
}

// Issue 27, item 8: a passing default run with --images failing (the CI's artifact: results.json,
// junit.xml, goldens.json, report/) fits 25 MB. Scaled per case: a 40th of the default suite
// (--shard 1/40, cases of every stage) writes at most 92 % of 25 MB / 1655 cases (13.9 KB) a
// case, beside the report's fixed files (its assets, the summary and matrix pages, the page of
// shared tolerance reasons: 0.32 MB of the whole suite's): the 8 % left (2 MB) holds those and a
// margin. The whole suite (1655 cases): 22.5 MB, docs/performance-notes.md ("The CI artifact");
// this slice 13.5 KB a case.
TEST(CliImages, FailingImagesRunFitsTheArtifactBudgetPerCase) {
  const fs::path out = temp_dir("artifact_budget");
  const Ran r = run("run --shard 1/40 --images failing --out '" + out.string() + "'");
  ASSERT_EQ(r.code, 0) << r.out;
  auto bytes_under = [](const fs::path& p) {
    uintmax_t n = 0;
    if (fs::is_regular_file(p)) return fs::file_size(p);
    for (const auto& e : fs::recursive_directory_iterator(p))
      if (e.is_regular_file()) n += e.file_size();
    return n;
  };
  uintmax_t fixed = 0;
  for (const char* f : {"assets", "index.html", "matrix.html", "tolerances.html"})
    fixed += bytes_under(out / "report" / f);
  const size_t cases = json::parse(read(out / "results.json"))["cases"].size();
  ASSERT_GT(cases, 20u);
  const double per_case = static_cast<double>(bytes_under(out) - fixed) / cases;
  EXPECT_LE(per_case, 0.92 * 25e6 / 1655) << cases << " cases, " << bytes_under(out) << " bytes";
  fs::remove_all(out);
}

}  // namespace
