#include "runner/verify.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "core/atomic_file.h"
#include "core/utf8.h"
#include "reference/reference_engine.h"
#include "runner/budget.h"
#include "runner/descendants.h"
#include "runner/export.h"
#include "runner/json_read.h"
#include "runner/provenance.h"
#include "runner/results.h"

namespace hdrc {

namespace fs = std::filesystem;

// ---- verify --candidate-dir ------------------------------------------------------------------

std::string CandidateDirEngine::image_path(const std::string& case_id) const {
  return dir_ + "/" + case_id + ".exr";
}

Status CandidateDirEngine::init() {
  std::error_code ec;
  const auto st = fs::status(dir_, ec);
  if (!fs::is_directory(st))
    return Error{valid_utf8(dir_), "",
                 fs::exists(st) ? "the candidate path is not a folder"
                                : "the candidate folder does not exist",
                 "a folder of ID.exr files"};
  return {};
}

DeviceInfo CandidateDirEngine::device() const {
  std::error_code ec;
  return {"candidate-dir", fs::absolute(dir_, ec).lexically_normal().string(), "images", "", {}};
}

std::string CandidateDirEngine::missing(const std::string& case_id) const {
  std::error_code ec;
  const std::string path = image_path(case_id);
  // Present in any form (a FIFO, a dangling symlink): reading it says what is wrong with it.
  if (fs::exists(fs::symlink_status(path, ec))) return "";
  return "missing candidate image " + valid_utf8(path);
}

Result<Image> CandidateDirEngine::run(const ResolvedCase& c) {
  auto img = read_image(image_path(c.spec.id));
  if (!img) {
    Error e = img.error();
    e.message = "bad candidate image: " + e.message;
    return e;
  }
  return img;
}

// ---- verify --candidate-cmd ------------------------------------------------------------------

Result<std::vector<std::string>> split_command_template(const std::string& text) {
  std::vector<std::string> words;
  std::string word;
  bool in_word = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\'') {
      const size_t end = text.find('\'', i + 1);
      if (end == std::string::npos)
        return Error{"", "--candidate-cmd", "unterminated ' at offset " + std::to_string(i),
                     "a closing '"};
      word += text.substr(i + 1, end - i - 1);
      in_word = true;
      i = end;
    } else if (c == '"') {
      size_t j = i + 1;
      for (; j < text.size() && text[j] != '"'; ++j) {
        if (text[j] == '\\' && j + 1 < text.size() && (text[j + 1] == '"' || text[j + 1] == '\\'))
          ++j;
        word += text[j];
      }
      if (j >= text.size())
        return Error{"", "--candidate-cmd", "unterminated \" at offset " + std::to_string(i),
                     "a closing \""};
      in_word = true;
      i = j;
    } else if (c == '\\' && i + 1 < text.size()) {
      word += text[++i];
      in_word = true;
    } else if (c == ' ' || c == '\t' || c == '\n') {
      if (in_word) words.push_back(std::move(word));
      word.clear();
      in_word = false;
    } else {
      word += c;
      in_word = true;
    }
  }
  if (in_word) words.push_back(std::move(word));
  if (words.empty())
    return Error{"", "--candidate-cmd", "the command template is empty",
                 "a program and its arguments with {input} {params} {output}"};
  return words;
}

std::string unknown_placeholder(const std::vector<std::string>& argv) {
  for (const std::string& w : argv)
    for (size_t at = w.find('{'); at != std::string::npos; at = w.find('{', at + 1)) {
      if (at > 0 && w[at - 1] == '$') continue;  // ${VAR}: the shell's, for an `sh -c` script
      size_t end = at + 1;
      while (end < w.size() && (std::islower(static_cast<unsigned char>(w[end])) ||
                                std::isdigit(static_cast<unsigned char>(w[end])) || w[end] == '_'))
        ++end;
      if (end == at + 1 || end >= w.size() || w[end] != '}') continue;
      const std::string name = w.substr(at, end - at + 1);
      if (name != "{input}" && name != "{params}" && name != "{output}" && name != "{id}")
        return name;
    }
  return "";
}

