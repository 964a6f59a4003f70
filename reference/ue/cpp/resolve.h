// From cvars and settings to the parameters the shaders receive, as UE 5.5's C++ computes them:
// PostProcessTonemap.cpp: GetTonemapperOutputDeviceParameters, PostProcessCombineLUTs.cpp
// (FCombineLUTParameters, GetMappingPolynomial), RenderCore.cpp: HDRConfigureCVars /
// ConfigureACESTonemapParams, UnrealEngine.cpp: HDRSettingChangedSinkCallback (the 0 → 1000 rule),
// SceneManagement.cpp: FDefaultWorkingColorSpaceUniformBuffer. Both engines get the result.
#pragma once

#include <string>

#include "core/case.h"
#include "core/pipeline.h"
#include "core/result.h"
#include "reference/color/ue_matrices.h"

namespace hdrc::ref {

// The working colour space of every case unless it names another (UE's default project setting).
const Chromaticities& default_working_chromaticities();

// The working colour space the settings choose: WorkingColorSpace (a preset 1–6, or 7 Custom with
// WorkingColorSpaceRedGreen / WorkingColorSpaceBlueWhite), built as UE's CPU builds it. Errors:
// chromaticities given with a preset, degenerate custom chromaticities.
Result<WorkingColorSpace> working_color_space_of(const SettingValues& st);

// Resolves the case's cvars and settings for an image of `width` × `height`.
Result<Resolution> resolve(const Case& c, int width, int height);

// Kept for the stages that need only the block.
Result<ParamBlock> resolve_params(const Case& c, int width, int height);

// Halton(index, base), the radical inverse used for the dither grain offset.
double halton(int index, int base);

}  // namespace hdrc::ref
