#include "reference/reference_engine.h"

#include "reference/color/ue_matrices.h"
#include "reference/lut_shaper.h"
#include "reference/tonemap.h"

namespace hdrc::ref {

namespace {

Vec3 shaper_round_trip(const ParamBlock& p, const Vec3& x) {
  Vec3 out;
  for (int c = 0; c < 3; ++c) {
    const double e = d3d::clamp_address(lut_encode(p.output_device, x[c]));
    out[c] = lut_decode(p.output_device, e);
  }
  return out;
}

// PostProcessCombineLUTs.usf device branches 7/8 (spec §4.12) followed by the tonemapper's post
// conversion (PostProcessTonemap.usf, spec §6.1 step 9). Grading is identity in this stage: the
// decoded lattice value is the GradedColor.
Vec3 linear_device(const ParamBlock& p, const Vec3& graded) {
  if (p.output_device == 8) return graded;  // HDR_LinearNoToneCurve: working colour space as is
  // HDR_LinearEXR: LinearToST2084(AP1_2_Output · ToAP1 · GradedColor) stored; the tonemapper
  // decodes it with ST2084ToLinear. PQ treats the value as nits, so the pair is an identity on
  // non-negative values and NaN on negative ones (pow of a negative base).
  const Vec3 out_gamut = p.ap1_to_output * (p.wcs_to_ap1 * graded);
  Vec3 out;
  for (int c = 0; c < 3; ++c) {
    const double v = out_gamut[c];
    const double stored = (std::isnan(v) || v < 0.0) ? d3d::kNaN : st2084::pq_from_nits(v);
    out[c] = st2084::nits_from_pq(stored);
  }
  return out;
}

}  // namespace

Vec3 run_pixel(StageId stage, const ParamBlock& p, const Vec3& rgb) {
  switch (stage) {
    case StageId::kShaper:
      return shaper_round_trip(p, rgb);
    case StageId::kLinearDevice:
      return linear_device(p, shaper_round_trip(p, rgb));
    case StageId::kCombineLuts:
    case StageId::kTonemap:
    case StageId::kDither:
      break;  // whole-image stages: see ReferenceEngine::run
  }
  return rgb;
}

Image lut_image(const BakedLut& lut) {
  const int n = lut.size;
  Image out(n * n, n);
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) {
        double* o = out.px(r + n * b, g);
        const Vec3& t = lut.at(r, g, b);
        o[0] = t[0];
        o[1] = t[1];
        o[2] = t[2];
        o[3] = 0.0;  // CombineLUTs writes alpha 0
      }
  return out;
}

DeviceInfo ReferenceEngine::device() const {
  return {"reference", "cpu (IEEE double)", "hdrconform reference", "-"};
}

Result<Image> ReferenceEngine::run(const ResolvedCase& c) {
  switch (c.spec.stage->id) {
    case StageId::kCombineLuts:
      return lut_image(bake_lut(c.params));
    case StageId::kTonemap: {
      const BakedLut lut = bake_lut(c.params);
      return tonemap_image(c.params, c.input, nullptr, &lut);
    }
    case StageId::kDither:
      return dither_image(c.params, c.input);
    default:
      break;
  }
  Image out(c.input.width, c.input.height);
  for (size_t i = 0; i < c.input.pixel_count(); ++i) {
    const double* in = &c.input.data[i * 4];
    const Vec3 rgb = run_pixel(c.spec.stage->id, c.params, {in[0], in[1], in[2]});
    double* o = &out.data[i * 4];
    o[0] = rgb[0];
    o[1] = rgb[1];
    o[2] = rgb[2];
    o[3] = in[3];  // alpha passes through
  }
  return out;
}

}  // namespace hdrc::ref
