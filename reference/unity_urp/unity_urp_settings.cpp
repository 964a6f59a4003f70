#include "reference/unity_urp/unity_urp_settings.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace hdrc {

namespace {

constexpr Vec4d s(double v) {
  return {v, 0, 0, 0};
}
// Vector4Parameter(new Vector4(1f, 1f, 1f, 0f)): the trackballs' default.
constexpr Vec4d kTrackball{1, 1, 1, 0};
// Color.white / Color.grey (UnityEngine.Color).
constexpr Vec4d kWhite{1, 1, 1, 1};
constexpr Vec4d kGrey{0.5, 0.5, 0.5, 1};

}  // namespace

const std::vector<SettingInfo>& unity_urp_setting_table() {
  // Runtime/Overrides/*.cs (URP 17 / Unity 6; the same defaults since URP 7): every parameter the
  // SDR colour grading reads. ClampedFloatParameter ranges are Unity's; for the unbounded types
  // (FloatParameter, MinFloatParameter, Vector4Parameter, HDR ColorParameter) the range is this
  // suite's and says why.
  static const std::vector<SettingInfo> table = {
      // UniversalRenderPipelineAsset (the effective mode: HDR only when the asset supports HDR).
      {"GradingMode", 1, s(0), 0, 1,
       "UniversalRenderPipelineAsset.colorGradingMode: LowDynamicRange (default) or "
       "HighDynamicRange: urp_grading_mode, lut_format"},
      {"LutSize", 1, s(32), 16, 65,
       "UniversalRenderPipelineAsset.colorGradingLutSize (clamped to [16, 65]): lut_size, "
       "urp_lut_params"},
      // Tonemapping.cs: VolumeParameter<TonemappingMode>(TonemappingMode.None).
      {"Tonemapping.mode", 1, s(0), 0, 2,
       "TonemappingMode None / Neutral / ACES: baked into the LUT (HDR grading) or applied before "
       "it (LDR grading): urp_tonemap_mode"},
      // WhiteBalance.cs: ClampedFloatParameter(0, -100, 100).
      {"WhiteBalance.temperature", 1, s(0), -100, 100,
       "ColorBalanceToLMSCoeffs: urp_color_balance"},
      {"WhiteBalance.tint", 1, s(0), -100, 100, "ColorBalanceToLMSCoeffs: urp_color_balance"},
      // ColorAdjustments.cs.
      {"ColorAdjustments.postExposure", 1, s(0), -100, 100,
       "EV (FloatParameter, unbounded in C#; +-100 keeps 2^EV finite in float32): "
       "urp_post_exposure"},
      {"ColorAdjustments.contrast", 1, s(0), -100, 100, "urp_hue_sat_con.z = contrast/100 + 1"},
      {"ColorAdjustments.colorFilter", 4, kWhite, 0, 1000,
       "HDR colour (ColorParameter(white, hdr: true, showAlpha: false)), r g b a: "
       "urp_color_filter = colorFilter.linear"},
      {"ColorAdjustments.hueShift", 1, s(0), -180, 180, "urp_hue_sat_con.x = hueShift/360"},
      {"ColorAdjustments.saturation", 1, s(0), -100, 100, "urp_hue_sat_con.y = saturation/100 + 1"},
      // SplitToning.cs: ColorParameter(Color.grey, false, false, true) and balance (0, -100, 100).
      {"SplitToning.shadows", 4, kGrey, 0, 1,
       "LDR colour, r g b a, kept in gamma space: urp_split_shadows.xyz"},
      {"SplitToning.highlights", 4, kGrey, 0, 1,
       "LDR colour, r g b a, kept in gamma space: urp_split_highlights.xyz"},
      {"SplitToning.balance", 1, s(0), -100, 100, "urp_split_shadows.w = balance/100"},
      // ChannelMixer.cs: ClampedFloatParameter(100 on the diagonal else 0, -200, 200).
      {"ChannelMixer.redOutRedIn", 1, s(100), -200, 200, "urp_channel_mixer_red.x"},
      {"ChannelMixer.redOutGreenIn", 1, s(0), -200, 200, "urp_channel_mixer_red.y"},
      {"ChannelMixer.redOutBlueIn", 1, s(0), -200, 200, "urp_channel_mixer_red.z"},
      {"ChannelMixer.greenOutRedIn", 1, s(0), -200, 200, "urp_channel_mixer_green.x"},
      {"ChannelMixer.greenOutGreenIn", 1, s(100), -200, 200, "urp_channel_mixer_green.y"},
      {"ChannelMixer.greenOutBlueIn", 1, s(0), -200, 200, "urp_channel_mixer_green.z"},
      {"ChannelMixer.blueOutRedIn", 1, s(0), -200, 200, "urp_channel_mixer_blue.x"},
      {"ChannelMixer.blueOutGreenIn", 1, s(0), -200, 200, "urp_channel_mixer_blue.y"},
      {"ChannelMixer.blueOutBlueIn", 1, s(100), -200, 200, "urp_channel_mixer_blue.z"},
      // ShadowsMidtonesHighlights.cs: Vector4Parameter((1, 1, 1, 0)) trackballs (unbounded in C#;
      // the editor's trackball gives rgb in [0, 1] and an offset slider w, docs/spec/unity_urp.md
      // §8 [U]: this suite
      // admits [-1, 2] per component) and MinFloatParameter limits (>= 0).
      {"ShadowsMidtonesHighlights.shadows", 4, kTrackball, -1, 2,
       "trackball (rgb, w offset): PrepareShadowsMidtonesHighlights: urp_shadows"},
      {"ShadowsMidtonesHighlights.midtones", 4, kTrackball, -1, 2,
       "trackball (rgb, w offset): PrepareShadowsMidtonesHighlights: urp_midtones"},
      {"ShadowsMidtonesHighlights.highlights", 4, kTrackball, -1, 2,
       "trackball (rgb, w offset): PrepareShadowsMidtonesHighlights: urp_highlights"},
      {"ShadowsMidtonesHighlights.shadowsStart", 1, s(0), 0, 1000, "urp_sha_hi_limits.x"},
      {"ShadowsMidtonesHighlights.shadowsEnd", 1, s(0.3), 0, 1000, "urp_sha_hi_limits.y"},
      {"ShadowsMidtonesHighlights.highlightsStart", 1, s(0.55), 0, 1000, "urp_sha_hi_limits.z"},
      {"ShadowsMidtonesHighlights.highlightsEnd", 1, s(1), 0, 1000, "urp_sha_hi_limits.w"},
      // LiftGammaGain.cs: Vector4Parameter((1, 1, 1, 0)) trackballs (as above).
      {"LiftGammaGain.lift", 4, kTrackball, -1, 2,
       "trackball (rgb, w offset): PrepareLiftGammaGain: urp_lift"},
      {"LiftGammaGain.gamma", 4, kTrackball, -1, 2,
       "trackball (rgb, w offset): PrepareLiftGammaGain: urp_gamma"},
      {"LiftGammaGain.gain", 4, kTrackball, -1, 2,
       "trackball (rgb, w offset): PrepareLiftGammaGain: urp_gain"},
  };
  return table;
}

