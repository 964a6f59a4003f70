// The double-precision reference of Unity URP's colour grading (reference/unity_urp/) against
// numbers from outside it:
//  * the hand values of docs/spec/unity_urp.md §6 (LogC, LogC^-1, ACEScc mid grey, the white
//    balance table, Neutral, the ACES fit, the whole bake at default settings), each derived from
//    the formulas as the comments say;
//  * ARRI's published LogC3 EI 800 code for 18 % grey, and OpenColorIO 2.1's built-in ARRI LogC
//    EI 800 and ACEScc transforms;
//  * Unity's fitted ACES against OpenColorIO 2.1's built-in ACES 1.0 SDR video output transform;
//  * round trips, the HSV tie rules, the host derivation, the LUT lattice and lookup;
//  * planted defects: what a one-constant or one-step error does to the baked strip.
#include "reference/unity_urp/unity_urp.h"

#include <OpenColorIO/OpenColorIO.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/case.h"
#include "reference/color/device_allowance.h"
#include "reference/color/strip_device_range.h"
#include "reference/color/ue_matrices.h"
#include "reference/unity_urp/unity_urp_pipeline.h"
#include "reference/unity_urp/unity_urp_settings.h"

namespace {

namespace urp = hdrc::ref::unity_urp;
namespace OCIO = OCIO_NAMESPACE;
using hdrc::Image;
using hdrc::ParamBlock;
using hdrc::SettingValues;
using hdrc::ref::Mat3;
using hdrc::ref::Vec3;

SettingValues new_settings() {
  return SettingValues(&hdrc::unity_urp_setting_table(), &hdrc::unity_urp_setting_choices);
}

// The parameter block of `s` (derive_unity_urp).
ParamBlock derive(const SettingValues& s) {
  ParamBlock p;
  hdrc::derive_unity_urp(s, &p);
  return p;
}

// Defaults with the grading mode and tone mapping given.
ParamBlock defaults(const char* grading, const char* tonemapping, int lut_size = 32) {
  SettingValues s = new_settings();
  EXPECT_TRUE(s.set_choice("GradingMode", grading).ok());
  EXPECT_TRUE(s.set_choice("Tonemapping.mode", tonemapping).ok());
  EXPECT_TRUE(s.set("LutSize", {static_cast<double>(lut_size), 0, 0, 0}, 1).ok());
  return derive(s);
}

Vec3 grey(double v) {
  return {v, v, v};
}

// --- LogC -------------------------------------------------------------------------------------

// Spec §6.1, by hand from Color.hlsl's fast LogC with Unity's EI 1000 constants
// (c = 0.244161, a = 5.555556, b = 0.047996, d = 0.386036):
//  LogC(0.18) = c·log10(5.555556·0.18 + 0.047996) + d = c·log10(1.04809608) + d
//             = 0.244161·0.0204022947 + 0.386036 = 0.391007035;
//  LogC(0)    = c·log10(0.047996) + d = 0.244161·(−1.318795) + d = 0.064037705;
//  LogC(1)    = c·log10(5.603552) + d = 0.244161·0.748463 + d = 0.568781574;
//  LogC^-1(0) = (10^(−0.386036/0.244161) − b)/a = (0.02615 − 0.047996)/a = −0.003916464;
//  LogC^-1(1) = (10^(0.613964/0.244161) − b)/a = (327.0280 − 0.047996)/a = 58.856632978;
//  LogC^-1(0.4135884) = 0.224769766 (the contrast pivot in linear, not 0.18).
TEST(UnityUrpLogC, HandValues) {
  EXPECT_NEAR(urp::logc_from_linear(0.18), 0.391007035, 1e-9);
  EXPECT_NEAR(urp::logc_from_linear(0.0), 0.064037705, 1e-9);
  EXPECT_NEAR(urp::logc_from_linear(1.0), 0.568781574, 1e-9);
  EXPECT_NEAR(urp::linear_from_logc(0.0), -0.003916464, 1e-9);
  EXPECT_NEAR(urp::linear_from_logc(1.0), 58.856632978, 1e-8);
  EXPECT_NEAR(urp::linear_from_logc(urp::kAcesccMidgray), 0.224769766, 1e-9);
  // The log argument a·x + b reaches 0 at x = −b/a = −0.0086393: −Inf there and below (max).
  EXPECT_EQ(urp::logc_from_linear(-0.01), -INFINITY);
}

// ARRI's published LogC3 code for 18 % grey at EI 800 is 0.391007 (ARRI, "ALEXA Log C Curve -
// Usage in VFX", 2017: 18 % grey → 0.391007 at EI 800). Unity's constants are EI 1000's, whose
// 18 % grey code differs by only 2.0e-7: the two curves agree at grey to 6 decimals, and the
// constants differ elsewhere (at 1.0: Unity 0.568782, EI 800 0.570632).
TEST(UnityUrpLogC, ArriEi800GreyAgainstUnityEi1000) {
  const double ei800 = urp::logc_from_linear_precise(0.18, urp::kArriLogC3Ei800);
  EXPECT_NEAR(ei800, 0.391007, 5e-7);     // the published 6-digit value
  EXPECT_NEAR(ei800, 0.391006832, 1e-9);  // by hand: 0.247190·log10(1.052272 ...) + 0.385537
  const double unity = urp::logc_from_linear(0.18);
  const double gap = unity - ei800;
  EXPECT_NEAR(gap, 2.03e-7, 0.05e-7);
  std::printf("LogC(0.18): Unity EI 1000 %.9f, ARRI EI 800 %.9f, gap %.3g\n", unity, ei800, gap);
  // Away from grey the two sets of constants part: at 1.0 EI 800 gives 0.247190·log10(5.607828) +
  // 0.385537 = 0.247190·0.7487947 + 0.385537 = 0.570632, Unity's EI 1000 0.568782.
  EXPECT_NEAR(urp::logc_from_linear_precise(1.0, urp::kArriLogC3Ei800), 0.570632, 1e-6);
}

// OpenColorIO 2.1's built-in "ARRI_ALEXA-LOGC-EI800-AWG_to_ACES2065-1" decodes EI 800 LogC (ARRI's
// piecewise curve), then maps ALEXA Wide Gamut to AP0. Both white points are D60-ish and the
// matrix keeps grey grey, so on grey codes above the linear segment (code > e·cut + f = 0.1497)
// it is the EI 800 decode: our linear_from_logc(EI 800) must match it. Tolerance 1e-5 relative:
// OCIO derives the LogC3 parameters from the exposure index by ARRI's formulas rather than using
// the 6-decimal published table, and evaluates in float32 with approximated exp2/log2; measured
// 5.8e-6 over codes 0.2-0.8.
TEST(UnityUrpLogC, Ei800DecodeMatchesOpenColorIO) {
  auto bt = OCIO::BuiltinTransform::Create();
  bt->setStyle("ARRI_ALEXA-LOGC-EI800-AWG_to_ACES2065-1");
  auto cpu = OCIO::Config::CreateRaw()->getProcessor(bt)->getDefaultCPUProcessor();
  double worst = 0;
  for (double code : {0.2, 0.3, 0.391007, 0.5, 0.6, 0.7, 0.8}) {
    float px[3] = {static_cast<float>(code), static_cast<float>(code), static_cast<float>(code)};
    cpu->applyRGB(px);
    const double ours = urp::linear_from_logc(code, urp::kArriLogC3Ei800);
    for (float v : px) worst = std::max(worst, std::fabs(v - ours) / std::fabs(ours));
  }
  std::printf("LogC EI 800 decode vs OCIO: max relative difference %.3g\n", worst);
  EXPECT_LT(worst, 1e-5);
  EXPECT_NEAR(urp::linear_from_logc(0.391007, urp::kArriLogC3Ei800), 0.18, 1e-6);
}

TEST(UnityUrpLogC, RoundTrips) {
  // Over the lattice's range, and both constant sets.
  for (const urp::LogCParams* k : {&urp::kUnityLogC, &urp::kArriLogC3Ei800}) {
    for (int i = 0; i <= 1000; ++i) {
      const double code = i / 1000.0;
      const double lin = urp::linear_from_logc(code, *k);
      EXPECT_NEAR(urp::logc_from_linear(lin, *k), code, 1e-13) << code;
      if (lin > -0.0039) {
        const double x = std::exp2(-12.0 + 18.0 * i / 1000.0);  // 2^-12 .. 2^6
        EXPECT_NEAR(urp::linear_from_logc(urp::logc_from_linear(x, *k), *k), x, 1e-13 * x + 1e-16);
      }
    }
  }
}

// --- ACEScc -----------------------------------------------------------------------------------

// ACEScc(0.18) = (log2 0.18 + 9.72)/17.52 = (−2.473931188 + 9.72)/17.52 = 0.413588403: Unity's
// ACEScc_MIDGRAY (0.4135884) is this value.
TEST(UnityUrpAcescc, MidGray) {
  EXPECT_NEAR(urp::acescc_from_linear(0.18), 0.413588402, 2e-9);
  EXPECT_NEAR(urp::acescc_from_linear(0.18), urp::kAcesccMidgray, 1e-7);
}

// OpenColorIO 2.1's built-in "ACEScc_to_ACES2065-1" is S-2014-003's decode followed by AP1 → AP0,
// which keeps grey grey; Unity's ACEScc_to_ACES is the same decode (without the matrix).
// Tolerance 2e-5 relative: OCIO's CPU path evaluates float32 with approximated exp2 (measured
// 3-5e-6 on the upper branch, 1.2e-5 on the lower one, where subtracting 2^-16 amplifies it).
TEST(UnityUrpAcescc, DecodeMatchesOpenColorIO) {
  auto bt = OCIO::BuiltinTransform::Create();
  bt->setStyle("ACEScc_to_ACES2065-1");
  auto cpu = OCIO::Config::CreateRaw()->getProcessor(bt)->getDefaultCPUProcessor();
  double worst = 0;
  for (int i = 0; i <= 100; ++i) {
    const double code = -0.35 + 1.8 * i / 100.0;  // across both branches and the HALF_MAX cap
    float px[3] = {static_cast<float>(code), static_cast<float>(code), static_cast<float>(code)};
    cpu->applyRGB(px);
    const double ours = urp::linear_from_acescc(static_cast<float>(code));
    for (float v : px) worst = std::max(worst, std::fabs(v - ours) / std::fabs(ours));
  }
  std::printf("ACEScc decode vs OCIO: max relative difference %.3g\n", worst);
  EXPECT_LT(worst, 2e-5);
}

TEST(UnityUrpAcescc, RoundTrip) {
  for (int i = 0; i <= 200; ++i) {
    const double x = std::exp2(-15.0 + 30.0 * i / 200.0);  // 2^-15 .. 2^15, both branches
    EXPECT_NEAR(urp::linear_from_acescc(urp::acescc_from_linear(x)), x, 1e-12 * x) << x;
  }
  // Below 2^-15 the encode's literal thresholds (0.00003051757, 0.00001525878) are 2^-15 and
  // 2^-16 truncated, so the round trip is close but not exact there.
  const double tiny = 1e-5;
  EXPECT_NEAR(urp::linear_from_acescc(urp::acescc_from_linear(tiny)), tiny, 1e-9);
  // Clamped: negatives encode as 0 does, and HALF_MAX caps the decode.
  EXPECT_EQ(urp::acescc_from_linear(-1.0), urp::acescc_from_linear(0.0));
  EXPECT_EQ(urp::linear_from_acescc(2.0), urp::kHalfMax);
}

// --- HSV ----------------------------------------------------------------------------------------

// RgbToHsv's ties follow HLSL step(a, x) = (x >= a): g = b takes the (g, b, 0, −1/3) branch, and
// r = max takes the (r, ...) branch. By hand:
//  grey (0.5, 0.5, 0.5): p = (0.5, 0.5, 0, −1/3), q = (0.5, 0.5, 0, 0.5), d = 0 → h = 0, s = 0.
//  (1, 1, 0): p = (1, 0, 0, −1/3), q = (1, 0, 0, 1) (r = p.x), d = 1 → h = 1/6.0001, s = 1/1.0001.
//  (0, 1, 1): p = (1, 1, 0, −1/3) (g = b), q = (1, 1, −1/3, 0), d = 1 → h = |−1/3 − 1/6.0001|.
// With the opposite tie rule grey would get h = 2/3 (the other branch's offset) — invisible through
// HsvToRgb while s = 0, but not through a hue-driven curve.
TEST(UnityUrpHsv, TiesFollowHlslStep) {
  Vec3 h = urp::hsv_from_rgb(grey(0.5));
  EXPECT_EQ(h[0], 0.0);
  EXPECT_EQ(h[1], 0.0);
  EXPECT_EQ(h[2], 0.5);
  h = urp::hsv_from_rgb({1, 1, 0});
  EXPECT_DOUBLE_EQ(h[0], 1.0 / 6.0001);
  EXPECT_DOUBLE_EQ(h[1], 1.0 / 1.0001);
  h = urp::hsv_from_rgb({0, 1, 1});
  EXPECT_DOUBLE_EQ(h[0], 1.0 / 3.0 + 1.0 / 6.0001);
  // HsvToRgb ignores the hue at s = 0.
  for (double hue : {0.0, 0.3, 2.0 / 3.0}) {
    const Vec3 c = urp::rgb_from_hsv({hue, 0.0, 0.5});
    EXPECT_EQ(c, grey(0.5));
  }
}

// RgbToHsv's ε = 1e-4 makes the pair inexact. By hand for (0.01, 0.005, 0.002) (g ≥ b, r ≥ g):
// q = (0.01, 0.002, 0, 0.005), d = 0.008, h = 0.003/(0.048 + 0.0001) = 0.0623701,
// s = 0.008/0.0101 = 0.7920792, v = 0.01; back: r = v = 0.01,
// g = v·(1 + s(6h − 1)) = 0.01·(1 − 0.79207921·0.62577963) = 0.0050433297,
// b = v·(1 − s) = 0.002079208: the docs/spec/unity_urp.md §6.6 LDR row (dark colours lose
// saturation).
TEST(UnityUrpHsv, RoundTripIsNotIdentity) {
  const Vec3 c = urp::rgb_from_hsv(urp::hsv_from_rgb({0.01, 0.005, 0.002}));
  EXPECT_NEAR(c[0], 0.01, 1e-15);
  EXPECT_NEAR(c[1], 0.0050433297, 1e-10);
  EXPECT_NEAR(c[2], 0.002079208, 1e-9);
  // For bright colours the error is ~ε relative to the chroma: below 2e-4 of v.
  for (const Vec3& x : {Vec3{1, 0.5, 0.25}, Vec3{0.2, 0.9, 0.4}, Vec3{2, 1, 3}}) {
    const Vec3 y = urp::rgb_from_hsv(urp::hsv_from_rgb(x));
    const double v = std::max({x[0], x[1], x[2]});
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(y[i], x[i], 2e-4 * v);
    EXPECT_NE(y, x);
  }
}

TEST(UnityUrpHsv, RotateHueWrapsOnce) {
  EXPECT_DOUBLE_EQ(urp::rotate_hue(1.25, 0, 1), 0.25);
  EXPECT_DOUBLE_EQ(urp::rotate_hue(-0.25, 0, 1), 0.75);
  EXPECT_EQ(urp::rotate_hue(1.0, 0, 1), 1.0);  // `>`: 1 stays 1
  EXPECT_EQ(urp::rotate_hue(0.0, 0, 1), 0.0);
}

// SoftLight: with blend 0.5 both branches give `base` (the default split toning is neutral); by
// hand SoftLight(0.25, 0.75) = √0.25·0.5 + 2·0.25·0.25 = 0.375, SoftLight(0.25, 0.25) = 2·0.25·0.25
// + 0.0625·0.5 = 0.15625.
TEST(UnityUrpSoftLight, Branches) {
  for (double a : {0.0, 0.1, 0.5, 1.0, 2.0}) EXPECT_DOUBLE_EQ(urp::soft_light(a, 0.5), a);
  EXPECT_DOUBLE_EQ(urp::soft_light(0.25, 0.75), 0.375);
  EXPECT_DOUBLE_EQ(urp::soft_light(0.25, 0.25), 0.15625);
}

// --- Host derivation --------------------------------------------------------------------------

// Spec §6.3 (double evaluation of ColorBalanceToLMSCoeffs); ours is float32 as C# evaluates it.
// The chromaticity → LMS step divides by y and subtracts, so float32 rounding is amplified:
// measured max deviation 7.2e-7 relative (S at (−50, 0)); the tolerance is 1e-6.
TEST(UnityUrpDerive, WhiteBalanceTable) {
  double worst = 0;
  const struct {
    double temperature, tint;
    Vec3 lms;
  } rows[] = {{0, 0, {1.000000400, 0.999999263, 1.000003748}},
              {50, 0, {1.075966476, 1.002321733, 0.712786884}},
              {-50, 0, {0.884846351, 1.041760850, 1.870207103}},
              {0, 50, {1.041004297, 0.937814861, 1.246913332}},
              {100, -100, {1.054395782, 1.544744948, 0.286573122}}};
  for (const auto& r : rows) {
    const auto got = urp::color_balance_to_lms_coeffs(static_cast<float>(r.temperature),
                                                      static_cast<float>(r.tint));
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(got[i], r.lms[i], 1e-6 * r.lms[i]) << r.temperature << " " << r.tint;
      worst = std::max(worst, std::fabs(got[i] - r.lms[i]) / r.lms[i]);
    }
  }
  std::printf("ColorBalanceToLMSCoeffs float32 vs double table: max relative %.3g\n", worst);
  // The default is not an identity: the z coefficient is 1 + 3.7e-6.
  const auto d = urp::color_balance_to_lms_coeffs(0, 0);
  EXPECT_GT(d[2] - 1.0f, 3e-6f);
}

