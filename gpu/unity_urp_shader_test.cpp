// The GLSL of Unity URP's colour grading (gpu/shaders/unity_urp/) against the double-precision
// reference (reference/unity_urp/unity_urp.h), on the Vulkan engine (lavapipe by default):
//  * every constant the GLSL hard-codes reads back as float(reference constant);
//  * each library function (LogC, ACEScc, HSV, the ACES fit, Neutral, the grade of every mode,
//    the uber pass's tone map, the half rounding) over lattice codes and ramps, within the
//    measured bounds below (printed);
//  * the two stage shaders through the engine: stages/lut_bake.comp's strip against
//    bake_lut_strip (in half ulps), and stages/color_grading.comp's image against grade_image;
//  * planted one-line defects in the GLSL (a LogC constant off by 1e-6, the hue wrap replaced by
//    a clamp, the split-toning balance sign) are caught by the strip comparison.
// The stage shaders run in a copy of the shader directory as the engine's combine_luts and tonemap
// passes (the same bindings: lut_store_2d, then lut_2d and in_px/out_px), so this test does not
// depend on the unity_urp stage table.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "gpu/device_bounds_test.h"
#include "gpu/shader_compiler.h"
#include "gpu/shader_probe.h"
#include "reference/unity_urp/unity_urp.h"
#include "reference/unity_urp/unity_urp_settings.h"

