// The output folder of `run`, `verify`, `merge` and `report` (--out), written so that a kill -9 at
// any moment leaves either the previous complete run or the new complete run there, never a mix,
// and holding plain files and folders only (no symlinks: GitLab's runner does not follow them for
// artifacts or `reports:junit`) (docs/output-folder.md):
//
//   OUT/.lock                 flock(2)ed by the command writing OUT; a second one is refused
//   OUT/results.json, OUT/junit.xml, OUT/goldens.json, OUT/report/, OUT/cases/<case id>/*.exr
//                             the published run
//   PARENT/.OUT.hdrconform-<unique>/
//                             a run being written (staging), beside OUT on the same file system;
//                             gone once the run ends
//
// A command writes the whole new output into its staging folder (which holds a hard link of
// OUT/.lock, so the lock survives the swap) and publishes it by exchanging the staging folder
// and OUT in one renameat2(RENAME_EXCHANGE): the one step at which a reader of OUT sees the new
// run instead of the old. The old output, now under the staging name, is then removed. Before
// any work the folder is validated (not empty, not the cases or goldens folder, not inside or
// around them, writable, not a mount point, holding nothing hdrconform did not write), and the
// cases and goldens folders are hashed, so that a run during which they changed (a candidate
// command writing into them) fails instead of publishing.
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

class OutputSet {
 public:
  // Validates `out_dir`, takes its lock (refusing when another command holds it), removes the
  // staging folders of commands that were killed, and creates this one's staging folder beside
  // OUT. `watched` folders (cases, goldens) are hashed now and again at publish(). `flag` names
  // the folder in errors ("--out", "OUT"). With `keep_except` non-empty the staging folder
  // starts as a copy of OUT (hard links) without the named top-level entries, and OUT may hold
  // anything: `report` rebuilds report/ of the published run that way.
  static Result<std::unique_ptr<OutputSet>> open(const std::string& out_dir,
                                                 const std::vector<std::string>& watched,
                                                 const std::string& flag = "--out",
                                                 const std::vector<std::string>& keep_except = {});
  ~OutputSet();  // removes the staging folder unless published; releases the lock
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  const std::string& staging() const { return staging_; }
  // Checks that the run is complete and the watched folders unchanged, then swaps the staging
  // folder in as OUT.
  Status publish();
  bool published() const { return published_; }

 private:
  OutputSet() = default;
  std::string out_, staging_;
  int lock_fd_ = -1;
  bool published_ = false;
  bool copy_ = false;  // the staging folder started as a copy of OUT (`report`)
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

}  // namespace hdrc
