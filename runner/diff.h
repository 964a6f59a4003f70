// Compares a candidate image with the reference image of the same case (docs/diff-metrics.md).
//
// Every output is first decoded to absolute luminance (nits) in a known gamut (OutputEncoding):
// PQ signals by the ST 2084 EOTF, SDR signals by their EOTF at a 100-nit reference white, scRGB at
// 80 nits per unit, scene-linear values at 100 nits per unit (UE's LinearToNitsScale).
//
// Per pixel and colour channel (RGB; alpha is judged for non-finite consistency only):
//   linear_abs = |cand − ref|                               (the output's own units)
//   linear_rel = linear_abs / max(|ref|, rel_floor)          (+Inf over a zero denominator)
//   pq_code10  = |PQ(max(nits(cand), f)) − PQ(max(nits(ref), f))| · 1023, pq_code12 the same
//                · 4095, with f = kSignBoundaryNoise · the pixel's largest |nits| (float32 noise)
// Per pixel: delta_e_itp = ΔE_ITP of ITU-R BT.2124 between the two colours, each converted to
// BT.2020 RGB in nits and to ICtCp (BT.2100). ≈ 1 is a just-noticeable difference.
//
// Non-finite values are judged first: NaN vs NaN and same-sign Inf vs Inf are consistent (OCIO's
// GPU tests and idiff agree on this); any other pairing with a non-finite value is a mismatch and
// fails the case before any metric. Numeric metrics cover the values finite on both sides.
#pragma once

#include <array>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "core/case.h"
#include "core/image.h"
#include "core/output_encoding.h"
#include "core/shader_interface.h"
#include "color/vec.h"

namespace hdrc {

// Luminance bands, by the reference pixel's luminance Y (nits): below 0.1, 0.1–1, 1–10, 10–100,
// 100–1000, 1000 and above. A band shows where an error lives ("fails only above 1000 nits").
inline constexpr int kBandCount = 6;
const char* band_name(int band);  // "<0.1", "0.1-1", ..., ">=1000" (nits)
int band_of_nits(double nits);    // NaN and negative: band 0

// One value of an image pair.
struct PixelRef {
  int x = -1, y = -1, channel = -1;  // channel 0–3 = R, G, B, A
  double input = 0, reference = 0, candidate = 0;
  int band = -1;  // the reference pixel's luminance band
  bool valid() const { return x >= 0; }
  // The whole pixel, for messages (describe_pixel): RGB of each image, the pixel's ΔE_ITP (NaN
  // when not finite on both sides), and for a LUT (combine_luts: N² × N, texel (r, g, b) at
  // (r + N·b, g)) its edge N, so the message names the lattice point (0: not a LUT).
  std::array<double, 3> input_rgb{}, reference_rgb{}, candidate_rgb{};
  double delta_e_itp = std::numeric_limits<double>::quiet_NaN();
  int lut_size = 0;
};

// Statistics of one metric over a set of values (all, or one band).
struct MetricStats {
  size_t count = 0;  // values (pixels for delta_e_itp)
  double max = 0, mean = 0, rms = 0;
  double p99 = 0, p999 = 0;        // nearest-rank percentiles
  size_t over = 0;                 // values over the tolerance's max
  double fraction_over = 0;        // over / count
  double at_allowed_fraction = 0;  // the value that the allowed fraction of values may exceed
                                   // (nearest rank 1 − allowed_fraction; = max when it is 0)
  PixelRef worst;                  // where max is (delta_e_itp: the channel differing most)
};

// Counts of special values on each side (RGBA), and how many non-finite pairs agree.
struct NonFiniteCensus {
  struct Side {
    size_t nan = 0, pos_inf = 0, neg_inf = 0, negative = 0;  // negative: finite values < 0
  };
  Side reference, candidate;
  size_t consistent = 0;  // NaN/NaN or same-sign Inf pairs
  size_t mismatch = 0;    // any other pair involving a non-finite value
  PixelRef first_mismatch;
  // NaN on one side, on the other a colour value within float32 noise of zero (|nits| <
  // kSignBoundaryNoise x the pixel's largest |nits|): the NaN of an encoding of a value whose sign
  // float32 noise decides (docs/diff-metrics.md, "Sign boundary"). Judged consistent, counted
  // here, never in the numeric metrics.
  size_t sign_boundary = 0;
  PixelRef first_sign_boundary;
  // The rule that made the reference's value non-finite at first_mismatch, where the reference
  // knows it ("LinearToST2084 of a negative value: pow of a negative base is NaN"); "" otherwise.
  std::string rule;
};

// The float32 noise bound of a pixel, relative to its largest |nits|: 2^-20, 16 float32 ulps
// (2^-24). It bounds the sign-boundary rule and is the PQ metric's floor.
inline constexpr double kSignBoundaryNoise = kFloat32Noise;  // core/image.h

struct DiffStats {
  size_t pixels = 0;  // pixels compared
  size_t values = 0;  // colour values finite on both sides
  NonFiniteCensus nonfinite;
  // Reference values replaced by the nearest value of their admissible range (core/image.h,
  // AdmissibleRange) because the candidate's lay elsewhere in it; the first such pixel.
  size_t admissible = 0;
  PixelRef first_admissible;
  std::array<MetricStats, kMetricCount> metric;
  std::array<std::array<MetricStats, kMetricCount>, kBandCount> band;
  std::array<size_t, kBandCount> band_pixels{};
  // The worst value overall: of the metric using most of its budget (or linear_rel when no
  // metric has a max), with `worst_metric` naming it.
  PixelRef worst;
  Metric worst_metric = Metric::kLinearRel;

