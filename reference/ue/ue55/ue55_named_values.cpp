#include "reference/ue/ue55/ue55_named_values.h"

#include "color/d3d_math.h"
#include "reference/reference_engine.h"
#include "reference/ue/aces/aces_output.h"
#include "reference/ue/combine_luts.h"
#include "reference/ue/grading/color_polynomial.h"
#include "reference/ue/grading/film_tonemap.h"
#include "reference/ue/grading/hlsl_ops.h"
#include "reference/ue/tonemap.h"
#include "reference/ue/ui/composite.h"
#include "reference/ue/visualize/histogram.h"
#include "reference/ue/visualize/visualize_hdr.h"

namespace hdrc::ref::ue55 {

namespace {

// The SDR film path's steps (PostProcessCombineLUTs.usf: CombineLUTsCommon, §4.8): the same
// functions combine_luts_texel calls, one step at a time.
void film_path_values(const ParamBlock& p, const Vec3& color_corrected,
                      std::vector<NamedValue>* out) {
  namespace g = grading;
  const Vec3 blue =
      g::hlsl::lerp(color_corrected, g::blue_correct_ap1() * color_corrected, p.blue_correction);
  add_named(out, "blue_corrected", blue);
  const g::FilmParams film{p.film_slope, p.film_toe, p.film_shoulder, p.film_black_clip,
                           p.film_white_clip};
  g::FilmToneMapTrace trace;
  const Vec3 tone = g::film_tone_map(blue, film, &trace);
  g::film_named_values(trace, /*detail=*/true, out);
  const Vec3 toned = g::hlsl::lerp(blue, tone, p.tone_curve_amount);
  add_named(out, "tone_curve", toned);
  const Vec3 unblue = g::hlsl::lerp(toned, g::blue_correct_inv_ap1() * toned, p.blue_correction);
  add_named(out, "blue_uncorrected", unblue);
  add_named(out, "film_color", g::hlsl::max0(p.wcs_from_ap1 * unblue));
}

// The ACES output transform's steps (TonemapCommon.ush: ACESOutputTransforms1000, ACES.ush:
// outputTransform, §5.1) with the parameters as the shader unpacks them.
void aces_values(const ParamBlock& p, const Vec3& graded, std::vector<NamedValue>* out) {
  const aces::AcesShaderParams a = aces_params(p);
  const double scm = a.scene_color_multiplier;
  Vec3 ap0 = p.wcs_to_ap0 * Vec3{graded[0] * scm, graded[1] * scm, graded[2] * scm};
  add_named(out, "aces", ap0);
  if (a.gamut_compression != 0.0) {
    const Vec3 compressed = aces::compress_color(ap0);
    for (int i = 0; i < 3; ++i) ap0[i] = ap0[i] + a.gamut_compression * (compressed[i] - ap0[i]);
    add_named(out, "aces_compressed", ap0);
  }
  const Vec3 rgb_pre = aces::rrt_sweeteners(ap0);
  add_named(out, "rrt", rgb_pre);
  Vec3 tone;
  for (int i = 0; i < 3; ++i) tone[i] = aces::ssts(rgb_pre[i], a.aces_params);
  add_named(out, "ssts", tone);
  const double y_min = a.aces_params.min.y, y_max = a.aces_params.max.y;
  add_named(out, "linear_cv",
            Vec3{(tone[0] - y_min) / (y_max - y_min), (tone[1] - y_min) / (y_max - y_min),
                 (tone[2] - y_min) / (y_max - y_min)});
}

}  // namespace

std::vector<NamedValue> tonemap_named_values(const ParamBlock& p, const Vec3& scene) {
  std::vector<NamedValue> out;
  add_named(&out, "input", scene);
  TonemapTrace t;
  tonemap_centre_pixel(p, scene, /*lut=*/nullptr, &t);
  add_named(&out, "exposed", t.exposed);
  add_named(&out, "encoded", t.encoded);
  // The texel at the coordinate the sampler addresses (clamped to [0, 1]).
  Vec3 e;
  for (int k = 0; k < 3; ++k) e[k] = d3d::clamp_address(t.encoded[k]);
  CombineLutsTrace c;
  combine_luts_texel(p, e, &c);
  add_named(&out, "decoded", c.decoded);
  add_named(&out, "white_balanced", c.white_balanced);
  add_named(&out, "ap1", c.ap1);
  add_named(&out, "expanded", c.expanded);
  add_named(&out, "color_corrected", c.color_corrected);
  const int device = p.output_device;
  const bool film = device <= 2 || device == 9;
  if (film) {
    film_path_values(p, c.color_corrected, &out);
    add_named(&out, "film", c.film);
  } else {
    add_named(&out, "graded", c.graded);
  }
  if (device >= 3 && device <= 6) {
    aces_values(p, c.graded, &out);
    add_named(&out, "aces_nits", c.aces_nits);
  }
  add_named(&out, "device", c.device);
  add_named(&out, "stored", c.stored);
  add_named(&out, "lut", t.lut);
  add_named(&out, "out", t.output);
  return out;
}

std::vector<NamedValue> ui_composite_named_values(const ParamBlock& p, const Vec3& scene,
                                                  const std::array<double, 4>& ui) {
  std::vector<NamedValue> out;
  add_named(&out, "input", scene);
  ui::UiCompositeTrace t;
  ui::composite_pixel({scene[0], scene[1], scene[2], 1.0}, ui, ui_composite_params(p), &t);
  add_named(&out, "ui", Vec3{t.ui[0], t.ui[1], t.ui[2]});
  add_named(&out, "ui_alpha", t.ui[3]);
  add_named(&out, "scene_nits", t.scene);
  add_named(&out, "composed", t.composed);
  add_named(&out, "after_cvd", t.after_cvd);
  add_named(&out, "out", Vec3{t.output[0], t.output[1], t.output[2]});
  return out;
}

std::vector<NamedValue> visualize_false_colour_named_values(const ParamBlock& p,
                                                            const Vec3& scene) {
  std::vector<NamedValue> out;
  add_named(&out, "input", scene);
  const visualize::EyeAdaptationParameters eye = eye_adaptation_parameters(p);
  const Vec3 unexposed{scene[0] / p.pre_exposure, scene[1] / p.pre_exposure,
                       scene[2] / p.pre_exposure};
  add_named(&out, "scene", unexposed);
  const double luminance = visualize::eye_adaptation_luminance(unexposed, eye);
  add_named(&out, "luminance", luminance);
  const double position = visualize::histogram_position_from_luminance(luminance, eye);
  add_named(&out, "position", position);
  add_named(&out, "out", visualize::colorize(position));
  return out;
}

}  // namespace hdrc::ref::ue55