const std::vector<SettingChoice>* unity_urp_setting_choices(std::string_view setting) {
  // ColorGradingMode and TonemappingMode enumerator names and values (URP Runtime).
  static const std::vector<SettingChoice> grading = {{"LowDynamicRange", 0},
                                                     {"HighDynamicRange", 1}};
  static const std::vector<SettingChoice> tonemapping = {{"None", 0}, {"Neutral", 1}, {"ACES", 2}};
  // colorGradingLutSize: an int, clamped to [16, 65] (UniversalRenderPipelineAsset: k_MinLutSize,
  // k_MaxLutSize); each integer is a named value so a fractional size is refused.
  static const std::vector<std::string> size_names = [] {
    std::vector<std::string> n;
    for (int i = 16; i <= 65; ++i) n.push_back(std::to_string(i));
    return n;
  }();
  static const std::vector<SettingChoice> sizes = [] {
    std::vector<SettingChoice> c;
    for (int i = 16; i <= 65; ++i) c.push_back({size_names[i - 16], static_cast<double>(i)});
    return c;
  }();
  if (setting == "GradingMode") return &grading;
  if (setting == "Tonemapping.mode") return &tonemapping;
  if (setting == "LutSize") return &sizes;
  return nullptr;
}

namespace ref::unity_urp {

float gamma_to_linear_space(float c) {
  // Mathf.GammaToLinearSpace (native; believed to be UnityCG.cginc GammaToLinearSpaceExact with
  // c^2.2 from 1, docs/spec/unity_urp.md §1 [U]).
  if (c <= 0.04045f) return c / 12.92f;
  if (c < 1.0f) return std::pow((c + 0.055f) / 1.055f, 2.4f);
  return std::pow(c, 2.2f);
}

namespace {

// ColorUtils.StandardIlluminantY: 2.87f * x - 3f * x * x - 0.27509507f.
float standard_illuminant_y(float x) {
  return 2.87f * x - 3.0f * x * x - 0.27509507f;
}

// ColorUtils.CIExyToLMS (CAT02 rows 0.7328 0.4296 -0.1624 / -0.7036 1.6975 0.0061 / 0.0030
// 0.0136 0.9834).
std::array<float, 3> cie_xy_to_lms(float x, float y) {
  const float big_y = 1.0f;
  const float big_x = big_y * x / y;
  const float big_z = big_y * (1.0f - x - y) / y;
  const float l = 0.7328f * big_x + 0.4296f * big_y - 0.1624f * big_z;
  const float m = -0.7036f * big_x + 1.6975f * big_y + 0.0061f * big_z;
  const float s = 0.0030f * big_x + 0.0136f * big_y + 0.9834f * big_z;
  return {l, m, s};
}

// ColorUtils.Luminance(Color): r * 0.2126729f + g * 0.7151522f + b * 0.072175f.
float luminance(const Float4& c) {
  return c[0] * 0.2126729f + c[1] * 0.7151522f + c[2] * 0.072175f;
}

}  // namespace

std::array<float, 3> color_balance_to_lms_coeffs(float temperature, float tint) {
  // ColorUtils.ColorBalanceToLMSCoeffs.
  const float t1 = temperature / 65.0f;
  const float t2 = tint / 65.0f;
  const float x = 0.31271f - t1 * (t1 < 0.0f ? 0.1f : 0.05f);
  const float y = standard_illuminant_y(x) + t2 * 0.05f;
  const std::array<float, 3> w1 = {0.949237f, 1.03542f, 1.08728f};  // D65 white point in LMS
  const std::array<float, 3> w2 = cie_xy_to_lms(x, y);
  return {w1[0] / w2[0], w1[1] / w2[1], w1[2] / w2[2]};
}

Float4 prepare_shadows_midtones_highlights(const Float4& in) {
  // ColorUtils.PrepareShadowsMidtonesHighlights (one vector): xyz linearised, weight = w * (Sign(w)
  // < 0 ? 1 : 4) with Mathf.Sign(0) = +1, xyz = max(xyz + weight, 0), w = 0.
  Float4 v = in;
  for (int i = 0; i < 3; ++i) v[i] = gamma_to_linear_space(v[i]);
  const float sign_w = v[3] >= 0.0f ? 1.0f : -1.0f;  // Mathf.Sign
  const float weight = v[3] * (sign_w < 0.0f ? 1.0f : 4.0f);
  for (int i = 0; i < 3; ++i) v[i] = std::max(v[i] + weight, 0.0f);
  v[3] = 0.0f;
  return v;
}

LiftGammaGain prepare_lift_gamma_gain(const Float4& in_lift, const Float4& in_gamma,
                                      const Float4& in_gain) {
  // ColorUtils.PrepareLiftGammaGain.
  LiftGammaGain out;
  Float4 lift = in_lift;
  for (int i = 0; i < 3; ++i) lift[i] = gamma_to_linear_space(lift[i]) * 0.15f;
  const float lum_lift = luminance(lift);
  for (int i = 0; i < 3; ++i) lift[i] = lift[i] - lum_lift + lift[3];
  lift[3] = 0.0f;
  out.lift = lift;

  Float4 gamma = in_gamma;
  for (int i = 0; i < 3; ++i) gamma[i] = gamma_to_linear_space(gamma[i]) * 0.8f;
  const float lum_gamma = luminance(gamma);
  gamma[3] += 1.0f;
  for (int i = 0; i < 3; ++i) gamma[i] = 1.0f / std::max(gamma[i] - lum_gamma + gamma[3], 1e-03f);
  gamma[3] = 0.0f;
  out.gamma = gamma;

  Float4 gain = in_gain;
  for (int i = 0; i < 3; ++i) gain[i] = gamma_to_linear_space(gain[i]) * 0.8f;
  const float lum_gain = luminance(gain);
  gain[3] += 1.0f;
  for (int i = 0; i < 3; ++i) gain[i] = gain[i] - lum_gain + gain[3];
  gain[3] = 0.0f;
  out.gain = gain;
  return out;
}

}  // namespace ref::unity_urp

