#include "runner/output_set.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
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

constexpr const char* kLock = ".lock";
// The top-level names hdrconform writes into OUT; `.runs` and `current` are those of the layout
// before plain files (a published run behind symlinks), replaced whole by the next run;
// review.html is `goldens diff`'s page (runner/goldens_diff.h).
constexpr const char* kOurs[] = {"results.json", "junit.xml", "goldens.json", "report",
                                 "cases",        ".runs",     "current",      "review.html"};
// Staging folders are named PARENT/.<OUT's name><kStagingInfix><unique>.
constexpr const char* kStagingInfix = ".hdrconform-";

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

// Removes a staging folder so that a kill at any moment leaves it recognisable as ours to the
// next command (remove_stale_staging): everything but its .lock first, the .lock last.
void remove_staging(const fs::path& dir) {
  std::error_code ec;
  std::vector<fs::path> children;
  for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator();
       it.increment(ec))
    if (it->path().filename() != kLock) children.push_back(it->path());
  for (const auto& c : children) fs::remove_all(c, ec);
  fs::remove(dir / kLock, ec);
  fs::remove(dir, ec);
}

// The staging folders beside `out` (canonical) that killed commands left: folders named
// .<name>.hdrconform-* whose .lock is OUT's lock file (a hard link made when they were created),
// or empty ones (killed between mkdir and link). Anything else of that name is left alone.
void remove_stale_staging(const fs::path& out) {
  struct stat lock_st {};
  if (::stat((out / kLock).c_str(), &lock_st) != 0) return;
  const std::string prefix = "." + out.filename().string() + kStagingInfix;
  std::error_code ec;
  std::vector<fs::path> stale;
  for (auto it = fs::directory_iterator(out.parent_path(), ec);
       !ec && it != fs::directory_iterator(); it.increment(ec)) {
    if (it->path().filename().string().rfind(prefix, 0) != 0) continue;
    if (!fs::is_directory(it->symlink_status(ec))) continue;
    struct stat st {};
    const bool ours = ::lstat((it->path() / kLock).c_str(), &st) == 0 &&
                      st.st_dev == lock_st.st_dev && st.st_ino == lock_st.st_ino;
    if (ours || fs::is_empty(it->path(), ec)) stale.push_back(it->path());
  }
  for (const auto& p : stale) remove_staging(p);
}

// OUT may hold only what hdrconform writes, since a run replaces it whole: nothing, or a
// previous output (its results.json written by hdrconform) with only hdrconform's names.
Status check_only_ours(const fs::path& out, const std::string& flag) {
  std::error_code ec;
  std::string foreign;
  bool any = false;
  for (auto it = fs::directory_iterator(out, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name == kLock || name.rfind(".hdrconform-write-test-", 0) == 0) continue;
    any = true;
    if (std::find(std::begin(kOurs), std::end(kOurs), name) == std::end(kOurs) && foreign.empty())
      foreign = name;
  }
  if (!any) return {};
  auto results = read_bounded_file((out / "results.json").string(), kMaxResultsFileBytes, "file");
  // The second member of every results.json (runner/results.cpp), compact or indented.
  const bool ours = results && (results->find("\"tool\":\"hdrconform\"") != std::string::npos ||
                                results->find("\"tool\": \"hdrconform\"") != std::string::npos);
  if (ours && foreign.empty()) return {};
  const std::string what = foreign.empty()
                               ? "holds files not written by hdrconform (no results.json of a run)"
                               : "holds " + foreign + ", not written by hdrconform";
  return Error{valid_utf8(out.string()), flag,
               valid_utf8(what) + "; a run replaces the output folder whole, so nothing was run",
               "an empty folder or one written by hdrconform run/verify/merge"};
}

