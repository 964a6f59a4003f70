#include "reference/ue/ue58/ue58_named_values.h"

#include "reference/ue/tonemap.h"
#include "reference/ue/ue58/ue58_pipeline.h"
#include "reference/ue/ue58/ue58_tonemap.h"
#include "reference/ue/ue58/ue58_ui_composite.h"

namespace hdrc::ref::ue58 {

std::vector<NamedValue> ui_composite_named_values(const ParamBlock& p, const Vec3& scene,
                                                  const std::array<double, 4>& ui) {
  std::vector<NamedValue> out;
  add_named(&out, "input", scene);
  const UiComposite58Params params = ui_composite58_params(p);
  UiComposite58Trace t;
  const ui::Vec4 o = composite_pixel58({scene[0], scene[1], scene[2], 1.0}, ui, params, &t);
  if (params.common.composite_mode != 0) {
    add_named(&out, "ui_unpremultiplied", t.unpremultiplied);
    add_named(&out, "ui_linear", t.linearized);
    add_named(&out, "ui", Vec3{t.pass.ui[0], t.pass.ui[1], t.pass.ui[2]});
    add_named(&out, "ui_alpha", t.pass.ui[3]);
    add_named(&out, "scene_nits", t.pass.scene);
    using Compose = UiComposite58Trace::Compose;
    if (t.compose != Compose::kScene) add_named(&out, "ui_levelled", t.ui_levelled);
    if (t.compose == Compose::kGamma) {
      add_named(&out, "blend_scene", t.blend_scene);
      add_named(&out, "blend_ui", t.blend_ui);
      add_named(&out, "blend_lerp", t.blend_lerp);
    }
    if (t.compose == Compose::kLinear) add_named(&out, "reinhard", t.reinhard);
    add_named(&out, "composed", t.pass.composed);
    add_named(&out, "after_cvd", t.pass.after_cvd);
  }
  add_named(&out, "out", Vec3{o[0], o[1], o[2]});
  add_named(&out, "out_alpha", o[3]);
  return out;
}

std::vector<NamedValue> vignette_named_values(const ParamBlock& p, double pos_x, double pos_y,
                                              double aspect) {
  std::vector<NamedValue> out;
  add_named(&out, "input", Vec3{pos_x, pos_y, aspect});
  VignetteTrace t;
  const Vec3 mask = vignette_mask(tonemap_vignette(p), pos_x, pos_y, aspect, &t);
  if (t.textured) {
    out.push_back({"vignette_space", {t.space[0], t.space[1]}, false});
    out.push_back({"uv", {t.uv[0], t.uv[1]}, false});
    out.push_back({"texel", {t.texel[0], t.texel[1]}, false});
    out.push_back({"taps", {t.taps[0], t.taps[1], t.taps[2], t.taps[3]}, false});
    add_named(&out, "sample", t.sample);
  }
  add_named(&out, "weight", t.weight);
  add_named(&out, "mask", mask);
  return out;
}

std::vector<NamedValue> visualize_named_values(const ResolvedCase& c) {
  std::vector<NamedValue> out;
  auto image = ue58_pipeline().reference(c, /*analytic_lut=*/false);
  if (!image || c.input.data.empty() || image->data.empty()) return out;
  const double* in = c.input.px(0, 0);
  add_named(&out, "input", Vec3{in[0], in[1], in[2]});
  for (const auto& [name, v] : image->values) add_named(&out, name, v);
  const double* px = image->px(0, 0);
  add_named(&out, "pixel", Vec3{px[0], px[1], px[2]});
  return out;
}

std::vector<std::vector<NamedValue>> named_values_of(
    const ResolvedCase& c, const std::vector<std::array<double, 3>>& colours) {
  std::vector<std::vector<NamedValue>> out(colours.size());
  if (!c.spec.stage || c.spec.stage->id != StageId::kUiComposite) return out;
  for (size_t i = 0; i < colours.size(); ++i) {
    std::array<double, 4> ui{0, 0, 0, 0};
    const int x = static_cast<int>(i);
    if (x < c.ui.width && c.ui.height > 0) {
      const double* u = c.ui.px(x, 0);
      ui = {u[0], u[1], u[2], u[3]};
    }
    const Vec3 scene{colours[i][0], colours[i][1], colours[i][2]};
    out[i] = ui_composite_named_values(c.params, scene, ui);
  }
  return out;
}

}  // namespace hdrc::ref::ue58