namespace {

using ref::unity_urp::Float4;

float get_f(const SettingValues& s, std::string_view name) {
  return static_cast<float>(s.get(name));
}

Float4 get_f4(const SettingValues& s, std::string_view name) {
  const Vec4d v = s.get4(name);
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]),
          static_cast<float>(v[3])};
}

std::array<double, 4> widen(const Float4& v) {
  return {v[0], v[1], v[2], v[3]};
}

}  // namespace

void derive_unity_urp(const SettingValues& s, ParamBlock* p) {
  namespace urp = ref::unity_urp;
  // The asset: grading mode, LUT size; ColorGradingLutPass.ConfigureDescriptor: H x H^2,
  // R16G16B16A16_SFloat (HDR, its first choice) or R8G8B8A8_UNorm (LDR).
  const bool hdr = s.get("GradingMode") == 1.0;
  const int h = static_cast<int>(s.get("LutSize"));
  p->urp_grading_mode = hdr ? 1 : 0;
  p->urp_tonemap_mode = static_cast<int32_t>(s.get("Tonemapping.mode"));
  p->lut_size = h;
  p->lut_layout = 1;
  p->lut_format = hdr ? 1 : 3;

  // PostProcessPass.SetupColorGrading / UberPostProcessPass: postExposureLinear =
  // Mathf.Pow(2f, postExposure) (Math.Pow in double, rounded to float); _Lut_Params =
  // (1f / lutWidth, 1f / lutHeight, lutHeight - 1f, postExposureLinear).
  const float post_exposure = static_cast<float>(
      std::pow(2.0, static_cast<double>(get_f(s, "ColorAdjustments.postExposure"))));
  p->urp_post_exposure = post_exposure;
  const int w = h * h;
  p->urp_lut_params = {1.0f / static_cast<float>(w), 1.0f / static_cast<float>(h),
                       static_cast<float>(h) - 1.0f, 0.0};

  // ColorGradingLutPass.ExecutePass.
  const auto lms = urp::color_balance_to_lms_coeffs(get_f(s, "WhiteBalance.temperature"),
                                                    get_f(s, "WhiteBalance.tint"));
  p->urp_color_balance = {lms[0], lms[1], lms[2], 0.0};
  const Float4 filter = get_f4(s, "ColorAdjustments.colorFilter");
  // colorAdjustments.colorFilter.value.linear: GammaToLinearSpace on r, g, b; alpha kept.
  p->urp_color_filter = {urp::gamma_to_linear_space(filter[0]),
                         urp::gamma_to_linear_space(filter[1]),
                         urp::gamma_to_linear_space(filter[2]), filter[3]};
  p->urp_hue_sat_con = {get_f(s, "ColorAdjustments.hueShift") / 360.0f,
                        get_f(s, "ColorAdjustments.saturation") / 100.0f + 1.0f,
                        get_f(s, "ColorAdjustments.contrast") / 100.0f + 1.0f, 0.0};
  auto mixer = [&](const char* r, const char* g, const char* b) {
    return std::array<double, 4>{get_f(s, r) / 100.0f, get_f(s, g) / 100.0f, get_f(s, b) / 100.0f,
                                 0.0};
  };
  p->urp_channel_mixer_red =
      mixer("ChannelMixer.redOutRedIn", "ChannelMixer.redOutGreenIn", "ChannelMixer.redOutBlueIn");
  p->urp_channel_mixer_green = mixer("ChannelMixer.greenOutRedIn", "ChannelMixer.greenOutGreenIn",
                                     "ChannelMixer.greenOutBlueIn");
  p->urp_channel_mixer_blue = mixer("ChannelMixer.blueOutRedIn", "ChannelMixer.blueOutGreenIn",
                                    "ChannelMixer.blueOutBlueIn");
  p->urp_sha_hi_limits = {get_f(s, "ShadowsMidtonesHighlights.shadowsStart"),
                          get_f(s, "ShadowsMidtonesHighlights.shadowsEnd"),
                          get_f(s, "ShadowsMidtonesHighlights.highlightsStart"),
                          get_f(s, "ShadowsMidtonesHighlights.highlightsEnd")};
  p->urp_shadows = widen(
      urp::prepare_shadows_midtones_highlights(get_f4(s, "ShadowsMidtonesHighlights.shadows")));
  p->urp_midtones = widen(
      urp::prepare_shadows_midtones_highlights(get_f4(s, "ShadowsMidtonesHighlights.midtones")));
  p->urp_highlights = widen(
      urp::prepare_shadows_midtones_highlights(get_f4(s, "ShadowsMidtonesHighlights.highlights")));
  const urp::LiftGammaGain lgg = urp::prepare_lift_gamma_gain(get_f4(s, "LiftGammaGain.lift"),
                                                              get_f4(s, "LiftGammaGain.gamma"),
                                                              get_f4(s, "LiftGammaGain.gain"));
  p->urp_lift = widen(lgg.lift);
  p->urp_gamma = widen(lgg.gamma);
  p->urp_gain = widen(lgg.gain);
  // ColorUtils.PrepareSplitToning: colours unchanged (gamma space), shadows.w = balance / 100f,
  // highlights.w = 0.
  Float4 split_shadows = get_f4(s, "SplitToning.shadows");
  Float4 split_highlights = get_f4(s, "SplitToning.highlights");
  split_shadows[3] = get_f(s, "SplitToning.balance") / 100.0f;
  split_highlights[3] = 0.0f;
  p->urp_split_shadows = widen(split_shadows);
  p->urp_split_highlights = widen(split_highlights);
}

}  // namespace hdrc
