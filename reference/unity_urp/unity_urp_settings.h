// The `unity_urp` pipeline's settings: the volume parameters of URP's colour grading overrides
// (Runtime/Overrides/*.cs: WhiteBalance, ColorAdjustments, SplitToning, ChannelMixer,
// ShadowsMidtonesHighlights, LiftGammaGain, Tonemapping) under Unity's names
// ("Component.parameter"), with Unity's defaults and ranges, plus the two pipeline-asset settings
// that shape the LUT (UniversalRenderPipelineAsset: colorGradingMode, colorGradingLutSize), and
// the host derivation that turns them into the shader constants as the C# does
// (ColorGradingLutPass.ExecutePass, UberPostProcessPass / PostProcessPass.SetupColorGrading,
// ColorUtils.*), in float32 where the C# is float. Spec: docs/spec/unity_urp.md §1.
#pragma once

#include <array>
#include <string_view>
#include <vector>

#include "core/settings.h"
#include "core/shader_interface.h"

namespace hdrc {

// The settings table (names, defaults, ranges per component, what each feeds).
const std::vector<SettingInfo>& unity_urp_setting_table();
// Named values: GradingMode (LowDynamicRange 0, HighDynamicRange 1), Tonemapping.mode (None 0,
// Neutral 1, ACES 2), LutSize (every integer 16-65, named by its digits: Unity clamps the asset's
// colorGradingLutSize to [16, 65], not to powers of two). nullptr for other settings.
const std::vector<SettingChoice>* unity_urp_setting_choices(std::string_view setting);

// Fills the urp_* fields and lut_size / lut_format / lut_layout of `p` from `s` (whose table is
// unity_urp_setting_table()); other fields are left alone. lut_layout = 1 (the H^2 x H strip);
// lut_format = 1 (RGBA16F) for HDR grading, 3 (RGBA8 UNORM) for LDR grading
// (ColorGradingLutPass: m_HdrLutFormat's first choice, m_LdrLutFormat).
void derive_unity_urp(const SettingValues& s, ParamBlock* p);

namespace ref::unity_urp {

// The host-side helpers of ColorUtils.cs and Mathf, in float32 as the C# evaluates them.
// Mathf.GammaToLinearSpace (native; docs/spec/unity_urp.md §1 [U]): c ≤ 0.04045: c/12.92; c < 1:
// ((c + 0.055)/ 1.055)^2.4; otherwise c^2.2.
float gamma_to_linear_space(float c);
// ColorUtils.ColorBalanceToLMSCoeffs(temperature, tint).
std::array<float, 3> color_balance_to_lms_coeffs(float temperature, float tint);
using Float4 = std::array<float, 4>;
// ColorUtils.PrepareShadowsMidtonesHighlights for one trackball vector.
Float4 prepare_shadows_midtones_highlights(const Float4& v);
// ColorUtils.PrepareLiftGammaGain: lift, gamma (reciprocal exponent) and gain.
struct LiftGammaGain {
  Float4 lift, gamma, gain;
};
LiftGammaGain prepare_lift_gamma_gain(const Float4& lift, const Float4& gamma, const Float4& gain);

}  // namespace ref::unity_urp
}  // namespace hdrc
