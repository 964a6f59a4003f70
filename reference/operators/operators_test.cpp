// Tests for the classic tone-mapping operators (reference/operators). Expected values come from
// outside the code under test: exact rational arithmetic on the published formulas (each value's
// fraction is written beside it; computed with Python's fractions.Fraction), the papers' own
// properties (Reinhard's white maps to 1, Hable's f(W) normalisation), docs/spec/unity_urp.md §6.4
// for Unity's Neutral, and UE's FilmToneMap presets restated from TonemapCommon.ush's comment.
#include "reference/operators/operators.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "reference/color/ue_matrices.h"
#include "reference/operators/operators_settings.h"
#include "reference/ue/grading/film_tonemap.h"

namespace {

namespace op = hdrc::ref::operators;
namespace g = hdrc::ref::grading;
using hdrc::ParamBlock;
using hdrc::ref::Vec3;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

ParamBlock default_params(op::Operator which) {
  hdrc::SettingValues s = op::operators_settings();
  EXPECT_TRUE(s.set("Operator", {double(which), 0, 0, 0}, 1).ok());
  ParamBlock p;
  op::derive_operators(s, &p);
  return p;
}

double grey(op::Operator which, double x) {
  return op::apply_operator(default_params(which), {x, x, x})[1];
}

// --- Reinhard ---

TEST(Reinhard, PublishedForm) {
  EXPECT_DOUBLE_EQ(op::reinhard(0.18), 9.0 / 59.0);  // 0.18 / 1.18
  EXPECT_DOUBLE_EQ(op::reinhard(1.0), 0.5);
  EXPECT_DOUBLE_EQ(op::reinhard(0.0), 0.0);
  EXPECT_DOUBLE_EQ(op::reinhard(3.0), 0.75);
}

TEST(Reinhard, WhitePointMapsToOne) {
  // Eq. 4 at L = L_white: L_white (1 + 1/L_white) / (1 + L_white) = 1.
  for (double white : {0.5, 1.0, 4.0, 11.2, 1000.0})
    EXPECT_NEAR(op::reinhard_white(white, white), 1.0, 1e-15) << "white " << white;
  // 1 · (1 + 1/125.44) / 2 = 0.50398596938775510 (L_white = 11.2).
  EXPECT_NEAR(op::reinhard_white(1.0, 11.2), 0.50398596938775510, 1e-15);
  // 0.18 (1 + 0.18/125.44) / 1.18 = 0.15276126340366655.
  EXPECT_NEAR(op::reinhard_white(0.18, 11.2), 0.15276126340366655, 1e-15);
  // L_white → ∞ is eq. 3.
  EXPECT_NEAR(op::reinhard_white(0.18, 1e12), op::reinhard(0.18), 1e-15);
}

TEST(Reinhard, ExposureIsKeyOverAdaptedLuminance) {
  EXPECT_DOUBLE_EQ(op::reinhard_exposure(0.18, 0.36), 0.5);  // eq. 2: a / L̄w
  EXPECT_DOUBLE_EQ(op::reinhard_exposure(op::kReinhardDefaultKey, 0.18), 1.0);
  ParamBlock p = default_params(op::Operator::kReinhard);
  p.op_exposure = 2.0;
  EXPECT_DOUBLE_EQ(op::apply_operator(p, {0.5, 0.5, 0.5})[0], 0.5);  // reinhard(1)
}

// --- Hable ---

TEST(Hable, WhiteNormalisationGivesOneAtWOverBias) {
  const op::HableParams h;  // GDC 2010 slides 142-143 constants, W 11.2, bias 2
  EXPECT_NEAR(op::hable(h.w / h.exposure_bias, h), 1.0, 1e-15);
  EXPECT_NEAR(op::rational_curve(h.w, h.curve), 504392.0 / 581565.0, 1e-15);  // f(11.2)
  // f(0.36) / f(11.2) = 421169373 / 2064980848.
  EXPECT_NEAR(op::hable(0.18, h), 421169373.0 / 2064980848.0, 1e-15);
  // f(0) = DE/DF − E/F = 0 exactly in rationals; in double a few ulp of E/F at most.
  EXPECT_NEAR(op::hable(0.0, h), 0.0, 1e-15);
  // The blog post's constants (A .15, B .50, C .10, D .20, E .02, F .30) at 0.18:
  // 0.12833844885562762.
  op::HableParams blog;
  blog.curve = {0.15, 0.50, 0.10, 0.20, 0.02, 0.30};
  EXPECT_NEAR(op::hable(0.18, blog), 0.12833844885562762, 1e-15);
}

// --- Narkowicz ---

TEST(AcesNarkowicz, PublishedValues) {
  // 0.18 (2.51·0.18 + 0.03) / (0.18 (2.43·0.18 + 0.59) + 0.14) = 21681/81233.
  EXPECT_NEAR(op::aces_narkowicz(0.18), 21681.0 / 81233.0, 1e-15);
  EXPECT_NEAR(op::aces_narkowicz(1.0), 127.0 / 158.0, 1e-15);  // 2.54 / 3.16
  // The engines' 0.6 pre-scale: the fit at 0.108 = 15633/111569.
  EXPECT_NEAR(op::aces_narkowicz(0.18, 0.6), 15633.0 / 111569.0, 1e-15);
  // The ratio reaches 1 where 0.08 x² − 0.56 x − 0.14 = 0: x = (0.56 + √0.3584) / 0.16 = 7.2417;
  // saturate holds it at 1 above (the ratio tends to 2.51/2.43 > 1).
  EXPECT_LT(op::aces_narkowicz(7.24), 1.0);
  EXPECT_EQ(op::aces_narkowicz(7.25), 1.0);
  EXPECT_EQ(op::aces_narkowicz(1e6), 1.0);
}

// --- Unity Neutral ---

TEST(UnityNeutral, SpecHandValues) {
  // docs/spec/unity_urp.md §6.4 (9 decimals), ws = 1/N(5.3) = 1.313386135.
  const struct {
    double x, out;
  } table[] = {{0, 0},
               {0.01, 0.010643104},
               {0.18, 0.181668635},
               {0.5, 0.416090502},
               {1, 0.631119326},
               {2, 0.838843511},
               {5.3, 1.046455202},
               {10, 1.124189083},
               {58.8, 1.207349892}};
  for (const auto& t : table) EXPECT_NEAR(op::unity_neutral(t.x), t.out, 5e-10) << "x " << t.x;
  EXPECT_NEAR(1.0 / op::rational_curve(op::kUnityNeutralWhiteLevel, op::kUnityNeutralCurve),
              1.313386135, 5e-10);
}

// --- UE FilmToneMap ---

TEST(UeFilmic, PresetsAreTonemapCommonsComment) {
  struct Want {
    op::FilmPreset preset;
    const char* name;
    double slope, toe, shoulder, black, white;
  };
  // TonemapCommon.ush (UE 5.5), the comment above FilmToneMap; Default: Scene.cpp.
  const Want want[] = {{op::FilmPreset::kDefault, "Default", 0.88, 0.55, 0.26, 0, 0.04},
                       {op::FilmPreset::kLegacy, "Legacy", 0.98, 0.3, 0.22, 0, 0.025},
                       {op::FilmPreset::kAces, "ACES", 0.91, 0.53, 0.23, 0, 0.035},
                       {op::FilmPreset::kUncharted, "Uncharted", 0.63, 0.55, 0.47, 0, 0.01},
                       {op::FilmPreset::kHp, "HP", 0.65, 0.63, 0.45, 0, 0}};
  for (const Want& w : want) {
    const g::FilmParams f = op::film_preset(w.preset);
    EXPECT_STREQ(op::film_preset_name(int(w.preset)), w.name);
    EXPECT_EQ(f.slope, w.slope) << w.name;
    EXPECT_EQ(f.toe, w.toe) << w.name;
    EXPECT_EQ(f.shoulder, w.shoulder) << w.name;
    EXPECT_EQ(f.black_clip, w.black) << w.name;
    EXPECT_EQ(f.white_clip, w.white) << w.name;
  }
  // The reused FilmToneMap's own defaults are the Default preset.
  const g::FilmParams d;
  EXPECT_EQ(d.slope, 0.88);
  EXPECT_EQ(d.white_clip, 0.04);
}

TEST(UeFilmic, GreyThroughEveryPreset) {
  // For a grey the AP0 saturation is ~0, so the glow (sigmoid_shaper(−2) = 0) and the red modifier
  // vanish and both desaturations leave it alone: the result is film_curve per channel, derived by
  // hand below (Python, from the formulas of film_tonemap.h):
  //  * 0.18: ToeMatch is solved so that the toe gives 0.18 at log10(0.18); log10(0.18) = −0.745 is
  //    below every preset's ToeMatch (Default −0.390, Legacy −0.061, ACES −0.373, Uncharted
  //    −0.250, HP −0.422) and the smoothstep weight there is 0 for all five, so out = 0.18.
  //  * 1.0: Default 0.72335945663, Legacy 0.69137277255, ACES 0.72637471026, Uncharted
  //    0.60438028457, HP 0.63642552272.
  // The Rec.709 ↔ AP1 float matrices keep a grey grey to ~1e-7 (their rows sum to 1 in float).
  const struct {
    op::FilmPreset preset;
    double at_one;
  } presets[] = {{op::FilmPreset::kDefault, 0.72335945663},
                 {op::FilmPreset::kLegacy, 0.69137277255},
                 {op::FilmPreset::kAces, 0.72637471026},
                 {op::FilmPreset::kUncharted, 0.60438028457},
                 {op::FilmPreset::kHp, 0.63642552272}};
  const op::UeFilmicSpace space = op::ue_filmic_space();
  for (const auto& t : presets) {
    const g::FilmParams f = op::film_preset(t.preset);
    const Vec3 mid = op::ue_filmic({0.18, 0.18, 0.18}, f, space);
    const Vec3 one = op::ue_filmic({1, 1, 1}, f, space);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(mid[c], 0.18, 1e-6) << op::film_preset_name(int(t.preset));
      EXPECT_NEAR(one[c], t.at_one, 1e-6) << op::film_preset_name(int(t.preset));
    }
  }
}

