// The classic tone-mapping operators as a pipeline module ("operators", core/pipeline.h): one
// stage, the chosen operator applied per pixel to a scene-linear Rec.709 image (operators.h).
#include "reference/operators/operators_pipeline.h"

#include <cmath>

#include "reference/color/noise_range.h"
#include "reference/color/ue_matrices.h"
#include "reference/operators/operators.h"
#include "reference/operators/operators_settings.h"
#include "reference/pipeline_support.h"

namespace hdrc::ref::operators {

namespace {

const std::vector<StageInfo>& operators_stages() {
  static const std::vector<StageInfo> table = {
      {StageId::kOther,
       "tone_curve",
       {{"operators/stages/curve.comp"}},
       "a classic tone-mapping operator per pixel (Reinhard, Reinhard with white point, Uncharted "
       "2 "
       "/ Hable, Narkowicz's ACES fit, Unity's Neutral, UE's FilmToneMap presets) after the "
       "exposure Key / AdaptedLuminance; scene-linear Rec.709 in, display-linear Rec.709 out",
       {},
       true,
       "operators",
       0,
       false,
       1,
       false,
       "docs/spec/operators.md#output-encoding"},
  };
  return table;
}

// Display-linear Rec.709: 1.0 is SDR white, 100 nits.
OutputEncoding encoding(const StageInfo&, const ParamBlock&) {
  return linear_rec709_encoding("display-linear x 100 nits");
}

// One pixel's device range (docs/precision.md, "Device allowances"): the per-channel operators
// step by step (operator_channel_device_range); UeFilmic (the matrices and FilmToneMap's
// log10/exp/pow, film_tonemap.glsl unchanged) kShaderNoise of the pixel's largest |channel|
// around the reference, the documented allowance for a stage's float32 arithmetic
// (reference/color/noise_range.h; as pq_grading's display mapping), then max(·, 0). Each range
// holds the reference's value; a pixel without one keeps the tight bounds.
void add_device_range(const ParamBlock& p, size_t pixel, const double* in, const double* ref,
                      std::vector<AdmissibleRange>* ranges) {
  AdmissibleRange a;
  a.pixel = pixel;
  if (static_cast<Operator>(p.op_operator) == Operator::kUeFilmic) {
    double big = 0;
    for (int ch = 0; ch < 3; ++ch) {
      if (!std::isfinite(ref[ch])) return;
      big = std::fmax(big, std::fabs(ref[ch]));
    }
    for (int ch = 0; ch < 3; ++ch) {
      a.lo[ch] = std::fmax(ref[ch] - kShaderNoise * big, 0.0);
      a.hi[ch] = ref[ch] + kShaderNoise * big;
    }
  } else {
    for (int ch = 0; ch < 3; ++ch) {
      spirv::Interval r;
      if (!std::isfinite(ref[ch]) || !operator_channel_device_range(p, in[ch], &r)) return;
      a.lo[ch] = std::fmin(r.lo, ref[ch]);
      a.hi[ch] = std::fmax(r.hi, ref[ch]);
    }
  }
  a.lo[3] = a.hi[3] = in[3];
  if (std::isnan(in[3])) a.nan_ok |= uint8_t(1u << 3);
  ranges->push_back(a);
}

Result<Image> reference(const ResolvedCase& c, bool /*analytic_lut: no LUT*/) {
  Image out(c.input.width, c.input.height);
  for (size_t i = 0; i < c.input.pixel_count(); ++i) {
    const double* in = &c.input.data[i * Image::kChannels];
    const Vec3 rgb = apply_operator(c.params, {in[0], in[1], in[2]});
    double* o = &out.data[i * Image::kChannels];
    o[0] = rgb[0];
    o[1] = rgb[1];
    o[2] = rgb[2];
    o[3] = in[3];  // alpha passes through (curve.comp)
    if (c.device_allowances) add_device_range(c.params, i, in, o, &out.device_admissible);
  }
  if (c.device_allowances)
    out.device_allowances = {"shader arithmetic (the Vulkan precision table's bounds)"};
  return out;
}

// Pipeline::named_values: docs/spec/operators.md's rows of each colour.
std::vector<std::vector<NamedValue>> named_values_of(const ResolvedCase& c,
                                                     const std::vector<Vec3>& colours) {
  std::vector<std::vector<NamedValue>> out;
  out.reserve(colours.size());
  for (const Vec3& colour : colours) out.push_back(named_values(c.params, colour));
  return out;
}

}  // namespace

const Pipeline& operators_pipeline() {
  static const Pipeline pipeline{
      "operators",
      "Classic tone-mapping operators",
      "docs/spec/operators.md",
      "Reinhard, Uncharted 2 / Hable, Narkowicz's ACES fit, Unity's Neutral and UE's FilmToneMap "
      "presets, one definition each, shared by the other pipelines",
      &operators_stages,
      &no_cvars,
      &operators_setting_table,
      &operators_setting_choices,
      &resolve_from_settings<&derive_operators>,
      &no_lattice,
      &encoding,
      &reference,
      // Measured per pixel, 2048x2048 minus 256x256, lavapipe (runner/budget.h).
      255,
      2500,
      &named_values_of,
      // Each stage's seconds per case, fitted to a default-suite run (2026-11-27, --images all,
      // -j 2, lavapipe; bench/shard_balance.py fit; docs/performance-notes.md, "Shard balance"):
      // µs per case, per pixel, per baked LUT texel.
      {{"tone_curve", 928, 0.903, 0}},
  };
  return pipeline;
}

}  // namespace hdrc::ref::operators
