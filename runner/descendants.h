// A candidate command's processes, all of them (issue 29): a child that leaves the command's
// process group (setsid) or whose parent exits first (a double fork) escapes a process-group kill
// and could write into the cases folder after `verify` published its verdicts. So the runner makes
// itself the child subreaper (prctl PR_SET_CHILD_SUBREAPER, proc(5)): such orphans are re-parented
// to it instead of to init, and stay its descendants, where /proc finds them.
//
// Every command carries a token in its environment (kCommandTokenVar), which its descendants
// inherit. At the case's end (run_command) every descendant of the runner that carries the case's
// token, or is in the command's process group, is killed with its whole subtree and reaped. Before
// a run is published (runner/output_set.h, which then hashes the cases and goldens folders) every
// descendant left is.
#pragma once

#include <sys/types.h>

#include <string>

#include "core/result.h"

namespace hdrc {

inline constexpr const char* kCommandTokenVar = "HDRC_COMMAND_TOKEN";

// Makes this process the child subreaper; idempotent. Errors carry the OS reason.
Status become_subreaper();
// Whether become_subreaper succeeded in this process.
bool is_subreaper();

// A token no other command of this process had ("<pid>-<n>").
std::string new_command_token();

// Kills every descendant of this process that carries `token` in its environment or belongs to
// process group `group` (the command's; 0: none), with all of their descendants, and reaps those
// that are (or become) this process's children. Returns how many processes were killed.
size_t kill_command_processes(const std::string& token, pid_t group);

// Kills and reaps every descendant of this process: only when no command is running. Returns how
// many processes were killed.
size_t kill_all_descendants();

}  // namespace hdrc
