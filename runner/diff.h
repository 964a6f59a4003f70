// Compares a candidate image with the reference image of the same case.
//
// Per pixel and channel (RGB; alpha is compared for non-finite consistency only):
//   abs  = |cand − ref|                                    (scene-linear units of the output)
//   rel  = abs / max(|ref|, rel_floor)                      (relative with a floor)
//   pq10 = |PQ(nits(cand)) − PQ(nits(ref))| · 1023, pq12 the same · 4095, where nits() maps the
//          stage's output to absolute luminance (docs/diff-metrics.md) and negative nits map to 0.
// Non-finite values are judged first: NaN vs NaN and same-sign Inf vs Inf are consistent; any
// other pairing with a non-finite value is a mismatch and fails the case before any metric.
#pragma once

#include <cstddef>
#include <string>

#include "core/case.h"
#include "core/image.h"

namespace hdrc {

// How a stage's output values map to absolute luminance (docs/diff-metrics.md): scene-linear
// values at 100 nits per unit, device signals decoded by their EOTF (SDR at a 100-nit white),
// scRGB at 80 nits per unit, LUT texels × 1.05 first.
struct OutputEncoding {
  StageId stage = StageId::kShaper;
  int device = 0;
  double inverse_gamma_z = 1.0 / 2.2;  // device 2's 1/Gamma
  double to_nits(double value) const;
  std::string describe() const;
};

struct PixelRef {
  int x = -1, y = -1, channel = -1;
  double input = 0, reference = 0, candidate = 0;
  bool valid() const { return x >= 0; }
};

struct DiffStats {
  size_t values = 0;         // pixels × 3 colour channels compared
  size_t nonfinite_ref = 0;  // NaN/Inf values in the reference (RGBA)
  size_t nonfinite_consistent = 0;
  size_t nonfinite_mismatch = 0;
  PixelRef first_mismatch;  // first non-finite mismatch in scan order
  double max_abs = 0, mean_abs = 0;
  double max_rel = 0, mean_rel = 0;
  double max_pq10 = 0, max_pq12 = 0, mean_pq10 = 0;
  PixelRef worst_rel;                  // the value with the largest rel
  PixelRef worst_pq;                   // the value with the largest pq10
  size_t over_rel = 0, over_pq10 = 0;  // values over the tolerance
};

struct Verdict {
  bool pass = false;
  std::string reason;  // one line: what failed and where, or the passing metrics
};

DiffStats diff_images(const Image& input, const Image& reference, const Image& candidate,
                      const OutputEncoding& encoding, const Tolerance& tol);

// Applies the tolerance. Written so that NaN fails: a metric passes only if `!(m > tol)` can be
// shown as `m <= tol`.
Verdict judge(const DiffStats& s, const Tolerance& tol);

// "(x, y) G: input 0.5 reference 0.49 candidate 0.48"
std::string describe_pixel(const PixelRef& p);

}  // namespace hdrc
