// The output folder of `run` and `verify` (--out), written so that a kill -9 at any moment leaves
// either the previous complete run or the new complete run there, never a mix
// (docs/output-folder.md):
//
//   OUT/.lock                 flock(2)ed by the run writing OUT; a second run is refused
//   OUT/.runs/<unique>/       one complete run: results.json, junit.xml, goldens.json, report/,
//                             cases/<case id>/*.exr
//   OUT/current               symlink to .runs/<unique>, replaced by one rename(2) to publish
//   OUT/results.json, OUT/junit.xml, OUT/goldens.json, OUT/report, OUT/cases
//                             symlinks to current/<name>, created once, so the documented paths
//                             always show the published run
//
// A run writes into its own staging folder .runs/<unique> and publishes it by swapping
// `current`; the previous run's folder is removed after the swap. Before any work the folder is
// validated (not empty, not the cases or goldens folder, not inside or around them, writable),
// and the cases and goldens folders are hashed, so that a run during which they changed (a
// candidate command writing into them) fails instead of publishing.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/result.h"

namespace hdrc {

// Checks a folder the program will write into (--out, export --out, goldens update --goldens):
// not empty, not (a symlink to) any of `protected_dirs`, not inside one, not holding one; a folder
// or creatable as one; writable (checked by creating and removing a file). `flag` names the
// option in errors, which carry the OS reason. Creates the folder.
Status validate_output_dir(const std::string& dir, const std::string& flag,
                           const std::vector<std::string>& protected_dirs);

// SHA-256 of every file under `dir` (regular files by content, symlinks by target), by path
// relative to `dir`. A missing folder has no entries.
std::map<std::string, std::string> tree_digest(const std::string& dir);

// Paths that differ between two digests ("added", "removed" or "changed"), at most `max`.
std::vector<std::string> digest_changes(const std::map<std::string, std::string>& before,
                                        const std::map<std::string, std::string>& after,
                                        size_t max = 5);

// If `dir` is an output folder with a published run, the run's folder (OUT/current resolved),
// else `dir` itself.
std::string published_run_dir(const std::string& dir);

class OutputSet {
 public:
  // Validates `out_dir`, takes its lock (refusing when another run holds it), removes staging
  // folders of runs that were killed, and creates this run's staging folder. `watched` folders
  // (cases, goldens) are hashed now and again at publish().
  static Result<std::unique_ptr<OutputSet>> open(const std::string& out_dir,
                                                 const std::vector<std::string>& watched);
  ~OutputSet();  // removes the staging folder unless published; releases the lock
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  const std::string& staging() const { return staging_; }
  // Checks the watched folders, then makes the staging folder the published run.
  Status publish();
  bool published() const { return published_; }

 private:
  OutputSet() = default;
  std::string out_, staging_, staging_name_;
  int lock_fd_ = -1;
  bool published_ = false;
  std::map<std::string, std::map<std::string, std::string>> digests_;
};

// The folder checks of the command line, before any work: run/verify open `*set` on --out
// (protecting the cases and goldens folders); export checks --out the same way; goldens update
// checks --goldens (protecting the cases folder; an empty value is reported by the caller).
Status check_output_folders(bool run_or_verify, bool export_cmd, bool goldens_update,
                            const std::string& out_dir, const std::string& cases_dir,
                            const std::string& goldens_dir, std::unique_ptr<OutputSet>* set);

// Publishes `set` (when not null) unless `code` is kExitBadInput (nothing is published then).
// Returns `code`, or kExitFail when publishing failed (the reason is printed).
int publish_run(OutputSet* set, int code);

// Takes OUT/.lock for a command that changes a published run (`report`). The lock is released
// when the returned object is destroyed.
class OutputLock {
 public:
  static Result<std::unique_ptr<OutputLock>> take(const std::string& out_dir);
  ~OutputLock();

 private:
  int fd_ = -1;
};

}  // namespace hdrc
