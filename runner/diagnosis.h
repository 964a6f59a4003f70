// Diagnosis hints for a failing case (docs/diagnosis.md): when the candidate's error matches a
// known porting mistake's signature, the verdict names it as a possible cause ("R and B swapped",
// "clamped to [0, 1] before the lookup", "a uniform scale of 1.25: 100 vs 80 nits per unit?").
// A hint is a hint: the verdict is never changed by one.
//
// The signatures (id, detector, thresholds, message, docs link) are data:
// runner/diagnosis_signatures.json, embedded at build time and read through the bounded JSON
// reader (runner/json_read.h). The detectors are the small functions of diagnosis.cpp, named by
// the signatures' "detector". Most compare the candidate with a *variant* of the reference (its
// channels permuted, re-encoded with another transfer function, scaled, offset) or with the
// reference of a variant of the case (the input saturated or with R and B swapped, the lookup
// tables sampled half a texel off), and fire when the variant explains almost all of the error.
//
// The pass runs for failing cases only (runner/run.cpp), so a passing case costs nothing; its
// work is one pass over the images per image detector, sampled on a fixed stride past
// kDiagnosisMaxPixels, plus one reference run per case-variant detector (skipped past that size).
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/case.h"
#include "core/image.h"
#include "core/output_encoding.h"
#include "core/result.h"

namespace hdrc {

// Past this many pixels the image detectors take every k-th pixel, and the case-variant
// detectors (one reference run each) are skipped.
inline constexpr size_t kDiagnosisMaxPixels = size_t{1} << 20;

struct Signature {
  std::string id;        // "channel_swap_rb": [a-z0-9_], unique
  std::string detector;  // one of diagnosis_detectors()
  std::map<std::string, double> params;
  std::string variant;  // the detector's variant, where it takes one ("saturate_input", ...)
  std::string message;  // what the hint says
  std::string docs;     // "docs/diagnosis.md#channel_swap_rb"
  // Fires only when no signature without this flag fired: a general symptom ("error grows with
  // saturation") that a specific cause (a channel swap) also shows.
  bool fallback = false;
};

struct Hint {
  std::string id, message, evidence, docs;
  // "possible cause: MESSAGE (EVIDENCE; see DOCS)": the text the reason line carries.
  std::string text() const;
};

// The detectors a signature may name, and for each its parameters (all required) and variants
// ("" when it takes none).
struct DetectorInfo {
  std::string name;
  std::vector<std::string> params;
  std::vector<std::string> variants;
  std::string what;  // one line, for the error messages and docs
};
const std::vector<DetectorInfo>& diagnosis_detectors();

// Parses and validates a signatures document (`file` names it in errors): every problem names
// the file, the JSON pointer, the value and the valid choices.
Result<std::vector<Signature>> parse_signatures(const std::string& file, const std::string& text);
// The embedded runner/diagnosis_signatures.json, parsed once (a build whose file is invalid fails
// its test, DiagnosisSignatures.EmbeddedFileIsValid).
const Result<std::vector<Signature>>& builtin_signatures();
const std::string& builtin_signatures_text();

// What a detector sees of one failing case.
struct DiagnosisInput {
  const Image* input = nullptr;  // null or another size: no input (a LUT bake's lattice is one)
  const Image* reference = nullptr;
  const Image* candidate = nullptr;
  const OutputEncoding* encoding = nullptr;
  // The case, and its reference for a changed copy of it (the case-variant detectors); either
  // null: those detectors do not run.
  const ResolvedCase* resolved = nullptr;
  std::function<Result<Image>(const ResolvedCase&)> reference_of;
};

// The hints whose signatures fire, in the signatures' order (fallbacks only when no other fired).
std::vector<Hint> diagnose(const std::vector<Signature>& signatures, const DiagnosisInput& in);

// The case variants the case-variant detectors compare with (exposed for the tests, which build
// planted mistakes from them): `variant` applied to a copy of `c`; false when it does not apply
// (no input image, no user LUT).
bool make_case_variant(const std::string& variant, ResolvedCase* c);

}  // namespace hdrc
