#include "reference/ue/ue58/ue58_ui_composite.h"

#include <cmath>
#include <string>

#include "color/d3d_math.h"
#include "color/gamma_correction.h"
#include "reference/ue/ue_pixel_device.h"

namespace hdrc::ref::ue58 {

namespace {

Vec3 rgb(const ui::Vec4& v) {
  return {v[0], v[1], v[2]};
}

// HLSL lerp(x, y, s) = x + s · (y − x).
double lerp(double x, double y, double s) {
  return x + s * (y - x);
}

}  // namespace

UiComposite58Params ui_composite58_params(const ParamBlock& p) {
  UiComposite58Params u;
  u.common.ui_level = p.ui_level;
  u.common.ui_luminance = p.ui_luminance;
  u.common.composite_mode = p.ui_composite_mode;
  u.common.output_device = p.output_device;
  u.common.cvd.type = static_cast<ui::CvdType>(p.cvd_type);
  u.common.cvd.severity = p.cvd_severity;
  u.common.cvd.correct = p.cvd_correct != 0;
  u.common.cvd.show_correction_with_deficiency = p.cvd_show_correction != 0;
  u.eotf = p.ue58_ui_eotf;
  u.eotf_gamma = p.ue58_ui_eotf_gamma;
  u.blend = p.ue58_ui_blend;
  u.blend_gamma = p.ue58_ui_blend_gamma;
  u.blend_inv_gamma = p.ue58_ui_blend_inv_gamma;
  return u;
}

Status validate(const UiComposite58Params& p) {
  if (Status s = ui::validate(p.common); !s) return s;
  auto fail = [](const std::string& name, const std::string& message, const std::string& choices) {
    return Status(Error{"", name, message, choices});
  };
  if (p.eotf != 0 && p.eotf != 1)
    return fail("r.HDR.UI.CompositeEOTF", "unknown value " + std::to_string(p.eotf),
                "0 gamma (r.HDR.UI.CompositeEOTF.Gamma), 1 sRGB");
  if (p.blend != 0 && p.blend != 1)
    return fail("r.HDR.UI.CompositeBlend", "unknown value " + std::to_string(p.blend),
                "0 gamma space (r.HDR.UI.CompositeBlend.Gamma), 1 linear");
  if (!(p.eotf_gamma > 0.0) || !std::isfinite(p.eotf_gamma))
    return fail("r.HDR.UI.CompositeEOTF.Gamma",
                "must be finite and positive, got " + std::to_string(p.eotf_gamma), "");
  if (!(p.blend_gamma > 0.0) || !std::isfinite(p.blend_gamma) || !std::isfinite(p.blend_inv_gamma))
    return fail("r.HDR.UI.CompositeBlend.Gamma",
                "must be finite and positive, got " + std::to_string(p.blend_gamma), "");
  return {};
}

ui::Vec4 compute_hdr_ui_color58(const ui::Vec4& ui, const UiComposite58Params& p,
                                UiComposite58Trace* trace) {
  const double a = ui[3];
  // "Undo premultiplied alpha to apply in HDR blend space": (a > 0) ? rgb / a : 0.
  Vec3 c = a > 0.0 ? Vec3{ui[0] / a, ui[1] / a, ui[2] / a} : Vec3{0.0, 0.0, 0.0};
  if (trace) trace->unpremultiplied = c;
  // LinearizeColor: pow(x, UICompositeEOTFGamma) (HLSL pow: NaN for a negative base) or
  // GammaCorrectionCommon.ush sRGBToLinear, which 5.8 has without the min-normal clamp (L16).
  for (double& v : c)
    v = p.eotf == 0 ? d3d::pow(v, p.eotf_gamma) : srgb_to_linear(v, MinNormalClamp::kOff);
  if (trace) trace->linearized = c;
  const Vec3 rec2020 = ui::srgb_to_rec2020() * c;
  const double l = p.common.ui_luminance;
  return {rec2020[0] * l, rec2020[1] * l, rec2020[2] * l, a};
}

Vec3 compose_ui_and_scene58(Vec3 scene, ui::Vec4 ui, const UiComposite58Params& p,
                            UiComposite58Trace* trace) {
  using Compose = UiComposite58Trace::Compose;
  const double a = ui[3];
  const double level = p.common.ui_level;
  if (trace) trace->compose = Compose::kScene;
  if (!(a > 0.0)) return scene;  // a <= 0 or NaN: the scene as it is
  for (int c = 0; c < 3; ++c) ui[c] *= level;
  if (trace) trace->ui_levelled = rgb(ui);
  if (!(a < 1.0)) {  // opaque UI replaces the scene
    if (trace) trace->compose = Compose::kOpaque;
    return rgb(ui);
  }
  if (p.blend != 0) {
    // Linear: UE 5.5's Reinhard under the UI, then "Composite in linear blend space".
    scene = ui::reinhard_under_ui(scene, a, level);
    if (trace) {
      trace->compose = Compose::kLinear;
      trace->reinhard = scene;
    }
    for (int c = 0; c < 3; ++c) scene[c] = lerp(scene[c], ui[c], a);
    return scene;
  }
  // Gamma: both to pow(saturate(x / UE_PQ_WHITE_NITS), 1 / gamma), lerp there, back to nits.
  if (trace) trace->compose = Compose::kGamma;
  for (int c = 0; c < 3; ++c) {
    const double u = d3d::pow(d3d::saturate(ui[c] / kPqWhiteNits), p.blend_inv_gamma);
    const double s = d3d::pow(d3d::saturate(scene[c] / kPqWhiteNits), p.blend_inv_gamma);
    const double mixed = lerp(s, u, a);
    if (trace) {
      trace->blend_scene[c] = s;
      trace->blend_ui[c] = u;
      trace->blend_lerp[c] = mixed;
    }
    scene[c] = d3d::pow(mixed, p.blend_gamma) * kPqWhiteNits;
  }
  return scene;
}

ui::Vec4 composite_pixel58(const ui::Vec4& scene, const ui::Vec4& ui, const UiComposite58Params& p,
                           UiComposite58Trace* trace) {
  const ui::BackBufferEncoding encoding = ui::back_buffer_encoding(p.common.output_device);
  if (p.common.composite_mode == 0) return ui::standard_blend(scene, ui, encoding);
  const ui::Vec4 ui_nits = compute_hdr_ui_color58(ui, p, trace);
  const Vec3 scene_nits = ui::compute_hdr_scene_color(rgb(scene), encoding);
  const Vec3 composed = compose_ui_and_scene58(scene_nits, ui_nits, p, trace);
  const Vec3 after_cvd = ui::apply_color_deficiency(composed, p.common.cvd);
  const Vec3 encoded = ui::encode_output(after_cvd, encoding);
  // "OutColor.w = UIColor.w" (5.5 wrote 1).
  const ui::Vec4 out{encoded[0], encoded[1], encoded[2], ui[3]};
  if (trace) trace->pass = {ui_nits, scene_nits, composed, after_cvd, out};
  return out;
}

ui::Vec4 composite_pixel58(const ui::Vec4& scene, const ui::Vec4& ui, const UiComposite58Params& p,
                           ui::UiCompositeTrace* trace) {
  if (!trace) return composite_pixel58(scene, ui, p, static_cast<UiComposite58Trace*>(nullptr));
  UiComposite58Trace t;
  const ui::Vec4 out = composite_pixel58(scene, ui, p, &t);
  if (p.common.composite_mode != 0) *trace = t.pass;
  return out;
}

Result<Image> composite_ui58(const Image& scene, const Image& ui, const UiComposite58Params& p) {
  if (Status s = validate(p); !s) return s.error();
  if (Status st = ui::check_ui_size(scene, ui); !st) return st.error();
  Image out(scene.width, scene.height);
  for (size_t i = 0; i < scene.pixel_count(); ++i) {
    const double* s = &scene.data[i * 4];
    const double* u = &ui.data[i * 4];
    const ui::Vec4 o = composite_pixel58({s[0], s[1], s[2], s[3]}, {u[0], u[1], u[2], u[3]}, p);
    for (int c = 0; c < 4; ++c) out.data[i * 4 + c] = o[c];
  }
  return out;
}

std::vector<AdmissibleRange> ui_composite58_device_ranges(const UiComposite58Params& p,
                                                          const Image& scene, const Image& ui,
                                                          const Image& reference) {
  if (p.common.composite_mode == 0) return {};
  return ue_device::ui_composite_device_ranges_of(
      p.common.output_device, scene, reference, [&](size_t i, const Vec3& scene_nits) {
        const double* t = &ui.data[i * 4];
        const ui::Vec4 ui_nits = compute_hdr_ui_color58({t[0], t[1], t[2], t[3]}, p);
        return ui::apply_color_deficiency(compose_ui_and_scene58(scene_nits, ui_nits, p),
                                          p.common.cvd);
      });
}

}  // namespace hdrc::ref::ue58