namespace {

namespace urp = hdrc::ref::unity_urp;
using hdrc::Image;
using hdrc::ParamBlock;
using hdrc::ResolvedCase;
using hdrc::SettingValues;
using hdrc::gpu::testing::ErrorStats;
using hdrc::gpu::testing::make_case;
using hdrc::gpu::testing::read_back;
using hdrc::ref::Mat3;
using hdrc::ref::Vec3;

SettingValues new_settings() {
  return SettingValues(&hdrc::unity_urp_setting_table(), &hdrc::unity_urp_setting_choices);
}

// A settings set: grading mode, tone mapping, LUT size, and optionally every grading control off
// its default ("busy": white balance, contrast, filter, hue, saturation, split toning, mixer,
// SMH, lift/gamma/gain all active).
SettingValues settings(const char* grading, const char* tonemapping, int lut_size, bool busy) {
  SettingValues s = new_settings();
  EXPECT_TRUE(s.set_choice("GradingMode", grading).ok());
  EXPECT_TRUE(s.set_choice("Tonemapping.mode", tonemapping).ok());
  EXPECT_TRUE(s.set("LutSize", {static_cast<double>(lut_size), 0, 0, 0}, 1).ok());
  if (busy) {
    auto set1 = [&](const char* n, double v) { EXPECT_TRUE(s.set(n, {v, 0, 0, 0}, 1).ok()) << n; };
    auto set4 = [&](const char* n, hdrc::Vec4d v) { EXPECT_TRUE(s.set(n, v, 4).ok()) << n; };
    set1("WhiteBalance.temperature", 25);
    set1("WhiteBalance.tint", -15);
    set1("ColorAdjustments.postExposure", 0.5);
    set1("ColorAdjustments.contrast", 30);
    set4("ColorAdjustments.colorFilter", {1.0, 0.9, 0.8, 1});
    set1("ColorAdjustments.hueShift", 40);
    set1("ColorAdjustments.saturation", 25);
    set4("SplitToning.shadows", {0.35, 0.45, 0.65, 1});
    set4("SplitToning.highlights", {0.7, 0.55, 0.35, 1});
    set1("SplitToning.balance", -20);
    set1("ChannelMixer.redOutGreenIn", 15);
    set1("ChannelMixer.blueOutBlueIn", 90);
    set4("ShadowsMidtonesHighlights.shadows", {0.9, 1.0, 1.1, 0.05});
    set4("ShadowsMidtonesHighlights.highlights", {1.05, 1.0, 0.9, -0.05});
    set4("LiftGammaGain.lift", {1.0, 0.95, 1.05, 0.02});
    set4("LiftGammaGain.gamma", {1.05, 1.0, 0.95, -0.1});
    set4("LiftGammaGain.gain", {1.0, 1.02, 0.98, 0.1});
  }
  return s;
}

// The block of `s`; lut_format >= 0 replaces the storage format derive_unity_urp chose (2:
// RGBA32F, which keeps the bake's float32 values).
ParamBlock urp_params(const SettingValues& s, int lut_format = -1) {
  ParamBlock p;
  hdrc::derive_unity_urp(s, &p);
  if (lut_format >= 0) p.lut_format = lut_format;
  return p;
}

// A case for `stage` on `input` whose block carries the unity_urp fields of `s`.
ResolvedCase urp_case(const char* stage, const Image& input, const SettingValues& s,
                      int lut_format = -1) {
  ResolvedCase rc = make_case(stage, 3, input);
  hdrc::derive_unity_urp(s, &rc.params);
  if (lut_format >= 0) rc.params.lut_format = lut_format;
  return rc;
}

// Both stage shaders compile where they are (their includes resolve from unity_urp/stages/).
TEST(UnityUrpShader, StageShadersCompileInPlace) {
  for (const char* shader :
       {"unity_urp/stages/lut_bake.comp", "unity_urp/stages/color_grading.comp"}) {
    auto spirv = hdrc::gpu::compile_compute(hdrc::gpu::default_shader_dir(), shader);
    EXPECT_TRUE(spirv.ok()) << shader << ": " << spirv.error().to_string();
  }
}

// --- Constants ----------------------------------------------------------------------------------

TEST(UnityUrpShader, ConstantsEqualTheReference) {
  struct Expected {
    std::string glsl;
    double reference;
  };
  std::vector<Expected> e = {
      {"URP_LOGC_A", urp::kUnityLogC.a},
      {"URP_LOGC_B", urp::kUnityLogC.b},
      {"URP_LOGC_C", urp::kUnityLogC.c},
      {"URP_LOGC_D", urp::kUnityLogC.d},
      {"URP_ACESCC_MIDGRAY", urp::kAcesccMidgray},
      {"URP_HALF_MAX", urp::kHalfMax},
      {"URP_ACESCC_MAX_CODE", (std::log2(urp::kHalfMax) + 9.72) / 17.52},
      {"URP_CURVE_CAP", urp::kCurveCap},
  };
  const struct {
    const char* glsl;
    const Mat3& m;
  } matrices[] = {
      {"URP_SRGB_TO_AP0", urp::kSrgbToAp0},      {"URP_AP0_TO_AP1", urp::kAp0ToAp1},
      {"URP_AP1_TO_AP0", urp::kAp1ToAp0},        {"URP_AP1_TO_XYZ", urp::kAp1ToXyz},
      {"URP_XYZ_TO_AP1", urp::kXyzToAp1},        {"URP_XYZ_TO_REC709", urp::kXyzToRec709},
      {"URP_D60_TO_D65_CAT", urp::kD60ToD65Cat}, {"URP_LINEAR_TO_LMS", urp::kLinearToLms},
      {"URP_LMS_TO_LINEAR", urp::kLmsToLinear}};
  // `const mat3 M = mat3(HLSL row-major list)`: M[i] is row i of the HLSL matrix.
  for (const auto& m : matrices)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        e.push_back({std::string(m.glsl) + "[" + std::to_string(r) + "][" + std::to_string(c) + "]",
                     m.m(r, c)});
  for (int c = 0; c < 3; ++c) {
    e.push_back({"URP_AP1_RGB_TO_Y[" + std::to_string(c) + "]", urp::kAp1RgbToY[c]});
    e.push_back({"URP_REC709_RGB_TO_Y[" + std::to_string(c) + "]", urp::kRec709RgbToY[c]});
  }
  std::vector<std::string> glsl;
  for (const auto& x : e) glsl.push_back(x.glsl);
  auto got = read_back(glsl, {"unity_urp/lib/unity_grade.glsl"});
  ASSERT_TRUE(got.ok()) << got.error().to_string();
  for (size_t k = 0; k < e.size(); ++k)
    EXPECT_EQ((*got)[k], static_cast<float>(e[k].reference)) << e[k].glsl;
}

// --- Functions ----------------------------------------------------------------------------------

// One probe for every function: in_px[i].w selects it, in_px[i].rgb is its argument.
enum Fn {
  kLogcEncode = 0,
  kLogcDecode,
  kAcesccEncode,
  kAcesccDecode,
  kHsvFromRgb,
  kRgbFromHsv,
  kAcesTonemap,
  kNeutral,
  kLutTexel,
  kColorGrade,
  kUberTonemap,
  kRoundToHalf,
  kRoundToUnorm8,
};

std::string function_probe() {
  return hdrc::gpu::testing::probe_preamble() +
         "#include \"unity_urp/lib/unity_grade.glsl\"\n"
         "#include \"unity_urp/lib/unity_lut.glsl\"\n"
         "void main() {\n"
         "  uint i = gl_GlobalInvocationID.x;\n"
         "  if (i >= uint(P.width * P.height)) return;\n"
         "  vec3 x = in_px[i].rgb;\n"
         "  int fn = int(in_px[i].w);\n"
         "  vec3 y = vec3(0.0);\n"
         "  if (fn == 0) y = urp_logc_from_linear(x);\n"
         "  if (fn == 1) y = urp_linear_from_logc(x);\n"
         "  if (fn == 2) y = vec3(urp_acescc_from_linear(x.r), urp_acescc_from_linear(x.g),\n"
         "                        urp_acescc_from_linear(x.b));\n"
         "  if (fn == 3) y = vec3(urp_linear_from_acescc(x.r), urp_linear_from_acescc(x.g),\n"
         "                        urp_linear_from_acescc(x.b));\n"
         "  if (fn == 4) y = urp_hsv_from_rgb(x);\n"
         "  if (fn == 5) y = urp_rgb_from_hsv(x);\n"
         "  if (fn == 6) y = urp_aces_tonemap(x);\n"
         "  if (fn == 7) y = urp_neutral_tonemap(x);\n"
         "  if (fn == 8) y = urp_lut_texel(x);\n"
         "  if (fn == 9) y = urp_color_grade(x);\n"
         "  if (fn == 10) y = urp_uber_tonemap(x, P.urp_tonemap_mode);\n"
         "  if (fn == 11) y = vec3(urp_round_to_half(x.r), urp_round_to_half(x.g),\n"
         "                        urp_round_to_half(x.b));\n"
         "  if (fn == 12) y = vec3(urp_round_to_unorm8(x.r), urp_round_to_unorm8(x.g),\n"
         "                        urp_round_to_unorm8(x.b));\n"
         "  out_px[i] = vec4(y, 0.0);\n"
         "}\n";
}

Vec3 reference_fn(Fn fn, const Vec3& x, const ParamBlock& p) {
  switch (fn) {
    case kLogcEncode:
      return urp::logc_from_linear(x);
    case kLogcDecode:
      return urp::linear_from_logc(x);
    case kAcesccEncode:
      return {urp::acescc_from_linear(x[0]), urp::acescc_from_linear(x[1]),
              urp::acescc_from_linear(x[2])};
    case kAcesccDecode:
      return {urp::linear_from_acescc(x[0]), urp::linear_from_acescc(x[1]),
              urp::linear_from_acescc(x[2])};
    case kHsvFromRgb:
      return urp::hsv_from_rgb(x);
    case kRgbFromHsv:
      return urp::rgb_from_hsv(x);
    case kAcesTonemap:
      return urp::aces_tonemap(x);
    case kNeutral:
      return urp::neutral_tonemap(x);
    case kLutTexel:
      return urp::lut_texel(x, p);
    case kColorGrade:
      return urp::color_grade(x, p);
    case kUberTonemap:
      return urp::uber_tonemap(x, urp::tonemap_mode(p));
    case kRoundToHalf:
      return {urp::quantize_texel(1, x[0]), urp::quantize_texel(1, x[1]),
              urp::quantize_texel(1, x[2])};
    case kRoundToUnorm8:  // the shader holds k/255 as the nearest float (the store takes k)
      return {static_cast<float>(urp::quantize_texel(3, x[0])),
              static_cast<float>(urp::quantize_texel(3, x[1])),
              static_cast<float>(urp::quantize_texel(3, x[2]))};
  }
  return {};
}

// What a conformant device may compute for `fn` at `x` beyond a float32-exact one, where the test
// derives it (the precision table, "Precision and Operation of SPIR-V Instructions"; reference/
// color/spirv_precision.h): LogC's encode c·(log2(a·x + b)·log10(2)) + d with log2's 3 ULP
// (2^-21 absolute inside [0.5, 2]) and every a·b + c fused or not; UNORM8's k/255 with OpFDiv's
// 2.5 ULP (k is exact: roundEven of a correctly rounded product away from ties). Elsewhere, and on
// a float32-exact device, the reference value itself: the tight bound alone.
hdrc::ref::Range3 device_range(Fn fn, const Vec3& x, const Vec3& want) {
  namespace sp = hdrc::ref::spirv;
  hdrc::ref::Range3 r = hdrc::ref::Range3::point(want);
  if (hdrc::gpu::testing::exact_device()) return r;
  for (int c = 0; c < 3; ++c) {
    sp::Interval v = sp::Interval::point(want[c]);
    if (fn == kLogcEncode) {
      const auto& k = urp::kUnityLogC;
      const sp::Interval t = sp::mul_add(sp::Interval::point(k.a), sp::Interval::point(x[c]),
                                         sp::Interval::point(k.b));
      if (!(t.lo > 0)) continue;
      const sp::Interval l = sp::mul(sp::log2(t), sp::Interval::point(0.30102999566398120));
      v = sp::mul_add(sp::Interval::point(k.c), l, sp::Interval::point(k.d));
    } else if (fn == kRoundToUnorm8) {
      v = sp::div(sp::Interval::point(std::nearbyint(want[c] * 255.0)), sp::Interval::point(255.0));
    } else {
      continue;
    }
    r.lo[c] = std::min(v.lo, want[c]);
    r.hi[c] = std::max(v.hi, want[c]);
  }
  return r;
}

// Runs `fn` on the GPU over `inputs` (each rounded to float, as the engine uploads them) and
// returns the error statistics against the reference: |gpu − ref| / max(largest |ref| of the
// pixel, floor). Relative to the pixel's largest channel, as float32 noise is (core/image.h
// kFloat32Noise): a channel far below the others (the HSV ε leaves ~1e-4·v in a zero channel)
// carries the rounding noise of the large ones.
ErrorStats measure(hdrc::gpu::testing::Probe& probe, Fn fn, const std::vector<Vec3>& inputs,
                   const SettingValues& s, double floor, std::string* worst = nullptr) {
  Image in(static_cast<int>(inputs.size()), 1);
  for (size_t i = 0; i < inputs.size(); ++i) {
    for (int c = 0; c < 3; ++c) in.data[i * 4 + c] = static_cast<float>(inputs[i][c]);
    in.data[i * 4 + 3] = fn;
  }
  const ResolvedCase rc = urp_case("shaper", in, s);
  ErrorStats stats;
  auto got = probe.run(rc);
  EXPECT_TRUE(got.ok()) << got.error().to_string();
  if (!got.ok()) return stats;
  double largest = -1;
  for (size_t i = 0; i < inputs.size(); ++i) {
    const Vec3 x = {in.data[i * 4], in.data[i * 4 + 1], in.data[i * 4 + 2]};
    const Vec3 want = reference_fn(fn, x, rc.params);
    const double scale =
        std::max({std::fabs(want[0]), std::fabs(want[1]), std::fabs(want[2]), floor});
    const hdrc::ref::Range3 range = device_range(fn, x, want);
    for (int c = 0; c < 3; ++c) {
      const double g = got->data[i * 4 + c];
      // On a float32-exact device |g − want|; elsewhere the distance outside the device range.
      const double e = g == want[c]              ? 0.0
                       : std::isnan(g - want[c]) ? std::fabs(g - want[c]) / scale
                                                 : hdrc::gpu::testing::outside(range, c, g) / scale;
      // NaN on either side is an infinite error (!(e <= bound) fails).
      stats.add(std::isnan(e) ? INFINITY : e);
      if (worst && e > largest) {
        largest = e;
        char buf[256];
        std::snprintf(buf, sizeof buf, "in (%.9g, %.9g, %.9g) ch %d ref %.9g gpu %.9g", x[0], x[1],
                      x[2], c, want[c], g);
        *worst = buf;
      }
    }
  }
  return stats;
}

std::vector<Vec3> lattice(int n, double lo = 0.0, double hi = 1.0) {
  std::vector<Vec3> v;
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r)
        v.push_back({lo + (hi - lo) * r / (n - 1), lo + (hi - lo) * g / (n - 1),
                     lo + (hi - lo) * b / (n - 1)});
  return v;
}

