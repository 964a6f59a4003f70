// A pipeline: one engine's HDR output path (UE 5.5's, Unity URP's colour grading, the classic tone
// operators), verified as a module. A pipeline owns its parameter tables, its stages and passes,
// its host derivation (parameters -> the shader parameter block, computed once as the engine's own
// C++/C# does), its double-precision reference, its GLSL shaders (named by its stages' passes), its
// cases (cases/<pipeline>/ for every pipeline but UE 5.5, whose case ids predate pipelines) and a
// docs page naming its sources of truth. The runner, diff, tolerance policy, export/verify, goldens
// and report reach a pipeline only through this interface (docs/pipelines.md: adding one).
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "core/case.h"
#include "core/cvars.h"
#include "core/image.h"
#include "core/named_value.h"
#include "core/output_encoding.h"
#include "core/result.h"
#include "core/settings.h"
#include "core/stage.h"

namespace hdrc {

// The host derivation's result: the parameter block both engines read, and why the pipeline's own
// parameters are degenerate for this combination ("" when they are not; such a case is reported
// DEGENERATE, never evaluated).
struct Resolution {
  ParamBlock params;
  std::string degenerate;
  // The LUTs bound at kBindingUserLut, slot by slot (null: a dummy). All null: the case's own
  // "lut" (if any) in slot 0, the default for a pipeline that binds one LUT.
  std::array<std::shared_ptr<const UserLut>, kUserLutSlots> user_luts{};
};

// What one case of a stage costs in a `run`, measured (bench/shard_balance.py fits it from a
// results.json's per-case seconds: reference, candidate and diff): the estimate `--shard` balances
// with when it has no recorded timings (runner/run.cpp, static_case_cost). Only the ratios between
// cases matter, so the figures are the measuring machine's microseconds.
struct StageCost {
  std::string_view stage;       // a stage of the pipeline (StageInfo::name)
  double us = 0;                // per case: engine dispatch, buffers, a user LUT's upload
  double us_per_pixel = 0;      // per pixel of the case's image (a LUT bake's: its N² x N lattice)
  double us_per_lut_texel = 0;  // per texel of the N³ LUT a stage bakes before its pixel passes
};

struct Pipeline {
  std::string_view name;         // "ue55": what cases, --pipeline and results.json use
  std::string_view title;        // "Unreal Engine 5.5 HDR output"
  std::string_view sources;      // the docs page naming its sources of truth
  std::string_view description;  // one line
  const std::vector<StageInfo>& (*stages)();
  // Console variables (UE's r.* cvars); an empty table when the pipeline has none.
  const std::vector<CvarInfo>& (*cvars)();
  // Settings (UE's post-process settings, Unity's volume parameters, ...) and their named values.
  const std::vector<SettingInfo>& (*settings)();
  SettingChoicesFn setting_choices;
  // The host derivation for an input of width x height.
  Result<Resolution> (*resolve)(const Case& c, int width, int height);
  // The "input" of a stage that takes none (a LUT bake): the lattice coordinate of LUT texel
  // (r, g, b) for the resolved parameters; the image is N^2 x N with texel (r, g, b) at (r + N b,
  // g).
  std::array<double, 3> (*lattice)(const ParamBlock& p, int r, int g, int b);
  // How `stage`'s outputs map to nits and BT.2020 for the resolved parameters.
  OutputEncoding (*output_encoding)(const StageInfo& stage, const ParamBlock& p);
  // The double-precision reference: the stage's output for the resolved case. analytic_lut: where
  // the pipeline bakes a LUT, evaluate the grade at each pixel instead of sampling the baked LUT
  // (`verify --reference analytic`).
  Result<Image> (*reference)(const ResolvedCase& c, bool analytic_lut);
  // What a case of this pipeline costs per pixel of its image, measured (runner/budget.h, which
  // estimates a case from them before any work; docs/performance-notes.md): peak resident bytes
  // and CPU nanoseconds. 0: not measured yet (the budget takes the dearest measured figures).
  double bytes_per_pixel = 0;
  double cpu_ns_per_pixel = 0;
  // The named intermediate values (docs/spec/<name>.md's worked-pixel rows) of each colour through
  // the resolved case's stage, one list per colour, from the reference's own stage functions; the
  // "out" value is what `reference` gives for that colour. A LUT the stage bakes is baked once for
  // all of them. `hdrconform probe --json` prints them. Null: the pipeline names none.
  std::vector<std::vector<NamedValue>> (*named_values)(
      const ResolvedCase& c, const std::vector<std::array<double, 3>>& colours) = nullptr;
  // Each stage's measured cost per case (StageCost); a stage not listed takes the dearest measured
  // figures of every pipeline (stage_cost).
  std::vector<StageCost> stage_costs = {};

  // A fresh settings set of this pipeline (its table and named values; unset values read as their
  // defaults).
  SettingValues new_settings() const { return SettingValues(&settings(), setting_choices); }
};

// Every pipeline, UE 5.5's first (reference/pipelines.cpp).
const std::vector<const Pipeline*>& pipeline_table();
const Pipeline* find_pipeline(std::string_view name);
const Pipeline& default_pipeline();                   // ue55
const Pipeline& pipeline_of(const StageInfo& stage);  // the pipeline that owns `stage`
std::string pipeline_names();                         // "ue55, unity_urp, operators"

// The stage called `name` in `pipeline`, or nullptr.
const StageInfo* find_stage(const Pipeline& pipeline, std::string_view name);
// "shaper, linear_device, ..." of one pipeline.
std::string stage_names(const Pipeline& pipeline);

// The measured cost of `stage` (its pipeline's stage_costs); for a stage not measured yet, the
// dearest of every measured figure (an estimate that errs on the costly side).
StageCost stage_cost(const StageInfo& stage);

// The output encoding of `stage` for the resolved parameters (its pipeline's).
OutputEncoding output_encoding(const StageInfo& stage, const ParamBlock& p);

}  // namespace hdrc
