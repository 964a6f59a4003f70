// UE 5.5's pipeline module ("ue55"), the default pipeline of every case.
#pragma once

#include <vector>

#include "core/pipeline.h"
#include "core/stage.h"

namespace hdrc::ref {

const Pipeline& ue55_pipeline();

// Its stages (ue55_stages.cpp).
const std::vector<StageInfo>& ue55_stage_table();

}  // namespace hdrc::ref