TEST(UeFilmic, IsGradingsFilmToneMapBetweenUesWorkingColorSpaceMatrices) {
  const hdrc::ref::WorkingColorSpace wcs =
      hdrc::ref::make_working_color_space(hdrc::ref::WorkingColorSpacePreset::kSrgb);
  const op::UeFilmicSpace space = op::ue_filmic_space();
  EXPECT_EQ(space.rec709_to_ap1.m, wcs.to_ap1.m);
  EXPECT_EQ(space.ap1_to_rec709.m, wcs.from_ap1.m);
  const g::FilmParams f = op::film_preset(op::FilmPreset::kUncharted);
  const Vec3 rgb{0.9, 0.2, 0.05};
  const Vec3 ap1 = g::film_tone_map(wcs.to_ap1 * rgb, f);
  const Vec3 want = wcs.from_ap1 * ap1;
  const Vec3 got = op::ue_filmic(rgb, f, space);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(got[c], std::fmax(0.0, want[c])) << c;
  // A dark saturated red leaves AP1 → Rec.709 with a negative green (−2.8e-4), which the final
  // max clears.
  const Vec3 red = op::ue_filmic({0.01, 0, 0}, f, space);
  const Vec3 red_raw = wcs.from_ap1 * g::film_tone_map(wcs.to_ap1 * Vec3{0.01, 0, 0}, f);
  bool some_negative = false;
  for (int c = 0; c < 3; ++c) {
    EXPECT_GE(red[c], 0.0);
    some_negative |= red_raw[c] < 0.0;
  }
  EXPECT_TRUE(some_negative) << "the test no longer reaches the max(0, ·)";
}