std::vector<Vec3> grey_ramp(double lo_log2, double hi_log2, int n) {
  std::vector<Vec3> v;
  for (int i = 0; i < n; ++i) {
    const double x = std::exp2(lo_log2 + (hi_log2 - lo_log2) * i / (n - 1));
    v.push_back({x, x, x});
  }
  return v;
}

// Colours for the tone maps: the 9³ lattice of [0, 1] scaled by 2^-6 .. 2^5, and a grey ramp.
std::vector<Vec3> scene_colours() {
  std::vector<Vec3> v = grey_ramp(-12, 6, 400);
  for (int e = -6; e <= 5; e += 1)
    for (const Vec3& c : lattice(9))
      v.push_back({c[0] * std::exp2(e), c[1] * std::exp2(e), c[2] * std::exp2(e)});
  return v;
}

struct Bound {
  const char* name;
  Fn fn;
  std::vector<Vec3> inputs;
  double floor;  // relative error denominator floor
  double bound;  // max allowed (measured on lavapipe x ~2, rounded up)
};

// Each function against the reference. Bounds: relative to max(|ref|, floor), the measured
// lavapipe maximum with a margin (printed on every run).
TEST(UnityUrpShader, FunctionsMatchTheReference) {
  hdrc::gpu::testing::Probe probe(function_probe());
  const SettingValues defaults = settings("HighDynamicRange", "None", 32, false);
  std::vector<Vec3> logc_in = grey_ramp(-14, 6, 300);
  for (double x : {0.0, -0.001, -0.0039, -0.0086}) logc_in.push_back({x, x, x});
  std::vector<Vec3> codes;
  for (int i = 0; i <= 1000; ++i) codes.push_back({i / 1000.0, i / 1000.0, i / 1000.0});
  std::vector<Vec3> acescc_codes;
  for (int i = 0; i <= 1000; ++i) {
    const double y = -0.36 + 1.83 * i / 1000.0;
    acescc_codes.push_back({y, y, y});
  }
  std::vector<Vec3> hsv_in = lattice(9, 0.0, 2.0);
  std::vector<Vec3> hsv_back;
  for (const Vec3& c : lattice(9)) hsv_back.push_back({c[0], c[1], 2.0 * c[2]});
  std::vector<Vec3> ap0;
  for (const Vec3& c : scene_colours()) ap0.push_back(urp::kSrgbToAp0 * c);
  std::vector<Vec3> halves = grey_ramp(-26, 17, 600);
  for (Vec3& h : halves) h = {h[0], -h[1] * 1.0001, h[2] * 0.9999};
  // Ties (to even), the largest half, overflow, subnormal ties.
  const double t = std::exp2(-11);
  halves.push_back({1 + t, 1 + 3 * t, -(1 + 5 * t)});
  halves.push_back({65519.0, 65520.0, -65504.0});
  halves.push_back({std::exp2(-25), 3 * std::exp2(-25), -5 * std::exp2(-25)});
  std::vector<Vec3> unorms;  // every code, a quarter code off, and out of range
  for (int k = -4; k <= 259; ++k)
    unorms.push_back({k / 255.0, (k + 0.25) / 255.0, (k - 0.3) / 255.0});

  // Bounds (relative to max(largest |ref| of the pixel, floor)): the lavapipe maxima printed below
  // with a margin. lavapipe's exp2/log2 are polynomial approximations (~2.7e-6 relative through
  // LogC^-1's 10^x); the codes (LogC, ACEScc encodes) are compared absolutely (floor 1); the ACEScc
  // decode's lower branch subtracts 2^-16 (floor 1e-3 below which the error is absolute); Neutral's
  // rational subtracts E/F = 0.0667 from ~0.068 near 0 (floor 1e-2).
  const Bound bounds[] = {
      {"LogC encode", kLogcEncode, logc_in, 1.0, 5e-7},
      {"LogC decode", kLogcDecode, codes, 1e-3, 5e-6},
      {"ACEScc encode", kAcesccEncode, grey_ramp(-18, 16, 400), 1.0, 5e-7},
      {"ACEScc decode", kAcesccDecode, acescc_codes, 1e-3, 5e-6},
      {"RgbToHsv", kHsvFromRgb, hsv_in, 1e-3, 5e-7},
      {"HsvToRgb", kRgbFromHsv, hsv_back, 1e-3, 1e-6},
      {"AcesTonemap", kAcesTonemap, ap0, 1e-3, 5e-6},
      {"Neutral", kNeutral, scene_colours(), 1e-2, 5e-6},
      {"half rounding", kRoundToHalf, halves, 1e-30, 0.0},
      {"UNORM8 rounding", kRoundToUnorm8, unorms, 1e-30, 0.0},
  };
  for (const Bound& b : bounds) {
    std::string worst;
    const ErrorStats st = measure(probe, b.fn, b.inputs, defaults, b.floor, &worst);
    std::printf("[ urp ] %-14s n %5zu rel max %.3g p99.9 %.3g | worst %s\n", b.name,
                st.errors.size(), st.max(), st.percentile(0.999), worst.c_str());
    EXPECT_LE(st.max(), b.bound) << b.name << ": " << worst;
  }
}

