// Unity URP's colour grading as a pipeline module ("unity_urp", core/pipeline.h): the internal LUT
// bake (LutBuilderHdr / LutBuilderLdr) and the uber pass's ApplyColorGrading
// (docs/spec/unity_urp.md, docs/unity_urp.md).
#include "reference/unity_urp/unity_urp_pipeline.h"

#include <cmath>
#include <string>

#include "reference/color/ue_matrices.h"
#include "reference/pipeline_support.h"
#include "reference/unity_urp/unity_urp.h"
#include "reference/unity_urp/unity_urp_settings.h"

namespace hdrc::ref::unity_urp {

namespace {

const std::vector<StageInfo>& unity_urp_stages() {
  static const std::vector<StageInfo> table = {
      {StageId::kOther,
       "lut_bake",
       {{"unity_urp/stages/lut_bake.comp", Dispatch::kLutTexels}},
       "the internal colour grading LUT as stored (LutBuilderHdr: LogC lattice, ColorGrade, tone "
       "map, RGBA16F; LutBuilderLdr: linear lattice, ColorGrade, saturate, RGBA8), H^2 x H strip "
       "with texel (r, g, b) at (r + H b, g)",
       {},
       false,
       "unity_urp"},
      {StageId::kOther,
       "color_grading",
       {{"unity_urp/stages/lut_bake.comp", Dispatch::kLutTexels},
        {"unity_urp/stages/color_grading.comp"}},
       "the uber pass's ApplyColorGrading (Common.hlsl): post exposure, then HDR grading: "
       "ApplyLut2D of saturate(LinearToLogC(x)); LDR grading: the tone map, saturate, ApplyLut2D; "
       "scene-linear Rec.709 in, linear Rec.709 out before the display encode",
       {},
       true,
       "unity_urp"},
  };
  return table;
}

std::array<double, 3> lattice(const ParamBlock& p, int r, int g, int b) {
  const Vec3 v = lattice_code(p.lut_size, r, g, b);
  return {v[0], v[1], v[2]};
}

// Both stages output linear Rec.709 (the LUT's texels are what the final pass adds to the frame
// before its display encode): 1.0 is SDR white, 100 nits.
OutputEncoding encoding(const StageInfo& stage, const ParamBlock&) {
  return linear_rec709_encoding(stage.name == "lut_bake" ? "texel, linear x 100 nits"
                                                         : "linear x 100 nits");
}

// analytic_lut: Unity's LUT is always baked (the strip is a stage of its own); both modes sample
// it.
Result<Image> reference(const ResolvedCase& c, bool /*analytic_lut*/) {
  const bool bake = c.spec.stage->name == "lut_bake";
  Image out = bake ? bake_lut_strip(c.params) : grade_image(c.input, c.params);
  if (!c.device_allowances) return out;
  // Device allowances: the texels' ranges (the bake stage's own output), or ApplyColorGrading's
  // range per pixel over them.
  const StripRange bounds = bake_lut_strip_device_range(c.params, c.device);
  // The weight box is the specification's: each axis's fraction and each tap's weight on the
  // sub-texel grid (strip_device_range.h, snap_weights; docs/precision.md, "Filter arithmetic").
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      const double* o = out.px(x, y);
      Range3 r;
      if (bake) {
        for (int ch = 0; ch < 3; ++ch) {
          r.lo[ch] = bounds.lo.px(x, y)[ch];
          r.hi[ch] = bounds.hi.px(x, y)[ch];
        }
      } else {
        const double* in = c.input.px(x, y);
        r = apply_color_grading_device_range(bounds, c.params, {in[0], in[1], in[2]},
                                             c.device.sub_texel_bits);
      }
      r.include({o[0], o[1], o[2]});
      // Alpha: 1 in the bake, the input's in the grade.
      out.device_admissible.push_back(
          to_admissible(static_cast<size_t>(y) * out.width + x, r, o[3], o[3], std::isnan(o[3])));
    }
  out.device_allowances = {
      "LUT storage rounding (either neighbour)",
      grades_in_aces(c.params)
          ? "shader noise (kFloat32Noise of the bake and the LUT coordinate)"
          : "shader arithmetic (the bake's grade in interval arithmetic on Vulkan's float32 "
            "bounds, kFloat32Noise of the LUT coordinate)"};
  if (!bake)
    out.device_allowances.insert(
        out.device_allowances.begin(),
        "filter weights (" + std::to_string(c.device.sub_texel_bits) + " sub-texel bits)");
  return out;
}

// Pipeline::named_values: docs/spec/unity_urp.md's lookup rows (§9) of each colour through
// ApplyColorGrading, on the strip baked once.
std::vector<std::vector<NamedValue>> named_values_of(const ResolvedCase& c,
                                                     const std::vector<Vec3>& colours) {
  const Image strip = bake_lut_strip(c.params);
  std::vector<std::vector<NamedValue>> out;
  out.reserve(colours.size());
  for (const Vec3& colour : colours) out.push_back(named_values(c.params, strip, colour));
  return out;
}

}  // namespace

const Pipeline& unity_urp_pipeline() {
  static const Pipeline pipeline{
      "unity_urp",
      "Unity URP colour grading",
      "docs/spec/unity_urp.md",
      "URP's internal colour grading LUT (HDR and LDR grading, tone mapping None / Neutral / ACES, "
      "LUT sizes 16-65) and its application in the uber pass, from Unity-Technologies/Graphics",
      &unity_urp_stages,
      &no_cvars,
      &unity_urp_setting_table,
      &unity_urp_setting_choices,
      &resolve_from_settings<&derive_unity_urp>,
      &lattice,
      &encoding,
      &reference,
      // Measured per pixel, 2048x2048 minus 256x256, lavapipe (runner/budget.h).
      235,
      2450,
      &named_values_of,
      // Each stage's seconds per case, fitted to a default-suite run (2026-11-27, --images all,
      // -j 2, lavapipe; bench/shard_balance.py fit; docs/performance-notes.md, "Shard balance"):
      // µs per case, per pixel, per baked LUT texel.
      {{"lut_bake", 1052, 1.42, 0}, {"color_grading", 2766, 0, 0.617}},
  };
  return pipeline;
}

}  // namespace hdrc::ref::unity_urp
