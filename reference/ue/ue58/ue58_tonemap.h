// UE 5.8's Tonemap pass in double precision (pipeline "ue58", stage ue58_tonemap): steps 1-5 are
// UE 5.5's (reference/ue/tonemap.h tonemap_final_linear: fringe, sharpen, tint, exposure, bloom)
// with 5.8's vignette; then ColorLookupTable with 5.8's shaper and LUTMax into the LUT that
// ue58_combine_luts bakes; device 7's ST2084ToLinear; no scRGB conversion. What 5.8 changed:
// docs/ue58-differences.md §1b (T1-T4); decisions: docs/ue58-decisions.md G.
//
// Sources (facts only, no code copied): unicorn2022/UE5.8.0 @
// 5d9a05c15b1f8c6d7b3354b360677ce30d688149, Engine/Shaders/Private/PostProcessTonemap.usf
// (ColorLookupTable, TonemapCommonVS, TonemapCommonPS, MainCS), PostProcessCommon.ush
// (ComputeVignetteMask, VignetteSpace), Engine/Source/Runtime/Renderer/Private/PostProcess/
// PostProcessTonemap.cpp (GetTonemapperOutputDeviceParameters, AddTonemapPass, RemapPermutation).
#pragma once

#include "core/image.h"
#include "core/shader_interface.h"
#include "reference/ue/combine_luts.h"
#include "reference/ue/lut_shaper.h"
#include "reference/ue/tonemap.h"
#include "reference/ue/ue58/ue58_combine_luts.h"

namespace hdrc::ref::ue58 {

// ColorLookupTable's addressing: PQ (with the [0, 10000]-nit clamp) iff LUTShaper, else log.
LutShaper tonemap_lut_shaper(const ParamBlock& p);
// The block's VignetteType / VignetteParams0-2.
Vignette tonemap_vignette(const ParamBlock& p);

// The outer LUT as ue58_combine_luts stores it (bake_outer_lut), as the tonemapper samples it.
BakedLut baked_outer_lut(const ParamBlock& p);
// The same with an evaluator of `p` (its inner texels kept for a later device bake).
BakedLut baked_outer_lut(const CombineLuts58& luts, const ParamBlock& p);

// The pass over `scene` (the viewport is the image), `bloom` and `dirt` as UE 5.5's
// tonemap_image. RGB: OutDeviceColor = the LUT's trilinear sample · LUTMax, decoded to nits for
// device 7 (LinearEXR), unchanged otherwise (5/6 included: T1); alpha: OutLuminance =
// dot(OutDeviceColor, (0.299, 0.587, 0.114)).
Image tonemap_image(const ParamBlock& p, const Image& scene, const Image* bloom, const Image* dirt,
                    const BakedLut& lut);

}  // namespace hdrc::ref::ue58
