// `hdrconform probe`: what UE 5.5 computes for given colours, for people debugging a port.
#pragma once

#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

#include "core/case.h"
#include "core/result.h"

namespace hdrc {

struct ProbeOptions {
  std::string pipeline = "ue55";     // core/pipeline.h; UE 5.5's stages are the ones below
  std::vector<std::string> set;      // "CVAR=VALUE"
  std::vector<std::string> setting;  // "NAME=VALUE" or "NAME=r,g,b,a"
  std::string lut = "analytic";      // analytic | baked
  std::string stage = "output";      // see probe_stage_names(); another pipeline: its stage that
                                     // takes an input (default: the last such stage)
  std::string ui = "0,0,0,0";        // --stage ui_composite: the UI pixel, premultiplied r,g,b,a
  std::string cube;                  // a stage that takes a user LUT: the .cube file (any path)
  bool json = false;
};

std::string probe_stage_names();

// Reads "R G B" lines from `in` (blank lines and lines starting with '#' are skipped) and writes
// one line per input to `out`: "R G B" with 9 significant digits, or a JSON document with --json.
// Errors (bad option, bad line) name the option or the line and the valid choices. For a pipeline
// other than UE 5.5, the lines (at most kMaxProbeColours) are one row of pixels through the
// pipeline's reference for that stage (its settings from --setting), so a LUT the stage bakes is
// baked once for them all.
Status run_probe(const ProbeOptions& options, std::istream& in, std::ostream& out);

// The most colours `probe` reads for a pipeline other than UE 5.5 (one image row, 32 bytes each).
inline constexpr size_t kMaxProbeColours = size_t{1} << 22;

// The longest standard-input line `probe` and `lut apply` read.
inline constexpr size_t kMaxInputLine = 4096;

// std::getline that stops reading past `max_length` characters, so that an input without
// newlines (/dev/zero) cannot grow a line without bound: a line longer than `max_length` comes
// back with max_length + 1 characters for the caller to report. False at the end of input.
bool read_bounded_line(std::istream& in, std::string* line, size_t max_length = kMaxInputLine);

}  // namespace hdrc
