#include "reference/operators/operators.h"

#include <algorithm>
#include <cmath>

#include "color/d3d_math.h"
#include "reference/color/device_allowance.h"
#include "reference/color/ue_matrices.h"
#include "reference/ue/grading/hlsl_ops.h"

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

Vec3 ue_filmic(const Vec3& rec709, const grading::FilmParams& film, const UeFilmicSpace& space,
               UeFilmicTrace* trace) {
  trace->ap1 = space.rec709_to_ap1 * rec709;
  trace->tone_ap1 = grading::film_tone_map(trace->ap1, film, &trace->film);
  trace->rec709 = space.ap1_to_rec709 * trace->tone_ap1;
  return grading::hlsl::max0(trace->rec709);
}

std::vector<NamedValue> named_values(const ParamBlock& p, const Vec3& in) {
  std::vector<NamedValue> out;
  add_named(&out, "input", in);
  add_named(&out, "exposure", p.op_exposure);
  const Vec3 x{p.op_exposure * in[0], p.op_exposure * in[1], p.op_exposure * in[2]};
  add_named(&out, "x", x);
  switch (static_cast<Operator>(p.op_operator)) {
    case Operator::kHable: {
      const RationalCurve k{p.op_hable_a, p.op_hable_b, p.op_hable_c,
                            p.op_hable_d, p.op_hable_e, p.op_hable_f};
      Vec3 f;
      for (int i = 0; i < 3; ++i) f[i] = rational_curve(p.op_hable_exposure_bias * x[i], k);
      add_named(&out, "f_bias_x", f);
      add_named(&out, "f_w", rational_curve(p.op_hable_w, k));
      break;
    }
    case Operator::kUnityNeutral: {
      const double ws = 1.0 / rational_curve(kUnityNeutralWhiteLevel, kUnityNeutralCurve);
      add_named(&out, "white_scale", ws);
      Vec3 n;
      for (int i = 0; i < 3; ++i)
        n[i] = rational_curve(d3d::max_num(0.0, x[i]) * ws, kUnityNeutralCurve);
      add_named(&out, "curve", n);
      break;
    }
    case Operator::kUeFilmic: {
      const grading::FilmParams film{p.film_slope, p.film_toe, p.film_shoulder, p.film_black_clip,
                                     p.film_white_clip};
      UeFilmicTrace t;
      ue_filmic(x, film, {p.op_rec709_to_ap1, p.op_ap1_to_rec709}, &t);
      add_named(&out, "ap1", t.ap1);
      grading::film_named_values(t.film, true, &out);
      add_named(&out, "tone_ap1", t.tone_ap1);
      add_named(&out, "rec709", t.rec709);
      break;
    }
    default:
      break;
  }
  add_named(&out, "out", apply_operator(p, in));
  return out;
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

// --- Device allowances ---

namespace {

using spirv::Interval;

// A float32 constant, uniform or input of exact value v: its float32 neighbours (a conversion to
// float32 is correctly rounded).
Interval constant(double v) {
  return {float_round_down(v), float_round_up(v)};
}

bool finite(const Interval& i) {
  return std::isfinite(i.lo) && std::isfinite(i.hi);
}

// OpFDiv where the divisor's range excludes 0 (else no range: *ok cleared).
Interval safe_div(Interval a, Interval b, bool* ok) {
  if (!(b.lo > 0 || b.hi < 0)) {
    *ok = false;
    return a;
  }
  return spirv::div(a, b);
}

Interval hull(Interval a, Interval b) {
  return {std::fmin(a.lo, b.lo), std::fmax(a.hi, b.hi)};
}

// Which branch of the shader's |y| <= 1 test a range of y may take: both where it straddles ±1.
bool may_be_small(Interval y) {
  return std::fmin(std::fabs(y.lo), std::fabs(y.hi)) <= 1.0 || (y.lo < 0 && y.hi > 0);
}
bool may_be_large(Interval y) {
  return std::fmax(std::fabs(y.lo), std::fabs(y.hi)) > 1.0;
}

// op_recip_large: 1/y (|y| > 1; the 2^126 cut-off gives 0, inside the interval's ends there).
Interval recip(Interval y, bool* ok) {
  return safe_div(Interval::point(1.0), y, ok);
}

// operators.glsl op_rational: f(y) = (y (A y + C B) + D E) / (y (A y + B) + D F) − E / F, or in
// 1/y above |y| = 1, with y = scale · x.
Interval rational_device(Interval x, Interval scale, const RationalCurve& kc, bool* ok) {
  using namespace spirv;
  const Interval a = constant(kc.a), b = constant(kc.b), c = constant(kc.c), d = constant(kc.d),
                 e = constant(kc.e), f = constant(kc.f);
  const Interval y = mul(scale, x);
  Interval q{HUGE_VAL, -HUGE_VAL};
  if (may_be_small(y)) {
    const Interval num = mul_add(y, mul_add(a, y, mul(c, b)), mul(d, e));
    const Interval den = mul_add(y, mul_add(a, y, b), mul(d, f));
    q = hull(q, safe_div(num, den, ok));
  }
  if (may_be_large(y)) {
    const Interval r = recip(y, ok);
    const Interval num = mul_add(r, mul_add(r, mul(d, e), mul(c, b)), a);
    const Interval den = mul_add(r, mul_add(r, mul(d, f), b), a);
    q = hull(q, safe_div(num, den, ok));
  }
  return sub(q, safe_div(e, f, ok));
}

}  // namespace

bool operator_channel_device_range(const ParamBlock& p, double x_in, Interval* out) {
  using namespace spirv;
  if (!std::isfinite(x_in)) return false;
  bool ok = true;
  const Interval x = constant(x_in);
  const Interval s = constant(p.op_exposure);
  const Interval one = Interval::point(1.0);
  Interval r;
  switch (static_cast<Operator>(p.op_operator)) {
    case Operator::kReinhard: {
      const Interval y = mul(s, x);
      r = {HUGE_VAL, -HUGE_VAL};
      if (may_be_small(y)) r = hull(r, safe_div(y, add(one, y), &ok));
      if (may_be_large(y)) r = hull(r, safe_div(one, add(one, recip(y, &ok)), &ok));
      break;
    }
    case Operator::kReinhardWhite: {
      const Interval w = constant(p.op_white_point);
      const Interval y = mul(s, x);
      const Interval t = mul_add(safe_div(s, mul(w, w), &ok), x, one);  // 1 + y / Lw²
      r = {HUGE_VAL, -HUGE_VAL};
      if (may_be_small(y)) r = hull(r, safe_div(mul(y, t), add(one, y), &ok));
      if (may_be_large(y)) r = hull(r, safe_div(t, add(one, recip(y, &ok)), &ok));
      break;
    }
    case Operator::kHable: {
      const RationalCurve k{p.op_hable_a, p.op_hable_b, p.op_hable_c,
                            p.op_hable_d, p.op_hable_e, p.op_hable_f};
      r = safe_div(rational_device(x, mul(constant(p.op_hable_exposure_bias), s), k, &ok),
                   rational_device(constant(p.op_hable_w), one, k, &ok), &ok);
      break;
    }
    case Operator::kAcesNarkowicz: {
      const NarkowiczFit& kf = kNarkowicz;
      const Interval a = constant(kf.a), b = constant(kf.b), c = constant(kf.c), d = constant(kf.d),
                     e = constant(kf.e);
      const Interval y = mul(mul(s, constant(p.op_narkowicz_pre_scale)), x);
      r = {HUGE_VAL, -HUGE_VAL};
      if (may_be_small(y))
        r = hull(r, safe_div(mul(y, mul_add(a, y, b)), mul_add(y, mul_add(c, y, d), e), &ok));
      if (may_be_large(y)) {
        const Interval rr = recip(y, &ok);
        r = hull(r, safe_div(mul_add(rr, b, a), mul_add(rr, mul_add(rr, e, d), c), &ok));
      }
      r = {d3d::saturate(r.lo), d3d::saturate(r.hi)};
      break;
    }
    case Operator::kUnityNeutral: {
      const Interval xc{std::fmax(x.lo, 0.0), std::fmax(x.hi, 0.0)};
      const Interval ws = safe_div(
          one, rational_device(constant(kUnityNeutralWhiteLevel), one, kUnityNeutralCurve, &ok),
          &ok);
      r = safe_div(mul(rational_device(xc, mul(s, ws), kUnityNeutralCurve, &ok), ws),
                   constant(kUnityNeutralWhiteClip), &ok);
      break;
    }
    default:
      return false;
  }
  if (!ok || !finite(r) || r.lo > r.hi) return false;
  *out = r;
  return true;
}

}  // namespace hdrc::ref::operators
