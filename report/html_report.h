// The browsable report of a run: a static folder that opens from disk (file://) or any static
// server, with no network access. It is a pure function of a results directory:
//
//   DIR/results.json                           the run (runner/results.cpp, results.schema.json)
//   DIR/cases/<case id>/{input,reference,candidate}.exr   the images of each case (when written)
//     → DIR/report/index.html                  summary: counts, worst cases, near misses, metadata
//       DIR/report/matrix.html                 verdict or a metric pivoted over two chosen cvars
//       DIR/report/cases.html                  every case: filters (stage, verdict, cvar, text),
//                                              sort; thumbnails
//       DIR/report/c/<slug>.html               one page per case, one file: parameters,
//                                              tolerance, statistics, images (exposure, heatmap,
//                                              mask, flip, slider, probe), the float data
//                                              (#case-px: the case's EXR files themselves, which
//                                              the page's script decodes, or packed float32)
//       DIR/report/t/<n>.png                   thumbnail atlases: the list pages' thumbnails of
//                                              64 cases each, stacked
//       DIR/report/data.js, assets/            the case table for the script pages; script, style
//
// The case page's script draws the previews, heatmaps and mask from the float data (images up
// to 4 Mpixel: assets/report.js previewData, heatData, maskData, mirroring the C++ below, which
// the browser test compares); only the thumbnails are made here, from the pixels they show.
// Larger images get no float data: their pictures are made here, in one PNG the page carries.
//
// Fields missing from results.json are shown as "—"; nothing in it is trusted: every string is
// escaped where it is written (HTML text, attributes, URLs, script data).
//
// SDR preview mapping (the same in C++ for the thumbnails and in assets/report.js for the panels
// and control): each value is decoded to absolute luminance with the case's output encoding (the
// one the diff uses, docs/diff-metrics.md; inputs are scene-linear × 100 nits except for
// ui_composite, whose input is a back buffer in the output's encoding), then
//   display = sRGB_OETF(clamp(nits / 100 · 2^EV, 0, 1))          (100 nits at EV 0 = SDR white)
// per channel, 8 bits. A pixel with a NaN channel is drawn magenta, with an infinite one cyan.
//
// Error heatmap: per pixel, the largest PQ error of its colour channels in 10-bit code values
// (|PQ(nits(cand)) − PQ(nits(ref))| · 1023, as runner/diff.cpp), coloured with VisualizeHDR's
// Colorize ramp (blue small, green, red large) over log10(error) from 1e-4 to 10 codes; an exact 0
// is black, a non-finite mismatch white.
#pragma once

#include <cstddef>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "core/result.h"

namespace hdrc {

std::string html_escape(const std::string& s);

namespace report {

// Percent-encodes a relative path for an href (every byte but A–Z a–z 0–9 - . _ ~ /).
std::string url_path_escape(const std::string& path);

// A file name for a case id: [A-Za-z0-9._-] kept, '/' → "__", anything else → '_'.
// Not unique by itself; write_report appends "-<n>" to later duplicates.
std::string case_slug(const std::string& id);

// Serialises JSON-encoded text for a <script> element: '<', '>', '&', U+2028 and U+2029 are
// written as \u escapes, so no string in the data can close the element or start markup.
std::string script_safe_json(const std::string& json_text);

// A case id as the list pages show it, at most `max_chars` characters (UTF-8 code points): the
// id itself when it fits, else its first path segment (the suite), "…", and the end of the id
// (its most specific part), e.g. "tonemap/…/dev3_gamut2_log_ramp". The full id goes in the
// link's title.
std::string short_case_id(const std::string& id, size_t max_chars);

// The metrics a case of results.json is judged on, from the tolerance the run used (its
// "tolerance" object, runner/tolerance.cpp tolerance_json: a metric key whose entry is not null
// is judged), in the order results.json lists them; "dither" when the dither criterion is judged.
// The matrix shows a metric only for the cases that judge it.
std::vector<std::string> judged_metrics(const nlohmann::json& result_case);

// Why a case did not pass, as a class the summary groups its worst cases by: the metric and the
// kind of failure, as the runner judged them (runner/diff.cpp judge: the first non-finite
// mismatch decides, then each metric in turn its hard cap, then its max or allowed fraction;
// runner/dither.cpp judge_dither: the dither criterion named by the reason). Read from the
// case's recorded statistics and tolerance:
//   {"non-finite", "non-finite mismatch"}     nonfinite.mismatch > 0
//   {<metric key>, "over hard cap"}           stats.overall.<metric>.max > tolerance.<metric>.hard
//   {<metric key>, "over tolerance"}          over its max (or its allowed fraction)
//   {"dither <criterion>", "over tolerance"}  a dither criterion (amplitude, mean, std, ...)
//   {"", <verdict, lower case>}               ERROR, MISSING, or a FAIL none of these explains
struct FailureClass {
  std::string metric, kind;
  std::string label() const;  // "pq_code10 over tolerance", "error"
};
FailureClass failure_class(const nlohmann::json& result_case);

struct ReportInfo {
  std::string index_path;  // DIR/report/index.html
  size_t cases = 0;
  size_t files = 0;
  size_t bytes = 0;        // total size of the report folder
  double seconds = 0;      // wall
  double cpu_seconds = 0;  // CPU time of the process (every thread) while it built the report
};

}  // namespace report

// Rebuilds `results_dir`/report/ from `results_dir`/results.json and the case images beside it.
// The new report is built in a sibling folder and swapped in, so a failed build leaves the old
// one. Errors name the file and, for bad JSON, the JSON pointer. The cases' images and pages are
// made on `jobs` threads (0: one per core); the report is the same for any number.
Result<report::ReportInfo> write_report(const std::string& results_dir, int jobs = 0);

}  // namespace hdrc
