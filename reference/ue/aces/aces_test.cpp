// Tests for the UE 5.5 ACES HDR output transform. Every expected number comes from outside this
// code: UE's own float literals (HDRHelper.h), docs/spec/ue55.md §13's golden values
// (double-precision recomputations, re-derived here), the spec's red-modifier table, and
// OpenColorIO 2.1's built-in ACES 1.1 HDR output transforms (an independent implementation of the
// same ACES 1.x SSTS).
#include <OpenColorIO/OpenColorIO.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "color/d3d_math.h"
#include "reference/color/ue_matrices.h"
#include "reference/ue/aces/aces_common.h"
#include "reference/ue/aces/aces_output.h"
#include "reference/ue/aces/aces_params.h"

namespace {

namespace OCIO = OCIO_NAMESPACE;
using hdrc::ref::Mat3;
using hdrc::ref::Vec3;
using namespace hdrc::ref::aces;
namespace lit = hdrc::ref::ue_literal;
namespace stdm = hdrc::ref::standard;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Signed distance in float ULPs (monotonic integer mapping of the bit patterns).
int64_t ulp_distance(float a, float b) {
  const auto key = [](float f) {
    int32_t i;
    std::memcpy(&i, &f, sizeof i);
    return i < 0 ? int64_t{INT32_MIN} - i : int64_t{i};
  };
  return key(a) - key(b);
}

double rel(double got, double want) {
  return std::fabs(got / want - 1.0);
}

// What HDRConfigureCVars passes for r.HDR.Display.MinLuminanceLog10 = -4: FMath::Pow(10, -4.f).
const float kMinLum = std::pow(10.0f, -4.0f);

AcesShaderParams shader_params(float max_nits, float scm = 1.5f, float gc = 0.0f) {
  return compute_aces_tonemap_params(
      configure_aces_tonemap_params(kMinLum, 15.0f, max_nits, scm, gc).packed);
}

Vec3 grey(double v) {
  return {v, v, v};
}

// ---------------------------------------------------------------------------------------------
// (a) CPU parameters against UE's own float values and the spec's double recomputations.

// HDRHelper.h: FACESTonemapParams() — "Default Values such as MinLuminanceLog10=-4,
// MidLuminance=15, MaxLuminance=1000" — UE's float results of this very computation
// (docs/spec/ue55.md §5.3).
struct UeFloats {
  std::array<float, 4> min_max{2.50898620e-06f, 1e-4f, 692.651123f, 1000.0f};
  std::array<float, 4> mid{0.0822144598f, 4.80000019f, 1.55f, 1.0f};
  std::array<float, 4> low0{-4.00000000f, -4.00000000f, -3.15737653f, -0.485249996f};
  std::array<float, 4> high0{-0.332863420f, 1.69534576f, 2.75812411f, 3.00000000f};
  float low4 = 1.84773231f;
  float high4 = 3.0f;
};

// Measured residual: 0 ULP in all 18 values (glibc 2.36 logf/log/log2/pow). This needs the log2
// inside RenderCore.cpp's shift() and expShift to be the double function: with log2f, Min.x
// comes out 3 ULP and Max.x 4 ULP away from UE's floats (decisions D5.3 says "float log2"; UE's
// own numbers say double).
TEST(AcesParams, DefaultLuminancesReproduceUeFloatsBitExactly) {
  const AcesConfigured c = configure_aces_tonemap_params(kMinLum, 15.0f, 1000.0f);
  ASSERT_TRUE(c.status.ok()) << c.status.error().to_string();
  const UeFloats ue;
  const AcesTonemapParams& p = c.packed;
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(ulp_distance(p.min_max_data[i], ue.min_max[i]), 0) << "ACESMinMaxData[" << i << "]";
    EXPECT_EQ(ulp_distance(p.mid_data[i], ue.mid[i]), 0) << "ACESMidData[" << i << "]";
    EXPECT_EQ(ulp_distance(p.coefs_low_0[i], ue.low0[i]), 0) << "ACESCoefsLow_0[" << i << "]";
    EXPECT_EQ(ulp_distance(p.coefs_high_0[i], ue.high0[i]), 0) << "ACESCoefsHigh_0[" << i << "]";
  }
  EXPECT_EQ(ulp_distance(p.coefs_low_4, ue.low4), 0);
  EXPECT_EQ(ulp_distance(p.coefs_high_4, ue.high4), 0);
  EXPECT_EQ(p.mid_data[3], 1.0f);  // never written by ConfigureACESTonemapParams (D5.3)
}

TEST(AcesParams, DefaultConstructedIsUeConstructor) {
  const AcesTonemapParams p;
  const UeFloats ue;
  EXPECT_EQ(p.min_max_data, ue.min_max);
  EXPECT_EQ(p.mid_data, ue.mid);
  EXPECT_EQ(p.coefs_low_0, ue.low0);
  EXPECT_EQ(p.coefs_high_0, ue.high0);
  EXPECT_EQ(p.coefs_low_4, ue.low4);
  EXPECT_EQ(p.coefs_high_4, ue.high4);
  EXPECT_EQ(p.scene_color_multiplier, 1.5f);
  EXPECT_EQ(p.gamut_compression, 0.0f);
}

