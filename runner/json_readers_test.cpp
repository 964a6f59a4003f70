// Every JSON file the tool reads from a path the user gives (issue 29): --candidate-limits FILE,
// --rerun-failed DIR (DIR/results.json), --timings FILE, merge's shards (DIR/results.json),
// report DIR (DIR/results.json) and the golden sidecars of --goldens DIR; the files found in
// --cases are runner/hostile_input_test.cpp's. Table-driven in that test's style: each reader is
// fed the hostile set (nested 100 000 deep, 1e999, /dev/zero, a FIFO, a folder, ill-formed UTF-8,
// truncated, empty, over the size limit) and a value of the wrong type at each field its code
// reads; every row asserts the exit code, the message's key parts (the file, the JSON pointer) and
// that nothing outside T/out changed. None may crash or hang.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/utf8.h"
#include "runner/output_set.h"
#include "runner/test_support.h"

#ifndef HDRC_SOURCE_DIR
#error "HDRC_SOURCE_DIR must be defined"
#endif

namespace fs = std::filesystem;
using namespace hdrc::test;  // runner/test_support.h

namespace {

const char* kBaseCase =
    R"({"stage": "shaper", "input": {"stimulus": "log_ramp", "width": 8, "height": 2}})";

// A results.json of the base case, written once by a reference run (SetUpTestSuite).
fs::path fixture_dir() {
  return fs::temp_directory_path() / ("hdrc_json_readers_fixture_" + std::to_string(::getpid()));
}
std::string& valid_results() {
  static std::string text;
  return text;
}

struct Row {
  std::string name;
  std::function<void(const fs::path& t)> setup;  // plants the bad input
  std::string args;                              // {T} is replaced by the row's folder
  int code;
  std::vector<std::string> expect;  // substrings of the combined output ({T} replaced)
};

std::string subst(std::string s, const fs::path& t) {
  for (size_t at; (at = s.find("{T}")) != std::string::npos;) s.replace(at, 3, t.string());
  return s;
}

std::string deep(const std::string& open, size_t n) {
  std::string s;
  s.reserve(open.size() * n);
  for (size_t i = 0; i < n; ++i) s += open;
  return s;
}

// One reader: the file (relative to T) it reads, the command that reads it, the exit code bad
// input gives, and the size limit it reads under.
struct Reader {
  std::string tag;
  std::string file;
  std::string args;
  int code;
  size_t max_bytes;
};

const std::string kCand = " --candidate-cmd 'sh {T}/cand.sh {output}'";
const std::vector<Reader>& readers() {
  static const std::vector<Reader> r = {
      {"candidate_limits", "limits.json",
       "verify --cases {T}/cases --out {T}/out" + kCand + " --candidate-limits {T}/limits.json", 2,
       size_t{64} << 20},
      {"rerun_failed", "prev/results.json",
       "run --engine reference --cases {T}/cases --out {T}/out --rerun-failed {T}/prev", 2,
       size_t{256} << 20},
      {"timings", "prev/results.json",
       "run --engine reference --cases {T}/cases --out {T}/out --shard 1/1 --timings "
       "{T}/prev/results.json",
       2, size_t{256} << 20},
      {"merge", "prev/results.json", "merge {T}/out {T}/prev {T}/shard2", 2, size_t{256} << 20},
      {"report", "prev/results.json", "report {T}/prev", 2, size_t{256} << 20},
      // A sidecar that cannot be read makes the case's golden stale: a golden failure (exit 1).
      {"golden_sidecar", "goldens/base/log_ramp.json",
       "run --engine reference --cases {T}/cases --goldens {T}/goldens --out {T}/out", 1,
       size_t{64} << 20},
  };
  return r;
}

// Beside each reader's file: what the command needs besides it.
void common_setup(const fs::path& t) {
  write(t / "cases/base.json", kBaseCase);
  write(t / "cand.sh", "#!/bin/sh\nexit 1\n");
  write(t / "shard2/results.json", valid_results());
  write(t / "goldens/base/log_ramp.exr", "not read: the sidecar is read first");
}

// The valid results.json with the value at `pointer` replaced by `value`.
std::string results_with(const std::string& pointer, const nlohmann::json& value) {
  auto j = nlohmann::ordered_json::parse(valid_results());
  j[nlohmann::ordered_json::json_pointer(pointer)] = value;
  return j.dump(1);
}

std::vector<Row> rows() {
  std::vector<Row> r;
  auto add = [&](Row row) { r.push_back(std::move(row)); };
  // ---- the hostile set, for every reader --------------------------------------------------
  for (const Reader& rd : readers()) {
    const std::string f = rd.file;
    auto plant = [f](std::string text) {
      return [f, text](const fs::path& t) { write(t / f, text); };
    };
    add({rd.tag + "_deep_arrays_100000",
         plant(deep("[", 100000)),
         rd.args,
         rd.code,
         {f, "nested more than 100 levels"}});
    add({rd.tag + "_deep_objects_100000",
         plant(deep("{\"a\":", 100000)),
         rd.args,
         rd.code,
         {f, "nested more than 100 levels"}});
    add({rd.tag + "_overflow_1e999",
         plant(R"({"limits": 1e999, "cases": [1e999]})"),
         rd.args,
         rd.code,
         {f, "malformed JSON", "1e999"}});
    add({rd.tag + "_dev_zero",
         [f](const fs::path& t) {
           fs::create_directories((t / f).parent_path());
           fs::create_symlink("/dev/zero", t / f);
         },
         rd.args,
         rd.code,
         {f, "not a regular file"}});
    add({rd.tag + "_fifo",
         [f](const fs::path& t) {
           fs::create_directories((t / f).parent_path());
           ASSERT_EQ(::mkfifo((t / f).c_str(), 0644), 0);
         },
         rd.args,
         rd.code,
         {f, "not a regular file"}});
    add({rd.tag + "_folder",
         [f](const fs::path& t) { fs::create_directories(t / f); },
         rd.args,
         rd.code,
         {f, "not a regular file"}});
    add({rd.tag + "_bad_utf8",
         plant("{\"description\": \"\xff\xfe\", \"cases\": []}"),
         rd.args,
         rd.code,
         {f, "malformed JSON"}});
    add({rd.tag + "_truncated",
         plant(R"({"limits": [{"cases": "x)"),
         rd.args,
         rd.code,
         {f, "malformed JSON"}});
    add({rd.tag + "_empty", plant(""), rd.args, rd.code, {f, "malformed JSON"}});
    const size_t max = rd.max_bytes;
    add({rd.tag + "_too_big",
         [f, max](const fs::path& t) {
           write(t / f, "{}");
           fs::resize_file(t / f, max + 1);  // sparse
         },
         rd.args,
         rd.code,
         {f, "over the limit"}});
  }

  // ---- --candidate-limits: a wrong value at each field -----------------------------------
  const Reader& lim = readers()[0];
  auto limits = [](std::string text) {
    return [text](const fs::path& t) { write(t / "limits.json", text); };
  };
  const std::string ok_limit = R"({"cases": "x/*", "engine": "candidate-cmd", "reason": "r"})";
  const std::vector<std::tuple<std::string, std::string, std::string, std::string>> bad_limits = {
      {"not_object", R"([1, 2])", "", "got array"},
      {"limits_missing", R"({"description": "d"})", "/limits", "missing limits"},
      {"limits_number", R"({"limits": 3})", "/limits", "expected an array of limits, got 3"},
      {"limit_string", R"({"limits": ["x"]})", "/limits/0", "expected an object, got string"},
      {"cases_number", R"({"limits": [{"cases": 3, "engine": "candidate-cmd", "reason": "r"}]})",
       "/limits/0/cases", "got 3"},
      {"engine_number", R"({"limits": [{"cases": "x", "engine": 7, "reason": "r"}]})",
       "/limits/0/engine", "candidate-cmd, candidate-dir"},
      {"engine_unknown", R"({"limits": [{"cases": "x", "engine": "vulkan", "reason": "r"}]})",
       "/limits/0/engine", "unknown engine \"vulkan\""},
      {"engine_near", R"({"limits": [{"cases": "x", "engine": "candidate-cdm", "reason": "r"}]})",
       "/limits/0/engine", "did you mean 'candidate-cmd'"},
      {"reason_null", R"({"limits": [{"cases": "x", "engine": "candidate-dir", "reason": null}]})",
       "/limits/0/reason", "got null"},
      {"reason_missing", R"({"limits": [{"cases": "x", "engine": "candidate-dir"}]})",
       "/limits/0/reason", "missing reason"},
      {"device_key", R"({"limits": [{"cases": "x", "engine": "candidate-cmd", "reason": "r",
                          "device": "*"}]})",
       "/limits/0/device", "unknown key 'device'"},
      {"unknown_top_key", R"({"limits": [], "limit": []})", "/limit", "unknown key 'limit'"},
      {"second_of_two_bad", R"({"limits": [)" + ok_limit + R"(, {"cases": ["x"]}]})",
       "/limits/1/cases", "got [\"x\"]"},
      {"too_many",
       R"({"limits": [)" +
           [&] {
             std::string s;
             for (int i = 0; i < 10001; ++i) s += (i ? "," : "") + ok_limit;
             return s;
           }() +
           "]}",
       "/limits", "more than 10000 limits"},
  };
  for (const auto& [name, text, pointer, what] : bad_limits)
    add({"candidate_limits_" + name,
         limits(text),
         lim.args,
         2,
         {"limits.json: " + pointer + (pointer.empty() ? "" : ": "), what}});

  // ---- results.json named by the user: a wrong value at each field its readers use ---------
  // (merge reads every field of its cross-checks; --rerun-failed /cases/*/id, verdict and the
  // goldens block; --timings /cases/*/id and seconds.)
  const std::vector<std::tuple<std::string, std::string, nlohmann::json, std::string>> bad_fields =
      {
          {"verdict_number", "/cases/0/verdict", 3, "value 3 is not allowed"},
          {"verdict_unknown", "/cases/0/verdict", "PASSED", "\"PASS\", \"FAIL\""},
          {"id_number", "/cases/0/id", 17, "expected \"string\", got 17"},
          {"case_string", "/cases/0", "x", "expected \"object\", got \"x\""},
          {"cases_object", "/cases", nlohmann::json::object(), "/cases"},
          {"seconds_string", "/cases/0/seconds", "fast", "/cases/0/seconds"},
          {"seconds_total_string", "/cases/0/seconds/total", "1", "/cases/0/seconds/total"},
          {"schema_version_string", "/schema_version", "2", "expected 2, got \"2\""},
          {"shard_number", "/shard", 1, "/shard"},
          {"wall_seconds_string", "/wall_seconds", "1", "/wall_seconds"},
          {"interrupted_string", "/interrupted", "no", "/interrupted"},
          {"summary_pass_string", "/summary/pass", "1", "/summary/pass"},
          {"provenance_number", "/provenance", 1, "/provenance"},
          {"tool_other", "/tool", "other", "/tool"},
      };
  for (const Reader& rd : readers()) {
    if (rd.tag != "rerun_failed" && rd.tag != "timings" && rd.tag != "merge") continue;
    for (const auto& [name, pointer, value, what] : bad_fields) {
      const std::string p = pointer;
      const nlohmann::json v = value;
      add({rd.tag + "_" + name,
           [p, v](const fs::path& t) { write(t / "prev/results.json", results_with(p, v)); },
           rd.args,
           2,
           {"prev/results.json: " + (p == "/cases" ? std::string("/cases") : p), what}});
    }
  }

  // ---- golden sidecars: a wrong type at each field -----------------------------------------
  const std::vector<std::pair<std::string, std::string>> bad_sidecars = {
      {"case_hash", R"({"case": "base/log_ramp", "case_hash": 5})"},
      {"input_hash", R"({"input_hash": ["a"]})"},
      {"reference_version", R"({"reference_version": {}})"},
      {"date", R"({"date": 20260101})"},
      {"values", R"({"values": [1]})"},
      {"width", R"({"width": "8"})"},
  };
  for (const auto& [field, text] : bad_sidecars) {
    const std::string tx = text;
    add({"golden_sidecar_" + field,
         [tx](const fs::path& t) { write(t / "goldens/base/log_ramp.json", tx); },
         readers().back().args,
         1,
         {"unreadable golden sidecar", "log_ramp.json: /" + field}});
  }
  add({"golden_sidecar_value_string",
       [](const fs::path& t) {
         write(t / "goldens/base/log_ramp.json", R"({"values": {"peak": "1"}})");
       },
       readers().back().args,
       1,
       {"unreadable golden sidecar", "log_ramp.json: /values/peak"}});

  // ---- a coverage requirement's name of another type (found in --cases) -------------------
  add({"coverage_requirement_name_number",
       [](const fs::path& t) {
         write(t / "cases/coverage.json",
               R"({"values": {}, "requirements": [{"name": 3, "stages": ["shaper"],
                   "full": ["x"]}]})");
       },
       "coverage --cases {T}/cases",
       2,
       {"coverage.json: /requirements/0/name", "a requirement needs a name, got 3"}});
  return r;
}

