#include "reference/unity_urp/unity_urp.h"

#include <Imath/half.h>

#include <algorithm>
#include <cmath>

#include "color/d3d_math.h"
#include "reference/color/device_allowance.h"
#include "reference/color/spirv_precision.h"
#include "reference/color/strip_device_range.h"
#include "reference/operators/operators.h"

namespace hdrc::ref::unity_urp {

namespace {

constexpr double kPi = 3.14159265358979323846;

double saturate(double x) {
  return d3d::saturate(x);
}
Vec3 saturate(const Vec3& c) {
  return {saturate(c[0]), saturate(c[1]), saturate(c[2])};
}
// HLSL lerp(a, b, t) = a + t (b − a).
double lerp(double a, double b, double t) {
  return a + t * (b - a);
}
// HLSL smoothstep(a, b, x) = t² (3 − 2t), t = saturate((x − a)/(b − a)). With a = b the division
// gives ±Inf (saturate: 1 or 0) or NaN (x = a: saturate(NaN) = 0 on D3D), docs/spec/unity_urp.md
// §7.6.
double smoothstep(double a, double b, double x) {
  const double t = saturate((x - a) / (b - a));
  return t * t * (3.0 - 2.0 * t);
}
// HLSL sign: −1, 0 or +1.
double sign(double x) {
  return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0);
}
// Common.hlsl: PositivePow(base, power) = pow(abs(base), power); HLSL pow(0, p > 0) = 0.
double positive_pow(double base, double power) {
  return std::pow(std::fabs(base), power);
}
double max3(const Vec3& c) {
  return std::max({c[0], c[1], c[2]});
}
double min3(const Vec3& c) {
  return std::min({c[0], c[1], c[2]});
}
Vec3 v3(const std::array<double, 4>& v) {
  return {v[0], v[1], v[2]};
}

}  // namespace

// --- LogC (Color.hlsl) -----------------------------------------------------------------------

double logc_from_linear(double x, const LogCParams& k) {
  // LinearToLogC (USE_PRECISE_LOGC 0): LogC.c * log10(max(LogC.a * x + LogC.b, 0.0)) + LogC.d.
  // HLSL max is maxNum: a NaN argument gives 0 and so −Inf.
  return k.c * std::log10(d3d::max_num(k.a * x + k.b, 0.0)) + k.d;
}

double linear_from_logc(double x, const LogCParams& k) {
  // LogCToLinear (fast): (pow(10.0, (x - LogC.d) / LogC.c) - LogC.b) / LogC.a.
  return (std::pow(10.0, (x - k.d) / k.c) - k.b) / k.a;
}

double logc_from_linear_precise(double x, const LogCParams& k) {
  // LinearToLogC_Precise: x > cut ? c·log10(max(a x + b, 0)) + d : e x + f.
  return x > k.cut ? k.c * std::log10(d3d::max_num(k.a * x + k.b, 0.0)) + k.d : k.e * x + k.f;
}

Vec3 logc_from_linear(const Vec3& x, const LogCParams& k) {
  return {logc_from_linear(x[0], k), logc_from_linear(x[1], k), logc_from_linear(x[2], k)};
}

Vec3 linear_from_logc(const Vec3& x, const LogCParams& k) {
  return {linear_from_logc(x[0], k), linear_from_logc(x[1], k), linear_from_logc(x[2], k)};
}

// --- ACEScc (ACES.hlsl) ----------------------------------------------------------------------

double acescc_from_linear(double x) {
  // ACES_to_ACEScc(half3): x = clamp(x, 0, HALF_MAX); thresholds 2^-15 and 2^-16 written as
  // 0.00003051757 and 0.00001525878.
  x = d3d::min_num(d3d::max_num(x, 0.0), kHalfMax);
  return x < 0.00003051757 ? (std::log2(0.00001525878 + x * 0.5) + 9.72) / 17.52
                           : (std::log2(x) + 9.72) / 17.52;
}

double linear_from_acescc(double y) {
  // ACEScc_to_ACES(half): the second threshold is (log2(HALF_MAX) + 9.72) / 17.52 as written.
  if (y < -0.3013698630) return (std::pow(2.0, y * 17.52 - 9.72) - std::pow(2.0, -16.0)) * 2.0;
  if (y < (std::log2(kHalfMax) + 9.72) / 17.52) return std::pow(2.0, y * 17.52 - 9.72);
  return kHalfMax;
}

double luminance_rec709(const Vec3& c) {
  return dot(c, kRec709RgbToY);
}
double luminance_ap1(const Vec3& c) {
  return dot(c, kAp1RgbToY);
}

// --- HSV, SoftLight (Color.hlsl) -------------------------------------------------------------

Vec3 hsv_from_rgb(const Vec3& c) {
  // RgbToHsv: K = (0, −1/3, 2/3, −1);
  // p = lerp((c.b, c.g, K.w, K.z), (c.g, c.b, K.x, K.y), step(c.b, c.g)), step(a, x) = x >= a;
  // q = lerp((p.x, p.y, p.w, c.r), (c.r, p.y, p.z, p.x), step(p.x, c.r)).
  const double r = c[0], g = c[1], b = c[2];
  std::array<double, 4> p, q;
  if (g >= b)
    p = {g, b, 0.0, -1.0 / 3.0};
  else
    p = {b, g, -1.0, 2.0 / 3.0};
  if (r >= p[0])
    q = {r, p[1], p[2], p[0]};
  else
    q = {p[0], p[1], p[3], r};
  const double d = q[0] - std::min(q[3], q[1]);
  const double e = 1.0e-4;  // RgbToHsv: const real e = 1.0e-4
  return {std::fabs(q[2] + (q[3] - q[1]) / (6.0 * d + e)), d / (q[0] + e), q[0]};
}

Vec3 rgb_from_hsv(const Vec3& hsv) {
  // HsvToRgb: K = (1, 2/3, 1/3, 3); p = abs(frac(c.xxx + K.xyz) * 6 − K.www);
  // c.z * lerp(K.xxx, saturate(p − K.xxx), c.y). frac(x) = x − floor(x).
  const double k[3] = {1.0, 2.0 / 3.0, 1.0 / 3.0};
  Vec3 out;
  for (int i = 0; i < 3; ++i) {
    const double t = hsv[0] + k[i];
    const double p = std::fabs((t - std::floor(t)) * 6.0 - 3.0);
    out[i] = hsv[2] * lerp(1.0, saturate(p - 1.0), hsv[1]);
  }
  return out;
}

double rotate_hue(double value, double low, double hi) {
  // RotateHue: value < low ? value + hi : (value > hi ? value − hi : value).
  return value < low ? value + hi : (value > hi ? value - hi : value);
}

double soft_light(double base, double blend) {
  // SoftLight: r1 = 2 base blend + base² (1 − 2 blend); r2 = √base (2 blend − 1) + 2 base (1 −
  // blend); t = step(0.5, blend); r2 t + (1 − t) r1.
  const double r1 = 2.0 * base * blend + base * base * (1.0 - 2.0 * blend);
  const double r2 = std::sqrt(base) * (2.0 * blend - 1.0) + 2.0 * base * (1.0 - blend);
  return blend >= 0.5 ? r2 : r1;
}

// --- Tone mapping ----------------------------------------------------------------------------

