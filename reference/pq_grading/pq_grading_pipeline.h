// PQ-space grading with a .cube LUT as a pipeline module ("pq_grading", core/pipeline.h).
#pragma once

#include "core/pipeline.h"

namespace hdrc::ref::pq_grading {

const Pipeline& pq_grading_pipeline();

}  // namespace hdrc::ref::pq_grading