// Spec §1.3: the Rec.709 weights add up to 1.0000001, so the default lift/gamma/gain are off
// identity by ~1e-7 (lift −1.5e-8, gamma 1 + 8e-8, gain 1 − 8e-8 in double; float32 rounds each
// to the nearest float).
TEST(UnityUrpDerive, LiftGammaGainDefaults) {
  const urp::Float4 one = {1, 1, 1, 0};
  const auto lgg = urp::prepare_lift_gamma_gain(one, one, one);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(lgg.lift[i], 0.0f);
    EXPECT_GT(lgg.lift[i], -3e-8f);
    EXPECT_NEAR(lgg.gamma[i], 1.0, 2.4e-7);
    EXPECT_NEAR(lgg.gain[i], 1.0, 2.4e-7);
  }
  EXPECT_NE(lgg.gain[0], 1.0f);
  EXPECT_EQ(lgg.lift[3], 0.0f);
}

TEST(UnityUrpDerive, SettingsToConstants) {
  SettingValues s = new_settings();
  ParamBlock p = derive(s);
  // Defaults: LDR grading, 32³ strip in RGBA8, no tone mapping, exposure 1.
  EXPECT_EQ(p.urp_grading_mode, 0);
  EXPECT_EQ(p.urp_tonemap_mode, 0);
  EXPECT_EQ(p.lut_size, 32);
  EXPECT_EQ(p.lut_layout, 1);
  EXPECT_EQ(p.lut_format, 3);
  EXPECT_EQ(p.urp_post_exposure, 1.0);
  EXPECT_EQ(p.urp_lut_params[0], 1.0 / 1024);
  EXPECT_EQ(p.urp_lut_params[1], 1.0 / 32);
  EXPECT_EQ(p.urp_lut_params[2], 31.0);
  EXPECT_EQ(p.urp_hue_sat_con, (std::array<double, 4>{0, 1, 1, 0}));
  EXPECT_EQ(p.urp_channel_mixer_green, (std::array<double, 4>{0, 1, 0, 0}));
  EXPECT_EQ(p.urp_split_shadows, (std::array<double, 4>{0.5, 0.5, 0.5, 0}));
  EXPECT_EQ(p.urp_sha_hi_limits, (std::array<double, 4>{0, 0.3f, 0.55f, 1}));
  EXPECT_EQ(p.urp_color_filter, (std::array<double, 4>{1, 1, 1, 1}));

  ASSERT_TRUE(s.set_choice("GradingMode", "HighDynamicRange").ok());
  ASSERT_TRUE(s.set_choice("Tonemapping.mode", "ACES").ok());
  ASSERT_TRUE(s.set("LutSize", {33, 0, 0, 0}, 1).ok());  // any integer 16-65
  ASSERT_TRUE(s.set("ColorAdjustments.postExposure", {1.5, 0, 0, 0}, 1).ok());
  ASSERT_TRUE(s.set("ColorAdjustments.hueShift", {90, 0, 0, 0}, 1).ok());
  ASSERT_TRUE(s.set("ColorAdjustments.saturation", {50, 0, 0, 0}, 1).ok());
  ASSERT_TRUE(s.set("ColorAdjustments.contrast", {-50, 0, 0, 0}, 1).ok());
  ASSERT_TRUE(s.set("ColorAdjustments.colorFilter", {0.5, 1, 2, 1}, 4).ok());
  ASSERT_TRUE(s.set("ChannelMixer.redOutGreenIn", {50, 0, 0, 0}, 1).ok());
  ASSERT_TRUE(s.set("SplitToning.balance", {-30, 0, 0, 0}, 1).ok());
  ASSERT_TRUE(s.set("ShadowsMidtonesHighlights.shadows", {0.5, 1, 1, 0.1}, 4).ok());
  ASSERT_TRUE(s.set("ShadowsMidtonesHighlights.highlights", {1, 1, 1, -0.1}, 4).ok());
  p = derive(s);
  EXPECT_EQ(p.urp_grading_mode, 1);
  EXPECT_EQ(p.urp_tonemap_mode, 2);
  EXPECT_EQ(p.lut_size, 33);
  EXPECT_EQ(p.lut_format, 1);
  EXPECT_EQ(p.urp_lut_params[0], 1.0f / 1089.0f);
  EXPECT_EQ(p.urp_lut_params[2], 32.0);
  EXPECT_EQ(p.urp_post_exposure, static_cast<float>(std::pow(2.0, 1.5)));  // 2.828427
  EXPECT_EQ(p.urp_hue_sat_con[0], 0.25);
  EXPECT_EQ(p.urp_hue_sat_con[1], 1.5);
  EXPECT_EQ(p.urp_hue_sat_con[2], 0.5);
  // colorFilter.linear: sRGB EOTF below 1 ((0.555/1.055)^2.4 = 0.2140411), 1, 2^2.2 = 4.5947934.
  EXPECT_NEAR(p.urp_color_filter[0], 0.2140411, 1e-7);
  EXPECT_EQ(p.urp_color_filter[1], 1.0);
  EXPECT_NEAR(p.urp_color_filter[2], 4.5947934, 1e-6);
  EXPECT_EQ(p.urp_channel_mixer_red, (std::array<double, 4>{1, 0.5, 0, 0}));
  EXPECT_EQ(p.urp_split_shadows[3], -0.3f);
  // SMH: w 0.1 → weight 4·0.1 added to the linearised rgb; w −0.1 → weight −0.1.
  EXPECT_NEAR(p.urp_shadows[0], 0.2140411 + 0.4, 1e-7);
  EXPECT_NEAR(p.urp_shadows[1], 1.4, 1e-7);
  EXPECT_NEAR(p.urp_highlights[0], 0.9, 1e-7);
  EXPECT_EQ(p.urp_shadows[3], 0.0);
}

