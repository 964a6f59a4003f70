// UE's fields of the shader interface (core/shader_interface.h HDRC_PARAM_BLOCK): the UE 5.5
// pipeline's parameters, and the fields every pipeline's shaders read (image size, LUT geometry,
// aux image sizes, the case's user LUT). A header of the interface floor: macros only, included by
// core/shader_interface.h and by nothing it depends on.
#pragma once

#define HDRC_UE55_PARAMS(X)                                                                       \
  X(I, width, "image width in pixels")                                                            \
  X(I, height, "image height in pixels")                                                          \
  X(I, output_device, "EDisplayOutputFormat after cvar resolution (0-9)")                         \
  X(I, output_gamut, "EDisplayColorGamut after cvar resolution (0-4)")                            \
  X(I, lut_size, "r.LUT.Size: LUT edge N")                                                        \
  X(I, lut_format,                                                                                \
    "LUT storage: 0 A2B10G10R10 UNORM, 1 RGBA16F, 2 RGBA32F, 3 RGBA8 UNORM (unity_urp LDR)")      \
  X(I, lut_layout, "LUT layout: 0 volume N^3, 1 2-D unwrapped N^2 x N")                           \
  X(I, wcs_is_srgb, "WorkingColorSpace.bIsSRGB")                                                  \
  X(I, white_balance_enabled, "0 when SKIP_TEMPERATURE (6500 K and tint 0)")                      \
  X(I, frame_index, "OutputFrameIndex mod 8 (dither Halton index)")                               \
  X(I, ui_composite_mode, "r.HDR.UI.CompositeMode")                                               \
  X(I, cvd_type, "colour vision deficiency: 0 normal, 1 deuteranope, 2 protanope, 3 tritanope")   \
  X(I, cvd_severity, "colour vision deficiency severity 0-10")                                    \
  X(I, cvd_correct, "daltonise (correct) instead of simulate")                                    \
  X(I, cvd_show_correction, "simulate the deficiency on the corrected image")                     \
  X(I, visualize_debug_type, "r.EyeAdaptation.VisualizeDebugType")                                \
  X(I, aux0_width, "width of the aux0 image (bloom / UI layer); set by the engine that binds it") \
  X(I, aux0_height, "height of the aux0 image")                                                   \
  X(I, aux1_width, "width of the aux1 image (bloom dirt mask); set by the engine")                \
  X(I, aux1_height, "height of the aux1 image")                                                   \
  X(F, output_max_luminance, "OutputMaxLuminance, nits (resolved r.HDR.Display.MaxLuminance)")    \
  X(F, expand_gamut, "ExpandGamut")                                                               \
  X(F, blue_correction, "BlueCorrection")                                                         \
  X(F, tone_curve_amount, "ToneCurveAmount")                                                      \
  X(F, film_slope, "FilmSlope")                                                                   \
  X(F, film_toe, "FilmToe")                                                                       \
  X(F, film_shoulder, "FilmShoulder")                                                             \
  X(F, film_black_clip, "FilmBlackClip")                                                          \
  X(F, film_white_clip, "FilmWhiteClip")                                                          \
  X(F, cc_shadows_max, "ColorCorrectionShadowsMax")                                               \
  X(F, cc_highlights_min, "ColorCorrectionHighlightsMin")                                         \
  X(F, cc_highlights_max, "ColorCorrectionHighlightsMax")                                         \
  X(F, aces_coefs_low_4, "ACESCoefsLow_4")                                                        \
  X(F, aces_coefs_high_4, "ACESCoefsHigh_4")                                                      \
  X(F, aces_scene_color_multiplier, "ACESSceneColorMultiplier")                                   \
  X(F, aces_gamut_compression, "ACESGamutCompression, clamped to [0, 1]")                         \
  X(F, exposure, "OneOverPreExposure * GlobalExposure")                                           \
  X(F, pre_exposure, "View.PreExposure")                                                          \
  X(F, vignette_intensity, "TonemapperParams.x")                                                  \
  X(F, sharpen_div6, "Sharpen / 6")                                                               \
  X(F, dither_amount, "BackbufferQuantizationDithering")                                          \
  X(F, ui_level, "r.HDR.UI.Level")                                                                \
  X(F, ui_luminance, "r.HDR.UI.Luminance, nits")                                                  \
  X(V4, inverse_gamma, "InverseGamma (1/DisplayGamma, 2.2/DisplayGamma, 1/max(Gamma,1), 0)")      \
  X(V4, mapping_polynomial, "r.Color.* polynomial (a, b, c, 0)")                                  \
  X(V4, color_scale, "View.ColorScale")                                                           \
  X(V4, overlay_color, "View.OverlayColor")                                                       \
  X(V4, scene_color_tint, "SceneColorTint")                                                       \
  X(V4, bloom_dirt_tint, "BloomDirtMaskTint * intensity / BloomIntensity")                        \
  X(V4, grain_random, "(Halton(i, 2), Halton(i, 3), 0, 0): dither grain offset")                  \
  X(V4, fringe, "(CAScale R, CAScale G, StartOffset, enabled)")                                   \
  X(V4, aces_min_max, "ACESMinMaxData")                                                           \
  X(V4, aces_mid, "ACESMidData")                                                                  \
  X(V4, aces_coefs_low_0, "ACESCoefsLow_0")                                                       \
  X(V4, aces_coefs_high_0, "ACESCoefsHigh_0")                                                     \
  X(V4, cc_saturation, "ColorSaturation")                                                         \
  X(V4, cc_contrast, "ColorContrast")                                                             \
  X(V4, cc_gamma, "ColorGamma")                                                                   \
  X(V4, cc_gain, "ColorGain")                                                                     \
  X(V4, cc_offset, "ColorOffset")                                                                 \
  X(V4, cc_saturation_shadows, "ColorSaturationShadows")                                          \
  X(V4, cc_contrast_shadows, "ColorContrastShadows")                                              \
  X(V4, cc_gamma_shadows, "ColorGammaShadows")                                                    \
  X(V4, cc_gain_shadows, "ColorGainShadows")                                                      \
  X(V4, cc_offset_shadows, "ColorOffsetShadows")                                                  \
  X(V4, cc_saturation_midtones, "ColorSaturationMidtones")                                        \
  X(V4, cc_contrast_midtones, "ColorContrastMidtones")                                            \
  X(V4, cc_gamma_midtones, "ColorGammaMidtones")                                                  \
  X(V4, cc_gain_midtones, "ColorGainMidtones")                                                    \
  X(V4, cc_offset_midtones, "ColorOffsetMidtones")                                                \
  X(V4, cc_saturation_highlights, "ColorSaturationHighlights")                                    \
  X(V4, cc_contrast_highlights, "ColorContrastHighlights")                                        \
  X(V4, cc_gamma_highlights, "ColorGammaHighlights")                                              \
  X(V4, cc_gain_highlights, "ColorGainHighlights")                                                \
  X(V4, cc_offset_highlights, "ColorOffsetHighlights")                                            \
  X(M3, wcs_to_ap1, "WorkingColorSpace.ToAP1, float as UE's CPU builds it")                       \
  X(M3, wcs_from_ap1, "WorkingColorSpace.FromAP1: inverse of the float ToAP1")                    \
  X(M3, wcs_to_ap0, "WorkingColorSpace.ToAP0")                                                    \
  X(M3, wcs_to_xyz,                                                                               \
    "WorkingColorSpace.ToXYZ (working RGB to CIE XYZ), float as UE's CPU builds it")              \
  X(M3, wcs_from_xyz,                                                                             \
    "WorkingColorSpace.FromXYZ (CIE XYZ to working RGB), float as UE's CPU builds it")            \
  X(M3, white_balance, "FromXYZ * CA(src, dst) * ToXYZ (identity when skipped)")                  \
  X(M3, ap1_to_output, "OuputGamutMappingMatrix(output_gamut), product of UE's literals")         \
  X(I, lut_blend_count, "BLENDCOUNT: 1 + the user LUTs blended (GenerateFinalTable; 1: none)")    \
  X(F, lut_weight_4, "LUTWeights[4]: the weight of user_lut[3] (Textures_4)")                     \
  X(V4, lut_weights, "LUTWeights[0..3]: the neutral weight, then user_lut[0..2] (Textures_1..3)") \
  HDRC_USER_LUT_PARAMS(X)

// The case's user LUT (a .cube file the case names, docs/cases.md), bound at kBindingUserLut: set
// from the case by the loader for every pipeline, so they sit with the fields every pipeline's
// shaders read (owner "ue55" in param_owner).
#define HDRC_USER_LUT_PARAMS(X)                                                                   \
  X(I, user_lut_size, "the case's user LUT: LUT_3D_SIZE N of its .cube; 0 when it names none")    \
  X(V4, user_lut_domain_min, "its DOMAIN_MIN (r, g, b, 0): the input of the first lattice point") \
  X(V4, user_lut_domain_max, "its DOMAIN_MAX (r, g, b, 0): the input of the last lattice point")
