// ACES RRT helper functions that TonemapCommon.ush: FilmToneMap borrows from ACES.ush, restated in
// double. Source: Engine/Shaders/Private/ACES.ush (chenyong2github/UnrealEngine, 5.0-era ACES 1.3
// copy, commit 09c29cbee980f5c5fbff6c93cf6132e5f4bcf97a): rgb_2_saturation, rgb_2_yc,
// sigmoid_shaper, glow_fwd, rgb_2_hue, center_hue. They are the ACES 1.3 RRT functions
// (aces-dev ACESlib.RRT_Common.ctl / ACESlib.Utilities_Color.ctl) except that rgb_2_hue returns 0
// instead of NaN for neutral input and clamps to [0, 360].
#pragma once
//
// The helpers live once, in reference/ue/aces/aces_common.h (ACES.ush); FilmToneMap uses the same
// functions under the names it has always used here.

#include "reference/ue/aces/aces_common.h"

namespace hdrc::ref::grading::film {

using aces::center_hue;
using aces::glow_fwd;
using aces::rgb_2_hue;
using aces::rgb_2_saturation;
using aces::rgb_2_yc;
using aces::sigmoid_shaper;

}  // namespace hdrc::ref::grading::film
