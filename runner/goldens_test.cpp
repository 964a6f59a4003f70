// Goldens: SHA-256 against FIPS 180-2's examples; the golden check end to end through the binary
// (missing golden -> the command that creates it; a golden pixel altered, as a changed reference
// formula would leave it -> the run fails naming the pixel; `goldens update` -> passes again and
// the sidecar shows the new reference version and output hash; a changed case -> stale).
#include "runner/goldens.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "runner/case_loader.h"
#include "runner/test_support.h"

#ifndef HDRC_BINARY
#error "HDRC_BINARY must be defined"
#endif

namespace {

namespace fs = std::filesystem;
using namespace hdrc::test;  // runner/test_support.h
using json = nlohmann::json;

TEST(Goldens, Sha256MatchesTheStandardsExamples) {
  // FIPS 180-2 Appendix B.1, B.2, and the empty message.
  EXPECT_EQ(hdrc::sha256_hex("abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(hdrc::sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(hdrc::sha256_hex(""),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  // Two blocks of padding (55, 56, 64 bytes cross the boundary).
  EXPECT_EQ(hdrc::sha256_hex(std::string(1000000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Goldens, ReferenceVersionIsStable) {
  const std::string v = hdrc::reference_version();
  EXPECT_EQ(v.rfind(std::to_string(hdrc::kReferenceVersion) + "/", 0), 0u) << v;
  EXPECT_EQ(v.size(), std::to_string(hdrc::kReferenceVersion).size() + 1 + 12);
  EXPECT_EQ(hdrc::reference_version(), v);
}

json read_json(const fs::path& p) {
  std::ifstream f(p);
  return json::parse(f);
}

TEST(Goldens, CheckFailsOnAnAlteredPixelAndUpdateAcceptsTheChange) {
  const fs::path dir = fs::temp_directory_path() / ("hdrc_goldens_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const fs::path cases = dir / "cases", goldens = dir / "goldens", out = dir / "out";
  fs::create_directories(cases / "t");
  const std::string case_text =
      R"({"stage": "tonemap", "cvars": {"r.HDR.EnableHDROutput": 1, "r.HDR.Display.OutputDevice": 3, "r.LUT.Size": 16},
          "input": {"stimulus": "colorchecker", "width": 24, "height": 2},
          "tolerance": {"linear_rel": 1e-5, "rel_floor": 1e-6, "pq_code10": 0.05, "reason": "reference vs reference"}})";
  std::ofstream(cases / "t/c.json") << case_text;
  const std::string id = "t/c/colorchecker";
  const std::string where =
      " --cases " + cases.string() + " --goldens " + goldens.string() + " --out " + out.string();
  const std::string cmd = "hdrconform goldens update --filter '" + id + "' --cases " +
                          cases.string() + " --goldens " + goldens.string();

  // 1. No golden yet: the run fails and says how to make one.
  Ran r = run("run --engine reference" + where);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("GOLDEN missing    " + id + "  no golden"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("create it with: " + cmd), std::string::npos) << r.out;

  // 2. `goldens update` writes the EXR and the sidecar; the run passes.
  r = run("goldens update --cases " + cases.string() + " --goldens " + goldens.string());
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("1 written"), std::string::npos) << r.out;
  const fs::path exr = goldens / (id + ".exr"), side = goldens / (id + ".json");
  ASSERT_TRUE(fs::exists(exr));
  const json first = read_json(side);
  EXPECT_EQ(first["case"], id);
  EXPECT_EQ(first["reference_version"], hdrc::reference_version());
  for (const char* k : {"case_hash", "input_hash", "output_hash"})
    EXPECT_EQ(first[k].get<std::string>().size(), 64u) << k;
  EXPECT_FALSE(first["date"].get<std::string>().empty());
  r = run("run --engine reference" + where);
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("goldens: 1 checked"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("1 match"), std::string::npos) << r.out;

  // 3. A golden made by a different reference (one pixel off, as a changed formula leaves it):
  // the run fails naming the pixel, the channel, both values and both reference versions.
  auto img = hdrc::read_image(exr.string());
  ASSERT_TRUE(img.ok());
  const float good = static_cast<float>(img->px(5, 1)[1]);
  img->px(5, 1)[1] = good * 1.001;
  ASSERT_TRUE(hdrc::write_exr(exr.string(), *img).ok());
  json old = first;
  old["reference_version"] = "0/000000000000";
  old["output_hash"] = hdrc::sha256_hex(hdrc::image_bytes(*img));
  std::ofstream(side) << old.dump(2);
  r = run("run --engine reference" + where);
  EXPECT_EQ(r.code, 1) << r.out;
  std::ostringstream want;
  want.precision(9);
  want << "GOLDEN regression " << id
       << "  golden regression: 1 value(s) differ, first at (5, 1) G:";
  EXPECT_NE(r.out.find(want.str()), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("(golden made by reference 0/000000000000, this is " +
                       hdrc::reference_version() + ")"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("if the change is intended: " + cmd), std::string::npos) << r.out;
  const json check = read_json(out / "goldens.json");
  EXPECT_EQ(check["failed"], 1);

  // 4. `goldens update` accepts the reference's output: the run passes, the sidecar changed.
  r = run("goldens update --filter '" + id + "' --cases " + cases.string() + " --goldens " +
          goldens.string());
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("1 written"), std::string::npos) << r.out;
  const json updated = read_json(side);
  EXPECT_EQ(updated["reference_version"], hdrc::reference_version());
  EXPECT_NE(updated["output_hash"], old["output_hash"]);
  EXPECT_EQ(updated["output_hash"], first["output_hash"]);
  auto back = hdrc::read_image(exr.string());
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(static_cast<float>(back->px(5, 1)[1]), good);
  r = run("run --engine reference" + where);
  EXPECT_EQ(r.code, 0) << r.out;
  // A second update changes nothing (the date and bytes stay).
  r = run("goldens update --cases " + cases.string() + " --goldens " + goldens.string());
  EXPECT_NE(r.out.find("0 written, 1 unchanged"), std::string::npos) << r.out;
  EXPECT_EQ(read_json(side)["date"], updated["date"]);

  // 5. The case changes: its golden is stale, and the run says which command refreshes it.
  std::string changed = case_text;
  changed.replace(changed.find("\"r.LUT.Size\": 16"), 16, "\"r.LUT.Size\": 17");
  std::ofstream(cases / "t/c.json") << changed;
  r = run("run --engine reference" + where);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("GOLDEN stale      " + id + "  stale golden: the case's definition changed"),
            std::string::npos)
      << r.out;

  // 6. Without --filter, goldens of cases no longer in the suite are removed (a golden is one
  // `goldens update` wrote: its sidecar names the case id of its own path).
  fs::create_directories(goldens / "gone");
  fs::copy_file(exr, goldens / "gone/x.exr");
  json gone = read_json(side);
  gone["case"] = "gone/x";
  std::ofstream(goldens / "gone/x.json") << gone.dump(2);
  r = run("goldens update --cases " + cases.string() + " --goldens " + goldens.string());
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("1 written, 0 unchanged, 1 removed"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(goldens / "gone"));
  fs::remove_all(dir);
}

// A custom --cases without --goldens: `goldens update` refuses (the repository's goldens belong
// to its cases), `run` says it did not check.
TEST(Goldens, CustomCasesNeedAnExplicitGoldenDirectory) {
  const fs::path dir = fs::temp_directory_path() / ("hdrc_goldens2_" + std::to_string(::getpid()));
  fs::create_directories(dir / "cases");
  std::ofstream(dir / "cases/a.json")
      << R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 8}, "tolerance": {"linear_rel": 1e-5, "reason": "x"}})";
  Ran r = run("goldens update --cases " + (dir / "cases").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("--goldens DIR is required"), std::string::npos) << r.out;
  r = run("run --engine reference --cases " + (dir / "cases").string() + " --out " +
          (dir / "out").string());
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("goldens: not checked"), std::string::npos) << r.out;
  fs::remove_all(dir);
}

