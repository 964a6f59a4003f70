// UE 5.8's HDR UI composite (issue 26; docs/ue58-differences.md §1c U1-U5, docs/ue58-decisions.md
// G), double precision. What 5.8 shares with 5.5 is UE 5.5's code (reference/ue/ui/composite.h):
// the back-buffer decode (ComputeHDRSceneColor), the Reinhard under translucent UI, the colour
// deficiency, the output encode and r.HDR.UI.CompositeMode 0's fixed-function blend.
//
// Sources (unicorn2022/UE5.8.0, commit 5d9a05c1):
//  * Engine/Shaders/Private/CompositeUIPixelShader.usf: Main / CompositeUICS, ComputeHDRUIColor
//    (un-premultiply: rgb / a for a > 0, else 0; then LinearizeColor; sRGB_2_Rec2020 ·
//    UILuminance), LinearizeColor (UICompositeEOTF 0: pow(x, UICompositeEOTFGamma); else
//    sRGBToLinear), ComposeUIAndScene (a > 0: UI · UILevel; a < 1: UICompositeBlend != 0 linear:
//    Reinhard then lerp(scene, UI, a); 0 gamma: pow(saturate(x / UE_PQ_WHITE_NITS),
//    UICompositeBlendInvGamma), lerp, pow(·, UICompositeBlendGamma) · UE_PQ_WHITE_NITS; a >= 1:
//    the UI replaces the scene; a <= 0: the scene), ApplyColorDeficiency, OutColor.w = UIColor.w.
//  * Engine/Source/Runtime/SlateRHIRenderer/Private/SlateRHIRenderer.cpp: the cvars
//    (r.HDR.UI.Level 1, r.HDR.UI.Luminance 203, r.HDR.UI.Luminance.Mode 0,
//    r.HDR.UI.CompositeEOTF 0, r.HDR.UI.CompositeEOTF.Gamma 2.4, r.HDR.UI.CompositeBlend 0,
//    r.HDR.UI.CompositeBlend.Gamma 2.4, r.HDR.UI.CompositeMode 1) and
//    FSlateRHIRenderer::DrawWindowViewport_RenderThread (FCompositeShaderCommonParameters:
//    UILuminance = Luminance.Mode ? r.HDR.UI.Luminance : HDRMetaData.HDRPaperWhiteInNits;
//    UICompositeBlendInvGamma = 1.f / UICompositeBlendGamma; SCRGB_ENCODING for output devices
//    5/6; APPLY_COLOR_DEFICIENCY as 5.5).
//  * Engine/Shaders/Private/GammaCorrectionCommon.ush: sRGBToLinear without 5.5's min-normal clamp
//    (docs/ue58-differences.md L16), UE_PQ_WHITE_NITS 10000, UE_SCRGB_WHITE_NITS 80.
#pragma once

#include "color/vec.h"
#include "core/image.h"
#include "core/result.h"
#include "core/shader_interface.h"
#include "reference/ue/ui/composite.h"

namespace hdrc::ref::ue58 {

inline constexpr double kPqWhiteNits = 10000.0;  // UE_PQ_WHITE_NITS (GammaCorrectionCommon.ush)

// The composite's parameters: UE 5.5's (level, UILuminance as resolved, mode, device, CVD; its
// use_709 and min_normal_clamp are unused here) and 5.8's.
struct UiComposite58Params {
  ui::UiCompositeParams common;
  int eotf = 0;              // UICompositeEOTF: 0 pow(x, eotf_gamma), 1 sRGBToLinear
  double eotf_gamma = 2.4;   // UICompositeEOTFGamma
  int blend = 0;             // UICompositeBlend: 0 gamma-space blend, else linear
  double blend_gamma = 2.4;  // UICompositeBlendGamma
  // UICompositeBlendInvGamma: 1.f / UICompositeBlendGamma, computed by the host in float.
  double blend_inv_gamma = 1.0 / 2.4;
};

// The parameters from a resolved ue58 parameter block.
UiComposite58Params ui_composite58_params(const ParamBlock& p);

// UE 5.5's checks (ui::validate) and the 5.8 ones: EOTF and blend selectors 0/1, gammas finite
// and positive.
Status validate(const UiComposite58Params& p);

// The steps of one pixel through the shader, as computed (docs/spec/ue58.md §1's worked pixels;
// reference/ue/ue58/ue58_named_values.h names them).
struct UiComposite58Trace {
  // ComputeHDRUIColor: the UI colour un-premultiplied, then LinearizeColor's value.
  Vec3 unpremultiplied{};
  Vec3 linearized{};
  // ComposeUIAndScene's branch: the scene unchanged (a <= 0 or NaN), the UI replacing it (a >= 1),
  // the gamma-space or the linear blend (0 < a < 1).
  enum class Compose { kScene, kOpaque, kGamma, kLinear } compose = Compose::kScene;
  Vec3 ui_levelled{};  // UI.rgb · UILevel (a > 0)
  // Gamma blend: g(Scene), g(UI) (g(x) = pow(saturate(x / 10000), UICompositeBlendInvGamma)) and
  // lerp(g(Scene), g(UI), a) before pow(·, UICompositeBlendGamma) · 10000.
  Vec3 blend_scene{}, blend_ui{}, blend_lerp{};
  Vec3 reinhard{};            // linear blend: the scene after 5.5's Reinhard under the UI
  ui::UiCompositeTrace pass;  // UI in nits, scene in nits, composed, after CVD, output
};

// ComputeHDRUIColor: un-premultiply (a > 0: rgb / a, else 0), LinearizeColor, sRGB_2_Rec2020 ·
// UILuminance; alpha unchanged. Nits, Rec.2020, no longer premultiplied. `trace`: the
// un-premultiplied and linearized colours.
ui::Vec4 compute_hdr_ui_color58(const ui::Vec4& ui, const UiComposite58Params& p,
                                UiComposite58Trace* trace = nullptr);

// ComposeUIAndScene of 5.8 over nits (the UI from compute_hdr_ui_color58). `trace`: the branch
// taken and its steps.
Vec3 compose_ui_and_scene58(Vec3 scene, ui::Vec4 ui, const UiComposite58Params& p,
                            UiComposite58Trace* trace = nullptr);

// One back-buffer pixel after the UI pass: mode != 0 the shader (alpha = the UI's alpha), mode 0
// Slate's blend (ui::standard_blend). `trace` is filled for mode != 0 only (alpha of `output` as
// written). Precondition: validate(p) is ok.
ui::Vec4 composite_pixel58(const ui::Vec4& scene, const ui::Vec4& ui, const UiComposite58Params& p,
                           ui::UiCompositeTrace* trace = nullptr);
// The same with every step of the shader (mode != 0 only).
ui::Vec4 composite_pixel58(const ui::Vec4& scene, const ui::Vec4& ui, const UiComposite58Params& p,
                           UiComposite58Trace* trace);

// composite_pixel58 over whole images of equal size. Errors: invalid parameters, different sizes.
Result<Image> composite_ui58(const Image& scene, const Image& ui, const UiComposite58Params& p);

// The device ranges (docs/precision.md, "Device allowances") of the composite's output image:
// UE 5.5's scheme (reference/ue/ue_pixel_device.h ui_composite_device_ranges) with 5.8's compose.
std::vector<AdmissibleRange> ui_composite58_device_ranges(const UiComposite58Params& p,
                                                          const Image& scene, const Image& ui,
                                                          const Image& reference);

}  // namespace hdrc::ref::ue58
