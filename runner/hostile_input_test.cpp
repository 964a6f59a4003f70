// Hostile input, table-driven (issue 12): every row builds a small suite in a fresh folder T,
// plants one bad input (a loader's file, a flag, an image, a candidate command), runs the binary
// under a hard time limit, and asserts the exit code, the key parts of the message, that the
// output is valid UTF-8 with no crash and no hang, and that nothing outside the folder the command
// may write (T/out unless the row says otherwise) changed.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "core/image.h"
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
using namespace hdrc::test;  // runner/test_support.h

namespace {

// Every row runs under a hard limit of 60 s: a hang is killed (exit 137) and reported as such.
Ran run_limited(const std::string& args) {
  return hdrc::test::run(args, "", 60);
}

// A small valid case: the shaper on an 8x2 log ramp (id "base/log_ramp").
const char* kBaseCase =
    R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 8, "height": 2}})";

void write_image(const fs::path& p, int w, int h, const std::vector<std::string>& channels,
                 OIIO::TypeDesc type = OIIO::TypeDesc::FLOAT) {
  fs::create_directories(p.parent_path());
  OIIO::ImageSpec spec(w, h, static_cast<int>(channels.size()), type);
  spec.channelnames = channels;
  spec.alpha_channel = -1;
  std::vector<float> px(static_cast<size_t>(w) * h * channels.size(), 0.5f);
  auto out = OIIO::ImageOutput::create(p.string());
  ASSERT_TRUE(out && out->open(p.string(), spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
  ASSERT_TRUE(out->close());
}

// An 8x2 EXR whose header claims 16384x16384 (dataWindow and displayWindow patched): decoding it
// would allocate gigabytes; the header check must refuse it first.
void write_huge_header_exr(const fs::path& p) {
  write_image(p, 8, 2, {"R", "G", "B", "A"});
  std::string bytes = read(p);
  for (const char* attr : {"dataWindow", "displayWindow"}) {
    const std::string key = std::string(attr) + std::string("\0box2i\0", 7);
    const size_t at = bytes.find(key);
    ASSERT_NE(at, std::string::npos) << attr;
    const size_t box = at + key.size() + 4;  // after the attribute's size
    const int32_t v[4] = {0, 0, 16383, 16383};
    bytes.replace(box, 16, reinterpret_cast<const char*>(v), 16);
  }
  write(p, bytes);
}

// A ZIP EXR of w x h black pixels, written a scanline at a time (a few MB however large).
void write_large_exr(const fs::path& p, int w, int h) {
  fs::create_directories(p.parent_path());
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::HALF);
  spec.attribute("compression", "zip");
  auto out = OIIO::ImageOutput::create(p.string());
  ASSERT_TRUE(out && out->open(p.string(), spec));
  std::vector<float> line(static_cast<size_t>(w) * 3, 0.0f);
  for (int y = 0; y < h; ++y)
    ASSERT_TRUE(out->write_scanline(y, 0, OIIO::TypeDesc::FLOAT, line.data()));
  ASSERT_TRUE(out->close());
}

// The files of T except those under `writable` (relative), with their digests.
std::map<std::string, std::string> snapshot(const fs::path& t, const std::string& writable) {
  auto all = hdrc::tree_digest(t.string());
  std::map<std::string, std::string> out;
  for (auto& [k, v] : all)
    if (writable.empty() || (k != writable && k.rfind(writable + "/", 0) != 0)) out[k] = v;
  return out;
}

struct Row {
  std::string name;
  std::function<void(const fs::path& t)> setup;  // plants the bad input (may be empty)
  std::string args;                              // {T} is replaced by the row's folder
  int code;
  std::vector<std::string> expect;  // substrings of the combined output
  std::string writable = "out";     // the folder of T the command may change
  int settle_s = 0;  // seconds waited after the command before T is compared (late writers)
};

std::string subst(std::string s, const fs::path& t) {
  for (size_t at; (at = s.find("{T}")) != std::string::npos;) s.replace(at, 3, t.string());
  return s;
}

void candidate(const fs::path& t, const std::string& script) {
  write(t / "cand.sh", "#!/bin/sh\n" + script + "\n");
}

void case_file(const fs::path& t, const std::string& name, const std::string& text) {
  write(t / "cases" / name, text);
}

fs::path ref_image() {
  return fs::temp_directory_path() / ("hdrc_hostile_ref_" + std::to_string(::getpid())) / "ref.exr";
}

const std::string kList = "list --cases {T}/cases";
const std::string kRun = "run --engine reference --cases {T}/cases --out {T}/out";
const std::string kVerifyCmd =
    "verify --cases {T}/cases --out {T}/out --candidate-cmd 'sh {T}/cand.sh {output} {input}'";
const std::string kVerifyDir = "verify --cases {T}/cases --out {T}/out --candidate-dir {T}/cand";

std::string deep(const std::string& open, size_t n) {
  std::string s;
  s.reserve(open.size() * n);
  for (size_t i = 0; i < n; ++i) s += open;
  return s;
}

std::vector<Row> rows() {
  std::vector<Row> r;
  auto add = [&](Row row) { r.push_back(std::move(row)); };
  const std::string case_json = kBaseCase;

  // ---- JSON: overflowing numbers, deep nesting, malformed text, in every loader -------------
  struct Loader {
    const char* tag;
    std::string file;  // under cases/
    std::string args;  // the command that reads it
    std::string valid_prefix;
  };
  const std::vector<Loader> loaders = {
      {"case", "bad.json", kList, ""},
      {"defaults", "defaults.json", kList, ""},
      {"known_limits", "known_limits.json", kList, ""},
      {"overlays", "tolerance_overlays.json", kRun, ""},
      {"coverage", "coverage.json", "coverage --cases {T}/cases", ""},
  };
  for (const Loader& l : loaders) {
    const std::string f = l.file;
    auto plant = [f](std::string text) {
      return [f, text](const fs::path& t) { case_file(t, f, text); };
    };
    add({"" + std::string(l.tag) + "_overflow_1e999",
         plant(R"({"description": 1e999})"),
         l.args,
         2,
         {f, "malformed JSON", "number overflow", "1e999"}});
    add({"" + std::string(l.tag) + "_overflow_neg",
         plant(R"({"x": [-1e400]})"),
         l.args,
         2,
         {f, "malformed JSON", "-1e400"}});
    add({"" + std::string(l.tag) + "_deep_arrays",
         plant(deep("[", 200000)),
         l.args,
         2,
         {f, "nested more than 100 levels"}});
    add({"" + std::string(l.tag) + "_deep_objects",
         plant(deep("{\"a\":", 50000)),
         l.args,
         2,
         {f, "nested more than 100 levels"}});
    add({"" + std::string(l.tag) + "_truncated",
         plant(R"({"stage": "sha)"),
         l.args,
         2,
         {f, "malformed JSON"}});
    add({"" + std::string(l.tag) + "_bad_utf8",
         plant("{\"description\": \"\xff\xfe\"}"),
         l.args,
         2,
         {f, "malformed JSON"}});
    add({"" + std::string(l.tag) + "_fifo",
         [f](const fs::path& t) {
           fs::create_directories(t / "cases");
           ASSERT_EQ(::mkfifo((t / "cases" / f).c_str(), 0644), 0);
         },
         l.args,
         2,
         {f, "not a regular file"}});
    add({"" + std::string(l.tag) + "_dangling_symlink",
         [f](const fs::path& t) { fs::create_symlink(t / "nowhere.json", t / "cases" / f); },
         l.args,
         2,
         {f}});
    add({"" + std::string(l.tag) + "_too_big",
         [f](const fs::path& t) {
           write(t / "cases" / f, "{}");
           fs::resize_file(t / "cases" / f, (size_t{64} << 20) + 1);  // sparse
         },
         l.args,
         2,
         {f, "over the limit"}});
  }
  add({"case_empty_file",
       [](const fs::path& t) { case_file(t, "bad.json", ""); },
       kList,
       2,
       {"bad.json", "malformed JSON"}});
  add({"case_not_object",
       [](const fs::path& t) { case_file(t, "bad.json", "null"); },
       kList,
       2,
       {"bad.json", "a case file is a JSON object"}});
  add({"case_nul_byte",
       [](const fs::path& t) { case_file(t, "bad.json", std::string("{\"a\0\": 1}", 10)); },
       kList,
       2,
       {"bad.json", "malformed JSON"}});
  add({"defaults_is_folder",
       [](const fs::path& t) { fs::create_directories(t / "cases/defaults.json"); },
       kList,
       2,
       {"defaults.json", "not a regular file"}});
  add({"case_deep_nesting_in_string_is_fine",
       [](const fs::path& t) {
         case_file(
             t, "b.json",
             R"({"description": ")" + deep("[", 1000) +
                 R"(", "stage": "shaper", "input": {"stimulus": "log_ramp", "width": 8, "height": 2}})");
       },
       kList,
       0,
       {"b/log_ramp"}});

  // ---- case files: where they may live and what they may be called --------------------------
  add({"case_symlink_outside",
       [](const fs::path& t) {
         write(t / "elsewhere/evil.json", kBaseCase);
         fs::create_symlink(t / "elsewhere/evil.json", t / "cases/evil.json");
       },
       kList,
       2,
       {"evil.json", "outside the cases folder"}});
  add({"case_symlink_outside_goldens_update",
       [](const fs::path& t) {
         write(t / "elsewhere/evil.json", kBaseCase);
         fs::create_symlink(t / "elsewhere/evil.json", t / "cases/evil.json");
       },
       "goldens update --cases {T}/cases --goldens {T}/out",
       2,
       {"outside the cases folder"}});
  add({"case_symlink_inside_ok",
       [](const fs::path& t) {
         write(t / "cases/real/a.json", kBaseCase);
         fs::create_symlink("real/a.json", t / "cases/alias.json");
       },
       kList,
       0,
       {"alias/log_ramp", "real/a/log_ramp"}});
  add({"case_symlinked_folder",
       [](const fs::path& t) {
         write(t / "cases/real/a.json", kBaseCase);
         fs::create_directory_symlink("real", t / "cases/linked");
       },
       kList,
       2,
       {"linked", "symlinked folder"}});
  add({"case_symlinked_folder_outside",
       [](const fs::path& t) {
         write(t / "elsewhere/a.json", kBaseCase);
         fs::create_directory_symlink(t / "elsewhere", t / "cases/linked");
       },
       kList,
       2,
       {"linked", "outside the cases folder"}});
  add({"casefile_dangling_symlink",
       [](const fs::path& t) { fs::create_symlink(t / "gone.json", t / "cases/gone.json"); },
       kList,
       2,
       {"gone.json", "dangling symlink"}});
  add({"case_name_not_utf8",
       [](const fs::path& t) { case_file(t, "bad\xff\xfe.json", kBaseCase); },
       kList,
       2,
       {"not valid UTF-8", "\xEF\xBF\xBD"}});
  add({"case_name_control_char",
       [](const fs::path& t) { case_file(t, "bad\nname.json", kBaseCase); },
       kList,
       2,
       {"control character"}});
  add({"case_name_dotdot",
       [](const fs::path& t) { case_file(t, "...json", kBaseCase); },
       kList,
       2,
       {"'..' component"}});
  add({"input_name_dotdot",
       [](const fs::path& t) {
         case_file(
             t, "n.json",
             R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 8, "height": 2, "name": ".."}})");
       },
       kList,
       2,
       {"n.json", "'..' component"}});
  add({"input_name_dot",
       [](const fs::path& t) {
         case_file(
             t, "n.json",
             R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 8, "height": 2, "name": "."}})");
       },
       kList,
       2,
       {"n.json", "'.' component"}});

  // ---- resource limits in case files -------------------------------------------------------
  add({"matrix_full_5e8",
       [](const fs::path& t) {
         std::string m =
             R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 8, "height": 2}, "matrix": {"settings": {)";
         const char* names[] = {"FilmSlope",     "FilmToe",        "FilmShoulder",
                                "FilmBlackClip", "FilmWhiteClip",  "BlueCorrection",
                                "ExpandGamut",   "ToneCurveAmount"};
         for (int i = 0; i < 8; ++i) {  // 13^8 = 8.2e8 cases
           m += std::string(i ? "," : "") + "\"" + names[i] + "\": [";
           for (int v = 0; v < 13; ++v) {  // appended: GCC 12 -O3 -Wrestrict (bug 105329)
             if (v) m += ',';
             m += std::to_string(0.01 * (v + 1));
           }
           m += "]";
         }
         case_file(t, "huge.json", m + "}}}");
       },
       kList,
       2,
       {"huge.json", "/matrix", "expands to about", "at most 20000"}});
  add({"stimulus_8192_squared",
       [](const fs::path& t) {
         case_file(
             t, "big.json",
             R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 8192, "height": 8192}})");
       },
       kList,
       2,
       {"big.json", "/input", "8192x8192", "more pixels than the limit"}});
  // Issue 29: the largest image is what fits the per-case budget (runner/budget.h); a case over
  // it is refused before any work, naming the case, its size, the estimate and the budget.
  add({"case_over_memory_budget",
       [](const fs::path& t) {
         case_file(
             t, "big.json",
             R"({"stage": "tonemap", "input": {"stimulus": "random", "width": 4096, "height": 4096}})");
       },
       kRun,
       2,
       {"big.json", "case big/random", "a 4096x4096 tonemap case needs an estimated",
        "over the memory budget of 1.50 GB per case", "refused before any work",
        "nothing was run"}});
  // And a case over a budget set on the command line (--memory-budget GB): refused the same way.
  add({"case_over_configured_memory_budget",
       [](const fs::path& t) {
         case_file(
             t, "c.json",
             R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 512, "height": 512}})");
       },
       kRun + " --memory-budget 0.2",
       2,
       {"c.json", "case c/log_ramp", "a 512x512 shaper case needs an estimated",
        "over the memory budget of 0.20 GB per case", "refused before any work",
        "nothing was run"}});
  add({"stimulus_width_huge",
       [](const fs::path& t) {
         case_file(
             t, "big.json",
             R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 1e300, "height": 2}})");
       },
       kList,
       2,
       {"big.json", "/input/width", "integers 1 to 8192"}});
  add({"stimulus_width_negative",
       [](const fs::path& t) {
         case_file(
             t, "big.json",
             R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": -8, "height": 2}})");
       },
       kList,
       2,
       {"big.json", "/input/width"}});

  // ---- input image files -------------------------------------------------------------------
  auto file_case = [](const fs::path& t, const std::string& file) {
    case_file(t, "img.json",
              R"({"stage": "shaper", "input": {"file": ")" + file + R"(", "name": "f"}})");
  };
  add({"input_file_escapes",
       [&](const fs::path& t) {
         write_image(t / "outside.exr", 8, 2, {"R", "G", "B"});
         file_case(t, "../outside.exr");
       },
       kList,
       2,
       {"img.json", "/input/file", "leaves the cases directory"}});
  add({"input_file_absolute",
       [&](const fs::path& t) { file_case(t, "/etc/passwd"); },
       kList,
       2,
       {"img.json", "leaves the cases directory"}});
  add({"input_file_symlink_out",
       [&](const fs::path& t) {
         write_image(t / "outside.exr", 8, 2, {"R", "G", "B"});
         fs::create_directories(t / "cases/inputs");
         fs::create_symlink(t / "outside.exr", t / "cases/inputs/l.exr");
         file_case(t, "inputs/l.exr");
       },
       kList,
       2,
       {"img.json", "leaves the cases directory"}});
  add({"input_file_dev_zero",
       [&](const fs::path& t) {
         fs::create_directories(t / "cases/inputs");
         fs::create_symlink("/dev/zero", t / "cases/inputs/z.exr");
         file_case(t, "inputs/z.exr");
       },
       kList,
       2,
       {"img.json", "leaves the cases directory"}});
  add({"input_file_fifo",
       [&](const fs::path& t) {
         fs::create_directories(t / "cases/inputs");
         ASSERT_EQ(::mkfifo((t / "cases/inputs/p.exr").c_str(), 0644), 0);
         file_case(t, "inputs/p.exr");
       },
       kList,
       2,
       {"img.json", "is not a regular file"}});
  add({"input_file_missing",
       [&](const fs::path& t) { file_case(t, "inputs/none.exr"); },
       kList,
       2,
       {"img.json", "does not exist"}});
  add({"input_file_is_folder",
       [&](const fs::path& t) {
         fs::create_directories(t / "cases/inputs/d.exr");
         file_case(t, "inputs/d.exr");
       },
       kList,
       2,
       {"img.json", "is not a regular file"}});
  add({"input_png_named_exr",
       [&](const fs::path& t) {
         write_image(t / "cases/inputs/p.png", 8, 2, {"R", "G", "B"}, OIIO::TypeDesc::UINT8);
         fs::rename(t / "cases/inputs/p.png", t / "cases/inputs/p.exr");
         file_case(t, "inputs/p.exr");
       },
       kRun,
       1,
       {"p.exr", "not an OpenEXR file"}});
  add({"input_xyz_channels",
       [&](const fs::path& t) {
         write_image(t / "cases/inputs/x.exr", 8, 2, {"X", "Y", "Z"});
         file_case(t, "inputs/x.exr");
       },
       kRun,
       1,
       {"x.exr", "channels are X,Y,Z"}});
  add({"input_bad_utf8_channels",
       [&](const fs::path& t) {
         write_image(t / "cases/inputs/u.exr", 8, 2, {"\xff\xfe", "G", "B"});
         file_case(t, "inputs/u.exr");
       },
       kRun,
       1,
       {"u.exr", "channels are"}});
  add({"input_header_16384_squared",
       [&](const fs::path& t) {
         write_huge_header_exr(t / "cases/inputs/h.exr");
         file_case(t, "inputs/h.exr");
       },
       kRun,
       1,
       {"h.exr", "the data window is 16384x16384", "at most 16777216 pixels"}});
  add({"input_4097_squared_zip_exr",
       [&](const fs::path& t) {
         write_large_exr(t / "cases/inputs/l.exr", 4097, 4097);
         file_case(t, "inputs/l.exr");
       },
       kRun,
       1,
       {"l.exr", "4097x4097", "at most 16777216 pixels"}});
  add({"input_truncated_exr",
       [&](const fs::path& t) {
         write_image(t / "cases/inputs/t.exr", 8, 2, {"R", "G", "B"});
         fs::resize_file(t / "cases/inputs/t.exr", 40);
         file_case(t, "inputs/t.exr");
       },
       kRun,
       1,
       {"t.exr"}});
  add({"input_empty_exr",
       [&](const fs::path& t) {
         write(t / "cases/inputs/e.exr", "");
         file_case(t, "inputs/e.exr");
       },
       kRun,
       1,
       {"e.exr", "not an OpenEXR file"}});

  // ---- flags: output folders ---------------------------------------------------------------
  add({"out_empty",
       nullptr,
       "run --engine reference --cases {T}/cases --out ''",
       2,
       {"--out", "empty"}});
  add({"out_is_cases",
       nullptr,
       "run --engine reference --cases {T}/cases --out {T}/cases",
       2,
       {"--out", "itself"}});
  add({"out_inside_cases",
       nullptr,
       "run --engine reference --cases {T}/cases --out {T}/cases/sub",
       2,
       {"--out", "is inside"}});
  add({"out_symlink_to_cases",
       [](const fs::path& t) { fs::create_directory_symlink(t / "cases", t / "link"); },
       "run --engine reference --cases {T}/cases --out {T}/link",
       2,
       {"--out", "itself"}});
  add({"out_holds_cases",
       nullptr,
       "run --engine reference --cases {T}/cases --out {T}",
       2,
       {"--out", "holds"}});
  add({"out_is_goldens",
       [](const fs::path& t) { fs::create_directories(t / "g"); },
       "run --engine reference --cases {T}/cases --goldens {T}/g --out {T}/g",
       2,
       {"--out", "itself"}});
  add({"out_is_a_file",
       [](const fs::path& t) { write(t / "out", "x"); },
       kRun,
       2,
       {"--out", "not a folder"}});
  add({"out_unwritable",
       nullptr,
       "run --engine reference --cases {T}/cases --out /proc/version/out",
       2,
       {"--out", "cannot create the folder"}});
  add({"out_foreign_folder",
       [](const fs::path& t) { write(t / "out/cases/mine.txt", "precious"); },
       kRun,
       2,
       {"not written by hdrconform"}});
  add({"verify_out_is_cases",
       nullptr,
       "verify --cases {T}/cases --out {T}/cases --candidate-dir {T}/cases",
       2,
       {"--out", "itself"}});
  add({"export_out_is_cases",
       nullptr,
       "export --cases {T}/cases --out {T}/cases",
       2,
       {"--out", "itself"}});
  add({"export_out_inside_cases",
       nullptr,
       "export --cases {T}/cases --out {T}/cases/x",
       2,
       {"--out", "is inside"}});
  add({"export_out_empty", nullptr, "export --cases {T}/cases --out ''", 2, {"--out", "empty"}});
  add({"goldens_is_cases",
       nullptr,
       "goldens update --cases {T}/cases --goldens {T}/cases",
       2,
       {"--goldens", "itself"}});
  add({"goldens_inside_cases",
       nullptr,
       "goldens update --cases {T}/cases --goldens {T}/cases/g",
       2,
       {"--goldens", "is inside"}});
  add({"goldens_holds_cases",
       nullptr,
       "goldens update --cases {T}/cases --goldens {T}",
       2,
       {"--goldens", "holds"}});
  add({"goldens_empty",
       nullptr,
       "goldens update --cases {T}/cases --goldens ''",
       2,
       {"--goldens"}});
  // goldens diff (runner/goldens_diff.h): its --out is protected like run's, its sources named.
  add({"goldens_diff_out_is_cases",
       nullptr,
       "goldens diff --cases {T}/cases --goldens {T}/out --old {T}/out --out {T}/cases",
       2,
       {"--out", "itself"}});
  add({"goldens_diff_out_is_old",
       nullptr,
       "goldens diff --cases {T}/cases --goldens {T}/cases/g --old {T}/out --out {T}/out",
       2,
       {"--out", "itself"}});
  add({"goldens_diff_old_missing",
       nullptr,
       "goldens diff --cases {T}/cases --goldens {T}/cases --old {T}/nowhere --out {T}/out/r",
       2,
       {"--old", "nowhere", "not a folder"}});
  add({"goldens_prunes_only_its_own",
       [](const fs::path& t) {
         write(t / "out/package.json", "{\"name\": \"x\"}");
         write(t / "out/notes/readme.exr", "not a golden");
         write(t / "out/old/case.json", "{\"case\": \"someone else\", \"case_hash\": \"x\"}");
       },
       "goldens update --cases {T}/cases --goldens {T}/out -j 1",
       0,
       {"wrote", "left alone: 2 file(s)"}});

  // ---- flags: numbers and choices ----------------------------------------------------------
  for (const char* bad : {"nan", "inf", "-1", "0", "1e999", "abc", "1e6", "-nan"})
    add({std::string("timeout_") + (bad[0] == '-' ? "neg_" : "") + (bad + (bad[0] == '-')),
         nullptr,
         "verify --cases {T}/cases --out {T}/out --timeout=" + std::string(bad) +
             " --candidate-cmd 'true {output}'",
         2,
         {"--timeout", "not a number of seconds"}});
  for (const char* bad : {"-1", "1e999", "99999", "x"})
    add({std::string("jobs_") + (bad[0] == '-' ? "neg" : bad),
         nullptr,
         kRun + " --jobs=" + bad,
         2,
         {"--jobs"}});
  for (const char* bad : {"0/1", "2/1", "1/0", "abc", "1/2/3", "-1/2"})
    add({std::string("shard_") + bad, nullptr, kRun + " --shard=" + bad, 2, {"--shard", "K/N"}});
  add({"shard_empty_run", nullptr, kRun + " --shard 2/2", 2, {"--shard 2/2 selects no case"}});
  add({"shard_empty_list", nullptr, kList + " --shard 2/2", 2, {"selects no case"}});
  add({"shard_empty_export",
       nullptr,
       "export --cases {T}/cases --out {T}/out --shard 3/3",
       2,
       {"selects no case"}});
  add({"cases_missing", nullptr, "list --cases {T}/none", 2, {"none", "does not exist"}});
  add({"cases_is_file",
       [](const fs::path& t) { write(t / "f", "x"); },
       "list --cases {T}/f",
       2,
       {"is not a folder"}});
  add({"cases_is_dev_null", nullptr, "list --cases /dev/null", 2, {"is not a folder"}});
  add({"filter_matches_nothing", nullptr, kList + " --filter 'zzz*'", 2, {"no case matches"}});
  add({"verify_no_candidate",
       nullptr,
       "verify --cases {T}/cases --out {T}/out",
       2,
       {"exactly one of"}});
  add({"verify_dir_missing", nullptr, kVerifyDir, 2, {"does not exist"}});
  add({"verify_dir_is_file",
       [](const fs::path& t) { write(t / "cand", "x"); },
       kVerifyDir,
       2,
       {"is not a folder"}});
  add({"verify_cmd_empty",
       nullptr,
       "verify --cases {T}/cases --out {T}/out --candidate-cmd ''",
       2,
       {"--candidate-cmd"}});
  add({"verify_cmd_unterminated",
       nullptr,
       "verify --cases {T}/cases --out {T}/out --candidate-cmd 'x \"a {output}'",
       2,
       {"unterminated"}});
  add({"verify_cmd_no_output",
       nullptr,
       "verify --cases {T}/cases --out {T}/out --candidate-cmd 'true {input}'",
       2,
       {"has no {output}"}});
  add({"report_missing_dir", nullptr, "report {T}/none", 2, {"results.json"}});
  // A read-only command writes nothing into a folder that is not a run's output (issue 29: report
  // CASES left CASES/.lock).
  add({"report_cases_folder_writes_nothing",
       nullptr,
       "report {T}/cases",
       2,
       {"{T}/cases/results.json", "cannot open"}});
  add({"report_foreign_results_writes_nothing",
       [](const fs::path& t) { write(t / "other/results.json", "[1, 2]"); },
       "report {T}/other",
       2,
       {"{T}/other/results.json", "/cases"}});
  add({"report_results_overflow",
       [](const fs::path& t) { write(t / "out/results.json", R"({"cases": [1e999]})"); },
       "report {T}/out",
       2,
       {"results.json", "malformed JSON", "number overflow"}});
  add({"report_results_deep",
       [](const fs::path& t) { write(t / "out/results.json", deep("[", 200000)); },
       "report {T}/out",
       2,
       {"results.json", "nested more than"}});
  add({"report_results_fifo",
       [](const fs::path& t) {
         fs::create_directories(t / "out");
         ASSERT_EQ(::mkfifo((t / "out/results.json").c_str(), 0644), 0);
       },
       "report {T}/out",
       2,
       {"results.json", "not a regular file"}});
  add({"report_results_folder",
       [](const fs::path& t) { fs::create_directories(t / "out/results.json"); },
       "report {T}/out",
       2,
       {"results.json", "not a regular file"}});
  add({"shader_dir_self_include",
       [](const fs::path& t) {
         const fs::path stages = fs::path(HDRC_SOURCE_DIR) / "gpu/shaders/stages";
         for (const auto& e : fs::directory_iterator(stages))
           write(t / "shaders/stages" / e.path().filename(),
                 "#version 450\n#extension GL_GOOGLE_include_directive : require\n"
                 "#include \"self.glsl\"\nvoid main() {}\n");
         write(t / "shaders/stages/self.glsl", "#include \"self.glsl\"\n");
       },
       "run --cases {T}/cases --out {T}/out --shader-dir {T}/shaders",
       1,
       {"#include nested more than 32 levels deep"}});

  // ---- candidate images (verify --candidate-dir) -------------------------------------------
  auto cand = [](std::function<void(const fs::path&)> make) {
    return [make](const fs::path& t) {
      fs::create_directories(t / "cand/base");
      make(t / "cand/base/log_ramp.exr");
    };
  };
  add({"cand_fifo",
       cand([](const fs::path& p) { ASSERT_EQ(::mkfifo(p.c_str(), 0644), 0); }),
       kVerifyDir,
       1,
       {"not a regular file"}});
  add({"cand_dev_zero",
       cand([](const fs::path& p) { fs::create_symlink("/dev/zero", p); }),
       kVerifyDir,
       1,
       {"not a regular file"}});
  add({"cand_dev_urandom",
       cand([](const fs::path& p) { fs::create_symlink("/dev/urandom", p); }),
       kVerifyDir,
       1,
       {"not a regular file"}});
  add({"cand_dangling",
       cand([](const fs::path& p) { fs::create_symlink("/nonexistent", p); }),
       kVerifyDir,
       1,
       {"No such file"}});
  add({"cand_folder",
       cand([](const fs::path& p) { fs::create_directories(p); }),
       kVerifyDir,
       1,
       {"not a regular file"}});
  add({"cand_png_named_exr",
       cand([](const fs::path& p) {
         write_image(p.string() + ".png", 8, 2, {"R", "G", "B"}, OIIO::TypeDesc::UINT8);
         fs::rename(p.string() + ".png", p);
       }),
       kVerifyDir,
       1,
       {"not an OpenEXR file"}});
  add({"cand_xyz",
       cand([](const fs::path& p) {
         write_image(p, 8, 2, {"X", "Y", "Z"});
       }),
       kVerifyDir,
       1,
       {"channels are X,Y,Z"}});
  add({"cand_two_channels",
       cand([](const fs::path& p) {
         write_image(p, 8, 2, {"R", "G"});
       }),
       kVerifyDir,
       1,
       {"2 channel(s)"}});
  add({"cand_16384_header",
       cand([](const fs::path& p) { write_huge_header_exr(p); }),
       kVerifyDir,
       1,
       {"the data window is 16384x16384", "at most 16777216 pixels"}});
  add({"cand_8192_squared",
       cand([](const fs::path& p) { write_large_exr(p, 8192, 8192); }),
       kVerifyDir,
       1,
       {"8192x8192", "at most 16777216 pixels"}});
  add({"cand_empty",
       cand([](const fs::path& p) { write(p, ""); }),
       kVerifyDir,
       1,
       {"not an OpenEXR file"}});
  add({"cand_garbage",
       cand([](const fs::path& p) { write(p, std::string(1000, '\xff')); }),
       kVerifyDir,
       1,
       {"not an OpenEXR file"}});
  add({"cand_magic_then_garbage",
       cand([](const fs::path& p) { write(p, "\x76\x2f\x31\x01" + std::string(500, '\xfe')); }),
       kVerifyDir,
       1,
       {"corrupt OpenEXR header"}});
  add({"cand_wrong_size",
       cand([](const fs::path& p) {
         write_image(p, 4, 4, {"R", "G", "B"});
       }),
       kVerifyDir,
       1,
       {"4x4"}});

  // ---- candidate commands (verify --candidate-cmd) -----------------------------------------
  auto script = [](const std::string& text) {
    return [text](const fs::path& t) { candidate(t, subst(text, t)); };
  };
  add({"cmd_binary_output",
       script("head -c 3000 /dev/urandom; printf '\\377\\376'; exit 1"),
       kVerifyCmd,
       1,
       {"exited with status 1"}});
  add({"cmd_huge_output",
       script("head -c 50000000 /dev/zero | tr '\\0' x; exit 1"),
       kVerifyCmd,
       1,
       {"exited with status 1"}});
  add({"cmd_endless_output", script("yes"), kVerifyCmd + " --timeout 2", 1, {"timed out"}});
  add({"cmd_sleeps", script("sleep 30"), kVerifyCmd + " --timeout 1", 1, {"timed out"}});
  add({"cmd_child_keeps_pipe",
       script("(sleep 30; echo late) & exit 3"),
       kVerifyCmd,
       1,
       {"exited with status 3"}});
  // Descendants cannot outlive verify (issue 29): a child that leaves the command's process
  // group (setsid), or also clears its environment (and with it the command's token), and writes
  // into the cases folder seconds later. It is killed at the case's end (or, without the token,
  // before the run is published), so the folder is unchanged long after verify returned.
  const std::string late_append = "sleep 2; echo late >> {T}/cases/base.json";
  add({"cmd_setsid_child_appends_later",
       script("cp " + ref_image().string() + " \"$1\"; setsid sh -c '" + late_append +
              "' </dev/null >/dev/null 2>&1 &"),
       kVerifyCmd,
       0,
       {"1 passed"},
       "out",
       4});
  add({"cmd_setsid_grandchild_appends_later",
       script("cp " + ref_image().string() + " \"$1\"; (setsid sh -c '(" + late_append +
              ") &' </dev/null >/dev/null 2>&1 &)"),
       kVerifyCmd,
       0,
       {"1 passed"},
       "out",
       4});
  add({"cmd_setsid_env_cleared_child_appends_later",
       script("cp " + ref_image().string() +
              " \"$1\"; setsid env -i sh -c 'sleep 6; echo late >> " +
              "{T}/cases/base.json' </dev/null >/dev/null 2>&1 &"),
       kVerifyCmd,
       0,
       {"1 passed"},
       "out",
       8});
  add({"cmd_setsid_child_after_timeout",
       script("setsid sh -c '" + late_append + "' </dev/null >/dev/null 2>&1 & sleep 30"),
       kVerifyCmd + " --timeout 1",
       1,
       {"timed out", "killed with every process it started"},
       "out",
       4});
  add({"cmd_setsid_child_appends_during_case",
       script("setsid sh -c 'echo now >> {T}/cases/base.json' </dev/null >/dev/null 2>&1 & "
              "sleep 1; cp " +
              ref_image().string() + " \"$1\""),
       kVerifyCmd,
       1,
       {"changed while the run ran", "base.json (changed)", "not published"},
       "*"});
  add({"cmd_writes_2gib",
       script("head -c 2147483648 /dev/zero > \"$1\""),
       kVerifyCmd,
       1,
       {"size limit"}});
  add({"cmd_output_fifo", script("mkfifo \"$1\""), kVerifyCmd, 1, {"not a regular file"}});
  add({"cmd_output_dev_zero",
       script("ln -s /dev/zero \"$1\""),
       kVerifyCmd,
       1,
       {"not a regular file"}});
  add({"cmd_output_dev_urandom",
       script("ln -s /dev/urandom \"$1\""),
       kVerifyCmd,
       1,
       {"not a regular file"}});
  add({"cmd_output_png", script("cp {T}/p.png \"$1\""), kVerifyCmd, 1, {"not an OpenEXR file"}});
  add({"cmd_no_image", script("exit 0"), kVerifyCmd, 1, {"wrote no image"}});
  add({"cmd_not_found",
       nullptr,
       "verify --cases {T}/cases --out {T}/out --candidate-cmd '/nonexistent/prog {output}'",
       1,
       {"exited with status 127"}});
  add({"cmd_appends_to_case",
       script("cp " + ref_image().string() + " \"$1\"; echo ' ' >> {T}/cases/base.json"),
       kVerifyCmd,
       1,
       {"changed while the run ran", "base.json (changed)", "not published"},
       "*"});
  add({"cmd_sandboxed_cannot_write_cases",
       script("cp " + ref_image().string() +
              " \"$1\"; echo ' ' >> {T}/cases/base.json 2>/dev/null; touch {T}/escape 2>/dev/null; "
              "exit 0"),
       kVerifyCmd + " --sandbox",
       0,
       {"1 passed"}});
  add({"cmd_passes",
       script("cp " + ref_image().string() + " \"$1\""),
       kVerifyCmd,
       0,
       {"1 passed"}});
  // ---- more of the same classes -----------------------------------------------------------
  add({"probe_stdin_dev_zero", nullptr, "probe < /dev/zero", 2, {"<stdin>", "longer than 4096"}});
  add({"probe_stdin_binary",
       [](const fs::path& t) { write(t / "bin.txt", "\xff\xfe 1 2\n"); },
       "probe < {T}/bin.txt",
       2,
       {"<stdin>", "line 1", "expected three numbers"}});
  add({"out_runs_is_symlink",
       [](const fs::path& t) {
         write(t / "victim/keep.txt", "precious");
         fs::create_directories(t / "out");
         fs::create_directory_symlink(t / "victim", t / "out/.runs");
       },
       kRun,
       2,
       {"not written by hdrconform", "replaces the output folder whole"}});
  add({"out_current_is_folder",
       [](const fs::path& t) { fs::create_directories(t / "out/current"); },
       kRun,
       2,
       {"not written by hdrconform"}});
  add({"filter_pathological_glob",
       nullptr,
       kList + " --filter '*a*a*a*a*a*a*a*a*a*a*a*a*a*a*a*a*a*a*a*a*b'",
       2,
       {"no case matches"}});
  add({"out_legacy_results_adopted",
       [](const fs::path& t) {
         write(t / "out/results.json", "{\"tool\": \"hdrconform\", \"cases\": []}");
         write(t / "out/junit.xml", "<testsuites/>");
       },
       kRun,
       0,
       {"1 passed"}});
  return r;
}

