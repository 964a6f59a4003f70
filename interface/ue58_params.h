// The `ue58` pipeline's part of the shader parameter block (core/shader_interface.h appends it to
// HDRC_PARAM_BLOCK): X(type, name, meaning), types I = int32, F = float32, V4 = vec4, M3 = 3x3
// matrix, V4A(n) = n vec4. Every field is prefixed `ue58_`; derive_ue58 (reference/ue/ue58/
// ue58_resolve.cpp) fills them as UE 5.8's C++ does (PostProcessCombineLUTs.cpp:
// GetInnerLUTParameters, GetTonemappingMethod, GetTonemappingMax; ACESUtils.cpp: the tables).
// The grading controls, matrices and ACES 1.3 parameters are UE 5.5's fields (identical meaning in
// 5.8, docs/ue58-differences.md §1e): HDRC_UE58_SHARED_PARAMS lists the ones CombineLUTs reads.
#pragma once

// UE 5.5's fields that 5.8's CombineLUTs reads with the same meaning (PostProcessCombineLUTs.usf,
// PostProcessCombineLUTsInner.usf; docs/ue58-differences.md §1e), exactly those the ue58 shaders
// read: image and LUT geometry, the working colour space, white balance, fake wide gamut,
// ColorCorrectAll, the film path (blue correction, FilmToneMap, r.Color.*, fade), the ACES 1.3
// parameters (r.HDR.Aces.Version 1) and the output gamut matrix. No user-LUT blend fields: the
// stage takes no user LUT (docs/ue58-decisions.md E5). output_max_luminance is the display's peak
// (docs/ue58-differences.md L12); inverse_gamma.y is 1 for device 9 (L11). The Tonemap pass
// (ue58_tonemap) reads the aux image sizes (bloom, dirt mask), exposure, sharpen, SceneColorTint,
// the dirt tint and the colour fringe with 5.5's meaning (docs/ue58-differences.md T4); its
// vignette and LUT scale are 5.8's own fields below (T2, T3). lut_layout (0: 5.8 bakes a volume
// only) and 5.5's vignette_intensity are read by the shared GLSL the pass includes
// (tonemap_variant.glsl, tonemap_effects.glsl: 5.5's tonemap_vignette, which 5.8 does not call).
// The UI composite's (CompositeUIPixelShader.usf) level, mode and colour-deficiency fields are
// 5.5's; ui_luminance holds 5.8's UILuminance as resolved (r.HDR.UI.Luminance.Mode: paper white
// or the cvar, U1). The dither stage (ue58_dither, 5.5's shader stages/dither.comp) reads 5.5's
// dither_amount (BackbufferQuantizationDithering) and grain_random (GrainRandomFull), which 5.8's
// AddTonemapPass sets by 5.5's rules (docs/ue58-decisions.md J).
// VisualizeHDR (ue58_visualize_hdr, 5.5's pass: docs/ue58-differences.md §1c′)
// reads pre_exposure (View.OneOverPreExposure), visualize_debug_type, exposure and the film fields.
#define HDRC_UE58_SHARED_PARAMS(Y) \
  Y(width)                         \
  Y(height)                        \
  Y(output_device)                 \
  Y(output_gamut)                  \
  Y(lut_size)                      \
  Y(lut_format)                    \
  Y(wcs_is_srgb)                   \
  Y(white_balance_enabled)         \
  Y(output_max_luminance)          \
  Y(expand_gamut)                  \
  Y(blue_correction)               \
  Y(tone_curve_amount)             \
  Y(film_slope)                    \
  Y(film_toe)                      \
  Y(film_shoulder)                 \
  Y(film_black_clip)               \
  Y(film_white_clip)               \
  Y(cc_shadows_max)                \
  Y(cc_highlights_min)             \
  Y(cc_highlights_max)             \
  Y(aces_coefs_low_4)              \
  Y(aces_coefs_high_4)             \
  Y(aces_scene_color_multiplier)   \
  Y(aces_gamut_compression)        \
  Y(inverse_gamma)                 \
  Y(mapping_polynomial)            \
  Y(color_scale)                   \
  Y(overlay_color)                 \
  Y(aces_min_max)                  \
  Y(aces_mid)                      \
  Y(aces_coefs_low_0)              \
  Y(aces_coefs_high_0)             \
  Y(cc_saturation)                 \
  Y(cc_contrast)                   \
  Y(cc_gamma)                      \
  Y(cc_gain)                       \
  Y(cc_offset)                     \
  Y(cc_saturation_shadows)         \
  Y(cc_contrast_shadows)           \
  Y(cc_gamma_shadows)              \
  Y(cc_gain_shadows)               \
  Y(cc_offset_shadows)             \
  Y(cc_saturation_midtones)        \
  Y(cc_contrast_midtones)          \
  Y(cc_gamma_midtones)             \
  Y(cc_gain_midtones)              \
  Y(cc_offset_midtones)            \
  Y(cc_saturation_highlights)      \
  Y(cc_contrast_highlights)        \
  Y(cc_gamma_highlights)           \
  Y(cc_gain_highlights)            \
  Y(cc_offset_highlights)          \
  Y(wcs_to_ap1)                    \
  Y(wcs_from_ap1)                  \
  Y(wcs_to_ap0)                    \
  Y(white_balance)                 \
  Y(ap1_to_output)                 \
  Y(aux0_width)                    \
  Y(aux0_height)                   \
  Y(aux1_width)                    \
  Y(aux1_height)                   \
  Y(exposure)                      \
  Y(pre_exposure)                  \
  Y(visualize_debug_type)          \
  Y(sharpen_div6)                  \
  Y(scene_color_tint)              \
  Y(bloom_dirt_tint)               \
  Y(fringe)                        \
  Y(lut_layout)                    \
  Y(vignette_intensity)            \
  Y(ui_composite_mode)             \
  Y(ui_level)                      \
  Y(ui_luminance)                  \
  Y(cvd_type)                      \
  Y(cvd_severity)                  \
  Y(cvd_correct)                   \
  Y(cvd_show_correction)           \
  Y(dither_amount)                 \
  Y(grain_random)

