// Golden changes a reviewer can judge (runner/goldens_diff.h), end to end through the binary:
// `goldens update` leaves an unchanged golden byte for byte (also under a new reference version)
// and prints how far a changed one moved; `goldens diff` writes the review of a planted change
// from a folder of old goldens and from a git revision, and its errors name what is wrong.
//
// The planted change: one value of a PQ-encoded golden (UE's ACES 1000-nit device 3, a PQ signal)
// lowered by exactly 0.5 / 1023. The PQ metric decodes and re-encodes the signal (ST 2084:
// PQ(nits(v)) = v), so that value moved by 0.5 10-bit code values and by 0.5 / 1023 in the
// output's own units, and no other value moved: max 0.5, p99 0.
#include "runner/goldens_diff.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "core/image.h"
#include "runner/goldens.h"
#include "runner/test_support.h"

#ifndef HDRC_BINARY
#error "HDRC_BINARY must be defined"
#endif

namespace {

namespace fs = std::filesystem;
using namespace hdrc::test;  // runner/test_support.h
using json = nlohmann::json;

const char* kId = "t/aces/log_ramp";
const char* kCase = R"({
  "stage": "tonemap",
  "cvars": {"r.HDR.EnableHDROutput": 1, "r.HDR.Display.OutputDevice": 3,
            "r.HDR.Display.ColorGamut": 2, "r.HDR.Display.MaxLuminance": 1000},
  "input": {"stimulus": "log_ramp", "width": 64, "height": 2},
  "tolerance": {"pq_code10": 0.25, "reason": "test"}
})";

