// A conformance case after loading: what to run, with which cvars, on which input, judged how.
#pragma once

#include <array>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/cvars.h"
#include "core/device_precision.h"
#include "core/image.h"
#include "core/settings.h"
#include "core/shader_interface.h"
#include "core/stage.h"

namespace hdrc {

// The metrics a tolerance can judge (runner/diff.h computes them; docs/diff-metrics.md).
enum class Metric : int {
  kLinearAbs,  // |cand − ref| per value, in the output's own units
  kLinearRel,  // |cand − ref| / max(|ref|, rel_floor) per value
  kPqCode10,   // |PQ(nits(cand)) − PQ(nits(ref))| in 10-bit code values, per value
  kPqCode12,   // the same in 12-bit code values
  kDeltaEItp,  // ΔE_ITP (ITU-R BT.2124) per pixel; ≈ 1 is a just-noticeable difference
};
inline constexpr int kMetricCount = 5;
// A limit that is not set: the criterion is not judged.
inline constexpr double kNotJudged = std::numeric_limits<double>::infinity();

// The property-based judgement of a quantisation dither (docs/diff-metrics.md, "Dither"): the
// candidate's noise d = candidate − undithered (the stage's input; the amount is the case's
// BackbufferQuantizationDithering, ParamBlock::dither_amount) must look like UE's triangular grain,
// whatever hash the device's sin produces. t = d / amount is triangular on [-1, 1] (variance 1/6).
//   * amplitude: every value |d| <= amount (plus float32 noise);
//   * mean: over each block of >= block_pixels pixels (raster order) and channel, |mean t| <=
//     mean_sigmas · sqrt(1 / (6 n));
//   * std: per channel |std(t) · sqrt(6) − 1| <= std_sigmas · sqrt((kurtosis − 1) / (4 n)),
//     the triangular distribution's kurtosis 2.4;
//   * histogram: per channel the Kolmogorov–Smirnov distance to the triangular CDF <= ks_c /
//     sqrt(n).
// The metric criteria of the same tolerance judge the exact pattern (the reference's own grain);
// `exact_pattern` says where: "always"; "float32_exact" (only on a candidate whose
// DevicePrecision::float32_exact is set; elsewhere they are reported, not judged); "never" (the
// properties alone, as on a device whose hash differs: a port whose grain is meant to differ, and
// the planted-defect tests on lavapipe).
struct DitherCriterion {
  bool judged = false;  // false: no dither criterion (the metrics alone judge)
  double mean_sigmas = 5.5;
  int block_pixels = 256;
  double std_sigmas = 5;
  double ks_c = 3.75;
  std::string exact_pattern = "float32_exact";
  std::string reason;  // why these bounds (required when given)
};

// Diff thresholds of one case: a policy read from data (runner/tolerance.h parses it;
// docs/tolerances.md). Criteria combine: the case fails when any judged criterion fails.
// Per metric m:
//   * max(m): a value over it is "over"; the case fails when more than allowed_fraction[m] of the
//     values (pixels for ΔE_ITP) are over (0: none may be);
//   * hard[m]: a cap no value may exceed, whatever the fraction;
//   * warn[m]: a passing case with any value over it passes with a warning.
// Every comparison is written so that NaN fails.
struct Tolerance {
  double linear_abs = kNotJudged;                       // max(kLinearAbs)
  double linear_rel = kNotJudged;                       // max(kLinearRel)
  double pq_code10 = kNotJudged;                        // max(kPqCode10)
  double pq_code12 = kNotJudged;                        // max(kPqCode12)
  double delta_e_itp = kNotJudged;                      // max(kDeltaEItp)
  double rel_floor = 0.0;                               // floor of the relative error's denominator
  std::array<double, kMetricCount> allowed_fraction{};  // in [0, 1]
  std::array<double, kMetricCount> hard{kNotJudged, kNotJudged, kNotJudged, kNotJudged, kNotJudged};
  std::array<double, kMetricCount> warn{kNotJudged, kNotJudged, kNotJudged, kNotJudged, kNotJudged};
  // The PQ metrics' near-black floor (nits; 0: none, docs/tolerances.md "The near-black floor"):
  // in a pixel whose ΔE_ITP and every channel's linear error pass their max, each channel is
  // evaluated by PQ no lower than this many nits.
  double pq_near_black = 0.0;
  DitherCriterion dither;  // the dither stage's properties (not judged unless set)
  std::string reason;      // why these numbers (measured error and its cause)
  std::string source;      // where they came from: "cases/x.json: /tolerance" or "default", and
                           // every overlay applied after it
  double max(Metric m) const;
  double& max(Metric m);
  // True when any criterion of `m` is set.
  bool judged(Metric m) const;
};

inline double& Tolerance::max(Metric m) {
  switch (m) {
    case Metric::kLinearAbs:
      return linear_abs;
    case Metric::kLinearRel:
      return linear_rel;
    case Metric::kPqCode10:
      return pq_code10;
    case Metric::kPqCode12:
      return pq_code12;
    case Metric::kDeltaEItp:
      break;
  }
  return delta_e_itp;
}
inline double Tolerance::max(Metric m) const {
  return const_cast<Tolerance*>(this)->max(m);
}
inline bool Tolerance::judged(Metric m) const {
  const int i = static_cast<int>(m);
  return max(m) < kNotJudged || hard[i] < kNotJudged || warn[i] < kNotJudged;
}

// Where a case's input image comes from.
struct InputSpec {
  std::string stimulus;  // a procedural stimulus name, or "" when `file` is set
  std::string file;      // an image under cases/ (resolved path), or ""
  int width = 0;
  int height = 0;
  // The stimulus' parameters by name (runner/stimuli.h: a number is a one-element list, a choice
  // its index); unset parameters take their defaults.
  std::map<std::string, std::vector<double>> params;
  std::string label;  // the name the case id uses for this input
  std::string describe() const;
};

// A 3-D LUT a case names (`"lut"` or a `"luts"` matrix dimension: a .cube file under cases/,
// docs/cases.md), as the loader read it (core/cube): the file's one 3-D table and its domain. Both
// engines receive it as the strip texture of ResolvedCase::user_lut and P.user_lut_*; shared by
// every case a matrix expands from one file.
struct UserLut {
  std::string file;   // resolved path of the .cube
  std::string name;   // the path as the case file names it, relative to cases/
  std::string label;  // the name case ids use for it: the file's stem
  std::string title;  // its TITLE ("" when none)
  int size = 0;       // LUT_3D_SIZE N
  std::array<float, 3> domain_min{0.f, 0.f, 0.f};  // DOMAIN_MIN (or LUT_3D_INPUT_RANGE's min)
  std::array<float, 3> domain_max{1.f, 1.f, 1.f};  // DOMAIN_MAX
  std::vector<std::array<float, 3>> table;         // N^3 rows: red fastest, then green, then blue
};

// The texture both engines bind for a user LUT: the strip N^2 x N of `hdrconform lut convert --to
// strip` (docs/cube-workflow.md), table row (r, g, b) at texel (r + N b, g), alpha 1.
Image user_lut_strip(const UserLut& lut);

// A value as an 8-bit UNORM texel holds it (UE's BGRA8 ColorLookupTable textures): NaN → 0,
// clamped to [0, 1], rounded to the nearest k/255 (ties to even), returned as k/255.
double unorm8_value(double v);

// One further post-process source's LUT for UE's blend (`"lut_blend"`, docs/cases.md): a LerpTo
// of `lut` at weight `weight` (in [0, 1]), after the case's own "lut" at ColorGradingIntensity.
struct LutBlendStep {
  std::shared_ptr<const UserLut> lut;
  double weight = 0.0;
};

struct Case {
  std::string id;    // stable, readable: "linear_device/dev7_gamut2_log_ramp"
  std::string file;  // the case file it came from
  // The same file relative to the cases folder it was loaded from ("lut/devices.json"): what an
  // export names, so a params.json carries no path of the machine that wrote it.
  std::string file_in_cases;
  const StageInfo* stage = nullptr;
  CvarValues cvars;
  SettingValues settings;  // post-process and view settings (UE defaults when unset)
  InputSpec input;
  InputSpec bloom;       // tonemap: the bloom texture (stimulus "" and file "": no bloom)
  InputSpec bloom_dirt;  // tonemap: the bloom dirt mask texture (empty: none)
  // A UI composite stage's UI layer (stimulus "": the ui_overlay stimulus at its defaults).
  InputSpec ui;
  // The user LUT (null: none); only for a stage whose StageInfo::user_lut allows one.
  std::shared_ptr<const UserLut> lut;
  // Further LUTs blended in order (only for a stage with StageInfo::user_lut_slots > 1).
  std::vector<LutBlendStep> lut_blend;
  Tolerance tolerance;
  // Non-empty (the reason) when the case pins UE's non-finite behaviour itself: it may compare no
  // finite value and is judged by the non-finite census (docs/diff-metrics.md). Any other case
  // that compares no finite value is an ERROR, never a PASS.
  std::string pins_nonfinite;
  // The suite tier the case belongs to: "quick" (the default suite) or "exhaustive" (only in
  // `--suite exhaustive`, which runs both tiers; docs/cases.md).
  std::string tier = "quick";
};

// A case with everything an engine needs: the host-derived parameters and the input pixels.
struct ResolvedCase {
  Case spec;
  ParamBlock params;
  Image input;
  Image ui;  // ui_composite: the UI layer (premultiplied, sRGB-encoded), same size as `input`
  Image bloom, bloom_dirt;  // tonemap: bloom and dirt mask textures (empty when not given)
  // The user LUTs' strip textures bound at kBindingUserLut, slot by slot (user_lut_strip of the
  // LUTs the host derivation put there: Resolution::user_luts; empty where none); their size and
  // the first one's domain are P.user_lut_size / user_lut_domain_min / _max.
  std::array<Image, kUserLutSlots> user_luts;
  bool has_user_lut() const { return !user_luts[0].data.empty(); }
  // Non-empty when UE computes degenerate parameters for this combination (e.g. an ACES device
  // while MaxLuminance resolves to 0): the case is reported as DEGENERATE, never evaluated as a
  // pass.
  std::string degenerate;
  // The precision properties of the device the candidate runs on, from which the reference derives
  // the device allowances (Image::device_admissible) when `device_allowances` is set (runner: by
  // default; `--no-device-allowance` turns them off). docs/precision.md, "Device allowances".
  DevicePrecision device;
  bool device_allowances = false;
};

}  // namespace hdrc
