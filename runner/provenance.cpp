#include "runner/provenance.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/install_paths.h"
#include "core/utf8.h"
#include "runner/goldens.h"

#ifndef HDRC_SOURCE_DIR
#define HDRC_SOURCE_DIR ""
#endif
#ifndef HDRC_BUILD_TYPE
#define HDRC_BUILD_TYPE "unknown"
#endif

namespace hdrc {

namespace fs = std::filesystem;

namespace {

// The first line a command prints ("" when it fails); the command is fixed text, never data.
std::string first_line_of(const std::string& cmd) {
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return "";
  std::array<char, 256> buf{};
  std::string out;
  if (fgets(buf.data(), buf.size(), p)) out = buf.data();
  std::string rest;
  while (fgets(buf.data(), buf.size(), p)) rest += buf.data();
  const int status = pclose(p);
  if (status != 0) return "";
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

std::string source_commit() {
  // A bundle (scripts/bundle.sh) records the commit it was made from: its source tree may be
  // absent, or have moved on, where it runs.
  if (const std::string share = installed_data_dir(); !share.empty()) {
    std::ifstream f(fs::path(share) / "source_commit");
    std::string line;
    return std::getline(f, line) && !line.empty() ? line : "unknown";
  }
  const std::string dir = HDRC_SOURCE_DIR;
  if (dir.empty() || !fs::exists(fs::path(dir) / ".git")) return "unknown";
  const std::string q = shell_quote(dir);
  std::string head = first_line_of("git -C " + q + " rev-parse HEAD 2>/dev/null");
  if (head.empty()) return "unknown";
  // Modified tracked files make the build differ from the commit.
  if (!first_line_of("git -C " + q + " status --porcelain --untracked-files=no 2>/dev/null")
           .empty())
    head += "-dirty";
  return head;
}

std::string compiler() {
#if defined(__clang__)
  return std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
  return std::string("gcc ") + __VERSION__;
#else
  return "unknown";
#endif
}

}  // namespace

std::string shell_quote(const std::string& word) {
  if (!word.empty() && word.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                              "0123456789-_./=:,+@%") == std::string::npos)
    return word;
  std::string out = "'";
  for (char c : word) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string command_line(int argc, char** argv) {
  std::string s;
  for (int i = 0; i < argc && i < 4096; ++i) {
    if (i) s += ' ';  // appended: GCC 12 -O3 -Wrestrict false positive (bug 105329)
    s += shell_quote(argv[i]);
  }
  return s;
}

std::string directory_hash(const std::string& dir) {
  std::error_code ec;
  if (dir.empty() || !fs::is_directory(dir, ec)) return "";
  std::vector<fs::path> files;
  for (auto it = fs::recursive_directory_iterator(dir, ec);
       !ec && it != fs::recursive_directory_iterator() && files.size() < 100000; it.increment(ec))
    if (it->is_regular_file(ec)) files.push_back(it->path());
  std::sort(files.begin(), files.end());
  std::string all;
  for (const auto& f : files) {
    std::ifstream in(f, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string rel = fs::relative(f, dir, ec).generic_string();
    all += rel + '\0' + std::to_string(ss.str().size()) + '\0' + ss.str();
  }
  return sha256_hex(all);
}

RunProvenance run_provenance(int argc, char** argv, const std::vector<Case>& cases,
                             const std::string& shader_dir, const std::string& images) {
  RunProvenance p;
  p.commit = source_commit();
  p.command_line = command_line(argc, argv);
  // Options that choose cases, outputs or parallelism are left out of the reproduce command.
  static const std::vector<std::string> kDrop = {
      "--filter",  "--shard",  "--out", "--rerun-failed", "--failed-first", "--maxfail",
      "--timings", "--images", "-j",    "--jobs"};
  for (int i = 0; i < argc && i < 4096; ++i) {
    const std::string a = argv[i];
    bool drop = false;
    for (const auto& d : kDrop) {
      if (a == d) {
        drop = true;
        ++i;  // and its value
        break;
      }
      if (a.rfind(d + "=", 0) == 0 || (d == "-j" && a.size() > 2 && a.rfind("-j", 0) == 0))
        drop = true;
    }
    if (drop) continue;
    p.reproduce += (p.reproduce.empty() ? "" : " ") + shell_quote(a);
    // argv[0] and the subcommand (the first word; CLI11 takes options after it) are not repeated.
    if (i >= 2 || (i == 1 && !a.empty() && a[0] == '-'))
      p.reproduce_args += (p.reproduce_args.empty() ? "" : " ") + shell_quote(a);
  }
  std::error_code ec;
  p.cwd = fs::current_path(ec).string();
  char host[256] = {0};
  if (::gethostname(host, sizeof host - 1) == 0) p.hostname = valid_utf8(host);
  if (!shader_dir.empty()) {
    p.shader_dir = fs::absolute(shader_dir, ec).lexically_normal().string();
    p.shader_hash = directory_hash(shader_dir);
  }
  p.build_type = HDRC_BUILD_TYPE;
  p.compiler = compiler();
  p.tool_version = "hdrconform, reference " + std::to_string(kReferenceVersion);
  std::string ids;
  for (const auto& c : cases) ids += c.id + '\0' + case_hash(c) + '\n';
  p.suite_fingerprint = sha256_hex(ids);
  p.suite_cases = cases.size();
  p.shard_plan = shard_plan_description();
  p.images = images;
  return p;
}

}  // namespace hdrc