// --- The dispatcher ---

TEST(ApplyOperator, DispatchesEveryOperatorWithItsFields) {
  const Vec3 rgb{0.05, 0.7, 3.0};
  const double exposure = 1.5;
  for (int id = 0; id < op::kOperatorCount; ++id) {
    ParamBlock p = default_params(static_cast<op::Operator>(id));
    p.op_exposure = exposure;
    const Vec3 got = op::apply_operator(p, rgb);
    const Vec3 x{exposure * rgb[0], exposure * rgb[1], exposure * rgb[2]};
    Vec3 want{};
    for (int c = 0; c < 3; ++c) {
      switch (static_cast<op::Operator>(id)) {
        case op::Operator::kReinhard:
          want[c] = op::reinhard(x[c]);
          break;
        case op::Operator::kReinhardWhite:
          want[c] = op::reinhard_white(x[c], 11.2);
          break;
        case op::Operator::kHable:
          want[c] = op::hable(x[c], op::HableParams{});
          break;
        case op::Operator::kAcesNarkowicz:
          want[c] = op::aces_narkowicz(x[c]);
          break;
        case op::Operator::kUnityNeutral:
          want[c] = op::unity_neutral(x[c]);
          break;
        case op::Operator::kUeFilmic:
          want = op::ue_filmic(x, op::film_preset(op::FilmPreset::kDefault), op::ue_filmic_space());
          break;
      }
    }
    for (int c = 0; c < 3; ++c) EXPECT_EQ(got[c], want[c]) << op::operator_name(id) << " " << c;
  }
  ParamBlock p = default_params(op::Operator::kHable);
  p.op_hable_w = 4.0;  // the fields, not the defaults, drive the operator
  EXPECT_NEAR(op::apply_operator(p, {2, 2, 2})[0], 1.0, 1e-15);  // f(2·2)/f(4)
  p.op_operator = 6;
  EXPECT_TRUE(std::isnan(op::apply_operator(p, {0.18, 0.18, 0.18})[0]));
  p.op_operator = -1;
  EXPECT_TRUE(std::isnan(op::apply_operator(p, {0.18, 0.18, 0.18})[2]));
}