Vec3 neutral_tonemap(const Vec3& x) {
  // Color.hlsl: NeutralTonemap is per channel (max(x, 0), Hable/Hejl curve with white level 5.3);
  // the shared operator is the one definition (reference/operators/operators.h).
  return {operators::unity_neutral(x[0]), operators::unity_neutral(x[1]),
          operators::unity_neutral(x[2])};
}

namespace {

// ACES.hlsl: RRT constants.
constexpr double kRrtGlowGain = 0.05;         // RRT_GLOW_GAIN
constexpr double kRrtGlowMid = 0.08;          // RRT_GLOW_MID
constexpr double kRrtRedScale = 0.82;         // RRT_RED_SCALE
constexpr double kRrtRedPivot = 0.03;         // RRT_RED_PIVOT
constexpr double kRrtRedHue = 0.0;            // RRT_RED_HUE
constexpr double kRrtRedWidth = 135.0;        // RRT_RED_WIDTH
constexpr double kRrtSatFactor = 0.96;        // RRT_SAT_FACTOR
constexpr double kOdtSatFactor = 0.93;        // ODT_SAT_FACTOR
constexpr double kDimSurroundGamma = 0.9811;  // DIM_SURROUND_GAMMA

// ACES.hlsl: rgb_2_saturation.
double rgb_2_saturation(const Vec3& rgb) {
  const double tiny = 1e-4;
  return (std::max(max3(rgb), tiny) - std::max(min3(rgb), tiny)) / std::max(max3(rgb), 1e-2);
}

// ACES.hlsl: rgb_2_yc (ycRadiusWeight 1.75; k clamped at 0 before the square root).
double rgb_2_yc(const Vec3& rgb) {
  const double r = rgb[0], g = rgb[1], b = rgb[2];
  const double k = std::max(b * (b - g) + g * (g - r) + r * (r - b), 0.0);
  return (b + g + r + 1.75 * std::sqrt(k)) / 3.0;
}

// ACES.hlsl: rgb_2_hue (degrees in [0, 360); 0 for r = g = b).
double rgb_2_hue(const Vec3& rgb) {
  double hue = 0.0;
  if (!(rgb[0] == rgb[1] && rgb[1] == rgb[2]))
    hue = (180.0 / kPi) *
          std::atan2(std::sqrt(3.0) * (rgb[1] - rgb[2]), 2.0 * rgb[0] - rgb[1] - rgb[2]);
  if (hue < 0.0) hue += 360.0;
  return hue;
}

// ACES.hlsl: center_hue.
double center_hue(double hue, double center) {
  double h = hue - center;
  if (h < -180.0)
    h += 360.0;
  else if (h > 180.0)
    h -= 360.0;
  return h;
}

// ACES.hlsl: sigmoid_shaper with FastSign (+1 at ±0; irrelevant here since 1 − t² = 0 at x = 0).
double sigmoid_shaper(double x) {
  const double t = std::max(1.0 - std::fabs(x / 2.0), 0.0);
  const double y = 1.0 + (x >= 0.0 ? 1.0 : -1.0) * (1.0 - t * t);
  return y / 2.0;
}

// ACES.hlsl: glow_fwd.
double glow_fwd(double yc, double gain, double mid) {
  if (yc <= 2.0 / 3.0 * mid) return gain;
  if (yc >= 2.0 * mid) return 0.0;
  return gain * (mid / yc - 1.0 / 2.0);
}

// ACES.hlsl: darkSurround_to_dimSurround with XYZ_2_xyY / xyY_2_XYZ (1e-4 guards).
Vec3 dark_to_dim_surround(const Vec3& linear_cv) {
  const Vec3 xyz = kAp1ToXyz * linear_cv;
  const double divisor = std::max(xyz[0] + xyz[1] + xyz[2], 1e-4);
  const double x = xyz[0] / divisor, y = xyz[1] / divisor;
  const double big_y = std::pow(std::clamp(xyz[1], 0.0, kHalfMax), kDimSurroundGamma);
  const double m = big_y / std::max(y, 1e-4);
  return kXyzToAp1 * Vec3{x * m, big_y, (1.0 - x - y) * m};
}

Vec3 desaturate_ap1(const Vec3& c, double factor) {
  // lerp(dot(c, AP1_RGB2Y).xxx, c, factor)
  const double y = luminance_ap1(c);
  return {lerp(y, c[0], factor), lerp(y, c[1], factor), lerp(y, c[2], factor)};
}

}  // namespace

Vec3 aces_tonemap(const Vec3& aces_in) {
  Vec3 aces = aces_in;
  // Glow module.
  const double saturation = rgb_2_saturation(aces);
  const double yc_in = rgb_2_yc(aces);
  const double s = sigmoid_shaper((saturation - 0.4) / 0.2);
  const double added_glow = 1.0 + glow_fwd(yc_in, kRrtGlowGain * s, kRrtGlowMid);
  for (double& c : aces) c *= added_glow;
  // Red modifier (hue weight: smoothstep(0, 1, 1 − |2 h / RRT_RED_WIDTH|)², the cubic basis
  // shaper replaced as Unity does).
  const double centered_hue = center_hue(rgb_2_hue(aces), kRrtRedHue);
  double hue_weight = smoothstep(0.0, 1.0, 1.0 - std::fabs(2.0 * centered_hue / kRrtRedWidth));
  hue_weight *= hue_weight;
  aces[0] += hue_weight * saturation * (kRrtRedPivot - aces[0]) * (1.0 - kRrtRedScale);
  // ACES to ACEScg, clamped after the matrix (the reference RRT clamps AP0 before it).
  Vec3 acescg = kAp0ToAp1 * aces;
  for (double& c : acescg) c = d3d::max_num(0.0, c);
  acescg = desaturate_ap1(acescg, kRrtSatFactor);
  // The fitted RRT + ODT tone scale (AcesTonemap: a = 0.0245786, b = 0.000090537,
  // c = 0.983729, d = 0.4329510, e = 0.238081).
  const double a = 0.0245786, b = 0.000090537, c = 0.983729, d = 0.4329510, e = 0.238081;
  Vec3 rgb_post;
  for (int i = 0; i < 3; ++i) {
    const double x = acescg[i];
    rgb_post[i] = (x * (x + a) - b) / (x * (c * x + d) + e);
  }
  Vec3 linear_cv = dark_to_dim_surround(rgb_post);
  linear_cv = desaturate_ap1(linear_cv, kOdtSatFactor);
  return kXyzToRec709 * (kD60ToD65Cat * (kAp1ToXyz * linear_cv));
}

Vec3 hdr_bake_tonemap(const Vec3& graded, TonemapMode mode) {
  switch (mode) {
    case TonemapMode::kNeutral:
      return neutral_tonemap(graded);
    case TonemapMode::kAces:
      // Tonemap: aces = ACEScg_to_ACES(colorLinear) (AP1_2_AP0_MAT).
      return aces_tonemap(kAp1ToAp0 * graded);
    case TonemapMode::kNone:
      break;
  }
  return graded;
}

