// What the suite covers, against what it declares it must cover (cases/coverage.json):
//   * per cvar or setting: every declared value and how many cases (of the stages it matters to)
//     run with it;
//   * per requirement: every combination of declared values it asks for ("full": every
//     combination of its dimensions; "of"/"with": every pair of values of each of `of` with each
//     of `with`) and whether some case of its stages holds it.
// A case covers the value a cvar or setting has in it, set or default. A combination held only
// by DEGENERATE cases (UE computes degenerate parameters there) counts as covered and is listed
// with its reason: it is reported as DEGENERATE by every run, never as a pass.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/case.h"
#include "core/result.h"

namespace hdrc {

struct CoverageRequirement {
  std::string name;
  std::vector<std::string> stages;
  std::vector<std::string> full;      // dimensions crossed exhaustively
  std::vector<std::string> of, with;  // pairs: each of `of` with each of `with`
};

struct Pipeline;

struct CoverageSpec {
  std::string file;
  const Pipeline* pipeline = nullptr;  // whose cvars, settings, stages and cases it declares
  std::map<std::string, std::vector<double>> values;  // declared values per cvar or setting
  std::vector<std::string> order;                     // names in file order
  std::vector<CoverageRequirement> requirements;
};

// Reads `cases_dir`/coverage.json (or another declaration beside it, e.g.
// coverage_exhaustive.json for `coverage --suite exhaustive`); errors name file, pointer, value
// and valid choices.
// `pipeline`: the pipeline whose cvars, settings and stages the file names (UE 5.5's when null);
// compute_coverage counts that pipeline's cases only.
CoverageSpec load_coverage_spec(const std::string& cases_dir, std::vector<Error>* errors,
                                const std::string& file_name = "coverage.json",
                                const Pipeline* pipeline = nullptr);
// The declaration a pipeline's coverage is checked against: coverage.json (coverage_exhaustive.json
// for the exhaustive suite) for UE 5.5, coverage_<pipeline>.json beside it for every other.
std::string coverage_file_name(const Pipeline& pipeline, const std::string& suite);

struct ValueCoverage {
  double value;
  int cases = 0;       // cases that run with it
  int degenerate = 0;  // of those, DEGENERATE ones
};

struct NameCoverage {
  std::string name;
  std::vector<std::string> stages;  // where it is counted (the stages of its requirements)
  std::vector<ValueCoverage> values;
};

struct RequirementCoverage {
  CoverageRequirement requirement;
  size_t combinations = 0;
  size_t covered = 0;                   // including those covered only by degenerate cases
  std::vector<std::string> missing;     // "r.X=1, r.Y=2"
  std::vector<std::string> degenerate;  // "r.X=1, r.Y=2: reason"
};

struct CoverageReport {
  std::vector<NameCoverage> names;
  std::vector<RequirementCoverage> requirements;
  size_t values_declared() const;
  size_t values_covered() const;
  size_t combinations() const;
  size_t combinations_covered() const;
  bool complete() const {
    return values_covered() == values_declared() && combinations_covered() == combinations();
  }
  std::string text() const;  // the table `hdrconform coverage` prints
};

CoverageReport compute_coverage(const CoverageSpec& spec, const std::vector<Case>& cases);

// The value of a cvar or setting in a case (its default when unset); scalar settings only.
double effective_value(const Case& c, const std::string& name);

}  // namespace hdrc
