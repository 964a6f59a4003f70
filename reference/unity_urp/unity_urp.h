// Unity URP colour grading in double precision: the internal LUT bake (LutBuilderHdr /
// LutBuilderLdr) and its application in the uber pass (Common.hlsl: ApplyColorGrading), SDR path.
// Formulas: docs/spec/unity_urp.md §1-§6; every constant and formula cites the Unity file and
// function it comes from (Unity-Technologies/Graphics, Packages/com.unity.render-pipelines.*).
//
// Scope and decisions:
//  * Desktop semantics: URP's `half`/`real` are fp32 on desktop D3D/Vulkan/GL
//  (docs/spec/unity_urp.md §7.2), so no
//    fp16 arithmetic is modelled; the shader constants are the float32 values derive_unity_urp
//    computes (held exactly in the doubles of ParamBlock) and the HLSL literals are used as
//    written.
//  * Curves (ColorCurves) at their defaults only (docs/spec/unity_urp.md §4): the secondary curves
//  (hue/sat/lum vs
//    sat, hue vs hue) are flat 0.5 textures, so satMult = (2 · 0.5)^3 = 1 and the hue offset is 0;
//    the YRGB identity curves, baked to 128 texels holding i/128 and sampled bilinearly with clamp
//    addressing at t + 1/256 (texel index 128 t), reduce to clamp(t, 0, 127/128). A non-default
//    curve needs Unity's AnimationCurve (Hermite keys, weights) and fp16 texel storage, which are
//    out of scope. The bilinear filter of the curve textures is taken as exact (real GPUs quantise
//    the weight, commonly to 8 bits: up to 2^-16 in t for the identity curve;
//    docs/spec/unity_urp.md §7.4).
//  * No user LUT (ColorLookup), no HDR output (docs/spec/unity_urp.md §2.7): out of scope.
//  * Mathf.GammaToLinearSpace is taken as sRGB below 1 and c^2.2 from 1 (docs/spec/unity_urp.md §1,
//  [U]).
#pragma once

#include <array>
#include <functional>

#include "color/vec.h"
#include "core/device_precision.h"
#include "core/image.h"
#include "core/shader_interface.h"
#include "reference/color/noise_range.h"
#include "reference/named_values.h"

