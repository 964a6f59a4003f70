// Post-process and view settings a case may set (UE's FPostProcessSettings members and the view
// values CombineLUTs and the tonemapper read), with UE 5.5's defaults
// (Scene.cpp: FPostProcessSettings::FPostProcessSettings, docs/spec/ue55.md §4.1, §6.1).
#pragma once

#include <array>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"

namespace hdrc {

struct SettingInfo {
  std::string_view name;
  int components;  // 1 (scalar) or 4 (a vec4 / linear colour with alpha)
  std::array<double, 4> default_value;
  double min_value, max_value;  // inclusive, per component
  std::string_view feeds;
};

const std::vector<SettingInfo>& setting_table();

// Settings whose values have names (an enum): the names in value order, e.g. WorkingColorSpace's
// presets. nullptr for a setting without named values.
struct SettingChoice {
  std::string_view name;
  double value;
};
const std::vector<SettingChoice>* setting_choices(std::string_view setting);
// "sRGB (1), Rec2020 (2), ..." for error messages and `cvars`; "" without named values.
std::string setting_choices_text(std::string_view setting);
const SettingInfo* find_setting(std::string_view name);
std::vector<std::string> nearest_setting_names(std::string_view name, size_t n = 3);

// A pipeline's settings: its table and its named values (UE 5.5's are setting_table() and
// setting_choices()). Every pipeline declares one (core/pipeline.h).
using SettingChoicesFn = const std::vector<SettingChoice>* (*)(std::string_view setting);
const SettingInfo* find_setting(const std::vector<SettingInfo>& table, std::string_view name);

using Vec4d = std::array<double, 4>;

class SettingValues {
 public:
  // UE 5.5's settings (setting_table(), setting_choices()).
  SettingValues() = default;
  // Another pipeline's settings: `table` (and `choices`, when some settings have named values)
  // outlive the values.
  explicit SettingValues(const std::vector<SettingInfo>* table, SettingChoicesFn choices = nullptr)
      : table_(table), choices_(choices) {}
  // Scalars are given as {v, 0, 0, 0}. Validates name, arity (`components`) and range.
  Status set(std::string_view name, const Vec4d& value, int components);
  // A named value of a setting with named values (setting_choices): "WorkingColorSpace" =
  // "Rec2020". The error names the valid choices.
  Status set_choice(std::string_view name, std::string_view choice);
  double get(std::string_view name) const { return get4(name)[0]; }
  Vec4d get4(std::string_view name) const;
  const std::map<std::string, Vec4d>& explicit_values() const { return values_; }
  const std::vector<SettingInfo>& table() const { return *table_; }
  // The named values of `setting` in this table (nullptr: none).
  const std::vector<SettingChoice>* choices(std::string_view setting) const {
    return choices_ ? choices_(setting) : nullptr;
  }
  // "sRGB (1), Rec2020 (2), ..." for errors; "" without named values.
  std::string choices_text(std::string_view setting) const;

 private:
  const std::vector<SettingInfo>* table_ = &setting_table();
  SettingChoicesFn choices_ = &setting_choices;
  std::map<std::string, Vec4d> values_;
};

}  // namespace hdrc
