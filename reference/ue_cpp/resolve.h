// From cvars to the parameters the shaders receive, as UE 5.5's C++ computes them
// (PostProcessTonemap.cpp: GetTonemapperOutputDeviceParameters, PostProcessCombineLUTs.cpp,
// SceneManagement.cpp: FDefaultWorkingColorSpaceUniformBuffer). Both engines get the result.
#pragma once

#include "core/case.h"
#include "core/result.h"
#include "reference/color/ue_matrices.h"

namespace hdrc::ref {

// The working colour space of every case unless it names another (UE's default project setting).
const Chromaticities& default_working_chromaticities();

// Resolves the case's cvars for an image of `width` × `height`. The error names the cvar.
Result<ParamBlock> resolve_params(const Case& c, int width, int height);

}  // namespace hdrc::ref