// The whole grade (ColorGrade + Tonemap, or the LDR bake) over a 17³ lattice of codes, for every
// mode at the default settings and with every control active; the uber pass's tone map over scene
// colours.
TEST(UnityUrpShader, GradeMatchesTheReference) {
  hdrc::gpu::testing::Probe probe(function_probe());
  // Bounds: the lavapipe maxima printed below with a margin, relative to the pixel's largest
  // channel. Neutral (and ACES) compress the largest channel up to 49x but not a small one beside
  // it, so the float32 noise of the graded pixel (largest channel up to 58.9) grows relative to
  // the tone-mapped pixel's largest channel.
  const struct {
    const char* grading;
    const char* tonemapping;
    bool busy;
    double bound;
  } modes[] = {
      {"HighDynamicRange", "None", false, 1e-5},   {"HighDynamicRange", "Neutral", false, 6e-5},
      {"HighDynamicRange", "ACES", false, 1.5e-5}, {"LowDynamicRange", "None", false, 3e-6},
      {"HighDynamicRange", "None", true, 3e-5},    {"HighDynamicRange", "Neutral", true, 4e-5},
      {"HighDynamicRange", "ACES", true, 5e-5},    {"LowDynamicRange", "None", true, 6e-6},
  };
  for (const auto& m : modes) {
    const SettingValues s = settings(m.grading, m.tonemapping, 32, m.busy);
    std::string worst;
    const ErrorStats st = measure(probe, kLutTexel, lattice(17), s, 1e-3, &worst);
    std::printf("[ urp ] grade %-16s %-7s %-5s rel max %.3g p99.9 %.3g | worst %s\n", m.grading,
                m.tonemapping, m.busy ? "busy" : "dflt", st.max(), st.percentile(0.999),
                worst.c_str());
    EXPECT_LE(st.max(), m.bound) << m.grading << " " << m.tonemapping << ": " << worst;
  }
  for (const char* t : {"None", "Neutral", "ACES"}) {
    const SettingValues s = settings("LowDynamicRange", t, 32, false);
    std::string worst;
    const ErrorStats st = measure(probe, kUberTonemap, scene_colours(), s, 1e-3, &worst);
    std::printf("[ urp ] uber tonemap %-7s rel max %.3g | worst %s\n", t, st.max(), worst.c_str());
    EXPECT_LE(st.max(), 3e-5) << t << ": " << worst;  // Neutral: 1.6e-5 measured (see above)
  }
}

