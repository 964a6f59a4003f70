#include "runner/output_set.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>

#include "core/utf8.h"
#include "runner/descendants.h"
#include "runner/goldens.h"
#include "runner/json_read.h"
#include "runner/run.h"

namespace hdrc {

namespace fs = std::filesystem;

namespace {

constexpr const char* kRuns = ".runs";
constexpr const char* kCurrent = "current";
constexpr const char* kLock = ".lock";
// The names users and CI read; each is a symlink to current/<name>.
constexpr const char* kPublished[] = {"results.json", "junit.xml", "goldens.json", "report",
                                      "cases"};

std::string os_error(int err) {
  return std::strerror(err);
}

// a == b or a inside b (both absolute, normalised).
bool within(const fs::path& a, const fs::path& b) {
  const fs::path rel = a.lexically_relative(b);
  return !rel.empty() && *rel.begin() != "..";
}

fs::path resolved(const std::string& p) {
  std::error_code ec;
  fs::path r = fs::weakly_canonical(fs::absolute(p, ec), ec);
  return r.lexically_normal();
}

Result<int> take_lock(const std::string& out_dir) {
  const std::string path = out_dir + "/" + kLock;
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd < 0)
    return Error{valid_utf8(path), "", "cannot create the lock file: " + os_error(errno), ""};
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    char holder[32] = {0};
    (void)!::pread(fd, holder, sizeof holder - 1, 0);
    ::close(fd);
    if (err == EWOULDBLOCK)
      return Error{valid_utf8(out_dir), "",
                   "another hdrconform run (pid " + valid_utf8(std::string(holder)) +
                       ") is writing to this output folder; nothing was run",
                   "wait for it, or give this run its own --out"};
    return Error{valid_utf8(path), "", "cannot lock: " + os_error(err), ""};
  }
  const std::string pid = std::to_string(::getpid());
  if (::ftruncate(fd, 0) == 0) (void)!::pwrite(fd, pid.data(), pid.size(), 0);
  return fd;
}

std::string unique_name() {
  std::random_device rd;
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  char buf[96];
  std::snprintf(
      buf, sizeof buf, "run-%lld-%d-%08x",
      static_cast<long long>(std::chrono::duration_cast<std::chrono::milliseconds>(now).count()),
      static_cast<int>(::getpid()), rd());
  return buf;
}

// Replaces (or creates) the symlink `link` -> `target` in one rename(2).
Status atomic_symlink(const fs::path& target, const fs::path& link) {
  const fs::path tmp = link.parent_path() / (".tmp-link-" + unique_name());
  std::error_code ec;
  fs::create_symlink(target, tmp, ec);
  if (ec)
    return Error{valid_utf8(tmp.string()), "", "cannot create a symlink: " + ec.message(), ""};
  if (::rename(tmp.c_str(), link.c_str()) != 0) {
    const int err = errno;
    fs::remove(tmp, ec);
    return Error{valid_utf8(link.string()), "", "cannot replace: " + os_error(err), ""};
  }
  return {};
}

bool is_link_to(const fs::path& link, const fs::path& target) {
  std::error_code ec;
  return fs::is_symlink(fs::symlink_status(link, ec)) && fs::read_symlink(link, ec) == target;
}

// Output folders written before the current/ layout: their files move into a run folder of
// their own (so they stay the "previous run"); anything else of a published name that is not
// ours stops the run rather than being touched.
Status adopt_legacy(const fs::path& out) {
  std::error_code ec;
  std::vector<fs::path> legacy;
  for (const char* name : kPublished) {
    const fs::path p = out / name;
    const auto st = fs::symlink_status(p, ec);
    if (!fs::exists(st) || is_link_to(p, fs::path(kCurrent) / name)) continue;
    legacy.push_back(p);
  }
  if (legacy.empty()) return {};
  auto results = read_bounded_file((out / "results.json").string(), kMaxResultsFileBytes, "file");
  const bool ours = results && results->find("\"tool\": \"hdrconform\"") != std::string::npos &&
                    !fs::is_symlink(fs::symlink_status(out / "results.json", ec));
  if (!ours)
    return Error{valid_utf8(legacy.front().string()), "",
                 "the output folder holds this name and it was not written by hdrconform; "
                 "nothing was run",
                 "an empty folder or one written by hdrconform run/verify"};
  if (fs::exists(fs::symlink_status(out / kCurrent, ec)))
    return Error{valid_utf8(legacy.front().string()), "",
                 "is not the symlink to current/ the output folder's layout needs",
                 "remove it (docs/output-folder.md)"};
  const fs::path dir = out / kRuns / ("legacy-" + unique_name());
  fs::create_directories(dir, ec);
  if (ec) return Error{valid_utf8(dir.string()), "", "cannot create: " + ec.message(), ""};
  for (const fs::path& p : legacy) {
    fs::rename(p, dir / p.filename(), ec);
    if (ec) return Error{valid_utf8(p.string()), "", "cannot move: " + ec.message(), ""};
  }
  return atomic_symlink(fs::path(kRuns) / dir.filename(), out / kCurrent);
}

