#include "core/settings.h"

#include <algorithm>
#include <cctype>
#include <sstream>

#include "core/nearest.h"

namespace hdrc {

namespace {
constexpr Vec4d k1{1, 1, 1, 1};
constexpr Vec4d k0{0, 0, 0, 0};
Vec4d s(double v) {
  return {v, 0, 0, 0};
}
}  // namespace

const std::vector<SettingInfo>& setting_table() {
  // Scene.cpp: FPostProcessSettings constructor (UE 5.5), docs/spec/ue55.md §4.1; view values from
  // FViewInfo (ColorScale / OverlayColor camera fade) and GEngine->DisplayGamma.
  static const std::vector<SettingInfo> table = [] {
    std::vector<SettingInfo> t = {
        {"WhiteTemp", 1, s(6500), 1000, 40000, "white balance temperature, K"},
        {"WhiteTint", 1, s(0), -1, 1, "white balance tint"},
        {"TemperatureType", 1, s(0), 0, 1,
         "0 TEMP_WhiteBalance, 1 TEMP_ColorTemperature (swaps source and destination white)"},
        {"ColorCorrectionShadowsMax", 1, s(0.09), -1, 1, "ColorCorrectAll shadow range"},
        {"ColorCorrectionHighlightsMin", 1, s(0.5), -1, 2, "ColorCorrectAll highlight start"},
        {"ColorCorrectionHighlightsMax", 1, s(1.0), 0, 10, "ColorCorrectAll highlight end"},
        {"BlueCorrection", 1, s(0.6), 0, 1, "SDR film path blue correction"},
        {"ExpandGamut", 1, s(1.0), 0, 1, "fake wide gamut amount"},
        {"ToneCurveAmount", 1, s(1.0), 0, 1, "FilmToneMap blend"},
        {"FilmSlope", 1, s(0.88), 0, 1, "FilmToneMap slope"},
        {"FilmToe", 1, s(0.55), 0, 1, "FilmToneMap toe"},
        {"FilmShoulder", 1, s(0.26), 0, 1, "FilmToneMap shoulder"},
        {"FilmBlackClip", 1, s(0.0), 0, 1, "FilmToneMap black clip"},
        {"FilmWhiteClip", 1, s(0.04), 0, 1, "FilmToneMap white clip"},
        // Scene.h / Scene.cpp (FPostProcessSettings): "Color Grading LUT Intensity", ClampMin 0,
        // ClampMax 1, default 1.0; it weighs the case's "lut" (ColorGradingLUT) in LerpTo
        // (docs/ue55-lut-blend-spec.md §2.1-§2.4).
        {"ColorGradingIntensity", 1, s(1.0), 0, 1,
         "weight of the case's user LUT (ColorGradingLUT) in CombineLUTs' blend"},
        {"ViewColorScale", 4, k1, 0, 16, "View.ColorScale (camera fade), rgb"},
        {"ViewOverlayColor", 4, k0, 0, 16, "View.OverlayColor (camera fade), rgb and blend in a"},
        {"DisplayGamma", 1, s(2.2), 1, 5, "GEngine->DisplayGamma (InverseGamma)"},
        {"SceneColorTint", 4, k1, 0, 16, "tonemapper SceneColorTint, rgb"},
        {"Exposure", 1, s(1.0), 0, 1e6,
         "GlobalExposure: the eye adaptation (or fixed) exposure the tonemapper applies"},
        {"PreExposure", 1, s(1.0), 1e-6, 1e6,
         "View.PreExposure: the scene colour input is pre-exposed by it; the tonemapper and "
         "VisualizeHDR divide it out"},
        {"VignetteIntensity", 1, s(0.4), 0, 1, "tonemapper vignette"},
        {"BloomIntensity", 1, s(0.675), 0, 8, "bloom intensity (divides the dirt mask tint)"},
        {"BloomDirtMaskIntensity", 1, s(0.0), 0, 8, "dirt mask intensity"},
        {"BloomDirtMaskTint", 4, {0.5, 0.5, 0.5, 1}, 0, 8, "dirt mask tint, rgb"},
        {"Sharpen", 1, s(0.0), 0, 10, "tonemapper sharpen (r.Tonemapper.Sharpen < 0)"},
        {"SceneFringeIntensity", 1, s(0.0), 0, 5, "chromatic aberration intensity"},
        {"ChromaticAberrationStartOffset", 1, s(0.0), 0, 1, "chromatic aberration start offset"},
        {"FrameIndex", 1, s(0), 0, 1e9, "view-state OutputFrameIndex (dither Halton index, mod 8)"},
        // Platform properties rather than UE settings (FSceneViewState::CreateLUTRenderTarget picks
        // them from RHI capabilities); cases choose them to cover every path a port may take.
        {"LUTFormat", 1, s(0), 0, 2,
         "LUT storage: 0 A2B10G10R10 UNORM (UE default), 1 RGBA16F (PF_FloatRGBA), 2 RGBA32F"},
        {"LUTLayout", 1, s(0), 0, 1, "LUT layout: 0 volume N^3 (desktop), 1 2-D unwrapped N^2 x N"},
        // Slate's colour vision deficiency (FSlateApplication::SetColorVisionDeficiencyType).
        {"ColorVisionDeficiencyType", 1, s(0), 0, 3,
         "0 NormalVision, 1 Deuteranope, 2 Protanope, 3 Tritanope"},
        {"ColorVisionDeficiencySeverity", 1, s(0), 0, 10, "severity 0-10 (truncated)"},
        {"ColorVisionDeficiencyCorrect", 1, s(0), 0, 1, "1: daltonise instead of simulate"},
        {"ColorVisionDeficiencyShowCorrection", 1, s(0), 0, 1,
         "1: simulate the deficiency on the corrected colours"},
        // The project's Working Color Space (RendererSettings.h: WorkingColorSpaceChoice,
        // EWorkingColorSpace numbering; reference/color/ue_matrices.h). Custom reads the two
        // chromaticity settings below (UE's Red/Green/Blue/WhiteChromaticityCoordinate).
        {"WorkingColorSpace", 1, s(1), 1, 7,
         "project Working Color Space: 1 sRGB, 2 Rec2020, 3 ACESAP0, 4 ACESAP1, 5 P3DCI, "
         "6 P3D65, 7 Custom (a name or its number)"},
        {"WorkingColorSpaceRedGreen",
         4,
         {0.64, 0.33, 0.30, 0.60},
         -1,
         2,
         "Custom working colour space: red x, y and green x, y (CIE 1931)"},
        {"WorkingColorSpaceBlueWhite",
         4,
         {0.15, 0.06, 0.3127, 0.3290},
         -1,
         2,
         "Custom working colour space: blue x, y and white x, y (CIE 1931)"},
    };
    // ColorCorrectAll: global and per-zone Saturation/Contrast/Gamma/Gain/Offset (vec4).
    static const std::vector<std::string> cc_names = [] {
      std::vector<std::string> n;
      for (const char* zone : {"", "Shadows", "Midtones", "Highlights"})
        for (const char* control : {"Saturation", "Contrast", "Gamma", "Gain", "Offset"})
          n.push_back(std::string("Color") + control + zone);
      return n;
    }();
    for (const std::string& n : cc_names) {
      const bool offset = n.rfind("ColorOffset", 0) == 0;
      const bool gamma = n.rfind("ColorGamma", 0) == 0;
      t.push_back({n, 4, offset ? k0 : k1, offset ? -1.0 : (gamma ? 0.01 : 0.0),
                   offset ? 1.0 : 10.0, "ColorCorrectAll control (rgb, w multiplies/adds all)"});
    }
    return t;
  }();
  return table;
}

const std::vector<SettingChoice>* setting_choices(std::string_view setting) {
  // RendererSettings.h: EWorkingColorSpace enumerator names and values (UE 5.5).
  static const std::vector<SettingChoice> wcs = {{"sRGB", 1},    {"Rec2020", 2}, {"ACESAP0", 3},
                                                 {"ACESAP1", 4}, {"P3DCI", 5},   {"P3D65", 6},
                                                 {"Custom", 7}};
  if (setting == "WorkingColorSpace") return &wcs;
  return nullptr;
}

namespace {
std::string choices_text_of(const std::vector<SettingChoice>* choices) {
  if (!choices) return "";
  std::ostringstream out;
  for (const auto& c : *choices)
    out << (out.tellp() > 0 ? ", " : "") << c.name << " (" << c.value << ")";
  return out.str();
}
}  // namespace

std::string setting_choices_text(std::string_view setting) {
  return choices_text_of(setting_choices(setting));
}

std::string SettingValues::choices_text(std::string_view setting) const {
  return choices_text_of(choices(setting));
}

const SettingInfo* find_setting(const std::vector<SettingInfo>& table, std::string_view name) {
  for (const auto& s : table)
    if (s.name == name) return &s;
  return nullptr;
}

const SettingInfo* find_setting(std::string_view name) {
  return find_setting(setting_table(), name);
}

std::vector<std::string> nearest_setting_names(std::string_view name, size_t n) {
  std::vector<std::string> names;
  for (const auto& s : setting_table()) names.emplace_back(s.name);
  return nearest_names(name, names, n);
}

Status SettingValues::set(std::string_view name, const Vec4d& value, int components) {
  const SettingInfo* info = find_setting(*table_, name);
  if (!info) {
    std::vector<std::string> names;
    for (const auto& s : *table_) names.emplace_back(s.name);
    // A name given without its component ("contrast" for Unity's "ColorAdjustments.contrast"):
    // the settings it ends, first; then the closest by edit distance.
    std::string near;
    auto lower = [](std::string t) {
      for (char& ch : t) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
      return t;
    };
    std::string tail = ".";  // appended, not "." + ...: GCC 12 -O3 -Wrestrict (bug 105329)
    tail += lower(std::string(name));
    for (const auto& n : names)
      if (lower(n).size() > tail.size() && lower(n).ends_with(tail))
        near += (near.empty() ? "" : ", ") + n;
    for (const auto& s : nearest_names(name, names, 3))
      if (near.find(s) == std::string::npos) near += (near.empty() ? "" : ", ") + s;
    return Error{"", "", "unknown setting '" + std::string(name) + "'", "nearest: " + near};
  }
  if (components != info->components) {
    return Error{"", "",
                 "setting " + std::string(name) + " takes " +
                     (info->components == 1 ? "a number" : "4 numbers [r, g, b, a]"),
                 info->components == 1 ? "a number" : "an array of 4 numbers"};
  }
  for (int c = 0; c < components; ++c) {
    if (!(value[c] >= info->min_value && value[c] <= info->max_value)) {
      std::ostringstream msg, range;
      msg << "setting " << name
          << (components > 1 ? std::string("[") + std::to_string(c) + "]" : "") << " = " << value[c]
          << " is out of range";
      range << info->min_value << " to " << info->max_value;
      return Error{"", "", msg.str(), range.str()};
    }
  }
  if (const auto* named_values = choices(name)) {
    const bool named = std::any_of(named_values->begin(), named_values->end(),
                                   [&](const SettingChoice& c) { return c.value == value[0]; });
    if (!named) {
      std::ostringstream msg;
      msg << "setting " << name << " = " << value[0] << " is not one of its values";
      return Error{"", "", msg.str(), choices_text(name)};
    }
  }
  Vec4d v = info->default_value;
  for (int c = 0; c < components; ++c) v[c] = value[c];
  values_[std::string(name)] = v;
  return {};
}

Status SettingValues::set_choice(std::string_view name, std::string_view choice) {
  const auto* named_values = choices(name);
  if (!named_values) {
    if (!find_setting(*table_, name))
      return set(name, {0, 0, 0, 0}, 1);  // the unknown-setting error
    return Error{"", "",
                 "setting " + std::string(name) + " takes a number, not the name '" +
                     std::string(choice) + "'",
                 "a number"};
  }
  for (const auto& c : *named_values)
    if (c.name == choice) return set(name, {c.value, 0, 0, 0}, 1);
  std::vector<std::string> names;
  for (const auto& c : *named_values) names.emplace_back(c.name);
  std::string near;
  for (const auto& n : nearest_names(choice, names, 1)) near = n;
  return Error{"", "",
               "unknown " + std::string(name) + " '" + std::string(choice) + "'" +
                   (near.empty() ? "" : " (did you mean " + near + "?)"),
               choices_text(name)};
}

Vec4d SettingValues::get4(std::string_view name) const {
  auto it = values_.find(std::string(name));
  if (it != values_.end()) return it->second;
  const SettingInfo* info = find_setting(*table_, name);
  return info ? info->default_value : Vec4d{0, 0, 0, 0};
}

}  // namespace hdrc
