// Inputs the fuzzers of fuzz/ found that crashed, hung or exhausted memory, one test each, with
// the input rebuilt here byte by byte (how each was found: the comment above it).
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/exr_header.h"
#include "core/image.h"
#include "runner/case_loader.h"
#include "runner/export.h"
#include "runner/tolerance.h"

namespace {

namespace fs = std::filesystem;

std::string le32(uint32_t v) {
  return {static_cast<char>(v & 0xff), static_cast<char>(v >> 8 & 0xff),
          static_cast<char>(v >> 16 & 0xff), static_cast<char>(v >> 24 & 0xff)};
}

std::string attribute(const std::string& name, const std::string& type, uint32_t size,
                      const std::string& value) {
  return name + '\0' + type + '\0' + le32(size) + value;
}

const std::string kMagic = std::string("\x76\x2f\x31\x01", 4) + le32(2);

fs::path write_temp(const std::string& name, const std::string& bytes) {
  const fs::path p =
      fs::temp_directory_path() / ("hdrc_fuzz_found_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p, std::ios::binary) << bytes;
  return p;
}

// fuzz/image_fuzzer, 10 s timeout: a string attribute whose size field reads 0x69784500
// (1.77 GB) in a 219-byte file; OpenEXR 3.1 allocated and cleared 1.77 GB before reading it
// (11 s, 1.2 GB RSS). Now refused before OpenEXR sees the file.
TEST(FuzzFound, AnExrAttributeLargerThanTheFileIsRefusedBeforeDecoding) {
  const fs::path p = write_temp(
      "attr.exr", kMagic + attribute("Exif:ImageHistory", "string", 0x69784500u, "Qoi --pattern"));
  const auto start = std::chrono::steady_clock::now();
  auto img = hdrc::read_image(p.string());
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_FALSE(img.ok());
  const std::string e = img.error().to_string();
  EXPECT_NE(e.find(p.string()), std::string::npos) << e;
  EXPECT_NE(e.find("attribute 'Exif:ImageHistory' declares 1769489664 bytes"), std::string::npos)
      << e;
  EXPECT_LT(seconds, 2.0);
  fs::remove(p);
}

// The same class: a data window beyond the pixel limit (OpenEXR sizes its offset table from it),
// and a multi-part file's chunkCount beyond what the file can hold.
TEST(FuzzFound, AnExrDataWindowOrChunkCountBeyondTheLimitsIsRefused) {
  const std::string box = le32(0) + le32(0) + le32(99999) + le32(99999);
  auto e = hdrc::check_exr_header(
      write_temp("window.exr", kMagic + attribute("dataWindow", "box2i", 16, box) + '\0').string());
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error().to_string().find("the data window is 100000x100000"), std::string::npos)
      << e.error().to_string();
  const std::string multipart = std::string("\x76\x2f\x31\x01", 4) + le32(2 | 0x1000);
  e = hdrc::check_exr_header(
      write_temp("chunks.exr",
                 multipart + attribute("chunkCount", "int", 4, le32(1u << 30)) + '\0' + '\0')
          .string());
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error().to_string().find("chunkCount is 1073741824"), std::string::npos)
      << e.error().to_string();
  // 16 648 451 × 1 (under the pixel limit): ZIP's compressor would allocate 16 lines of it, 2 GB
  // (fuzz/image_fuzzer; the file is fuzz/corpus/image/oom_wide_window.exr).
  const std::string wide = le32(0) + le32(0) + le32(16648450) + le32(0);
  e = hdrc::check_exr_header(
      write_temp("wide.exr", kMagic + attribute("dataWindow", "box2i", 16, wide) + '\0').string());
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error().to_string().find("the data window is 16648451x1, at most 65536 pixels wide"),
            std::string::npos)
      << e.error().to_string();
  for (const char* n : {"window.exr", "chunks.exr", "wide.exr"})
    fs::remove(fs::temp_directory_path() /
               ("hdrc_fuzz_found_" + std::to_string(::getpid()) + "_" + n));
}

