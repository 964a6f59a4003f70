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

#include <vector>

#include "core/image.h"
#include "core/shader_interface.h"
#include "reference/ue/combine_luts.h"
#include "reference/ue/lut_shaper.h"
#include "reference/ue/tonemap.h"
#include "reference/ue/ue58/ue58_combine_luts.h"

namespace hdrc::ref::ue58 {

// ColorLookupTable's addressing: PQ (with the [0, 10000]-nit clamp) iff LUTShaper, else log.
LutShaper tonemap_lut_shaper(const ParamBlock& p);
// The block's VignetteType / VignetteParams0-2, USE_VIGNETTE_TEXTURE and the VignetteTexture.
Vignette tonemap_vignette(const ParamBlock& p);

// The Texture vignette's texture (FPostProcessSettings::VignetteTexture), the red channel a UNORM8
// texture stores (k/255), row-major, row 0 at V 0. `which` is the setting VignetteTexture:
// 0 none, for which AddTonemapPass binds GSystemTextures' white dummy (1 x 1, value 1); two
// generated stimuli: 1 Radial, 16 x 16, saturate(1 − d²) with d the texel centre's distance
// from the texture's centre in units of half its width (0 beyond the inscribed circle); 2 Ramp,
// 16 x 8, 0.1 + 0.9 · x' · (0.25 + 0.75 · y') with x', y' the texel centre in [0, 1] (rising to
// the right and down the rows: a mirrored or transposed read changes it).
struct VignetteTextureImage {
  int width = 1, height = 1;
  std::vector<double> texels{1.0};
};
VignetteTextureImage vignette_texture_stimulus(int which);

// The Texture branch's mask per channel on a conformant device (`use_texture` set, Intensity > 0):
// the bilinear sample's range with `sub_texel_bits` (linear_tap_boxes on each axis with the
// shader coordinate's float32 noise, filter_taps in the UNORM8 texture's filtering precision),
// through lerp(1, sample, Intensity) and lerp(Colour, 1, Weight). False when the pixel does not
// take the Texture branch.
bool vignette_texture_device_range(const Vignette& v, double pos_x, double pos_y, double aspect,
                                   int sub_texel_bits, Vec3* lo, Vec3* hi);

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

// The outer LUT as a conformant device with precision `device` may store it, as the tonemapper
// samples it: the texels of baked_outer_lut and per texel bake_outer_lut_device's range (flags:
// kAmbiguous, the NaN bits), for sample_lut_device_range.
BakedLut baked_outer_lut_device(const CombineLuts58& luts, const ParamBlock& p,
                                const DevicePrecision& device);

// The same pass, and with `device_lut` (baked_outer_lut_device of `p`) the device allowances too
// (Image::device_admissible), as UE 5.5's pass derives them (reference/ue/tonemap.h
// tonemap_device_range): the lookup of the device LUT's ranges through the hardware filter with
// `sub_texel_bits` (filter_taps) at the shader's coordinate (its encode's noise), × LUTMax, then
// device 7's PQ decode on the device (pq_decode_on_device); devices 5/6 unchanged (T1).
Image tonemap_image(const ParamBlock& p, const Image& scene, const Image* bloom, const Image* dirt,
                    const BakedLut& lut, const BakedLut* device_lut, int sub_texel_bits);

}  // namespace hdrc::ref::ue58