Vec3 uber_tonemap(const Vec3& x, TonemapMode mode) {
  // Common.hlsl: ApplyTonemap: ACES on unity_to_ACES(input) (sRGB_2_AP0), Neutral, then saturate.
  Vec3 out = x;
  if (mode == TonemapMode::kAces) out = aces_tonemap(kSrgbToAp0 * x);
  if (mode == TonemapMode::kNeutral) out = neutral_tonemap(x);
  return saturate(out);
}

// --- The grade -------------------------------------------------------------------------------

GradingMode grading_mode(const ParamBlock& p) {
  return p.urp_grading_mode == 1 ? GradingMode::kHighDynamicRange : GradingMode::kLowDynamicRange;
}

TonemapMode tonemap_mode(const ParamBlock& p) {
  return p.urp_tonemap_mode == 2   ? TonemapMode::kAces
         : p.urp_tonemap_mode == 1 ? TonemapMode::kNeutral
                                   : TonemapMode::kNone;
}

bool grades_in_aces(const ParamBlock& p) {
  return grading_mode(p) == GradingMode::kHighDynamicRange && tonemap_mode(p) == TonemapMode::kAces;
}

namespace {
// Common.hlsl: GetLuminance: AcesLuminance under _TONEMAP_ACES, Luminance otherwise.
double grade_luminance(const Vec3& c, bool aces) {
  return aces ? luminance_ap1(c) : luminance_rec709(c);
}
}  // namespace

Vec3 white_balance(const Vec3& c, const ParamBlock& p) {
  // ColorGrade: colorLMS = LinearToLMS(colorLinear) * _ColorBalance.xyz; LMSToLinear(colorLMS).
  Vec3 lms = kLinearToLms * c;
  for (int i = 0; i < 3; ++i) lms[i] *= p.urp_color_balance[i];
  return kLmsToLinear * lms;
}

Vec3 contrast(const Vec3& c, const ParamBlock& p, bool aces, const LogCParams& k) {
  // ColorGrade: colorLog = (colorLog − ACEScc_MIDGRAY) * _HueSatCon.z + ACEScc_MIDGRAY, in
  // ACES_to_ACEScc(unity_to_ACES(c)) (ACES) or LinearToLogC(c).
  const double gain = p.urp_hue_sat_con[2];
  if (aces) {
    const Vec3 ap0 = kSrgbToAp0 * c;
    Vec3 out;
    for (int i = 0; i < 3; ++i) {
      const double l = (acescc_from_linear(ap0[i]) - kAcesccMidgray) * gain + kAcesccMidgray;
      out[i] = linear_from_acescc(l);
    }
    return kAp0ToAp1 * out;  // ACES_to_ACEScg
  }
  Vec3 out;
  for (int i = 0; i < 3; ++i) {
    const double l = (logc_from_linear(c[i], k) - kAcesccMidgray) * gain + kAcesccMidgray;
    out[i] = linear_from_logc(l, k);
  }
  return out;
}

Vec3 color_filter(const Vec3& c, const ParamBlock& p) {
  // colorLinear *= _ColorFilter.xyz; colorLinear = max(0.0, colorLinear).
  Vec3 out;
  for (int i = 0; i < 3; ++i) out[i] = d3d::max_num(0.0, c[i] * p.urp_color_filter[i]);
  return out;
}

Vec3 split_toning(const Vec3& c, const ParamBlock& p, bool aces) {
  // colorGamma = PositivePow(c, 1/2.2); luma = saturate(GetLuminance(saturate(colorGamma)) +
  // balance); shadows = lerp(0.5, _SplitShadows, 1 − luma); highlights = lerp(0.5,
  // _SplitHighlights, luma); two SoftLights; PositivePow(colorGamma, 2.2).
  const double balance = p.urp_split_shadows[3];
  Vec3 gamma;
  for (int i = 0; i < 3; ++i) gamma[i] = positive_pow(c[i], 1.0 / 2.2);
  const double luma = saturate(grade_luminance(saturate(gamma), aces) + balance);
  Vec3 out;
  for (int i = 0; i < 3; ++i) {
    const double sh = lerp(0.5, p.urp_split_shadows[i], 1.0 - luma);
    const double hi = lerp(0.5, p.urp_split_highlights[i], luma);
    out[i] = positive_pow(soft_light(soft_light(gamma[i], sh), hi), 2.2);
  }
  return out;
}

Vec3 channel_mixer(const Vec3& c, const ParamBlock& p) {
  // float3(dot(c, _ChannelMixerRed.xyz), dot(c, _ChannelMixerGreen.xyz), dot(c, ...Blue.xyz)).
  return {dot(c, v3(p.urp_channel_mixer_red)), dot(c, v3(p.urp_channel_mixer_green)),
          dot(c, v3(p.urp_channel_mixer_blue))};
}

Vec3 shadows_midtones_highlights(const Vec3& c, const ParamBlock& p, bool aces) {
  // shadowsFactor = 1 − smoothstep(limits.x, limits.y, luma); highlightsFactor =
  // smoothstep(limits.z, limits.w, luma); midtones = 1 − both; c·Sh·wS + c·Mid·wM + c·Hi·wH.
  const double luma = grade_luminance(c, aces);
  const auto& lim = p.urp_sha_hi_limits;
  const double ws = 1.0 - smoothstep(lim[0], lim[1], luma);
  const double wh = smoothstep(lim[2], lim[3], luma);
  const double wm = 1.0 - ws - wh;
  Vec3 out;
  for (int i = 0; i < 3; ++i)
    out[i] = c[i] * p.urp_shadows[i] * ws + c[i] * p.urp_midtones[i] * wm +
             c[i] * p.urp_highlights[i] * wh;
  return out;
}

Vec3 lift_gamma_gain(const Vec3& c, const ParamBlock& p) {
  // colorLinear = colorLinear * _Gain.xyz + _Lift.xyz; sign(c) * pow(abs(c), _Gamma.xyz).
  Vec3 out;
  for (int i = 0; i < 3; ++i) {
    const double x = c[i] * p.urp_gain[i] + p.urp_lift[i];
    out[i] = sign(x) * std::pow(std::fabs(x), p.urp_gamma[i]);
  }
  return out;
}

Vec3 hue_shift(const Vec3& c, const ParamBlock& p) {
  // hsv = RgbToHsv(c); hue = hsv.x + _HueSatCon.x (+ EvaluateCurve(HueVsHue) − 0.5 = 0 at the
  // default curve); hsv.x = RotateHue(hue, 0, 1); HsvToRgb(hsv).
  Vec3 hsv = hsv_from_rgb(c);
  hsv[0] = rotate_hue(hsv[0] + p.urp_hue_sat_con[0], 0.0, 1.0);
  return rgb_from_hsv(hsv);
}

Vec3 saturation(const Vec3& c, const ParamBlock& p, bool aces) {
  // luma = GetLuminance(c); luma + (_HueSatCon.y * satMult) * (c − luma), satMult = 1 at the
  // default curves ((2 · 0.5)³).
  const double luma = grade_luminance(c, aces);
  const double sat_mult = 1.0;
  Vec3 out;
  for (int i = 0; i < 3; ++i) out[i] = luma + (p.urp_hue_sat_con[1] * sat_mult) * (c[i] - luma);
  return out;
}