TEST(ApplyOperator, MonotonicOnALogRamp) {
  for (int id = 0; id < op::kOperatorCount; ++id) {
    const ParamBlock p = default_params(static_cast<op::Operator>(id));
    double last = -kInf;
    for (int k = 0; k <= 800; ++k) {  // 1e-4 .. 1e4, 100 steps a decade
      const double x = std::pow(10.0, -4.0 + k / 100.0);
      const double y = op::apply_operator(p, {x, x, x})[1];
      ASSERT_TRUE(std::isfinite(y)) << op::operator_name(id) << " x " << x;
      // Narkowicz saturates at 1 from x = 7.24: non-decreasing; every other curve increases.
      if (id == int(op::Operator::kAcesNarkowicz))
        ASSERT_GE(y, last) << op::operator_name(id) << " x " << x;
      else
        ASSERT_GT(y, last) << op::operator_name(id) << " x " << x;
      last = y;
    }
  }
}

// --- Non-finite and negative inputs: the published formula in IEEE double with HLSL semantics ---

struct Hostile {
  op::Operator which;
  double x;
  double want;  // NaN: the result must be NaN
};

TEST(ApplyOperator, NonFiniteAndNegativeInputs) {
  const double h_w = 504392.0 / 581565.0;  // Hable f(11.2)
  const Hostile table[] = {
      // x / (1 + x): ∞/∞ = NaN; the pole at −1 is −1/+0 = −Inf; −0.5 → −1.
      {op::Operator::kReinhard, kNaN, kNaN},
      {op::Operator::kReinhard, kInf, kNaN},
      {op::Operator::kReinhard, -kInf, kNaN},
      {op::Operator::kReinhard, -1.0, -kInf},
      {op::Operator::kReinhard, -0.5, -1.0},
      {op::Operator::kReinhard, -2.0, 2.0},
      // x (1 + x/125.44) / (1 + x): the same pole; −0.5 → −(1 − 0.5/125.44) = −0.99601403061.
      {op::Operator::kReinhardWhite, kNaN, kNaN},
      {op::Operator::kReinhardWhite, kInf, kNaN},
      {op::Operator::kReinhardWhite, -kInf, kNaN},
      {op::Operator::kReinhardWhite, -1.0, -kInf},
      {op::Operator::kReinhardWhite, -0.5, -0.99601403061224490},
      // f(∞) = ∞/∞; at −0.5, f(−1) = 0.192 / −0.02 − 1/30 (between the denominator's roots,
      // −0.122 and −0.560 in input units) → (−9.6 − 1/30) / f(11.2) = −11204819/1008784.
      {op::Operator::kHable, kNaN, kNaN},
      {op::Operator::kHable, kInf, kNaN},
      {op::Operator::kHable, -kInf, kNaN},
      {op::Operator::kHable, -0.5, (-9.6 - 1.0 / 30.0) / h_w},
      // saturate(NaN) = 0, and ±∞ give ∞/∞; −1 → 2.48/1.98 > 1 → 1; −0.005 → a negative ratio → 0.
      {op::Operator::kAcesNarkowicz, kNaN, 0.0},
      {op::Operator::kAcesNarkowicz, kInf, 0.0},
      {op::Operator::kAcesNarkowicz, -kInf, 0.0},
      {op::Operator::kAcesNarkowicz, -1.0, 1.0},
      {op::Operator::kAcesNarkowicz, -0.005, 0.0},
      // max(x, 0) first (maxNum: NaN → 0); N(∞) = ∞/∞.
      {op::Operator::kUnityNeutral, kNaN, 0.0},
      {op::Operator::kUnityNeutral, kInf, kNaN},
      {op::Operator::kUnityNeutral, -kInf, 0.0},
      {op::Operator::kUnityNeutral, -1.0, 0.0},
      // A NaN channel makes every AP0 channel NaN; FilmToneMap's max(0, ·) returns 0 for it (and
      // film_curve(0) = NaN for a clipped channel is cleaned the same way). ∞ through the
      // mixed-sign AP1 → AP0 rows is ∞ − ∞ = NaN: 0 as well. A negative grey clips to 0.
      {op::Operator::kUeFilmic, kNaN, 0.0},
      {op::Operator::kUeFilmic, kInf, 0.0},
      {op::Operator::kUeFilmic, -kInf, 0.0},
      {op::Operator::kUeFilmic, -1.0, 0.0},
  };
  for (const Hostile& t : table) {
    const double got = grey(t.which, t.x);
    const std::string what =
        std::string(op::operator_name(int(t.which))) + " at " + std::to_string(t.x);
    if (std::isnan(t.want)) {
      EXPECT_TRUE(std::isnan(got)) << what << " gave " << got;
    } else if (std::isinf(t.want)) {
      EXPECT_EQ(got, t.want) << what;
    } else {
      EXPECT_NEAR(got, t.want, 1e-14 * std::fmax(1.0, std::fabs(t.want))) << what;
    }
  }
}