std::vector<std::string> expand_placeholders(const std::vector<std::string>& argv,
                                             const std::string& input, const std::string& params,
                                             const std::string& output, const std::string& id) {
  const std::pair<const char*, const std::string*> subs[] = {
      {"{input}", &input}, {"{params}", &params}, {"{output}", &output}, {"{id}", &id}};
  std::vector<std::string> out;
  for (std::string w : argv) {
    for (const auto& [key, value] : subs) {
      const std::string k = key;
      for (size_t at = w.find(k); at != std::string::npos; at = w.find(k, at + value->size()))
        w.replace(at, k.size(), *value);
    }
    out.push_back(std::move(w));
  }
  return out;
}

std::string check_timeout_seconds(std::string& text) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v) ||
      v <= 0 || v > kMaxTimeoutSeconds)
    return "--timeout '" + valid_utf8(text.substr(0, 40)) + "' is not a number of seconds in (0, " +
           std::to_string(static_cast<int>(kMaxTimeoutSeconds)) + "]";
  return "";
}

namespace {

// Appends what is readable from `fd` now (non-blocking) to `keep` up to `max_keep` bytes; the
// rest is counted in `*dropped`. Returns false at end of file.
bool drain(int fd, std::string* keep, size_t max_keep, size_t* dropped) {
  char buf[65536];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n > 0) {
      const size_t room = max_keep - std::min(max_keep, keep->size());
      keep->append(buf, std::min(room, static_cast<size_t>(n)));
      *dropped += static_cast<size_t>(n) - std::min(room, static_cast<size_t>(n));
      continue;
    }
    if (n == 0) return false;
    if (errno == EINTR) continue;
    return errno == EAGAIN || errno == EWOULDBLOCK ? true : false;
  }
}

}  // namespace

