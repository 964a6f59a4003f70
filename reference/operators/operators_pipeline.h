// The classic tone-mapping operators' pipeline module ("operators").
#pragma once

#include "core/pipeline.h"

namespace hdrc::ref::operators {

const Pipeline& operators_pipeline();

}  // namespace hdrc::ref::operators
