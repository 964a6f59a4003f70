#include "reference/operators/operators_settings.h"

#include "reference/operators/operators.h"

namespace hdrc::ref::operators {

namespace {
constexpr hdrc::Vec4d s1(double v) {
  return {v, 0, 0, 0};
}
}  // namespace

const std::vector<hdrc::SettingInfo>& operators_setting_table() {
  // Defaults are the published values (operators.h cites each); ranges keep every formula's
  // divisions away from zero: Key, AdaptedLuminance and WhitePoint > 0; Hable's A > 0 (the curve's
  // limit A/A), D > 0 and F > 0 (f(0) = DE/DF − E/F).
  static const HableParams kHable{};
  static const std::vector<hdrc::SettingInfo> table = {
      {"Operator", 1, s1(0), 0, kOperatorCount - 1,
       "op_operator: 0 Reinhard, 1 ReinhardWhite, 2 Hable, 3 AcesNarkowicz, 4 UnityNeutral, "
       "5 UeFilmic (a name or its number)"},
      {"Key", 1, s1(kReinhardDefaultKey), 1e-6, 1e6,
       "op_exposure = Key / AdaptedLuminance (Reinhard 2002 eq. 2, the key a); scales every "
       "operator's input"},
      {"AdaptedLuminance", 1, s1(kReinhardDefaultKey), 1e-6, 1e6,
       "op_exposure's divisor: the scene's log-average luminance (Reinhard eq. 1), measured "
       "outside; the default equals Key's, so op_exposure = 1"},
      {"WhitePoint", 1, s1(kHable.w), 1e-3, 1e6,
       "op_white_point: ReinhardWhite's L_white, mapped to 1 (default: Hable's W, so both "
       "white-point operators reach 1 at the same input)"},
      {"HableA", 1, s1(kHable.curve.a), 1e-6, 10, "op_hable_a: shoulder strength"},
      {"HableB", 1, s1(kHable.curve.b), 0, 10, "op_hable_b: linear strength"},
      {"HableC", 1, s1(kHable.curve.c), 0, 10, "op_hable_c: linear angle"},
      {"HableD", 1, s1(kHable.curve.d), 1e-6, 10, "op_hable_d: toe strength"},
      {"HableE", 1, s1(kHable.curve.e), 0, 10, "op_hable_e: toe numerator"},
      {"HableF", 1, s1(kHable.curve.f), 1e-6, 10, "op_hable_f: toe denominator"},
      {"HableW", 1, s1(kHable.w), 1e-3, 1e6, "op_hable_w: linear white, out = f(bias x) / f(W)"},
      {"ExposureBias", 1, s1(kHable.exposure_bias), 1e-6, 1e6,
       "op_hable_exposure_bias: Hable's input multiplier"},
      {"NarkowiczPreScale", 1, s1(1.0), 1e-6, 1e6,
       "op_narkowicz_pre_scale: multiplies the ACES fit's input (1: the published form; many "
       "engines use 0.6)"},
      {"FilmPreset", 1, s1(0), 0, kFilmPresetCount - 1,
       "film_slope/toe/shoulder/black_clip/white_clip for UeFilmic: 0 Default, 1 Legacy, 2 ACES, "
       "3 Uncharted, 4 HP (a name or its number)"},
  };
  return table;
}

const std::vector<hdrc::SettingChoice>* operators_setting_choices(std::string_view setting) {
  static const std::vector<hdrc::SettingChoice> operators = [] {
    std::vector<hdrc::SettingChoice> c;
    for (int i = 0; i < kOperatorCount; ++i) c.push_back({operator_name(i), double(i)});
    return c;
  }();
  static const std::vector<hdrc::SettingChoice> presets = [] {
    std::vector<hdrc::SettingChoice> c;
    for (int i = 0; i < kFilmPresetCount; ++i) c.push_back({film_preset_name(i), double(i)});
    return c;
  }();
  if (setting == "Operator") return &operators;
  if (setting == "FilmPreset") return &presets;
  return nullptr;
}

hdrc::SettingValues operators_settings() {
  return hdrc::SettingValues(&operators_setting_table(), &operators_setting_choices);
}

void derive_operators(const hdrc::SettingValues& s, hdrc::ParamBlock* p) {
  auto get = [&s](std::string_view name) {
    if (hdrc::find_setting(s.table(), name)) return s.get(name);
    return hdrc::find_setting(operators_setting_table(), name)->default_value[0];
  };
  p->op_operator = static_cast<int>(get("Operator"));
  p->op_exposure = reinhard_exposure(get("Key"), get("AdaptedLuminance"));
  p->op_white_point = get("WhitePoint");
  p->op_hable_a = get("HableA");
  p->op_hable_b = get("HableB");
  p->op_hable_c = get("HableC");
  p->op_hable_d = get("HableD");
  p->op_hable_e = get("HableE");
  p->op_hable_f = get("HableF");
  p->op_hable_w = get("HableW");
  p->op_hable_exposure_bias = get("ExposureBias");
  p->op_narkowicz_pre_scale = get("NarkowiczPreScale");
  const grading::FilmParams film = film_preset(static_cast<FilmPreset>(get("FilmPreset")));
  p->film_slope = film.slope;
  p->film_toe = film.toe;
  p->film_shoulder = film.shoulder;
  p->film_black_clip = film.black_clip;
  p->film_white_clip = film.white_clip;
  const UeFilmicSpace space = ue_filmic_space();
  p->op_rec709_to_ap1 = space.rec709_to_ap1;
  p->op_ap1_to_rec709 = space.ap1_to_rec709;
}

}  // namespace hdrc::ref::operators