std::string bytes_of(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// A temp folder with cases/t/aces.json and goldens/ made by `goldens update`.
struct Fixture {
  fs::path dir, cases, goldens;
  std::string cases_arg;
  Fixture(const std::string& name) {
    dir = fs::temp_directory_path() / ("hdrc_gdiff_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    cases = dir / "cases";
    goldens = dir / "goldens";
    fs::create_directories(cases / "t");
    std::ofstream(cases / "t/aces.json") << kCase;
    cases_arg = " --cases " + cases.string() + " --goldens " + goldens.string();
  }
  ~Fixture() { fs::remove_all(dir); }
  fs::path exr() const { return goldens / (std::string(kId) + ".exr"); }
  fs::path sidecar() const { return goldens / (std::string(kId) + ".json"); }
  // Lowers value (x 50, y 1, G) of the golden, a PQ signal of about 0.5 (far from black, so that
  // it stays a valid signal), by 0.5 / 1023; returns it before the change.
  double plant(const fs::path& exr_path) const {
    auto img = hdrc::read_image(exr_path.string());
    EXPECT_TRUE(img.ok());
    double& v = img->px(50, 1)[1];
    EXPECT_GT(v, 0.1);
    const double before = v;
    v = static_cast<float>(v - 0.5 / 1023);
    EXPECT_TRUE(bool(hdrc::write_exr(exr_path.string(), *img)));
    return before;
  }
};

// The numbers of a move line: "PQ max A p99 B (10-bit codes), ΔE_ITP max C p99 D, linear max E".
std::vector<double> move_numbers(const std::string& out, const std::string& id) {
  const std::regex re("changed " + id +
                      ": PQ max ([^ ]+) p99 ([^ ]+) \\(10-bit codes\\), ΔE_ITP max ([^ ]+) p99 "
                      "([^ ]+), linear max ([^;]+); 1 value\\(s\\) changed");
  std::smatch m;
  if (!std::regex_search(out, m, re)) return {};
  std::vector<double> v;
  for (int i = 1; i <= 5; ++i) v.push_back(std::stod(m[i].str()));
  return v;
}

void expect_planted_move(const std::string& out) {
  const std::vector<double> n = move_numbers(out, kId);
  ASSERT_EQ(n.size(), 5u) << out;
  EXPECT_NEAR(n[0], 0.5, 0.5e-3) << out;  // PQ max (printed to 3 digits)
  EXPECT_EQ(n[1], 0.0) << out;            // p99: one value of 384 moved
  EXPECT_GT(n[2], 0.0) << out;            // ΔE_ITP of the one pixel
  EXPECT_EQ(n[3], 0.0) << out;
  EXPECT_NEAR(n[4], 0.5 / 1023, 0.5e-3 * 0.5 / 1023) << out;
}

TEST(GoldensUpdate, UnchangedGoldensStayByteIdenticalAndAChangeIsMeasured) {
  Fixture f("update");
  Ran r = run("goldens update" + f.cases_arg);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("new " + std::string(kId) + ": wrote"), std::string::npos) << r.out;
  const std::string exr = bytes_of(f.exr()), side = bytes_of(f.sidecar());

  // Again: nothing is written.
  r = run("goldens update" + f.cases_arg);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("0 written, 1 unchanged"), std::string::npos) << r.out;
  EXPECT_EQ(bytes_of(f.exr()), exr);
  EXPECT_EQ(bytes_of(f.sidecar()), side);

  // A golden made by another reference version, with the same pixels, hashes and values: left
  // as it is (git shows no change), its sidecar still naming the version that wrote it.
  json j = json::parse(side);
  j["reference_version"] = "1/000000000000";
  const std::string other_version = j.dump(2) + "\n";
  std::ofstream(f.sidecar()) << other_version;
  r = run("goldens update" + f.cases_arg);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("0 written, 1 unchanged"), std::string::npos) << r.out;
  EXPECT_EQ(bytes_of(f.sidecar()), other_version);
  EXPECT_EQ(bytes_of(f.exr()), exr);
  std::ofstream(f.sidecar()) << side;

  // The planted change: update measures the move back to the reference's output, says where
  // to review it, and rewrites the golden with the very bytes it had (no date in the EXR).
  f.plant(f.exr());
  r = run("goldens update" + f.cases_arg);
  ASSERT_EQ(r.code, 0) << r.out;
  expect_planted_move(r.out);
  EXPECT_NE(r.out.find("1 written, 0 unchanged"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("goldens: 1 changed; largest move PQ 0.5 (10-bit codes, " +
                       std::string(kId) + ")"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("review the change: hdrconform goldens diff --cases"), std::string::npos)
      << r.out;
  EXPECT_EQ(bytes_of(f.exr()), exr);
}

TEST(GoldensDiff, ReviewsAPlantedChangeAgainstAnOldFolder) {
  Fixture f("old");
  ASSERT_EQ(run("goldens update" + f.cases_arg).code, 0);
  const fs::path old = f.dir / "old", out = f.dir / "review";
  fs::copy(f.goldens, old, fs::copy_options::recursive);

  // Nothing differs: an empty review.
  Ran r = run("goldens diff" + f.cases_arg + " --old " + old.string() + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("goldens diff: 0 changed, 0 added, 0 removed"), std::string::npos) << r.out;
  EXPECT_NE(bytes_of(out / "review.html").find("No golden differs."), std::string::npos);

  f.plant(f.exr());
  r = run("goldens diff" + f.cases_arg + " --old " + old.string() + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  expect_planted_move(r.out);
  EXPECT_NE(r.out.find("goldens diff: 1 changed, 0 added, 0 removed"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("review: " + (out / "review.html").string()), std::string::npos) << r.out;
  // The review page links the case page; the case's images are the old golden (reference) and
  // the new (candidate), files as they are, with the case's input for the ramp plot.
  const std::string html = bytes_of(out / "review.html");
  EXPECT_NE(html.find("href=\"report/c/t__aces__log_ramp.html\""), std::string::npos) << html;
  EXPECT_TRUE(fs::is_regular_file(out / "report/c/t__aces__log_ramp.html"));
  EXPECT_EQ(bytes_of(out / "cases" / kId / "reference.exr"),
            bytes_of(old / (std::string(kId) + ".exr")));
  EXPECT_EQ(bytes_of(out / "cases" / kId / "candidate.exr"), bytes_of(f.exr()));
  const json results = json::parse(bytes_of(out / "results.json"));
  ASSERT_EQ(results["cases"].size(), 1u);
  EXPECT_EQ(results["cases"][0]["id"], kId);
  // Over the case's tolerance (0.25 codes): a port matching the old golden fails the new one.
  EXPECT_EQ(results["cases"][0]["verdict"], "FAIL");
  EXPECT_TRUE(results["cases"][0]["images"].contains("input"));

  // Only the bytes differ (the same pixels written again by another writer): listed, no views.
  fs::copy_file(old / (std::string(kId) + ".exr"), f.exr(), fs::copy_options::overwrite_existing);
  {
    auto img = hdrc::read_image(f.exr().string());
    ASSERT_TRUE(img.ok());
    std::vector<float> px(img->data.begin(), img->data.end());
    OIIO::ImageSpec spec(img->width, img->height, 4, OIIO::TypeDesc::FLOAT);
    spec.attribute("compression", "piz");
    auto o = OIIO::ImageOutput::create(f.exr().string());
    ASSERT_TRUE(o && o->open(f.exr().string(), spec) &&
                o->write_image(OIIO::TypeDesc::FLOAT, px.data()) && o->close());
  }
  ASSERT_NE(bytes_of(f.exr()), bytes_of(old / (std::string(kId) + ".exr")));
  r = run("goldens diff" + f.cases_arg + " --old " + old.string() + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("0 changed, 0 added, 0 removed, 1 with the same pixels"), std::string::npos)
      << r.out;
}

TEST(GoldensDiff, ReviewsTheWorkingTreeAgainstAGitRevision) {
  Fixture f("git");
  ASSERT_EQ(run("goldens update" + f.cases_arg).code, 0);
  const std::string git = "git -C " + f.dir.string() + " -c user.name=t -c user.email=t@t ";
  ASSERT_EQ(
      std::system(
          (git + "init -q && " + git + "add goldens && " + git + "commit -q -m goldens").c_str()),
      0);
  const fs::path out = f.dir / "review";
  f.plant(f.exr());
  fs::create_directories(f.goldens / "t/new");
  fs::copy_file(f.exr(), f.goldens / "t/new/x.exr");  // untracked: an added golden
  Ran r = run("goldens diff" + f.cases_arg + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  expect_planted_move(r.out);
  EXPECT_NE(r.out.find("added t/new/x"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("goldens diff: 1 changed, 1 added, 0 removed"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("(old: HEAD)"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(out / ".old")) << "the fetched blobs are not left in the output";

  // A revision that is not one: the error names --since and the revision, and the way out.
  r = run("goldens diff" + f.cases_arg + " --since no-such-rev --out " + out.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("--since"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("no-such-rev"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--old DIR"), std::string::npos) << r.out;
  // An option-like revision is refused before git sees it.
  r = run("goldens diff" + f.cases_arg + " --since=--output=x --out " + out.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_FALSE(fs::exists(f.goldens / "x"));
}

TEST(GoldensDiff, RefusesConflictingSourcesAndAFolderOutsideGit) {
  Fixture f("errors");
  ASSERT_EQ(run("goldens update" + f.cases_arg).code, 0);
  const fs::path out = f.dir / "review";
  Ran r = run("goldens diff" + f.cases_arg + " --since HEAD --old " + f.goldens.string() +
              " --out " + out.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("--since and --old"), std::string::npos) << r.out;
  // Not in a git checkout (the temp folder): the error says to pass --old.
  r = run("goldens diff" + f.cases_arg + " --out " + out.string(),
          "GIT_CEILING_DIRECTORIES=" + f.dir.parent_path().string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("--old DIR"), std::string::npos) << r.out;
  // The goldens folder itself is no output folder: refused before anything is written there.
  r = run("goldens diff" + f.cases_arg + " --old " + f.goldens.string() + " --out " +
          f.goldens.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("--out"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(f.goldens / "review.html"));
}

}  // namespace