// A channel list declaring more bytes than its entries hold: OpenEXR reads the list by its
// structure and the next attribute right after it, so a 16M-wide data window placed inside the
// declared size reached OpenEXR's ZIP compressor (2 GB) while a walk by the declared size skipped
// it (fuzz/image_fuzzer, 2026-11-27; the file is fuzz/corpus/image/oom_chlist_hides_window.exr).
TEST(FuzzFound, AnExrChannelListIsWalkedAsOpenExrReadsIt) {
  const std::string channel = std::string("R\0", 2) + le32(2) + std::string(4, '\0') + le32(1) +
                              le32(1);  // FLOAT, pLinear + reserved, x/y sampling 1
  const std::string wide = le32(0) + le32(0) + le32(16648450) + le32(0);
  const std::string hidden = attribute("dataWindow", "box2i", 16, wide);
  const std::string list = channel + '\0';
  const std::string file =
      kMagic +
      attribute("channels", "chlist", static_cast<uint32_t>(list.size() + hidden.size()), list) +
      hidden + '\0';
  auto e = hdrc::check_exr_header(write_temp("chlist.exr", file).string());
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error().to_string().find("the data window is 16648451x1, at most 65536 pixels wide"),
            std::string::npos)
      << e.error().to_string();
  fs::remove(fs::temp_directory_path() /
             ("hdrc_fuzz_found_" + std::to_string(::getpid()) + "_chlist.exr"));
}

// A valid EXR, and a file that is not EXR at all, pass the header check unchanged.
TEST(FuzzFound, TheExrHeaderCheckPassesValidFiles) {
  hdrc::Image img(3, 2);
  for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = 0.25 * static_cast<double>(i);
  const fs::path p =
      fs::temp_directory_path() / ("hdrc_fuzz_found_" + std::to_string(::getpid()) + "_valid.exr");
  ASSERT_TRUE(hdrc::write_exr(p.string(), img).ok());
  EXPECT_TRUE(hdrc::check_exr_header(p.string()).ok());
  auto back = hdrc::read_image(p.string());
  ASSERT_TRUE(back.ok()) << back.error().to_string();
  EXPECT_EQ(back->data, img.data);
  fs::remove(p);
  EXPECT_TRUE(hdrc::check_exr_header(write_temp("text.txt", "not an image").string()).ok());
  fs::remove(fs::temp_directory_path() /
             ("hdrc_fuzz_found_" + std::to_string(::getpid()) + "_text.txt"));
}

// A number beyond a double's range (1e999) made nlohmann throw out_of_range.406, which the loaders
// did not catch (they caught parse_error only): std::terminate. Found by hand while checking the
// fuzzers' reach (10 minutes of fuzz/case_file_fuzzer had not produced it; fuzz/json.dict now
// gives the fuzzers JSON's number syntax). Every loader now reports it as malformed JSON naming
// the file.
TEST(FuzzFound, ANumberBeyondADoubleIsAnErrorNamingTheFile) {
  const std::string text = R"({"stage": "tonemap", "cvars": {"r.LUT.Size": 1e999}})";
  std::vector<hdrc::Error> errors;
  auto cases = hdrc::parse_case_file("cases/t/big.json", text, "cases", "t/big",
                                     hdrc::SuiteDefaults{}, &errors);
  EXPECT_TRUE(cases.empty());
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].to_string().find("cases/t/big.json"), std::string::npos);
  EXPECT_NE(errors[0].to_string().find("number overflow parsing '1e999'"), std::string::npos)
      << errors[0].to_string();

  errors.clear();
  hdrc::parse_tolerance_overlays("tolerance_overlays.json", R"({"overlays": [1e999]})", &errors);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].to_string().find("number overflow"), std::string::npos);

  const fs::path p = write_temp("params.json", R"({"stage": "tonemap", "params": -1e999})");
  auto rc = hdrc::load_exported_case(p.string());
  ASSERT_FALSE(rc.ok());
  EXPECT_NE(rc.error().to_string().find("number overflow"), std::string::npos);
  EXPECT_NE(rc.error().to_string().find(p.string()), std::string::npos);
  fs::remove(p);
}

}  // namespace
