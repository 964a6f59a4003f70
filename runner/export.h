// `hdrconform export`: everything another engine needs to render the suite's cases, as files.
//
// Layout (the same under `export --out DIR` and under `verify --out DIR`, which exports each case
// before running a candidate command on it):
//   DIR/manifest.json                 {"tool", "cases": [{"id", "stage", "dir", "degenerate"}]}
//   DIR/cases/<case id>/params.json   the case: stage and passes, cvars, settings, the input files,
//                                     the output expected (size, encoding) and "params": every
//                                     ParamBlock field by name, derived values included (ACES
//                                     coefficients, matrices, InverseGamma, ...)
//   DIR/cases/<case id>/input.exr     the input image (float32 RGBA)
//   DIR/cases/<case id>/{ui,bloom,bloom_dirt}.exr   the stage's other images, when it has them
// README.md ("Verifying a port") describes how a port uses these files.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/case.h"
#include "core/result.h"
#include "core/shader_interface.h"
#include "runner/diff.h"

namespace hdrc {

// Every ParamBlock field `pipeline`'s cases carry (param_carried_by: UE 5.5's fields and the
// pipeline's own) by name: I → integer, F → number, V4 → [4 numbers], M3 → [[3], [3], [3]] (rows).
// Numbers are written so they read back to the same double.
nlohmann::ordered_json params_json(const ParamBlock& p, std::string_view pipeline = "ue55");
// The inverse; every field `pipeline` carries must be present, the others keep their block
// defaults. Errors name `file` and the JSON pointer.
Result<ParamBlock> params_from_json(const nlohmann::ordered_json& j, const std::string& file,
                                    const std::string& pointer, std::string_view pipeline = "ue55");

// params.json's format version: a port checks it (2: "storage", "resolved" and the full
// "output" block; runner/params.schema.json describes it, docs/candidate-protocol.md explains it).
inline constexpr int kExportFormatVersion = 3;

// The params.json document of a resolved case (image file names relative to its folder, case_file
// relative to the cases folder the case was loaded from). A pipeline other than UE 5.5 carries only
// what applies to it: "resolved" (UE's cvar resolution) is null, "storage" is null unless the
// pipeline stores a LUT of its own (lut_size), "params" holds its fields and the UE fields it reads
// (param_carried_by), and output.formula names the docs section that defines the stored value.
nlohmann::ordered_json case_export_json(const ResolvedCase& rc);

// Writes params.json and the case's images into `dir` (each atomically).
Status export_case(const ResolvedCase& rc, const std::string& dir);

// A case read back from an export folder: what a port (e.g. examples/) starts from.
Result<ResolvedCase> load_exported_case(const std::string& params_path);

struct ExportSummary {
  size_t cases = 0, degenerate = 0;
  std::vector<Error> errors;  // cases that could not be resolved or written
};
// Exports `cases` into `out_dir` and writes its manifest.json.
ExportSummary export_cases(const std::vector<Case>& cases, const std::string& out_dir);

}  // namespace hdrc
