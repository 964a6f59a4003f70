#include "reference/operators/operators.h"

#include <cmath>

#include "reference/color/d3d_math.h"
#include "reference/color/ue_matrices.h"
#include "reference/grading/hlsl_ops.h"

namespace hdrc::ref::operators {

const char* operator_name(int op) {
  static const char* const kNames[kOperatorCount] = {"Reinhard",      "ReinhardWhite", "Hable",
                                                     "AcesNarkowicz", "UnityNeutral",  "UeFilmic"};
  return (op >= 0 && op < kOperatorCount) ? kNames[op] : nullptr;
}

double reinhard_exposure(double key, double adapted_luminance) {
  return key / adapted_luminance;
}

double reinhard(double x) {
  return x / (1.0 + x);
}

double reinhard_white(double x, double white) {
  return x * (1.0 + x / (white * white)) / (1.0 + x);
}

double rational_curve(double x, const RationalCurve& k) {
  return (x * (k.a * x + k.c * k.b) + k.d * k.e) / (x * (k.a * x + k.b) + k.d * k.f) - k.e / k.f;
}

double hable(double x, const HableParams& p) {
  return rational_curve(p.exposure_bias * x, p.curve) / rational_curve(p.w, p.curve);
}

double aces_narkowicz(double x, double pre_scale) {
  const NarkowiczFit& k = kNarkowicz;
  const double y = pre_scale * x;
  return d3d::saturate((y * (k.a * y + k.b)) / (y * (k.c * y + k.d) + k.e));
}

double unity_neutral(double x) {
  // Color.hlsl: NeutralTonemap — max, white scale, curve, scale, "post-curve white point
  // adjustment", in that order.
  x = d3d::max_num(0.0, x);
  const double white_scale = 1.0 / rational_curve(kUnityNeutralWhiteLevel, kUnityNeutralCurve);
  x = rational_curve(x * white_scale, kUnityNeutralCurve);
  x *= white_scale;
  return x / kUnityNeutralWhiteClip;
}

const char* film_preset_name(int preset) {
  static const char* const kNames[kFilmPresetCount] = {"Default", "Legacy", "ACES", "Uncharted",
                                                       "HP"};
  return (preset >= 0 && preset < kFilmPresetCount) ? kNames[preset] : nullptr;
}

grading::FilmParams film_preset(FilmPreset preset) {
  // {slope, toe, shoulder, black clip, white clip}
  switch (preset) {
    case FilmPreset::kLegacy:
      return {0.98, 0.3, 0.22, 0.0, 0.025};  // TonemapCommon.ush: "Legacy settings"
    case FilmPreset::kAces:
      return {0.91, 0.53, 0.23, 0.0, 0.035};  // "ACES settings"
    case FilmPreset::kUncharted:
      return {0.63, 0.55, 0.47, 0.0, 0.01};  // "Uncharted settings"
    case FilmPreset::kHp:
      return {0.65, 0.63, 0.45, 0.0, 0.0};  // "HP settings"
    case FilmPreset::kDefault:
      break;
  }
  return grading::FilmParams{};  // Scene.cpp FPostProcessSettings: 0.88, 0.55, 0.26, 0, 0.04
}

UeFilmicSpace ue_filmic_space() {
  const WorkingColorSpace wcs = make_working_color_space(WorkingColorSpacePreset::kSrgb);
  return {wcs.to_ap1, wcs.from_ap1};
}

Vec3 ue_filmic(const Vec3& rec709, const grading::FilmParams& film, const UeFilmicSpace& space) {
  const Vec3 tone_ap1 = grading::film_tone_map(space.rec709_to_ap1 * rec709, film);
  return grading::hlsl::max0(space.ap1_to_rec709 * tone_ap1);
}

Vec3 apply_operator(const ParamBlock& p, const Vec3& scene_linear) {
  const Vec3 x = {p.op_exposure * scene_linear[0], p.op_exposure * scene_linear[1],
                  p.op_exposure * scene_linear[2]};
  auto per_channel = [&x](auto&& f) { return Vec3{f(x[0]), f(x[1]), f(x[2])}; };
  switch (static_cast<Operator>(p.op_operator)) {
    case Operator::kReinhard:
      return per_channel([](double v) { return reinhard(v); });
    case Operator::kReinhardWhite:
      return per_channel([&p](double v) { return reinhard_white(v, p.op_white_point); });
    case Operator::kHable: {
      const HableParams h{
          {p.op_hable_a, p.op_hable_b, p.op_hable_c, p.op_hable_d, p.op_hable_e, p.op_hable_f},
          p.op_hable_w,
          p.op_hable_exposure_bias};
      return per_channel([&h](double v) { return hable(v, h); });
    }
    case Operator::kAcesNarkowicz:
      return per_channel([&p](double v) { return aces_narkowicz(v, p.op_narkowicz_pre_scale); });
    case Operator::kUnityNeutral:
      return per_channel([](double v) { return unity_neutral(v); });
    case Operator::kUeFilmic: {
      const grading::FilmParams film{p.film_slope, p.film_toe, p.film_shoulder, p.film_black_clip,
                                     p.film_white_clip};
      return ue_filmic(x, film, {p.op_rec709_to_ap1, p.op_ap1_to_rec709});
    }
  }
  return {d3d::kNaN, d3d::kNaN, d3d::kNaN};
}

}  // namespace hdrc::ref::operators