TEST(UnityUrpDerive, TableValidates) {
  SettingValues s = new_settings();
  EXPECT_FALSE(s.set("LutSize", {32.5, 0, 0, 0}, 1).ok());  // not an integer
  EXPECT_FALSE(s.set("LutSize", {66, 0, 0, 0}, 1).ok());
  EXPECT_FALSE(s.set("LutSize", {15, 0, 0, 0}, 1).ok());
  EXPECT_TRUE(s.set_choice("LutSize", "64").ok());
  EXPECT_FALSE(s.set("WhiteBalance.temperature", {101, 0, 0, 0}, 1).ok());
  EXPECT_FALSE(s.set("ChannelMixer.redOutRedIn", {-201, 0, 0, 0}, 1).ok());
  EXPECT_FALSE(s.set_choice("Tonemapping.mode", "Filmic").ok());
  EXPECT_FALSE(s.set("ColorAdjustments.colorFilter", {1, 0, 0, 0}, 1).ok());  // takes 4 numbers
  // Every table entry's default lies in its range, and every named setting has its default named.
  for (const auto& info : hdrc::unity_urp_setting_table()) {
    for (int c = 0; c < info.components; ++c) {
      EXPECT_GE(info.default_value[c], info.min_value) << info.name;
      EXPECT_LE(info.default_value[c], info.max_value) << info.name;
    }
    if (const auto* choices = hdrc::unity_urp_setting_choices(info.name)) {
      const bool named = std::any_of(choices->begin(), choices->end(), [&](const auto& c) {
        return c.value == info.default_value[0];
      });
      EXPECT_TRUE(named) << info.name;
    }
  }
}