Vec3 default_yrgb_curves(const Vec3& c, bool hdr) {
  // EvaluateCurve at t + kHalfPixel, twice (master, then R/G/B), on identity curves:
  // clamp(t, 0, 127/128) (docs/spec/unity_urp.md §4). HDR wraps them in FastTonemap /
  // FastTonemapInvert.
  auto curve = [](double t) { return std::clamp(t, 0.0, kCurveCap); };
  if (!hdr) return {curve(c[0]), curve(c[1]), curve(c[2])};
  const double to = 1.0 / (max3(c) + 1.0);  // FastTonemap: c * rcp(Max3(c) + 1)
  Vec3 t = {curve(c[0] * to), curve(c[1] * to), curve(c[2] * to)};
  const double back = 1.0 / (1.0 - max3(t));  // FastTonemapInvert: c * rcp(1 − Max3(c))
  return {t[0] * back, t[1] * back, t[2] * back};
}

Vec3 color_grade(const Vec3& code, const ParamBlock& p, const LogCParams& k) {
  // LutBuilderHdr.shader: ColorGrade.
  const bool aces = grades_in_aces(p);
  Vec3 c = linear_from_logc(code, k);
  c = white_balance(c, p);
  c = contrast(c, p, aces, k);
  c = color_filter(c, p);
  c = split_toning(c, p, aces);
  c = channel_mixer(c, p);
  c = shadows_midtones_highlights(c, p, aces);
  c = lift_gamma_gain(c, p);
  c = hue_shift(c, p);
  c = saturation(c, p, aces);
  c = default_yrgb_curves(c, true);
  for (double& x : c) x = d3d::max_num(0.0, x);
  return c;  // RotateToColorGradeOutputSpace: unchanged without HDR output
}

Vec3 ldr_bake(const Vec3& code, const ParamBlock& p, const LogCParams& k) {
  // LutBuilderLdr.shader: FragLutBuilderLdr (linear lattice, LogC contrast, Rec.709 luminance, no
  // FastTonemap around the curves, saturate at the end).
  Vec3 c = white_balance(code, p);
  c = contrast(c, p, false, k);
  c = color_filter(c, p);
  c = split_toning(c, p, false);
  c = channel_mixer(c, p);
  c = shadows_midtones_highlights(c, p, false);
  c = lift_gamma_gain(c, p);
  c = hue_shift(c, p);
  c = saturation(c, p, false);
  c = default_yrgb_curves(c, false);
  return saturate(c);
}

Vec3 lut_texel(const Vec3& code, const ParamBlock& p, const LogCParams& k) {
  if (grading_mode(p) == GradingMode::kLowDynamicRange) return ldr_bake(code, p, k);
  return hdr_bake_tonemap(color_grade(code, p, k), tonemap_mode(p));
}

// --- The strip -------------------------------------------------------------------------------

Vec3 lattice_code(int size, int r, int g, int b) {
  const double scale = 1.0 / (size - 1);
  return {r * scale, g * scale, b * scale};
}

double quantize_texel(int lut_format, double v) {
  switch (lut_format) {
    case 1:  // RGBA16F: the float32 value rounded to half, nearest even (Imath::half).
      return static_cast<double>(static_cast<float>(Imath::half(static_cast<float>(v))));
    case 3:  // RGBA8 UNORM: nearest k/255 (D3D's float → UNORM; NaN → 0).
      return std::nearbyint(saturate(v) * 255.0) / 255.0;
    default:
      return static_cast<double>(static_cast<float>(v));
  }
}

Image bake_strip(int size, int lut_format, const std::function<Vec3(const Vec3& code)>& texel) {
  Image strip(size * size, size);
  for (int b = 0; b < size; ++b)
    for (int g = 0; g < size; ++g)
      for (int r = 0; r < size; ++r) {
        const Vec3 v = texel(lattice_code(size, r, g, b));
        double* o = strip.px(r + size * b, g);
        for (int c = 0; c < 3; ++c) o[c] = quantize_texel(lut_format, v[c]);
        o[3] = 1.0;
      }
  return strip;
}

Image bake_lut_strip(const ParamBlock& p) {
  return bake_strip(p.lut_size, p.lut_format,
                    [&](const Vec3& code) { return lut_texel(code, p, kUnityLogC); });
}

namespace {
// A hardware bilinear sample of the strip at normalised (u, v), clamp-to-edge, exact weights.
Vec3 sample_bilinear(const Image& strip, double u, double v) {
  const double x = u * strip.width - 0.5, y = v * strip.height - 0.5;
  const double x0 = std::floor(x), y0 = std::floor(y);
  const double fx = x - x0, fy = y - y0;
  auto clampi = [](double i, int n) {  // clamp-to-edge; a NaN coordinate reads texel 0
    return i >= 0 ? static_cast<int>(std::min(i, static_cast<double>(n - 1))) : 0;
  };
  const int xa = clampi(x0, strip.width), xb = clampi(x0 + 1, strip.width);
  const int ya = clampi(y0, strip.height), yb = clampi(y0 + 1, strip.height);
  Vec3 out;
  for (int c = 0; c < 3; ++c) {
    const double top = lerp(strip.px(xa, ya)[c], strip.px(xb, ya)[c], fx);
    const double bottom = lerp(strip.px(xa, yb)[c], strip.px(xb, yb)[c], fx);
    out[c] = lerp(top, bottom, fy);
  }
  return out;
}
}  // namespace

Vec3 apply_lut_2d(const Image& strip, const Vec3& uvw, const std::array<double, 4>& lut_params) {
  // ApplyLut2D: uvw.z *= scaleOffset.z; shift = floor(uvw.z); uvw.xy = uvw.xy * scaleOffset.z *
  // scaleOffset.xy + scaleOffset.xy * 0.5; uvw.x += shift * scaleOffset.y; lerp of the samples at
  // uvw.xy and uvw.xy + (scaleOffset.y, 0) by uvw.z − shift.
  const double z = uvw[2] * lut_params[2];
  const double shift = std::floor(z);
  const double u =
      uvw[0] * lut_params[2] * lut_params[0] + lut_params[0] * 0.5 + shift * lut_params[1];
  const double v = uvw[1] * lut_params[2] * lut_params[1] + lut_params[1] * 0.5;
  const Vec3 a = sample_bilinear(strip, u, v);
  const Vec3 b = sample_bilinear(strip, u + lut_params[1], v);
  const double t = z - shift;
  return {lerp(a[0], b[0], t), lerp(a[1], b[1], t), lerp(a[2], b[2], t)};
}

Vec3 apply_color_grading(const Image& strip, const ParamBlock& p, const Vec3& scene_linear) {
  // ApplyColorGrading: input *= postExposure.
  Vec3 x = scene_linear;
  for (double& c : x) c *= p.urp_post_exposure;
  if (grading_mode(p) == GradingMode::kHighDynamicRange) {
    // inputLutSpace = saturate(LinearToLogC(input)); ApplyLut2D.
    return apply_lut_2d(strip, saturate(logc_from_linear(x)), p.urp_lut_params);
  }
  // input = ApplyTonemap(input); ApplyLut2D (linear coordinates).
  return apply_lut_2d(strip, uber_tonemap(x, tonemap_mode(p)), p.urp_lut_params);
}

