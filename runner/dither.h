// The property-based judgement of a quantisation dither (docs/diff-metrics.md, "Dither"): what a
// conformant implementation of UE's triangular grain satisfies whatever its device's sin makes of
// the hash frac(sin(u + v·543.31)·493013), judged against the undithered image and the case's
// amount (core/case.h DitherCriterion).
//
// The undithered value is the dither stage's input (the reference adds its grain to exactly that
// image: reference/ue/tonemap.cpp dither_image), the amount is the host-derived
// BackbufferQuantizationDithering (ParamBlock::dither_amount: 1/(2^bits − 1) under
// r.BackbufferQuantizationDitheringOverride, else 1/255 on an 8-bit SDR back buffer and 1/1023
// otherwise, 0 on devices 8/9; reference/ue/cpp/resolve.cpp). Both are resolved in process for
// `run` and `verify` alike, so a port is judged by the same numbers.
#pragma once

#include <array>
#include <cstddef>
#include <string>

#include "core/case.h"
#include "core/engine.h"
#include "core/image.h"
#include "runner/diff.h"

namespace hdrc {

// The variance of the triangular distribution on [-1, 1] (density 1 − |t|) is 1/6 and its
// kurtosis (fourth moment / variance²) 2.4: (1/15) / (1/36).
inline constexpr double kTriangularVariance = 1.0 / 6.0;
inline constexpr double kTriangularKurtosis = 2.4;
// A value enters the statistics only where float32 resolves its noise: one float32 spacing of
// max(|undithered|, |candidate|) (<= 2^-23 of it) at most 2^-9 of the amount, so the noise t is
// known to 2^-8 (kDitherRounding; rounding of the input, the product and the sum). Coarser values
// (scRGB or nits at 16-bit amounts) are judged by the amplitude alone.
inline constexpr double kDitherResolution = 1.0 / 512.0;  // 2^-9
inline constexpr double kDitherRounding = 1.0 / 256.0;    // 2^-8, in units of the amount
// The fewest values a statistic is judged on (a block's mean, a channel's std and histogram).
inline constexpr size_t kDitherMinValues = 64;

// One colour channel's statistics of t = (candidate − undithered) / amount.
struct DitherChannelStats {
  size_t n = 0;            // values entering the statistics (resolved: kDitherResolution)
  size_t blocks = 0;       // blocks whose mean was judged (>= kDitherMinValues values)
  double mean_z = 0;       // the largest |block mean| in sigmas, sqrt(1 / (6 n_block))
  int worst_block = -1;    // its block (raster order, block_pixels pixels each)
  bool mean_over = false;  // some block's mean over its bound
  double mean_used = 0;    // the largest |block mean| / its bound
  double std_ratio = 0;    // std(t) · sqrt(6): 1 for the triangular distribution
  double std_bound = 0;    // the allowed |std_ratio − 1|
  double ks = 0;           // Kolmogorov–Smirnov distance to the triangular CDF
  double ks_bound = 0;     // the allowed distance
  bool judged = false;     // n >= kDitherMinValues: std and histogram judged
};

struct DitherStats {
  double amount = 0;          // BackbufferQuantizationDithering of the case
  size_t values = 0;          // colour values finite on both sides
  size_t over_amplitude = 0;  // values with |d| over amount + float32 noise
  double max_amplitude = 0;   // max |d| / amount (amount 0: max |d| / its noise bound)
  // The value using most of its amplitude bound (x < 0: none).
  int worst_x = -1, worst_y = -1, worst_channel = -1;
  double worst_undithered = 0, worst_candidate = 0;
  size_t resolved = 0;  // values entering the statistics
  std::array<DitherChannelStats, 3> channel;
  bool statistics = false;  // amount > 0 and some channel judged (else the amplitude alone)
};

// The statistics of `candidate` against `undithered` for `amount` and the criterion's bounds.
// The images have the same size (checked by the caller).
DitherStats dither_stats(const Image& undithered, const Image& candidate, double amount,
                         const DitherCriterion& criterion);

// The triangular CDF on [-1, 1]: (1 + t)²/2 below 0, 1 − (1 − t)²/2 above; 0 and 1 outside.
double triangular_cdf(double t);

// Whether the candidate evaluates sin/cos/division and filtering as float32-exact, the hash
// deterministic (DevicePrecision::float32_exact): set by the device, or the reference engine, or
// the Vulkan engine on llvmpipe without a device model (whose sin is deterministic and agrees with
// the host's at 86 % of values: docs/precision.md, "Dither").
bool float32_exact_device(const DeviceInfo& d);

// Whether the tolerance's metric criteria (the exact pattern) are judged on `device`.
bool exact_pattern_judged(const DitherCriterion& c, const DeviceInfo& device);

// The verdict of a case with a dither criterion: the non-finite census as judge() does, then the
// amplitude, block means, std and histogram, then the metric criteria where the exact pattern is
// judged (exact_pattern_judged); elsewhere their outcome is reported in the reason, not judged.
Verdict judge_dither(const DiffStats& s, const DitherStats& d, const Tolerance& tol,
                     bool exact_pattern, bool pins_nonfinite);

}  // namespace hdrc