CommandResult run_command(const std::vector<std::string>& argv, const std::string& log_path,
                          double timeout_s, const CommandLimits& limits) {
  CommandResult r;
  // Everything the child needs is prepared before fork: after it, in a multi-threaded process,
  // the child may only call async-signal-safe functions until exec.
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  // Its environment, with the token every process it starts inherits (runner/descendants.h).
  const std::string token = new_command_token();
  const std::string token_entry = std::string(kCommandTokenVar) + "=" + token;
  const std::string token_prefix = std::string(kCommandTokenVar) + "=";
  std::vector<char*> env;
  for (char** e = environ; e && *e; ++e)
    if (std::strncmp(*e, token_prefix.c_str(), token_prefix.size()) != 0) env.push_back(*e);
  env.push_back(const_cast<char*>(token_entry.c_str()));
  env.push_back(nullptr);
  int pipe_fd[2];
  if (::pipe2(pipe_fd, O_CLOEXEC) != 0) {
    r.error = std::string("pipe failed: ") + std::strerror(errno);
    return r;
  }
  const rlim_t fsize = static_cast<rlim_t>(limits.max_file_bytes);
  const pid_t pid = fork();
  if (pid < 0) {
    r.error = std::string("fork failed: ") + std::strerror(errno);
    ::close(pipe_fd[0]);
    ::close(pipe_fd[1]);
    return r;
  }
  if (pid == 0) {
    setpgid(0, 0);  // its own group: it and its children are killed together; Ctrl-C reaches us
    const int null_in = open("/dev/null", O_RDONLY);
    if (null_in >= 0) dup2(null_in, 0);
    dup2(pipe_fd[1], 1);  // dup2 clears O_CLOEXEC on 1 and 2 only
    dup2(pipe_fd[1], 2);
    // No file it writes (its image included) may grow past the limit: SIGXFSZ ends it.
    const struct rlimit fl = {fsize, fsize};
    setrlimit(RLIMIT_FSIZE, &fl);
    const struct rlimit no_core = {0, 0};
    setrlimit(RLIMIT_CORE, &no_core);
    execvpe(args[0], args.data(), env.data());
    const char msg[] = "hdrconform: exec failed\n";
    (void)!write(2, msg, sizeof msg - 1);
    _exit(127);
  }
  ::close(pipe_fd[1]);
  setpgid(pid, pid);  // also from the parent, so the group exists before any kill below
  const int out_fd = pipe_fd[0];
  fcntl(out_fd, F_SETFL, fcntl(out_fd, F_GETFL) | O_NONBLOCK);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  std::string captured;
  size_t dropped = 0;
  bool open_pipe = true;
  for (;;) {
    if (open_pipe) {
      pollfd pfd{out_fd, POLLIN, 0};
      (void)::poll(&pfd, 1, 10);
      open_pipe = drain(out_fd, &captured, limits.max_log_bytes, &dropped);
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    // Exited? Not reaped yet (WNOWAIT): while the leader is a zombie its group id cannot be
    // reused, so the group kill below reaches only its own processes.
    siginfo_t info{};
    if (::waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 &&
        info.si_pid == pid)
      break;
    if (std::chrono::steady_clock::now() >= deadline) {
      r.timed_out = true;
      break;
    }
  }
  // The whole group goes, on a normal exit too, and then every process it started that left the
  // group (setsid) or was orphaned (a double fork): the runner is their subreaper, and they carry
  // the command's token (runner/descendants.h). Nothing it started outlives the case.
  kill(-pid, SIGKILL);
  kill_command_processes(token, pid);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (open_pipe) drain(out_fd, &captured, limits.max_log_bytes, &dropped);
  ::close(out_fd);
  if (!r.timed_out) {
    if (WIFEXITED(status)) r.exit_status = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  }
  r.output = valid_utf8(captured);
  r.output_dropped = dropped;
  std::string log = captured;
  if (dropped)
    log += "\n[hdrconform: " + std::to_string(dropped) + " more bytes of output dropped; limit " +
           std::to_string(limits.max_log_bytes) + "]\n";
  if (!log_path.empty()) (void)write_file_atomic(log_path, log);
  return r;
}

std::string sandbox_program() {
  // Found as the candidate command itself is (execvp): on PATH, or /usr/bin:/bin without one.
  const char* path = std::getenv("PATH");
  const std::string dirs = path ? path : "/usr/bin:/bin";
  for (size_t at = 0; at <= dirs.size();) {
    size_t end = dirs.find(':', at);
    if (end == std::string::npos) end = dirs.size();
    const std::string dir = dirs.substr(at, end - at);
    at = end + 1;
    if (dir.empty() || dir[0] != '/') continue;  // a relative entry would depend on the cwd
    const std::string p = dir + "/bwrap";
    if (::access(p.c_str(), X_OK) == 0) return p;
  }
  return "";
}

std::vector<std::string> sandbox_argv(const std::vector<std::string>& argv,
                                      const std::string& case_dir) {
  std::error_code ec;
  const std::string dir = fs::absolute(case_dir, ec).lexically_normal().string();
  // A read-only view of the whole system, no network, its own session; only the case's own
  // folder is writable (and is its TMPDIR). Its own PID namespace, whose init (bwrap's) ends with
  // the command: the kernel then kills every process left in the namespace (pid_namespaces(7)),
  // so no background child outlives the case. --die-with-parent: when the runner kills bwrap (a
  // timeout, the case's end), the namespace's init gets SIGKILL and the namespace goes with it
  // (bwrap(1)). Without the PID namespace the command's children, in bwrap's new session and
  // user namespace, escaped both the process-group kill and the token search.
  std::vector<std::string> out = {sandbox_program(),
                                  "--ro-bind",
                                  "/",
                                  "/",
                                  "--dev",
                                  "/dev",
                                  "--proc",
                                  "/proc",
                                  "--bind",
                                  dir,
                                  dir,
                                  "--unshare-net",
                                  "--unshare-ipc",
                                  "--unshare-pid",
                                  "--new-session",
                                  "--die-with-parent",
                                  "--setenv",
                                  "TMPDIR",
                                  dir,
                                  "--chdir",
                                  dir,
                                  "--"};
  out.insert(out.end(), argv.begin(), argv.end());
  return out;
}

Status CandidateCommandEngine::init() {
  if (argv_.empty()) return Error{"", "--candidate-cmd", "the command template is empty", ""};
  // The command's orphans are re-parented to us, to be killed at the case's end.
  if (Status st = become_subreaper(); !st) return st;
  if (sandbox_ && sandbox_program().empty())
    return Error{"", "--sandbox",
                 "bubblewrap (bwrap) is not installed (not found on PATH " +
                     valid_utf8(std::getenv("PATH") ? std::getenv("PATH") : "(unset)") +
                     "), so candidate commands cannot be sandboxed",
                 "install Debian's package bubblewrap, or run without --sandbox"};
  return {};
}

DeviceInfo CandidateCommandEngine::device() const {
  std::string cmd;
  for (const auto& a : argv_) cmd += (cmd.empty() ? "" : " ") + a;
  return {"candidate-cmd", cmd, "command", "", {}};
}

namespace {
// The first non-empty line of the candidate's log, at most 200 characters: its reason.
std::string first_line_of(const std::string& path) {
  std::ifstream f(path);
  std::string line;
  for (int i = 0; i < 100 && std::getline(f, line); ++i) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (line.empty()) continue;
    return line.size() > 200 ? line.substr(0, 200) + "..." : line;
  }
  return "";
}

std::string tail_of(std::string s, size_t max_chars) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  if (s.size() > max_chars) s = "..." + s.substr(s.size() - max_chars);
  for (char& c : s)
    if (c == '\n' || (static_cast<unsigned char>(c) < 0x20 && c != '\t')) c = '|';
  return valid_utf8(s);  // the cut may split a character; the output may be any bytes
}
}  // namespace