void PrintTo(const Row& row, std::ostream* os) {
  *os << row.name;
}

class JsonReaders : public ::testing::TestWithParam<Row> {
 protected:
  static void SetUpTestSuite() {
    const fs::path dir = fixture_dir();
    fs::remove_all(dir);
    write(dir / "cases/base.json", kBaseCase);
    const Ran r = run("run --engine reference --images none --cases " + (dir / "cases").string() +
                          " --out " + (dir / "out").string(),
                      "", 120);
    valid_results() = r.code == 0 ? read(dir / "out/results.json") : "";
    if (valid_results().empty()) valid_results() = "set-up failed: " + r.out;
  }
  static void TearDownTestSuite() { fs::remove_all(fixture_dir()); }
};

TEST_P(JsonReaders, ClearErrorNoCrashNoHangNothingOutsideOutChanged) {
  ASSERT_TRUE(nlohmann::json::accept(valid_results())) << valid_results();
  const Row& row = GetParam();
  const fs::path t =
      fs::temp_directory_path() / ("hdrc_json_readers_" + std::to_string(::getpid())) / row.name;
  fs::remove_all(t);
  common_setup(t);
  row.setup(t);
  auto outside = [&] {
    auto all = hdrc::tree_digest(t.string());
    std::map<std::string, std::string> kept;
    for (auto& [k, v] : all)
      if (k != "out" && k.rfind("out/", 0) != 0) kept[k] = v;
    return kept;
  };
  const auto before = outside();
  const auto repo_before = hdrc::tree_digest(std::string(HDRC_SOURCE_DIR) + "/cases");
  const Ran r = run(subst(row.args, t), "", 60);
  SCOPED_TRACE(r.out.substr(0, 3000));
  EXPECT_NE(r.code, 137) << "hang: killed after the time limit";
  EXPECT_LT(r.code, 128) << "crash: killed by a signal";
  EXPECT_EQ(r.code, row.code);
  for (const auto& want : row.expect)
    EXPECT_NE(r.out.find(subst(want, t)), std::string::npos) << "missing: " << want;
  EXPECT_TRUE(hdrc::is_valid_utf8(r.out)) << "the messages are not valid UTF-8";
  const auto changes = hdrc::digest_changes(before, outside(), 20);
  EXPECT_TRUE(changes.empty()) << "changed outside out: " << ::testing::PrintToString(changes);
  EXPECT_EQ(hdrc::tree_digest(std::string(HDRC_SOURCE_DIR) + "/cases"), repo_before);
  if (!::testing::Test::HasFailure()) fs::remove_all(t);
}

INSTANTIATE_TEST_SUITE_P(Table, JsonReaders, ::testing::ValuesIn(rows()), [](const auto& info) {
  return hdrc::test::gtest_param_name(info.param.name);
});

// Every reader gets the whole hostile set, and the table stays at its size.
TEST(JsonReaders, TableHasEveryReaderAndAtLeast100Rows) {
  const auto all = rows();
  EXPECT_GE(all.size(), 100u);
  for (const Reader& rd : readers()) {
    size_t n = 0;
    for (const Row& row : all) n += row.name.rfind(rd.tag + "_", 0) == 0;
    EXPECT_GE(n, 10u) << rd.tag;
  }
}

}  // namespace
