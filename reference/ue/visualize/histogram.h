// Auto-exposure ("eye adaptation") parameters and the 64-bucket luminance histogram of UE 5.5, as
// VisualizeHDR (docs/spec/ue55.md §9) reads them, in double precision.
//
// Sources (facts restated, no code copied):
//  * Engine/Source/Runtime/Renderer/Private/PostProcess/PostProcessEyeAdaptation.cpp:
//    GetEyeAdaptationParameters, LuminanceMaxFromLensAttenuation, GetAutoExposureCompensationFrom*
//    and the r.EyeAdaptation.* cvars (izzy2lost/UnrealEngineUWP 5.5, commit 05f15fb1…).
//  * Engine/Source/Runtime/Engine/Private/Scene.cpp: FCameraExposureSettings defaults
//  (izzy2lost 5.5,
//    commit 0cc0a068…); SceneView.cpp: r.DefaultFeature.AutoExposure.Bias = 1.0,
//    r.DefaultFeature.AutoExposure.ExtendDefaultLuminanceRange = 0 ("1: UE5 default"; new-project
//    templates write True to DefaultEngine.ini).
//  * Engine/Shaders/Private/PostProcessHistogramCommon.ush: CalculateEyeAdaptationLuminance,
//    ComputeHistogramPosition*, GetHistogramBucket, ComputeAverageLuminanceWithoutOutlier
//    (izzy2lost 5.5, commit 2ad5a489…).
//  * Engine/Shaders/Private/PostProcessVisualizeHDR.usf: ComputePlaceInHistogram (izzy2lost 5.5,
//    commit 39bb2572…).
//  * Histogram generation: Engine/Shaders/Private/Histogram.usf: MainAtomicCS,
//    CalculateBucketsAndWeights, PackFloatToUINT32, HistogramConvertCS
//    (chenyong2github/UnrealEngine UE5 copy, commit 3961015d…), selected by r.Histogram.UseAtomic =
//    1 in PostProcessHistogram.cpp: AddHistogramPass (UE5.2+ and UE5.8.0 copies; no 5.5 copy of
//    either file is indexed — assumed unchanged in 5.5). The legacy path (PostProcessHistogram.usf
//    MainCS + reduce, r.Histogram.UseAtomic = 0) splats with the same weights but is not modelled
//    here.
//
// UE computes the parameters in float32 on the CPU; they are computed here in double (the float
// values differ by at most one float ulp, e.g. HistogramScale 1/30).
#pragma once

#include <array>
#include <vector>

#include "color/vec.h"
#include "core/image.h"