// Spec §13 values are a double recomputation; UE's float path differs from them by the float
// rounding of the interpolated stop (ulp(12.0) = 9.5e-7 → 6.6e-7 relative in 0.18·2^stop) and of
// expShift. Measured worst: 1.04e-6 relative (Max.x at 1000 nits), 8.7e-7 (Max.x at 2000), 4.9e-7
// (Max.x at 600); expShift 6.1e-7 (1000) and 5.1e-7 (2000) absolute; coefficients ≤ 1.8e-7
// absolute. Tolerances: 1.5e-6 relative, 1e-6 absolute for expShift and log10-nit coefficients.
// The spec's values are confirmed (no disagreement).
TEST(AcesParams, AgreeWithSpecDoubleRecomputation) {
  const AcesConfigured c1000 = configure_aces_tonemap_params(kMinLum, 15.0f, 1000.0f);
  EXPECT_NEAR(c1000.exp_shift, 1.130532253, 1e-6);
  EXPECT_LT(rel(c1000.packed.min_max_data[0], 2.50898723e-6), 1.5e-6);
  EXPECT_LT(rel(c1000.packed.min_max_data[2], 692.651845), 1.5e-6);
  EXPECT_LT(rel(c1000.packed.mid_data[0], 0.0822144936), 1.5e-6);
  const std::array<double, 5> low{-4, -4, -3.15737658, -0.485249996, 1.84773247};
  const std::array<double, 5> high{-0.33286347, 1.69534594, 2.75812412, 3, 3};
  for (int i = 0; i < 5; ++i) {
    const float l = i < 4 ? c1000.packed.coefs_low_0[i] : c1000.packed.coefs_low_4;
    const float h = i < 4 ? c1000.packed.coefs_high_0[i] : c1000.packed.coefs_high_4;
    EXPECT_NEAR(l, low[i], 1e-6) << "coefsLow[" << i << "]";
    EXPECT_NEAR(h, high[i], 1e-6) << "coefsHigh[" << i << "]";
  }

  const AcesConfigured c2000 = configure_aces_tonemap_params(kMinLum, 15.0f, 2000.0f);
  ASSERT_TRUE(c2000.status.ok());
  EXPECT_NEAR(c2000.exp_shift, 1.120178900, 1e-6);
  EXPECT_LT(rel(c2000.packed.min_max_data[2], 1963.63794), 1.5e-6);
  const std::array<double, 5> high2000{-0.448966155, 1.81144863, 3.03115399, 3.30103, 3.30103};
  for (int i = 0; i < 5; ++i) {
    const float h = i < 4 ? c2000.packed.coefs_high_0[i] : c2000.packed.coefs_high_4;
    EXPECT_NEAR(h, high2000[i], 1e-6) << "coefsHigh[" << i << "] at 2000 nits";
  }

  const AcesConfigured c600 = configure_aces_tonemap_params(kMinLum, 15.0f, 600.0f);
  ASSERT_TRUE(c600.status.ok());
  EXPECT_LT(rel(c600.packed.min_max_data[2], 320.82883), 1.5e-6);
  const std::array<double, 5> high600{-0.247299786, 1.60978226, 2.55741077, 2.77815125, 2.77815125};
  for (int i = 0; i < 5; ++i) {
    const float h = i < 4 ? c600.packed.coefs_high_0[i] : c600.packed.coefs_high_4;
    EXPECT_NEAR(h, high600[i], 1e-6) << "coefsHigh[" << i << "] at 600 nits";
  }
}

// ssts with UE's float parameters vs docs/spec/ue55.md §13 (double parameters). Measured relative
// residuals: 0.18 → 3.7e-7 (15.0000055 nits), 0.27 → 3.3e-7, 1 → 2.7e-7, 10 → 2.8e-7; at 2000 nits
// 0.27 → 2.4e-7. All from the float rounding of the parameters; tolerance 5e-7. The spec's values
// are confirmed (no disagreement).
TEST(Ssts, SpecGoldenValues) {
  const TsParams p = shader_params(1000.0f).aces_params;
  EXPECT_LT(rel(ssts(0.18, p), 15.0), 5e-7);
  EXPECT_LT(rel(ssts(0.27, p), 25.4976829), 5e-7);
  EXPECT_LT(rel(ssts(1.0, p), 107.437004), 5e-7);
  EXPECT_LT(rel(ssts(10.0, p), 516.275015), 5e-7);
  // At and above Max.x the curve is flat at Max.y; at and below Min.x at Min.y.
  EXPECT_LT(rel(ssts(692.66, p), 1000.0), 1e-12);
  EXPECT_LT(rel(ssts(1e6, p), 1000.0), 1e-12);
  EXPECT_LT(rel(ssts(0.0, p), 1e-4), 1e-7);
  // The shifted mid point: 10^((coefsHigh[0] + coefsHigh[1])/2) with float coefficients is
  // 10^0.68124117 vs log10(4.8) = 0.68124124 (measured 1.6e-7).
  EXPECT_LT(rel(ssts(p.mid.x, p), 4.8), 3e-7);
  EXPECT_LT(rel(ssts(0.27, shader_params(2000.0f).aces_params), 25.8457295), 5e-7);
}

// Spec §13 "HDR grey chain" through ACESOutputTransforms1000 with the sRGB working colour space's
// ToAP0 (float, as UE uploads it) and SceneColorMultiplier 1.5. Measured relative residuals
// ≤ 3.5e-7 (float parameters plus the ≤ 1e-7 grey drift of the float ToAP0 rows).
TEST(OutputTransform, SpecHdrGreyChain) {
  const AcesShaderParams p = shader_params(1000.0f);
  const Mat3 to_ap0 = hdrc::ref::make_working_color_space(stdm::kSrgb).to_ap0;
  const std::array<std::array<double, 2>, 4> chain{
      {{0.18, 25.497585}, {1.0, 154.035412}, {10.0, 606.611787}, {100.0, 930.719800}}};
  for (const auto& [scene, nits] : chain) {
    const Vec3 out = aces_output_transforms_1000(grey(scene), to_ap0, p);
    for (int i = 0; i < 3; ++i) EXPECT_LT(rel(out[i], nits), 5e-7) << "scene " << scene;
  }
}