// ---- the candidate protocol ------------------------------------------------------------------

void DeclinedStages::add(const std::string& stage, const std::string& reason) {
  std::lock_guard<std::mutex> lock(mu_);
  stages_.emplace(stage, reason);  // the first case to decline names the reason
}

std::string DeclinedStages::reason(const std::string& stage) const {
  std::lock_guard<std::mutex> lock(mu_);
  auto it = stages_.find(stage);
  return it == stages_.end() ? "" : it->second;
}

std::string CandidateCommandEngine::unsupported(const ResolvedCase& c) const {
  if (!c.spec.stage) return "";
  if (std::string why = declined_->reason(std::string(c.spec.stage->name)); !why.empty())
    return why;
  return c.spec.id == declined_case_ ? declined_reason_ : "";
}

Error CandidateCommandEngine::decline(const ResolvedCase& c, int status, const std::string& said) {
  const std::string stage = c.spec.stage ? std::string(c.spec.stage->name) : "?";
  const std::string what = said.empty() ? "" : ": " + said;
  if (status == kCandidateDeclinesStage) {
    declined_->add(stage, "the candidate declined stage " + stage + " (exit " +
                              std::to_string(status) + " on " + c.spec.id + ")" + what);
  } else {
    declined_case_ = c.spec.id;
    declined_reason_ =
        "the candidate declined this case (exit " + std::to_string(status) + ")" + what;
  }
  return Error{argv_[0], "", unsupported(c), ""};
}

Result<Image> CandidateCommandEngine::run(const ResolvedCase& c) {
  declined_case_.clear();
  declined_reason_.clear();
  // Under --sandbox the command runs in its case folder (sandbox_argv's --chdir): every path it
  // is given is absolute, or a relative --out would name a folder inside that one.
  std::string dir = out_dir_ + "/" + case_image_dir(c.spec.id);
  if (sandbox_) {
    std::error_code aec;
    dir = fs::absolute(dir, aec).lexically_normal().string();
  }
  if (Status st = export_case(c, dir); !st) return st.error();
  const std::string output = dir + "/candidate_output.exr";
  const std::string log = dir + "/candidate.log";
  std::error_code ec;
  fs::remove(output, ec);
  fs::remove(log, ec);
  const auto t0 = std::chrono::steady_clock::now();
  auto argv =
      expand_placeholders(argv_, dir + "/input.exr", dir + "/params.json", output, c.spec.id);
  if (sandbox_) argv = sandbox_argv(argv, dir);
  const CommandResult r = run_command(argv, log, timeout_s_);
  if (r.error.empty() && !r.timed_out && r.signal == 0 &&
      (r.exit_status == kCandidateDeclinesCase || r.exit_status == kCandidateDeclinesStage))
    return decline(c, r.exit_status, first_line_of(log));
  std::string why;
  if (!r.error.empty())
    why = r.error;
  else if (r.timed_out)
    why = "timed out after " + format_number(timeout_s_) +
          " s (killed with every process it started); a slower port (an interpreted one baking a "
          "64^3 LUT takes minutes) needs a larger --timeout, and --rerun-failed DIR repeats only "
          "the cases that did not pass";
  else if (r.signal == SIGXFSZ)
    why = "wrote a file over the size limit of " + std::to_string(kMaxImageFileBytes) +
          " bytes (killed by SIGXFSZ)";
  else if (r.signal != 0)
    why = "killed by signal " + std::to_string(r.signal);
  else if (r.exit_status != 0)
    why = "exited with status " + std::to_string(r.exit_status);
  if (!why.empty()) {
    const std::string out = tail_of(r.output, 300);
    return Error{valid_utf8(argv_[0]), "",
                 "candidate command " + why + (out.empty() ? "" : "; output: " + out), ""};
  }
  if (!fs::exists(fs::symlink_status(output, ec)))
    return Error{valid_utf8(argv_[0]), "",
                 "candidate command exited 0 but wrote no image at " + valid_utf8(output), ""};
  auto img = read_image(output);
  fs::remove(output, ec);
  // --timeout covers the command and the reading of what it wrote.
  if (img &&
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > timeout_s_)
    return Error{valid_utf8(argv_[0]), "",
                 "candidate command and the reading of its image took over --timeout " +
                     format_number(timeout_s_) + " s",
                 ""};
  if (!img) {
    Error e = img.error();
    e.message = "bad candidate image: " + e.message;
    return e;
  }
  return img;
}