// --- Settings and their derivation ---

TEST(OperatorsSettings, TableChoicesAndDefaults) {
  const auto& table = op::operators_setting_table();
  const std::vector<std::string> names = {"Operator",
                                          "Key",
                                          "AdaptedLuminance",
                                          "WhitePoint",
                                          "HableA",
                                          "HableB",
                                          "HableC",
                                          "HableD",
                                          "HableE",
                                          "HableF",
                                          "HableW",
                                          "ExposureBias",
                                          "NarkowiczPreScale",
                                          "FilmPreset"};
  ASSERT_EQ(table.size(), names.size());
  for (size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(table[i].name, names[i]);
    EXPECT_EQ(table[i].components, 1);
    EXPECT_GE(table[i].default_value[0], table[i].min_value) << names[i];
    EXPECT_LE(table[i].default_value[0], table[i].max_value) << names[i];
    EXPECT_FALSE(table[i].feeds.empty()) << names[i];
  }
  const auto* ops = op::operators_setting_choices("Operator");
  ASSERT_NE(ops, nullptr);
  const char* op_names[] = {"Reinhard",      "ReinhardWhite", "Hable",
                            "AcesNarkowicz", "UnityNeutral",  "UeFilmic"};
  ASSERT_EQ(ops->size(), 6u);
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ((*ops)[i].name, op_names[i]);
    EXPECT_EQ((*ops)[i].value, i);
  }
  const auto* presets = op::operators_setting_choices("FilmPreset");
  ASSERT_NE(presets, nullptr);
  const char* preset_names[] = {"Default", "Legacy", "ACES", "Uncharted", "HP"};
  ASSERT_EQ(presets->size(), 5u);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ((*presets)[i].name, preset_names[i]);
    EXPECT_EQ((*presets)[i].value, i);
  }
  EXPECT_EQ(op::operators_setting_choices("Key"), nullptr);

  // Defaults derive the published constants.
  ParamBlock p;
  op::derive_operators(op::operators_settings(), &p);
  EXPECT_EQ(p.op_operator, 0);
  EXPECT_EQ(p.op_exposure, 1.0);  // 0.18 / 0.18
  EXPECT_EQ(p.op_white_point, 11.2);
  EXPECT_EQ(p.op_hable_a, 0.22);
  EXPECT_EQ(p.op_hable_b, 0.30);
  EXPECT_EQ(p.op_hable_c, 0.10);
  EXPECT_EQ(p.op_hable_d, 0.20);
  EXPECT_EQ(p.op_hable_e, 0.01);
  EXPECT_EQ(p.op_hable_f, 0.30);
  EXPECT_EQ(p.op_hable_w, 11.2);
  EXPECT_EQ(p.op_hable_exposure_bias, 2.0);
  EXPECT_EQ(p.op_narkowicz_pre_scale, 1.0);
  EXPECT_EQ(p.film_slope, 0.88);
  EXPECT_EQ(p.film_toe, 0.55);
  EXPECT_EQ(p.film_shoulder, 0.26);
  EXPECT_EQ(p.film_black_clip, 0.0);
  EXPECT_EQ(p.film_white_clip, 0.04);
  const auto wcs = hdrc::ref::make_working_color_space(hdrc::ref::WorkingColorSpacePreset::kSrgb);
  EXPECT_EQ(p.op_rec709_to_ap1.m, wcs.to_ap1.m);
  EXPECT_EQ(p.op_ap1_to_rec709.m, wcs.from_ap1.m);
}