void PrintTo(const Row& row, std::ostream* os) {
  *os << row.name;
}

class HostileInput : public ::testing::TestWithParam<Row> {
 protected:
  // The reference's own image of the base case, for candidates that pass. Made once; a failure
  // here is recorded and fails every row (GoogleTest reports a fatal failure in SetUpTestSuite as
  // the rows being skipped, and a skipped row must never read as a pass).
  static void SetUpTestSuite() {
    setup_error() = "";
    const fs::path dir = ref_image().parent_path();
    fs::remove_all(dir);
    write(dir / "cases/base.json", kBaseCase);
    const Ran r = run_limited("run --engine reference --images all --cases " +
                              (dir / "cases").string() + " --out " + (dir / "out").string());
    std::error_code ec;
    if (r.code != 0)
      setup_error() =
          "the reference run of the base case exited " + std::to_string(r.code) + ": " + r.out;
    else if (!fs::copy_file(dir / "out/cases/base/log_ramp/reference.exr", ref_image(), ec))
      setup_error() = "cannot copy the base case's reference image: " + ec.message();
  }
  void SetUp() override { ASSERT_EQ(setup_error(), "") << "suite set-up failed"; }
  static std::string& setup_error() {
    static std::string e;
    return e;
  }
};

TEST_P(HostileInput, ClearErrorNoCrashNoHangNothingOutsideChanged) {
  const Row& row = GetParam();
  const fs::path t =
      fs::temp_directory_path() / ("hdrc_hostile_" + std::to_string(::getpid())) / row.name;
  fs::remove_all(t);
  write(t / "cases/base.json", kBaseCase);
  write_image(t / "p.png", 8, 2, {"R", "G", "B"}, OIIO::TypeDesc::UINT8);
  if (row.setup) row.setup(t);
  const auto repo_before = hdrc::tree_digest(std::string(HDRC_SOURCE_DIR) + "/cases");
  const auto before = snapshot(t, row.writable);
  const Ran r = run_limited(subst(row.args, t));
  if (row.settle_s > 0) ::sleep(static_cast<unsigned>(row.settle_s));
  SCOPED_TRACE(r.out.substr(0, 3000));
  EXPECT_NE(r.code, 137) << "hang: killed after the time limit";
  EXPECT_LT(r.code, 128) << "crash: killed by a signal";
  if (row.code >= 0) {
    EXPECT_EQ(r.code, row.code);
  }
  for (const auto& want : row.expect) {
    EXPECT_NE(r.out.find(subst(want, t)), std::string::npos) << "missing: " << want;
  }
  EXPECT_TRUE(hdrc::is_valid_utf8(r.out)) << "the messages are not valid UTF-8";
  if (row.writable != "*") {
    const auto changes = hdrc::digest_changes(before, snapshot(t, row.writable), 20);
    EXPECT_TRUE(changes.empty()) << "changed outside " << row.writable << ": "
                                 << ::testing::PrintToString(changes);
  }
  EXPECT_EQ(hdrc::tree_digest(std::string(HDRC_SOURCE_DIR) + "/cases"), repo_before);
  // Whatever was published is complete and valid JSON/UTF-8.
  if (fs::is_symlink(t / "out/results.json") && fs::exists(t / "out/results.json") &&
      row.writable == "out") {
    const std::string results = read(t / "out/results.json");
    EXPECT_TRUE(hdrc::is_valid_utf8(results));
    EXPECT_TRUE(nlohmann::json::accept(results));
    EXPECT_TRUE(hdrc::is_valid_utf8(read(t / "out/junit.xml")));
    EXPECT_TRUE(fs::exists(t / "out/report/index.html"));
    for (const auto& e : fs::recursive_directory_iterator(t / "out"))
      if (e.path().filename() == "candidate.log") {
        EXPECT_LE(fs::file_size(e.path()), (size_t{1} << 20) + 200);
      }
  }
  if (!::testing::Test::HasFailure()) fs::remove_all(t);
}

INSTANTIATE_TEST_SUITE_P(Table, HostileInput, ::testing::ValuesIn(rows()), [](const auto& info) {
  return hdrc::test::gtest_param_name(info.param.name);
});

TEST(HostileInput, TableHasAtLeast100Rows) {
  EXPECT_GE(rows().size(), 100u);
}

}  // namespace
