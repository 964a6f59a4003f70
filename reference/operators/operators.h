// The classic tone-mapping operators (pipeline `operators`), in double precision: Reinhard (simple
// and with a white point), Hable's Uncharted 2 filmic curve, Narkowicz's ACES fit, Unity's Neutral
// and UE's FilmToneMap. Each one has exactly one definition here; the Unity URP pipeline calls
// unity_neutral, and the UE filmic operator calls reference/grading's film_tone_map (not a copy).
// GPU mirror: gpu/shaders/operators/lib/operators.glsl.
//
// Input is scene-linear with Rec.709/sRGB primaries; every operator except UeFilmic works per
// channel. Non-finite and negative inputs: each operator is its published formula evaluated in
// IEEE-754 arithmetic with HLSL's (D3D's) semantics for the intrinsics the published code uses
// (saturate(NaN) = 0, max = maxNum), and nothing added. So 0·∞ and ∞/∞ give NaN: +Inf becomes NaN
// for Reinhard, ReinhardWhite, Hable and UnityNeutral, and 0 for AcesNarkowicz (saturate of NaN)
// and UeFilmic (FilmToneMap's max(0, ·) of NaN); negative inputs follow the rational formulas
// through their poles (Reinhard's at −1, Hable's denominator's two negative roots, −0.122 and
// −0.560 at the default constants) except where the source clamps (UnityNeutral's max(x, 0),
// FilmToneMap's max(0, ·)). The tests pin each of these. The GLSL reproduces all of it, and its
// float32 rationals keep finite inputs up to float32's maximum; the one known gap is UeFilmic
// above ~1.8e19 (gpu/operators_shader_test.cpp).
#pragma once

#include "color/vec.h"
#include "core/shader_interface.h"
#include "reference/color/spirv_precision.h"
#include "reference/ue/grading/film_tonemap.h"

