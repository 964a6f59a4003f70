// UE 5.5's pipeline module ("ue55"), the default pipeline of every case.
#pragma once

#include "core/pipeline.h"

namespace hdrc::ref {

const Pipeline& ue55_pipeline();

}  // namespace hdrc::ref