namespace hdrc::ref::visualize {

// HISTOGRAM_SIZE (PostProcessHistogramCommon.ush; FHistogramAtomicCS::HistogramSize).
inline constexpr int kHistogramSize = 64;
using Histogram = std::array<double, kHistogramSize>;

// 18 % grey (GetEyeAdaptationParameters: kMiddleGrey).
inline constexpr double kMiddleGrey = 0.18;
// ISO 12232:2006 saturation-speed constant (LuminanceMaxFromLensAttenuation).
inline constexpr double kIsoSaturationSpeedConstant = 0.78;

enum class AutoExposureMethod { kHistogram, kBasic, kManual };

// The inputs GetEyeAdaptationParameters reads: the view's final post-process settings, the
// r.EyeAdaptation.* cvars and the project setting. Defaults are UE 5.5's for a UE5 project
// (extended luminance range on). Use default_settings(false) for the legacy (UE4) range.
struct EyeAdaptationSettings {
  // r.DefaultFeature.AutoExposure.ExtendDefaultLuminanceRange: when true, MinBrightness,
  // MaxBrightness, HistogramLogMin and HistogramLogMax are EV100; otherwise luminance / log2.
  bool extended_luminance_range = true;
  AutoExposureMethod method = AutoExposureMethod::kHistogram;  // FCameraExposureSettings::Method
  double low_percent = 10.0;                                   // AutoExposureLowPercent, %
  double high_percent = 90.0;                                  // AutoExposureHighPercent, %
  double min_brightness = -10.0;     // AutoExposureMinBrightness (EV100; legacy 0.03, luminance)
  double max_brightness = 20.0;      // AutoExposureMaxBrightness (EV100; legacy 8.0, luminance)
  double histogram_log_min = -10.0;  // HistogramLogMin (EV100; legacy −8, log2 luminance)
  double histogram_log_max = 20.0;   // HistogramLogMax (EV100; legacy 4, log2 luminance)
  double speed_up = 3.0;             // AutoExposureSpeedUp
  double speed_down = 1.0;           // AutoExposureSpeedDown
  double exposure_bias = 1.0;        // AutoExposureBias, EV (r.DefaultFeature.AutoExposure.Bias)
  double lens_attenuation = 0.78;    // r.EyeAdaptation.LensAttenuation
  double black_histogram_bucket_influence = 0.0;  // r.EyeAdaptation.BlackHistogramBucketInfluence
  double exponential_transition_distance = 1.5;   // r.EyeAdaptation.ExponentialTransitionDistance
  int visualize_debug_type = 0;                   // r.EyeAdaptation.VisualizeDebugType
  // IsAutoExposureDebugMode (no lighting, debug view modes, ...): compensation forced to 1.
  bool debug_view_mode = false;
  // EngineShowFlags.EyeAdaptation; off forces manual mode with white points locked to 1.
  bool eye_adaptation_show_flag = true;
  bool camera_cut = false;  // View.bCameraCut (feeds ForceTarget)
};

// FCameraExposureSettings::FCameraExposureSettings (Scene.cpp) for either luminance range.
EyeAdaptationSettings default_settings(bool extended_luminance_range);

// FEyeAdaptationParameters as GetEyeAdaptationParameters fills it (the fields VisualizeHDR and the
// histogram read, plus the adaptation-speed terms). Not modelled: AutoExposureBiasCurve (the
// curve compensation is 1), fixed exposure (ExposureSettings.bFixed), the physical-camera EV100 of
// manual mode (AutoExposureApplyPhysicalCameraExposure, default off), mobile LDR's bias − 1, the
// IgnoreMaterials terms and the meter mask (GWhiteTexture: every screen weight is 1).
struct EyeAdaptationParameters {
  double exposure_low_percent;            // clamp(Low, 1, 99)/100, then min(·, High)
  double exposure_high_percent;           // clamp(High, 1, 99)/100
  double min_average_luminance;           // MinWhitePointLuminance · 0.18
  double max_average_luminance;           // MaxWhitePointLuminance · 0.18
  double exposure_compensation_settings;  // 2^AutoExposureBias (1 in debug view modes)
  double exposure_compensation_curve;     // 1 (no curve modelled)
  double histogram_log_min;               // log2 luminance at histogram position 0
  double histogram_log_max;               // log2 luminance at histogram position 1
  double histogram_scale;                 // 1/(LogMax − LogMin)
  double histogram_bias;                  // −LogMin · Scale
  double luminance_min;                   // 2^LogMin (histogram / manual), 0.0001 (basic)
  double luminance_max;  // 0.78/max(LensAttenuation, 0.01) if extended range, else 1
  double black_histogram_bucket_influence;
  double grey_mult;  // 1 for manual, 0.18 otherwise
  double exponential_up_m;
  double exponential_down_m;
  double start_distance;
  double force_target;  // 1 on camera cut, manual mode, MinBrightness ≥ MaxBrightness, speeds < 0
  int visualize_debug_type;
  AutoExposureMethod method;
};

EyeAdaptationParameters compute_eye_adaptation_parameters(const EyeAdaptationSettings& s);

// PostProcessEyeAdaptation.h helpers (docs/ue55-decisions.md D9):
//   EV100ToLog2 = EV100 + log2(LuminanceMax); EV100ToLuminance = LuminanceMax · 2^EV100;
//   LuminanceToEV100 = log2(L / LuminanceMax); Log2ToEV100 = Log2 − log2(LuminanceMax).
double ev100_to_log2(double luminance_max, double ev100);
double ev100_to_luminance(double luminance_max, double ev100);
double luminance_to_ev100(double luminance_max, double luminance);
double log2_to_ev100(double luminance_max, double log2_luminance);

// PostProcessHistogramCommon.ush. Position 0..1 across the histogram ↔ log2 luminance.
double histogram_position_from_log_luminance(double log2_luminance,
                                             const EyeAdaptationParameters& p);
double histogram_position_from_luminance(double luminance, const EyeAdaptationParameters& p);
double log_luminance_from_histogram_position(double position, const EyeAdaptationParameters& p);
double luminance_from_histogram_position(double position, const EyeAdaptationParameters& p);

// CalculateEyeAdaptationLuminance: max(mean(R, G, B), LuminanceMin) — the mean of RGB, not a
// weighted luminance. HLSL max on D3D is maxNum, so NaN input gives LuminanceMin.
double eye_adaptation_luminance(const Vec3& rgb, const EyeAdaptationParameters& p);

// The histogram UE 5.5 builds from the pre-tonemap scene colour (r.Histogram.UseAtomic = 1):
// for every pixel of the image (the whole image is the viewport),
//   L = CalculateEyeAdaptationLuminance(rgb · one_over_pre_exposure)
//   f = saturate(log2(L)·Scale + Bias) · 63;  b0 = floor(f), b1 = min(b0 + 1, 63)
//   w1 = frac(f), w0 = 1 − w1, and w0 ·= BlackHistogramBucketInfluence when b0 = 0
// i.e. a linear ("bilinear") splat between the two buckets that straddle the position — not
// nearest-bucket. Each weight is stored as the 13.19 fixed-point integer trunc(w · 2^19)
// (PackFloatToUINT32) and summed exactly; HistogramConvertCS then multiplies the sum by
// 0.5/(W·H) (the 0.5 reproduces the legacy reduce pass's bilinear halving). With the default
// BlackHistogramBucketInfluence 0, black pixels (and NaN ones, whose L becomes LuminanceMin)
// contribute nothing: they land on position 0 with all their weight on bucket 0.
Histogram build_histogram(const Image& hdr_scene_color, const EyeAdaptationParameters& p,
                          double one_over_pre_exposure = 1.0);

// Bucket 0 ↔ position 0, bucket 63 ↔ position 1 (the splat's centres).
double bucket_centre_position(int bucket);

double histogram_sum(const Histogram& h);  // ComputeHistogramSum
double histogram_max(const Histogram& h);  // ComputeHistogramMax (VisualizeHDR)

// PostProcessVisualizeHDR.usf: ComputePlaceInHistogram — the fraction of histogram weight below
// the pixel: logL = log2(dot(rgb, 1)/3) (no LuminanceMin clamp, unlike the histogram itself), and
// bucket i counts fully below when logL ≥ the log luminance of position (i+1)/63, not at all at or
// below that of i/63, linearly between: Σ w_i · saturate((logL − lo_i)/(hi_i − lo_i)) / Σ w_i.
// (Bucket i is treated as spanning [i/63, (i+1)/63], half a bucket above where the splat centres
// it.) Non-finite rules, as on D3D: logL = NaN (NaN or negative mean) → every term saturate(NaN)
// = 0 → percentile 0; black → log2 0 = −∞ → 0; an empty histogram → 0/0 = NaN.
double place_in_histogram(const Vec3& rgb, const Histogram& h, const EyeAdaptationParameters& p);

// PostProcessHistogramCommon.ush: ComputeAverageLuminanceWithoutOutlier(h, sum·Low, sum·High) —
// exp2 of the weighted mean log luminance at the bucket centres, after removing the lowest
// ExposureLowPercent and everything above ExposureHighPercent of the total weight.
double average_luminance_without_outliers(const Histogram& h, const EyeAdaptationParameters& p);

}  // namespace hdrc::ref::visualize