// Copies `from` into `to` as hard links (folders recursively, symlinks followed), leaving out
// the top-level names in `except` and the lock.
Status link_tree(const fs::path& from, const fs::path& to, const std::vector<std::string>& except) {
  std::error_code ec;
  for (auto it = fs::directory_iterator(from, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name == kLock || std::find(except.begin(), except.end(), name) != except.end()) continue;
    std::error_code cec;
    fs::copy(it->path(), to / name,
             fs::copy_options::recursive | fs::copy_options::create_hard_links, cec);
    if (cec)
      return Error{valid_utf8(it->path().string()), "",
                   "cannot link into " + valid_utf8(to.string()) + ": " + cec.message(), ""};
  }
  return {};
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

Result<std::unique_ptr<OutputSet>> OutputSet::open(const std::string& out_dir,
                                                   const std::vector<std::string>& watched,
                                                   const std::string& flag,
                                                   const std::vector<std::string>& keep_except) {
  if (Status st = validate_output_dir(out_dir, flag, watched); !st) return st.error();
  std::unique_ptr<OutputSet> set(new OutputSet);
  std::error_code ec;
  // The folder swapped is the real one (a symlinked --out stays a symlink to it).
  const fs::path out = fs::canonical(out_dir, ec);
  if (ec || out.parent_path() == out)
    return Error{valid_utf8(out_dir), flag, "cannot be published into (the root folder)",
                 "a folder of its own"};
  set->out_ = out.string();
  // The swap moves OUT's folder away: a process working inside it would be left in a removed
  // folder (and `--out .` would remove the shell's).
  if (const fs::path cwd = fs::current_path(ec); !ec && within(cwd.lexically_normal(), out))
    return Error{valid_utf8(out_dir), flag,
                 "is the current folder or holds it; a run replaces the output folder whole",
                 "a folder of its own, e.g. out"};
  auto fd = take_lock(out_dir);
  if (!fd) return fd.error();
  set->lock_fd_ = *fd;
  // A copy keeps everything OUT holds; a new output replaces it, so OUT must hold only ours.
  if (keep_except.empty())
    if (Status st = check_only_ours(out, flag); !st) return st.error();
  // The staging folder is swapped with OUT by a rename, which cannot cross file systems.
  struct stat out_st {
  }, parent_st{};
  if (::stat(out.c_str(), &out_st) != 0 || ::stat(out.parent_path().c_str(), &parent_st) != 0 ||
      out_st.st_dev != parent_st.st_dev)
    return Error{valid_utf8(out_dir), flag,
                 "is a mount point: a run is written beside it and swapped in by a rename, which "
                 "cannot cross file systems; nothing was run",
                 "a folder inside it, e.g. " + valid_utf8((out / "out").string())};
  remove_stale_staging(out);
  const fs::path staging =
      out.parent_path() / ("." + out.filename().string() + kStagingInfix + unique_name());
  fs::create_directory(staging, ec);
  if (!ec) fs::create_hard_link(out / kLock, staging / kLock, ec);
  if (ec)
    return Error{valid_utf8(staging.string()), flag,
                 "cannot create the staging folder beside the output folder: " + ec.message(),
                 "a run is written beside OUT and swapped in whole: OUT's parent folder must be "
                 "writable"};
  set->staging_ = staging.string();
  set->copy_ = !keep_except.empty();
  if (!keep_except.empty())
    if (Status st = link_tree(out, staging, keep_except); !st) return st.error();
  for (const std::string& w : watched)
    if (!w.empty()) set->digests_[w] = tree_digest(w);
  return set;
}

Status OutputSet::publish() {
  // Only a complete run is published (a full disk can leave results.json unwritten).
  // (A copy for `report` keeps what the folder had: a results folder may lack junit.xml.)
  for (const char* required : {"results.json", "junit.xml", "report/index.html"}) {
    std::error_code ec;
    if (copy_ && std::string(required) == "junit.xml") continue;
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
  // The publication: one atomic exchange of two names (renameat2(2), Linux 3.15, glibc 2.28).
  if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, out_.c_str(), RENAME_EXCHANGE) != 0)
    return Error{valid_utf8(out_), "",
                 "cannot swap the new run in (renameat2 RENAME_EXCHANGE): " + os_error(errno) +
                     "; it is not published",
                 "a local file system that supports RENAME_EXCHANGE (ext4, xfs, btrfs, tmpfs)"};
  published_ = true;
  remove_staging(staging_);  // the previous output, now under the staging name
  return {};
}

OutputSet::~OutputSet() {
  if (!published_ && !staging_.empty()) remove_staging(staging_);  // an unpublished run
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

}  // namespace hdrc