// --- Tone mapping -----------------------------------------------------------------------------

// Spec §6.4: Neutral with ws = 1/N(5.3) = 1.313386135, per channel, not clamped above 1.
TEST(UnityUrpTonemap, NeutralTable) {
  const double in[] = {0, 0.01, 0.18, 0.5, 1, 2, 5.3, 10, 58.8};
  const double out[] = {0,           0.010643104, 0.181668635, 0.416090502, 0.631119326,
                        0.838843511, 1.046455202, 1.124189083, 1.207349892};
  for (int i = 0; i < 9; ++i) {
    const Vec3 y = urp::neutral_tonemap({in[i], in[i] * 2, -1});
    EXPECT_NEAR(y[0], out[i], 1e-9) << in[i];
    EXPECT_EQ(y[2], 0.0);  // negatives clamp to 0 first
  }
}

// Spec §6.5, the fit's row: sRGB-linear grey → sRGB_2_AP0 → AcesTonemap, G channel.
TEST(UnityUrpTonemap, AcesFitTable) {
  const double in[] = {0.01, 0.05, 0.18, 0.5, 1, 2, 4, 8, 16, 58.85};
  const double out[] = {0.001198, 0.015045, 0.110172, 0.381319, 0.624745,
                        0.806885, 0.910651, 0.963722, 0.990122, 1.009166};
  for (int i = 0; i < 10; ++i) {
    const Vec3 y = urp::aces_tonemap(urp::kSrgbToAp0 * grey(in[i]));
    EXPECT_NEAR(y[1], out[i], 6e-7) << in[i];
  }
  // Pure red comes out slightly negative in green (no final clamp).
  const Vec3 red = urp::aces_tonemap(urp::kSrgbToAp0 * Vec3{1, 0, 0});
  EXPECT_NEAR(red[0], 0.616949, 1e-6);
  EXPECT_NEAR(red[1], -0.006271, 1e-6);
  EXPECT_NEAR(red[2], 0.002299, 1e-6);
}

// Unity's fitted ACES (AcesTonemap, TONEMAPPING_USE_FULL_ACES 0) against OpenColorIO 2.1's
// built-in ACES 1.0 SDR video output transform ("ACES-OUTPUT - ACES2065-1_to_CIE-XYZ-D65 -
// SDR-VIDEO_1.0": RRT + the Rec.709 100-nit dim ODT up to display-linear CIE XYZ D65), composed
// with CIE XYZ → linear Rec.709 (the normalised primary matrix of BT.709 / D65, inverted) and the
// ODT's [0, 1] clip. Unity's output is clipped to [0, 1] the same way (the uber pass saturates in
// LDR grading; an 8-bit target does in HDR grading).
//
// The residual is the fit itself (docs/spec/unity_urp.md §6.5): Unity replaces the RRT's segmented
// spline c5 and the ODT's c9 (48 nits) plus Y_2_linCV with one rational function of each AP1
// channel, fitted by Stephen Hill (BakingLab, via MJP); it clamps AP1 after the AP0 → AP1 matrix
// instead of AP0 before it, and rounds the matrices and AP1_RGB2Y to 6-10 digits. Measured (OCIO's
// float32 CPU path): grey ramp 2^-8 .. 58.86: max 0.0128 linear at 2.35 (the fit is brighter in the
// upper mid-tones: 0.110 vs 0.104 at 0.18, and reaches 1.0 near 25.7); colours (primaries,
// secondaries, skin, pastels and saturated tints at 2^-6 .. 2^5): max 0.0198 (green x 8).
TEST(UnityUrpTonemap, AcesAgainstOpenColorIoSdrVideo) {
  auto bt = OCIO::BuiltinTransform::Create();
  bt->setStyle("ACES-OUTPUT - ACES2065-1_to_CIE-XYZ-D65 - SDR-VIDEO_1.0");
  auto cpu = OCIO::Config::CreateRaw()->getProcessor(bt)->getDefaultCPUProcessor();
  const Mat3 xyz_to_rec709 =
      hdrc::ref::inverse(hdrc::ref::standard::rgb_to_xyz(hdrc::ref::standard::kSrgb));
  auto clip = [](double v) { return std::clamp(v, 0.0, 1.0); };
  auto compare = [&](const Vec3& srgb_linear, double* worst, Vec3* worst_in) {
    const Vec3 ap0 = urp::kSrgbToAp0 * srgb_linear;
    float px[3] = {static_cast<float>(ap0[0]), static_cast<float>(ap0[1]),
                   static_cast<float>(ap0[2])};
    cpu->applyRGB(px);
    const Vec3 ocio = xyz_to_rec709 * Vec3{px[0], px[1], px[2]};
    const Vec3 unity = urp::aces_tonemap(ap0);
    for (int c = 0; c < 3; ++c) {
      const double d = std::fabs(clip(unity[c]) - clip(ocio[c]));
      if (d > *worst) {
        *worst = d;
        *worst_in = srgb_linear;
      }
    }
  };
  double grey_worst = 0, colour_worst = 0;
  Vec3 grey_at{}, colour_at{};
  for (int i = 0; i <= 200; ++i)
    compare(grey(std::exp2(-8.0 + 13.88 * i / 200.0)), &grey_worst, &grey_at);
  const Vec3 colours[] = {{1, 0, 0},       {0, 1, 0},       {0, 0, 1},        {1, 1, 0},
                          {0, 1, 1},       {1, 0, 1},       {0.8, 0.5, 0.35}, {0.6, 0.8, 1.0},
                          {1.0, 0.7, 0.8}, {0.9, 0.1, 0.1}, {0.1, 0.6, 0.2},  {0.2, 0.3, 0.9},
                          {0.95, 0.9, 0.2}};
  for (const Vec3& c : colours)
    for (int e = -6; e <= 5; ++e) {
      const double k = std::exp2(e);
      compare({c[0] * k, c[1] * k, c[2] * k}, &colour_worst, &colour_at);
    }
  std::printf(
      "Unity ACES fit vs OCIO 2.1 SDR-VIDEO_1.0 (linear Rec.709, clipped): grey max %.4f at %.4g, "
      "colours max %.4f at (%.4g, %.4g, %.4g)\n",
      grey_worst, grey_at[0], colour_worst, colour_at[0], colour_at[1], colour_at[2]);
  EXPECT_LT(grey_worst, 0.013);
  EXPECT_GT(grey_worst, 0.008);  // the fit is not the reference: the residual is real
  EXPECT_LT(colour_worst, 0.025);
}

