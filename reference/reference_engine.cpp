#include "reference/reference_engine.h"

#include <algorithm>
#include <optional>

#include "reference/color/ue_matrices.h"
#include "reference/ue/grading/film_tonemap.h"
#include "reference/ue/lut_cache.h"
#include "reference/ue/lut_shaper.h"
#include "reference/ue/tonemap.h"
#include "reference/ue/ue_pixel_device.h"
#include "reference/ue/ui/composite.h"
#include "reference/ue/visualize/histogram.h"
#include "reference/ue/visualize/visualize_hdr.h"
#include "reference/ue/visualize_device.h"

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

// PostProcessCombineLUTs.usf device branches 7/8 (docs/spec/ue55.md §4.12) followed by the
// tonemapper's post conversion (PostProcessTonemap.usf, docs/spec/ue55.md §6.1 step 9). Grading is
// identity in this stage: the decoded lattice value is the GradedColor.
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
    case StageId::kUiComposite:
    case StageId::kVisualizeHdr:
    case StageId::kOther:
      break;  // whole-image stages (run_ue55) and other pipelines' stages
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
  if (!lut.has_ranges()) return out;
  // The texels float32 cannot decide, in the image's pixel order (row g, column r + N·b).
  for (int g = 0; g < n; ++g)
    for (int b = 0; b < n; ++b)
      for (int r = 0; r < n; ++r) {
        const size_t i = lut.index(r, g, b);
        if (!(lut.flags[i] & BakedLut::kAmbiguous)) continue;
        AdmissibleRange a;
        a.pixel = static_cast<size_t>(g) * out.width + r + static_cast<size_t>(n) * b;
        for (int c = 0; c < 3; ++c) {
          a.lo[c] = lut.lo[i][c];
          a.hi[c] = lut.hi[i][c];
        }
        a.nan_ok = lut.flags[i] & 0x7;
        out.admissible.push_back(a);
      }
  return out;
}

ui::UiCompositeParams ui_composite_params(const ParamBlock& p) {
  ui::UiCompositeParams u;
  u.ui_level = p.ui_level;
  u.ui_luminance = p.ui_luminance;
  u.composite_mode = p.ui_composite_mode;
  u.output_device = p.output_device;
  u.cvd.type = static_cast<ui::CvdType>(p.cvd_type);
  u.cvd.severity = p.cvd_severity;
  u.cvd.correct = p.cvd_correct != 0;
  u.cvd.show_correction_with_deficiency = p.cvd_show_correction != 0;
  return u;
}

visualize::EyeAdaptationParameters eye_adaptation_parameters(const ParamBlock& p) {
  auto settings = visualize::default_settings(true);
  settings.visualize_debug_type = p.visualize_debug_type;
  return visualize::compute_eye_adaptation_parameters(settings);
}

Result<Image> ui_composite_stage(const ParamBlock& p, const Image& back_buffer,
                                 const Image& ui_layer) {
  const ui::UiCompositeParams u = ui_composite_params(p);
  return ui::composite_ui(back_buffer, ui_layer, u);
}

namespace {

// The Tonemap pass with UE's baked LUT (or, analytic_lut, CombineLUTs per pixel). A small image
// bakes only the texels it reads (LazyBakedLut, bit-identical); a large one bakes the whole LUT
// through the process-wide cache, shared with the cases of the same parameters.
Image baked_tonemap_image(const ParamBlock& p, const Image& scene, const Image* bloom,
                          const Image* dirt, bool analytic_lut) {
  if (analytic_lut) return tonemap_image(p, scene, bloom, dirt, nullptr);
  if (lazy_bake_pays(p, scene.pixel_count())) {
    LazyBakedLut lazy(p);
    return tonemap_image(p, scene, bloom, dirt, nullptr, &lazy);
  }
  return tonemap_image(p, scene, bloom, dirt, cached_bake_lut(p).get());
}

// VisualizeHDR's inputs over `hdr_scene` and its tonemapped image (which must outlive them).
visualize::VisualizeHdrInputs visualize_inputs(const ParamBlock& p, const Image& hdr_scene,
                                               const Image& tonemapped) {
  visualize::VisualizeHdrInputs in;
  in.params = eye_adaptation_parameters(p);
  in.scene_color = &tonemapped;
  in.hdr_scene_color = &hdr_scene;
  in.one_over_pre_exposure = 1.0 / p.pre_exposure;
  in.histogram = visualize::build_histogram(hdr_scene, in.params, in.one_over_pre_exposure);
  // EyeAdaptationBuffer[0].x holds the plain exposure (PostProcessVisualizeHDR.usf MainPS reads
  // it as EyeAdaptationResult; the Tonemap pass reads the same entry and applies
  // OneOverPreExposure on its own). p.exposure is Exposure / PreExposure (resolve.cpp).
  in.eye.exposure = p.exposure * p.pre_exposure;
  in.eye.exposure_bias_only = 1.0;
  in.eye.average_scene_luminance =
      visualize::average_luminance_without_outliers(in.histogram, in.params);
  // The overlay's tone curve: FilmToneMap with the view's film settings, fed a grey in AP1
  // (docs/ue55-decisions.md D9).
  const grading::FilmParams film{p.film_slope, p.film_toe, p.film_shoulder, p.film_black_clip,
                                 p.film_white_clip};
  in.tone_curve = [film](const Vec3& c) { return grading::film_tone_map(c, film); };
  return in;
}

// VisualizeHDR's image over `tonemapped` with its printed numbers.
Image visualize_hdr_image(const visualize::VisualizeHdrInputs& in) {
  visualize::VisualizeHdrResult r = visualize::visualize_hdr(in);
  const auto& t = r.text;
  r.image.values = {{"meter_luminance", t.meter_luminance},
                    {"meter_ev100", t.meter_ev100},
                    {"illuminance_lux", t.illuminance_lux},
                    {"exposure_without_bias_ev", t.exposure_without_bias_ev},
                    {"exposure_ev100", t.exposure_ev100},
                    {"exposure_px", t.exposure_px},
                    {"average_luminance_px", t.average_luminance_px},
                    {"average_scene_luminance", in.eye.average_scene_luminance}};
  return r.image;
}

}  // namespace

