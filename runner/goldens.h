// Goldens: the reference engine's outputs, stored so that a port can be compared with them
// without building the reference, and so that a change of the reference itself is caught.
//
// Layout: goldens/<case id>.exr (32-bit float RGBA, ZIP compression) and goldens/<case id>.json,
// the sidecar with the provenance (goldens/README.md):
//   case, stage, width, height,
//   case_hash         SHA-256 of the case's definition (stage, the cvars and settings it sets,
//                     the input spec; an input file by its content),
//   input_hash        SHA-256 of the input pixels both engines get (float32, plus bloom, dirt
//                     and UI layers),
//   output_hash       SHA-256 of the golden's float32 pixels,
//   reference_version kReferenceVersion and the reference's fingerprint (reference_fingerprint),
//   values            the named numbers the stage outputs (VisualizeHDR's printed numbers),
//   date              when this golden was written (UTC).
// Only `hdrconform goldens update` writes goldens/ (update_goldens); `hdrconform run` checks the
// reference's outputs against them (check_golden).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/case.h"
#include "core/image.h"
#include "core/result.h"

namespace hdrc {

// Bumped by hand when the reference is changed on purpose (a decision revised, a formula fixed).
// The fingerprint below changes by itself with any change of what the reference computes on its
// probe cases; the two together are the reference version a golden records.
inline constexpr int kReferenceVersion = 1;

// SHA-256 (FIPS 180-4) of `data`, as 64 lowercase hex digits.
std::string sha256_hex(const std::string& data);

// The float32 bytes of an image's pixels (what EXR goldens store), for hashing.
std::string image_bytes(const Image& img);

// SHA-256 of the case's definition: stage, the cvars and settings it sets explicitly, its input,
// bloom and dirt specs (an input file by the SHA-256 of its content). Not the tolerance: it does
// not change the reference's output.
std::string case_hash(const Case& c);
// SHA-256 of the input pixels (and bloom, dirt, UI layers) both engines get.
std::string input_hash(const ResolvedCase& r);

// "1/<12 hex digits>": kReferenceVersion and a hash of the reference engine's outputs on fixed
// probe cases of every stage (runner/goldens.cpp: probe_cases). Computed once per process.
const std::string& reference_version();

struct GoldenPaths {
  std::string exr, sidecar;
};
GoldenPaths golden_paths(const std::string& goldens_dir, const std::string& case_id);

// The command that (re)creates the golden of `case_id` (`extra` adds e.g. "--cases DIR").
std::string golden_update_command(const std::string& case_id, const std::string& extra = "");

struct GoldenCheck {
  enum Outcome { kMatch, kMissing, kStale, kRegression } outcome = kMatch;
  std::string message;  // for all but kMatch: what differs, where, and the command to run
  double deviation =
      0;  // the largest deviation of a pixel value in units of the bound (≤ 1: match)
};

// Compares the reference's output for `c` with its golden. `reference` is the reference engine's
// image (as the run wrote it), `values` its named numbers, `resolved` the case's inputs.
// Pixels must be equal as float32 within the bound of runner/golden_compare.h (docs/goldens.md:
// 2 ULPs, or a fraction of the image's scale, measured across compilers and optimisation
// levels); NaN matches NaN, infinities match by sign.
GoldenCheck check_golden(const std::string& goldens_dir, const Case& c,
                         const ResolvedCase& resolved, const Image& reference,
                         const std::string& update_extra = "");

struct GoldenUpdateReport {
  int written = 0, unchanged = 0, skipped_degenerate = 0, removed = 0;
  int changed = 0;  // written over a golden whose pixels differ (the others: new, or a sidecar)
  // The largest moves of those (runner/goldens_diff.h, GoldenMove) and their case ids: 10-bit PQ
  // codes (+inf for a golden whose size changed), ΔE_ITP.
  std::pair<double, std::string> largest_pq10{0.0, ""}, largest_itp{0.0, ""};
  // One per written/removed golden, in id order: "changed ID: <how far it moved>; wrote PATH",
  // "new ID: wrote PATH", "sidecar ID: same pixels, wrote PATH", "removed PATH"; and errors.
  std::vector<std::string> lines;
  std::vector<Error> errors;
};

// Runs the reference on `cases` (with `jobs` threads; 0 = every core) and writes each output and
// its sidecar to `goldens_dir` atomically, unless the golden there already has the same pixels,
// hashes and named values (so unchanged goldens keep their date and bytes, whatever the reference
// version: the sidecar keeps the version that wrote it). An EXR whose pixels are unchanged is
// never rewritten (only its sidecar, when a hash changed). Degenerate cases get no
// golden. With `prune`, goldens of cases not in `cases` are deleted (use it with the full suite
// only).
GoldenUpdateReport update_goldens(const std::vector<Case>& cases, const std::string& goldens_dir,
                                  bool prune, int jobs = 0);

// The golden check of `hdrconform run`: every case of `cases` whose reference image the run
// wrote (listed in OUT/results.json with images.reference) is compared with its golden, and its
// named values with the sidecar's. Prints one line per failing case and a summary line, writes
// OUT/goldens.json (atomically). A run with any failure fails (exit code 1). The cases are checked
// on `jobs` threads (0: one per core); lines and goldens.json are in the cases' order for any.
struct GoldenRunSummary {
  int checked = 0, missing = 0, stale = 0, regressions = 0;
  int failed() const { return missing + stale + regressions; }
};
GoldenRunSummary check_run_against_goldens(const std::vector<Case>& cases,
                                           const std::string& out_dir,
                                           const std::string& goldens_dir,
                                           const std::string& update_extra = "", int jobs = 1);

// The goldens' size budget, enforced by Goldens.TheRepositorysGoldensStayWithinTheirBudget
// (docs/goldens.md, "Size"). Measured 2026-11-27: 1381 goldens, 33.45 MB (76 % of the tracked
// tree's bytes, 83 % of its files); the largest image 2.52 MB (lut/storage/lut64_dev3_fmt2_layout1,
// a 64³ float LUT), the largest sidecar 818 bytes; then the ue58 pipeline's 247 goldens, 5.40 MB
// (16³ LUTs). The budget leaves about 8 % for new cases: more needs a decision (smaller images,
// coarser stimuli, or a new pipeline's measured size stated in docs/goldens.md), not a silent
// growth.
inline constexpr uintmax_t kGoldensBudgetBytes = 42'000'000;     // the whole folder
inline constexpr uintmax_t kGoldenImageBudgetBytes = 3'000'000;  // one EXR
inline constexpr uintmax_t kGoldenSidecarBudgetBytes = 4096;     // one sidecar

// Total size in bytes of the files under `goldens_dir`.
uintmax_t directory_bytes(const std::string& dir);

}  // namespace hdrc