// outputTransform after rrt_sweeteners on a range (output_transform_tail_range), against the spec's
// ssts values above (docs/spec/ue55.md §13; 1000 nits). The matrices after the tone scale compose
// to XYZ_2_AP1 · AP1_2_XYZ ≈ I (the float literals' off-diagonals ~1e-7), linCV = (y − 1e-4)/(1000
// − 1e-4) stays below 1 (no limit_to_primaries clamp), so each channel's range is the tone scale's
// range of that channel within 1e-5 relative.
TEST(OutputTransform, TailRangeMapsEachChannelsEndsThroughTheToneScale) {
  const AcesShaderParams p = shader_params(1000.0f);
  hdrc::ref::Range3 grey = hdrc::ref::Range3::point({0.18, 0.18, 0.18});
  const hdrc::ref::Range3 g = output_transform_tail_range(grey, p);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(rel(g.lo[i], 15.0), 1e-5) << i;
    EXPECT_LT(rel(g.hi[i], 15.0), 1e-5) << i;
  }
  // A saturated red (10 → 516.275 nits) with green and blue anywhere in [0.18, 0.27].
  hdrc::ref::Range3 box;
  box.lo = {10.0, 0.18, 0.18};
  box.hi = {10.0, 0.27, 0.27};
  const hdrc::ref::Range3 b = output_transform_tail_range(box, p);
  EXPECT_LT(rel(b.lo[0], 516.275015), 1e-5);
  EXPECT_LT(rel(b.hi[0], 516.275015), 1e-5);
  for (int i = 1; i < 3; ++i) {
    EXPECT_LT(rel(b.lo[i], 15.0), 1e-5) << i;
    EXPECT_LT(rel(b.hi[i], 25.4976829), 1e-5) << i;
  }
}

// Why the device range takes the shader noise before the tone scale (combine_luts.cpp
// device_texel_range): rgb_pre = (10, 0.27, 0.27) with kShaderNoise = 2^-15 of its largest
// channel, e = 10·2^-15 = 3.05e-4, is ±0.113 % of green. The tone scale's log-log slope around
// 0.27 lies between its secants from the spec values, ln(25.4977/15)/ln(1.5) = 1.309 and
// ln(107.437/25.4977)/ln(1/0.27) = 1.098, so green's output width is 25.4977 × [1.098, 1.309] ×
// 2e/0.27 = [0.063, 0.076] nits: over twice the 2 × 2^-15 × 516.275 = 0.0315 nits that the same
// noise taken after the transform (relative to the tone-mapped red) admits.
TEST(OutputTransform, ShaderNoiseBeforeTheToneScaleWidensASaturatedPixelsDarkChannel) {
  const AcesShaderParams p = shader_params(1000.0f);
  const Vec3 pre{10.0, 0.27, 0.27};
  hdrc::ref::Range3 r = hdrc::ref::Range3::point(pre);
  ASSERT_TRUE(hdrc::ref::widen_noise(pre, hdrc::ref::kShaderNoise, &r));
  const hdrc::ref::Range3 out = output_transform_tail_range(r, p);
  const double width = out.hi[1] - out.lo[1];
  EXPECT_GT(width, 0.063);
  EXPECT_LT(width, 0.076);
  EXPECT_GT(width, 2.0 * hdrc::ref::kShaderNoise * 516.275015);
}

// Forward/inverse pair: RenderCore.cpp's float inv_ssts undoes the shader ssts to float precision
// where the curve has slope: the error in x is the float rounding of y (and of inv_ssts' float
// arithmetic) divided by d log y / d log x, which goes to 0 at Min.x and Max.x (1.5e-4 in the
// first quarter decade above Min.x, 0.12 in the last one below Max.x). Over
// [Min.x·10^0.25, Max.x·10^−0.5] the measured worst is 7.8e-6; bound 1e-5.
TEST(InvSsts, RoundTripsSsts) {
  const AcesConfigured c = configure_aces_tonemap_params(kMinLum, 15.0f, 1000.0f);
  const TsParams p = compute_aces_tonemap_params(c.packed).aces_params;
  const double lo = std::log10(p.min.x) + 0.25, hi = std::log10(p.max.x) - 0.5;
  double worst = 0.0;
  for (int k = 0; k <= 2000; ++k) {
    const double lx = lo + (hi - lo) * k / 2000;
    const double x = std::pow(10.0, lx);
    const auto back = inv_ssts(static_cast<float>(ssts(x, p)), c.ts);
    ASSERT_TRUE(back.has_value()) << "x = " << x;
    worst = std::fmax(worst, rel(*back, x));
  }
  EXPECT_LT(worst, 1e-5);
  EXPECT_LT(rel(*inv_ssts(1e-5f, c.ts), c.ts.min.x), 1e-6);    // below Min.y → Min.x
  EXPECT_LT(rel(*inv_ssts(5000.0f, c.ts), c.ts.max.x), 1e-6);  // above Max.y → Max.x
}

// Decisions D5.3: the C++ inv_ssts low-spline search leaves the coefficients uninitialised when
// logy lies in (KNOT_Y_LOW[3], log10(Mid.y)]. With float coefficients KNOT_Y_LOW[3] =
// 0.68124116 < log10f(4.80000019) = 0.6812412, so a float luminance just under 4.8 nits reaches
// UE's undefined case; the reference reports it instead of returning garbage.
TEST(InvSsts, UninitialisedSegmentIsReported) {
  const TsParamsF p = init_ts_params(kMinLum, 1000.0f);
  float unmatched = 0.0f;
  for (float y = 4.7999f; y <= 4.8001f; y = std::nextafter(y, 10.0f)) {
    if (!inv_ssts(y, p)) {
      unmatched = y;
      break;
    }
  }
  ASSERT_NE(unmatched, 0.0f) << "no luminance near Mid.y hits the unmatched interval";
  const AcesConfigured c = configure_aces_tonemap_params(kMinLum, unmatched, 1000.0f);
  ASSERT_FALSE(c.status.ok());
  EXPECT_NE(c.status.error().message.find("uninitialised"), std::string::npos);
  EXPECT_TRUE(std::isnan(c.exp_shift));
  // The default Mid (15 nits) is far from it.
  EXPECT_TRUE(configure_aces_tonemap_params(kMinLum, 15.0f, 1000.0f).status.ok());
}

