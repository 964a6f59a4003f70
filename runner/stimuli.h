// Procedural, deterministic input images. Values are scene-linear in the working colour space,
// where 1.0 is 100 nits on the PQ shaper's scale (TonemapCommon.ush LinearToNitsScale).
#pragma once

#include <string>
#include <string_view>

#include "core/image.h"
#include "core/result.h"

namespace hdrc {

struct StimulusInfo {
  std::string_view name;
  int default_width, default_height;
  std::string_view description;
};

const std::vector<StimulusInfo>& stimulus_table();
const StimulusInfo* find_stimulus(std::string_view name);
std::string stimulus_names();

// Rows of every stimulus cycle through four colourings of the row's value v:
// (v, v, v), (v, 0, 0), (0, v, 0), (0, 0, v).
Result<Image> make_stimulus(std::string_view name, int width, int height);

}  // namespace hdrc