TEST(OperatorsSettings, DeriveEveryChoiceAndValue) {
  const char* op_names[] = {"Reinhard",      "ReinhardWhite", "Hable",
                            "AcesNarkowicz", "UnityNeutral",  "UeFilmic"};
  for (int i = 0; i < 6; ++i) {
    hdrc::SettingValues s = op::operators_settings();
    ASSERT_TRUE(s.set_choice("Operator", op_names[i]).ok()) << op_names[i];
    ParamBlock p;
    op::derive_operators(s, &p);
    EXPECT_EQ(p.op_operator, i) << op_names[i];
  }
  const struct {
    const char* name;
    double slope, toe, shoulder, black, white;
  } presets[] = {{"Default", 0.88, 0.55, 0.26, 0, 0.04},
                 {"Legacy", 0.98, 0.3, 0.22, 0, 0.025},
                 {"ACES", 0.91, 0.53, 0.23, 0, 0.035},
                 {"Uncharted", 0.63, 0.55, 0.47, 0, 0.01},
                 {"HP", 0.65, 0.63, 0.45, 0, 0}};
  for (const auto& t : presets) {
    hdrc::SettingValues s = op::operators_settings();
    ASSERT_TRUE(s.set_choice("FilmPreset", t.name).ok()) << t.name;
    ParamBlock p;
    op::derive_operators(s, &p);
    EXPECT_EQ(p.film_slope, t.slope) << t.name;
    EXPECT_EQ(p.film_toe, t.toe) << t.name;
    EXPECT_EQ(p.film_shoulder, t.shoulder) << t.name;
    EXPECT_EQ(p.film_black_clip, t.black) << t.name;
    EXPECT_EQ(p.film_white_clip, t.white) << t.name;
  }
  hdrc::SettingValues s = op::operators_settings();
  const struct {
    const char* name;
    double value;
  } values[] = {{"Key", 0.36},         {"AdaptedLuminance", 0.09},
                {"WhitePoint", 4.0},   {"HableA", 0.15},
                {"HableB", 0.5},       {"HableC", 0.11},
                {"HableD", 0.21},      {"HableE", 0.02},
                {"HableF", 0.31},      {"HableW", 8.0},
                {"ExposureBias", 1.5}, {"NarkowiczPreScale", 0.6}};
  for (const auto& v : values) ASSERT_TRUE(s.set(v.name, {v.value, 0, 0, 0}, 1).ok()) << v.name;
  ParamBlock p;
  op::derive_operators(s, &p);
  EXPECT_EQ(p.op_exposure, 4.0);  // 0.36 / 0.09
  EXPECT_EQ(p.op_white_point, 4.0);
  EXPECT_EQ(p.op_hable_a, 0.15);
  EXPECT_EQ(p.op_hable_b, 0.5);
  EXPECT_EQ(p.op_hable_c, 0.11);
  EXPECT_EQ(p.op_hable_d, 0.21);
  EXPECT_EQ(p.op_hable_e, 0.02);
  EXPECT_EQ(p.op_hable_f, 0.31);
  EXPECT_EQ(p.op_hable_w, 8.0);
  EXPECT_EQ(p.op_hable_exposure_bias, 1.5);
  EXPECT_EQ(p.op_narkowicz_pre_scale, 0.6);
}

