// Device allowances for UE 5.5's VisualizeHDR stage (reference/ue/visualize/visualize_hdr.h): the
// range of each output channel a conformant Vulkan device may produce running the GLSL port
// (gpu/shaders/stages/visualize_histogram.comp, visualize_hdr.comp; lib/visualize_*.glsl) in
// float32, derived from the bounds of the Vulkan precision table
// (reference/color/spirv_precision.h; Vulkan spec, "Precision and Operation of SPIR-V
// Instructions") step by step, the way the shader computes each value. docs/precision.md, "Device
// allowances", "VisualizeHDR".
//
// What each output pixel's range is made of:
//  * the tonemapped scene: the Tonemap pass's device range (tonemap_image's device overload),
//    carried through every step that follows as the shader writes it (the panel frame's three
//    lerps run over every pixel outside the meters: lerp(border, rgb, 1) = border + 1·(rgb −
//    border) is not exactly rgb in float32);
//  * the histogram pass's numbers: every bucket's 13.19 fixed-point sum over the pixels' splat
//    weights, each pixel's position carried from its colour through
//    CalculateEyeAdaptationLuminance, log2 and the position's multiply-add in interval arithmetic
//    (a position range that crosses an integer moves weight between buckets; trunc is
//    nondecreasing); the bucket values, their max and the outlier-free average over those sums; the
//    exposure lines' positions;
//  * the comparisons that place panel elements (region tint u < pos_min, the bar top
//    histogram/max ≥ 1 − v, the three lines |inset_x − px| < 2 or 3, debug type 1's percentile
//    bands): both outcomes are admissible exactly where the compared values' ranges straddle the
//    threshold; elsewhere the reference's outcome is the only one;
//  * the overlay FilmToneMap(EyeAdaptationResult · L(u)): L(u)'s exp2 and division bounds, then
//    FilmToneMap at the ends of its (grey) input range widened by kShaderNoise × the largest
//    channel (the documented allowance for a stage's float32 ACES/FilmToneMap arithmetic,
//    reference/color/noise_range.h), then the mask saturate(1 − 100·|mapped − (1 − v)|);
//  * each lerp a + t·(b − a) over ranges of a, b, t: multilinear, so its extremes lie at the
//    corners, plus the three roundings (0.5 ULP each at the largest magnitudes; a fused
//    multiply-add only removes one).
// Integer and exact-float decisions (the meter regions, the panel's rect distance in integers, the
// bar's integer bucket, y > top + 9) are the reference's.
#pragma once

#include <vector>

#include "core/image.h"
#include "reference/color/spirv_precision.h"
#include "reference/ue/visualize/visualize_hdr.h"

namespace hdrc::ref::visualize {

struct VisualizeDeviceInputs {
  const VisualizeHdrInputs* in = nullptr;  // the reference's inputs (scene = the tight tonemapped)
  const Image* reference = nullptr;        // visualize_hdr's output image
  // The Tonemap pass's device ranges over `in->scene_color` (pixel order); a pixel without one is
  // its point value.
  const std::vector<AdmissibleRange>* scene_ranges = nullptr;
  double exposure = 1.0;      // P.exposure as the parameter block holds it (Exposure/PreExposure)
  double pre_exposure = 1.0;  // P.pre_exposure
};

// HLSL lerp a + t·(b − a) over ranges of a, b and t as a device may evaluate it: the exact
// extremes at the corners, widened by the subtraction's, the product's and the sum's 0.5 ULP.
spirv::Interval lerp_range(spirv::Interval a, spirv::Interval b, spirv::Interval t);
// sqrt(n), n > 0, as inherited from 1.0 / inversesqrt(n) (2 ULP, then OpFDiv's 2.5 ULP).
spirv::Interval sqrt_range(double n);

// Every pixel whose device range admits more than its reference value, each range containing the
// reference value.
std::vector<AdmissibleRange> visualize_hdr_device_ranges(const VisualizeDeviceInputs& d);

}  // namespace hdrc::ref::visualize