std::vector<NamedValue> texel_named_values(const ParamBlock& p, const Vec3& code) {
  std::vector<NamedValue> out;
  const bool hdr = grading_mode(p) == GradingMode::kHighDynamicRange;
  const bool aces = grades_in_aces(p);
  // The same steps, in the same order, as color_grade (HDR) and ldr_bake (LDR).
  add_named(&out, "input", code);
  Vec3 c = hdr ? linear_from_logc(code) : code;
  add_named(&out, "decoded", c);
  c = white_balance(c, p);
  add_named(&out, "white_balanced", c);
  c = contrast(c, p, aces);
  add_named(&out, "contrast", c);
  c = color_filter(c, p);
  add_named(&out, "color_filtered", c);
  c = split_toning(c, p, aces);
  add_named(&out, "split_toned", c);
  c = channel_mixer(c, p);
  add_named(&out, "channel_mixed", c);
  c = shadows_midtones_highlights(c, p, aces);
  add_named(&out, "smh", c);
  c = lift_gamma_gain(c, p);
  add_named(&out, "lift_gamma_gain", c);
  add_named(&out, "hsv", hsv_from_rgb(c));
  c = hue_shift(c, p);
  add_named(&out, "hue_shifted", c);
  c = saturation(c, p, aces);
  add_named(&out, "saturated", c);
  c = default_yrgb_curves(c, hdr);
  add_named(&out, "curves", c);
  if (hdr) {
    for (double& x : c) x = d3d::max_num(0.0, x);
    add_named(&out, "graded", c);
    if (tonemap_mode(p) == TonemapMode::kAces) add_named(&out, "aces", kAp1ToAp0 * c);
    c = hdr_bake_tonemap(c, tonemap_mode(p));
  } else {
    c = saturate(c);
  }
  add_named(&out, "out", c);
  Vec3 stored;
  for (int i = 0; i < 3; ++i) stored[i] = quantize_texel(p.lut_format, c[i]);
  add_named(&out, "stored", stored);
  return out;
}

std::vector<NamedValue> named_values(const ParamBlock& p, const Image& strip, const Vec3& scene) {
  std::vector<NamedValue> out;
  add_named(&out, "input", scene);
  Vec3 x = scene;
  for (double& c : x) c *= p.urp_post_exposure;
  add_named(&out, "exposed", x);
  Vec3 uvw;
  if (grading_mode(p) == GradingMode::kHighDynamicRange) {
    const Vec3 logc = logc_from_linear(x);
    add_named(&out, "logc", logc);
    uvw = saturate(logc);
  } else {
    uvw = uber_tonemap(x, tonemap_mode(p));
  }
  add_named(&out, "uvw", uvw);
  // ApplyLut2D's own steps (apply_lut_2d above).
  const std::array<double, 4>& lp = p.urp_lut_params;
  const double z = uvw[2] * lp[2];
  const double shift = std::floor(z);
  add_named(&out, "slice", shift);
  add_named(&out, "slice_frac", z - shift);
  const double u = uvw[0] * lp[2] * lp[0] + lp[0] * 0.5 + shift * lp[1];
  const double v = uvw[1] * lp[2] * lp[1] + lp[1] * 0.5;
  add_named(&out, "u", u);
  add_named(&out, "v", v);
  add_named(&out, "tap0", sample_bilinear(strip, u, v));
  add_named(&out, "tap1", sample_bilinear(strip, u + lp[1], v));
  add_named(&out, "out", apply_color_grading(strip, p, scene));
  return out;
}