TEST(OperatorsSettings, ValidationErrors) {
  hdrc::SettingValues s = op::operators_settings();
  EXPECT_FALSE(s.set("Key", {0, 0, 0, 0}, 1).ok());               // Key / L̄w needs Key > 0
  EXPECT_FALSE(s.set("AdaptedLuminance", {0, 0, 0, 0}, 1).ok());  // a division by zero
  EXPECT_FALSE(s.set("HableF", {0, 0, 0, 0}, 1).ok());            // E / F
  EXPECT_FALSE(s.set("Operator", {2.5, 0, 0, 0}, 1).ok());        // not a named value
  EXPECT_FALSE(s.set("Operator", {6, 0, 0, 0}, 1).ok());
  const auto bad = s.set_choice("Operator", "Hables");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("did you mean Hable?"), std::string::npos)
      << bad.error().message;
  EXPECT_FALSE(s.set_choice("FilmPreset", "Filmic").ok());
  EXPECT_FALSE(s.set("FilmSlope", {0.9, 0, 0, 0}, 1).ok());  // UE's setting, not this table's
}

TEST(OperatorsSettings, ValuesOverAnotherTableDeriveTheDefaults) {
  ParamBlock from_ue, from_ours;
  op::derive_operators(hdrc::SettingValues(), &from_ue);  // UE 5.5's table: none of ours
  op::derive_operators(op::operators_settings(), &from_ours);
  EXPECT_EQ(from_ue.op_exposure, from_ours.op_exposure);
  EXPECT_EQ(from_ue.op_hable_w, from_ours.op_hable_w);
  EXPECT_EQ(from_ue.film_slope, from_ours.film_slope);
  EXPECT_EQ(from_ue.op_narkowicz_pre_scale, 1.0);
}

}  // namespace

// Reinhard at x = 0.5, exposure 1, in the precision table's interval arithmetic: y = 0.5·1 with
// 0.5 ulp(0.5) = 2^-25 either way; 1 + y = 1.5 ± 2^-25, widened by 0.5 ulp(1.5) = 2^-24: ±3·2^-25;
// y/(1 + y) over those ends, to first order 1/3 ∓ 2^-25·(2/3 + 2/3), then 2.5 ulp(1/3) =
// 2.5·2^-25: 1/3 ∓ 2^-25·23/6 (second-order terms ~2^-50).
TEST(OperatorDeviceRange, ReinhardAtOneHalfFromThePrecisionTable) {
  hdrc::ParamBlock p{};
  p.op_operator = 0;
  p.op_exposure = 1.0;
  hdrc::ref::spirv::Interval r;
  ASSERT_TRUE(hdrc::ref::operators::operator_channel_device_range(p, 0.5, &r));
  EXPECT_NEAR(r.lo, 1.0 / 3 - 0x1p-25 * 23 / 6, 1e-13);
  EXPECT_NEAR(r.hi, 1.0 / 3 + 0x1p-25 * 23 / 6, 1e-13);
  // A NaN input gets no range (the tight bounds judge it).
  EXPECT_FALSE(hdrc::ref::operators::operator_channel_device_range(p, std::nan(""), &r));
}