namespace hdrc::ref::unity_urp {

// ---------------------------------------------------------------------------------------------
// Enumerations as the parameter block carries them.

// UniversalRenderPipelineAsset.colorGradingMode (ColorGradingMode).
enum class GradingMode { kLowDynamicRange = 0, kHighDynamicRange = 1 };
// Tonemapping.mode (TonemappingMode); HDR grading bakes it into the LUT, LDR grading applies it in
// the uber pass before the lookup.
enum class TonemapMode { kNone = 0, kNeutral = 1, kAces = 2 };

// ---------------------------------------------------------------------------------------------
// ALEXA LogC3 (Color.hlsl: ParamsLogC / LogC, "Alexa LogC converters (El 1000)").

struct LogCParams {
  double cut, a, b, c, d, e, f;
};
// Color.hlsl: `static const ParamsLogC LogC`, ARRI LogC3 EI 1000 as Unity writes it.
inline constexpr LogCParams kUnityLogC = {0.011361, 5.555556, 0.047996, 0.244161,
                                          0.386036, 5.301883, 0.092819};
// ARRI, "ALEXA Log C Curve - Usage in VFX" (2017), table of LogC3 parameters, EI 800 row
// (for the published 18 % grey code 0.391007; Unity does not use it).
inline constexpr LogCParams kArriLogC3Ei800 = {0.010591, 5.555556, 0.052272, 0.247190,
                                               0.385537, 5.367655, 0.092809};

// Color.hlsl: LinearToLogC with USE_PRECISE_LOGC = 0: c·log10(max(a·x + b, 0)) + d everywhere
// (cut, e and f unused); −Inf where a·x + b ≤ 0.
double logc_from_linear(double x, const LogCParams& k = kUnityLogC);
// Color.hlsl: LogCToLinear (fast form): (10^((x − d)/c) − b)/a.
double linear_from_logc(double x, const LogCParams& k = kUnityLogC);
// Color.hlsl: LinearToLogC_Precise / ARRI's piecewise curve: e·x + f at or below cut.
double logc_from_linear_precise(double x, const LogCParams& k);
Vec3 logc_from_linear(const Vec3& x, const LogCParams& k = kUnityLogC);
Vec3 linear_from_logc(const Vec3& x, const LogCParams& k = kUnityLogC);

// ---------------------------------------------------------------------------------------------
// ACES helpers (ACES.hlsl).

inline constexpr double kAcesccMidgray = 0.4135884;  // ACES.hlsl: ACEScc_MIDGRAY
inline constexpr double kHalfMax = 65504.0;          // Common.hlsl: HALF_MAX
// ACES.hlsl: ACES_to_ACEScc(half3), the vector form the grade uses: x clamped to [0, HALF_MAX],
// (log2(0.00001525878 + x/2) + 9.72)/17.52 below 0.00003051757, else (log2 x + 9.72)/17.52.
double acescc_from_linear(double x);
// ACES.hlsl: ACEScc_to_ACES(half): (2^(17.52 y − 9.72) − 2^-16)·2 below −0.3013698630,
// 2^(17.52 y − 9.72) below (log2 HALF_MAX + 9.72)/17.52, else HALF_MAX.
double linear_from_acescc(double y);

// ACES.hlsl matrices (row-major as written there; out = M · in). All `half3x3`: fp32 on desktop.
inline constexpr Mat3 kSrgbToAp0{{0.4397010, 0.3829780, 0.1773350,  //
                                  0.0897923, 0.8134230, 0.0967616,  //
                                  0.0175440, 0.1115440, 0.8707040}};
inline constexpr Mat3 kAp0ToAp1{{1.4514393161, -0.2365107469, -0.2149285693,  //
                                 -0.0765537734, 1.1762296998, -0.0996759264,  //
                                 0.0083161484, -0.0060324498, 0.9977163014}};
inline constexpr Mat3 kAp1ToAp0{{0.6954522414, 0.1406786965, 0.1638690622,  //
                                 0.0447945634, 0.8596711185, 0.0955343182,  //
                                 -0.0055258826, 0.0040252103, 1.0015006723}};
inline constexpr Mat3 kAp1ToXyz{{0.6624541811, 0.1340042065, 0.1561876870,  //
                                 0.2722287168, 0.6740817658, 0.0536895174,  //
                                 -0.0055746495, 0.0040607335, 1.0103391003}};
inline constexpr Mat3 kXyzToAp1{{1.6410233797, -0.3248032942, -0.2364246952,  //
                                 -0.6636628587, 1.6153315917, 0.0167563477,   //
                                 0.0117218943, -0.0082844420, 0.9883948585}};
inline constexpr Mat3 kXyzToRec709{{3.2409699419, -1.5373831776, -0.4986107603,  //
                                    -0.9692436363, 1.8759675015, 0.0415550574,   //
                                    0.0556300797, -0.2039769589, 1.0569715142}};
inline constexpr Mat3 kD60ToD65Cat{{0.98722400, -0.00611327, 0.0159533,  //
                                    -0.00759836, 1.00186000, 0.0053302,  //
                                    0.00307257, -0.00509595, 1.0816800}};
// ACES.hlsl: AP1_RGB2Y.
inline constexpr Vec3 kAp1RgbToY = {0.272229, 0.674082, 0.0536895};

// Color.hlsl: LinearToLMS (LIN_2_LMS_MAT) and LMSToLinear (LMS_2_LIN_MAT), explicitly float.
inline constexpr Mat3 kLinearToLms{{3.90405e-1, 5.49941e-1, 8.92632e-3,  //
                                    7.08416e-2, 9.63172e-1, 1.35775e-3,  //
                                    2.31082e-2, 1.28021e-1, 9.36245e-1}};
inline constexpr Mat3 kLmsToLinear{{2.85847e+0, -1.62879e+0, -2.48910e-2,  //
                                    -2.10182e-1, 1.15820e+0, 3.24281e-4,   //
                                    -4.18120e-2, -1.18169e-1, 1.06867e+0}};
// Color.hlsl: Luminance (Rec.709 weights as Unity writes them).
inline constexpr Vec3 kRec709RgbToY = {0.2126729, 0.7151522, 0.0721750};

double luminance_rec709(const Vec3& c);  // Color.hlsl: Luminance
double luminance_ap1(const Vec3& c);     // Color.hlsl: AcesLuminance

// ---------------------------------------------------------------------------------------------
// Colour utilities (Color.hlsl).

// RgbToHsv: the branch-free form with HLSL step(a, x) = (x >= a) deciding the ties, and its
// ε = 1e-4 (so not exactly invertible). Returns (h in [0, 1], s, v).
Vec3 hsv_from_rgb(const Vec3& c);
// HsvToRgb: v · lerp(1, saturate(|frac(h + K)·6 − 3| − 1), s), K = (1, 2/3, 1/3).
Vec3 rgb_from_hsv(const Vec3& hsv);
// RotateHue(value, low, hi): one wrap by hi (hi = 1 in the grade).
double rotate_hue(double value, double low, double hi);
// SoftLight(base, blend), per channel: blend ≥ 0.5 (step) → √base·(2 blend − 1) + 2 base (1 −
// blend), else 2 base blend + base² (1 − 2 blend).
double soft_light(double base, double blend);

// ---------------------------------------------------------------------------------------------
// Tone mapping (docs/spec/unity_urp.md §2.6).

// Color.hlsl: NeutralTonemap, per channel through the shared operator
// (reference/operators/operators.h: operators::unity_neutral, which clamps negatives to 0).
Vec3 neutral_tonemap(const Vec3& x);
// Color.hlsl: AcesTonemap with TONEMAPPING_USE_FULL_ACES = 0 (the fitted RRT + ODT): input
// ACES2065-1 (AP0 linear), output linear Rec.709, not clamped.
Vec3 aces_tonemap(const Vec3& aces);
// LutBuilderHdr.shader: Tonemap. `graded` is ColorGrade's output: linear sRGB for None/Neutral,
// ACEScg for ACES (moved to AP0 with AP1_2_AP0_MAT here). Not clamped.
Vec3 hdr_bake_tonemap(const Vec3& graded, TonemapMode mode);
// Common.hlsl: ApplyTonemap (the LDR-grading uber pass): ACES on sRGB_2_AP0 · x, Neutral, or
// nothing, then saturate.
Vec3 uber_tonemap(const Vec3& x, TonemapMode mode);

// ---------------------------------------------------------------------------------------------
// The grade (docs/spec/unity_urp.md §2.3 HDR `ColorGrade`, §3 LDR `FragLutBuilderLdr`), as the
// steps the shaders run. `aces`: the HDR bake with _TONEMAP_ACES (ACES grading spaces, AP1
// luminance). Each step is public so tests can compose a variant of the grade with one step
// changed.

GradingMode grading_mode(const ParamBlock& p);
TonemapMode tonemap_mode(const ParamBlock& p);
// True when the HDR bake grades in ACES spaces (HDR grading with ACES tone mapping).
bool grades_in_aces(const ParamBlock& p);

// Step 2: white balance in LMS: LMSToLinear(_ColorBalance ⊙ LinearToLMS(c)).
Vec3 white_balance(const Vec3& c, const ParamBlock& p);
// Step 3: contrast about ACEScc_MIDGRAY in LogC (or in ACEScc of sRGB_2_AP0 · c when `aces`,
// returning ACEScg: AP0_2_AP1 · ACEScc_to_ACES).
Vec3 contrast(const Vec3& c, const ParamBlock& p, bool aces, const LogCParams& k = kUnityLogC);
// Steps 4-5: c ⊙ _ColorFilter, then max(c, 0).
Vec3 color_filter(const Vec3& c, const ParamBlock& p);
// Step 6: split toning in gamma space (|c|^(1/2.2), two SoftLights, |c|^2.2).
Vec3 split_toning(const Vec3& c, const ParamBlock& p, bool aces);
// Step 7: the Adobe-style channel mixer (dot products with _ChannelMixerRed/Green/Blue).
Vec3 channel_mixer(const Vec3& c, const ParamBlock& p);
// Step 8: shadows/midtones/highlights weights from smoothsteps of the luminance.
Vec3 shadows_midtones_highlights(const Vec3& c, const ParamBlock& p, bool aces);
// Step 9: c·gain + lift, then sign(c)·|c|^gamma.
Vec3 lift_gamma_gain(const Vec3& c, const ParamBlock& p);
// Step 10: RgbToHsv, hue + _HueSatCon.x (default curves: no hue-vs-hue offset), RotateHue,
// HsvToRgb. Returns the colour; the default curves' satMult is 1.
Vec3 hue_shift(const Vec3& c, const ParamBlock& p);
// Step 11: global saturation λ + _HueSatCon.y · satMult · (c − λ), λ the grade's luminance.
Vec3 saturation(const Vec3& c, const ParamBlock& p, bool aces);
// Step 12 with default curves: HDR: FastTonemap, clamp(t, 0, 127/128), FastTonemapInvert; LDR:
// the curves see c directly: clamp(c, 0, 127/128).
Vec3 default_yrgb_curves(const Vec3& c, bool hdr);
inline constexpr double kCurveCap = 127.0 / 128.0;  // last texel of a 128-texel identity curve

// LutBuilderHdr.shader: ColorGrade(code) for a LogC lattice code (mode per p.urp_tonemap_mode):
// linear sRGB for None/Neutral, ACEScg for ACES, ≥ 0.
Vec3 color_grade(const Vec3& code, const ParamBlock& p, const LogCParams& k = kUnityLogC);
// LutBuilderLdr.shader: FragLutBuilderLdr's colour for a linear lattice code, saturated.
Vec3 ldr_bake(const Vec3& code, const ParamBlock& p, const LogCParams& k = kUnityLogC);
// The texel the bake writes for lattice code `code`, before storage rounding: HDR:
// Tonemap(ColorGrade(code)); LDR: ldr_bake(code).
Vec3 lut_texel(const Vec3& code, const ParamBlock& p, const LogCParams& k = kUnityLogC);

// ---------------------------------------------------------------------------------------------
// The strip LUT (docs/spec/unity_urp.md §2.1, §5.3).

// Color.hlsl: GetLutStripValue for texel (r, g, b) of an H-sized LUT: (r, g, b)/(H − 1), red the
// column within slice b, green the row.
Vec3 lattice_code(int size, int r, int g, int b);
// The value a texel holds in storage format `lut_format`: 1 RGBA16F (round to nearest even of the
// float32 value, overflow → ±Inf), 3 RGBA8 UNORM (saturate, nearest k/255), else float32.
double quantize_texel(int lut_format, double v);
// The H² x H strip (texel (r, g, b) at (r + H b, g); alpha 1), each texel `texel(code)` rounded to
// `lut_format`.
Image bake_strip(int size, int lut_format, const std::function<Vec3(const Vec3& code)>& texel);
// The internal LUT as stored: bake_strip(p.lut_size, p.lut_format, lut_texel(·, p)).
Image bake_lut_strip(const ParamBlock& p);

// Color.hlsl: ApplyLut2D(tex, uvw, (1/W, 1/H, H − 1)) on a stored strip: two bilinear taps
// (clamp-to-edge, exact weights) one slice apart, lerped by the fractional blue slice.
Vec3 apply_lut_2d(const Image& strip, const Vec3& uvw, const std::array<double, 4>& lut_params);

// Common.hlsl: ApplyColorGrading without the user LUT: post exposure; HDR: ApplyLut2D of
// saturate(LinearToLogC(x)); LDR: ApplyLut2D of ApplyTonemap(x). Input scene-linear Rec.709.
Vec3 apply_color_grading(const Image& strip, const ParamBlock& p, const Vec3& scene_linear);

// The named intermediate values of docs/spec/unity_urp.md's worked pixels
// (reference/named_values.h; reference/spec_worked_pixels_test.cpp compares them), from the
// functions above, step by step. texel_named_values: the bake of the texel at lattice code `code`
// (each channel in [0, 1]): the grade's steps (LutBuilderHdr.shader: ColorGrade and Tonemap, or
// LutBuilderLdr.shader: FragLutBuilderLdr), its "out" (lut_texel) and the value the texel stores
// ("stored"). named_values: ApplyColorGrading of one scene colour on the stored strip (post
// exposure, the lookup coordinate, ApplyLut2D's slice, taps and lerp); its "out" is
// apply_color_grading's.
std::vector<NamedValue> texel_named_values(const ParamBlock& p, const Vec3& code);
std::vector<NamedValue> named_values(const ParamBlock& p, const Image& strip, const Vec3& scene);

// Bakes the strip once and grades every pixel of `input` (rgb; alpha passes through).
Image grade_image(const Image& input, const ParamBlock& p);

// ---------------------------------------------------------------------------------------------
// Device allowances (docs/precision.md, "Device allowances").

// What a conformant device may compute for lut_texel(code, p) before storage. Grading in Rec.709
// (LDR grading; HDR grading with tone mapping None or Neutral): ColorGrade evaluated in interval
// arithmetic with the Vulkan specification's bound of every float32 operation
// (reference/color/spirv_precision.h), step by step as gpu/shaders/unity_urp/lib/unity_grade.glsl
// runs it: each channel's range carries its inputs' ranges through the matrices, the pows and
// the saturation's subtraction; RgbToHsv takes every branch its step()s leave undecided; Neutral
// at the ends with kFloat32Noise for its own arithmetic. Always at least the texel ± kFloat32Noise
// of its largest channel (all of it under ACES grading, not yet derived step by step).
Range3 lut_texel_device_range(const Vec3& code, const ParamBlock& p);

// What a conformant device with precision `d` may hold in each texel of the internal LUT:
// lut_texel_device_range, then the storage format's neighbours either way
// (device_allowance.h: RGBA16F rounds by the device's float16 rounding mode unless d.fp16_rte,
// UNORM to either of the two nearest codes, float32 to either neighbour). Contains
// bake_lut_strip(p) texel by texel.
struct StripRange {
  Image lo, hi;
};
StripRange bake_lut_strip_device_range(const ParamBlock& p, const DevicePrecision& d);

// ApplyColorGrading's output range on a device with `sub_texel_bits` sub-texel bits reading the
// strip held within `bounds` (bake_lut_strip_device_range): the exact coordinate (post exposure,
// LogC or the uber tone map) with kFloat32Noise for its float32 arithmetic, the weight boxes of the
// two bilinear taps and each tap's weight on the sub-texel grid (snap_weights, the default), the
// filter's arithmetic in the strip format's precision (VK-GL-CTS's filtering precision: RGBA16F,
// RGBA8 UNORM or float32) and the lerp (reference/color/strip_device_range.h). Contains
// apply_color_grading of the reference strip.
Range3 apply_color_grading_device_range(const StripRange& bounds, const ParamBlock& p,
                                        const Vec3& scene_linear, int sub_texel_bits,
                                        bool snap_weights = true);

}  // namespace hdrc::ref::unity_urp