// --- The bake ---------------------------------------------------------------------------------

// Spec §6.2: for H = 32 the strip pixel (32·17 + 5, 9) holds lattice code (5, 9, 17)/31.
TEST(UnityUrpBake, LatticeLayout) {
  const Image strip = urp::bake_strip(32, 2, [](const Vec3& code) { return code; });
  ASSERT_EQ(strip.width, 1024);
  ASSERT_EQ(strip.height, 32);
  const double* t = strip.px(32 * 17 + 5, 9);
  EXPECT_EQ(t[0], static_cast<float>(5.0 / 31));
  EXPECT_EQ(t[1], static_cast<float>(9.0 / 31));
  EXPECT_EQ(t[2], static_cast<float>(17.0 / 31));
  EXPECT_EQ(t[3], 1.0);
}

// Spec §6.6: the whole bake at default settings, lattice codes in, texel out (before storage),
// a double evaluation of the formulas with the constants evaluated in double; ours uses the
// float32 constants derive_unity_urp computes (the white balance coefficients differ from the
// double ones by up to 7e-7 relative, UnityUrpDerive.WhiteBalanceTable), and the table prints 7
// digits: tolerance 1e-6 relative plus half the last printed digit.
TEST(UnityUrpBake, DefaultsTable) {
  const double c18 = urp::logc_from_linear(0.18), c1 = urp::logc_from_linear(1.0);
  auto expect3 = [](const Vec3& got, const Vec3& want, double digit, const char* what) {
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(got[i], want[i], 1e-6 * std::fabs(want[i]) + digit / 2) << what;
  };
  const ParamBlock none = defaults("HighDynamicRange", "None");
  expect3(urp::lut_texel(grey(c18), none), {0.1799998, 0.1799997, 0.1800015}, 1e-7,
          "HDR None 0.18");
  expect3(urp::lut_texel(grey(1), none), {58.85667, 58.85658, 58.85717}, 1e-5, "HDR None 1");
  expect3(urp::lut_texel({0.5, 0.3, 0.2}, none), {0.5186271, 0.0714099, 0.0225977}, 1e-7,
          "HDR None (0.5, 0.3, 0.2)");
  EXPECT_EQ(urp::lut_texel(grey(0), none), grey(0));  // −0.0039 clamped at step 5
  const ParamBlock neutral = defaults("HighDynamicRange", "Neutral");
  EXPECT_NEAR(urp::lut_texel(grey(c18), neutral)[1], 0.1816684, 1.5e-7);
  EXPECT_NEAR(urp::lut_texel(grey(1), neutral)[1], 1.2073674, 1.5e-6);
  EXPECT_EQ(urp::lut_texel(grey(0), neutral), grey(0));
  const ParamBlock aces = defaults("HighDynamicRange", "ACES");
  expect3(urp::lut_texel(grey(c18), aces), {0.1101979, 0.1101635, 0.1101414}, 1e-7,
          "HDR ACES 0.18");
  EXPECT_NEAR(urp::lut_texel(grey(c1), aces)[1], 0.6247, 1e-4);
  EXPECT_NEAR(urp::lut_texel(grey(1), aces)[1], 1.00917, 1e-5);
  const ParamBlock ldr = defaults("LowDynamicRange", "None");
  expect3(urp::lut_texel(grey(0.18), ldr), {0.1799998, 0.1799997, 0.1800015}, 1e-7, "LDR 0.18");
  EXPECT_EQ(urp::lut_texel(grey(1), ldr), grey(urp::kCurveCap));  // 127/128 = 0.9921875
  expect3(urp::lut_texel({0.01, 0.005, 0.002}, ldr), {0.0100000, 0.0050433, 0.0020792}, 1e-7,
          "LDR dark");
}

// Storage: RGBA16F rounds to nearest even half, RGBA8 to the nearest k/255 of the saturated
// value. LDR white: 0.9921875·255 = 253.008 → 253/255.
TEST(UnityUrpBake, Storage) {
  EXPECT_EQ(urp::quantize_texel(1, 0.1), 0.0999755859375);  // half nearest to 0.1
  EXPECT_EQ(urp::quantize_texel(1, 58.85667), 58.84375);    // spacing 1/32 at 32-64: 1883/32
  EXPECT_EQ(urp::quantize_texel(1, 70000.0), INFINITY);
  EXPECT_EQ(urp::quantize_texel(3, urp::kCurveCap), 253.0 / 255.0);
  EXPECT_EQ(urp::quantize_texel(3, -0.2), 0.0);
  const ParamBlock ldr = defaults("LowDynamicRange", "None", 16);
  const Image strip = urp::bake_lut_strip(ldr);
  EXPECT_EQ(strip.px(16 * 15 + 15, 15)[0], 253.0 / 255.0);
  for (int x = 0; x < strip.width; ++x)
    for (int y = 0; y < strip.height; ++y)
      for (int c = 0; c < 3; ++c) {
        const double k = strip.px(x, y)[c] * 255.0;
        ASSERT_EQ(k, std::round(k));
      }
}

// --- The lookup -------------------------------------------------------------------------------