// The committed goldens keep within their budget (runner/goldens.h, docs/goldens.md "Size"): the
// folder's bytes, each image's and each sidecar's; and every image has its sidecar and every
// sidecar its image (an image left without one is a golden no `goldens update` prunes).
TEST(Goldens, TheRepositorysGoldensStayWithinTheirBudget) {
  const fs::path dir = fs::path(HDRC_SOURCE_DIR) / "goldens";
  uintmax_t total = 0;
  size_t images = 0;
  std::vector<std::string> over, unpaired, foreign;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    const fs::path& p = e.path();
    const uintmax_t size = e.file_size();
    total += size;
    const std::string rel = p.lexically_relative(dir).generic_string();
    fs::path pair = p;
    if (p.extension() == ".exr") {
      ++images;
      if (size > hdrc::kGoldenImageBudgetBytes) over.push_back(rel + " " + std::to_string(size));
      if (!fs::exists(pair.replace_extension(".json"))) unpaired.push_back(rel);
    } else if (p.extension() == ".json") {
      if (size > hdrc::kGoldenSidecarBudgetBytes) over.push_back(rel + " " + std::to_string(size));
      if (!fs::exists(pair.replace_extension(".exr"))) unpaired.push_back(rel);
    } else if (rel != "README.md") {
      foreign.push_back(rel);
    }
  }
  EXPECT_GT(images, 1000u) << "the suite's goldens are in " << dir;
  EXPECT_LE(total, hdrc::kGoldensBudgetBytes) << "goldens/ holds " << total << " bytes";
  EXPECT_TRUE(over.empty()) << ::testing::PrintToString(over);
  EXPECT_TRUE(unpaired.empty()) << ::testing::PrintToString(unpaired);
  EXPECT_TRUE(foreign.empty()) << ::testing::PrintToString(foreign);
}

}  // namespace
