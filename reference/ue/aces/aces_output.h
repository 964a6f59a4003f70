// The shader side of UE 5.5's ACES HDR output transform (devices 3–6), in double precision, fed
// with the float parameters the CPU packs (aces_params.h). Spec §5.1, §5.2; decisions D2.
//
// Sources: TonemapCommon.ush 5.5 (izzy2lost/UnrealEngineUWP, commit
// aff11acf0c218535669021f6e646b3bcf6ad94a5): ComputeACESTonemapParams, ACESOutputTransforms1000/
// 2000; ACES.ush (5.0-era copy, chenyong2github/UnrealEngine, commit
// 09c29cbee980f5c5fbff6c93cf6132e5f4bcf97a): ssts, rrt_sweeteners, compressColor, outputTransform.
// The 5.5 `outputTransform(aces, TsParams, ...)` overload is reconstructed [R]: the 5.0 body with
// the parameters given and Y_MIN = Min.y, Y_MAX = Max.y (decisions D2).
//
// Non-finite values (D3D HLSL semantics, color/d3d_math.h): any NaN or ±Inf channel in
// the AP0 input makes compressColor return NaN in every channel, and the unconditional
// lerp(aces, compressed, GamutCompression) keeps that NaN even for GamutCompression = 0
// (0·NaN = NaN); rrt_sweeteners' glow then multiplies all channels by NaN and its
// clamp(aces, 0, 65535) = min(max(NaN, 0), 65535) turns them into 0. So a pixel with any
// non-finite channel leaves as black (≤ 1e-12 nits per channel). Negative channels are clamped to
// 0 in AP0 and again in AP1 by rrt_sweeteners; the tone scale never sees a negative value.
#pragma once

#include <array>

#include "color/vec.h"
#include "reference/color/noise_range.h"
#include "reference/ue/aces/aces_params.h"

namespace hdrc::ref::aces {

// ACES.ush: TsPoint / TsParams (shader form: coefsLow/coefsHigh have 6 entries, [5] = [4], so that
// ssts's j + 2 index stays in range when knot_coord rounds up to 3).
struct TsPoint {
  double x;      // ACES (AP1, after the RRT sweeteners)
  double y;      // nits
  double slope;  // d log10(y) / d log10(x)
};

struct TsParams {
  TsPoint min, mid, max;
  std::array<double, 6> coefs_low;   // log10 nits
  std::array<double, 6> coefs_high;  // log10 nits
};

// What ssts derives from TsParams alone for every channel it maps (ACES.ush computes these inline
// each time, with the same operations): the logarithms of the knots and, per spline interval j,
// mul(coefs[j..j+2], M1) (see ssts in aces_output.cpp).
struct SplineSegment {
  double a, b, c;  // logy = t²·a + t·b + c
};
struct SstsPrecomputed {
  double min_x, mid_x, max_x;              // log10 of Min.x, Mid.x, Max.x
  double min_icpt, max_icpt;               // log10(Min.y) − Min.slope·log10(Min.x), same for Max
  std::array<SplineSegment, 4> low, high;  // mul(coefs[j..j+2], M1) of each spline, j = 0 … 3
};
SstsPrecomputed ssts_precompute(const TsParams& c);

// TonemapCommon.ush: FACESTonemapParams.
struct AcesShaderParams {
  TsParams aces_params;
  double scene_color_multiplier;
  double gamut_compression;  // already clamped to [0, 1] on the CPU
  // Not a shader parameter: ssts_precompute(aces_params), computed once by
  // compute_aces_tonemap_params instead of once per pixel.
  SstsPrecomputed ssts_pre;
};

// TonemapCommon.ush: ComputeACESTonemapParams — unpacks the shader parameters; Min.slope and
// Max.slope are 0, Mid.slope = ACESMidData.z, coefs[4] and coefs[5] both = ACESCoefs*_4.
AcesShaderParams compute_aces_tonemap_params(const AcesTonemapParams& packed);

// ACES.ush: ssts — the single-stage tone scale, per channel: ACES (AP1) → nits. Spec §5.2.
double ssts(double x, const TsParams& c);

// ACES.ush: rrt_sweeteners — glow, red modifier, clamps, AP0→AP1 (literal) and the 0.96 global
// desaturation. ACES2065-1 (AP0) in, AP1 out (finite and ≥ 0 for every input).
Vec3 rrt_sweeteners(const Vec3& aces);

// ACES.ush: compressColor — ACES 1.3 reference gamut compression in AP1 distance space, bypassed
// when max(AP1) < 1e-10 or any AP0 component is negative (UE addition). AP0 in, AP0 out.
Vec3 compress_color(const Vec3& aces);

// ACES.ush: outputTransform, TsParams overload as UE 5.5 calls it (display and limiting primaries
// ACEScg D60, EOTF 4 = linear, dark surround, STRETCH_BLACK, no D60 sim, full range):
// AP0 in, display-referred linear nits with AP1 primaries (D60 white) out, each channel in
// [0, Max.y].
Vec3 output_transform(const Vec3& aces, const TsParams& params);

// TonemapCommon.ush: ACESOutputTransforms1000 / ACESOutputTransforms2000 (identical bodies; the
// name only tells which device selected the parameters). `scene_linear` is in the working colour
// space, `wcs_to_ap0` is WorkingColorSpace.ToAP0. Returns nits, AP1 primaries.
Vec3 aces_output_transforms_1000(const Vec3& scene_linear, const Mat3& wcs_to_ap0,
                                 const AcesShaderParams& params);
Vec3 aces_output_transforms_2000(const Vec3& scene_linear, const Mat3& wcs_to_ap0,
                                 const AcesShaderParams& params);

// rrt_sweeteners' result (AP1) for ACESOutputTransforms1000/2000's input: the value outputTransform
// passes to the tone scale (ssts), per channel.
Vec3 aces_rgb_pre(const Vec3& scene_linear, const Mat3& wcs_to_ap0, const AcesShaderParams& params);

// The range of outputTransform's result (nits, AP1) for every rrt_sweeteners result in `rgb_pre`:
// the tone scale, Y_2_linCV, limit_to_primaries, the display matrix and linCV_2_Y evaluated on the
// range in exact real arithmetic (each step nondecreasing per channel or linear). The device's own
// float32 error of these steps is not in it (the caller adds it).
Range3 output_transform_tail_range(const Range3& rgb_pre, const AcesShaderParams& params);

}  // namespace hdrc::ref::aces