// --- The stage shaders through the engine -------------------------------------------------------

std::string read_shader(const std::string& relative) {
  std::ifstream f(hdrc::gpu::default_shader_dir() + "/" + relative);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

// A shader-directory copy where the engine's combine_luts pass is lut_bake.comp and its tonemap
// pass color_grading.comp (their ../lib includes pointed at unity_urp/lib). A planted defect
// replaces the text `from` of library file `lib` with `to`.
class UrpStageEngine {
 public:
  // `follow_model`: the engine runs under HDRC_DEVICE_MODEL (device_bounds_test.h test_options),
  // for a test whose bounds have a derived branch; else on the device as it is.
  explicit UrpStageEngine(const std::string& lib = "", const std::string& from = "",
                          const std::string& to = "", bool follow_model = false)
      : dir_("urp") {
    auto relink = [](std::string s) {
      for (size_t at; (at = s.find("\"../lib/")) != std::string::npos;)
        s.replace(at, 8, "\"../unity_urp/lib/");
      return s;
    };
    dir_.write("stages/combine_luts.comp", relink(read_shader("unity_urp/stages/lut_bake.comp")));
    dir_.write("stages/tonemap.comp", relink(read_shader("unity_urp/stages/color_grading.comp")));
    if (!lib.empty()) {
      std::string text = read_shader(lib);
      const size_t at = text.find(from);
      planted_ = at != std::string::npos;
      if (planted_) text.replace(at, from.size(), to);
      dir_.write(lib, text);
    }
    hdrc::gpu::VulkanOptions o =
        follow_model ? hdrc::gpu::testing::test_options() : hdrc::gpu::VulkanOptions{};
    o.shader_dir = dir_.path();
    engine_ = std::make_unique<hdrc::gpu::VulkanEngine>(o);
    init_ = engine_->init();
  }
  bool planted() const { return planted_; }
  // The baked strip (N² x N), as the engine reads the LUT image back.
  hdrc::Result<Image> bake(const SettingValues& s, int lut_format = -1) {
    if (!init_) return init_.error();
    return engine_->run(urp_case("combine_luts", Image(1, 1), s, lut_format));
  }
  // The graded image.
  hdrc::Result<Image> grade(const SettingValues& s, const Image& input, int lut_format = -1) {
    if (!init_) return init_.error();
    return engine_->run(urp_case("tonemap", input, s, lut_format));
  }

 private:
  hdrc::gpu::testing::ShaderDirCopy dir_;
  std::unique_ptr<hdrc::gpu::VulkanEngine> engine_;
  hdrc::Status init_;
  bool planted_ = false;
};

// The spacing of halves at |v|.
double half_ulp(double v) {
  const double a = std::fabs(v);
  if (a < std::exp2(-14)) return std::exp2(-24);
  return std::exp2(std::floor(std::log2(a)) - 10);
}

// GPU strip vs reference strip, per channel value, in units of the storage format at the texel's
// largest |channel| (half ulps for RGBA16F, 1/255 for RGBA8, float32 ulps for RGBA32F): float32
// noise scales with the largest channel, so a small channel beside large ones (the HSV ε leaves
// ~1e-4·v in a channel that should be 0) may differ by many of its own ulps.
double unit_of(int lut_format, double largest) {
  if (lut_format == 3) return 1.0 / 255.0;
  if (lut_format == 2) return std::exp2(std::floor(std::log2(std::max(largest, 1e-30))) - 23);
  return half_ulp(largest);
}

struct StripDiff {
  int values = 0, exact = 0, one_unit = 0, more = 0;
  double max_units = 0;
  std::string worst;
};
StripDiff compare_strips(const Image& gpu, const Image& ref, int lut_format) {
  StripDiff d;
  for (int y = 0; y < ref.height; ++y)
    for (int x = 0; x < ref.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double* t = ref.px(x, y);
        const double r = t[c], g = gpu.px(x, y)[c];
        const double largest = std::max({std::fabs(t[0]), std::fabs(t[1]), std::fabs(t[2])});
        const double u = g == r ? 0.0 : std::fabs(g - r) / unit_of(lut_format, largest);
        ++d.values;
        if (u == 0)
          ++d.exact;
        else if (u <= 1.0 + 1e-9)
          ++d.one_unit;
        else
          ++d.more;
        if (!(u <= d.max_units)) {
          d.max_units = std::isnan(u) ? INFINITY : u;
          char buf[200];
          std::snprintf(buf, sizeof buf, "texel (%d, %d) ch %d ref %.9g gpu %.9g", x, y, c, r, g);
          d.worst = buf;
        }
      }
  return d;
}

struct BakeCase {
  const char* grading;
  const char* tonemapping;
  int size;
  bool busy;
  int lut_format;  // -1: as derived (RGBA16F for HDR grading)
};

StripDiff bake_and_compare(UrpStageEngine& engine, const BakeCase& c) {
  const SettingValues s = settings(c.grading, c.tonemapping, c.size, c.busy);
  const ParamBlock p = urp_params(s, c.lut_format);
  auto got = engine.bake(s, c.lut_format);
  EXPECT_TRUE(got.ok()) << got.error().to_string();
  if (!got.ok()) return {};
  const Image want = urp::bake_lut_strip(p);
  EXPECT_EQ(got->width, want.width);
  EXPECT_EQ(got->height, want.height);
  const StripDiff d = compare_strips(*got, want, p.lut_format);
  std::printf(
      "[ urp ] bake %-16s %-7s H %2d %-4s fmt %d: %6d values, %6d exact, %5d off by 1 "
      "unit, %d more (max %.3g units; %s)\n",
      c.grading, c.tonemapping, c.size, c.busy ? "busy" : "dflt", p.lut_format, d.values, d.exact,
      d.one_unit, d.more, d.max_units, d.worst.c_str());
  return d;
}

// lut_bake.comp's strip against bake_lut_strip. RGBA16F: float32 and double agree on the stored
// half except where the exact value lies within the float32 evaluation's error of a rounding
// boundary, which moves it by one unit (of the texel's largest channel; a channel far below it
// flips its own, finer rounding more often). Measured on lavapipe (whose exp2/log2 are
// approximations, ~2.7e-6 relative): up to 9.9 % of the values off by one unit at the default
// settings, none by more. With every control active the grade is ill-conditioned in places (e.g.
// a saturation of 1.25 leaving 0.84 as the difference of two values near 43, and the YRGB curve
// cap making a channel proportional to 1/(largest + 1)): one value in 786432 moved 2.5 units at
// H = 64 (ACES). RGBA32F (the LDR grade without its 8-bit storage): the float32 values themselves,
// in float32 ulps of the texel's largest channel: measured 19-49 (LDR), 935 (HDR, busy: the
// contrast and exponential decode amplify lavapipe's exp2 error; 5.6e-5 relative).
TEST(UnityUrpShader, BakeStageMatchesTheReference) {
  UrpStageEngine engine;
  const BakeCase fp16[] = {
      {"HighDynamicRange", "None", 32, false, -1}, {"HighDynamicRange", "Neutral", 33, false, -1},
      {"HighDynamicRange", "ACES", 32, false, -1}, {"HighDynamicRange", "None", 17, true, -1},
      {"HighDynamicRange", "ACES", 64, true, -1},  {"HighDynamicRange", "Neutral", 16, true, -1}};
  for (const BakeCase& c : fp16) {
    const StripDiff d = bake_and_compare(engine, c);
    if (c.busy) {
      EXPECT_LE(d.more, d.values / 100000) << c.grading << " " << c.tonemapping << ": " << d.worst;
      EXPECT_LE(d.max_units, 4.0) << c.grading << " " << c.tonemapping << ": " << d.worst;
    } else {
      EXPECT_EQ(d.more, 0) << c.grading << " " << c.tonemapping << ": " << d.worst;
    }
    EXPECT_LE(d.one_unit, d.values / 8) << c.grading << " " << c.tonemapping;
  }
  const BakeCase fp32[] = {{"LowDynamicRange", "None", 32, false, 2},
                           {"LowDynamicRange", "ACES", 32, true, 2},
                           {"HighDynamicRange", "None", 32, true, 2}};
  for (const BakeCase& c : fp32) {
    const StripDiff d = bake_and_compare(engine, c);
    const double bound = c.grading[0] == 'L' ? 128.0 : 2048.0;
    EXPECT_LE(d.max_units, bound) << c.grading << " " << c.tonemapping << ": " << d.worst;
  }
}

// The LDR bake in its own storage, RGBA8 UNORM (lut_format 3): within one unit (1/255) where the
// value lies within float32 noise of a rounding boundary.
TEST(UnityUrpShader, BakeStageRgba8MatchesTheReference) {
  UrpStageEngine engine;
  const SettingValues s = settings("LowDynamicRange", "None", 32, false);
  auto probe = engine.bake(s);
  if (!probe.ok() &&
      probe.error().message.find("LUT format 3 is not supported") != std::string::npos)
    GTEST_SKIP() << "the Vulkan engine has no RGBA8 LUT storage (lut_format 3) yet: "
                 << probe.error().message;
  for (const BakeCase& c : {BakeCase{"LowDynamicRange", "None", 32, false, -1},
                            BakeCase{"LowDynamicRange", "Neutral", 33, true, -1},
                            BakeCase{"LowDynamicRange", "ACES", 16, true, -1}}) {
    const StripDiff d = bake_and_compare(engine, c);
    EXPECT_EQ(d.more, 0) << c.grading << " " << c.tonemapping << ": " << d.worst;
    EXPECT_LE(d.one_unit, d.values / 100) << c.grading << " " << c.tonemapping;
  }
}

// Scene colours for the final pass: a grey ramp 2^-10 .. 2^7 (beyond the LogC range at both ends),
// colours, a negative channel, zero.
Image scene_image() {
  std::vector<Vec3> v = grey_ramp(-10, 7, 256);
  for (const Vec3& c : lattice(7, 0.0, 1.0))
    for (double k : {0.05, 0.4, 3.0}) v.push_back({c[0] * k, c[1] * k, c[2] * k});
  v.push_back({-0.1, 0.2, 0.3});
  v.push_back({0, 0, 0});
  Image in(static_cast<int>(v.size()), 1);
  for (size_t i = 0; i < v.size(); ++i) {
    for (int c = 0; c < 3; ++c) in.data[i * 4 + c] = static_cast<float>(v[i][c]);
    in.data[i * 4 + 3] = 0.5;
  }
  return in;
}

// color_grading.comp (after lut_bake.comp) against grade_image, and against the reference's lookup
// of the GPU's own strip, which isolates the lookup (the engine's bilinear filter against exact
// weights). Errors relative to the pixel's largest channel (floor 1e-3).
void grade_and_compare(UrpStageEngine& engine, const BakeCase& c, double bound_reference,
                       double bound_lookup) {
  const Image in = scene_image();
  const SettingValues s = settings(c.grading, c.tonemapping, c.size, c.busy);
  const ParamBlock p = urp_params(s, c.lut_format);
  auto got = engine.grade(s, in, c.lut_format);
  ASSERT_TRUE(got.ok()) << got.error().to_string();
  auto strip = engine.bake(s, c.lut_format);
  ASSERT_TRUE(strip.ok()) << strip.error().to_string();
  const Image want = urp::grade_image(in, p);
  // Elsewhere than on a float32-exact device: the distance outside ApplyColorGrading's device
  // range (unity_urp.h apply_color_grading_device_range: the weight boxes of subTexelPrecisionBits,
  // "Texel Filtering", and kFloat32Noise for the coordinate), over the strip as a conformant
  // device may bake it (bake_lut_strip_device_range) for the reference, over the GPU's own strip
  // for the lookup.
  const bool exact = hdrc::gpu::testing::exact_device();
  const hdrc::DevicePrecision& device = hdrc::gpu::testing::test_device().precision;
  urp::StripRange baked, own_strip{*strip, *strip};
  if (!exact) baked = urp::bake_lut_strip_device_range(p, device);
  ErrorStats vs_reference, vs_lookup;
  for (int x = 0; x < in.width; ++x) {
    const double* i = in.px(x, 0);
    const Vec3 own = urp::apply_color_grading(*strip, p, {i[0], i[1], i[2]});
    const double* w = want.px(x, 0);
    const double scale = std::max({std::fabs(w[0]), std::fabs(w[1]), std::fabs(w[2]), 1e-3});
    hdrc::ref::Range3 r_ref, r_own;
    if (!exact) {
      r_ref = urp::apply_color_grading_device_range(baked, p, {i[0], i[1], i[2]},
                                                    device.sub_texel_bits);
      r_own = urp::apply_color_grading_device_range(own_strip, p, {i[0], i[1], i[2]},
                                                    device.sub_texel_bits);
    }
    for (int ch = 0; ch < 3; ++ch) {
      const double g = got->px(x, 0)[ch];
      if (exact) {
        vs_reference.add(std::fabs(g - w[ch]) / scale);
        vs_lookup.add(std::fabs(g - own[ch]) / scale);
      } else {
        vs_reference.add(hdrc::gpu::testing::outside(r_ref, ch, g) / scale);
        vs_lookup.add(hdrc::gpu::testing::outside(r_own, ch, g) / scale);
      }
    }
    EXPECT_EQ(got->px(x, 0)[3], 0.5);
  }
  std::printf(
      "[ urp ] grading %-16s %-7s %-4s fmt %d: rel |gpu - reference| max %.3g p99.9 %.3g; "
      "rel |gpu - lookup of the gpu strip| max %.3g\n",
      c.grading, c.tonemapping, c.busy ? "busy" : "dflt", p.lut_format, vs_reference.max(),
      vs_reference.percentile(0.999), vs_lookup.max());
  EXPECT_LE(vs_reference.max(), bound_reference) << c.grading << " " << c.tonemapping;
  EXPECT_LE(vs_lookup.max(), bound_lookup) << c.grading << " " << c.tonemapping;
}

TEST(UnityUrpShader, GradingStageMatchesTheReference) {
  UrpStageEngine engine("", "", "", /*follow_model=*/true);
  // RGBA16F strips: the GPU's strip differs from the reference's by a half ulp in some texels
  // (BakeStageMatchesTheReference), so the image does by up to a half ulp relative (9.8e-4);
  // the lookup alone (lavapipe's bilinear filter) is far tighter.
  for (const BakeCase& c : {BakeCase{"HighDynamicRange", "None", 32, false, -1},
                            BakeCase{"HighDynamicRange", "ACES", 32, true, -1},
                            BakeCase{"HighDynamicRange", "Neutral", 33, false, -1}})
    grade_and_compare(engine, c, 1e-3, 1e-4);
  // LDR grading with RGBA32F storage (the engine has no RGBA8 yet: BakeStageRgba8...).
  for (const BakeCase& c : {BakeCase{"LowDynamicRange", "None", 32, false, 2},
                            BakeCase{"LowDynamicRange", "ACES", 32, true, 2},
                            BakeCase{"LowDynamicRange", "Neutral", 32, false, 2}})
    grade_and_compare(engine, c, 1e-4, 1e-4);
}

// --- Planted defects ----------------------------------------------------------------------------

// Each defect is one line of GLSL changed in a copy of the shaders; the bake's strip is compared
// with the reference's as in BakeStageMatchesTheReference, where the unplanted shaders never
// differ by more than one unit.
TEST(UnityUrpShader, PlantedDefectsAreCaught) {
  const struct {
    const char* name;
    const char* lib;
    const char* from;
    const char* to;
    BakeCase bake;
  } defects[] = {
      {"hue wrap -> clamp",
       "unity_urp/lib/unity_color.glsl",
       "return value < low ? value + hi : (value > hi ? value - hi : value);",
       "return clamp(value, low, hi);",
       {"HighDynamicRange", "None", 32, true, -1}},
      {"split balance sign",
       "unity_urp/lib/unity_grade.glsl",
       "float balance = P.urp_split_shadows.w;",
       "float balance = -P.urp_split_shadows.w;",
       {"HighDynamicRange", "None", 32, true, -1}},
  };
  for (const auto& d : defects) {
    UrpStageEngine engine(d.lib, d.from, d.to);
    ASSERT_TRUE(engine.planted()) << d.name << ": the planted line is not in " << d.lib;
    std::printf("[ urp ] planted %s:\n", d.name);
    const StripDiff diff = bake_and_compare(engine, d.bake);
    EXPECT_GT(diff.more, diff.values / 100) << d.name;
  }
}

// LogC's c off by 1e-6 (0.244161 → 0.244162) changes LogC^-1 by 4e-6 .. 2.4e-5 relative over most
// of the lattice: at most 0.05 of a half ulp, which in RGBA16F only adds values off by one unit.
// Near black, where LogC^-1 = (10^x − b)/a cancels, the change is ~0.3 %: a few dozen texels move
// by two units there (measured: 27 of 98304 at H = 32), so the RGBA16F strip catches the defect
// only through those. With RGBA32F storage the values themselves are compared: the defect's
// largest deviation stands clear of the unplanted shaders' (both measured here, on this device:
// 948 vs 30100 float32 ulps of the texel's largest channel on lavapipe).
TEST(UnityUrpShader, PlantedLogCConstantShowsInFloatStorage) {
  const BakeCase c = {"HighDynamicRange", "None", 32, false, 2};
  UrpStageEngine clean;
  UrpStageEngine planted("unity_urp/lib/unity_color.glsl", "URP_LOGC_C = 0.244161;",
                         "URP_LOGC_C = 0.244162;");
  ASSERT_TRUE(planted.planted());
  std::printf("[ urp ] unplanted:\n");
  const StripDiff base = bake_and_compare(clean, c);
  std::printf("[ urp ] planted LogC c + 1e-6:\n");
  const StripDiff bad = bake_and_compare(planted, c);
  BakeCase half = c;
  half.lut_format = -1;
  std::printf("[ urp ] the same in RGBA16F, unplanted then planted:\n");
  const StripDiff base16 = bake_and_compare(clean, half);
  const StripDiff bad16 = bake_and_compare(planted, half);
  EXPECT_GT(bad.max_units, 8.0 * base.max_units);
  EXPECT_EQ(base16.more, 0);
  EXPECT_GT(bad16.more, 0);
  EXPECT_GT(bad16.one_unit, base16.one_unit);
}

}  // namespace

