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
#include "reference/ue/aces/aces_params.h"

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

// RenderCore.cpp ConfigureACESTonemapParams (float32 as UE) for a display peak of `max_luminance`
// nits with the r.HDR.Display.Min/MidLuminance and r.HDR.Aces.* cvars, its packed values written
// to p's ACES 1.3 fields (aces_min_max, aces_mid, aces_coefs_*); the scene colour multiplier and
// gamut compression fields are the caller's. Shared by UE 5.5 and 5.8 (whose ACES 1.3 is 5.5's).
// The result's status says whether the luminances are degenerate.
aces::AcesConfigured configure_aces13(const CvarValues& cv, double max_luminance, ParamBlock* p);

// Halton(index, base), the radical inverse used for the dither grain offset.
double halton(int index, int base);

}  // namespace hdrc::ref
