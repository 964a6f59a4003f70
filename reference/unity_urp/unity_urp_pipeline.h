// Unity URP colour grading's pipeline module ("unity_urp").
#pragma once

#include "core/pipeline.h"

namespace hdrc::ref::unity_urp {

const Pipeline& unity_urp_pipeline();

}  // namespace hdrc::ref::unity_urp
