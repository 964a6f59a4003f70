#include "reference/ue/grading/film_tonemap.h"

#include <cmath>

#include "color/d3d_math.h"
#include "reference/ue/grading/film_common.h"
#include "reference/ue/grading/hlsl_ops.h"

namespace hdrc::ref::grading {
namespace {

// TonemapCommon.ush: FilmToneMap uses the ACES RRT glow and red-modifier constants.
constexpr double kGlowGain = aces::kRrtGlowGain;
constexpr double kGlowMid = aces::kRrtGlowMid;
constexpr double kRedScale = aces::kRrtRedScale;
constexpr double kRedPivot = aces::kRrtRedPivot;
constexpr double kRedHue = aces::kRrtRedHue;
constexpr double kRedWidth = aces::kRrtRedWidth;
constexpr double kPreDesaturate = 0.96;
constexpr double kPostDesaturate = 0.93;
constexpr double kMatch = 0.18;  // InMatch = OutMatch

Vec3 desaturate(const Vec3& c, double amount) {
  return hlsl::lerp(dot(c, ue_literal::kAp1RgbToY), c, amount);
}

}  // namespace

FilmCurveMatch film_curve_match(const FilmParams& p) {
  FilmCurveMatch m{};
  m.toe_scale = 1.0 + p.black_clip - p.toe;
  m.shoulder_scale = 1.0 + p.white_clip - p.shoulder;
  if (p.toe > 0.8) {
    // "0.18 will be on straight segment"
    m.toe_match = (1.0 - p.toe - kMatch) / p.slope + std::log10(kMatch);
  } else {
    // "0.18 will be on toe segment": solve toe(log10 0.18) = 0.18.
    const double bt = (kMatch + p.black_clip) / m.toe_scale - 1.0;
    m.toe_match =
        std::log10(kMatch) - 0.5 * std::log((1.0 + bt) / (1.0 - bt)) * (m.toe_scale / p.slope);
  }
  m.straight_match = (1.0 - p.toe) / p.slope - m.toe_match;
  m.shoulder_match = p.shoulder / p.slope - m.straight_match;
  return m;
}

namespace {

// film_curve with its match points computed once per parameter set (they depend on the
// parameters only; computing them per channel cost three log10 and a log each).
struct CurveTrace {
  double log_color, toe, straight, shoulder, blend;
};

double film_curve_matched(double w, const FilmParams& p, const FilmCurveMatch& m,
                          CurveTrace* trace = nullptr) {
  const double log_color = std::log10(w);
  const double straight = p.slope * (log_color + m.straight_match);
  const double toe =
      -p.black_clip + (2.0 * m.toe_scale) / (1.0 + std::exp((-2.0 * p.slope / m.toe_scale) *
                                                            (log_color - m.toe_match)));
  const double shoulder =
      (1.0 + p.white_clip) -
      (2.0 * m.shoulder_scale) /
          (1.0 + std::exp((2.0 * p.slope / m.shoulder_scale) * (log_color - m.shoulder_match)));
  const double toe_color = log_color < m.toe_match ? toe : straight;
  const double shoulder_color = log_color > m.shoulder_match ? shoulder : straight;
  double t = d3d::saturate((log_color - m.toe_match) / (m.shoulder_match - m.toe_match));
  if (m.shoulder_match < m.toe_match) t = 1.0 - t;
  t = (3.0 - 2.0 * t) * t * t;
  if (trace) *trace = {log_color, toe, straight, shoulder, t};
  return hlsl::lerp(toe_color, shoulder_color, t);
}

}  // namespace

double film_curve(double w, const FilmParams& p) {
  return film_curve_matched(w, p, film_curve_match(p));
}

double red_modifier_hue_weight(double hue_deg) {
  const double centered = film::center_hue(hue_deg, kRedHue);
  const double s = hlsl::smoothstep(0.0, 1.0, 1.0 - std::fabs(2.0 * centered / kRedWidth));
  return s * s;
}

Vec3 film_tone_map(const Vec3& ap1, const FilmParams& p) {
  return film_tone_map(ap1, p, nullptr);
}

Vec3 film_tone_map(const Vec3& ap1, const FilmParams& p, FilmToneMapTrace* trace) {
  using namespace ue_literal;
  // The shader's local AP1_2_AP0 = XYZ_2_AP0_MAT · AP1_2_XYZ_MAT (not the AP1_2_AP0_MAT literal).
  static const Mat3 kAp1ToAp0Product = kXyzToAp0 * kAp1ToXyz;
  Vec3 ap0 = kAp1ToAp0Product * ap1;

  if (trace) trace->ap0 = ap0;

  const double saturation = film::rgb_2_saturation(ap0);
  const double yc_in = film::rgb_2_yc(ap0);
  const double s = film::sigmoid_shaper((saturation - 0.4) / 0.2);
  const double added_glow = 1.0 + film::glow_fwd(yc_in, kGlowGain * s, kGlowMid);
  for (double& c : ap0) c *= added_glow;

  const double hue = film::rgb_2_hue(ap0);
  const double hue_weight = red_modifier_hue_weight(hue);
  if (trace) {
    trace->saturation = saturation;
    trace->yc = yc_in;
    trace->sigmoid = s;
    trace->glow = added_glow;
    trace->ap0_glow = ap0;
    trace->hue = hue;
    trace->hue_weight = hue_weight;
  }
  ap0[0] += hue_weight * saturation * (kRedPivot - ap0[0]) * (1.0 - kRedScale);

  Vec3 working = hlsl::max0(kAp0ToAp1 * ap0);  // AP0_2_AP1_MAT literal
  if (trace) {
    trace->ap0_red = ap0;
    trace->ap1_clamped = working;
  }
  working = desaturate(working, kPreDesaturate);

  const FilmCurveMatch m = film_curve_match(p);
  Vec3 tone;
  for (int i = 0; i < 3; ++i) {
    CurveTrace ct;
    tone[i] = film_curve_matched(working[i], p, m, trace ? &ct : nullptr);
    if (trace) {
      trace->log_color[i] = ct.log_color;
      trace->toe[i] = ct.toe;
      trace->straight[i] = ct.straight;
      trace->shoulder[i] = ct.shoulder;
      trace->blend[i] = ct.blend;
    }
  }
  const Vec3 post = desaturate(tone, kPostDesaturate);
  if (trace) {
    trace->match = m;
    trace->ap1_desat = working;
    trace->tone = tone;
    trace->post_desat = post;
  }
  return hlsl::max0(post);
}

void film_named_values(const FilmToneMapTrace& t, bool detail, std::vector<NamedValue>* out) {
  add_named(out, "toe_scale", t.match.toe_scale, detail);
  add_named(out, "shoulder_scale", t.match.shoulder_scale, detail);
  add_named(out, "toe_match", t.match.toe_match, detail);
  add_named(out, "straight_match", t.match.straight_match, detail);
  add_named(out, "shoulder_match", t.match.shoulder_match, detail);
  add_named(out, "ap0", t.ap0, detail);
  add_named(out, "saturation", t.saturation, detail);
  add_named(out, "yc", t.yc, detail);
  add_named(out, "sigmoid", t.sigmoid, detail);
  add_named(out, "glow", t.glow, detail);
  add_named(out, "ap0_glow", t.ap0_glow, detail);
  add_named(out, "hue", t.hue, detail);
  add_named(out, "hue_weight", t.hue_weight, detail);
  add_named(out, "ap0_red", t.ap0_red, detail);
  add_named(out, "ap1_clamped", t.ap1_clamped, detail);
  add_named(out, "ap1_desat", t.ap1_desat, detail);
  add_named(out, "log_color", t.log_color, detail);
  add_named(out, "toe", t.toe, detail);
  add_named(out, "straight", t.straight, detail);
  add_named(out, "shoulder", t.shoulder, detail);
  add_named(out, "blend", t.blend, detail);
  add_named(out, "tone", t.tone, detail);
  add_named(out, "post_desat", t.post_desat, detail);
}

std::vector<NamedValue> film_tone_map_named_values(const Vec3& ap1, const FilmParams& p) {
  std::vector<NamedValue> out;
  add_named(&out, "input", ap1);
  FilmToneMapTrace t;
  const Vec3 result = film_tone_map(ap1, p, &t);
  film_named_values(t, false, &out);
  add_named(&out, "out", result);
  return out;
}

const Mat3 kBlueCorrectAp0{{0.9404372683, -0.0183068787, 0.0778696104,  //
                            0.0083786969, 0.8286599939, 0.1629613092,   //
                            0.0005471261, -0.0008833746, 1.0003362486}};
const Mat3 kBlueCorrectInvAp0{{1.06318, 0.0233956, -0.0865726,  //
                               -0.0106337, 1.20632, -0.19569,   //
                               -0.000590887, 0.00105248, 0.999538}};

Mat3 blue_correct_ap1() {
  using namespace ue_literal;
  return (kXyzToAp1 * kAp0ToXyz) * (kBlueCorrectAp0 * (kXyzToAp0 * kAp1ToXyz));
}

Mat3 blue_correct_inv_ap1() {
  using namespace ue_literal;
  return (kXyzToAp1 * kAp0ToXyz) * (kBlueCorrectInvAp0 * (kXyzToAp0 * kAp1ToXyz));
}

Vec3 film_path_ap1(const Vec3& color_ap1, const FilmPathParams& p) {
  static const Mat3 kBlue = blue_correct_ap1();
  static const Mat3 kBlueInv = blue_correct_inv_ap1();
  Vec3 c = hlsl::lerp(color_ap1, kBlue * color_ap1, p.blue_correction);
  c = hlsl::lerp(c, film_tone_map(c, p.film), p.tone_curve_amount);
  return hlsl::lerp(c, kBlueInv * c, p.blue_correction);
}

Vec3 film_color(const Vec3& color_ap1, const FilmPathParams& p, const WorkingColorSpace& wcs) {
  return hlsl::max0(wcs.from_ap1 * film_path_ap1(color_ap1, p));
}

}  // namespace hdrc::ref::grading