std::vector<KnownLimit> load_candidate_limits(const std::string& path, std::vector<Error>* errors) {
  // Bounded like every JSON input (runner/json_read.h): a regular file, its size and nesting
  // checked before parsing, an overflowing number an error; the form is known_limits.json's.
  auto doc = read_json_file<nlohmann::ordered_json>(path, "candidate limits file");
  if (!doc) {
    errors->push_back(doc.error());
    return {};
  }
  return parse_known_limits(*doc, path, {"candidate-cmd", "candidate-dir"},
                            /*device_key=*/false, errors);
}

std::string reproduce_command(const RunReport& r, const std::string& case_id) {
  return "hdrconform " + r.command + " --filter " + shell_quote("=" + case_id) +
         " --out out/repro" + (r.reproduce_args.empty() ? "" : " " + r.reproduce_args);
}

// ---- the run/verify driver -------------------------------------------------------------------

namespace {

std::atomic<bool> g_interrupt{false};

void on_sigint(int) {
  g_interrupt.store(true);
  const char msg[] =
      "\nhdrconform: interrupted; finishing the running cases (Ctrl-C again to abort)\n";
  (void)!write(2, msg, sizeof msg - 1);
  signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends the process at once
}

class Progress {
 public:
  Progress(bool tty, std::function<std::string(const std::string&)> reproduce)
      : tty_(tty), reproduce(std::move(reproduce)) {}
  void operator()(const CaseResult& r, size_t index, size_t total) {
    if (r.verdict == CaseVerdict::kFail || r.verdict == CaseVerdict::kError ||
        r.verdict == CaseVerdict::kMissing)
      ++bad_;
    if (!tty_ || r.verdict == CaseVerdict::kFail || r.verdict == CaseVerdict::kError ||
        r.verdict == CaseVerdict::kMissing) {
      if (tty_) std::printf("\r\033[K");
      std::printf("[%zu/%zu] %-5s %s  %s\n", index + 1, total, verdict_name(r.verdict),
                  r.spec.id.c_str(), r.reason.c_str());
      if (r.verdict == CaseVerdict::kFail)
        std::printf("        tolerance from %s\n", r.tolerance.source.c_str());
      if (r.verdict == CaseVerdict::kFail || r.verdict == CaseVerdict::kError)
        std::printf("        reproduce: %s\n", reproduce(r.spec.id).c_str());
      for (const auto& w : r.warnings) std::printf("        warning: %s\n", w.c_str());
    }
    if (tty_) {
      const int width = 30;
      const int filled = static_cast<int>(width * (index + 1) / std::max<size_t>(total, 1));
      std::printf("\r\033[K[%s%s] %zu/%zu cases, %d failing", std::string(filled, '#').c_str(),
                  std::string(width - filled, '.').c_str(), index + 1, total, bad_);
      if (index + 1 == total) std::printf("\n");
    }
    std::fflush(stdout);
  }

