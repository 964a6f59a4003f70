// Which cases a command runs: --filter patterns, --rerun-failed, and the command-line hints that
// go with them (no match, an unknown subcommand).
#pragma once

#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/case.h"
#include "core/result.h"

namespace hdrc {

// --filter, given once or more, each value a comma-separated list of patterns; a case is selected
// when any pattern matches its id. A pattern with a glob character (* ? [) is matched against the
// whole id (fnmatch, '*' crosses '/'); "=ID" selects exactly that id (the reproduce command of a
// case page); any other pattern is a substring of the id ("lut" selects every case whose id
// contains "lut"). A pattern after '!' excludes what it matches, whatever the order (gtest's
// POS-NEG, pytest's "not"): "tonemap/*,!hdr" is every tonemap case but those with "hdr";
// exclusions alone start from every case.
struct CaseSelection {
  std::vector<std::string> patterns;  // empty: every case
  // --rerun-failed DIR: only the cases DIR/results.json lists as FAIL, ERROR or MISSING, or whose
  // golden check failed.
  std::string rerun_dir;
  std::optional<std::set<std::string>> rerun_ids;
  // --pipeline: only the cases of these pipelines (core/pipeline.h); empty: every pipeline.
  std::vector<std::string> pipelines;
  bool matches(const std::string& id) const;
  bool matches(const Case& c) const;  // its id, and its stage's pipeline
  std::string describe() const;  // for messages: "--filter 'a,b' --pipeline p --rerun-failed DIR"
};

// Splits --filter values (CLI11 joins repeated values with '\n') on newlines and commas.
std::vector<std::string> split_filter(const std::string& text);

// Builds the selection; with a rerun directory, reads DIR/results.json (errors name the file).
// `pipeline_text`: --pipeline's comma-separated pipeline names (an unknown one is an error naming
// the valid choices).
Result<CaseSelection> make_selection(const std::string& filter_text, const std::string& rerun_dir,
                                     const std::string& pipeline_text = "");

// The ids of DIR/results.json's failed cases (FAIL, ERROR, MISSING, or a failed golden).
Result<std::set<std::string>> failed_case_ids(const std::string& results_dir);

// "no case matches ...": the patterns, then a hint: the closest case ids and id components
// (did you mean), and how patterns are matched.
std::string no_match_message(const CaseSelection& sel, const std::vector<Case>& all,
                             const std::string& cases_dir);

// The command name closest to a mistyped one (case-insensitive edit distance at most 3, or a
// prefix), or "" when none is close.
std::string closest_command(const std::string& typed, const std::vector<std::string>& commands);

}  // namespace hdrc