// Spec §5.4: with HDR off UE configures MaxLuminance = 0 and uploads what log10(0) gives.
TEST(AcesParams, DegenerateInputsAreReported) {
  const AcesConfigured off = configure_aces_tonemap_params(kMinLum, 15.0f, 0.0f);
  ASSERT_FALSE(off.status.ok());
  EXPECT_NE(off.status.error().message.find("not finite and positive"), std::string::npos);
  EXPECT_NE(off.status.error().message.find("0) nits"), std::string::npos);
  // What UE uploads anyway: Max.y = 0 and −Inf high coefficients (log10 of 0).
  EXPECT_EQ(off.packed.min_max_data[3], 0.0f);
  EXPECT_TRUE(std::isinf(off.packed.coefs_high_0[3]) && off.packed.coefs_high_0[3] < 0.0f);

  EXPECT_FALSE(validate_aces_luminances(0.0f, 15.0f, 1000.0f).ok());
  EXPECT_FALSE(validate_aces_luminances(-1.0f, 15.0f, 1000.0f).ok());
  EXPECT_FALSE(validate_aces_luminances(kMinLum, std::nanf(""), 1000.0f).ok());
  EXPECT_FALSE(validate_aces_luminances(kMinLum, 15.0f, INFINITY).ok());
  EXPECT_FALSE(validate_aces_luminances(kMinLum, 1000.0f, 1000.0f).ok());
  EXPECT_FALSE(validate_aces_luminances(20.0f, 15.0f, 1000.0f).ok());
  EXPECT_TRUE(validate_aces_luminances(kMinLum, 15.0f, 600.0f).ok());
}

// HDRHelper.h: GetACESTonemapParameters clamps GamutCompression with FMath::Clamp (NaN → 1);
// SceneColorMultiplier is passed through.
TEST(AcesParams, GamutCompressionClampedSceneColorMultiplierNot) {
  const auto gc = [](float v) {
    return configure_aces_tonemap_params(kMinLum, 15.0f, 1000.0f, 1.5f, v).packed.gamut_compression;
  };
  EXPECT_EQ(gc(0.3f), 0.3f);
  EXPECT_EQ(gc(2.0f), 1.0f);
  EXPECT_EQ(gc(-0.5f), 0.0f);
  EXPECT_EQ(gc(std::nanf("")), 1.0f);
  EXPECT_EQ(
      configure_aces_tonemap_params(kMinLum, 15.0f, 1000.0f, 7.0f).packed.scene_color_multiplier,
      7.0f);
}

// ---------------------------------------------------------------------------------------------
// Shader helpers against published numbers.

// Spec §13 red-modifier weights, ACES cubic B-spline column, hue 0/10/30/60 degrees.
TEST(AcesCommon, CubicBasisShaperSpecWeights) {
  EXPECT_NEAR(cubic_basis_shaper(0.0, 135.0), 1.0, 5e-7);
  EXPECT_NEAR(cubic_basis_shaper(10.0, 135.0), 0.887822, 5e-7);
  EXPECT_NEAR(cubic_basis_shaper(30.0, 135.0), 0.341564, 5e-7);
  EXPECT_NEAR(cubic_basis_shaper(60.0, 135.0), 0.002743, 5e-7);
  EXPECT_NEAR(cubic_basis_shaper(-30.0, 135.0), cubic_basis_shaper(30.0, 135.0), 1e-15);
  EXPECT_EQ(cubic_basis_shaper(67.5, 135.0), 0.0);
  EXPECT_EQ(cubic_basis_shaper(kNaN, 135.0), 0.0);
}

TEST(AcesCommon, HueAndSaturationEdgeCases) {
  EXPECT_EQ(rgb_2_hue(grey(0.5)), 0.0);             // UE: 0 for neutrals (CTL: NaN)
  EXPECT_NEAR(rgb_2_hue({0, 1, 0}), 120.0, 1e-12);  // green
  EXPECT_NEAR(rgb_2_hue({0, 0, 1}), 240.0, 1e-12);  // blue
  EXPECT_EQ(rgb_2_hue({kNaN, 1, 0}), 0.0);          // clamp(NaN, 0, 360) = 0 on D3D
  EXPECT_EQ(rgb_2_saturation(grey(3.0)), 0.0);
  EXPECT_NEAR(rgb_2_saturation({1, 0, 0}), 1.0, 1e-9);
  EXPECT_EQ(sigmoid_shaper(-2.0), 0.0);
  EXPECT_EQ(sigmoid_shaper(2.0), 1.0);
  EXPECT_EQ(sigmoid_shaper(0.0), 0.5);
  EXPECT_EQ(center_hue(350.0, 0.0), -10.0);
}

// compressColor: a colour whose AP1 red sits exactly at the cyan limit (distance 1.147) is mapped
// onto the AP1 gamut boundary (red 0); in-gamut colours (distance < threshold) and colours with a
// negative AP0 component (UE's bypass) are returned unchanged (up to the literal AP0↔AP1 round
// trip, ≤ 1e-9).
TEST(CompressColor, LimitMapsToBoundaryAndBypasses) {
  const Vec3 ap1_at_limit{1.0 - 1.147, 1.0, 0.5};
  const Vec3 aces = lit::kAp1ToAp0 * ap1_at_limit;
  ASSERT_TRUE(aces[0] > 0 && aces[1] > 0 && aces[2] > 0);
  const Vec3 out_ap1 = lit::kAp0ToAp1 * compress_color(aces);
  EXPECT_NEAR(out_ap1[0], 0.0, 1e-6);
  EXPECT_NEAR(out_ap1[1], 1.0, 1e-9);  // the achromatic (max) channel is untouched
  EXPECT_NEAR(out_ap1[2], 0.5, 1e-9);  // distance 0.5 < 0.880: not compressed

  const Vec3 in_gamut = lit::kAp1ToAp0 * Vec3{0.3, 0.5, 0.2};
  const Vec3 same = compress_color(in_gamut);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(same[i], in_gamut[i], 1e-9);

  const Vec3 negative{-0.01, 0.5, 0.2};  // a negative AP0 channel: bypassed
  const Vec3 kept = compress_color(negative);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(kept[i], negative[i], 1e-9);
}