// ApplyLut2D at lattice inputs returns the stored texel (the taps land on texel centres; the blue
// weight is 0), and between them it is trilinear: at the midpoint of two lattice nodes in blue it
// is their mean.
TEST(UnityUrpApply, LatticeExactAndTrilinear) {
  const ParamBlock p = defaults("HighDynamicRange", "None", 16);
  const Image strip = urp::bake_lut_strip(p);
  for (int b : {0, 7, 15})
    for (int g : {0, 3, 15})
      for (int r : {0, 9, 15}) {
        const Vec3 code = urp::lattice_code(16, r, g, b);
        const Vec3 got = urp::apply_lut_2d(strip, code, p.urp_lut_params);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], strip.px(r + 16 * b, g)[c], 1e-12);
      }
  const Vec3 mid = urp::apply_lut_2d(strip, {3.0 / 15, 4.0 / 15, 6.5 / 15}, p.urp_lut_params);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(mid[c], 0.5 * (strip.px(3 + 16 * 6, 4)[c] + strip.px(3 + 16 * 7, 4)[c]), 1e-12);
}

// End to end at defaults. HDR None: 18 % grey is LogC code 0.391007035, 12.1212 lattice steps of
// 1/31, so the lookup is the lerp of nodes 12 and 13 (LogC^-1 = 0.1731704 and 0.2378143 with the
// near-identity default grade) at 0.1212181: 0.1810064, 0.56 % above 0.18 — linear interpolation
// of an exponential with a step ratio of 10^(1/(31·0.244161)) = 1.356 (max error ln²(1.356)/8 =
// 1.2 %), Unity's own behaviour at H = 32; the fp16 storage of the two nodes adds up to 5e-4.
// LDR maps white to 253/255 (docs/spec/unity_urp.md §6.6, the curve cap). Post exposure scales the
// input before everything.
TEST(UnityUrpApply, EndToEnd) {
  const ParamBlock hdr = defaults("HighDynamicRange", "None");
  Image in(3, 1);
  for (int c = 0; c < 3; ++c) {
    in.px(0, 0)[c] = 0.18;
    in.px(1, 0)[c] = 1.0;
    in.px(2, 0)[c] = 0.09;
  }
  in.px(0, 0)[3] = 0.25;
  const Image out = urp::grade_image(in, hdr);
  const double u = urp::logc_from_linear(0.18) * 31.0;
  const double f = u - std::floor(u);
  const double lerp =
      (1 - f) * urp::linear_from_logc(12.0 / 31) + f * urp::linear_from_logc(13.0 / 31);
  EXPECT_NEAR(lerp, 0.1810064, 1e-7);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(out.px(0, 0)[c], lerp, 5e-4 * lerp);
  EXPECT_EQ(out.px(0, 0)[3], 0.25);  // alpha passes through
  const Image ldr_out = urp::grade_image(in, defaults("LowDynamicRange", "None"));
  for (int c = 0; c < 3; ++c) EXPECT_EQ(ldr_out.px(1, 0)[c], 253.0 / 255.0);

  SettingValues s = new_settings();
  ASSERT_TRUE(s.set_choice("GradingMode", "HighDynamicRange").ok());
  ASSERT_TRUE(s.set("ColorAdjustments.postExposure", {1, 0, 0, 0}, 1).ok());
  const Image exposed = urp::grade_image(in, derive(s));
  for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(exposed.px(2, 0)[c], out.px(0, 0)[c]);
}

// --- Planted defects --------------------------------------------------------------------------

// The largest change between two strips relative to the larger |value| of the texel, and how many
// texels changed by more than float32 noise (hdrc::kFloat32Noise = 2^-20 relative).
struct StripChange {
  double max_relative = 0;
  int changed = 0;
};
StripChange compare_strips(const Image& a, const Image& b) {
  StripChange s;
  for (size_t i = 0; i < a.data.size(); ++i) {
    const double scale = std::max({std::fabs(a.data[i]), std::fabs(b.data[i]), 1e-6});
    const double r = std::fabs(a.data[i] - b.data[i]) / scale;
    s.max_relative = std::max(s.max_relative, r);
    if (r > hdrc::kFloat32Noise) ++s.changed;
  }
  return s;
}

// A variant of the HDR None/Neutral grade with the hue rotation replaced (`rotate`), composed
// from the reference's own steps in LutBuilderHdr's order.
template <class Rotate>
Vec3 grade_with_rotation(const Vec3& code, const ParamBlock& p, Rotate rotate) {
  Vec3 c = urp::linear_from_logc(code);
  c = urp::white_balance(c, p);
  c = urp::contrast(c, p, false);
  c = urp::color_filter(c, p);
  c = urp::split_toning(c, p, false);
  c = urp::channel_mixer(c, p);
  c = urp::shadows_midtones_highlights(c, p, false);
  c = urp::lift_gamma_gain(c, p);
  Vec3 hsv = urp::hsv_from_rgb(c);
  hsv[0] = rotate(hsv[0] + p.urp_hue_sat_con[0]);
  c = urp::rgb_from_hsv(hsv);
  c = urp::saturation(c, p, false);
  c = urp::default_yrgb_curves(c, true);
  for (double& x : c) x = std::max(0.0, x);
  return c;
}

// One LogC constant off by 1e-6 (c = 0.244161 → 0.244162) moves the HDR strip's texels by 4e-6 to
// 2e-5 relative (more near the zero of LogC^-1): far above float32 noise (2^-20) in nine texels
// of ten before storage, and enough to flip the fp16 rounding of thousands of stored values.
// (Through the whole pass the change mostly cancels: the uber pass encodes with the same constants
// the bake decodes with, so a consistent planted LogC error shows in the strip, not in the graded
// image.)
TEST(UnityUrpPlantedDefects, LogCConstant) {
  const ParamBlock p = defaults("HighDynamicRange", "None", 32);
  urp::LogCParams k = urp::kUnityLogC;
  k.c += 1e-6;
  auto texel = [&](const urp::LogCParams& kk) {
    return [&p, kk](const Vec3& code) { return urp::lut_texel(code, p, kk); };
  };
  const StripChange raw = compare_strips(urp::bake_strip(32, 2, texel(urp::kUnityLogC)),
                                         urp::bake_strip(32, 2, texel(k)));
  const StripChange stored =
      compare_strips(urp::bake_lut_strip(p), urp::bake_strip(32, 1, texel(k)));
  std::printf(
      "LogC c + 1e-6: float32 strip max rel %.3g (%d texels > 2^-20); fp16 strip max rel "
      "%.3g (%d changed)\n",
      raw.max_relative, raw.changed, stored.max_relative, stored.changed);
  EXPECT_GT(raw.max_relative, 1e-5);
  EXPECT_GT(raw.changed, 32 * 32 * 32 * 3 * 8 / 10);
  EXPECT_GT(stored.changed, 1000);
}