// Removes every run folder but `keep` (the lock is held: none is in use).
void remove_other_runs(const fs::path& out, const std::string& keep) {
  std::error_code ec;
  std::vector<fs::path> old;
  for (auto it = fs::directory_iterator(out / kRuns, ec); !ec && it != fs::directory_iterator();
       it.increment(ec))
    if (it->path().filename() != keep) old.push_back(it->path());
  for (const auto& p : old) fs::remove_all(p, ec);
  for (auto it = fs::directory_iterator(out, ec); !ec && it != fs::directory_iterator();
       it.increment(ec))
    if (it->path().filename().string().rfind(".tmp-link-", 0) == 0) old.push_back(it->path());
  for (const auto& p : old) fs::remove(p, ec);
}

std::string current_run_name(const fs::path& out) {
  std::error_code ec;
  const fs::path target = fs::read_symlink(out / kCurrent, ec);
  return ec ? "" : target.filename().string();
}

}  // namespace

Status validate_output_dir(const std::string& dir, const std::string& flag,
                           const std::vector<std::string>& protected_dirs) {
  if (dir.empty()) return Error{"", flag, "the folder is empty (\"\")", "a folder path, e.g. out"};
  const fs::path out = resolved(dir);
  for (const std::string& pd : protected_dirs) {
    if (pd.empty()) continue;
    const fs::path p = resolved(pd);
    std::string why;
    if (out == p)
      why = "is the folder " + p.string() + " itself";
    else if (within(out, p))
      why = "is inside " + p.string();
    else if (within(p, out))
      why = "holds " + p.string();
    if (!why.empty())
      return Error{valid_utf8(dir), flag,
                   valid_utf8(why) + " (resolved: " + valid_utf8(out.string()) +
                       "), which this command must not write into",
                   "a folder of its own, outside the cases and goldens folders"};
  }
  std::error_code ec;
  const auto st = fs::status(dir, ec);
  if (fs::exists(st) && !fs::is_directory(st))
    return Error{valid_utf8(dir), flag, "exists and is not a folder", "a folder path"};
  fs::create_directories(dir, ec);
  if (ec) return Error{valid_utf8(dir), flag, "cannot create the folder: " + ec.message(), ""};
  const std::string probe = dir + "/.hdrconform-write-test-" + std::to_string(::getpid());
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0)
    return Error{valid_utf8(dir), flag, "the folder is not writable: " + os_error(errno), ""};
  ::close(fd);
  ::unlink(probe.c_str());
  return {};
}

std::map<std::string, std::string> tree_digest(const std::string& dir) {
  std::map<std::string, std::string> out;
  std::error_code ec;
  size_t n = 0;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (++n > 200000) break;
    const auto type = it->symlink_status(ec).type();
    const std::string rel = it->path().lexically_relative(dir).generic_string();
    if (type == fs::file_type::symlink) {
      out[rel] = "symlink:" + fs::read_symlink(it->path(), ec).string();
    } else if (type == fs::file_type::regular) {
      auto text = read_bounded_file(it->path().string(), size_t{1} << 30, "file");
      out[rel] = text ? sha256_hex(*text) : "unreadable";
    } else if (type != fs::file_type::directory) {
      out[rel] = "special";
    }
  }
  return out;
}

std::vector<std::string> digest_changes(const std::map<std::string, std::string>& before,
                                        const std::map<std::string, std::string>& after,
                                        size_t max) {
  std::vector<std::string> out;
  for (const auto& [k, v] : before) {
    auto it = after.find(k);
    if (it == after.end())
      out.push_back(k + " (removed)");
    else if (it->second != v)
      out.push_back(k + " (changed)");
  }
  for (const auto& [k, v] : after)
    if (!before.count(k)) out.push_back(k + " (added)");
  if (out.size() > max) {
    const size_t more = out.size() - max;
    out.resize(max);
    out.push_back("and " + std::to_string(more) + " more");
  }
  return out;
}

std::string published_run_dir(const std::string& dir) {
  std::error_code ec;
  const fs::path cur = fs::path(dir) / kCurrent;
  if (fs::is_symlink(fs::symlink_status(cur, ec)) && fs::is_directory(cur, ec))
    return (fs::path(dir) / kRuns / current_run_name(dir)).string();
  return dir;
}

