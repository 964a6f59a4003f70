// Golden changes a reviewer can judge (docs/goldens.md, "Reviewing a golden change"):
//
//   * how far a golden moved: runner/diff.cpp's metrics (diff_images, the one metric code path of
//     run and verify) of the new golden against the old one, under the case's output encoding:
//     max and p99 in 10-bit PQ code values, ΔE_ITP max and p99, linear max. `goldens update`
//     prints it for every golden it rewrites.
//   * `hdrconform goldens diff`: the goldens of a git revision (or of a folder) against the
//     working tree's, as a results folder whose cases are the changed goldens (old as the
//     reference, new as the candidate) and its report, so that every view of the report's case
//     page (previews, heatmaps, ΔE_ITP histogram, the ramp plot with both curves) shows the
//     change, plus OUT/review.html, one page listing every changed, added and removed golden.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/case.h"
#include "core/image.h"
#include "core/result.h"
#include "runner/diff.h"

namespace hdrc {

// Whether two images hold the same float32 values bit for bit (the same size too).
bool same_pixels(const Image& a, const Image& b);

struct GoldenMove {
  bool resized = false;       // the images differ in size: no metric
  size_t values_changed = 0;  // RGBA values not bit-identical
  size_t nonfinite_mismatch = 0;
  double pq10_max = 0, pq10_p99 = 0;  // 10-bit PQ code values, per colour value
  double itp_max = 0, itp_p99 = 0;    // ΔE_ITP (BT.2124) per pixel
  double linear_max = 0;              // |new − old| in the output's own units
};

// How far `now` moved from `before` (both the reference's output for `resolved`): diff_images
// with `before` as the reference, `now` as the candidate, the case's output encoding and
// tolerance; `stats` receives the full statistics when given.
GoldenMove golden_move(const Case& c, const ResolvedCase& resolved, const Image& before,
                       const Image& now, DiffStats* stats = nullptr);

// "PQ max 0.412 p99 0.0871 (10-bit codes), ΔE_ITP max 1.3 p99 0.2, linear max 0.00312;
// 1204 of 4096 values changed".
std::string describe_move(const GoldenMove& m);

struct GoldensDiffOptions {
  std::string goldens_dir;     // the new goldens (the working tree's)
  std::string old_dir;         // --old DIR: the old goldens from a folder; "" : from git
  std::string since = "HEAD";  // --since REV: the revision whose goldens are the old ones
  std::string command_line;    // recorded in results.json and shown by review.html
  int jobs = 0;                // report threads (0: one per core)
};

struct GoldensDiffReport {
  int changed = 0, added = 0, removed = 0, bytes_only = 0, no_case = 0;
  std::vector<std::string> lines;  // one per golden that differs, in id order
  std::string review_page;         // OUT/review.html (relative to OUT)
};

// Writes the review into `staging` (an OutputSet's staging folder, published by the caller):
// results.json, cases/<id>/{input,reference,candidate}.exr (reference: the old golden, candidate:
// the new), report/ (write_report) and review.html. `cases` gives each changed golden its stage,
// encoding, input and tolerance; a golden with no case among them is listed without views.
// Errors name the revision, the file, or the field.
Result<GoldensDiffReport> goldens_diff(const std::vector<Case>& cases,
                                       const GoldensDiffOptions& opt, const std::string& staging);

}  // namespace hdrc
