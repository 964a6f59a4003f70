// The CPU side of UE 5.5's ACES HDR output transform: the tone-scale (SSTS) parameters that
// Engine/Source/Runtime/RenderCore/Private/RenderCore.cpp: ConfigureACESTonemapParams computes and
// HDRHelper.h: GetACESTonemapParameters copies into shader parameters (docs/spec/ue55.md §5.3,
// decisions D5.3).
//
// Precision: UE computes these in C++ float32, with a few sub-expressions in double (a float mixed
// with a double literal is promoted). This file reproduces every one of those promotions, so the
// packed values are UE's float values, not a double recomputation (which differs by ~1e-6
// relative, docs/spec/ue55.md §5.3). The shader side (aces_output.h) takes these float values in
// double.
//
// Conventions of the emulation (each cited where it is used):
//  * FMath::LogX(10, float v) = logf(v) / logf(10) in float; FMath::LogX(10, double v) =
//    log(v) / log(10) in double (UnrealMathUtility.h: MIX_FLOATS_2_ARGS promotes mixed arguments to
//    the type of A·B).
//  * FMath::Pow(10, float) = powf; pow(2., float), log2(float / 0.18) and the unqualified
//    log2(float) of shift() / expShift are double (the last one established by matching UE's
//    floats).
//  * FMath::Clamp(x, lo, hi) = x < lo ? lo : (x < hi ? x : hi), so Clamp(NaN, lo, hi) = hi.
#pragma once

#include <array>
#include <optional>

#include "core/result.h"

namespace hdrc::ref::aces {

// RenderCore.cpp: TsPoint / TsParams (the C++ struct has 5 coefficients per spline; the shader
// struct has 6, see aces_output.h).
struct TsPointF {
  float x;      // ACES value (AP1 after the RRT sweeteners)
  float y;      // luminance, nits
  float slope;  // d log10(y) / d log10(x)
};

struct TsParamsF {
  TsPointF min, mid, max;
  std::array<float, 5> coefs_low;   // log10 nits
  std::array<float, 5> coefs_high;  // log10 nits
};

// What UE packs into shader parameters (HDRHelper.h: FACESTonemapParams, copied by
// GetACESTonemapParameters into FACESTonemapShaderParameters). Stored as float, exactly the bits UE
// uploads. Default member values are the FACESTonemapParams() constructor's ("MinLuminanceLog10=-4,
// MidLuminance=15, MaxLuminance=1000, SceneColorMultiplier=1.5"), i.e. the state before
// HDRConfigureCVars first runs.
struct AcesTonemapParams {
  // ACESMinMaxData = (Min.x, Min.y, Max.x, Max.y); x in ACES, y in nits.
  std::array<float, 4> min_max_data{2.50898620e-06f, 1e-4f, 692.651123f, 1000.0f};
  // ACESMidData = (Mid.x, Mid.y, Mid.slope, w). ConfigureACESTonemapParams never writes w; it keeps
  // the constructor's 1.0 (decisions D5.3). The shader does not read w.
  std::array<float, 4> mid_data{0.0822144598f, 4.80000019f, 1.55f, 1.0f};
  std::array<float, 4> coefs_low_0{-4.0f, -4.0f, -3.15737653f, -0.485249996f};  // coefsLow[0..3]
  std::array<float, 4> coefs_high_0{-0.332863420f, 1.69534576f, 2.75812411f, 3.0f};
  float coefs_low_4 = 1.84773231f;      // coefsLow[4]
  float coefs_high_4 = 3.0f;            // coefsHigh[4]
  float scene_color_multiplier = 1.5f;  // r.HDR.Aces.SceneColorMultiplier, not clamped
  float gamut_compression = 0.0f;       // r.HDR.Aces.GamutCompression clamped to [0, 1]
};

// RenderCore.cpp: interpolate1D — lerp(y0, y1, Clamp((v − x0)/(x1 − x0), 0, 1)) in float.
struct TablePointF {
  float x, y;
};
float interpolate_1d(const std::array<TablePointF, 2>& table, float value);

// RenderCore.cpp: lookup_ACESmin / lookup_ACESmax — 0.18·2^stop with stop interpolated from
// log10(luminance) between (1e-4 nits, −15 stops)…(0.02, −6.5) and (48, 6.5)…(10000, 18).
float lookup_aces_min(float min_luminance);  // nits → ACES
float lookup_aces_max(float max_luminance);  // nits → ACES

// RenderCore.cpp: init_TsParams. Spline coefficients from the unshifted Min/Mid/Max points, then
// the three x values are shifted by 2^−exp_shift.
TsParamsF init_ts_params(float min_luminance, float max_luminance, float exp_shift = 0.0f);

// RenderCore.cpp: inv_ssts, the C++ inverse tone scale (nits → ACES). Returns nullopt where UE
// reads uninitialised coefficients: a luminance inside (Min.y, Max.y) that falls in none of the
// knot intervals the C++ tests (low spline: KNOT_Y_LOW[i] < logy <= KNOT_Y_LOW[i+1]; high spline:
// the first interval also accepts logy == KNOT_Y_HIGH[0]). Decisions D5.3.
std::optional<float> inv_ssts(float luminance, const TsParamsF& c);

// Everything ConfigureACESTonemapParams computes for one (Min, Mid, Max), plus whether the inputs
// are degenerate. `packed` is what UE would upload even when `status` is an error (UE has no
// check; with MaxLuminance 0 it uploads −Inf coefficients), so a conformance case can still
// reproduce UE, but callers must look at `status` first.
struct AcesConfigured {
  TsParamsF ts;            // the shifted parameters (PARAMS in UE)
  float exp_shift = 0.0f;  // log2(inv_ssts(Mid, PARAMS_DEFAULT)) − log2(0.18)
  AcesTonemapParams packed;
  Status status;  // error: degenerate luminances, or inv_ssts(Mid) hit UE's uninitialised case
};

// RenderCore.cpp: ConfigureACESTonemapParams(Min, Mid, Max) followed by HDRHelper.h:
// GetACESTonemapParameters (the GamutCompression clamp). Luminances in nits, as UE passes them
// (HDRConfigureCVars: Min = FMath::Pow(10, r.HDR.Display.MinLuminanceLog10), Mid =
// r.HDR.Display.MidLuminance, Max = float(r.HDR.Display.MaxLuminance)).
AcesConfigured configure_aces_tonemap_params(float min_luminance, float mid_luminance,
                                             float max_luminance,
                                             float scene_color_multiplier = 1.5f,
                                             float gamut_compression_cvar = 0.0f);

// The degenerate-input check on its own: every luminance finite and > 0 (UE takes log10 of all
// three) and Min < Mid < Max (otherwise the spline folds over). With HDR off UE configures
// MaxLuminance = 0 (docs/spec/ue55.md §5.4), which this reports as an error naming the value.
Status validate_aces_luminances(float min_luminance, float mid_luminance, float max_luminance);

}  // namespace hdrc::ref::aces
