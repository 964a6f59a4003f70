// The GLSL classic tone-mapping operators (gpu/shaders/operators/lib/operators.glsl, run through
// the stage shader gpu/shaders/operators/stages/curve.comp) against the double-precision reference
// (reference/operators/operators.h), on lavapipe:
//  * every constant the GLSL hard-codes reads back as float(reference constant);
//  * every operator, at its defaults and with other parameters, over a log ramp 1e-4..1e4 (grey and
//    two colours) and hostile values (NaN, ±Inf, poles, negatives, subnormals, float32's largest
//    values): non-finite results exactly where the reference's (rounded to float32) are, finite
//    ones within the measured bounds below;
//  * a planted one-constant defect is caught and located.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "gpu/shader_probe.h"
#include "reference/operators/operators.h"
#include "reference/operators/operators_settings.h"

namespace {

using hdrc::Image;
using hdrc::ParamBlock;
using hdrc::ResolvedCase;
using hdrc::gpu::testing::ErrorStats;
using hdrc::gpu::testing::make_case;
using hdrc::gpu::testing::read_back;
using hdrc::ref::Vec3;
namespace op = hdrc::ref::operators;

constexpr float kFloatMax = std::numeric_limits<float>::max();
constexpr float kFloatMin = std::numeric_limits<float>::min();  // smallest normal
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(OperatorsShader, ConstantsEqualTheReference) {
  struct Expected {
    std::string glsl;
    double reference;
  };
  const std::vector<Expected> e = {
      {"OP_REINHARD", double(op::Operator::kReinhard)},
      {"OP_REINHARD_WHITE", double(op::Operator::kReinhardWhite)},
      {"OP_HABLE", double(op::Operator::kHable)},
      {"OP_ACES_NARKOWICZ", double(op::Operator::kAcesNarkowicz)},
      {"OP_UNITY_NEUTRAL", double(op::Operator::kUnityNeutral)},
      {"OP_UE_FILMIC", double(op::Operator::kUeFilmic)},
      {"OP_NARKOWICZ_A", op::kNarkowicz.a},
      {"OP_NARKOWICZ_B", op::kNarkowicz.b},
      {"OP_NARKOWICZ_C", op::kNarkowicz.c},
      {"OP_NARKOWICZ_D", op::kNarkowicz.d},
      {"OP_NARKOWICZ_E", op::kNarkowicz.e},
      {"OP_UNITY_NEUTRAL_A", op::kUnityNeutralCurve.a},
      {"OP_UNITY_NEUTRAL_B", op::kUnityNeutralCurve.b},
      {"OP_UNITY_NEUTRAL_C", op::kUnityNeutralCurve.c},
      {"OP_UNITY_NEUTRAL_D", op::kUnityNeutralCurve.d},
      {"OP_UNITY_NEUTRAL_E", op::kUnityNeutralCurve.e},
      {"OP_UNITY_NEUTRAL_F", op::kUnityNeutralCurve.f},
      {"OP_UNITY_NEUTRAL_WHITE_LEVEL", op::kUnityNeutralWhiteLevel},
      {"OP_UNITY_NEUTRAL_WHITE_CLIP", op::kUnityNeutralWhiteClip},
      {"OP_RECIP_LIMIT", std::ldexp(1.0, 126)},
  };
  std::vector<std::string> glsl;
  for (const auto& x : e) glsl.push_back(x.glsl);
  auto got = read_back(glsl, {"operators/lib/operators.glsl"});
  ASSERT_TRUE(got.ok()) << got.error().to_string();
  ASSERT_EQ(got->size(), e.size());
  for (size_t k = 0; k < e.size(); ++k)
    EXPECT_EQ((*got)[k], static_cast<float>(e[k].reference)) << e[k].glsl;
}

// The stage as the operators pipeline will declare it (one pass over the pixels).
const hdrc::StageInfo& curve_stage() {
  static const hdrc::StageInfo stage{hdrc::StageId::kOther,
                                     "curve",
                                     {{"operators/stages/curve.comp", hdrc::Dispatch::kPixels}},
                                     "classic tone-mapping operator per pixel",
                                     {},
                                     true,
                                     "operators"};
  return stage;
}

// The input: a log ramp 1e-4..1e4 (200 steps a decade) as grey, (v, 0.5v, 0.1v) and
// (0.05v, v, 0.4v), then hostile pixels, each as grey, (h, 0.18, 1) and (0.5, h, 4). Every value is
// a float32 (the engine uploads float32; the reference reads the same numbers). Hable's poles are
// irrational (no float input is one, and within 1e-7 of one the result's condition number is
// ~1e7), so its negative inputs are -0.5, -1, -2 and -1e10; Reinhard's pole -1 is exact.
Image make_input() {
  std::vector<Vec3> px;
  const int steps = 1600;
  for (int k = 0; k <= steps; ++k) {
    const double v = static_cast<float>(std::pow(10.0, -4.0 + 8.0 * k / steps));
    px.push_back({v, v, v});
    px.push_back({v, static_cast<float>(0.5 * v), static_cast<float>(0.1 * v)});
    px.push_back({static_cast<float>(0.05 * v), v, static_cast<float>(0.4 * v)});
  }
  const double hostile[] = {kNaN, kInf,  -kInf,   -1.0,      -0.5,      -2.0,       -1e-4, -0.0,
                            0.0,  1e-40, 1.4e-45, kFloatMin, kFloatMax, -kFloatMax, 1e38,  1e30,
                            1e20, 1e19,  1e10,    -1e10,     7.2416573, 11.2,       5.6};
  for (double h : hostile) {
    const double v = static_cast<float>(h);
    px.push_back({v, v, v});
    px.push_back({v, 0.18, 1.0});
    px.push_back({0.5, v, 4.0});
  }
  Image img(static_cast<int>(px.size()), 1);
  for (size_t i = 0; i < px.size(); ++i) {
    for (int c = 0; c < 3; ++c) img.data[i * 4 + c] = px[i][c];
    img.data[i * 4 + 3] = 1.0;
  }
  return img;
}

struct Variant {
  std::string name;
  op::Operator which;
  void (*tweak)(hdrc::SettingValues*);  // settings beyond Operator (nullptr: defaults)
  // Bounds, measured on lavapipe (see the report line each run prints, and docs/precision.md):
  double max_rel;  // |gpu − ref| / |ref| over finite results with |ref| >= 1e-6
  double max_abs;  // |gpu − ref| over finite results with |ref| < 1e-6
  // Known limit: pixels with a finite channel whose |input| exceeds this are not compared, only
  // counted and reported (the reason is at the variant).
  double known_limit_above = kInf;
};

struct Measured {
  ErrorStats rel, abs;
  int nonfinite_mismatch = 0, nonfinite_consistent = 0, compared = 0, known_limit = 0;
  size_t worst = 0;
  int worst_channel = 0;
  double worst_in = 0, worst_ref = 0, worst_gpu = 0;
  std::string first_mismatch;
};

enum class Kind { kFinite, kNaN, kPosInf, kNegInf };
Kind kind(double v) {
  if (std::isnan(v)) return Kind::kNaN;
  if (std::isinf(v)) return v > 0 ? Kind::kPosInf : Kind::kNegInf;
  return Kind::kFinite;
}

ResolvedCase operators_case(const Variant& v, const Image& input) {
  ResolvedCase rc = make_case("shaper", 3, input);
  rc.spec.stage = &curve_stage();
  hdrc::SettingValues s = op::operators_settings();
  EXPECT_TRUE(s.set("Operator", {double(v.which), 0, 0, 0}, 1).ok());
  if (v.tweak) v.tweak(&s);
  op::derive_operators(s, &rc.params);
  return rc;
}

Measured measure(const Variant& v, const ResolvedCase& rc, const Image& gpu) {
  Measured m;
  const Image& in = rc.input;
  for (size_t i = 0; i < size_t(in.width) * in.height; ++i) {
    const Vec3 x{in.data[i * 4], in.data[i * 4 + 1], in.data[i * 4 + 2]};
    auto beyond = [&v](double c) { return std::isfinite(c) && std::fabs(c) > v.known_limit_above; };
    if (beyond(x[0]) || beyond(x[1]) || beyond(x[2])) {
      ++m.known_limit;
      continue;
    }
    const Vec3 ref = op::apply_operator(rc.params, x);
    for (int c = 0; c < 3; ++c) {
      // The output image is float32: the reference rounded to float is what the GPU can store
      // (a result beyond float32's range is +-Inf there).
      const double want = static_cast<float>(ref[c]);
      const double got = gpu.data[i * 4 + c];
      if (kind(want) != Kind::kFinite || kind(got) != Kind::kFinite) {
        if (kind(want) == kind(got)) {
          ++m.nonfinite_consistent;
        } else {
          if (m.first_mismatch.empty())
            m.first_mismatch = "pixel " + std::to_string(i) + " channel " + std::to_string(c) +
                               ": input " + std::to_string(x[c]) + ", reference " +
                               std::to_string(want) + ", GPU " + std::to_string(got);
          ++m.nonfinite_mismatch;
        }
        continue;
      }
      ++m.compared;
      const double err = std::fabs(got - ref[c]);
      if (std::fabs(ref[c]) < 1e-6) {
        // Near black the absolute error is the measure. Results below float32's normal range
        // may be flushed to 0 (Vulkan allows it): within one smallest normal counts as 0.
        m.abs.add(std::fabs(ref[c]) < kFloatMin && err <= kFloatMin ? 0.0 : err);
        continue;
      }
      const double rel = err / std::fabs(ref[c]);
      if (m.rel.errors.empty() || rel > m.rel.max()) {
        m.worst = i;
        m.worst_channel = c;
        m.worst_in = x[c];
        m.worst_ref = ref[c];
        m.worst_gpu = got;
      }
      m.rel.add(rel);
    }
  }
  return m;
}

void set(hdrc::SettingValues* s, const char* name, double value) {
  ASSERT_TRUE(s->set(name, {value, 0, 0, 0}, 1).ok()) << name;
}
void preset(hdrc::SettingValues* s, const char* name) {
  ASSERT_TRUE(s->set_choice("FilmPreset", name).ok()) << name;
}

// UeFilmic's known limit: FilmToneMap's rgb_2_yc (the ACES.ush helper in aces_common.glsl, reused
// unchanged) squares AP0 values (sqrt(b (b − g) + g (g − r) + r (r − b))), which overflows float32
// above sqrt(FLT_MAX) = 1.8e19; the GPU then returns 0 where the double reference reaches the
// shoulder (1 + WhiteClip). Measured: inputs up to 1e19 agree, 1e20 and above do not.
constexpr double kFilmFloatLimit = 1.8e19;

const std::vector<Variant>& variants() {
  // Bounds: about 2x the maxima measured on lavapipe (llvmpipe, Mesa 22.3), which each run prints.
  // Hable and UnityNeutral evaluate f(x) = num/den − E/F, which cancels near black in float32
  // (an absolute error of about an ulp of E/F, 1e-9, on a result of 4e-6 at the ramp's darkest
  // channel 5e-6): their relative bound is set by that, not by the curve's shape. UeFilmic's worst
  // channels are small ones next to large ones (e.g. red 4.7e-5 of (0.01, 0.2, 0.08) under HP):
  // differences of large terms of the AP1 -> Rec.709 matrix, carrying the large channels' error.
  static const std::vector<Variant> v = {
      {"Reinhard", op::Operator::kReinhard, nullptr, 2.5e-7, 1e-12},
      {"Reinhard exposure 2.5", op::Operator::kReinhard, [](auto* s) { set(s, "Key", 0.45); }, 3e-7,
       1e-12},
      {"ReinhardWhite", op::Operator::kReinhardWhite, nullptr, 4e-7, 1e-12},
      {"ReinhardWhite Lw 2", op::Operator::kReinhardWhite, [](auto* s) { set(s, "WhitePoint", 2); },
       4e-7, 1e-12},
      {"Hable", op::Operator::kHable, nullptr, 3e-3, 1e-8},
      {"Hable blog constants", op::Operator::kHable,
       [](auto* s) {
         set(s, "HableA", 0.15);
         set(s, "HableB", 0.50);
         set(s, "HableC", 0.10);
         set(s, "HableD", 0.20);
         set(s, "HableE", 0.02);
         set(s, "HableF", 0.30);
       },
       8e-3, 2e-8},
      {"AcesNarkowicz", op::Operator::kAcesNarkowicz, nullptr, 4e-7, 1e-12},
      {"AcesNarkowicz pre-scale 0.6", op::Operator::kAcesNarkowicz,
       [](auto* s) { set(s, "NarkowiczPreScale", 0.6); }, 6e-7, 2e-13},
      {"UnityNeutral", op::Operator::kUnityNeutral, nullptr, 6e-3, 2e-8},
      {"UeFilmic Default", op::Operator::kUeFilmic, nullptr, 8e-5, 1e-10, kFilmFloatLimit},
      {"UeFilmic Legacy", op::Operator::kUeFilmic, [](auto* s) { preset(s, "Legacy"); }, 1.2e-4,
       1e-10, kFilmFloatLimit},
      {"UeFilmic ACES", op::Operator::kUeFilmic, [](auto* s) { preset(s, "ACES"); }, 1e-4, 1e-10,
       kFilmFloatLimit},
      {"UeFilmic Uncharted", op::Operator::kUeFilmic, [](auto* s) { preset(s, "Uncharted"); }, 1e-4,
       1e-10, kFilmFloatLimit},
      {"UeFilmic HP", op::Operator::kUeFilmic, [](auto* s) { preset(s, "HP"); }, 8e-4, 1e-10,
       kFilmFloatLimit},
  };
  return v;
}

TEST(OperatorsShader, CurveStageMatchesReference) {
  hdrc::gpu::VulkanOptions o;
  o.shader_dir = hdrc::gpu::default_shader_dir();
  hdrc::gpu::VulkanEngine engine(o);
  auto init = engine.init();
  ASSERT_TRUE(init.ok()) << init.error().to_string();
  const Image input = make_input();
  for (const Variant& v : variants()) {
    const ResolvedCase rc = operators_case(v, input);
    auto got = engine.run(rc);
    ASSERT_TRUE(got.ok()) << v.name << ": " << got.error().to_string();
    const Measured m = measure(v, rc, *got);
    std::printf(
        "[ operators ] %-28s rel max %.3g (p99.9 %.3g; input %.9g ch %d: ref %.9g gpu %.9g), "
        "abs max %.3g, %d compared, non-finite consistent %d, mismatched %d, known limit %d px\n",
        v.name.c_str(), m.rel.max(), m.rel.percentile(0.999), m.worst_in, m.worst_channel,
        m.worst_ref, m.worst_gpu, m.abs.max(), m.compared, m.nonfinite_consistent,
        m.nonfinite_mismatch, m.known_limit);
    EXPECT_EQ(m.nonfinite_mismatch, 0) << v.name << ": first at " << m.first_mismatch;
    EXPECT_TRUE(m.rel.max() <= v.max_rel)
        << v.name << ": rel " << m.rel.max() << " > " << v.max_rel << " at pixel " << m.worst
        << " channel " << m.worst_channel << " (input " << m.worst_in << ", reference "
        << m.worst_ref << ", GPU " << m.worst_gpu << ")";
    EXPECT_TRUE(m.abs.max() <= v.max_abs) << v.name << ": abs " << m.abs.max();
    // Alpha passes through.
    for (size_t i = 0; i < size_t(input.width); ++i) ASSERT_EQ(got->data[i * 4 + 3], 1.0);
  }
}

// Test the tester: a 4e-6 change of one constant and a dropped NaN/negative guard must fail, and
// the report must name the pixel.
TEST(OperatorsShader, PlantedDefectsAreCaught) {
  const std::string lib = "operators/lib/operators.glsl";
  std::ifstream file(hdrc::gpu::default_shader_dir() + "/" + lib);
  const std::string source((std::istreambuf_iterator<char>(file)),
                           std::istreambuf_iterator<char>());
  const Image input = make_input();
  const struct {
    const char* from;
    const char* to;
    op::Operator which;
    bool numeric;  // caught by the relative bound (else by the non-finite census)
  } defects[] = {
      {"const float OP_NARKOWICZ_C = 2.43;", "const float OP_NARKOWICZ_C = 2.43001;",
       op::Operator::kAcesNarkowicz, true},
      {"  x = max_d3d(x, 0.0);\n  if (isinf(x))", "  if (isinf(x))", op::Operator::kUnityNeutral,
       false},
  };
  for (const auto& d : defects) {
    const size_t at = source.find(d.from);
    ASSERT_NE(at, std::string::npos) << d.from;
    std::string planted = source;
    planted.replace(at, std::string(d.from).size(), d.to);
    hdrc::gpu::testing::ShaderDirCopy dir("ops_planted");
    dir.write(lib, planted);
    hdrc::gpu::VulkanOptions o;
    o.shader_dir = dir.path();
    hdrc::gpu::VulkanEngine engine(o);
    ASSERT_TRUE(engine.init().ok());
    const Variant* v = nullptr;
    for (const Variant& x : variants())
      if (x.which == d.which && !x.tweak) v = &x;
    ASSERT_NE(v, nullptr);
    const ResolvedCase rc = operators_case(*v, input);
    auto got = engine.run(rc);
    ASSERT_TRUE(got.ok()) << got.error().to_string();
    const Measured m = measure(*v, rc, *got);
    if (d.numeric) {
      EXPECT_GT(m.rel.max(), v->max_rel) << d.to;
      EXPECT_TRUE(std::isfinite(m.worst_ref) && std::isfinite(m.worst_gpu));
      std::printf(
          "[ operators ] planted '%s': rel %.3g at pixel %zu ch %d (input %.9g, ref %.9g, "
          "gpu %.9g)\n",
          d.to, m.rel.max(), m.worst, m.worst_channel, m.worst_in, m.worst_ref, m.worst_gpu);
    } else {
      EXPECT_GT(m.nonfinite_mismatch + (m.rel.max() > v->max_rel ? 1 : 0), 0) << d.from;
      EXPECT_FALSE(m.first_mismatch.empty());
      std::printf("[ operators ] planted: dropped max(x, 0): %d non-finite mismatches, first %s\n",
                  m.nonfinite_mismatch, m.first_mismatch.c_str());
    }
  }
}

}  // namespace
