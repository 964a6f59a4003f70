#include "runner/descendants.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <map>
#include <set>
#include <thread>
#include <vector>

namespace hdrc {

namespace {

std::atomic<bool> g_subreaper{false};
std::atomic<unsigned long> g_next_token{0};

struct Proc {
  pid_t ppid = 0, pgrp = 0;
  char state = '?';  // 'Z': a zombie, to be reaped by its parent
};

// Up to `max` bytes of a /proc file ("" when the process is gone or the file unreadable).
std::string read_proc(const std::string& path, size_t max) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return "";
  std::string out;
  char buf[4096];
  while (out.size() < max) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    out.append(buf, static_cast<size_t>(n));
  }
  ::close(fd);
  return out;
}

// Every process now, from /proc/<pid>/stat (proc(5)): the state, parent and process group follow
// the command name, which is in parentheses and may itself hold ')' and spaces.
std::map<pid_t, Proc> list_processes() {
  std::map<pid_t, Proc> out;
  DIR* d = ::opendir("/proc");
  if (!d) return out;
  while (const dirent* e = ::readdir(d)) {
    char* end = nullptr;
    const long pid = std::strtol(e->d_name, &end, 10);
    if (pid <= 0 || *end != '\0') continue;
    const std::string stat = read_proc("/proc/" + std::string(e->d_name) + "/stat", 1024);
    const size_t close = stat.rfind(')');
    if (close == std::string::npos) continue;
    Proc p;
    int ppid = 0, pgrp = 0;
    if (std::sscanf(stat.c_str() + close + 1, " %c %d %d", &p.state, &ppid, &pgrp) != 3) continue;
    p.ppid = ppid;
    p.pgrp = pgrp;
    out[static_cast<pid_t>(pid)] = p;
  }
  ::closedir(d);
  return out;
}

// Whether `pid`'s environment (as it was at its exec) holds the entry `entry` ("NAME=value").
bool has_env_entry(pid_t pid, const std::string& entry) {
  const std::string env = read_proc("/proc/" + std::to_string(pid) + "/environ", size_t{1} << 20);
  for (size_t at = 0; at < env.size();) {
    size_t end = env.find('\0', at);
    if (end == std::string::npos) end = env.size();
    if (env.compare(at, end - at, entry) == 0) return true;
    at = end + 1;
  }
  return false;
}

// Kills the descendants of this process that `select` picks, and all of theirs, until none is
// left (a process may fork while it is being killed), reaping those that are this process's
// children. `skip`: a descendant neither killed nor reaped here (the command's own process, which
// run_command reaps). Gives up after 2 s (a process in uninterruptible sleep). Returns how many
// processes were sent SIGKILL.
size_t sweep(const std::function<bool(pid_t, const Proc&)>& select, pid_t skip) {
  const pid_t self = ::getpid();
  std::set<pid_t> killed, signalled;  // taken (zombies included); sent SIGKILL
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  for (;;) {
    const std::map<pid_t, Proc> procs = list_processes();
    std::multimap<pid_t, pid_t> children;
    for (const auto& [pid, p] : procs) children.emplace(p.ppid, pid);
    // The subtree under `root` (itself included), by parent links; a pid is visited once.
    std::function<void(pid_t, std::set<pid_t>*)> subtree = [&](pid_t root, std::set<pid_t>* into) {
      std::vector<pid_t> stack = {root};
      while (!stack.empty()) {
        const pid_t p = stack.back();
        stack.pop_back();
        if (p == skip || !into->insert(p).second) continue;
        for (auto [it, end] = children.equal_range(p); it != end; ++it) stack.push_back(it->second);
      }
    };
    std::set<pid_t> mine;
    subtree(self, &mine);
    mine.erase(self);
    std::set<pid_t> targets;
    for (const pid_t p : mine)
      if (!targets.count(p) && (killed.count(p) || select(p, procs.at(p)))) subtree(p, &targets);
    for (const pid_t p : targets) {
      const Proc& pr = procs.at(p);
      if (pr.state != 'Z') {
        ::kill(p, SIGKILL);
        signalled.insert(p);
      }
      killed.insert(p);
      if (pr.ppid == self) (void)::waitpid(p, nullptr, WNOHANG);
    }
    if (targets.empty() || std::chrono::steady_clock::now() > deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return signalled.size();
}

}  // namespace

Status become_subreaper() {
  if (g_subreaper.load()) return {};
  if (::prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0) != 0)
    return Error{"", "", std::string("cannot become the child subreaper: ") + std::strerror(errno),
                 ""};
  g_subreaper.store(true);
  return {};
}

bool is_subreaper() {
  return g_subreaper.load();
}

std::string new_command_token() {
  return std::to_string(::getpid()) + "-" + std::to_string(g_next_token.fetch_add(1));
}

size_t kill_command_processes(const std::string& token, pid_t group) {
  const std::string entry = std::string(kCommandTokenVar) + "=" + token;
  return sweep(
      [&](pid_t pid, const Proc& p) {
        return (group > 0 && p.pgrp == group) || (p.state != 'Z' && has_env_entry(pid, entry));
      },
      group);
}

size_t kill_all_descendants() {
  return sweep([](pid_t, const Proc&) { return true; }, 0);
}

}  // namespace hdrc