Image visualize_hdr_over(const ParamBlock& p, const Image& hdr_scene, const Image& tonemapped,
                         bool device_allowances) {
  const visualize::VisualizeHdrInputs in = visualize_inputs(p, hdr_scene, tonemapped);
  Image out = visualize_hdr_image(in);
  if (!device_allowances) return out;
  // The tonemapped scene with the Tonemap pass's device ranges (its values are the tight pass's,
  // so it is the scene VisualizeHDR shows), carried through VisualizeHDR's own steps with the
  // ranges of the histogram pass and the panel (reference/ue/visualize_device.h).
  visualize::VisualizeDeviceInputs d;
  d.in = &in;
  d.reference = &out;
  d.scene_ranges = &tonemapped.device_admissible;
  d.exposure = p.exposure;
  d.pre_exposure = p.pre_exposure;
  out.device_admissible = visualize::visualize_hdr_device_ranges(d);
  // The scene's allowances, and VisualizeHDR's own arithmetic (named once).
  out.device_allowances = tonemapped.device_allowances;
  const std::string arithmetic = "shader arithmetic (the Vulkan precision table's bounds)";
  if (std::find(out.device_allowances.begin(), out.device_allowances.end(), arithmetic) ==
      out.device_allowances.end())
    out.device_allowances.push_back(arithmetic);
  return out;
}

Result<Image> visualize_hdr_stage(const ParamBlock& p, const Image& hdr_scene, bool analytic_lut) {
  const Image tonemapped = baked_tonemap_image(p, hdr_scene, nullptr, nullptr, analytic_lut);
  return visualize_hdr_over(p, hdr_scene, tonemapped, false);
}

DeviceInfo ReferenceEngine::device() const {
  return {"reference",
          analytic_lut_ ? "cpu (IEEE double), analytic LUT" : "cpu (IEEE double)",
          "hdrconform reference",
          "-",
          {}};
}

Result<Image> ReferenceEngine::run(const ResolvedCase& c) {
  return pipeline_of(*c.spec.stage).reference(c, analytic_lut_);
}

Result<Image> run_ue55(const ResolvedCase& c, bool analytic_lut) {
  switch (c.spec.stage->id) {
    case StageId::kCombineLuts: {
      // With user LUTs blended the bake depends on their texels, which the cache's key (the
      // parameter block) does not hold: baked directly.
      std::optional<UeLutSet> luts;
      if (c.params.lut_blend_count > 1) luts = ue_lut_set(c.user_luts);
      Image out =
          luts ? lut_image(bake_lut(c.params, &*luts)) : lut_image(*cached_bake_lut(c.params));
      if (c.device_allowances) {
        const BakedLut device = bake_lut_device(c.params, c.device, luts ? &*luts : nullptr);
        out.device_admissible = lut_image(device).admissible;
        out.device_allowances = {"LUT storage rounding (either neighbour)",
                                 "shader arithmetic (the Vulkan precision table's bounds)"};
      }
      return out;
    }
    case StageId::kTonemap: {
      const Image* bloom = c.bloom.data.empty() ? nullptr : &c.bloom;
      const Image* dirt = c.bloom_dirt.data.empty() ? nullptr : &c.bloom_dirt;
      if (c.device_allowances && !analytic_lut) {
        const BakedLut device = bake_lut_device(c.params, c.device);
        return tonemap_image(c.params, c.input, bloom, dirt, &device, nullptr, &device,
                             c.device.sub_texel_bits);
      }
      return baked_tonemap_image(c.params, c.input, bloom, dirt, analytic_lut);
    }
    case StageId::kDither:
      return dither_image(c.params, c.input);
    case StageId::kUiComposite: {
      auto out = ui_composite_stage(c.params, c.input, c.ui);
      if (out && c.device_allowances) {
        out->device_admissible =
            ue_device::ui_composite_device_ranges(c.params, c.input, c.ui, *out);
        out->device_allowances = {"shader arithmetic (the Vulkan precision table's bounds)"};
      }
      return out;
    }
    case StageId::kVisualizeHdr: {
      if (!c.device_allowances || analytic_lut) {
        return visualize_hdr_stage(c.params, c.input, analytic_lut);
      }
      // The tonemapped scene with the Tonemap pass's device ranges (tonemap_image's device
      // overload), through VisualizeHDR with its own ranges (visualize_hdr_over).
      const BakedLut device = bake_lut_device(c.params, c.device);
      const Image tm = tonemap_image(c.params, c.input, nullptr, nullptr, &device, nullptr, &device,
                                     c.device.sub_texel_bits);
      return visualize_hdr_over(c.params, c.input, tm, true);
    }
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
  if (c.device_allowances &&
      (c.spec.stage->id == StageId::kShaper || c.spec.stage->id == StageId::kLinearDevice)) {
    out.device_admissible =
        ue_device::per_pixel_device_ranges(c.spec.stage->id, c.params, c.input, out);
    out.device_allowances = {"shader arithmetic (the Vulkan precision table's bounds)"};
  }
  return out;
}

}  // namespace hdrc::ref