// ---------------------------------------------------------------------------------------------
// (b) OpenColorIO 2.1 as an oracle.
//
// "ACES-OUTPUT - ACES2065-1_to_CIE-XYZ-D65 - HDR-VIDEO-<N>nit-15nit-REC2020lim_1.1"
// (OCIO src/OpenColorIO/transforms/builtins/ACES.cpp): glow + red modifier, clamp, AP0→AP1,
// clamp, RRT_SAT_MAT, log10, a GradingBSplineCurve holding the SSTS knots and slopes (8-digit
// floats), 10^x, (Y − 1e-4)/(Y_MAX − 1e-4), AP1→Rec.2020 (no CAT), clamp [0, 1], Rec.2020→XYZ,
// Bradford D60→D65, × Y_MAX/100 ("The PQ curve expects nits / 100": XYZ 1.0 = 100 nits).
// For ACES greys the glow and red modifier are inactive (saturation 0) and UE's pipeline reduces
// to the same maths, so OCIO's Y·100 must equal our nits — except where Rec.2020 limiting clips:
// a D60 grey has Rec.2020 red > 1 once linCV > ≈ 0.97, which OCIO clips and UE (limiting to AP1)
// does not. `ocio_rec2020_limited_nits` applies that step (double, matrices from primaries as OCIO
// builds them) to our output so the comparison covers the whole range.

OCIO::ConstCPUProcessorRcPtr ocio_processor(const OCIO::ConstTransformRcPtr& t) {
  // Processor caching off: OCIO 2.1.2's cache key ignores GradingBSplineCurve slopes (observed:
  // changing only a slope returned the previous processor). Lossless optimisation: no
  // OPTIMIZATION_FAST_LOG_EXP_POW approximations (measured identical to the default here).
  static const OCIO::ConfigRcPtr cfg = [] {
    OCIO::ConfigRcPtr c = OCIO::Config::CreateRaw()->createEditableCopy();
    c->setProcessorCacheFlags(OCIO::PROCESSOR_CACHE_OFF);
    return c;
  }();
  return cfg->getProcessor(t)->getOptimizedCPUProcessor(OCIO::OPTIMIZATION_LOSSLESS);
}

OCIO::ConstCPUProcessorRcPtr ocio_hdr_video(int nits) {
  auto bt = OCIO::BuiltinTransform::Create();
  bt->setStyle(("ACES-OUTPUT - ACES2065-1_to_CIE-XYZ-D65 - HDR-VIDEO-" + std::to_string(nits) +
                "nit-15nit-REC2020lim_1.1")
                   .c_str());
  return ocio_processor(bt);
}

Vec3 white_xyz(double x, double y) {
  return {x / y, 1.0, (1.0 - x - y) / y};
}

double ocio_rec2020_limited_nits(const Vec3& ap1_nits, double y_max) {
  const Mat3 ap1_to_xyz = stdm::rgb_to_xyz(stdm::kAp1);
  const Mat3 rec2020_to_xyz = stdm::rgb_to_xyz(stdm::kRec2020);
  Vec3 rgb = hdrc::ref::inverse(rec2020_to_xyz) * (ap1_to_xyz * ap1_nits);
  for (double& v : rgb) v = std::fmin(std::fmax(v / y_max, 0.0), 1.0);
  const Mat3 cat = stdm::bradford(white_xyz(0.32168, 0.33767), white_xyz(0.3127, 0.3290));
  return (cat * (rec2020_to_xyz * rgb))[1] * y_max;
}

struct OcioComparison {
  double worst_limited = 0;    // vs our output with OCIO's Rec.2020 limiting applied
  double worst_unlimited = 0;  // vs our raw AP1 luminance
  double at_worst = 0;         // ACES input of worst_limited
};

// Greys ACES2065-1 1e-4 … 1e3, 20 per decade, fed straight to the AP0 input (ToAP0 = identity,
// SceneColorMultiplier 1, GamutCompression 0), for inputs up to `max_aces`.
OcioComparison compare_with_ocio(int nits, double max_aces) {
  const auto cpu = ocio_hdr_video(nits);
  const AcesShaderParams p = shader_params(static_cast<float>(nits), 1.0f, 0.0f);
  OcioComparison r;
  for (int k = 0; k <= 140; ++k) {
    const double x = std::pow(10.0, -4.0 + k / 20.0);
    if (x > max_aces) break;
    float px[3] = {static_cast<float>(x), static_cast<float>(x), static_cast<float>(x)};
    cpu->applyRGB(px);
    const double ocio_nits = 100.0 * px[1];  // OCIO: XYZ Y = nits / 100
    const Vec3 out = aces_output_transforms_1000(grey(x), Mat3::identity(), p);
    const double limited = rel(ocio_nits, ocio_rec2020_limited_nits(out, nits));
    const double unlimited = rel(ocio_nits, hdrc::ref::dot(out, lit::kAp1RgbToY));
    if (!(limited <= r.worst_limited)) {
      r.worst_limited = limited;
      r.at_worst = x;
    }
    r.worst_unlimited = std::fmax(r.worst_unlimited, unlimited);
  }
  return r;
}

// Measured (glibc 2.36, OCIO 2.1.2): worst 1.5e-6 relative over both with limiting modelled
// (2000 nits without the model: 2.96e-3, OCIO's Rec.2020 clip above ACES ≈ 700; 4000 nits does
// not reach the clip below ACES 1000). The residual is OCIO's float32 evaluation (log10/pow and
// 8-digit knots) and UE's float parameters (≤ 1e-6, see AgreeWithSpecDoubleRecomputation); bound
// 1e-5.
TEST(OcioOracle, Hdr2000And4000GreysMatch) {
  for (const int nits : {2000, 4000}) {
    const OcioComparison r = compare_with_ocio(nits, 1e3);
    EXPECT_LT(r.worst_limited, 1e-5) << nits << " nits, worst at ACES " << r.at_worst;
  }
  EXPECT_GT(compare_with_ocio(2000, 1e3).worst_unlimited, 1e-3);  // the clip is really there
}

