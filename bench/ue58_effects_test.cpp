// Pins effects of docs/ue58-decisions.md F ("5.5 -> 5.8 differences, measured") against the same
// effects computed by hand from the formulas, so that the table cannot drift silently: the
// measurement (bench/ue58_effects.h, through the double references) and a hand computation here
// (ST 2084's constants, GammaCorrectionCommon.ush's LogToLin/LinToLog, 10-bit UNORM rounding and a
// linear interpolation) must agree, and both must give the documented numbers.
//
// The hand computations use device 7 (LinearEXR: the LUT stores LinearToST2084 of the graded
// colour, PostProcessCombineLUTs.usf) with ExpandGamut 0, where every CombineLUTs step is the
// identity on each channel alone (white balance, ColorCorrect and the fade at their defaults;
// WorkingColorSpace.ToAP1 then AP1_2_Output within float of the identity), so that the trilinear
// lookup of a grey reduces to a linear interpolation between two stored values per channel.
#include "bench/ue58_effects.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "reference/ue/ue58/ue58_combine_luts.h"

namespace {

using namespace hdrc::ue58fx;

// SMPTE ST 2084 by hand: nits -> signal and back.
constexpr double kM1 = 2610.0 / 16384, kM2 = 2523.0 / 4096 * 128, kC1 = 3424.0 / 4096,
                 kC2 = 2413.0 / 4096 * 32, kC3 = 2392.0 / 4096 * 32;
double pq(double nits) {
  const double l = std::pow(std::max(nits, 0.0) / 10000, kM1);
  return std::pow((kC1 + kC2 * l) / (1 + kC3 * l), kM2);
}
double pq_inv(double e) {
  const double p = std::pow(e, 1 / kM2);
  return 10000 * std::pow(std::max(p - kC1, 0.0) / (kC2 - kC3 * p), 1 / kM1);
}
// GammaCorrectionCommon.ush: LogToLin(x) = exp2((x - 444/1023) * 14) * 0.18 and its inverse,
// saturated.
double log_to_lin(double x) {
  return std::exp2((x - 444.0 / 1023.0) * 14.0) * 0.18;
}
double lin_to_log(double l) {
  return std::clamp(std::log2(l / 0.18) / 14.0 + 444.0 / 1023.0, 0.0, 1.0);
}
double unorm10(double v) {
  return std::round(std::clamp(v, 0.0, 1.0) * 1023.0) / 1023.0;
}

constexpr int kLutSize = 32;  // r.LUT.Size

// Device 7's output for grey x, in 10-bit PQ codes (the signal is PQ, so codes = 1023 * signal):
// the shaper encode, the two stored neighbours (LinearToST2084 of the decoded lattice value, as
// 10-bit UNORM after the scale k = LUTInvMax), interpolated, times 1/k.
double device7_code(double x, bool pq_shaper, double k) {
  const double e = pq_shaper ? pq(100 * x) : lin_to_log(x + log_to_lin(0));
  const double pos = e * (kLutSize - 1);
  const int i0 = std::min(static_cast<int>(std::floor(pos)), kLutSize - 1);
  const int i1 = std::min(i0 + 1, kLutSize - 1);
  const double t = pos - std::floor(pos);
  const auto stored = [&](int i) {
    const double c = static_cast<double>(i) / (kLutSize - 1);
    const double linear = pq_shaper ? pq_inv(c) / 100 : log_to_lin(c) - log_to_lin(0);
    return unorm10(pq(linear) * k) / k;
  };
  return 1023.0 * ((1 - t) * stored(i0) + t * stored(i1));
}

Config device7(bool pq_shaper, bool lut_105) {
  Config c;
  c.cvars = {{"r.HDR.Display.OutputDevice", 7}};
  c.settings = {{"ExpandGamut", 0}, {"r.LUT.Shaper", pq_shaper ? 1 : 0}};
  if (lut_105)
    c.tweak = [](hdrc::ParamBlock& p) { p.ue58_lut_inv_max = static_cast<double>(1.f / 1.05f); };
  return c;
}

struct HandMax {
  double max = 0;
  double at = 0;
};

// L7 (r.LUT.Shaper 0: the log lattice for every device, 5.5 used PQ for devices >= 3): on the
// grey ramp of device 7 the log shaper's top, LogToLin(1) - LogToLin(0) = 43.7, clips the brighter
// greys, which the PQ lattice (to 100 = 10 000 nits) keeps.
TEST(Ue58Effects, ShaperLogVsPqOnDevice7GreysByHand) {
  Path a(device7(true, false)), b(device7(false, false));
  const auto greys = grey_ramp();
  const Effect e = measure(a, b, greys);
  EXPECT_EQ(e.unit, "10-bit PQ codes");
  HandMax hand;
  for (const Stimulus& s : greys) {
    const double d = std::fabs(device7_code(s.x[0], true, 1) - device7_code(s.x[0], false, 1));
    if (d > hand.max) hand = {d, s.x[0]};
  }
  EXPECT_NEAR(e.max, hand.max, 1e-6)
      << "worst grey by hand " << hand.at << ", measured " << e.worst;
  // The documented size (docs/ue58-decisions.md F, L7 device 7 greys): 83.0 codes at the top grey,
  // where the log lattice holds PQ(43.7) and the PQ lattice PQ(256).
  EXPECT_NEAR(hand.max, 83.0, 0.05);
  EXPECT_NEAR(log_to_lin(1) - log_to_lin(0), 43.705, 0.0005);
  // Per grey too, not only the maximum.
  for (const double x : {0.001, 0.18, 1.0, 10.0, 100.0}) {
    SCOPED_TRACE(x);
    EXPECT_NEAR(1023 * a.signal({x, x, x})[1], device7_code(x, true, 1), 1e-6);
    EXPECT_NEAR(1023 * b.signal({x, x, x})[1], device7_code(x, false, 1), 1e-6);
  }
}

// L8 (LUTInvMax 1 instead of 1/1.05 outside Filmic devices 0, 1, 9): the stored 10-bit step is
// 1/1023 instead of 1.05/1023, so a value moves by less than one code.
TEST(Ue58Effects, LutScaleOnDevice7GreysByHand) {
  Path a(device7(false, true)), b(device7(false, false));
  const auto greys = grey_ramp();
  const Effect e = measure(a, b, greys);
  const double k = static_cast<double>(1.f / 1.05f);
  HandMax hand;
  for (const Stimulus& s : greys) {
    const double d = std::fabs(device7_code(s.x[0], false, k) - device7_code(s.x[0], false, 1));
    if (d > hand.max) hand = {d, s.x[0]};
  }
  EXPECT_NEAR(e.max, hand.max, 1e-6) << "worst grey by hand " << hand.at;
  EXPECT_LT(hand.max, 1.0);
  EXPECT_NEAR(hand.max, 0.866, 0.0005);  // docs/ue58-decisions.md F, L8 device 7 greys
}

// L6 (paper white): TotalSceneColorMultiplier = PaperWhite / 203 * 1.5 scales the graded colour
// before the ACES 2.0 transform, so with the inner transform evaluated exactly the outer texel of
// colour x at paper white 406 is the texel of 2x at 203 (GetInnerLUTParameters; at the default 203
// the factor is 1.5, 5.5's ACESSceneColorMultiplier: no change).
TEST(Ue58Effects, PaperWhiteIsAnExposureBeforeTheTransform) {
  const auto params = [](double paper_white) {
    Config c;
    c.cvars = {{"r.HDR.Display.OutputDevice", 3},
               {"r.HDR.Display.ColorGamut", 2},
               {"r.HDR.EnableHDROutput", 1}};
    c.settings = {{"TonemappingMethod", 1}, {"ExpandGamut", 0}, {"r.HDR.PaperWhite", paper_white}};
    return Path(c).params();
  };
  const hdrc::ParamBlock p406 = params(406), p203 = params(203);
  EXPECT_EQ(p406.ue58_total_scene_color_multiplier, 406.0 / 203.0 * 1.5);
  EXPECT_EQ(p203.ue58_total_scene_color_multiplier, 1.5);
  hdrc::ref::ue58::CombineLuts58 l406(p406), l203(p203);
  l406.set_exact_inner(true);
  l203.set_exact_inner(true);
  for (const Vec3& x : {Vec3{0.01, 0.01, 0.01}, Vec3{0.18, 0.18, 0.18}, Vec3{0.4, 0.1, 0.05},
                        Vec3{0.02, 0.3, 0.9}, Vec3{4, 1, 0.5}}) {
    Vec3 e1, e2;
    for (int c = 0; c < 3; ++c) {
      e1[c] = lin_to_log(x[c] + log_to_lin(0));
      e2[c] = lin_to_log(2 * x[c] + log_to_lin(0));
    }
    const Vec3 t1 = l406.outer_texel(e1), t2 = l203.outer_texel(e2);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(t1[c], t2[c], 1e-9) << x[0] << " " << c;
  }
}

// U1 (UI white 300 nits in 5.5, paper white 203 in 5.8): the PQ code difference of the two whites.
TEST(Ue58Effects, UiWhiteByHand) {
  const double hand = 1023 * (pq(300) - pq(203));
  EXPECT_NEAR(pq_code(300) - pq_code(203), hand, 1e-9);
  EXPECT_NEAR(hand, 42.12, 0.005);  // docs/ue58-decisions.md F, U1
}

// U3 and U5 through the two composites (measure_ui) at their worst stimulus, UI white at alpha 0.1
// (premultiplied: 0.1, 0.1, 0.1, 0.1) over a black PQ back buffer (device 3), against the nits
// computed by hand from CompositeUIPixelShader.usf's formulas (grey, so the sRGB->Rec2020 matrix
// drops out): U3, 5.8 at 203 nits: linear blend lerp(0, 203, 0.1) = 20.3 nits, gamma-space blend
// (0.1 (203/10000)^(1/2.4))^2.4 10000 = 203 0.1^2.4 nits (UICompositeBlendInvGamma is the float
// 1.f/2.4f, 4e-8 from 1/2.4); U5, at 300 nits with sRGB: 5.5 decodes the premultiplied code,
// sRGBToLinear(0.1) 300, 5.8 the un-premultiplied one, 0.1 sRGBToLinear(1) 300 = 30 nits.
TEST(Ue58Effects, UiBlendSpaceAndUnpremultiplyByHand) {
  const std::vector<UiStimulus> one = {
      {"ui white a0.1 over black", {pq(0), pq(0), pq(0), 1.0}, {0.1, 0.1, 0.1, 0.1}}};
  const std::vector<std::pair<std::string, double>> d3 = {{"r.HDR.Display.OutputDevice", 3},
                                                          {"r.HDR.Display.ColorGamut", 2},
                                                          {"r.HDR.EnableHDROutput", 1}};
  UiConfig gamma, linear;
  gamma.cvars = linear.cvars = d3;
  linear.settings = {{"r.HDR.UI.CompositeBlend", 1}};
  const double u3 = 1023 * (pq(20.3) - pq(203 * std::pow(0.1, 2.4)));
  EXPECT_NEAR(measure_ui(linear, gamma, one).max, u3, 1e-3);
  EXPECT_NEAR(u3, 224, 0.5);  // docs/ue58-decisions.md F, U3
  auto cv300 = d3;
  cv300.push_back({"r.HDR.UI.Luminance", 300});
  UiConfig u55, u58;
  u55.ue55 = true;
  u55.cvars = u58.cvars = cv300;
  u55.tweak55 = [](hdrc::ref::ui::UiCompositeParams& p) {
    p.min_normal_clamp = hdrc::ref::MinNormalClamp::kOff;
  };
  u58.settings = {{"r.HDR.UI.Luminance.Mode", 1},
                  {"r.HDR.UI.CompositeEOTF", 1},
                  {"r.HDR.UI.CompositeBlend", 1}};
  const double srgb01 = std::pow((0.1 + 0.055) / 1.055, 2.4);  // sRGBToLinear(0.1), 0.1 > 0.04045
  const double u5 = 1023 * (pq(30) - pq(srgb01 * 300));
  EXPECT_NEAR(measure_ui(u55, u58, one).max, u5, 1e-3);
  EXPECT_NEAR(u5, 184, 0.5);  // docs/ue58-decisions.md F, U5
}

}  // namespace