Result<std::unique_ptr<OutputSet>> OutputSet::open(const std::string& out_dir,
                                                   const std::vector<std::string>& watched) {
  if (Status st = validate_output_dir(out_dir, "--out", watched); !st) return st.error();
  std::unique_ptr<OutputSet> set(new OutputSet);
  set->out_ = out_dir;
  auto fd = take_lock(out_dir);
  if (!fd) return fd.error();
  set->lock_fd_ = *fd;
  const fs::path out(out_dir);
  if (Status st = adopt_legacy(out); !st) return st.error();
  std::error_code ec;
  // .runs and current are ours: a symlinked .runs would make the clean-up below delete another
  // folder's files.
  const auto runs_type = fs::symlink_status(out / kRuns, ec).type();
  const auto current_type = fs::symlink_status(out / kCurrent, ec).type();
  if ((runs_type != fs::file_type::not_found && runs_type != fs::file_type::directory) ||
      (current_type != fs::file_type::not_found && current_type != fs::file_type::symlink))
    return Error{valid_utf8(out_dir), "--out",
                 "holds a .runs that is not a plain folder or a current that is not a symlink; "
                 "nothing was run",
                 "an empty folder or one written by hdrconform run/verify"};
  fs::create_directories(out / kRuns, ec);
  if (ec) return Error{valid_utf8(out_dir), "--out", "cannot create .runs: " + ec.message(), ""};
  remove_other_runs(out, current_run_name(out));  // staging folders of killed runs
  // The published names, each a symlink through `current` (dangling until the first publish).
  for (const char* name : kPublished)
    if (!is_link_to(out / name, fs::path(kCurrent) / name))
      if (Status st = atomic_symlink(fs::path(kCurrent) / name, out / name); !st) return st.error();
  set->staging_name_ = unique_name();
  set->staging_ = (out / kRuns / set->staging_name_).string();
  fs::create_directories(set->staging_, ec);
  if (ec)
    return Error{valid_utf8(set->staging_), "", "cannot create the run folder: " + ec.message(),
                 ""};
  for (const std::string& w : watched)
    if (!w.empty()) set->digests_[w] = tree_digest(w);
  return set;
}

Status OutputSet::publish() {
  // Only a complete run is published (a full disk can leave results.json unwritten).
  for (const char* required : {"results.json", "junit.xml", "report/index.html"}) {
    std::error_code ec;
    if (!fs::is_regular_file(fs::path(staging_) / required, ec))
      return Error{valid_utf8(staging_), "",
                   std::string("the run is incomplete (no ") + required + "); it is not published",
                   ""};
  }
  // Every process a candidate command started is gone before the folders are hashed: one that
  // escaped its case's kill could write after the check (runner/descendants.h).
  if (is_subreaper()) kill_all_descendants();
  for (const auto& [dir, before] : digests_) {
    const auto changes = digest_changes(before, tree_digest(dir));
    if (changes.empty()) continue;
    std::string list;
    for (const auto& c : changes) list += (list.empty() ? "" : ", ") + c;
    return Error{
        valid_utf8(dir), "",
        "changed while the run ran (" + valid_utf8(list) + "); the run is not published and fails",
        "a candidate command that writes only its {output} (see --sandbox)"};
  }
  if (Status st = atomic_symlink(fs::path(kRuns) / staging_name_, fs::path(out_) / kCurrent); !st)
    return st;
  published_ = true;
  remove_other_runs(out_, staging_name_);
  return {};
}

OutputSet::~OutputSet() {
  std::error_code ec;
  if (!published_ && !staging_.empty()) fs::remove_all(staging_, ec);
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

Status check_output_folders(bool run_or_verify, bool export_cmd, bool goldens_update,
                            const std::string& out_dir, const std::string& cases_dir,
                            const std::string& goldens_dir, std::unique_ptr<OutputSet>* set) {
  if (run_or_verify) {
    auto o = OutputSet::open(out_dir, {cases_dir, goldens_dir});
    if (!o) return o.error();
    *set = std::move(*o);
  }
  if (export_cmd) return validate_output_dir(out_dir, "--out", {cases_dir, goldens_dir});
  if (goldens_update && !goldens_dir.empty())
    return validate_output_dir(goldens_dir, "--goldens", {cases_dir});
  return {};
}

int publish_run(OutputSet* set, int code) {
  if (!set || code == kExitBadInput) return code;
  if (Status st = set->publish(); !st) {
    std::fprintf(stderr, "error: %s\n", st.error().to_string().c_str());
    return kExitFail;
  }
  return code;
}

Result<std::unique_ptr<OutputLock>> OutputLock::take(const std::string& out_dir) {
  std::error_code ec;
  if (!fs::is_directory(out_dir, ec)) return std::unique_ptr<OutputLock>();  // nothing to guard
  auto fd = take_lock(out_dir);
  if (!fd) return fd.error();
  std::unique_ptr<OutputLock> l(new OutputLock);
  l->fd_ = *fd;
  return l;
}

OutputLock::~OutputLock() {
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace hdrc