// 1000 nits: OCIO 2.1.2 does not evaluate its own 1000-nit SSTS knots as the B-spline they
// describe. In its GradingBSplineCurve fit (GradingBSplineCurve.cpp: AdjustSlopes) the last
// segment's 2·secant − slope evaluates to −1.6e-7 in float, which triggers a slope rescale by
// ≈0.995 and a refit with extra knots; the curve then leaves the B-spline between the upper knots
// (log10 ACES 0.2235 … 2.8405) by up to 2.0e-4 in log10 (4.7e-4 relative). UE (and the ACES CTL,
// and OCIO's own 2000/4000 curves) use the exact quadratic B-spline. So the built-in is compared
// up to the first upper knot (ACES 10^0.2235 = 1.672), and the next test shows the cause.
TEST(OcioOracle, Hdr1000GreysMatchBelowOcioRefitSegment) {
  const OcioComparison r = compare_with_ocio(1000, 1.672);
  EXPECT_LT(r.worst_limited, 1e-5) << "worst at ACES " << r.at_worst;  // measured 1.6e-6
  const OcioComparison all = compare_with_ocio(1000, 1e3);
  EXPECT_GT(all.worst_limited, 1e-4);  // OCIO's refit curve (4.7e-4): this test must see it
  EXPECT_LT(all.worst_limited, 1e-3);  // measured 4.65e-4
}

// OCIO's own 1000-nit control points and slopes (OCIO ACES.cpp, Generate_hdr_tonecurve_ops,
// Y_MAX == 1000), as a GradingRGBCurveTransform on log10 values: verbatim they reproduce the
// built-in's deviation; with the knot-5 slope lowered by 3e-7 (so AdjustSlopes does not fire)
// OCIO's B-spline equals our ssts to 5.1e-7 in log10 over the whole curve.
TEST(OcioOracle, Hdr1000DeviationIsOcioSlopeAdjustment) {
  const std::array<float, 7> x{-5.60050155f, -4.09535157f, -2.59020159f, -1.08505161f,
                               0.22347059f,  1.53199279f,  2.84051500f};
  const std::array<float, 7> y{-4.00000000f, -3.57868829f, -1.82131329f, 0.68124124f,
                               2.22673503f,  2.87906206f,  3.00000000f};
  const std::array<float, 7> slopes{0.f,         0.55982688f, 1.77532247f, 1.55f,
                                    0.81219728f, 0.1848466f,  0.f};
  const TsParams p = shader_params(1000.0f).aces_params;
  const auto worst_log_error = [&](float slope5_offset) {
    auto curve = OCIO::GradingBSplineCurve::Create(7);
    for (size_t i = 0; i < 7; ++i) {
      curve->getControlPoint(i) = {x[i], y[i]};
      curve->setSlope(i, slopes[i] + (i == 5 ? slope5_offset : 0.0f));
    }
    auto identity = OCIO::GradingBSplineCurve::Create({{0.f, 0.f}, {1.f, 1.f}});
    auto t = OCIO::GradingRGBCurveTransform::Create(OCIO::GRADING_LOG);
    t->setValue(OCIO::GradingRGBCurve::Create(identity, identity, identity, curve));
    const auto cpu = ocio_processor(t);
    double worst = 0.0;
    for (int k = 0; k <= 600; ++k) {
      const double lx = -5.5 + 0.015 * k;
      float v[3] = {static_cast<float>(lx), static_cast<float>(lx), static_cast<float>(lx)};
      cpu->applyRGB(v);
      worst = std::fmax(worst, std::fabs(v[0] - std::log10(ssts(std::pow(10.0, lx), p))));
    }
    return worst;
  };
  EXPECT_GT(worst_log_error(0.0f), 1.5e-4);  // measured 2.02e-4, as the built-in
  EXPECT_LT(worst_log_error(-3e-7f), 1e-6);  // measured 5.1e-7
}

// ---------------------------------------------------------------------------------------------
// (c) Properties and non-finite inputs.

// Strictly increasing between Min.x and Max.x, flat outside. One exception, a property of
// evaluating UE's float parameters in double: the spline ends at (coefsHigh[3] + coefsHigh[4])/2 =
// log10f(Max.y) rounded to float, the flat part at log10(Max.y) in double. For 600 nits the float
// is above (2.77815127 vs 2.7781512504), so the curve drops by 5.3e-8 relative at Max.x (a float
// shader, which also rounds log10(Max.y), has no step). Steps down ≤ 1e-7 relative are allowed at
// the joins only.
TEST(Ssts, MonotonicOnDenseGreyRamp) {
  for (const float max_nits : {600.0f, 1000.0f, 2000.0f, 4000.0f}) {
    const TsParams p = shader_params(max_nits).aces_params;
    double prev = ssts(1e-8, p);
    int violations = 0;
    for (int k = 1; k <= 200000; ++k) {
      const double x = std::pow(10.0, -8.0 + 13.0 * k / 200000);  // 1e-8 … 1e5 ACES
      const double y = ssts(x, p);
      const bool inside = x > p.min.x * 1.0001 && x < p.max.x * 0.9999;
      if (inside ? !(y > prev) : !(y >= prev * (1.0 - 1e-7))) ++violations;
      prev = y;
    }
    EXPECT_EQ(violations, 0) << max_nits << " nits";
  }
}

