// PQ-space grading with an artist's .cube LUT as a pipeline module ("pq_grading"): one stage,
// pq_grade, per pixel (pq_grading.h; docs/pq_grading.md).
#include "reference/pq_grading/pq_grading_pipeline.h"

#include <cmath>
#include <string>

#include "reference/color/ue_matrices.h"
#include "reference/pipeline_support.h"
#include "reference/pq_grading/pq_grading.h"

namespace hdrc::ref::pq_grading {

namespace {

const std::vector<StageInfo>& stages() {
  static const std::vector<StageInfo> table = {
      {StageId::kOther,
       "pq_grade",
       {{"pq_grading/stages/grade.comp"}},
       "scene colour (stored in RGBA16F) x ExposureFract, saturate, PQ encode, the case's 33^3 "
       ".cube LUT sampled from its strip texture (two bilinear taps), PQ decode, / ExposureFract "
       "x Amplify, UE's FilmToneMap (HDR) or Narkowicz's ACES fit (SDR), the back buffer's "
       "encoding (PQ, scRGB, sRGB, gamma 2.2); Rec.709 primaries throughout",
       {},
       true,
       "pq_grading",
       kLutSize,
       false,
       1,
       false,
       "docs/spec/pq_grading.md#output-encoding"},
  };
  return table;
}

OutputEncoding encoding(const StageInfo&, const ParamBlock& p) {
  OutputEncoding e;
  e.to_rec2020 = standard::rgb_to_rgb(standard::kSrgb, standard::kRec2020);
  e.gamut = "Rec.709";
  switch (static_cast<BackBuffer>(p.pq_back_buffer)) {
    case BackBuffer::kR10G10B10A2:
      e.transfer = OutputEncoding::Transfer::kPq;
      e.nits_scale = 1.0;
      e.transfer_name = "PQ (ST 2084) of display nits";
      break;
    case BackBuffer::kRgba16f:
      e.transfer = OutputEncoding::Transfer::kLinear;
      e.nits_scale = kScRgbWhiteNits;
      e.transfer_name = "scRGB linear (1.0 = 80 nits)";
      break;
    case BackBuffer::kSrgb8:
      e.transfer = OutputEncoding::Transfer::kSrgb;
      e.nits_scale = kSdrWhiteNits;
      e.transfer_name = "sRGB-encoded as stored (1.0 = 100 nits)";
      break;
    case BackBuffer::kRgb8:
      e.transfer = OutputEncoding::Transfer::kGamma;
      e.gamma = kRgb8Gamma;
      e.nits_scale = kSdrWhiteNits;
      e.transfer_name = "gamma 2.2 (1.0 = 100 nits)";
      break;
  }
  return e;
}

Result<Image> reference(const ResolvedCase& c, bool analytic_lut) {
  if (c.user_luts[0].data.empty() || c.params.user_lut_size < 2 ||
      c.user_luts[0].width != c.params.user_lut_size * c.params.user_lut_size ||
      c.user_luts[0].height != c.params.user_lut_size)
    return Error{c.spec.file, "/lut",
                 "pq_grade needs the case's user LUT (a strip N^2 x N for user_lut_size N)",
                 "\"lut\": a 33^3 .cube under cases/"};
  const StripLut lut = strip_lut(c.user_luts[0], c.params);
  const LutEval eval = analytic_lut ? LutEval::kTrilinear : LutEval::kStrip;
  Image out(c.input.width, c.input.height);
  for (size_t i = 0; i < c.input.pixel_count(); ++i) {
    const double* in = &c.input.data[i * Image::kChannels];
    const Trace t = grade(c.params, lut, {in[0], in[1], in[2]}, eval);
    double* o = &out.data[i * Image::kChannels];
    o[0] = t.out[0];
    o[1] = t.out[1];
    o[2] = t.out[2];
    o[3] = in[3];  // alpha passes through (grade.comp)
    if (c.device_allowances && !analytic_lut) {
      const Range3 r = grade_device_range(c.params, lut, {in[0], in[1], in[2]}, c.device);
      AdmissibleRange a;
      a.pixel = i;
      for (int ch = 0; ch < 3; ++ch) {
        a.lo[ch] = r.lo[ch];
        a.hi[ch] = r.hi[ch];
        if (r.nan[ch] || std::isnan(o[ch])) a.nan_ok |= uint8_t(1u << ch);
      }
      a.lo[3] = a.hi[3] = in[3];
      if (std::isnan(in[3])) a.nan_ok |= uint8_t(1u << 3);
      out.device_admissible.push_back(a);
    }
  }
  if (c.device_allowances && !analytic_lut) {
    out.device_allowances = {
        "filter weights (" + std::to_string(c.device.sub_texel_bits) + " sub-texel bits)",
        "shader arithmetic (the Vulkan precision table's bounds)",
        "shader noise (kShaderNoise of the display mapping, kFloat32Noise of the LUT coordinate)"};
    if (!c.device.fp16_rte) out.device_allowances.push_back("RGBA16F rounding (either neighbour)");
  }
  return out;
}

// Pipeline::named_values: docs/spec/pq_grading.md's rows of each colour, the strip unpacked once
// (none without the case's user LUT: `reference` reports that error).
std::vector<std::vector<NamedValue>> named_values_of(const ResolvedCase& c,
                                                     const std::vector<Vec3>& colours) {
  std::vector<std::vector<NamedValue>> out;
  if (c.user_luts[0].data.empty()) return out;
  const StripLut lut = strip_lut(c.user_luts[0], c.params);
  out.reserve(colours.size());
  for (const Vec3& colour : colours) out.push_back(named_values(c.params, lut, colour));
  return out;
}

}  // namespace

const Pipeline& pq_grading_pipeline() {
  static const Pipeline pipeline{
      "pq_grading",
      "PQ-space grading with a .cube LUT",
      "docs/spec/pq_grading.md",
      "scene colour -> PQ -> an artist's 33^3 .cube (strip texture) -> display mapping (UE's "
      "FilmToneMap or Narkowicz's ACES fit) -> the back buffer's encoding",
      &stages,
      &no_cvars,
      &pq_grading_setting_table,
      &pq_grading_setting_choices,
      &resolve_from_settings<&derive_pq_grading>,
      &no_lattice,
      &encoding,
      &reference,
      // Measured per pixel, 2048x2048 minus 256x256, lavapipe (runner/budget.h).
      245,
      3400,
      &named_values_of,
      // Each stage's seconds per case, fitted to a default-suite run (2026-11-27, --images all,
      // -j 2, lavapipe; bench/shard_balance.py fit; docs/performance-notes.md, "Shard balance"):
      // µs per case, per pixel, per baked LUT texel.
      {{"pq_grade", 848, 1.61, 0}},
  };
  return pipeline;
}

}  // namespace hdrc::ref::pq_grading
