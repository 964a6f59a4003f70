// The pipeline stages a case can name. Each stage is one compute shader on the GPU side and one
// function on the reference side.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace hdrc {

enum class StageId {
  kShaper,        // LUT shaper encode → clamp (sampler addressing) → CombineLUTs decode
  kLinearDevice,  // shaper round trip, then device 7 or 8 encode and the tonemapper's decode
  kCombineLuts,   // the baked LUT itself (stored, quantised texels), laid out N² × N
  kTonemap,       // the Tonemap pass up to the per-device post conversion (no dither)
  kDither,        // the quantisation dither added to the input image
  kUiComposite,   // the HDR UI composite over a back-buffer image (the `ui_overlay` stimulus)
  kVisualizeHdr,  // VisualizeHDR over an HDR scene colour image
};

struct StageInfo {
  StageId id;
  std::string_view name;         // the name cases use
  std::string_view shader;       // compute shader, relative to the shader directory; "" = none
                                 // yet (its cases are listed in cases/known_limits.json)
  std::string_view description;  // one line, with the spec sections it implements
  std::vector<int> devices;      // output devices the stage is defined for
  bool takes_input = true;       // false: the output does not depend on an input image
};

const std::vector<StageInfo>& stage_table();
const StageInfo* find_stage(std::string_view name);
std::string stage_names();  // "shaper, linear_device"

}  // namespace hdrc