// Every channel of the output stays within [0, Max.y] for extreme and saturated inputs, with and
// without gamut compression. The bound carries 1e-9 relative for the literal XYZ↔AP1 round trip
// after limit_to_primaries (XYZ_2_AP1_MAT·AP1_2_XYZ_MAT ≠ I beyond the 10th digit; measured
// overshoot 9.0e-11 relative).
TEST(OutputTransform, NeverExceedsMaxLuminance) {
  uint64_t state = 12345;
  const auto next = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0;  // [0, 1)
  };
  for (const float max_nits : {1000.0f, 2000.0f}) {
    for (const float gc : {0.0f, 1.0f}) {
      const AcesShaderParams p = shader_params(max_nits, 1.5f, gc);
      double worst = 0.0;
      for (int k = 0; k < 20000; ++k) {
        Vec3 c;
        for (double& v : c) v = std::pow(10.0, -6.0 + 12.0 * next()) * (next() < 0.1 ? -1 : 1);
        if (k % 3 == 0) c[k % 2] = 0.0;  // fully saturated
        const Vec3 out = aces_output_transforms_2000(c, Mat3::identity(), p);
        for (const double v : out) {
          ASSERT_GE(v, 0.0);
          worst = std::fmax(worst, v);
        }
      }
      EXPECT_LE(worst, max_nits * (1.0 + 1e-9)) << max_nits << " nits, GC " << gc;
      EXPECT_GT(worst, max_nits * 0.99);  // the range really reaches the peak
    }
  }
}

// D3D semantics (header of aces_output.h): any NaN or ±Inf channel → black; negatives are
// clamped to 0 before the tone scale, whose floor Min.y maps to 0 nits with STRETCH_BLACK.
TEST(OutputTransform, NonFiniteAndNegativeInputs) {
  const AcesShaderParams p = shader_params(1000.0f);
  const Mat3 id = Mat3::identity();
  for (const Vec3& in : {Vec3{kNaN, 0.18, 0.18}, Vec3{0.18, kNaN, 0.18}, grey(kNaN),
                         Vec3{kInf, 0.18, 0.18}, grey(kInf), Vec3{-kInf, 1.0, 1.0}}) {
    const Vec3 out = aces_output_transforms_1000(in, id, p);
    for (const double v : out) EXPECT_LE(v, 1e-12) << in[0] << " " << in[1] << " " << in[2];
  }
  for (const float gc : {0.0f, 1.0f}) {
    const AcesShaderParams pg = shader_params(1000.0f, 1.5f, gc);
    for (const double v : aces_output_transforms_1000(grey(-1.0), id, pg)) EXPECT_LE(v, 1e-12);
    for (const double v : aces_output_transforms_1000(grey(0.0), id, pg)) EXPECT_LE(v, 1e-12);
    const Vec3 mixed = aces_output_transforms_1000({-0.5, 0.3, 0.1}, id, pg);
    for (const double v : mixed) EXPECT_TRUE(std::isfinite(v) && v >= 0.0 && v <= 1000.0);
  }
  // NaN never reaches ssts (sweeteners clamp it), but ssts itself maps NaN like x ≤ Min.x.
  EXPECT_EQ(ssts(kNaN, p.aces_params), ssts(0.0, p.aces_params));
}

// ---------------------------------------------------------------------------------------------
// (d) Bit-exact pin of the output transform.
//
// The reference is what goldens are checked against, so an optimisation of it must not change a
// single output bit. `pinned_colour` draws a deterministic spread of AP0/working-space colours:
// exact specials (±0, NaN, ±Inf, subnormals, DBL_MAX, HALF_MAX, …), uniform [−1, 1], log-uniform
// positives 1e-12 … 1e5, subnormal-to-tiny magnitudes, small negatives, greys and two-equal-channel
// colours (rgb_2_hue's special case). `pinned_hash` runs every colour through
// aces_output_transforms_1000 for four parameter sets (1000 and 2000 nits; gamut compression 0,
// 0.5, 1; scene colour multiplier 1.5 and 1) and two working spaces (identity, sRGB → AP0) and
// folds the 3 output doubles' bytes into one 64-bit FNV-1a hash per parameter set.
constexpr int kPinnedColours = 131072;

