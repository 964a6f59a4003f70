// UE 5.8's HDR output pipeline as a module (core/pipeline.h), first stage: CombineLUTs with its
// inner LUT (ue58_combine_luts.h). Settings are UE 5.5's (the grading controls 5.8 shares) plus
// 5.8's own; the host derivation runs UE 5.5's (reference/ue/cpp/resolve.cpp) for what is shared,
// then what 5.8's C++ adds (PostProcessCombineLUTs.cpp: GetTonemappingMethod, GetTonemappingMax,
// GetInnerLUTParameters, AddCombineLUTPass; ACESUtils.cpp: the tables). docs/ue58-decisions.md E.
#include "reference/ue/ue58/ue58_pipeline.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <type_traits>

#include "core/cvars.h"
#include "core/settings.h"
#include "reference/color/ue_matrices.h"
#include "reference/reference_engine.h"
#include "reference/ue/aces/aces_params.h"
#include "reference/ue/aces2/aces2.h"
#include "reference/ue/cpp/resolve.h"
#include "reference/ue/tonemap.h"
#include "reference/ue/ue55/ue55_pipeline.h"
#include "reference/ue/ue58/ue58_combine_luts.h"
#include "reference/ue/ue58/ue58_named_values.h"
#include "reference/ue/ue58/ue58_tonemap.h"
#include "reference/ue/ue58/ue58_ui_composite.h"