  std::array<double, kMetricCount> over_limit{};  // the max each `over` was counted against
  const MetricStats& operator[](Metric m) const { return metric[static_cast<int>(m)]; }
  // Kept for report/html_report.cpp (reads these three names).
  double max_rel = 0, max_pq10 = 0;
  PixelRef worst_rel;
};

// One pixel of the reference resolved against its admissible range: per channel the candidate's
// value clamped into [lo, hi], NaN where the candidate is NaN and NaN is admissible, else the
// reference's own value. Writes 4 values to `out`; returns how many differ from the reference's.
size_t resolve_admissible(const AdmissibleRange& range, const double* reference,
                          const double* candidate, double* out);

// The images must have the same size (checked by the caller). Where the reference has admissible
// ranges, the candidate is compared with resolve_admissible's values.
DiffStats diff_images(const Image& input, const Image& reference, const Image& candidate,
                      const OutputEncoding& encoding, const Tolerance& tol);

struct Verdict {
  bool pass = false;
  bool error = false;                 // not judgeable (nothing compared): an ERROR, not a FAIL
  std::string reason;                 // one line: what failed and where, or the passing metrics
  std::vector<std::string> warnings;  // one line per metric over its warn level
  // Passed with every metric that has a max under 10 % of it (for an allowed fraction: the value
  // at that fraction): the tolerance could be tightened.
  bool could_be_tightened = false;
  double budget_used = 0;  // budget_used(stats, tol), failing cases included
};

// The share of the tolerance used, the one figure results.json and the report show: over every
// metric with a max, observed / max (with an allowed fraction: the value that fraction may
// exceed / max) and, where a hard cap is set, max / hard. Under 1 when every limit holds, over 1
// when one fails; kNotJudged (+inf) for a non-finite mismatch or NaN statistics.
double budget_used(const DiffStats& s, const Tolerance& tol);

// Applies the tolerance: non-finite mismatches first, then per metric the hard cap and the
// allowed fraction over max. Written so that NaN fails (`!(m <= tol)`). A case in which no finite
// value was compared is an ERROR ("nothing compared") unless it `pins_nonfinite` (Case): then the
// census judges it, and it needs at least one non-finite value to pin.
Verdict judge(const DiffStats& s, const Tolerance& tol, bool pins_nonfinite = false);

// "(517, 0) G, 10-100 nits: input 0.5 reference 0.49 candidate 0.48; pixel RGB input (…)
// reference (…) candidate (…), ΔE_ITP 0.31". A LUT texel is named by its lattice point:
// "lattice (r 6, g 0, b 1) = pixel (22, 0) G, …".
std::string describe_pixel(const PixelRef& p);

// Why the reference is non-finite at `p` for `stage`/`device`, where UE's rule is known from the
// input (NaN in, PQ of a negative or +Inf, a device encode of a negative); "" when not known.
std::string nonfinite_rule(StageId stage, int device, const PixelRef& p);

// BT.2100 ICtCp of a BT.2020 RGB colour in nits (PQ variant), and BT.2124's ΔE_ITP.
ref::Vec3 ictcp_from_rec2020_nits(const ref::Vec3& rgb_nits);
// The same with `pq(nits)` for the PQ non-linearity of each LMS component (the diff's: black for
// NaN and negatives, capped at 10 000 nits): ictcp_from_rec2020_nits is this with that function,
// and the report passes a cache of it (report/images.cpp), the same numbers.
template <class Pq>
ref::Vec3 ictcp_from_rec2020_nits_with(const ref::Vec3& rgb, Pq&& pq) {
  // ITU-R BT.2100-2 Table 7: LMS from BT.2020 RGB, the PQ non-linearity (inverse EOTF on
  // absolute luminance) per component, then I, Ct, Cp. The integer/4096 forms are the standard's.
  const ref::Mat3 kRgbToLms{{1688.0 / 4096, 2146.0 / 4096, 262.0 / 4096,  //
                             683.0 / 4096, 2951.0 / 4096, 462.0 / 4096,   //
                             99.0 / 4096, 309.0 / 4096, 3688.0 / 4096}};
  const ref::Vec3 lms = kRgbToLms * rgb;
  const ref::Vec3 p{pq(lms[0]), pq(lms[1]), pq(lms[2])};
  return {0.5 * p[0] + 0.5 * p[1], (6610.0 * p[0] - 13613.0 * p[1] + 7003.0 * p[2]) / 4096.0,
          (17933.0 * p[0] - 17390.0 * p[1] - 543.0 * p[2]) / 4096.0};
}
double delta_e_itp(const ref::Vec3& ictcp_a, const ref::Vec3& ictcp_b);

}  // namespace hdrc
