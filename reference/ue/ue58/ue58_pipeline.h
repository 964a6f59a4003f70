// UE 5.8's HDR output pipeline ("ue58"), first stage: CombineLUTs with its inner LUT
// (docs/ue58-decisions.md E).
#pragma once

#include <vector>

#include "core/pipeline.h"

namespace hdrc::ref::ue58 {

const Pipeline& ue58_pipeline();
// Its settings: UE 5.5's (without LUTLayout) and 5.8's own.
const std::vector<SettingInfo>& ue58_setting_table();

}  // namespace hdrc::ref::ue58