 private:
  bool tty_;
  std::function<std::string(const std::string&)> reproduce;
  int bad_ = 0;
};

// UNSUPPORTED cases, grouped by reason (a declined stage gives one line for all its cases).
void print_unsupported(const RunReport& report) {
  std::map<std::string, std::vector<const CaseResult*>> by_reason;
  for (const auto& c : report.cases)
    if (c.verdict == CaseVerdict::kUnsupported) by_reason[c.reason].push_back(&c);
  if (!report.candidate_limits_file.empty())
    std::printf("  %zu deviation(s) declared by the candidate in %s\n",
                report.candidate_limits.size(), report.candidate_limits_file.c_str());
  if (by_reason.empty()) return;
  std::printf("  UNSUPPORTED (never a pass%s):\n",
              report.require_all ? "; --require-all: they fail the run" : "");
  for (const auto& [reason, list] : by_reason) {
    std::printf("    %zu case(s): %s (e.g. %s)\n", list.size(), reason.c_str(),
                list.front()->spec.id.c_str());
  }
}

// The details of the summary; its headline (counts, device) is printed at the very end, after
// the golden check, by finish_run_outputs (runner/results.h: headline_of).
void print_summary(const RunReport& report) {
  if (report.warned() > 0) std::printf("  %d passed with warnings\n", report.warned());
  std::vector<const CaseResult*> by_time, by_budget;
  int tighten = 0;
  for (const auto& c : report.cases) {
    if (c.seconds() > 0) by_time.push_back(&c);
    if (c.has_stats && c.verdict != CaseVerdict::kFail) by_budget.push_back(&c);
    tighten += c.could_be_tightened;
  }
  std::sort(by_time.begin(), by_time.end(),
            [](auto* a, auto* b) { return a->seconds() > b->seconds(); });
  std::sort(by_budget.begin(), by_budget.end(),
            [](auto* a, auto* b) { return a->budget_used > b->budget_used; });
  if (!by_time.empty()) {
    std::printf("  slowest:");
    for (size_t i = 0; i < std::min<size_t>(3, by_time.size()); ++i)
      std::printf("%s %s %.2f s", i ? "," : "", by_time[i]->spec.id.c_str(), by_time[i]->seconds());
    std::printf("\n");
  }
  for (const auto& c : report.cases)
    if (c.verdict == CaseVerdict::kFail)
      std::printf("  FAIL %s: %s\n", c.spec.id.c_str(), c.reason.c_str());
  print_unsupported(report);
  if (!by_budget.empty()) {
    std::printf("  closest to their tolerance:");
    for (size_t i = 0; i < std::min<size_t>(3, by_budget.size()); ++i)
      std::printf("%s %s %.0f %%", i ? "," : "", by_budget[i]->spec.id.c_str(),
                  100.0 * by_budget[i]->budget_used);
    std::printf("\n");
  }
  if (tighten > 0)
    std::printf("  %d case(s) use under 10 %% of their tolerance (could be tightened)\n", tighten);
}

}  // namespace