// Hue-shift wrap. With a +90° shift (hue + 0.25) every hue above 0.75 leaves [0, 1] and
// RotateHue wraps it once. Two planted variants:
//  * the wrap removed: HsvToRgb takes frac(h + K) of the hue, so an unwrapped hue 1.1 gives the
//    colour of 0.1 — the strip moves only by rounding (here: double rounding, < 1e-12; on a GPU:
//    float32 noise). A missing or reversed wrap is therefore NOT detectable and must not be
//    planted as a defect;
//  * the wrap replaced by a clamp to [0, 1] (saturate instead of RotateHue): detectable.
TEST(UnityUrpPlantedDefects, HueShiftWrap) {
  SettingValues s = new_settings();
  ASSERT_TRUE(s.set_choice("GradingMode", "HighDynamicRange").ok());
  ASSERT_TRUE(s.set("ColorAdjustments.hueShift", {90, 0, 0, 0}, 1).ok());
  const ParamBlock p = derive(s);
  const Image unity = urp::bake_strip(32, 2, [&](const Vec3& c) { return urp::color_grade(c, p); });
  const Image composed = urp::bake_strip(32, 2, [&](const Vec3& c) {
    return grade_with_rotation(c, p, [](double h) { return urp::rotate_hue(h, 0.0, 1.0); });
  });
  const Image no_wrap = urp::bake_strip(
      32, 2, [&](const Vec3& c) { return grade_with_rotation(c, p, [](double h) { return h; }); });
  const Image clamped = urp::bake_strip(32, 2, [&](const Vec3& c) {
    return grade_with_rotation(c, p, [](double h) { return std::clamp(h, 0.0, 1.0); });
  });
  EXPECT_EQ(compare_strips(unity, composed).max_relative, 0.0);  // the composition is the grade
  const StripChange missing = compare_strips(unity, no_wrap);
  const StripChange clamp = compare_strips(unity, clamped);
  std::printf(
      "hue wrap removed: max rel %.3g (%d texels); wrap -> clamp: max rel %.3g (%d texels)\n",
      missing.max_relative, missing.changed, clamp.max_relative, clamp.changed);
  EXPECT_LT(missing.max_relative, 1e-12);
  EXPECT_EQ(missing.changed, 0);
  EXPECT_GT(clamp.max_relative, 0.1);
  EXPECT_GT(clamp.changed, 1000);
}

// Split-toning balance with its sign flipped (urp_split_shadows.w = +0.3 instead of −0.3) moves
// the shadows/highlights crossover: visible wherever the split colours differ from grey.
TEST(UnityUrpPlantedDefects, SplitToningBalanceSign) {
  SettingValues s = new_settings();
  ASSERT_TRUE(s.set_choice("GradingMode", "HighDynamicRange").ok());
  ASSERT_TRUE(s.set("SplitToning.shadows", {0.3, 0.45, 0.7, 1}, 4).ok());
  ASSERT_TRUE(s.set("SplitToning.highlights", {0.75, 0.55, 0.3, 1}, 4).ok());
  ASSERT_TRUE(s.set("SplitToning.balance", {-30, 0, 0, 0}, 1).ok());
  const ParamBlock p = derive(s);
  ParamBlock flipped = p;
  flipped.urp_split_shadows[3] = -p.urp_split_shadows[3];
  const StripChange change = compare_strips(urp::bake_lut_strip(p), urp::bake_lut_strip(flipped));
  std::printf("split balance sign: fp16 strip max rel %.3g (%d texels changed)\n",
              change.max_relative, change.changed);
  EXPECT_GT(change.max_relative, 0.01);
  EXPECT_GT(change.changed, 1000);
}

// --- Device allowances -----------------------------------------------------------------------

// The internal LUT's device bounds: every stored texel inside, and both storage results of the
// bake's value admitted (RGBA16F without RTE: the nearest half and the one toward zero; RGBA8
// UNORM: floor and ceil of v·255): a store toward zero (the worst-case device model's) lies within
// them. A texel one code beyond (UNORM: k + 2 when v rounds to k + 1) lies outside where the bake's
// noise is far from a code boundary.
TEST(UnityUrpDevice, BakeBoundsHoldBothStorageNeighbours) {
  hdrc::DevicePrecision d;  // fp16_rte false
  for (const char* mode : {"HighDynamicRange", "LowDynamicRange"}) {
    const ParamBlock p = defaults(mode, "Neutral", 16);
    const Image strip = urp::bake_lut_strip(p);
    const urp::StripRange b = urp::bake_lut_strip_device_range(p, d);
    int outside = 0, texels = 0;
    for (int y = 0; y < strip.height; ++y)
      for (int x = 0; x < strip.width; ++x) {
        const int n = p.lut_size, r = x % n, bb = x / n;
        const Vec3 v = urp::lut_texel(urp::lattice_code(n, r, y, bb), p);
        for (int c = 0; c < 3; ++c) {
          const double lo = b.lo.px(x, y)[c], hi = b.hi.px(x, y)[c];
          EXPECT_LE(lo, strip.px(x, y)[c]);
          EXPECT_GE(hi, strip.px(x, y)[c]);
          if (p.lut_format == 1) {  // RTE or RTZ (Vulkan's float16 rounding modes)
            const double rtz =
                v[c] >= 0 ? hdrc::ref::half_round_down(v[c]) : hdrc::ref::half_round_up(v[c]);
            EXPECT_LE(lo, std::fmin(rtz, urp::quantize_texel(1, v[c])));
            EXPECT_GE(hi, std::fmax(rtz, urp::quantize_texel(1, v[c])));
          } else {
            ASSERT_EQ(p.lut_format, 3);
            EXPECT_LE(lo, std::floor(std::clamp(v[c], 0.0, 1.0) * 255) / 255);
            EXPECT_GE(hi, std::ceil(std::clamp(v[c], 0.0, 1.0) * 255) / 255);
            const double k = std::nearbyint(std::clamp(v[c], 0.0, 1.0) * 255);
            if (k + 2 <= 255) {
              ++texels;
              if ((k + 2) / 255 > hi) ++outside;
            }
          }
        }
      }
    if (p.lut_format == 3) {
      EXPECT_GT(outside, texels * 9 / 10) << outside << " / " << texels;
    }
  }
}

// The graded look of cases/unity_urp/graded_look.json (every control off its default), HDR
// grading, no tone mapping.
ParamBlock graded_look() {
  SettingValues s = new_settings();
  EXPECT_TRUE(s.set_choice("GradingMode", "HighDynamicRange").ok());
  EXPECT_TRUE(s.set_choice("Tonemapping.mode", "None").ok());
  const struct {
    const char* name;
    std::array<double, 4> v;
    int n;
  } values[] = {{"WhiteBalance.temperature", {20, 0, 0, 0}, 1},
                {"WhiteBalance.tint", {-10, 0, 0, 0}, 1},
                {"ColorAdjustments.contrast", {25, 0, 0, 0}, 1},
                {"ColorAdjustments.colorFilter", {1, 0.95, 0.9, 1}, 4},
                {"ColorAdjustments.hueShift", {-20, 0, 0, 0}, 1},
                {"ColorAdjustments.saturation", {15, 0, 0, 0}, 1},
                {"SplitToning.shadows", {0.35, 0.45, 0.6, 1}, 4},
                {"SplitToning.highlights", {0.6, 0.5, 0.4, 1}, 4},
                {"SplitToning.balance", {-20, 0, 0, 0}, 1},
                {"ChannelMixer.redOutGreenIn", {-10, 0, 0, 0}, 1},
                {"ShadowsMidtonesHighlights.shadows", {1, 0.95, 1.05, 0.1}, 4},
                {"LiftGammaGain.lift", {1, 1, 1.05, 0.02}, 4},
                {"LiftGammaGain.gamma", {1, 1, 1, 0.1}, 4},
                {"LiftGammaGain.gain", {1.02, 1, 0.98, 0}, 4}};
  for (const auto& v : values) EXPECT_TRUE(s.set(v.name, v.v, v.n).ok()) << v.name;
  return derive(s);
}

