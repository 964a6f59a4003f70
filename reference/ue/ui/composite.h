// The HDR UI composite of UE 5.5 (docs/spec/ue55.md §8; docs/ue55-decisions.md D3, D8, D8a), double
// precision.
//
// Sources (izzy2lost/UnrealEngineUWP, 5.5):
//  * Engine/Shaders/Private/CompositeUIPixelShader.usf (commit 0ac46dcf): Main / CompositeUICS,
//    ComputeHDRUIColor, ComputeHDRSceneColor, ComposeUIAndScene, ApplyColorDeficiency,
//    LinearizeColor (USE_LUT_FOR_UI = 0: the ACES UI LUT is compiled out).
//  * Engine/Source/Runtime/SlateRHIRenderer/Private/SlateRHIRenderer.cpp (commit 01203093):
//    CompositeUIWithHdrRenderTarget, FSlateRHIRenderer::DrawWindow_RenderThread,
//    FCompositeShaderBase::SetParametersBase / SetColorDeficiencyParamsBase.
//
// Pipeline for r.HDR.UI.CompositeMode != 0 (per pixel, both textures point-sampled at the centre):
//   UI    (premultiplied, sRGB-encoded RGB as Slate wrote it into UITargetRT, linear alpha)
//         → sRGBToLinear → sRGB→Rec2020 (literal product) → × UILuminance      [nits, Rec2020]
//   scene (back-buffer code: PQ for devices other than 5/6, scRGB for 5/6)
//         → PQ: ST2084ToLinear; scRGB: sRGB→Rec2020 · scene · 80                [nits, Rec2020]
//   ComposeUIAndScene (Reinhard under translucent UI, premultiplied over) → ApplyColorDeficiency
//   → PQ: LinearToST2084; scRGB: Rec2020→sRGB · (x / 80); alpha = 1.
//
// r.HDR.UI.CompositeMode = 0 ("0: Standard compositing"): CompositeUIWithHdrRenderTarget() is
// false, so no UI target and no composite shader exist. DrawWindow_RenderThread draws the Slate
// batches straight into the back buffer with bIsHDR = true, which makes RenderSlateBatch call
// SetUseGammaCorrection(false) (DisplayGamma 1.0 in FSlateRHIRenderingPolicy::DrawElements). The
// back buffer then holds the UI blended by the fixed-function blender in the back buffer's own
// code values: out = ui.rgb + (1 − ui.a) · scene (premultiplied "over"; Slate's non-premultiplied
// SrcAlpha/InvSrcAlpha batches accumulate to the same result). No linearisation, no nits, no
// Reinhard: on a PQ back buffer a UI value of 1.0 is PQ code 1.0 (10000 nits), on scRGB 1.0 is
// 80 nits. This reference models mode 0 that way: PQ (UNORM10 swap chain) clamps blender inputs
// and output to [0, 1] (NaN → 0, D3D UNORM rules); scRGB (FP16) does not clamp. Slate's own
// per-element gamma step (SlateElementPixelShader.usf: GammaCorrect, which only acts for
// SOURCE_IN_LINEAR_SPACE shaders) differs between the modes (2.2 into UITargetRT for mode 1,
// 1.0 for mode 0); that is upstream of this stage: a case supplies the UI layer as Slate wrote it
// for the mode it tests. Colour-vision deficiency in mode 0 goes through Slate's own post-process
// path (not modelled): validate() rejects mode 0 with an active deficiency.
#pragma once

#include <array>

#include "color/gamma_correction.h"
#include "color/vec.h"
#include "core/image.h"
#include "core/result.h"
#include "reference/ue/ui/color_deficiency.h"

