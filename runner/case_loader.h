// Loads case files (cases/**/*.json), validates every field, expands `matrix` into cases.
// All errors name the file, the JSON pointer, the offending value and the valid choices (with the
// nearest valid name for a misspelt one); loading reports every invalid file, and the caller runs
// nothing when there is any error. The format is cases/schema.json, described in docs/cases.md.
#pragma once

#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/case.h"
#include "core/result.h"

namespace hdrc {

// Files at the top of the cases directory that configure the suite and are not case files.
// defaults.json: shared tolerance sets and presets; coverage.json: the declared coverage;
// known_limits.json: engine limits; tolerance_overlays.json: tolerance overlays; schema.json.
bool is_suite_config_file(const std::string& cases_dir, const std::string& path);

// A named bundle of cvars and settings from cases/defaults.json (`"preset": NAME` in a case).
struct Preset {
  CvarValues cvars;
  SettingValues settings;
};

// cases/defaults.json: tolerance sets (`"tolerance": NAME` in a case) and presets, defined once.
struct SuiteDefaults {
  std::string file;  // the defaults file read ("" when absent)
  std::map<std::string, Tolerance> tolerances;
  std::map<std::string, Preset> presets;
};

// Reads `cases_dir`/defaults.json (absent: none). Errors are located like case errors.
SuiteDefaults load_suite_defaults(const std::string& cases_dir, std::vector<Error>* errors);

struct LoadedCases {
  std::vector<Case> cases;    // sorted by id
  std::vector<Error> errors;  // empty when every file is valid
  SuiteDefaults defaults;
};

// Bounds on what a case folder may ask for, checked before any expansion or allocation.
inline constexpr size_t kMaxCases = 100000;           // cases in the whole suite
inline constexpr size_t kMaxCasesPerFile = 20000;     // cases one file's matrix expands to
inline constexpr size_t kMaxCaseDirEntries = 100000;  // files and folders under cases/

// Loads every case file under `cases_dir` (every *.json except the suite configuration files).
// Only regular files count, or symlinks to regular files inside `cases_dir` (named by the link);
// a dangling symlink, a symlink leaving the folder, a symlinked folder, a *.json that is not a
// regular file and a file whose name is no valid case id are errors (never silently skipped).
// `suite` "quick" (the default suite) keeps the cases of tier "quick"; "exhaustive" keeps every
// case (both tiers). Every file is validated whatever the suite.
LoadedCases load_cases(const std::string& cases_dir, const std::string& suite = "quick");

// The suite names `load_cases` accepts: quick, exhaustive.
const std::vector<std::string>& suite_names();

// A case id is a relative path of non-empty, printable UTF-8 names, none '.' or '..', so that
// OUT/cases/<id> and <goldens>/<id>.exr stay inside their folders.
Status check_case_id(const std::string& id);

// Parses one case file's text (exposed for tests). `cases_dir` bounds input file paths; named
// tolerance sets and presets come from `defaults`.
std::vector<Case> parse_case_file(const std::string& file, const std::string& text,
                                  const std::string& cases_dir, const std::string& name,
                                  const SuiteDefaults& defaults, std::vector<Error>* errors);
// The same with the defaults of `cases_dir` (their errors are appended too).
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
  // A glob over the candidate device's name (optional), with ", worst-case device model" appended
  // under `--device-model worst` (runner/run.cpp known_limit_device_name).
  std::string device = "*";
};

// Reads `cases_dir`/known_limits.json (absent: none). Errors are located like case errors.
std::vector<KnownLimit> load_known_limits(const std::string& cases_dir, std::vector<Error>* errors);

inline constexpr size_t kMaxKnownLimits = 10000;

// The limits of a parsed limits file (cases/known_limits.json, `verify --candidate-limits`):
// {"limits": [{"cases", "engine", "device" (when `device_key`), "reason"}, ...]}, with "$schema"
// and "description" beside "limits"; `engines` the valid engine names. Every error names `file`,
// the JSON pointer, the value and the valid choices; only valid limits are returned.
std::vector<KnownLimit> parse_known_limits(const nlohmann::ordered_json& doc,
                                           const std::string& file,
                                           const std::vector<std::string>& engines, bool device_key,
                                           std::vector<Error>* errors);

// Glob match (`*`, `?`, `[...]`) of a case id.
bool matches_filter(const std::string& id, const std::string& glob);

// The short name a matrix dimension has in case ids ("r.HDR.Display.OutputDevice" -> "dev",
// "LUTFormat" -> "fmt").
std::string id_name(const std::string& cvar_or_setting);

// Builds the engine input: the stimulus or the image file, the resolved parameters and the user
// LUT (attach_user_lut).
Result<ResolvedCase> resolve_case(const Case& c);

// A user LUT (docs/cases.md, "lut"): the .cube at `path` (relative to `cases_dir`, and refused when
// it leaves it; any path when `cases_dir` is empty), read with core/cube, with one 3-D table and,
// when `stage` requires a size, that size. Errors (no file or pointer: the caller's) name the
// value and the valid choices: not .cube, missing, unparsable (the .cube's line), 1-D only, a 1-D
// shaper, the wrong size.
Result<std::shared_ptr<const UserLut>> read_user_lut(const std::string& cases_dir,
                                                     const std::string& path,
                                                     const StageInfo* stage);
// The size rule of read_user_lut alone (a LUT read for another stage); and its valid choices.
Status check_user_lut_size(const UserLut& lut, const StageInfo* stage,
                           const std::string& cases_dir);
std::string user_lut_choices(const std::string& cases_dir, const StageInfo* stage);
// Gives `r` the user LUT (null: none): spec.lut, the strip texture user_lut and
// P.user_lut_size / user_lut_domain_min / _max (zeros without one).
Status attach_user_lut(const std::shared_ptr<const UserLut>& lut, ResolvedCase* r);
// Gives `r` the strip textures of `slots` (binding kBindingUserLut, slot by slot; null: none),
// rounded to 8-bit UNORM for a stage with StageInfo::user_lut_unorm8, and P.user_lut_* (the
// first LUT's size and domain; every LUT must have that size).
Status attach_user_luts(const std::array<std::shared_ptr<const UserLut>, kUserLutSlots>& slots,
                        ResolvedCase* r);

}  // namespace hdrc
