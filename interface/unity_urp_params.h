// The `unity_urp` pipeline's part of the shader parameter block (core/shader_interface.h appends
// it to HDRC_PARAM_BLOCK): X(type, name, meaning), types I = int32, F = float32, V4 = vec4,
// M3 = 3x3 matrix. Every field is prefixed `urp_`; these are the shader constants Unity's C#
// (ColorGradingLutPass / UberPostProcessPass) derives from the volume settings, computed once on
// the host; the reference reads them from ParamBlock and the shaders from the generated block `P`.
//
// derive_unity_urp (reference/unity_urp/unity_urp_settings.h) fills them in float32, as the C#
// does (docs/spec/unity_urp.md §1). The LUT geometry reuses the common fields: lut_size = H (the
// strip is H^2 x H, texel (r + H b, g)), lut_layout = 1 (that unwrapped strip), lut_format = 1
// (RGBA16F, HDR grading) or 3 (RGBA8 UNORM, LDR grading).
#pragma once

// The fields of UE 5.5's part of the block that this pipeline reads: the image size and the LUT
// geometry (lut_size, lut_format, lut_layout, as above). A case of this pipeline carries these and
// its own urp_* fields, nothing else of UE's (param_carried_by, core/shader_interface.h).
#define HDRC_UNITY_URP_SHARED_PARAMS(Y) Y(width) Y(height) Y(lut_size) Y(lut_format) Y(lut_layout)

#define HDRC_UNITY_URP_PARAMS(X)                                                                   \
  X(I, urp_grading_mode, "ColorGradingMode: 0 LowDynamicRange, 1 HighDynamicRange")                \
  X(I, urp_tonemap_mode, "TonemappingMode: 0 None, 1 Neutral, 2 ACES")                             \
  X(F, urp_post_exposure, "2^ColorAdjustments.postExposure (UberPost _Lut_Params.w)")              \
  X(V4, urp_lut_params, "UberPost _Lut_Params without w: (1/W, 1/H, H - 1, 0), W = H^2")           \
  X(V4, urp_color_balance, "_ColorBalance: ColorBalanceToLMSCoeffs(temperature, tint), w 0")       \
  X(V4, urp_color_filter, "_ColorFilter: colorFilter.linear (rgb), alpha in w")                    \
  X(V4, urp_hue_sat_con, "_HueSatCon: (hueShift/360, saturation/100 + 1, contrast/100 + 1, 0)")    \
  X(V4, urp_channel_mixer_red, "_ChannelMixerRed: (redOutRedIn, redOutGreenIn, redOutBlueIn)/100") \
  X(V4, urp_channel_mixer_green, "_ChannelMixerGreen: greenOut{Red,Green,Blue}In / 100")           \
  X(V4, urp_channel_mixer_blue, "_ChannelMixerBlue: blueOut{Red,Green,Blue}In / 100")              \
  X(V4, urp_lift, "_Lift: PrepareLiftGammaGain lift (added after gain)")                           \
  X(V4, urp_gamma, "_Gamma: PrepareLiftGammaGain gamma (the exponent, already reciprocal)")        \
  X(V4, urp_gain, "_Gain: PrepareLiftGammaGain gain")                                              \
  X(V4, urp_shadows, "_Shadows: PrepareShadowsMidtonesHighlights shadows")                         \
  X(V4, urp_midtones, "_Midtones: PrepareShadowsMidtonesHighlights midtones")                      \
  X(V4, urp_highlights, "_Highlights: PrepareShadowsMidtonesHighlights highlights")                \
  X(V4, urp_sha_hi_limits, "_ShaHiLimits: (shadowsStart, shadowsEnd, highlightsStart, End)")       \
  X(V4, urp_split_shadows, "_SplitShadows: shadows colour (gamma space), w = balance/100")         \
  X(V4, urp_split_highlights, "_SplitHighlights: highlights colour (gamma space), w 0")