uint64_t splitmix64(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

double unit(uint64_t& state) {  // [0, 1), 53 bits
  return static_cast<double>(splitmix64(state) >> 11) / 9007199254740992.0;
}

double pinned_channel(uint64_t& state) {
  static constexpr double kSpecials[] = {
      0.0,
      -0.0,
      kNaN,
      -kNaN,
      kInf,
      -kInf,
      std::numeric_limits<double>::denorm_min(),
      std::numeric_limits<double>::min(),
      std::numeric_limits<double>::max(),
      -std::numeric_limits<double>::max(),
      -1e-300,
      6e289,  // huge, and still finite after ×1.5 and a working-space matrix
      -6e289,
      9.9e289,
      1e200,
      1e-10,
      -1.0,
      1.0,
      0.18,
      65504.0,
      65535.0,
      1e5};
  constexpr int kNumSpecials = sizeof kSpecials / sizeof kSpecials[0];
  switch (splitmix64(state) % 16) {
    case 0:
      return kSpecials[splitmix64(state) % kNumSpecials];
    case 1:
    case 2:
      return -1.0 + 2.0 * unit(state);
    case 3:
      return std::pow(10.0, -320.0 + 308.0 * unit(state));  // subnormal … 1e-12
    case 4:
      return -std::pow(10.0, -12.0 + 12.0 * unit(state));  // −1e-12 … −1
    case 5:
      return 1e5 * unit(state);
    default:
      return std::pow(10.0, -12.0 + 17.0 * unit(state));  // 1e-12 … 1e5
  }
}

Vec3 pinned_colour(uint64_t& state) {
  Vec3 c{pinned_channel(state), pinned_channel(state), pinned_channel(state)};
  switch (splitmix64(state) % 16) {
    case 0:
      c[1] = c[2] = c[0];  // grey
      break;
    case 1:
      c[2] = c[1];
      break;
    default:
      break;
  }
  return c;
}

struct PinnedSet {
  float max_nits, scm, gc;
};
constexpr PinnedSet kPinnedSets[] = {
    {1000.0f, 1.5f, 0.0f}, {1000.0f, 1.5f, 1.0f}, {1000.0f, 1.5f, 0.5f}, {2000.0f, 1.0f, 0.25f}};

// NaNs are hashed as one canonical NaN: which NaN an operation returns (sign, payload) depends on
// the operand order the compiler picks (x86 returns the first operand's NaN), so GCC and clang
// builds of the same code differ there (the sanitizer stage's clang build did, on the pieces);
// the reference only promises "NaN".
void fnv1a(uint64_t& hash, const Vec3& v) {
  Vec3 c = v;
  for (double& x : c)
    if (std::isnan(x)) x = std::numeric_limits<double>::quiet_NaN();
  unsigned char bytes[sizeof c];
  std::memcpy(bytes, c.data(), sizeof c);
  for (const unsigned char b : bytes) hash = (hash ^ b) * 0x100000001b3ULL;  // FNV prime
}

uint64_t pinned_hash(const PinnedSet& set, std::vector<Vec3>& samples, int& interior) {
  const AcesShaderParams p = shader_params(set.max_nits, set.scm, set.gc);
  const Mat3 working_to_ap0[] = {lit::kXyzToAp0 * lit::kSrgbToXyz, Mat3::identity()};
  uint64_t hash = 0xcbf29ce484222325ULL;  // FNV-1a 64 offset basis
  uint64_t state = 20240517;
  for (int k = 0; k < kPinnedColours; ++k) {
    const Vec3 in = pinned_colour(state);
    for (const Mat3& m : working_to_ap0) {
      const Vec3 out = aces_output_transforms_1000(in, m, p);
      fnv1a(hash, out);
      if (k < 4) samples.push_back(out);
      if (out[1] > 0.0 && out[1] < 0.999 * set.max_nits) ++interior;
    }
  }
  return hash;
}

// Generated by running this test against the implementation at commit c8f0796 (before the
// optimisations of issue 17's performance item) in both the Release (-O3) and RelWithDebInfo (-O2)
// builds, which agree (GCC 12, glibc 2.36's libm: the bits of pow, log10 and atan2 are part of
// what is pinned, so another libm may need its own constants). A changed hash means some output bit
// of the reference changed: that is a change to the reference's results, not an optimisation, and
// the goldens have to be reviewed.
constexpr uint64_t kPinnedHashes[] = {0x267e6b4b733f1cf0ULL, 0x31fe2224218d853aULL,
                                      0x7280a803c4ef2894ULL, 0xaefd3a30c5c56ba2ULL};

TEST(OutputTransform, BitIdenticalToPinnedHash) {
  for (size_t s = 0; s < std::size(kPinnedSets); ++s) {
    std::vector<Vec3> samples;
    int interior = 0;
    const uint64_t h = pinned_hash(kPinnedSets[s], samples, interior);
    std::ostringstream msg;
    msg.precision(17);
    msg << "set " << s << ": hash 0x" << std::hex << h << std::dec << ", first outputs:";
    for (const Vec3& v : samples) msg << " (" << v[0] << ", " << v[1] << ", " << v[2] << ")";
    EXPECT_EQ(h, kPinnedHashes[s]) << msg.str();
    // The pin covers the curve, not just black and the peak: measured 131834 … 161424 of 262144 per
    // set.
    EXPECT_GT(interior, 2 * kPinnedColours * 4 / 10) << interior;
  }
}

// The public pieces on the same colours, so that each stays bit-identical on its own too (they see
// inputs the full transform never passes them: negatives and non-finite values in
// rrt_sweeteners and ssts, gamut compression of any colour). Hash taken as kPinnedHashes' (with
// NaNs canonical, from the same commit c8f0796, -O2 and -O3).
TEST(OutputTransform, PiecesBitIdenticalToPinnedHash) {
  const AcesShaderParams p = shader_params(1000.0f);
  uint64_t hash = 0xcbf29ce484222325ULL;
  uint64_t state = 20240517;
  for (int k = 0; k < kPinnedColours; ++k) {
    const Vec3 in = pinned_colour(state);
    fnv1a(hash, rrt_sweeteners(in));
    fnv1a(hash, compress_color(in));
    fnv1a(hash, output_transform(in, p.aces_params));
    fnv1a(hash,
          {ssts(in[0], p.aces_params), ssts(in[1], p.aces_params), ssts(in[2], p.aces_params)});
  }
  EXPECT_EQ(hash, 0x579bc411733bf03bULL) << std::hex << hash;
}

// d3d::max_num/min_num (HLSL max/min, used by every helper above) return std::fmax/std::fmin's
// bits for every pair: all pairs of specials (±0, ±NaN, ±Inf, subnormals, extremes) and random
// pairs, a quarter of them equal.
TEST(AcesCommon, MaxNumMinNumAreLibmBitForBit) {
  std::vector<double> v = {0.0,
                           -0.0,
                           kNaN,
                           -kNaN,
                           kInf,
                           -kInf,
                           1.0,
                           -1.0,
                           1e-10,
                           0.01,
                           65504.0,
                           std::numeric_limits<double>::denorm_min(),
                           -std::numeric_limits<double>::denorm_min(),
                           std::numeric_limits<double>::max(),
                           std::numeric_limits<double>::lowest()};
  uint64_t state = 99;
  for (int k = 0; k < 20000; ++k) v.push_back(std::ldexp(unit(state) - 0.5, k % 200 - 100));
  const auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  int mismatches = 0;
  for (size_t i = 0; i < 15; ++i) {
    for (size_t j = 0; j < v.size(); ++j) {
      mismatches += !same(hdrc::ref::d3d::max_num(v[i], v[j]), std::fmax(v[i], v[j]));
      mismatches += !same(hdrc::ref::d3d::max_num(v[j], v[i]), std::fmax(v[j], v[i]));
      mismatches += !same(hdrc::ref::d3d::min_num(v[i], v[j]), std::fmin(v[i], v[j]));
      mismatches += !same(hdrc::ref::d3d::min_num(v[j], v[i]), std::fmin(v[j], v[i]));
    }
  }
  for (size_t j = 15; j + 1 < v.size(); ++j) {
    const double b = j % 4 == 0 ? v[j] : v[j + 1];
    mismatches += !same(hdrc::ref::d3d::max_num(v[j], b), std::fmax(v[j], b));
    mismatches += !same(hdrc::ref::d3d::min_num(v[j], b), std::fmin(v[j], b));
  }
  EXPECT_EQ(mismatches, 0);
}

}  // namespace
