#include "reference/ue/cpp/resolve.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "reference/ue/aces/aces_params.h"
#include "reference/ue/cpp/lut_blend_table.h"
#include "reference/ue/grading/color_polynomial.h"
#include "reference/ue/grading/white_balance.h"

namespace hdrc::ref {

const Chromaticities& default_working_chromaticities() {
  return standard::kSrgb;
}

double halton(int index, int base) {
  double result = 0.0, f = 1.0;
  for (int i = index; i > 0; i /= base) {
    f /= base;
    result += f * (i % base);
  }
  return result;
}

Result<WorkingColorSpace> working_color_space_of(const SettingValues& st) {
  const int preset = static_cast<int>(st.get("WorkingColorSpace"));
  const auto& explicit_values = st.explicit_values();
  const bool custom = preset == static_cast<int>(WorkingColorSpacePreset::kCustom);
  if (!custom) {
    // UE ignores the chromaticity coordinates unless the choice is Custom (their EditCondition);
    // a case that sets them with a preset is a mistake.
    for (const char* name : {"WorkingColorSpaceRedGreen", "WorkingColorSpaceBlueWhite"})
      if (explicit_values.count(name))
        return Error{"", "/settings/" + std::string(name),
                     std::string(name) +
                         " applies only when WorkingColorSpace is Custom (7); "
                         "it is " +
                         (working_color_space_name(preset) ? working_color_space_name(preset)
                                                           : std::to_string(preset)),
                     "WorkingColorSpace Custom, or remove " + std::string(name)};
    return make_working_color_space(static_cast<WorkingColorSpacePreset>(preset));
  }
  const Vec4d rg = st.get4("WorkingColorSpaceRedGreen");
  const Vec4d bw = st.get4("WorkingColorSpaceBlueWhite");
  const Chromaticities c{rg[0], rg[1], rg[2], rg[3], bw[0], bw[1], bw[2], bw[3]};
  if (const std::string problem = chromaticities_problem(c); !problem.empty()) {
    char values[160];
    std::snprintf(values, sizeof values, "R (%g, %g) G (%g, %g) B (%g, %g) W (%g, %g)", c.rx, c.ry,
                  c.gx, c.gy, c.bx, c.by, c.wx, c.wy);
    return Error{"", "/settings/WorkingColorSpaceRedGreen",
                 "custom working colour space " + std::string(values) + ": " + problem,
                 "chromaticities of three independent primaries around a white with y > 0"};
  }
  return make_working_color_space(c);
}

namespace {
std::array<double, 4> v4(const Vec4d& v) {
  return {v[0], v[1], v[2], v[3]};
}
}  // namespace

Result<Resolution> resolve(const Case& c, int width, int height) {
  Resolution r;
  ParamBlock& p = r.params;
  const CvarValues& cv = c.cvars;
  const SettingValues& st = c.settings;
  p.width = width;
  p.height = height;

  // Output device and gamut: the cvars, clamped to the enums (HDRGetMetaData, docs/spec/ue55.md
  // §7.1).
  int device = std::clamp(cv.get_int("r.HDR.Display.OutputDevice"), 0, 9);
  p.output_gamut = std::clamp(cv.get_int("r.HDR.Display.ColorGamut"), 0, 4);
  // GetTonemapperOutputDeviceParameters (docs/spec/ue55.md §6.2): device 2 with Gamma 0 uses 2.2;
  // Gamma > 0 turns devices 0 and 1 into the explicit-gamma device 2.
  double gamma = cv.get("r.TonemapperGamma");
  if (device == 2 && gamma == 0.0) gamma = 2.2;
  if (gamma > 0.0 && (device == 0 || device == 1)) device = 2;
  p.output_device = device;
  const auto inv_gamma = grading::get_inverse_gamma(st.get("DisplayGamma"), gamma);
  p.inverse_gamma = {inv_gamma.x, inv_gamma.y, inv_gamma.z, 0.0};

  // HDRSettingChangedSinkCallback: with HDR on, a display nit level of 0 falls back to 1000;
  // with HDR off HDRConfigureCVars leaves MaxLuminance at the cvar (0 by default).
  const bool hdr = cv.get_int("r.HDR.EnableHDROutput") != 0;
  double max_lum = cv.get("r.HDR.Display.MaxLuminance");
  if (hdr && max_lum == 0.0) max_lum = 1000.0;
  p.output_max_luminance = max_lum;

  // ACES parameters (RenderCore.cpp: ConfigureACESTonemapParams; float32 as UE).
  const auto aces = configure_aces13(cv, max_lum, &p);
  const auto& a = aces.packed;
  p.aces_scene_color_multiplier = a.scene_color_multiplier;
  p.aces_gamut_compression = a.gamut_compression;
  // Only stages that run CombineLUTs' device encoding use these parameters.
  const bool encodes =
      c.stage && (c.stage->id == StageId::kCombineLuts || c.stage->id == StageId::kTonemap);
  if (encodes && !aces.status.ok() && device >= 3 && device <= 6) {
    r.degenerate = "ACES device " + std::to_string(device) +
                   " with degenerate tone-scale parameters (MaxLuminance resolves to " +
                   std::to_string(static_cast<int>(max_lum)) +
                   (hdr ? "" : " because r.HDR.EnableHDROutput is 0") +
                   "): " + aces.status.error().message;
  }

  // Working colour space (the project setting, RendererSettings.cpp:
  // UpdateWorkingColorSpaceAndChromaticities) and the output gamut.
  auto wcs_result = working_color_space_of(st);
  if (!wcs_result) return wcs_result.error();
  const WorkingColorSpace& wcs = *wcs_result;
  p.wcs_to_xyz = wcs.to_xyz;
  p.wcs_from_xyz = wcs.from_xyz;
  p.wcs_to_ap1 = wcs.to_ap1;
  p.wcs_from_ap1 = wcs.from_ap1;
  p.wcs_to_ap0 = wcs.to_ap0;
  p.wcs_is_srgb = wcs.is_srgb ? 1 : 0;
  p.ap1_to_output = ap1_to_output_gamut(p.output_gamut);

  // White balance (SKIP_TEMPERATURE permutation when 6500 K / tint 0).
  grading::WhiteBalanceParams wb;
  wb.white_temp = st.get("WhiteTemp");
  wb.white_tint = st.get("WhiteTint");
  wb.temperature_type = st.get("TemperatureType") == 0
                            ? grading::TemperatureType::kWhiteBalance
                            : grading::TemperatureType::kColorTemperature;
  p.white_balance_enabled = grading::white_balance_skipped(wb) ? 0 : 1;
  p.white_balance =
      p.white_balance_enabled ? grading::white_balance_matrix(wb, wcs) : Mat3::identity();

  p.expand_gamut = st.get("ExpandGamut");
  p.blue_correction = st.get("BlueCorrection");
  p.tone_curve_amount = st.get("ToneCurveAmount");
  p.film_slope = st.get("FilmSlope");
  p.film_toe = st.get("FilmToe");
  p.film_shoulder = st.get("FilmShoulder");
  p.film_black_clip = st.get("FilmBlackClip");
  p.film_white_clip = st.get("FilmWhiteClip");

  // The user colour-grading LUTs (docs/ue55-lut-blend-spec.md §2): the case's "lut" as one
  // post-process source at ColorGradingIntensity (OverridePostProcessSettings, BlendWeight 1),
  // then each "lut_blend" step as a LerpTo, then GenerateFinalTable once, as UE's C++ does. The
  // table's textures go to the user-LUT slots (Textures_1..4), its weights to LUTWeights.
  {
    std::vector<std::shared_ptr<const UserLut>> luts;  // distinct LUTs: the index is the texture
    auto id = [&](const std::shared_ptr<const UserLut>& l) {
      for (size_t i = 0; i < luts.size(); ++i)
        if (luts[i]->name == l->name) return static_cast<int>(i);
      luts.push_back(l);
      return static_cast<int>(luts.size() - 1);
    };
    ContributingLuts list;
    if (c.lut)
      list.override_from_source(id(c.lut), static_cast<float>(st.get("ColorGradingIntensity")),
                                1.0f);
    for (const LutBlendStep& step : c.lut_blend)
      if (step.lut) list.lerp_to(id(step.lut), static_cast<float>(step.weight));
    const LutBlendTable table = generate_final_table(list.entries());
    p.lut_blend_count = table.count;
    p.lut_weights = {table.weight[0], table.weight[1], table.weight[2], table.weight[3]};
    p.lut_weight_4 = table.weight[4];
    if (c.stage && c.stage->user_lut_slots > 1) {
      for (int i = 1; i < table.count; ++i)
        r.user_luts[static_cast<size_t>(i - 1)] = luts[static_cast<size_t>(table.lut[i])];
    }
  }
  p.cc_shadows_max = st.get("ColorCorrectionShadowsMax");
  p.cc_highlights_min = st.get("ColorCorrectionHighlightsMin");
  p.cc_highlights_max = st.get("ColorCorrectionHighlightsMax");
#define HDRC_CC(field, name)                                 \
  p.field = v4(st.get4("Color" name));                       \
  p.field##_shadows = v4(st.get4("Color" name "Shadows"));   \
  p.field##_midtones = v4(st.get4("Color" name "Midtones")); \
  p.field##_highlights = v4(st.get4("Color" name "Highlights"));
  HDRC_CC(cc_saturation, "Saturation")
  HDRC_CC(cc_contrast, "Contrast")
  HDRC_CC(cc_gamma, "Gamma")
  HDRC_CC(cc_gain, "Gain")
  HDRC_CC(cc_offset, "Offset")
#undef HDRC_CC

  const auto poly = grading::get_mapping_polynomial(
      {cv.get("r.Color.Min"), cv.get("r.Color.Mid"), cv.get("r.Color.Max")});
  p.mapping_polynomial = {poly.a, poly.b, poly.c, 0.0};
  p.color_scale = v4(st.get4("ViewColorScale"));
  p.overlay_color = v4(st.get4("ViewOverlayColor"));

  p.lut_size = cv.get_int("r.LUT.Size");
  p.lut_format = static_cast<int>(st.get("LUTFormat"));
  p.lut_layout = static_cast<int>(st.get("LUTLayout"));

  // Tonemapper (PostProcessTonemap.cpp: AddTonemapPass, docs/spec/ue55.md §6.1).
  p.scene_color_tint = v4(st.get4("SceneColorTint"));
  p.pre_exposure = st.get("PreExposure");
  p.exposure = st.get("Exposure") / p.pre_exposure;  // OneOverPreExposure · GlobalExposure
  p.vignette_intensity = st.get("VignetteIntensity");
  const double sharpen_cvar = cv.get("r.Tonemapper.Sharpen");
  const double sharpen =
      std::clamp(sharpen_cvar >= 0.0 ? sharpen_cvar : st.get("Sharpen"), 0.0, 10.0);
  p.sharpen_div6 = sharpen / 6.0;
  const int dither_bits = cv.get_int("r.BackbufferQuantizationDitheringOverride");
  if (device == 8 || device == 9) {
    p.dither_amount = 0.0;
  } else if (dither_bits > 0) {
    p.dither_amount = 1.0 / (std::exp2(dither_bits) - 1.0);
  } else {
    // AddTonemapPass: 1/1023 unless the view family's render target is PF_B8G8R8A8/PF_R8G8B8A8.
    // An SDR back buffer has r.DefaultBackBufferPixelFormat's format (default 4, A2B10G10R10:
    // 5.5 SceneTextures.cpp); an HDR swap chain is 10-bit or float (docs/ue55-decisions.md D10).
    const bool eight_bit = device <= 2 && cv.get_int("r.DefaultBackBufferPixelFormat") == 0;
    p.dither_amount = eight_bit ? 1.0 / 255.0 : 1.0 / 1023.0;
  }
  p.frame_index = static_cast<int>(st.get("FrameIndex")) % 8;
  p.grain_random = {halton(p.frame_index, 2), halton(p.frame_index, 3), 0.0, 0.0};
  const double bloom_intensity = st.get("BloomIntensity");
  const Vec4d dirt_tint = st.get4("BloomDirtMaskTint");
  const double dirt_scale =
      bloom_intensity > 0.0 ? st.get("BloomDirtMaskIntensity") / bloom_intensity : 0.0;
  p.bloom_dirt_tint = {dirt_tint[0] * dirt_scale, dirt_tint[1] * dirt_scale,
                       dirt_tint[2] * dirt_scale, 0.0};
  const double fringe_intensity = st.get("SceneFringeIntensity");
  const double start = st.get("ChromaticAberrationStartOffset");
  const double mult = start < 1.0 - 1e-4 ? 1.0 / (1.0 - start) : 0.0;
  const double offset = fringe_intensity * 0.01;
  p.fringe = {offset * 0.007 * (611.3 - 464.3) * mult, offset * 0.007 * (549.1 - 464.3) * mult,
              start, fringe_intensity > 0.01 ? 1.0 : 0.0};

  p.ui_composite_mode = cv.get_int("r.HDR.UI.CompositeMode");
  p.cvd_type = static_cast<int>(st.get("ColorVisionDeficiencyType"));
  p.cvd_severity = static_cast<int>(st.get("ColorVisionDeficiencySeverity"));
  p.cvd_correct = static_cast<int>(st.get("ColorVisionDeficiencyCorrect"));
  p.cvd_show_correction = static_cast<int>(st.get("ColorVisionDeficiencyShowCorrection"));
  p.visualize_debug_type = cv.get_int("r.EyeAdaptation.VisualizeDebugType");
  p.ui_level = cv.get("r.HDR.UI.Level");
  p.ui_luminance = cv.get("r.HDR.UI.Luminance");
  return r;
}

Result<ParamBlock> resolve_params(const Case& c, int width, int height) {
  auto r = resolve(c, width, height);
  if (!r) return r.error();
  return r->params;
}

aces::AcesConfigured configure_aces13(const CvarValues& cv, double max_luminance, ParamBlock* p) {
  const float min_lum =
      std::pow(10.0f, static_cast<float>(cv.get("r.HDR.Display.MinLuminanceLog10")));
  auto aces = aces::configure_aces_tonemap_params(
      min_lum, static_cast<float>(cv.get("r.HDR.Display.MidLuminance")),
      static_cast<float>(max_luminance),
      static_cast<float>(cv.get("r.HDR.Aces.SceneColorMultiplier")),
      static_cast<float>(cv.get("r.HDR.Aces.GamutCompression")));
  const auto& a = aces.packed;
  p->aces_min_max = {a.min_max_data[0], a.min_max_data[1], a.min_max_data[2], a.min_max_data[3]};
  p->aces_mid = {a.mid_data[0], a.mid_data[1], a.mid_data[2], a.mid_data[3]};
  p->aces_coefs_low_0 = {a.coefs_low_0[0], a.coefs_low_0[1], a.coefs_low_0[2], a.coefs_low_0[3]};
  p->aces_coefs_high_0 = {a.coefs_high_0[0], a.coefs_high_0[1], a.coefs_high_0[2],
                          a.coefs_high_0[3]};
  p->aces_coefs_low_4 = a.coefs_low_4;
  p->aces_coefs_high_4 = a.coefs_high_4;
  return aces;
}

}  // namespace hdrc::ref
