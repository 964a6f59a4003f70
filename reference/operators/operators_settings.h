// The `operators` pipeline's user-facing settings and their host derivation into the parameter
// block (the op_* fields of interface/operators_params.h and the UE block's film_*).
//
//   hdrc::SettingValues s(&operators_setting_table(), &operators_setting_choices);
//   s.set_choice("Operator", "Hable");
//   hdrc::ParamBlock p;
//   derive_operators(s, &p);   // then apply_operator(p, rgb) / the GPU stage read p
#pragma once

#include <string_view>
#include <vector>

#include "core/settings.h"
#include "core/shader_interface.h"

namespace hdrc::ref::operators {

// Operator (named: Reinhard, ReinhardWhite, Hable, AcesNarkowicz, UnityNeutral, UeFilmic), Key,
// AdaptedLuminance, WhitePoint, HableA..HableF, HableW, ExposureBias, NarkowiczPreScale,
// FilmPreset (named: Default, Legacy, ACES, Uncharted, HP). Defaults and ranges are documented in
// the table (operators_settings.cpp).
const std::vector<hdrc::SettingInfo>& operators_setting_table();

// The named values of "Operator" and "FilmPreset" (their enum values); nullptr for the others.
const std::vector<hdrc::SettingChoice>* operators_setting_choices(std::string_view setting);

// Settings values over this pipeline's table.
hdrc::SettingValues operators_settings();

// Fills every op_* field and film_slope/toe/shoulder/black_clip/white_clip of `p` from `s`
// (other fields untouched): op_exposure = Key / AdaptedLuminance, the Hable and Narkowicz values
// as given, FilmPreset's five values, and UE's sRGB working-colour-space matrices. A setting that
// `s`'s table does not have takes this pipeline's default, so values over another table derive
// the defaults rather than zeros.
void derive_operators(const hdrc::SettingValues& s, hdrc::ParamBlock* p);

}  // namespace hdrc::ref::operators