namespace hdrc::ref::operators {

// The values of the op_operator field and of the "Operator" setting.
enum class Operator : int {
  kReinhard = 0,
  kReinhardWhite = 1,
  kHable = 2,
  kAcesNarkowicz = 3,
  kUnityNeutral = 4,
  kUeFilmic = 5,
};
inline constexpr int kOperatorCount = 6;
// "Reinhard", "ReinhardWhite", "Hable", "AcesNarkowicz", "UnityNeutral", "UeFilmic"; nullptr
// outside 0-5.
const char* operator_name(int op);

// --- Reinhard et al. 2002, "Photographic Tone Reproduction for Digital Images" (SIGGRAPH) ---

// Eq. 2: L(x, y) = a / L̄w · Lw(x, y), the key `a` mapped onto the scene's log-average luminance
// L̄w (eq. 1, measured outside). This is the scale op_exposure holds (dimensionless).
inline constexpr double kReinhardDefaultKey = 0.18;              // "a", §3 ("normal-key", 0.18)
double reinhard_exposure(double key, double adapted_luminance);  // key / adapted_luminance

// Eq. 3: Ld = L / (1 + L).
double reinhard(double x);

// Eq. 4: Ld = L (1 + L / L_white²) / (1 + L); 1 at L = L_white.
double reinhard_white(double x, double white);

// --- The rational "filmic" curve of Hable (Uncharted 2) and Unity's Neutral ---

// f(x) = (x (A x + C B) + D E) / (x (A x + B) + D F) − E / F. John Hable, "Uncharted 2: HDR
// Lighting" (GDC 2010) and "Filmic Tonemapping Operators" (filmicworlds.com, 2010); Unity's
// Color.hlsl: NeutralCurve is the same function with other constants.
struct RationalCurve {
  double a, b, c, d, e, f;
};
double rational_curve(double x, const RationalCurve& k);

// Hable's operator: f(bias · x) / f(W). The defaults are the GDC 2010 slides' constants (142-143)
// (shoulder strength A 0.22, linear strength B 0.30, linear angle C 0.10, toe strength D 0.20, toe
// numerator E 0.01, toe denominator F 0.30, linear white W 11.2); the exposure bias 2.0 is the blog
// post's code (whose own constants are A 0.15, B 0.50, C 0.10, D 0.20, E 0.02, F 0.30).
struct HableParams {
  RationalCurve curve{0.22, 0.30, 0.10, 0.20, 0.01, 0.30};
  double w = 11.2;
  double exposure_bias = 2.0;
};
double hable(double x, const HableParams& p);

// --- Krzysztof Narkowicz, "ACES Filmic Tone Mapping Curve" (knarkowicz.wordpress.com, 2016) ---

// saturate(x (a x + b) / (x (c x + d) + e)), x = pre_scale · input. The published form has no
// pre-scale (1); many engines use 0.6. The denominator has no real root.
struct NarkowiczFit {
  double a = 2.51, b = 0.03, c = 2.43, d = 0.59, e = 0.14;
};
inline constexpr NarkowiczFit kNarkowicz{};
double aces_narkowicz(double x, double pre_scale = 1.0);

// --- Unity's Neutral: Color.hlsl NeutralTonemap (Unity-Technologies/Graphics, commit
// f115daf974a0e6696efa96b440cd015f41e0e090; docs/spec/unity_urp.md §2.6) ---

inline constexpr RationalCurve kUnityNeutralCurve{0.2, 0.29, 0.24, 0.272, 0.02, 0.3};  // a..f
inline constexpr double kUnityNeutralWhiteLevel = 5.3;                                 // whiteLevel
inline constexpr double kUnityNeutralWhiteClip = 1.0;                                  // whiteClip
// x = max(x, 0) (maxNum: NaN → 0); ws = 1 / N(whiteLevel); out = N(x · ws) · ws / whiteClip, with
// N = rational_curve(·, kUnityNeutralCurve). Not clamped (above 1 from x ≈ 4.035).
double unity_neutral(double x);

// --- UE 5.5's FilmToneMap (TonemapCommon.ush; reference/ue/grading/film_tonemap.h) ---

// The presets: Default from Scene.cpp FPostProcessSettings (UE 5.5), the others from the comment
// above FilmToneMap in TonemapCommon.ush (izzy2lost/UnrealEngineUWP 5.5, commit
// aff11acf0c218535669021f6e646b3bcf6ad94a5): "Uncharted settings", "HP settings", "Legacy
// settings", "ACES settings". Values of the "FilmPreset" setting.
enum class FilmPreset : int { kDefault = 0, kLegacy = 1, kAces = 2, kUncharted = 3, kHp = 4 };
inline constexpr int kFilmPresetCount = 5;
const char* film_preset_name(int preset);  // "Default", "Legacy", "ACES", "Uncharted", "HP"
// Slope / toe / shoulder / black clip / white clip of a preset (Default outside 0-4).
grading::FilmParams film_preset(FilmPreset preset);

// The pipeline's input is Rec.709, UE's curve works in AP1, so the operator converts as UE 5.5's
// CombineLUTs does with the default (sRGB) Working Color Space: WorkingColorSpace.ToAP1,
// FilmToneMap, then max(0, WorkingColorSpace.FromAP1 · ·) (PostProcessCombineLUTs.usf: the
// FilmColor line of CombineLUTsCommon). The matrices are UE's float-cast ones
// (make_working_color_space(kSrgb) in reference/color/ue_matrices.h), carried in op_rec709_to_ap1 /
// op_ap1_to_rec709. Unlike UE's whole film path there is no blue correction (BlueCorrection 0) and
// ToneCurveAmount is 1.
struct UeFilmicSpace {
  Mat3 rec709_to_ap1, ap1_to_rec709;
};
UeFilmicSpace ue_filmic_space();
Vec3 ue_filmic(const Vec3& rec709, const grading::FilmParams& film, const UeFilmicSpace& space);
// The same with its named intermediate values (docs/spec/operators.md, the UeFilmic worked pixel).
struct UeFilmicTrace {
  Vec3 ap1;                        // rec709_to_ap1 · input
  grading::FilmToneMapTrace film;  // FilmToneMap's steps
  Vec3 tone_ap1;                   // FilmToneMap(ap1)
  Vec3 rec709;                     // ap1_to_rec709 · tone_ap1, before max(0, ·)
};
Vec3 ue_filmic(const Vec3& rec709, const grading::FilmParams& film, const UeFilmicSpace& space,
               UeFilmicTrace* trace);

// --- The pipeline's one stage ---

// One pixel's named intermediate values (docs/spec/operators.md, its worked pixels; probe --json):
// input, exposure, x, the operator's own (Hable: f_bias_x, f_w; UnityNeutral: white_scale, curve;
// UeFilmic: ap1, FilmToneMap's steps as `detail`, tone_ap1, rec709), out = apply_operator.
std::vector<NamedValue> named_values(const ParamBlock& p, const Vec3& scene_linear);

// x = op_exposure · scene_linear, then the operator op_operator with its op_* fields (UeFilmic:
// film_* and the op_ matrices). An op_operator outside 0-5 gives NaN in every channel.
Vec3 apply_operator(const ParamBlock& p, const Vec3& scene_linear);

// Device allowances (docs/precision.md, "Device allowances"): the range of one output channel a
// conformant Vulkan device may return evaluating the per-channel operators (Reinhard, Reinhard
// with white point, Hable, Narkowicz, Unity's Neutral) as gpu/shaders/operators/lib/operators.glsl
// writes them, step by step in the interval arithmetic of the Vulkan precision table
// (reference/color/spirv_precision.h: add/sub/mul 0.5 ULP, div 2.5 ULP, a·b + c fused or not),
// the input, uniforms and constants as the interval between their float32 neighbours. False where
// no range is derived (a non-finite input or result, a denominator whose range holds 0, UeFilmic:
// see operators_pipeline.cpp).
bool operator_channel_device_range(const ParamBlock& p, double x, spirv::Interval* out);

}  // namespace hdrc::ref::operators
