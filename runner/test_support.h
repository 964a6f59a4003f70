// Shared by the tests that drive the hdrconform binary (cli, cli_report, verify, hostile input,
// output set, coverage, goldens): one way to run it, hermetic and bounded, and the small file
// helpers those tests need.
//
// Hermetic: the binary's defaults may depend on the environment (CI=1 keeps only failing cases'
// images, runner/main.cpp), and a test must mean the same on a developer's machine and in CI. So
// every run starts from the caller's environment with CI removed; a test that means to exercise
// such a default passes it explicitly in `env` ("CI=1").
// Bounded: a hang is killed after `limit_s` seconds and reads as exit 137; a crash reads as
// 128 + the signal's number, never as an exit code the binary could have chosen.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#ifndef HDRC_BINARY
#error "HDRC_BINARY must be defined"
#endif

namespace hdrc::test {

struct Ran {
  int code;         // exit status; 128 + signal for a crash; 137 for a run killed at its limit
  std::string out;  // stdout and stderr, interleaved as written
  double seconds;   // wall time
};

// Runs `hdrconform ARGS` through /bin/sh (ARGS may quote and redirect). Stdin is /dev/null unless
// ARGS redirects it. `env` is "VAR=value ..." added to the environment.
inline Ran run(const std::string& args, const std::string& env = "", int limit_s = 600) {
  const std::string cmd = "env -u CI " + env + " timeout -s KILL " + std::to_string(limit_s) + " " +
                          std::string(HDRC_BINARY) + " " + args + " 2>&1" +
                          (args.find('<') == std::string::npos ? " </dev/null" : "");
  const auto t0 = std::chrono::steady_clock::now();
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return {-1, "popen failed for: " + cmd, 0};
  std::string out;
  std::array<char, 4096> buf;
  while (size_t n = fread(buf.data(), 1, buf.size(), p)) out.append(buf.data(), n);
  const int status = pclose(p);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), out, s};
}

// HDRC_ALLOW_NO_VULKAN set (not "", "0", "false", "no"): this machine has no Vulkan device, and
// a test or conformance run that needs one is skipped instead of failing (runner/ctest_run.sh).
inline bool vulkan_optional() {
  const char* v = std::getenv("HDRC_ALLOW_NO_VULKAN");
  if (!v) return false;
  const std::string s = v;
  return !(s.empty() || s == "0" || s == "false" || s == "no");
}

// A table row's name as a gtest parameter name: every character that is not a letter or digit
// becomes '_' (INSTANTIATE_TEST_SUITE_P's name generator).
inline std::string gtest_param_name(std::string name) {
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

// A fresh, empty folder for this process: TMP/hdrc_<name>_<pid>.
inline std::filesystem::path temp_dir(const std::string& name) {
  std::filesystem::path p =
      std::filesystem::temp_directory_path() / ("hdrc_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p;
}

inline std::string read(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// Writes `text` to `p`, creating its folders.
inline void write(const std::filesystem::path& p, const std::string& text) {
  std::filesystem::create_directories(p.parent_path());
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f << text;
}

#ifdef HDRC_SOURCE_DIR
// A planted defect: `from` replaced by `to` in `shader` (a path under gpu/shaders) of a copy of the
// suite's shaders, then `hdrconform run SELECTION` (e.g. "--pipeline unity_urp" or "--filter
// 'lut/devices/*'") on that copy without goldens. Returns the ids of the FAIL cases (results.json)
// and the console output in `out`; the run must exit `expected_code` (1: something failed) and
// `from` must be in the shader. `results_json`, when given, receives the run's results.json.
inline std::vector<std::string> planted_shader_failures(const std::string& shader,
                                                        const std::string& from,
                                                        const std::string& to,
                                                        const std::string& selection,
                                                        std::string* out, int expected_code = 1,
                                                        nlohmann::json* results_json = nullptr) {
  namespace fs = std::filesystem;
  const fs::path shaders = temp_dir("planted_shader");
  const fs::path results = temp_dir("planted_shader_out");
  fs::copy(fs::path(HDRC_SOURCE_DIR) / "gpu/shaders", shaders, fs::copy_options::recursive);
  std::string text = read(shaders / shader);
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << shader << ": " << from;
  if (at == std::string::npos) return {};
  text.replace(at, from.size(), to);
  write(shaders / shader, text);
  const Ran r = run("run " + selection + " --no-goldens --shader-dir " + shaders.string() +
                    " --out " + results.string());
  *out = r.out;
  EXPECT_EQ(r.code, expected_code) << r.out;
  std::vector<std::string> failing;
  const auto j = nlohmann::json::parse(read(results / "results.json"));
  for (const auto& c : j["cases"])
    if (c["verdict"] == "FAIL") failing.push_back(c["id"].get<std::string>());
  if (results_json) *results_json = j;
  fs::remove_all(shaders);
  fs::remove_all(results);
  return failing;
}
#endif

}  // namespace hdrc::test
