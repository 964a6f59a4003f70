// The pipeline stages a case can name. Each stage belongs to one pipeline (core/pipeline.h) and is
// an ordered list of compute passes on the GPU side (docs/gpu-interface.md) and one function of its
// pipeline's reference. Stage names are unique across pipelines (a test checks it), so a stage name
// alone (results.json, tolerance files) names its pipeline too.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace hdrc {

// The UE family's stages (reference/ue/), which its engines dispatch on; kOther for every other
// pipeline's.
enum class StageId {
  kShaper,        // LUT shaper encode → clamp (sampler addressing) → CombineLUTs decode
  kLinearDevice,  // shaper round trip, then device 7 or 8 encode and the tonemapper's decode
  kCombineLuts,   // the baked LUT itself (stored, quantised texels), laid out N² × N
  kTonemap,       // the Tonemap pass up to the per-device post conversion (no dither)
  kDither,        // the quantisation dither added to the input image
  kUiComposite,   // the HDR UI composite over a back-buffer image (the `ui_overlay` stimulus)
  kVisualizeHdr,  // VisualizeHDR over an HDR scene colour image
  kOther,         // a stage of another pipeline: everything about it comes from its pipeline
};

// How many invocations a pass is dispatched over (1-D, in workgroups of kLocalSizeX).
enum class Dispatch {
  kPixels,     // width × height: one invocation per pixel of the case's input image
  kLutTexels,  // N³ (N = r.LUT.Size): one invocation per LUT texel, r fastest, then g, then b
  kOneGroup,   // a single workgroup (kLocalSizeX invocations), e.g. a reduction into scratch
};

// One compute pass of a stage.
struct StagePass {
  std::string_view shader;  // compute shader, relative to the shader directory
  Dispatch domain = Dispatch::kPixels;
  // true: the pass's out_px (binding 2) is the scratch buffer instead of the stage's output, so
  // scratch_px[0, width·height) holds its image for the passes after it.
  bool output_to_scratch = false;
};

struct StageInfo {
  StageId id;                          // the UE family's stages; kOther for every other pipeline's
  std::string_view name;               // the name cases use
  std::vector<StagePass> passes;       // GPU passes, run in order in one submission
  std::string_view description;        // one line, with the spec sections it implements
  std::vector<int> devices;            // output devices the stage is defined for
  bool takes_input = true;             // false: the output does not depend on an input image
  std::string_view pipeline = "ue55";  // the pipeline it belongs to (core/pipeline.h)
  // The user LUT a case may name ("lut", docs/cases.md): 0 none allowed; -1 required, any
  // LUT_3D_SIZE; N > 0 required, LUT_3D_SIZE exactly N.
  int user_lut = 0;
  // A case may name none even so (user_lut != 0): UE's CombineLUTs without a ColorGradingLUT.
  bool user_lut_optional = false;
  // How many LUTs the stage binds at once (binding kBindingUserLut is an array of kUserLutSlots,
  // docs/gpu-interface.md): 1, or up to kUserLutSlots for a stage whose pipeline blends several
  // (UE's CombineLUTs: Textures_1..4); more than one comes from a case's "lut_blend" list.
  int user_lut_slots = 1;
  // The texels the engines bind: false RGBA32F (the .cube's floats), true 8-bit UNORM (the host
  // rounds each value once to the nearest k/255, as UE's ColorLookupTable texture group stores
  // BGRA8; both engines see those values).
  bool user_lut_unorm8 = false;
  // Another pipeline's stage (kOther): the docs section that defines its stored value, which
  // params.json's output.formula names ("docs/spec/pq_grading.md#output-encoding"); "": the
  // pipeline's `sources` page. UE 5.5's stages name their UE function instead (runner/export.cpp).
  std::string_view output_spec = "";
  // The Tonemap pass of a UE version: a case may give "bloom" and "bloom_dirt" images, which the
  // engines bind as aux0 / aux1 (docs/gpu-interface.md).
  bool bloom_inputs = false;
};

// The pass shaders of `stage` that do not exist under `shader_dir` (empty: the stage has a complete
// GPU implementation there).
std::vector<std::string> missing_shaders(const StageInfo& stage, const std::string& shader_dir);

// The file under `shader_dir` that implements pass shader `shader` ("stages/X.comp"): the shader
// itself, or, when it is absent and "stages/X.hlsl" exists, that HLSL port of it
// (docs/gpu-interface.md, "HLSL"). Relative to `shader_dir`.
std::string pass_shader_file(const std::string& shader_dir, std::string_view shader);

// A stage of any pipeline by name (reference/pipelines.cpp, over every pipeline's table), or
// nullptr.
const StageInfo* find_stage(std::string_view name);
std::string stage_names();  // every pipeline's: "shaper, linear_device, ..."

}  // namespace hdrc
