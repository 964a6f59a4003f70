// Loads case files (cases/**/*.json), validates every field, expands `matrix` into cases.
// All errors name the file, the JSON pointer, the offending value and the valid choices; loading
// reports every invalid file, and the caller runs nothing when there is any error.
#pragma once

#include <string>
#include <vector>

#include "core/case.h"
#include "core/result.h"

namespace hdrc {

struct LoadedCases {
  std::vector<Case> cases;    // sorted by id
  std::vector<Error> errors;  // empty when every file is valid
};

// Loads every *.json under `cases_dir` except schema.json.
LoadedCases load_cases(const std::string& cases_dir);

// Parses one case file's text (exposed for tests). `cases_dir` bounds input file paths.
std::vector<Case> parse_case_file(const std::string& file, const std::string& text,
                                  const std::string& cases_dir, const std::string& name,
                                  std::vector<Error>* errors);

// The defaults a case gets when its file sets no tolerance (documented in docs/tolerances.md).
Tolerance default_tolerance();

// A listed limitation of an engine: its cases are reported as KNOWN_LIMIT with the reason, never
// as passed and never silently skipped (cases/known_limits.json).
struct KnownLimit {
  std::string cases;   // glob over case ids
  std::string engine;  // candidate engine name ("vulkan")
  std::string reason;  // why, with the issue that lifts it
};

// Reads `cases_dir`/known_limits.json (absent: none). Errors are located like case errors.
std::vector<KnownLimit> load_known_limits(const std::string& cases_dir, std::vector<Error>* errors);

// Glob match (`*`, `?`, `[...]`) of a case id.
bool matches_filter(const std::string& id, const std::string& glob);

// Builds the engine input: the stimulus or the image file, and the resolved parameters.
Result<ResolvedCase> resolve_case(const Case& c);

}  // namespace hdrc