Image grade_image(const Image& input, const ParamBlock& p) {
  const Image strip = bake_lut_strip(p);
  Image out(input.width, input.height);
  for (int y = 0; y < input.height; ++y)
    for (int x = 0; x < input.width; ++x) {
      const double* i = input.px(x, y);
      const Vec3 graded = apply_color_grading(strip, p, {i[0], i[1], i[2]});
      double* o = out.px(x, y);
      for (int c = 0; c < 3; ++c) o[c] = graded[c];
      o[3] = i[3];
    }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Device allowances.

namespace {
// Vulkan's float16 rounding modes are RTE and RTZ (VkPhysicalDeviceFloatControlsProperties:
// shaderRoundingModeRTEFloat16 / RTZFloat16): a store that does not guarantee RTE gives the
// nearest half or the one toward zero, not the one away from zero.
double half_toward_zero(double v) {
  return v >= 0 ? half_round_down(v) : half_round_up(v);
}
// The storage neighbour of `v` in `lut_format` (quantize_texel's formats), the lower one for the
// low end of a range and the upper one for its high end (`up`).
double store_end(int lut_format, const DevicePrecision& d, double v, bool up) {
  switch (lut_format) {
    case 1: {
      const double q = quantize_texel(1, v);
      if (d.fp16_rte) return q;
      return up ? std::fmax(q, half_toward_zero(v)) : std::fmin(q, half_toward_zero(v));
    }
    case 3:
      return up ? unorm_ceil(v, 255.0) : unorm_floor(v, 255.0);
    default:
      return up ? float_round_up(v) : float_round_down(v);
  }
}
}  // namespace

// ---------------------------------------------------------------------------------------------
// The bake's texel range on a conformant device: ColorGrade evaluated in interval arithmetic with
// the Vulkan specification's bound of every float32 operation (spirv_precision.h, "Precision and
// Operation of SPIR-V Instructions"), step by step as gpu/shaders/unity_urp/lib/unity_grade.glsl
// runs it. A dark channel of a bright texel is a difference of large terms (the LMS matrices of the
// white balance, the saturation lerp): its range is the subtraction of its inputs' ranges, which a
// relative noise of the texel's largest channel does not bound (PositivePow(x, 1/2.2) of split
// toning then opens a channel near 0 by the slope of x^(1/2.2)).

namespace {

using spirv::Interval;

// A constant as the reference holds it (double) or the shader does (its float32 rounding).
Interval konst(double v) {
  const double f = static_cast<float>(v);
  return {std::fmin(v, f), std::fmax(v, f)};
}
Interval ipt(double v) {
  return Interval::point(v);
}
Interval hull(Interval a, Interval b) {
  return {std::fmin(a.lo, b.lo), std::fmax(a.hi, b.hi)};
}
Interval imax(Interval a, Interval b) {
  return {std::fmax(a.lo, b.lo), std::fmax(a.hi, b.hi)};
}
Interval imin(Interval a, Interval b) {
  return {std::fmin(a.lo, b.lo), std::fmin(a.hi, b.hi)};
}
Interval iclamp(Interval a, double lo, double hi) {
  return {std::clamp(a.lo, lo, hi), std::clamp(a.hi, lo, hi)};
}
Interval iabs(Interval a) {
  if (a.lo >= 0) return a;
  if (a.hi <= 0) return {-a.hi, -a.lo};
  return {0.0, std::fmax(-a.lo, a.hi)};
}
bool finite(Interval a) {
  return std::isfinite(a.lo) && std::isfinite(a.hi);
}
// exp2 with −Inf admitted (exp2(−Inf) = 0).
Interval iexp2(Interval x) {
  if (std::isnan(x.lo) || std::isnan(x.hi)) return {0.0, HUGE_VAL};
  if (!finite(x)) {
    if (x.hi == -HUGE_VAL) return {0.0, 0.0};
    const double lo = x.lo == -HUGE_VAL ? 0.0 : std::fmax(spirv::exp2({x.lo, x.lo}).lo, 0.0);
    const double hi = x.hi == HUGE_VAL ? HUGE_VAL : spirv::exp2({x.hi, x.hi}).hi;
    return {lo, hi};
  }
  Interval r = spirv::exp2(x);
  return {std::fmax(r.lo, 0.0), r.hi};  // a device's exp2 is never negative: IEEE ordering
}
// log2 of x ≥ 0 (the argument's lower end at or below 0 admits −Inf: log2_d3d(0) = −Inf).
Interval ilog2(Interval x) {
  if (x.hi <= 0) return {-HUGE_VAL, -HUGE_VAL};
  if (x.lo <= 0) return {-HUGE_VAL, spirv::log2({x.hi, x.hi}).hi};
  return spirv::log2(x);
}
// Common.hlsl PositivePow / pow_d3d(|x|, y), y > 0: 0 at 0, else exp2(y·log2|x|); nondecreasing
// in |x|.
Interval ipow(Interval x, double y) {
  x = iabs(x);
  const Interval r = iexp2(spirv::mul(ilog2(x), konst(y)));
  return {x.lo == 0 ? 0.0 : r.lo, x.hi == 0 ? 0.0 : r.hi};
}
// sign(x)·pow(|x|, y): nondecreasing, odd.
Interval signed_pow(Interval x, double y) {
  auto end = [&](double v, bool low) {
    if (v == 0) return 0.0;
    const Interval r = ipow(ipt(v), y);
    return v > 0 ? (low ? r.lo : r.hi) : (low ? -r.hi : -r.lo);
  };
  return {end(x.lo, true), end(x.hi, false)};
}
// sqrt: inherited from 1.0 / inversesqrt(x), inversesqrt 2 ULP (spirvenv-op-prec). x ≥ 0.
Interval isqrt(Interval x) {
  x = {std::fmax(x.lo, 0.0), std::fmax(x.hi, 0.0)};
  if (x.hi == 0) return {0.0, 0.0};
  const Interval rs =
      spirv::widen_ulp({1.0 / std::sqrt(x.hi), x.lo > 0 ? 1.0 / std::sqrt(x.lo) : HUGE_VAL}, 2.0);
  Interval r =
      x.lo > 0 ? spirv::div(ipt(1.0), rs) : Interval{0.0, spirv::div(ipt(1.0), {rs.lo, rs.lo}).hi};
  return {std::fmax(r.lo, 0.0), r.hi};
}

// The specification's bounds (spirv_precision.h) with unbounded ends kept: an infinite end stays
// as it is (no ULP to widen by), and a product of 0 and an unbounded end is 0 (the end stands for
// "arbitrarily large", not for an infinite value).
double widen_end(double v, double n, bool up) {
  if (!std::isfinite(v)) return v;
  return up ? v + n * spirv::ulp32(v) : v - n * spirv::ulp32(v);
}
Interval widen(Interval r, double n) {
  return {widen_end(r.lo, n, false), widen_end(r.hi, n, true)};
}
double prod(double a, double b) {
  return a == 0 || b == 0 ? 0.0 : a * b;
}
Interval iadd(Interval a, Interval b) {
  return widen({a.lo + b.lo, a.hi + b.hi}, 0.5);
}
Interval isub(Interval a, Interval b) {
  return widen({a.lo - b.hi, a.hi - b.lo}, 0.5);
}
Interval imul_exact(Interval a, Interval b) {
  const double q[4] = {prod(a.lo, b.lo), prod(a.lo, b.hi), prod(a.hi, b.lo), prod(a.hi, b.hi)};
  return {*std::min_element(q, q + 4), *std::max_element(q, q + 4)};
}
Interval imul(Interval a, Interval b) {
  return widen(imul_exact(a, b), 0.5);
}
// a·b + c, fused or not: the unfused bound contains the fused one (spirv_precision.h mul_add).
Interval imad(Interval a, Interval b, Interval c) {
  return iadd(imul(a, b), c);
}
// OpFDiv, 2.5 ULP; b must not contain 0 (the callers divide by constants and by ranges above 0).
Interval idiv(Interval a, Interval b) {
  const double q[4] = {a.lo / b.lo, a.lo / b.hi, a.hi / b.lo, a.hi / b.hi};
  return widen({*std::min_element(q, q + 4), *std::max_element(q, q + 4)}, 2.5);
}

using IV3 = std::array<Interval, 3>;

IV3 mat_mul(const Mat3& m, const IV3& v) {
  IV3 out;
  for (int i = 0; i < 3; ++i)
    out[i] = imad(konst(m(i, 2)), v[2], imad(konst(m(i, 1)), v[1], imul(konst(m(i, 0)), v[0])));
  return out;
}
Interval idot(const IV3& v, const Vec3& w) {
  return imad(konst(w[2]), v[2], imad(konst(w[1]), v[1], imul(konst(w[0]), v[0])));
}

// LogCToLinear: (pow10_d3d((x − d)/c) − b)/a, pow10_d3d(y) = exp2(y·LOG2_OF_10).
Interval linear_from_logc_dev(Interval x) {
  const LogCParams& k = kUnityLogC;
  const Interval y = idiv(isub(x, konst(k.d)), konst(k.c));
  const Interval p = iexp2(imul(y, konst(std::log2(10.0))));
  return idiv(isub(p, konst(k.b)), konst(k.a));
}
// LinearToLogC: c·(log2_d3d(max(a·x + b, 0))·LOG10_OF_2) + d.
Interval logc_from_linear_dev(Interval x) {
  const LogCParams& k = kUnityLogC;
  Interval arg = imad(konst(k.a), x, konst(k.b));
  arg = imax(arg, ipt(0.0));
  const Interval l = imul(ilog2(arg), konst(std::log10(2.0)));
  return imad(konst(k.c), l, konst(k.d));
}

// SoftLight: both branches where blend ≥ 0.5 is undecided.
Interval soft_light_dev(Interval base, Interval blend) {
  base = {std::fmax(base.lo, 0.0), std::fmax(base.hi, 0.0)};
  auto r1 = [&] {
    return iadd(imul(imul(ipt(2.0), base), blend),
                imul(imul(base, base), isub(ipt(1.0), imul(ipt(2.0), blend))));
  };
  auto r2 = [&] {
    return iadd(imul(isqrt(base), isub(imul(ipt(2.0), blend), ipt(1.0))),
                imul(imul(ipt(2.0), base), isub(ipt(1.0), blend)));
  };
  if (blend.lo >= 0.5) return r2();
  if (blend.hi < 0.5) return r1();
  return hull(r1(), r2());
}

// smoothstep_d3d(a, b, x) over an interval x.
Interval smoothstep_dev(double a, double b, Interval x) {
  if (a == b) {
    // (x − a)/0: ±Inf or NaN; saturate: 1 above a, 0 at or below it.
    return {x.lo > a ? 1.0 : 0.0, x.hi > a ? 1.0 : 0.0};
  }
  Interval t = idiv(isub(x, konst(a)), isub(konst(b), konst(a)));
  t = iclamp(t, 0.0, 1.0);
  return iclamp(imul(imul(t, t), isub(ipt(3.0), imul(ipt(2.0), t))), 0.0, 1.0);
}

// saturate(|frac(t)·6 − 3| − 1) over t, exactly: piecewise linear with corners at multiples of 1/6.
Interval hsv_channel(Interval t) {
  auto f = [](double v) {
    return std::clamp(std::fabs((v - std::floor(v)) * 6.0 - 3.0) - 1.0, 0.0, 1.0);
  };
  if (!finite(t) || t.hi - t.lo >= 1.0) return {0.0, 1.0};
  double lo = std::fmin(f(t.lo), f(t.hi)), hi = std::fmax(f(t.lo), f(t.hi));
  for (double k = std::floor(t.lo * 6.0) + 1; k / 6.0 < t.hi; k += 1) {
    lo = std::fmin(lo, f(k / 6.0));
    hi = std::fmax(hi, f(k / 6.0));
  }
  // The float32 steps after t: fract (x − floor x, 0.5 ULP of t), ·6 (the ULP scaled by 6, 0.5
  // ULP of 6), − 3 (0.5 ULP of 3), − 1 (0.5 ULP of 2).
  const double big = std::fmax(std::fabs(t.lo), std::fabs(t.hi));
  const double e =
      3.0 * spirv::ulp32(big) + 0.5 * (spirv::ulp32(6.0) + spirv::ulp32(3.0) + spirv::ulp32(2.0));
  return {std::fmax(lo - e, 0.0), std::fmin(hi + e, 1.0)};
}

// Steps 10: RgbToHsv (every branch of its two step()s the ranges leave undecided), the hue offset
// and RotateHue, HsvToRgb. HsvToRgb is 1-periodic in the hue, so RotateHue's ±1 changes only the
// rounding of the hue (0.5 ULP of values up to 2): the hue is carried unwrapped.
IV3 hue_shift_dev(const IV3& c, const ParamBlock& p) {
  const Interval everything = {-HUGE_VAL, HUGE_VAL};
  IV3 out;
  bool any = false;
  const Interval r = c[0], g = c[1], b = c[2];
  for (const bool gb : {true, false}) {
    if (gb && !(g.hi >= b.lo)) continue;
    if (!gb && !(g.lo < b.hi)) continue;
    const std::array<Interval, 4> pv =
        gb ? std::array<Interval, 4>{g, b, ipt(0.0), konst(-1.0 / 3.0)}
           : std::array<Interval, 4>{b, g, ipt(-1.0), konst(2.0 / 3.0)};
    for (const bool rp : {true, false}) {
      if (rp && !(r.hi >= pv[0].lo)) continue;
      if (!rp && !(r.lo < pv[0].hi)) continue;
      const std::array<Interval, 4> q = rp ? std::array<Interval, 4>{r, pv[1], pv[2], pv[0]}
                                           : std::array<Interval, 4>{pv[0], pv[1], pv[3], r};
      // Within the branch q.x is the largest of q.x, q.y, q.w, so d = q.x − min(q.w, q.y) ≥ 0 and
      // |q.w − q.y| ≤ d exactly, and so after rounding (monotone): the ranges, taken channel by
      // channel, are narrowed to what the branch implies.
      Interval d = isub(q[0], imin(q[3], q[1]));
      if (d.hi < 0) continue;  // the branch cannot be taken
      d.lo = std::fmax(d.lo, 0.0);
      Interval num = isub(q[3], q[1]);
      num = {std::fmax(num.lo, -d.hi), std::fmin(num.hi, d.hi)};
      const Interval e = konst(1.0e-4);
      const Interval den = imad(ipt(6.0), d, e);
      const Interval den2 = iadd(q[0], e);
      if (!(den.lo > 0) || !(den2.lo > 0)) return {everything, everything, everything};
      const Interval h = iabs(iadd(q[2], idiv(num, den)));
      const Interval s = idiv(d, den2);
      const Interval v = q[0];
      Interval hue = iadd(h, konst(p.urp_hue_sat_con[0]));
      hue = {hue.lo - 0.5 * spirv::ulp32(2.0), hue.hi + 0.5 * spirv::ulp32(2.0)};
      const double kk[3] = {1.0, 2.0 / 3.0, 1.0 / 3.0};
      for (int i = 0; i < 3; ++i) {
        const Interval f = hsv_channel(iadd(hue, konst(kk[i])));
        // lerp_d3d(1, f, s) = 1 + s·(f − 1), then v·that.
        const Interval l = imad(s, isub(f, ipt(1.0)), ipt(1.0));
        const Interval o = imul(v, l);
        out[i] = any ? hull(out[i], o) : o;
      }
      any = true;
    }
  }
  if (!any) return {everything, everything, everything};
  return out;
}

// Step 12 (HDR): t = clamp(c·rcp(Max3(c) + 1), 0, 127/128), t·rcp(1 − Max3(t)). Exactly c_i while
// Max3(c) ≤ 127, else 128·min(c_i/(Max3 + 1), 127/128): nondecreasing in c_i ≥ 0, nonincreasing in
// Max3, evaluated at the box's corners. Rounding: Max3 + 1 (0.5 ULP), rcp (OpFDiv, 2.5), the
// product (0.5) give t within 3.5 ULP of t, relative 3.5·2^-23; 1 − Max3(t) (0.5 ULP) carries Max3
// (t)'s error divided by 1 − Max3(t), then rcp (2.5) and the last product (0.5): relative
// 3.5·2^-23·tmax/(1 − tmax) + 7·2^-23 of the output.
IV3 hdr_curves_dev(const IV3& c) {
  Interval m = imax(imax(c[0], c[1]), c[2]);
  m = {std::fmax(m.lo, 0.0), std::fmax(m.hi, 0.0)};
  auto exact = [](double ci, double mx) {
    return std::clamp(ci / (mx + 1), 0.0, kCurveCap) / (1.0 - std::fmin(mx / (mx + 1), kCurveCap));
  };
  const double tmax = std::fmin(m.hi / (m.hi + 1), kCurveCap);
  const double rel = 0x1p-23 * (3.5 * tmax / (1 - tmax) + 7.0);
  IV3 out;
  for (int i = 0; i < 3; ++i) {
    const double lo = exact(c[i].lo, m.hi), hi = exact(c[i].hi, m.lo);
    out[i] = {lo - rel * std::fabs(lo), hi + rel * std::fabs(hi)};
  }
  return out;
}

// LutBuilderHdr ColorGrade / LutBuilderLdr FragLutBuilderLdr (grading in Rec.709: not ACES) over
// the lattice code, as unity_grade.glsl's steps.
IV3 grade_dev(const Vec3& code, const ParamBlock& p, bool hdr) {
  IV3 c;
  for (int i = 0; i < 3; ++i) {
    // urp_lattice_code: texel / float(size − 1), one division.
    const Interval t = spirv::widen_ulp(ipt(code[i]), 2.5);
    c[i] = hdr ? linear_from_logc_dev(t) : t;
  }
  // White balance: LMS matrix, the balance, back.
  c = mat_mul(kLinearToLms, c);
  for (int i = 0; i < 3; ++i) c[i] = imul(c[i], ipt(p.urp_color_balance[i]));
  c = mat_mul(kLmsToLinear, c);
  // Contrast in LogC.
  for (int i = 0; i < 3; ++i) {
    const Interval l = imad(isub(logc_from_linear_dev(c[i]), konst(kAcesccMidgray)),
                            ipt(p.urp_hue_sat_con[2]), konst(kAcesccMidgray));
    c[i] = linear_from_logc_dev(l);
  }
  // Colour filter, max(0, ·).
  for (int i = 0; i < 3; ++i) c[i] = imax(imul(c[i], ipt(p.urp_color_filter[i])), ipt(0.0));
  // Split toning.
  {
    IV3 g;
    for (int i = 0; i < 3; ++i) g[i] = ipow(c[i], 1.0 / 2.2);
    IV3 gs;
    for (int i = 0; i < 3; ++i) gs[i] = iclamp(g[i], 0.0, 1.0);
    const Interval luma =
        iclamp(iadd(idot(gs, kRec709RgbToY), ipt(p.urp_split_shadows[3])), 0.0, 1.0);
    for (int i = 0; i < 3; ++i) {
      const Interval sh =
          imad(isub(ipt(1.0), luma), isub(ipt(p.urp_split_shadows[i]), ipt(0.5)), ipt(0.5));
      const Interval hi = imad(luma, isub(ipt(p.urp_split_highlights[i]), ipt(0.5)), ipt(0.5));
      c[i] = ipow(soft_light_dev(soft_light_dev(g[i], sh), hi), 2.2);
    }
  }
  // Channel mixer.
  {
    const IV3 in = c;
    c[0] = idot(in, v3(p.urp_channel_mixer_red));
    c[1] = idot(in, v3(p.urp_channel_mixer_green));
    c[2] = idot(in, v3(p.urp_channel_mixer_blue));
  }
  // Shadows / midtones / highlights.
  {
    const Interval luma = idot(c, kRec709RgbToY);
    const auto& lim = p.urp_sha_hi_limits;
    const Interval ws = isub(ipt(1.0), smoothstep_dev(lim[0], lim[1], luma));
    const Interval wh = smoothstep_dev(lim[2], lim[3], luma);
    const Interval wm = isub(isub(ipt(1.0), ws), wh);
    for (int i = 0; i < 3; ++i)
      c[i] = iadd(iadd(imul(imul(c[i], ipt(p.urp_shadows[i])), ws),
                       imul(imul(c[i], ipt(p.urp_midtones[i])), wm)),
                  imul(imul(c[i], ipt(p.urp_highlights[i])), wh));
  }
  // Lift, gamma, gain.
  for (int i = 0; i < 3; ++i)
    c[i] = signed_pow(imad(c[i], ipt(p.urp_gain[i]), ipt(p.urp_lift[i])), p.urp_gamma[i]);
  c = hue_shift_dev(c, p);
  // Saturation: luma + k·(c − luma).
  {
    const Interval luma = idot(c, kRec709RgbToY);
    for (int i = 0; i < 3; ++i) c[i] = imad(ipt(p.urp_hue_sat_con[1]), isub(c[i], luma), luma);
  }
  if (hdr) {
    c = hdr_curves_dev(c);
    for (int i = 0; i < 3; ++i) c[i] = imax(c[i], ipt(0.0));
  } else {
    for (int i = 0; i < 3; ++i) c[i] = iclamp(iclamp(c[i], 0.0, kCurveCap), 0.0, 1.0);
  }
  return c;
}

}  // namespace

Range3 lut_texel_device_range(const Vec3& code, const ParamBlock& p) {
  const Vec3 v = lut_texel(code, p, kUnityLogC);
  double big = 0;
  for (int c = 0; c < 3; ++c)
    if (std::isfinite(v[c])) big = std::fmax(big, std::fabs(v[c]));
  const double e = kFloat32Noise * big;
  Range3 r;
  for (int c = 0; c < 3; ++c) {
    r.lo[c] = v[c] - e;
    r.hi[c] = v[c] + e;
    r.nan[c] = std::isnan(v[c]);
  }
  if (grades_in_aces(p)) return r;  // ACES spaces and the ACES tone map: not derived yet
  const bool hdr = grading_mode(p) == GradingMode::kHighDynamicRange;
  IV3 dev = grade_dev(code, p, hdr);
  if (hdr && tonemap_mode(p) == TonemapMode::kNeutral)
    for (Interval& i : dev) {
      // NeutralTonemap is nondecreasing per channel: its value at the ends, with kFloat32Noise
      // for its own arithmetic.
      const double a = operators::unity_neutral(i.lo), z = operators::unity_neutral(i.hi);
      i = {a - kFloat32Noise * std::fabs(a), z + kFloat32Noise * std::fabs(z)};
    }
  for (int c = 0; c < 3; ++c)
    if (!std::isnan(v[c]) && !std::isnan(dev[c].lo) && !std::isnan(dev[c].hi)) {
      r.lo[c] = std::fmin(r.lo[c], dev[c].lo);
      r.hi[c] = std::fmax(r.hi[c], dev[c].hi);
    }
  return r;
}

StripRange bake_lut_strip_device_range(const ParamBlock& p, const DevicePrecision& d) {
  const int n = p.lut_size;
  StripRange s{Image(n * n, n), Image(n * n, n)};
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) {
        const Vec3 code = lattice_code(n, r, g, b);
        const Vec3 v = lut_texel(code, p, kUnityLogC);
        const Range3 range = lut_texel_device_range(code, p);
        double* lo = s.lo.px(r + n * b, g);
        double* hi = s.hi.px(r + n * b, g);
        for (int c = 0; c < 3; ++c) {
          const double q = quantize_texel(p.lut_format, v[c]);  // the tight texel
          if (std::isnan(v[c])) {
            lo[c] = hi[c] = q;
            continue;
          }
          lo[c] = std::fmin(q, store_end(p.lut_format, d, range.lo[c], false));
          hi[c] = std::fmax(q, store_end(p.lut_format, d, range.hi[c], true));
        }
        lo[3] = hi[3] = 1.0;
      }
  return s;
}