namespace hdrc::ref::ue58 {

namespace {

constexpr std::array<double, 4> s(double v) {
  return {v, 0, 0, 0};
}

// UE 5.8's settings: UE 5.5's (the same FPostProcessSettings and platform properties; LUTLayout
// left out, 5.8 bakes only a volume LUT: docs/ue58-differences.md L14), then 5.8's. The 5.8-only
// console variables are settings here (docs/ue58-decisions.md E4): the cvar table is UE's one
// table (core/cvars.cpp), which 5.8 shares for everything else.
const std::vector<SettingInfo>& settings() {
  static const std::vector<SettingInfo> table = [] {
    std::vector<SettingInfo> t;
    for (const SettingInfo& i : setting_table())
      if (i.name != "LUTLayout") t.push_back(i);
    const std::vector<SettingInfo> own = {
        {"TonemappingMethod", 1, s(0), 0, 1,
         "FPostProcessSettings::TonemappingMethod (5.8, default Filmic: Scene.cpp): 0 Filmic, 1 "
         "StandardACES; also chooses TonemappingSDRInvEOTF's default (PostProcessCombineLUTs.cpp: "
         "GetCombineLUTParameters)"},
        {"r.LUT.TonemappingMethod", 1, s(-1), -1, 1,
         "cvar r.LUT.TonemappingMethod: -1 the post-process setting, 0 Filmic, 1 StandardACES "
         "(PostProcessCombineLUTs.cpp: GetTonemappingMethod)"},
        {"r.LUT.TonemappingSDRInvEOTF", 1, s(-1), -1, 1,
         "cvar r.LUT.TonemappingSDRInvEOTF: -1 sRGB for a Filmic setting, BT.1886 for "
         "StandardACES; 0 sRGB; 1 BT.1886 (PostProcessCombineLUTs.cpp)"},
        {"r.HDR.Aces.Version", 1, s(2), 1, 2,
         "cvar r.HDR.Aces.Version (RenderCore.cpp, default 2): 1 ACES 1.3, 2 ACES 2.0 "
         "(FLUTInnerCS USE_ACES_2 = version > 1)"},
        {"r.HDR.PaperWhite", 1, s(203), 1, 10000,
         "cvar r.HDR.PaperWhite / the display's paper white, nits: TotalSceneColorMultiplier = "
         "PaperWhite / 203 * ACESSceneColorMultiplier (GetInnerLUTParameters)"},
        {"r.LUT.Shaper", 1, s(0), 0, 1,
         "cvar r.LUT.Shaper (PostProcessTonemap.cpp, default 0): 0 log lattice, 1 PQ lattice, "
         "every device"},
        {"r.LUT.Inner.Size", 1, s(64), 2, 128, "cvar r.LUT.Inner.Size: the inner LUT's edge"},
        // The vignette 5.8 added to FPostProcessSettings (Scene.h / Scene.cpp defaults:
        // docs/ue58-differences.md T3); VignetteIntensity is UE 5.5's setting.
        {"VignetteType", 1, s(0), 0, 2,
         "FPostProcessSettings::VignetteType (EVignetteType): 0 CosineFourthLaw, 1 Texture, 2 Oval "
         "(PostProcessTonemap.cpp: AddTonemapPass, USE_ADVANCED_VIGNETTE)"},
        {"VignetteCenterX", 1, s(0.5), -10, 10,
         "FPostProcessSettings::VignetteCenter.X, viewport UV (VignetteParams1.x)"},
        {"VignetteCenterY", 1, s(0.5), -10, 10,
         "FPostProcessSettings::VignetteCenter.Y, viewport UV (VignetteParams1.y)"},
        {"VignetteSizeX", 1, s(1), 0, 100,
         "FPostProcessSettings::VignetteSize.X (VignetteParams1.z = 1 / max(0.001, X); Oval)"},
        {"VignetteSizeY", 1, s(1), 0, 100,
         "FPostProcessSettings::VignetteSize.Y (VignetteParams1.w = 1 / max(0.001, Y); Oval)"},
        {"VignetteSoftness", 1, s(5), 0, 100,
         "FPostProcessSettings::VignetteSoftness (VignetteParams2; Oval)"},
        {"VignetteColor",
         4,
         {0, 0, 0, 1},
         0,
         100,
         "FPostProcessSettings::VignetteColor, rgb (VignetteParams0.yzw; alpha unused): mask = "
         "lerp(colour, 1, weight)"},
        // The Texture vignette (docs/ue58-decisions.md G4): the renderer's feature level, which
        // RemapPermutation reads (USE_VIGNETTE_TEXTURE only above SM5), and the texture
        // FPostProcessSettings::VignetteTexture names, here a generated stimulus.
        {"FeatureLevel", 1, s(3), 3, 4,
         "the view's ERHIFeatureLevel: 3 SM5, 4 SM6 (PostProcessTonemap.cpp RemapPermutation: "
         "USE_VIGNETTE_TEXTURE off at SM5 and below)"},
        {"VignetteTexture", 1, s(0), 0, 2,
         "FPostProcessSettings::VignetteTexture: 0 none (AddTonemapPass binds the white dummy), "
         "1 Radial (16 x 16), 2 Ramp (16 x 8), generated UNORM8 red-channel stimuli "
         "(ue58_tonemap.h vignette_texture_stimulus)"},
        // The UI composite's 5.8 console variables (SlateRHIRenderer.cpp: CVarHDRUILuminanceMode,
        // CVarHDRUICompositeEOTF/Gamma, CVarHDRUICompositeBlend/Gamma; docs/ue58-differences.md
        // U1-U3). The gammas have no range in UE; here (0, 10], a pow of 0 being meaningless.
        {"r.HDR.UI.Luminance.Mode", 1, s(0), 0, 1,
         "cvar r.HDR.UI.Luminance.Mode (SlateRHIRenderer.cpp, default 0): UILuminance = 0 the "
         "viewport's paper white (HDRMetaData.HDRPaperWhiteInNits: r.HDR.PaperWhite here), 1 "
         "r.HDR.UI.Luminance (5.8 default 203)"},
        {"r.HDR.UI.CompositeEOTF", 1, s(0), 0, 1,
         "cvar r.HDR.UI.CompositeEOTF (default 0): the UI's EOTF in the composite, 0 pow(x, "
         "r.HDR.UI.CompositeEOTF.Gamma), 1 sRGB (CompositeUIPixelShader.usf: LinearizeColor)"},
        {"r.HDR.UI.CompositeEOTF.Gamma", 1, s(2.4), 0.01, 10,
         "cvar r.HDR.UI.CompositeEOTF.Gamma (default 2.4, BT.1886 per BT.2408)"},
        {"r.HDR.UI.CompositeBlend", 1, s(0), 0, 1,
         "cvar r.HDR.UI.CompositeBlend (default 0): translucent UI blended 0 in a gamma space "
         "(pow(saturate(x / 10000), 1 / gamma)), 1 linearly after a Reinhard "
         "(CompositeUIPixelShader.usf: ComposeUIAndScene)"},
        {"r.HDR.UI.CompositeBlend.Gamma", 1, s(2.4), 0.01, 10,
         "cvar r.HDR.UI.CompositeBlend.Gamma (default 2.4); the host passes 1.f / gamma as "
         "UICompositeBlendInvGamma"},
        {"LimitingGamut", 1, s(-1), -1, 4,
         "the display's limiting colour space (RenderTarget->GetLimitingColorSpace), an "
         "EDisplayColorGamut; -1: P3-D65 for devices 3-6 (HDR without a listed display), sRGB "
         "otherwise (RenderCore.cpp: HDRGetDefaultMetaData / HDRGetMetaDataForWindow)"},
    };
    t.insert(t.end(), own.begin(), own.end());
    return t;
  }();
  return table;
}

const std::vector<SettingChoice>* choices(std::string_view setting) {
  static const std::vector<SettingChoice> method = {{"Filmic", 0}, {"StandardACES", 1}};
  static const std::vector<SettingChoice> vignette = {
      {"CosineFourthLaw", 0}, {"Texture", 1}, {"Oval", 2}};
  if (setting == "VignetteType") return &vignette;
  static const std::vector<SettingChoice> feature_level = {{"SM5", 3}, {"SM6", 4}};
  if (setting == "FeatureLevel") return &feature_level;
  static const std::vector<SettingChoice> texture = {{"None", 0}, {"Radial", 1}, {"Ramp", 2}};
  if (setting == "VignetteTexture") return &texture;
  static const std::vector<SettingChoice> gamut = {{"Auto", -1},   {"sRGB", 0}, {"DCIP3", 1},
                                                   {"Rec2020", 2}, {"ACES", 3}, {"ACEScg", 4}};
  if (setting == "TonemappingMethod") return &method;
  if (setting == "LimitingGamut") return &gamut;
  return setting_choices(setting);
}

const aces2::Chromaticities& gamut_chromaticities(int gamut) {
  switch (gamut) {
    case 1:
      return aces2::kP3D65;
    case 2:
      return aces2::kRec2020;
    case 3:
      return aces2::kAp0;
    case 4:
      return aces2::kAp1;
    default:
      return aces2::kRec709;
  }
}

aces2::Chromaticities to_aces2(const Chromaticities& c) {
  return {{c.rx, c.ry}, {c.gx, c.gy}, {c.bx, c.by}, {c.wx, c.wy}};
}

// PostProcessCombineLUTs.cpp: DoesGamutWhitePointMatch — the white within 3 * 2^-11 in x and y of
// D65 (gamuts 0-2) or the ACES white (3-4).
bool white_matches(int output_gamut, const aces2::Chromaticities& c) {
  constexpr double kTolerance = 3.0 / 2048.0;
  const bool d60 = output_gamut == 3 || output_gamut == 4;
  const double x = d60 ? .32168 : .3127, y = d60 ? .33767 : .329;
  return std::fabs(c.white[0] - x) <= kTolerance && std::fabs(c.white[1] - y) <= kTolerance;
}

Result<Resolution> resolve58(const Case& c, int width, int height) {
  // Everything 5.8 shares with 5.5 (the grading controls, matrices, device, gamut, gamma).
  auto base = resolve(c, width, height);
  if (!base) return base.error();
  Resolution r = *base;
  r.degenerate.clear();
  ParamBlock& p = r.params;
  const SettingValues& st = c.settings;
  const CvarValues& cv = c.cvars;
  const int device = p.output_device;
  const bool hdr_device = device >= 3 && device <= 6;

  // OutputMaxLuminance (docs/ue58-differences.md L12): the render target's peak — 100 for an SDR
  // target; for an HDR one r.HDR.Display.MaxLuminance, 0 meaning the 1000-nit default.
  const double max_cvar = cv.get("r.HDR.Display.MaxLuminance");
  p.output_max_luminance = hdr_device ? (max_cvar > 0.0 ? max_cvar : 1000.0) : 100.0;

  // GetTonemappingMethod: the cvar when >= 0, else the post-process setting.
  const int method_setting = static_cast<int>(st.get("TonemappingMethod"));
  const int method_cvar = static_cast<int>(st.get("r.LUT.TonemappingMethod"));
  p.ue58_tonemapping_method = method_cvar >= 0 ? method_cvar : method_setting;
  const bool aces_method = p.ue58_tonemapping_method == static_cast<int>(Method::kStandardAces);
  // GetCombineLUTParameters: TonemappingSDRInvEOTF, its default keyed on the *setting*.
  const int eotf_cvar = static_cast<int>(st.get("r.LUT.TonemappingSDRInvEOTF"));
  p.ue58_sdr_inv_eotf = eotf_cvar >= 0 ? eotf_cvar : (method_setting == 1 ? 1 : 0);
  p.ue58_aces_version = static_cast<int>(st.get("r.HDR.Aces.Version"));
  p.ue58_lut_shaper = static_cast<int>(st.get("r.LUT.Shaper"));
  p.ue58_inner_lut_size = static_cast<int>(st.get("r.LUT.Inner.Size"));
  // GetTonemappingMax: 1.05 for Filmic on devices 0, 1 and 9, else 1; LUTInvMax = 1 / that.
  const bool lut_max_105 = !aces_method && (device == 0 || device == 1 || device == 9);
  p.ue58_lut_inv_max = lut_max_105 ? static_cast<double>(1.f / 1.05f) : 1.0;
  // The Tonemap pass's LUTMax is GetTonemappingMax itself (AddTonemapPass), a float.
  p.ue58_lut_max = lut_max_105 ? static_cast<double>(1.05f) : 1.0;
  // AddTonemapPass: VignetteType and VignetteParams0-2 (float constants).
  p.ue58_vignette_type = static_cast<int>(st.get("VignetteType"));
  const auto color = st.get4("VignetteColor");
  const double center[2] = {st.get("VignetteCenterX"), st.get("VignetteCenterY")};
  const double size[2] = {st.get("VignetteSizeX"), st.get("VignetteSizeY")};
  auto f = [](double v) { return static_cast<double>(static_cast<float>(v)); };
  p.ue58_vignette_params0 = {f(st.get("VignetteIntensity")), f(color[0]), f(color[1]), f(color[2])};
  p.ue58_vignette_params1 = {f(center[0]), f(center[1]), f(1.0 / std::max(0.001, size[0])),
                             f(1.0 / std::max(0.001, size[1]))};
  p.ue58_vignette_params2 = f(st.get("VignetteSoftness"));
  // BuildCommonPermutationDomain: USE_VIGNETTE_TEXTURE = VignetteType == Texture;
  // RemapPermutation turns it off at FeatureLevel <= SM5. AddTonemapPass binds the post-process
  // settings' VignetteTexture for the Texture type, else GSystemTextures' white dummy.
  const int feature_level = static_cast<int>(st.get("FeatureLevel"));
  p.ue58_vignette_texture = p.ue58_vignette_type == 1 && feature_level > 3 ? 1 : 0;
  const VignetteTextureImage tex = vignette_texture_stimulus(
      p.ue58_vignette_type == 1 ? static_cast<int>(st.get("VignetteTexture")) : 0);
  p.ue58_vignette_tex_width = tex.width;
  p.ue58_vignette_tex_height = tex.height;
  for (size_t i = 0; i < tex.texels.size(); ++i) p.ue58_vignette_tex[i / 4][i % 4] = tex.texels[i];
  // GetTonemapperOutputDeviceParameters: InverseGamma.y = 1 for device 9 (L11).
  if (device == 9) p.inverse_gamma[1] = 1.0;
  // AddCombineLUTPass: bUseFloatOutput for the scRGB devices (L15); both LUTs share the format.
  p.lut_layout = 0;
  if (device == 5 || device == 6) p.lut_format = 1;
  p.ue58_inner_format = p.lut_format;
  p.ue58_inner_needed = (aces_method || p.output_max_luminance > 100.0) ? 1 : 0;

  // GetInnerLUTParameters: paper white and TotalSceneColorMultiplier (float, as UE).
  p.ue58_paper_white = st.get("r.HDR.PaperWhite");
  p.ue58_total_scene_color_multiplier =
      static_cast<double>(static_cast<float>(p.ue58_paper_white) / 203.f *
                          static_cast<float>(p.aces_scene_color_multiplier));

  // The ACES 1.3 parameters: GetACESTonemapParameters, HDRConfigureCVars' global set for
  // r.HDR.Display.MaxLuminance, or FACESTonemapParams' 1000-nit defaults when that is 0.
  const auto aces13 = configure_aces13(cv, max_cvar > 0.0 ? max_cvar : 1000.0, &p);

  // The limiting colour space and the white-scale flags.
  int limiting = static_cast<int>(st.get("LimitingGamut"));
  if (limiting < 0) limiting = hdr_device ? 1 : 0;
  p.ue58_limiting_gamut = limiting;
  auto wcs = working_color_space_of(st);
  if (!wcs) return wcs.error();
  const aces2::Chromaticities working = to_aces2(wcs->chroma);
  const aces2::Chromaticities& limit = gamut_chromaticities(limiting);
  const aces2::Chromaticities& output = gamut_chromaticities(p.output_gamut);
  p.ue58_scale_white = white_matches(p.output_gamut, limit) ? 0 : 1;
  p.ue58_scale_white_sdr = white_matches(p.output_gamut, working) ? 0 : 1;
  p.ue58_wcs_from_ap0 = inverse(p.wcs_to_ap0);

  // ACES 2.0: forward at OutputMaxLuminance with the limiting primaries (GetTransformResources),
  // the SDR set at 100 nits with the working colour space (GetTransformResourcesSDR).
  // The UI composite and the dither bake no LUT: their cases carry no ACES tables (nor their
  // degenerate peaks).
  const bool bakes_luts = c.stage == nullptr ||
                          (c.stage->id != StageId::kUiComposite && c.stage->id != StageId::kDither);
  if (bakes_luts && p.ue58_aces_version > 1 && p.ue58_inner_needed) {
    if (!(p.output_max_luminance >= 100.0)) {
      r.degenerate = "ACES 2.0 at OutputMaxLuminance " + std::to_string(p.output_max_luminance) +
                     " nits (the tonescale needs a peak of at least 100 nits)";
      return r;
    }
    const aces2::Params fwd = aces2::make_params(p.output_max_luminance, limit, output);
    pack_aces2_set(fwd, aces2::make_tables(fwd, limit), false, &p);
    const aces2::Params sdr = aces2::make_params(100.0, working, output);
    pack_aces2_set(sdr, aces2::make_tables(sdr, working), true, &p);
  }
  // The block holds only what a ue58 case carries (param_carried_by): UE 5.5's fields that 5.5's
  // derivation set and no ue58 shader reads (5.5's Tonemap and the user-LUT blend) go back to
  // their defaults, so params.json and the engines see the same block.
  // The dither (AddTonemapPass, 5.8 as 5.5; docs/ue58-decisions.md J1):
  // BackbufferQuantizationDithering and GrainRandomFull are 5.5's resolution above, unchanged: 0
  // for devices 8/9 (HDR_LinearNoToneCurve, HDR_LinearWithToneCurve), 1/(2^b - 1) under
  // r.BackbufferQuantizationDitheringOverride b > 0, else 1/1023, or 1/255 for an 8-bit back buffer
  // (r.DefaultBackBufferPixelFormat 0, still default 4 in 5.8's SceneTextures.cpp); the grain
  // offset (Halton(i, 2), Halton(i, 3)) of i = OutputFrameIndex mod 8 (GrainRandomFromFrame,
  // PostProcessTonemap.h).
  // The UI composite (SlateRHIRenderer.cpp: DrawWindowViewport_RenderThread): UILuminance is the
  // paper white unless r.HDR.UI.Luminance.Mode is 1, then r.HDR.UI.Luminance, whose 5.8 default is
  // 203 (the shared cvar table holds 5.5's 300: an unset cvar reads 203 here;
  // docs/ue58-decisions.md H1). Level, mode and colour deficiency are 5.5's resolution (resolve
  // above).
  if (static_cast<int>(st.get("r.HDR.UI.Luminance.Mode")) == 1)
    p.ui_luminance = cv.is_set("r.HDR.UI.Luminance") ? cv.get("r.HDR.UI.Luminance") : 203.0;
  else
    p.ui_luminance = p.ue58_paper_white;
  p.ue58_ui_eotf = static_cast<int>(st.get("r.HDR.UI.CompositeEOTF"));
  p.ue58_ui_eotf_gamma = static_cast<float>(st.get("r.HDR.UI.CompositeEOTF.Gamma"));
  p.ue58_ui_blend = static_cast<int>(st.get("r.HDR.UI.CompositeBlend"));
  const float blend_gamma = static_cast<float>(st.get("r.HDR.UI.CompositeBlend.Gamma"));
  p.ue58_ui_blend_gamma = blend_gamma;
  p.ue58_ui_blend_inv_gamma = 1.f / blend_gamma;  // the host's float division

  const ParamBlock defaults;
  for_each_param(p, [&](FieldKind, const char* name, auto& field) {
    if (!param_carried_by(name, "ue58")) {
      using T = std::decay_t<decltype(field)>;
      for_each_param(defaults, [&](FieldKind, const char* other, const auto& v) {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, T>)
          if (std::string_view(other) == name) field = v;
      });
    }
  });
  if (bakes_luts && p.ue58_aces_version == 1 && p.ue58_inner_needed && !aces13.status.ok())
    r.degenerate =
        "ACES 1.3 with degenerate tone-scale parameters: " + aces13.status.error().message;
  return r;
}

const std::vector<StageInfo>& stages() {
  static const std::vector<StageInfo> table = {
      {StageId::kOther,
       "ue58_combine_luts",
       {{"ue58/stages/combine_luts_inner.comp", Dispatch::kPixels, true},
        {"ue58/stages/combine_luts.comp", Dispatch::kLutTexels}},
       "UE 5.8 CombineLUTs: the inner LUT (r.LUT.Inner.Size^3, ACES 1.3 or 2.0 output transform "
       "indexed by PQ, or Filmic's automatic-HDR inverse then forward ACES 2.0; stored in the LUT "
       "format) sampled trilinearly by the outer bake; both tone-mapping methods, devices 0-9, "
       "gamuts 0-4; every outer texel as stored (OutDeviceColor * LUTInvMax), N^2 x N with texel "
       "(r, g, b) at (r + N b, g)",
       {0, 1, 2, 3, 4, 5, 6, 7, 8, 9},
       false,
       "ue58"},
      {StageId::kOther,
       "ue58_tonemap",
       {{"ue58/stages/combine_luts_inner.comp", Dispatch::kPixels, true},
        {"ue58/stages/combine_luts.comp", Dispatch::kLutTexels},
        {"ue58/stages/tonemap.comp"}},
       "UE 5.8 Tonemap pass (PostProcessTonemap.usf: TonemapCommonPS): fringe, sharpen, 5.8's "
       "vignette (cosine-fourth law with centre and colour; Oval), tint, exposure, bloom, then "
       "ColorLookupTable into ue58_combine_luts' LUT (r.LUT.Shaper: log or clamped PQ; x LUTMax "
       "1.05 or 1), ST2084ToLinear for device 7, scRGB written unchanged; alpha = OutLuminance",
       {0, 1, 2, 3, 4, 5, 6, 7, 8, 9},
       true,
       "ue58",
       0,
       false,
       1,
       false,
       "",
       true},
      // The Tonemap pass's last step, judged on its own as UE 5.5's (docs/ue58-decisions.md J):
      // 5.8's TonemapCommonPS adds 5.5's triangular grain to OutColor after ColorLookupTable x
      // LUTMax and device 7's ST2084ToLinear, so the input is what ue58_tonemap writes. One
      // shader: 5.5's stages/dither.comp (lib/dither.glsl), with 5.8's host values.
      {StageId::kDither,
       "ue58_dither",
       {{"stages/dither.comp"}},
       "UE 5.8's quantisation dither (PostProcessTonemap.usf: the end of TonemapCommonPS, 5.5's "
       "grain): the input is the Tonemap pass's output (ue58_tonemap's encoding: device code, "
       "scRGB for 5/6, nits for 7, linear for 8/9) plus the triangular grain x "
       "BackbufferQuantizationDithering (0 for devices 8/9); alpha passes through",
       {0, 1, 2, 3, 4, 5, 6, 7, 8, 9},
       true,
       "ue58",
       0,
       false,
       1,
       false,
       "docs/spec/ue58.md#2-quantisation-dither-postprocesstonemapusf-58"},
      {StageId::kUiComposite,
       "ue58_ui_composite",
       {{"ue58/stages/ui_composite.comp"}},
       "UE 5.8's HDR UI composite (CompositeUIPixelShader.usf): the input is the back buffer (PQ "
       "signals for devices 3/4, scRGB for 5/6), the UI is the ui_overlay stimulus of the same "
       "size; un-premultiply, the UI EOTF (gamma or sRGB), UILuminance (paper white or "
       "r.HDR.UI.Luminance), translucent UI blended in a gamma space or linearly after a "
       "Reinhard, opaque UI replacing the scene, colour deficiency, encode; alpha = the UI's",
       {3, 4, 5, 6},
       true,
       "ue58",
       0,
       false,
       1,
       false,
       "docs/spec/ue58.md#1-hdr-ui-composite-compositeuipixelshaderusf-58"},
      // VisualizeHDR is UE 5.5's pass in 5.8 (docs/ue58-differences.md §1c′, docs/ue58-decisions.md
      // K): UE 5.5's two passes (gpu/shaders/stages/visualize_*.comp) over 5.8's tonemapped scene,
      // which the Tonemap pass leaves in the scratch buffer as 5.5's visualize_hdr stage does.
      {StageId::kOther,
       "ue58_visualize_hdr",
       {{"ue58/stages/combine_luts_inner.comp", Dispatch::kPixels, true},
        {"ue58/stages/combine_luts.comp", Dispatch::kLutTexels},
        {"ue58/stages/tonemap.comp", Dispatch::kPixels, true},
        {"stages/visualize_histogram.comp", Dispatch::kOneGroup},
        {"stages/visualize_hdr.comp"}},
       "UE 5.8 VisualizeHDR (PostProcessVisualizeHDR.usf: MainPS, UE 5.5's pass on desktop): the "
       "input is the HDR scene colour; the tonemapped scene is ue58_tonemap's (without bloom), "
       "the 64-bucket histogram and the average luminance come from the reference pipeline; the "
       "printed numbers go to results.json",
       {0, 1, 2, 3, 4, 5, 6, 7, 8, 9},
       true,
       "ue58",
       0,
       false,
       1,
       false,
       "docs/spec/ue58.md#3-visualizehdr-postprocessvisualizehdrusf-58"},
  };
  return table;
}

std::array<double, 3> lattice(const ParamBlock& p, int r, int g, int b) {
  const double step = 1.0 / (p.lut_size - 1);
  return {r * step, g * step, b * step};
}

// How a stored texel becomes nits: divided by LUTInvMax (PostProcessTonemap.usf multiplies by
// LUTMax), then the device's encoding; the gamut is the output gamut, except device 8's working
// colour space and Filmic's UE-29935 shortcut (sRGB working space and output gamut: the same).
// The Tonemap pass's output is the texel · LUTMax (no pre-scale), device 7's decoded to nits.
OutputEncoding encoding(const StageInfo& stage, const ParamBlock& p) {
  // The UI composite writes the back buffer as UE 5.5's does (PQ Rec.2020 or scRGB).
  if (stage.id == StageId::kUiComposite) return ue55_pipeline().output_encoding(stage, p);
  using T = OutputEncoding::Transfer;
  // The dither adds its grain to what the Tonemap pass writes, and VisualizeHDR draws its panel in
  // the tonemapped scene's signal: the same encoding.
  const bool tonemap = stage.name == "ue58_tonemap" || stage.id == StageId::kDither ||
                       stage.name == "ue58_visualize_hdr";
  OutputEncoding e;
  e.stage = StageId::kOther;
  e.device = p.output_device;
  e.pre_scale = tonemap ? 1.0 : 1.0 / p.ue58_lut_inv_max;
  namespace sd = standard;
  const Chromaticities* gamuts[] = {&sd::kSrgb, &sd::kP3D65, &sd::kRec2020, &sd::kAp0, &sd::kAp1};
  if (p.output_device == 8) {
    e.to_rec2020 = sd::rgb_to_rgb(sd::kAp1, sd::kRec2020) * p.wcs_to_ap1;
    e.gamut = "working colour space";
  } else {
    e.to_rec2020 = sd::rgb_to_rgb(*gamuts[std::clamp(p.output_gamut, 0, 4)], sd::kRec2020);
    e.gamut = output_gamut_name(p.output_gamut);
  }
  switch (p.output_device) {
    case 0:
      if (p.ue58_sdr_inv_eotf == 0) {
        e.transfer = T::kSrgb;
        e.transfer_name = "sRGB EOTF x 100 nits";
      } else {
        e.transfer = T::kGamma;
        e.gamma = 2.4;
        e.transfer_name = "BT.1886 (gamma 2.4) x 100 nits";
      }
      e.nits_scale = 100.0;
      break;
    case 1:
      e.transfer = T::kRec709;
      e.nits_scale = 100.0;
      e.transfer_name = "Rec.709 inverse OETF x 100 nits";
      break;
    case 2:
      e.transfer = T::kGamma;
      e.gamma = 1.0 / p.inverse_gamma[2];
      e.nits_scale = 100.0;
      e.transfer_name = "gamma x 100 nits";
      break;
    case 5:
    case 6:
      e.transfer = T::kLinear;
      e.nits_scale = 80.0;
      e.transfer_name = "scRGB x 80 nits";
      break;
    case 8:
    case 9:
      e.transfer = T::kLinear;
      e.nits_scale = 100.0;
      e.transfer_name = "scene-linear x 100 nits";
      break;
    case 7:
      if (tonemap) {  // ST2084ToLinear in the pass: nits
        e.transfer = T::kLinear;
        e.nits_scale = 1.0;
        e.transfer_name = "nits";
        break;
      }
      [[fallthrough]];
    default:  // 3, 4, 7
      e.transfer = T::kPq;
      e.nits_scale = 1.0;
      e.transfer_name = "PQ EOTF";
  }
  if (e.pre_scale != 1.0) e.transfer_name = "texel x 1.05, " + e.transfer_name;
  // A NaN marks a negative value under a power-law encoding (explicit gamma, PQ of device 7).
  e.nan_marks_negative_value = p.output_device == 2 || (p.output_device == 7 && !tonemap);
  return e;
}

// The UI composite stage (ue58_ui_composite.h), with its device ranges.
Result<Image> ui_reference(const ResolvedCase& c) {
  const UiComposite58Params u = ui_composite58_params(c.params);
  auto out = composite_ui58(c.input, c.ui, u);
  if (out && c.device_allowances) {
    out->device_admissible = ui_composite58_device_ranges(u, c.input, c.ui, *out);
    out->device_allowances = {"shader arithmetic (the Vulkan precision table's bounds)"};
  }
  return out;
}

Result<Image> reference(const ResolvedCase& c, bool) {
  if (c.spec.stage->id == StageId::kUiComposite) return ui_reference(c);
  // UE 5.5's dither, written once (reference/ue/tonemap.cpp dither_image), on 5.8's values.
  if (c.spec.stage->id == StageId::kDither) return dither_image(c.params, c.input);
  const ParamBlock& p = c.params;
  const CombineLuts58 luts(p);  // one evaluator: the device ranges reuse its inner texels
  if (c.spec.stage && c.spec.stage->name == "ue58_tonemap") {
    const Image* bloom = c.bloom.data.empty() ? nullptr : &c.bloom;
    const Image* dirt = c.bloom_dirt.data.empty() ? nullptr : &c.bloom_dirt;
    if (!c.device_allowances)
      return tonemap_image(p, c.input, bloom, dirt, baked_outer_lut(luts, p));
    // What a conformant device may return (docs/ue58-decisions.md G9): the device bake's ranges
    // (E8) through the pass's lookup and post conversion as UE 5.5's pass derives them.
    const BakedLut device = baked_outer_lut_device(luts, p, c.device);
    return tonemap_image(p, c.input, bloom, dirt, device, &device, c.device.sub_texel_bits);
  }
  if (c.spec.stage && c.spec.stage->name == "ue58_visualize_hdr") {
    // UE 5.5's VisualizeHDR (visualize_hdr_over) over 5.8's Tonemap pass without bloom
    // (AddVisualizeHDRPass reads the tonemapped SceneColor and SceneColorBeforeTonemap); with
    // device allowances, the pass's ranges (G9) feed VisualizeHDR's (docs/ue58-decisions.md K).
    if (!c.device_allowances)
      return visualize_hdr_over(
          p, c.input, tonemap_image(p, c.input, nullptr, nullptr, baked_outer_lut(luts, p)), false);
    const BakedLut device = baked_outer_lut_device(luts, p, c.device);
    const Image tm =
        tonemap_image(p, c.input, nullptr, nullptr, device, &device, c.device.sub_texel_bits);
    return visualize_hdr_over(p, c.input, tm, true);
  }
  const std::vector<Vec3> lut = bake_outer_lut(luts, p);
  const int n = p.lut_size;
  Image out(n * n, n);
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) {
        double* o = out.px(r + n * b, g);
        const Vec3& t = lut[(static_cast<size_t>(b) * n + g) * n + r];
        o[0] = t[0];
        o[1] = t[1];
        o[2] = t[2];
        o[3] = 0.0;  // MainCS writes alpha 0
      }
  if (c.device_allowances) {
    // What a conformant device with the candidate's precision may store (docs/ue58-decisions.md
    // E8): both LUTs' either-way stores, the inner lookup's weight box, the arithmetic's bounds.
    const DeviceLutRanges d = bake_outer_lut_device(luts, p, c.device);
    out.device_admissible.reserve(d.lo.size());
    for (int b = 0; b < n; ++b)
      for (int g = 0; g < n; ++g)
        for (int r = 0; r < n; ++r) {
          const size_t i = (static_cast<size_t>(b) * n + g) * n + r;
          AdmissibleRange a;
          a.pixel = static_cast<size_t>(g) * out.width + r + n * b;
          for (int ch = 0; ch < 3; ++ch) {
            a.lo[ch] = d.lo[i][ch];
            a.hi[ch] = d.hi[i][ch];
          }
          a.nan_ok = d.nan[i] & 0x7;
          out.device_admissible.push_back(a);
        }
    std::sort(out.device_admissible.begin(), out.device_admissible.end(),
              [](const AdmissibleRange& x, const AdmissibleRange& y) { return x.pixel < y.pixel; });
    out.device_allowances = {"LUT storage rounding (either neighbour; inner and outer LUT)"};
    if (p.ue58_inner_needed)
      out.device_allowances.push_back("filter weights (the inner LUT's trilinear lookup, " +
                                      std::to_string(c.device.sub_texel_bits) + " sub-texel bits)");
    out.device_allowances.push_back("shader arithmetic (the Vulkan precision table's bounds)");
  }
  return out;
}

}  // namespace

const std::vector<SettingInfo>& ue58_setting_table() {
  return settings();
}

const Pipeline& ue58_pipeline() {
  static const Pipeline pipeline{
      "ue58",
      "Unreal Engine 5.8 HDR output (CombineLUTs, Tonemap, UI composite, VisualizeHDR)",
      "docs/ue58-decisions.md",
      "UE 5.8's CombineLUTs with its inner LUT: Filmic and StandardACES, ACES 1.3 and 2.0; its "
      "Tonemap pass; the HDR UI composite; VisualizeHDR (docs/ue58-differences.md, "
      "docs/ue58-decisions.md)",
      &stages,
      &cvar_table,
      &settings,
      &choices,
      &resolve58,
      &lattice,
      &encoding,
      &reference,
      0,  // bytes and CPU time per pixel: not measured (runner/budget.h takes the dearest)
      0,
      // docs/spec/ue58.md's worked pixels' rows (reference/ue/ue58/ue58_named_values.h).
      &named_values_of,
  };
  return pipeline;
}

}  // namespace hdrc::ref::ue58