namespace {

// Hostile scene values through the final pass (lut_bake.comp then color_grading.comp): NaN, ±Inf,
// negatives, float32's largest values. HDR grading: saturate(LogC(x)) maps NaN (maxNum → 0 → −Inf)
// and −Inf to the LUT's first texel and +Inf to its last; LDR grading: ApplyTonemap's saturate
// maps NaN to 0. Every output must be finite and match the reference's lookup of the GPU's strip,
// with one known exception: LDR grading with ACES applies the fitted tone map to the scene value
// itself, and float32 overflows there above ~1.8e19 (x·(x + a) in the fitted rational, the
// squares in rgb_2_yc), as Unity's own shader does (desktop fp32): ∞/∞ = NaN, saturated to 0 —
// black where the double reference gives white. Those inputs are counted, not compared.
TEST(UnityUrpShader, NonFiniteInputsFollowTheReference) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const double big = std::numeric_limits<float>::max();
  const double specials[] = {nan, inf, -inf, -1.0, 0.0, 0.18, 1e30, big};
  std::vector<Vec3> v;
  for (double a : specials)
    for (double b : specials) v.push_back({a, b, 0.5});
  Image in(static_cast<int>(v.size()), 1);
  for (size_t i = 0; i < v.size(); ++i) {
    for (int c = 0; c < 3; ++c) in.data[i * 4 + c] = v[i][c];
    in.data[i * 4 + 3] = 1.0;
  }
  UrpStageEngine engine;
  for (const BakeCase& c : {BakeCase{"HighDynamicRange", "None", 32, false, -1},
                            BakeCase{"HighDynamicRange", "ACES", 32, false, -1},
                            BakeCase{"LowDynamicRange", "None", 32, false, 2},
                            BakeCase{"LowDynamicRange", "Neutral", 32, false, 2},
                            BakeCase{"LowDynamicRange", "ACES", 32, false, 2}}) {
    const SettingValues s = settings(c.grading, c.tonemapping, c.size, c.busy);
    const ParamBlock p = urp_params(s, c.lut_format);
    auto got = engine.grade(s, in, c.lut_format);
    ASSERT_TRUE(got.ok()) << got.error().to_string();
    auto strip = engine.bake(s, c.lut_format);
    ASSERT_TRUE(strip.ok()) << strip.error().to_string();
    int mismatches = 0, overflows = 0;
    const bool aces_ldr = p.urp_grading_mode == 0 && p.urp_tonemap_mode == 2;
    for (int x = 0; x < in.width; ++x) {
      const double largest_finite = std::max(
          {std::isfinite(v[x][0]) ? v[x][0] : 0.0, std::isfinite(v[x][1]) ? v[x][1] : 0.0, 0.5});
      if (aces_ldr && largest_finite > 1.8e19) {
        ++overflows;
        for (int ch = 0; ch < 3; ++ch)
          EXPECT_EQ(got->px(x, 0)[ch], 0.0) << v[x][0] << " " << v[x][1];
        continue;
      }
      const Vec3 want = urp::apply_color_grading(*strip, p, v[x]);
      const double scale =
          std::max({std::fabs(want[0]), std::fabs(want[1]), std::fabs(want[2]), 1e-3});
      // Elsewhere than on a float32-exact device: the distance outside the lookup's device range
      // over the GPU's own strip (the weight boxes of subTexelPrecisionBits, "Texel Filtering").
      hdrc::ref::Range3 range = hdrc::ref::Range3::point(want);
      if (!hdrc::gpu::testing::exact_device())
        range = urp::apply_color_grading_device_range(
            urp::StripRange{*strip, *strip}, p, v[x],
            hdrc::gpu::testing::test_device().precision.sub_texel_bits);
      for (int ch = 0; ch < 3; ++ch) {
        const double g = got->px(x, 0)[ch];
        if (!std::isfinite(want[ch]) ||
            !(hdrc::gpu::testing::outside(range, ch, g) <= 1e-4 * scale)) {
          ++mismatches;
          ADD_FAILURE() << c.grading << " " << c.tonemapping << ": input (" << v[x][0] << ", "
                        << v[x][1] << ", " << v[x][2] << ") ch " << ch << " reference " << want[ch]
                        << " gpu " << g;
        }
      }
    }
    std::printf(
        "[ urp ] hostile inputs %-16s %-7s: %d of %d values differ (%d pixels float32 "
        "overflow, black)\n",
        c.grading, c.tonemapping, mismatches, 3 * in.width, overflows);
  }
}

}  // namespace