// The ACES 2.0 parameter block (reference/ue/aces2/aces2.h ParamsT: init_ODTParams' values, 76
// scalars = 19 vec4 in ParamsT's std430 order) and the three host tables UE binds as R32F
// textures read with Load (ACESUtils.cpp), texel for texel: reach M 360 x 1 (texel i at
// [i/4][i%4]), gamut cusp 3 x 362 (row r = vec4(J, M, h, 0) at [r]), upper-hull gamma 362 x 1
// (texel i at [i/4][i%4], two unused components at the end).
#define HDRC_UE58_ACES2_SET(X, suffix, what)                                                      \
  X(V4A(19), ue58_aces2_params##suffix, what ": init_ODTParams / init_TSParams (ParamsT)")        \
  X(V4A(90), ue58_reach_table##suffix, what ": ACES_ReachMTable, texel i at [i/4][i%4]")          \
  X(V4A(362), ue58_cusp_table##suffix, what ": ACES_GamutCuspTable, row r = (J, M, h, 0) at [r]") \
  X(V4A(91), ue58_gamma_table##suffix, what ": ACES_UpperHullGammaTable, texel i at [i/4][i%4]")

#define HDRC_UE58_PARAMS(X)                                                                        \
  X(I, ue58_tonemapping_method,                                                                    \
    "0 Filmic, 1 StandardACES (PostProcessCombineLUTs.cpp: GetTonemappingMethod)")                 \
  X(I, ue58_aces_version, "r.HDR.Aces.Version: 1 ACES 1.3, 2 ACES 2.0 (USE_ACES_2 = version > 1)") \
  X(I, ue58_sdr_inv_eotf, "TonemappingSDRInvEOTF: 0 sRGB, 1 BT.1886 (gamma 2.4)")                  \
  X(I, ue58_lut_shaper, "r.LUT.Shaper: 0 log lattice, 1 PQ lattice (LUTShaper)")                   \
  X(I, ue58_inner_lut_size, "r.LUT.Inner.Size: the inner LUT's edge (InnerLUTSize)")               \
  X(I, ue58_inner_needed,                                                                          \
    "1 when the inner LUT is baked: StandardACES, or Filmic with OutputMaxLuminance > 100")        \
  X(I, ue58_inner_format, "inner LUT storage: 0 A2B10G10R10 UNORM, 1 RGBA16F (float LUT)")         \
  X(I, ue58_limiting_gamut, "the display's limiting colour space, EDisplayColorGamut 0-4")         \
  X(I, ue58_scale_white, "bScaleWhite: output and limiting white points differ")                   \
  X(I, ue58_scale_white_sdr, "bScaleWhiteSDR: output and working white points differ")             \
  X(F, ue58_lut_inv_max, "LUTInvMax: 1/1.05 (Filmic, devices 0, 1, 9) or 1 (GetTonemappingMax)")   \
  X(F, ue58_paper_white, "paper white, nits (r.HDR.PaperWhite)")                                   \
  X(F, ue58_total_scene_color_multiplier,                                                          \
    "TotalSceneColorMultiplier = PaperWhite / 203 * ACESSceneColorMultiplier")                     \
  X(M3, ue58_wcs_from_ap0, "WorkingColorSpace.FromAP0 (ACESInvOutputTransform)")                   \
  X(F, ue58_lut_max, "LUTMax: 1.05 (Filmic, devices 0, 1, 9) or 1 (GetTonemappingMax), Tonemap")   \
  X(I, ue58_vignette_type, "VignetteType: 0 CosineFourthLaw, 1 Texture, 2 Oval (EVignetteType)")   \
  X(V4, ue58_vignette_params0, "VignetteParams0: (VignetteIntensity, VignetteColor.rgb)")          \
  X(V4, ue58_vignette_params1, "VignetteParams1: (VignetteCenter, 1 / max(0.001, VignetteSize))")  \
  X(F, ue58_vignette_params2, "VignetteParams2: VignetteSoftness")                                 \
  X(I, ue58_vignette_texture,                                                                      \
    "USE_VIGNETTE_TEXTURE after RemapPermutation: 1 VignetteType Texture at feature level SM6")    \
  X(I, ue58_vignette_tex_width, "VignetteTexture's width in texels (1: UE's white dummy)")         \
  X(I, ue58_vignette_tex_height, "VignetteTexture's height in texels (1: UE's white dummy)")       \
  X(V4A(64), ue58_vignette_tex,                                                                    \
    "VignetteTexture's red channel (UNORM8, k/255), texel i (row-major, row 0 at V 0) at "         \
    "[i/4][i%4]")                                                                                  \
  X(I, ue58_ui_eotf, "UICompositeEOTF: 0 pow(x, UICompositeEOTFGamma), 1 sRGBToLinear")            \
  X(F, ue58_ui_eotf_gamma, "UICompositeEOTFGamma (r.HDR.UI.CompositeEOTF.Gamma)")                  \
  X(I, ue58_ui_blend, "UICompositeBlend: 0 gamma-space blend, 1 linear (Reinhard, lerp)")          \
  X(F, ue58_ui_blend_gamma, "UICompositeBlendGamma (r.HDR.UI.CompositeBlend.Gamma)")               \
  X(F, ue58_ui_blend_inv_gamma, "UICompositeBlendInvGamma = 1.f / UICompositeBlendGamma (host)")   \
  HDRC_UE58_ACES2_SET(X, , "forward ACES 2.0 at OutputMaxLuminance, limiting primaries")           \
  HDRC_UE58_ACES2_SET(X, _sdr, "SDR inverse ACES 2.0 at 100 nits, working primaries")