// Bilinear weights snapped to the 2^-bits grid, by hand (reference/color/strip_device_range.h,
// snap_weights, the default; device_allowance.h filter_taps' weight_bits): a 2-edge strip (4 x 2
// texels) holding 1 in texel (1, 0) of slice 0 and 0 elsewhere, read at t = (0.6, 0.05, 0): α = 0.6
// and β = 0.05 snap to [153, 154]/256 and [12, 13]/256 (8 bits), so the weight α(1 − β) of texel
// (1, 0) lies in [153·243, 154·244]/65536 = [0.5673370, 0.5733643]; snapped on its own it is [145,
// 147]/256 = [0.56640625, 0.57421875]. The slice lerp adds 2.5 ULP of the larger sample (2.5·2^-24
// < 1.5e-7).
TEST(UnityUrpDevice, SnappedWeightsByHand) {
  Image lo(4, 2), hi(4, 2);
  lo.px(1, 0)[0] = hi.px(1, 0)[0] = 1.0;
  const hdrc::ref::Range3 t = hdrc::ref::Range3::point({0.6, 0.05, 0.0});
  const hdrc::ref::Range3 axis = hdrc::ref::strip_lookup_device_range(
      {&lo, &hi, 2}, t, 8, 0.0, hdrc::ref::FilterArithmetic::exact(), false);
  EXPECT_NEAR(axis.lo[0], 153.0 * 243 / 65536, 2e-7);
  EXPECT_NEAR(axis.hi[0], 154.0 * 244 / 65536, 2e-7);
  const hdrc::ref::Range3 snapped = hdrc::ref::strip_lookup_device_range({&lo, &hi, 2}, t, 8, 0.0);
  EXPECT_NEAR(snapped.lo[0], 145.0 / 256, 2e-7);
  EXPECT_NEAR(snapped.hi[0], 147.0 / 256, 2e-7);
}

// The HDR curves' rounding by hand (lut_texel_device_range): at the defaults (HDR, no tone map)
// the white lattice code (1, 1, 1) decodes to 58.8566 (LogC^-1(1) above), which FastTonemap maps
// to 58.8566/59.8566 = 0.98329, under the cap 127/128: the texel is 58.8566 again, and t's
// rounding (Max3 + 1, rcp, product: 3.5 ULP, relative 3.5·2^-23) carried through 1 − t
// (divided by 1 − t = 1/59.8566) and the last rcp and product (7·2^-23 in all) give
// 2^-23·(3.5·58.8566 + 7) = 2.539e-5 of 58.8566 = 1.494e-3 either way, at least.
TEST(UnityUrpDevice, CurvesRoundingByHand) {
  const ParamBlock p = defaults("HighDynamicRange", "None");
  const hdrc::ref::Range3 r = urp::lut_texel_device_range({1, 1, 1}, p);
  const Vec3 v = urp::lut_texel({1, 1, 1}, p);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(v[c], 58.8566, 1e-3);  // the white balance's float32 coefficients move it
    EXPECT_LE(r.lo[c], v[c] - 1.494e-3);
    EXPECT_GE(r.hi[c], v[c] + 1.494e-3);
    EXPECT_LT(r.hi[c] - r.lo[c], 1e-3 * v[c]);  // a grey: RgbToHsv's hue is open, s·v = d tiny
  }
}

// The H200's value (2026-11-27, docs/precision.md) in unity_urp/graded_look/
// gradingmode1_mode0_postexposure0_hue_sweep at (18, 3): scene (15.5831203, 9.34987259, 0), graded
// (57.84375, 1.9765625, 0.193969727) against the reference's (57.8382562, 1.97031513,
// 0.176768041). Its blue is texel (27, 24)'s 6.2085 by a weight of 0.03124 = 8/256 where the
// exact weight is 0.6330·0.0450 = 0.0285 and the axis boxes allow at most 0.6367·0.0469 = 0.0298:
// the product snapped to the 8-bit grid. Inside the ranges with snapped weights, outside without,
// the filter's products and sums in float16 as VK-GL-CTS verifies an RGBA16F texture included
// (device_allowance.h filter_taps; 1956/65536 is a float16 value): not a bound the specification
// admits (docs/precision.md, "Filter arithmetic").
TEST(UnityUrpDevice, H200GradedLookPixelNeedsSnappedWeights) {
  ParamBlock p = graded_look();
  hdrc::DevicePrecision d;
  d.sub_texel_bits = 8;
  d.fp16_rte = true;
  const urp::StripRange b = urp::bake_lut_strip_device_range(p, d);
  const Vec3 in = {15.5831203, 9.34987259, 0};
  const Vec3 h200 = {57.84375, 1.9765625, 0.193969727};
  const hdrc::ref::Range3 axis = urp::apply_color_grading_device_range(b, p, in, 8, false);
  const hdrc::ref::Range3 snapped = urp::apply_color_grading_device_range(b, p, in, 8, true);
  EXPECT_GT(h200[2], axis.hi[2]);
  for (int c = 0; c < 3; ++c) {
    EXPECT_LE(snapped.lo[c], h200[c]) << c;
    EXPECT_GE(snapped.hi[c], h200[c]) << c;
  }
}

// The pipeline's reference with device allowances, both stages, HDR and LDR grading: the tight
// output is unchanged bit for bit, every pixel has a device range holding its value, the grade's
// ranges are not all points.
TEST(UnityUrpDevice, TightOutputUnchangedAndEveryPixelHasARange) {
  const auto& pipeline = hdrc::ref::unity_urp::unity_urp_pipeline();
  for (const hdrc::StageInfo& stage : pipeline.stages())
    for (const char* mode : {"HighDynamicRange", "LowDynamicRange"}) {
      hdrc::ResolvedCase rc;
      hdrc::Case spec;
      spec.stage = &stage;
      rc.spec = spec;
      rc.params = defaults(mode, "ACES", 16);
      rc.params.urp_hue_sat_con[0] = 0.1;  // a hue shift: a LUT that is not the identity
      rc.input = Image(64, 4);
      for (size_t i = 0; i < rc.input.pixel_count(); ++i) {
        double* px = &rc.input.data[i * Image::kChannels];
        const double k = std::pow(10.0, -3.0 + 4.0 * static_cast<double>(i % 64) / 63);
        px[0] = k;
        px[1] = k * (0.2 + 0.25 * static_cast<double>(i / 64));
        px[2] = k * 0.6;
        px[3] = 0.5;
      }
      if (stage.name == "lut_bake") rc.input = Image(16 * 16, 16);
      auto tight = pipeline.reference(rc, false);
      rc.device_allowances = true;
      rc.device.sub_texel_bits = 8;
      auto dev = pipeline.reference(rc, false);
      ASSERT_TRUE(tight && dev);
      EXPECT_EQ(tight->data, dev->data) << stage.name << " " << mode;
      EXPECT_TRUE(tight->device_admissible.empty());
      ASSERT_EQ(dev->device_admissible.size(), dev->pixel_count());
      int wider = 0;
      for (size_t i = 0; i < dev->device_admissible.size(); ++i) {
        const hdrc::AdmissibleRange& a = dev->device_admissible[i];
        EXPECT_EQ(a.pixel, i);
        for (int c = 0; c < 4; ++c) {
          EXPECT_LE(a.lo[c], dev->data[i * 4 + c]) << i;
          EXPECT_GE(a.hi[c], dev->data[i * 4 + c]) << i;
          if (c < 3 && a.hi[c] > a.lo[c]) ++wider;
        }
      }
      EXPECT_GT(wider, static_cast<int>(dev->pixel_count())) << stage.name << " " << mode;
    }
}

}  // namespace
