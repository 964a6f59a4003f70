#include "core/cvars.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

#include "core/nearest.h"

namespace hdrc {

const std::vector<CvarInfo>& cvar_table() {
  // Defaults and meanings: docs/spec/ue55.md §10 (RenderCore.cpp, PostProcessCombineLUTs.cpp,
  // PostProcessTonemap.cpp of UE 5.5). Ranges are what a case may ask for: UE clamps the enum
  // cvars to these ranges; a case outside them is a mistake in the case, not a UE behaviour to
  // test.
  static const std::vector<CvarInfo> table = {
      {"r.HDR.EnableHDROutput", CvarType::kInt, 0, 0, 1,
       "HDR swap chain on/off (RenderCore.cpp: IsHDREnabled)"},
      {"r.HDR.Display.OutputDevice", CvarType::kInt, 0, 0, 9,
       "EDisplayOutputFormat: LUT shaper, device encoding, tonemapper post conversion"},
      {"r.HDR.Display.ColorGamut", CvarType::kInt, 0, 0, 4,
       "EDisplayColorGamut: OuputGamutMappingMatrix in CombineLUTs"},
      {"r.HDR.Display.MaxLuminance", CvarType::kInt, 0, 0, 10000,
       "display peak nits: ACES tone scale max, scRGB scale (0 resolves to 1000 when HDR is on)"},
      {"r.HDR.Display.MinLuminanceLog10", CvarType::kFloat, -4.0, -6.0, 0.0,
       "log10 of the ACES tone scale minimum (nits)"},
      {"r.HDR.Display.MidLuminance", CvarType::kFloat, 15.0, 1.0, 100.0,
       "nits of 18% grey after the ACES tone scale"},
      {"r.HDR.Aces.SceneColorMultiplier", CvarType::kFloat, 1.5, 0.0, 16.0,
       "scene colour multiplier before the ACES output transform"},
      {"r.HDR.Aces.GamutCompression", CvarType::kFloat, 0.0, 0.0, 1.0,
       "blend towards the ACES 1.3 reference gamut compression"},
      {"r.LUT.Size", CvarType::kInt, 32, 16, 64, "edge length of the CombineLUTs LUT"},
      {"r.Color.Min", CvarType::kFloat, 0.0, -10.0, 10.0,
       "r.Color.* remap polynomial: output at 0 (PostProcessCombineLUTs.cpp: "
       "GetMappingPolynomial)"},
      {"r.Color.Mid", CvarType::kFloat, 0.5, -10.0, 10.0, "r.Color.* remap: output at 0.5"},
      {"r.Color.Max", CvarType::kFloat, 1.0, -10.0, 10.0, "r.Color.* remap: output at 1"},
      {"r.TonemapperGamma", CvarType::kFloat, 0.0, 0.0, 10.0,
       "> 0 forces the explicit-gamma device 2 for devices 0/1 "
       "(GetTonemapperOutputDeviceParameters)"},
      {"r.Tonemapper.Sharpen", CvarType::kFloat, -1.0, -1.0, 10.0,
       "< 0: the post-process Sharpen setting; else overrides it (clamped to 10)"},
      {"r.BackbufferQuantizationDitheringOverride", CvarType::kInt, 0, 0, 16,
       "dither bits; 0 = from the back buffer format"},
      {"r.DefaultBackBufferPixelFormat", CvarType::kInt, 4, 0, 4,
       "SDR back buffer: 0 8-bit RGBA (dither 1/255), 1 16-bit RGBA, 2 float RGB, 3 float RGBA, "
       "4 10-bit RGB 2-bit alpha (default; these dither 1/1023). SceneTextures.cpp"},
      {"r.HDR.UI.CompositeMode", CvarType::kInt, 1, 0, 1, "1: HDR UI composite shader"},
      {"r.HDR.UI.Level", CvarType::kFloat, 1.0, 0.0, 10.0, "UI luminance scale in the composite"},
      {"r.HDR.UI.Luminance", CvarType::kFloat, 300.0, 1.0, 10000.0, "UI white in nits"},
      {"r.EyeAdaptation.VisualizeDebugType", CvarType::kInt, 0, 0, 2,
       "VisualizeHDR background: 0 scene, 1 histogram percentile, 2 luminance"},
  };
  return table;
}

const CvarInfo* find_cvar(std::string_view name) {
  for (const auto& c : cvar_table())
    if (c.name == name) return &c;
  return nullptr;
}

std::vector<std::string> nearest_cvar_names(std::string_view name, size_t n) {
  std::vector<std::string> names;
  for (const auto& c : cvar_table()) names.emplace_back(c.name);
  return nearest_names(name, names, n);
}

Status CvarValues::set(std::string_view name, double value) {
  const CvarInfo* info = find_cvar(name);
  if (!info) {
    std::string near;
    for (const auto& s : nearest_cvar_names(name)) near += (near.empty() ? "" : ", ") + s;
    return Error{"", "", "unknown cvar '" + std::string(name) + "'", "nearest: " + near};
  }
  if (info->type == CvarType::kInt && value != std::floor(value)) {
    return Error{
        "", "", "cvar " + std::string(name) + " is an integer, got " + format_number(value),
        "integers " + format_number(info->min_value) + " to " + format_number(info->max_value)};
  }
  if (!(value >= info->min_value && value <= info->max_value)) {
    return Error{"", "",
                 "cvar " + std::string(name) + " = " + format_number(value) + " is out of range",
                 format_number(info->min_value) + " to " + format_number(info->max_value)};
  }
  values_[std::string(name)] = value;
  return {};
}

double CvarValues::get(std::string_view name) const {
  auto it = values_.find(std::string(name));
  if (it != values_.end()) return it->second;
  const CvarInfo* info = find_cvar(name);
  return info ? info->default_value : 0.0;
}

}  // namespace hdrc