namespace hdrc::ref::ui {

using Vec4 = std::array<double, 4>;  // RGBA

// The back buffer the composite reads and writes (the SCRGB_ENCODING permutation).
enum class BackBufferEncoding { kPq, kScRgb };

// GSlateColorDeficiency* globals (set by SetColorVisionDeficiencyType). UE passes them to the
// shader as floats: type and severity cast from their integers, the flags as 1.0 / 0.0.
struct CvdSettings {
  CvdType type = CvdType::kNormalVision;
  int severity = 0;                              // 0..10
  bool correct = false;                          // bCorrectDeficiency
  bool show_correction_with_deficiency = false;  // bSimulateCorrectionWithDeficiency
};

struct UiCompositeParams {
  double ui_level = 1.0;        // r.HDR.UI.Level (UILevel), multiplies the composed UI
  double ui_luminance = 300.0;  // r.HDR.UI.Luminance (UILuminance), nits of UI white
  int composite_mode = 1;       // r.HDR.UI.CompositeMode: 0 standard blending, else the shader
  // The viewport's EDisplayOutputFormat (FViewportInfo::HDRDisplayOutputFormat from
  // HDRGetMetaData, not the cvar): 5/6 select scRGB, every other value PQ (D8a).
  int output_device = 3;
  CvdSettings cvd;
  // LinearizeColor's USE_709 branch (Rec709ToLinear instead of sRGBToLinear). 5.5's
  // FCompositePS/FCompositeCS::ModifyCompilationEnvironment never define USE_709, so UE always
  // takes the sRGB branch; the switch exists to test the branch, default off.
  bool use_709 = false;
  MinNormalClamp min_normal_clamp = kDefaultMinNormalClamp;  // D3, default on
};

inline constexpr double kScRgbScaleFactor = 80.0;  // ScRGBScaleFactor: nits at scRGB 1.0
// ComposeUIAndScene's Rec.2020 luma weights KR, KG, KB (BT.2020 Table 4 rounded as UE writes).
inline constexpr Vec3 kRec2020LumaWeights{0.2627, 0.678, 0.0593};

// Checks the parameters the reference cannot evaluate: non-finite level or luminance, a CVD type
// outside 0..3 or severity outside 0..10, an output device outside 0..9 (EDisplayOutputFormat),
// and mode 0 with an active deficiency.
Status validate(const UiCompositeParams& p);

// SCRGB_ENCODING: scRGB iff the viewport device is HDR_ACES_1000nit_ScRGB (5) or
// HDR_ACES_2000nit_ScRGB (6), PQ otherwise (SlateRHIRenderer.cpp: bUseScRGB).
BackBufferEncoding back_buffer_encoding(int output_device);

// APPLY_COLOR_DEFICIENCY: type != NormalVision && severity > 0 (bApplyColorDeficiencyFilter).
bool color_deficiency_active(const CvdSettings& cvd);

// The shader's constant products of UE's literal matrices (ACES.ush), evaluated in double.
const Mat3& srgb_to_rec2020();  // mul(XYZ_2_Rec2020_MAT, sRGB_2_XYZ_MAT)
const Mat3& rec2020_to_srgb();  // mul(XYZ_2_sRGB_MAT, Rec2020_2_XYZ_MAT)

// LinearizeColor: sRGBToLinear, or Rec709ToLinear when p.use_709 (each with p.min_normal_clamp).
Vec3 linearize_ui_color(const Vec3& encoded, const UiCompositeParams& p);

// ComputeHDRUIColor: rgb → srgb_to_rec2020 · LinearizeColor(rgb) · UILuminance (nits, Rec.2020,
// still premultiplied); alpha passes unchanged.
Vec4 compute_hdr_ui_color(const Vec4& ui, const UiCompositeParams& p);

// ComputeHDRSceneColor: back-buffer code → nits in Rec.2020 primaries. PQ: ST2084ToLinear (the
// back buffer's own gamut, Rec.2020 for devices 3/4); scRGB: srgb_to_rec2020 · scene · 80.
Vec3 compute_hdr_scene_color(const Vec3& scene, BackBufferEncoding encoding);

// ComposeUIAndScene's Reinhard under translucent UI (the part UE 5.8's linear blend keeps, shared
// with reference/ue/ue58/ue58_ui_composite.cpp): scene = max(scene, 0);
// L = dot(scene, kRec2020LumaWeights) / level; scene *= lerp(1, level / (L + 1), a).
Vec3 reinhard_under_ui(Vec3 scene, double a, double ui_level);

// ComposeUIAndScene(scene, ui, level), nits in and out. Only when 0 < ui.a < 1 (NaN alpha fails
// the test): scene = max(scene, 0); L = dot(scene, kRec2020LumaWeights) / level;
// scene *= lerp(1, level / (L + 1), ui.a). Always: scene · (1 − ui.a) + ui.rgb · level.
// max(scene, 0) is maxNum, so a NaN scene channel becomes 0 under translucent UI; under opaque UI
// scene · 0 keeps NaN/Inf as NaN, as IEEE hardware does.
Vec3 compose_ui_and_scene(Vec3 scene, const Vec4& ui, double ui_level);

// ApplyColorDeficiency: when color_deficiency_active(cvd), rec2020 → rec2020_to_srgb →
// color_deficiency() → srgb_to_rec2020; otherwise the permutation is compiled out and the colour
// passes unchanged (bit-exact).
Vec3 apply_color_deficiency(const Vec3& rec2020, const CvdSettings& cvd);

// The composite's output encode: PQ: LinearToST2084 per channel (no clamp: a negative channel,
// possible after the CVD matrices, gives NaN as on the GPU); scRGB: rec2020_to_srgb · (x / 80).
Vec3 encode_output(const Vec3& rec2020_nits, BackBufferEncoding encoding);

// Intermediate values of composite_pixel for mode != 0 (nits, Rec.2020 unless noted).
struct UiCompositeTrace {
  Vec4 ui{};         // ComputeHDRUIColor
  Vec3 scene{};      // ComputeHDRSceneColor
  Vec3 composed{};   // ComposeUIAndScene
  Vec3 after_cvd{};  // ApplyColorDeficiency
  Vec4 output{};     // back-buffer code, alpha 1
};

// r.HDR.UI.CompositeMode 0: Slate's fixed-function premultiplied blend into the back buffer's
// code values (documented at the top; UE 5.8 unchanged: CompositeUIWithSceneHDR() is false).
Vec4 standard_blend(const Vec4& scene, const Vec4& ui, BackBufferEncoding encoding);

// One back-buffer pixel after the UI pass. `scene` is the back-buffer code (alpha used only by
// mode 0's blend), `ui` the premultiplied UI texel. Mode != 0: the shader (alpha out = 1);
// mode 0: standard blending as documented at the top. `trace` is filled for mode != 0 only.
// Precondition: validate(p) is ok.
Vec4 composite_pixel(const Vec4& scene, const Vec4& ui, const UiCompositeParams& p,
                     UiCompositeTrace* trace = nullptr);

// The UI layer and the back buffer have the same size (an error naming both sizes if not): UE
// 5.5's and 5.8's composite alike.
Status check_ui_size(const Image& scene, const Image& ui);

// composite_pixel over whole images of equal size: `scene` back-buffer encoded, `ui` the
// premultiplied UI layer. Errors: invalid parameters (validate) or different image sizes.
Result<Image> composite_ui(const Image& scene, const Image& ui, const UiCompositeParams& p);

}  // namespace hdrc::ref::ui