Range3 apply_color_grading_device_range(const StripRange& bounds, const ParamBlock& p,
                                        const Vec3& scene_linear, int sub_texel_bits,
                                        bool snap_weights) {
  Vec3 x = scene_linear;
  for (double& c : x) c *= p.urp_post_exposure;
  const Vec3 coord = grading_mode(p) == GradingMode::kHighDynamicRange
                         ? saturate(logc_from_linear(x))
                         : uber_tonemap(x, tonemap_mode(p));
  // ApplyLut2D's sampling is strip_lookup_device_range's: with scaleOffset = (1/W, 1/H, H − 1),
  // u·W − 0.5 = uvw.x·(H − 1) + H·floor(uvw.z·(H − 1)), v·H − 0.5 = uvw.y·(H − 1).
  // The filter's own arithmetic in the strip's storage precision (device_allowance.h
  // FilterArithmetic, VK-GL-CTS's filtering precision): RGBA16F, RGBA8 UNORM, else RGBA32F.
  const FilterArithmetic fa = p.lut_format == 1   ? FilterArithmetic::float16()
                              : p.lut_format == 3 ? FilterArithmetic::unorm(8)
                                                  : FilterArithmetic::float32();
  return strip_lookup_device_range({&bounds.lo, &bounds.hi, p.lut_size}, Range3::point(coord),
                                   sub_texel_bits, kFloat32Noise, fa, snap_weights);
}

}  // namespace hdrc::ref::unity_urp