int run_suite(std::vector<Case> cases, const std::vector<KnownLimit>& limits,
              const EngineFactory& candidate, const SuiteOptions& options) {
  std::vector<Error> errors;
  RunOptions ro;
  ro.overlays = load_tolerance_overlays(options.cases_dir, &errors);
  const bool analytic = options.reference == "analytic";
  if (!analytic && options.reference != "baked")
    errors.push_back(Error{"", "--reference", "unknown reference mode '" + options.reference + "'",
                           kReferenceModes});
  if (analytic) {
    // Tolerances measured for a per-pixel (no LUT) candidate against the analytic reference.
    const std::string path = options.cases_dir + "/tolerance_overlays_analytic.json";
    std::ifstream f(path);
    if (f) {
      const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
      for (auto& o : parse_tolerance_overlays(path, text, &errors)) ro.overlays.push_back(o);
    }
  }
  std::vector<KnownLimit> all_limits = limits;
  std::vector<KnownLimit> candidate_limits;
  if (!options.candidate_limits.empty()) {
    candidate_limits = load_candidate_limits(options.candidate_limits, &errors);
    for (KnownLimit k : candidate_limits) {
      if (k.engine != options.candidate_engine) continue;  // declared for the other mode
      k.reason = "declared by the candidate (" + options.candidate_limits + "): " + k.reason;
      all_limits.push_back(k);
    }
  }
  if (!errors.empty()) {
    for (const auto& e : errors) std::fprintf(stderr, "error: %s\n", e.to_string().c_str());
    std::fprintf(stderr, "%zu error(s) in tolerance overlays or options; nothing was run\n",
                 errors.size());
    return kExitBadInput;
  }
  if (!options.shard.empty()) {
    auto shard = parse_shard(options.shard);
    if (!shard) {
      std::fprintf(stderr, "error: %s\n", shard.error().to_string().c_str());
      return kExitBadInput;
    }
    const size_t all = cases.size();
    cases = select_shard(cases, *shard);
    if (cases.empty()) {
      std::fprintf(stderr,
                   "error: --shard %s selects no case: there are only %zu case(s) to share; "
                   "nothing was run\n",
                   options.shard.c_str(), all);
      return kExitBadInput;
    }
  }
  if (!options.failed_first_dir.empty()) {
    const auto first = std::stable_partition(cases.begin(), cases.end(), [&](const Case& c) {
      return options.failed_first.count(c.id) > 0;
    });
    std::printf("failed first: %zu case(s) that failed in %s/results.json run first\n",
                static_cast<size_t>(first - cases.begin()), options.failed_first_dir.c_str());
  }
  ro.max_fail = options.max_fail;
  // The run's memory budget: every case must fit it alone (refused here, before any work, as
  // the loader refused those over the per-case budget); -j runs as many at once as it holds.
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  ro.memory_budget = run_memory_budget(
      options.memory_budget,
      static_cast<int>(std::min<size_t>(options.jobs > 0 ? options.jobs : cores, cases.size())));
  // The images kept for the report are held beside the running cases (runner/budget.h).
  if (ro.memory_budget > 0)
    ro.memory_budget = std::max(1.0, ro.memory_budget - static_cast<double>(kKeptImagesBytes));
  if (ro.memory_budget > 0) {
    size_t refused = 0;
    for (const Case& c : cases)
      if (Status st = check_case_budget(c, ro.memory_budget); !st) {
        if (++refused <= 20) std::fprintf(stderr, "error: %s\n", st.error().to_string().c_str());
      }
    if (refused > 0) {
      std::fprintf(stderr, "%zu case(s) over the run's memory budget of %s; nothing was run\n",
                   refused, format_bytes(ro.memory_budget).c_str());
      return kExitBadInput;
    }
  }
  ro.jobs = options.jobs;
  ro.device_allowances = options.device_allowances;
  ro.known_limits = all_limits;
  ro.image_dir = options.out_dir;
  ro.interrupt = &g_interrupt;
  RunReport proto;  // what a reproduce command needs before the report exists
  proto.command = options.command;
  proto.reproduce_args = options.reproduce_args;
  Progress progress(isatty(STDOUT_FILENO),
                    [proto](const std::string& id) { return reproduce_command(proto, id); });
  ro.on_case = [&](const CaseResult& r, size_t i, size_t n) { progress(r, i, n); };
  if (options.candidate_dir) {
    const CandidateDirEngine* dir = options.candidate_dir;
    ro.missing_candidate = [dir](const Case& c) { return dir->missing(c.id); };
  }
  struct sigaction sa {};
  sa.sa_handler = on_sigint;
  sigemptyset(&sa.sa_mask);
  struct sigaction old {};
  sigaction(SIGINT, &sa, &old);

  RunReport report = run_cases(
      cases, [analytic] { return std::make_unique<ref::ReferenceEngine>(analytic); }, candidate,
      ro);
  sigaction(SIGINT, &old, nullptr);
  report.command = options.command;
  report.shard = options.shard;
  report.require_all = options.require_all;
  report.candidate_limits_file = options.candidate_limits;
  report.candidate_limits = candidate_limits;
  report.reference_mode = options.reference;
  report.reproduce_args = options.reproduce_args;
  report.provenance = options.provenance;
  if (!report.candidate_unavailable.empty())
    std::printf("candidate unavailable: %s\n", report.candidate_unavailable.c_str());
  if (Status st = write_run_outputs(report, options.out_dir); !st) {
    std::fprintf(stderr, "error: %s\n", st.error().to_string().c_str());
    return kExitFail;
  }
  print_summary(report);
  if (report.interrupted) std::printf("interrupted: unfinished cases are NOT_RUN\n");
  if (report.stopped_by_max_fail)
    std::printf("stopped: --maxfail %d: %d cases failed; %d cases not run (NOT_RUN)\n",
                report.max_fail,
                report.count(CaseVerdict::kFail) + report.count(CaseVerdict::kError) +
                    report.count(CaseVerdict::kMissing),
                report.count(CaseVerdict::kNotRun));
  return report.exit_code();
}

}  // namespace hdrc
