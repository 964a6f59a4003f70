#include "reference/ue/visualize/histogram.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "color/d3d_math.h"

namespace hdrc::ref::visualize {

EyeAdaptationSettings default_settings(bool extended_luminance_range) {
  EyeAdaptationSettings s;
  s.extended_luminance_range = extended_luminance_range;
  if (!extended_luminance_range) {
    // Scene.cpp: FCameraExposureSettings, legacy branch (luminance and log2 luminance).
    s.min_brightness = 0.03;
    s.max_brightness = 8.0;
    s.histogram_log_min = -8.0;
    s.histogram_log_max = 4.0;
  }
  return s;
}

double ev100_to_log2(double luminance_max, double ev100) {
  return ev100 + std::log2(luminance_max);
}
double ev100_to_luminance(double luminance_max, double ev100) {
  return luminance_max * std::exp2(ev100);
}
double luminance_to_ev100(double luminance_max, double luminance) {
  return std::log2(luminance / luminance_max);
}
double log2_to_ev100(double luminance_max, double log2_luminance) {
  return log2_luminance - std::log2(luminance_max);
}

EyeAdaptationParameters compute_eye_adaptation_parameters(const EyeAdaptationSettings& s) {
  const bool extended = s.extended_luminance_range;

  // GetAutoExposureMethod: with the EyeAdaptation show flag off the method is manual.
  const AutoExposureMethod method =
      s.eye_adaptation_show_flag ? s.method : AutoExposureMethod::kManual;

  // LuminanceMaxFromLensAttenuation.
  const double luminance_max =
      extended ? kIsoSaturationSpeedConstant / std::max(s.lens_attenuation, 0.01) : 1.0;

  const double high = std::clamp(s.high_percent, 1.0, 99.0) * 0.01;
  const double low = std::min(std::clamp(s.low_percent, 1.0, 99.0) * 0.01, high);

  const double log_max =
      extended ? ev100_to_log2(luminance_max, s.histogram_log_max) : s.histogram_log_max;
  const double log_min =
      std::min(extended ? ev100_to_log2(luminance_max, s.histogram_log_min) : s.histogram_log_min,
               log_max - 1.0);

  double min_white = 1.0;
  double max_white = 1.0;
  double compensation_settings =
      std::exp2(s.exposure_bias);   // GetAutoExposureCompensationFromSettings
  double compensation_curve = 1.0;  // no AutoExposureBiasCurve
  const double grey_mult = method == AutoExposureMethod::kManual ? 1.0 : kMiddleGrey;

  if (s.debug_view_mode) {
    compensation_settings = 1.0;
    compensation_curve = 1.0;
  } else if (s.eye_adaptation_show_flag) {
    if (method == AutoExposureMethod::kManual) {
      // CalculateManualAutoExposure with the physical camera off: EV100ToLuminance(LMax, 0).
      min_white = max_white = ev100_to_luminance(luminance_max, 0.0);
    } else if (extended) {
      min_white = ev100_to_luminance(luminance_max, s.min_brightness);
      max_white = ev100_to_luminance(luminance_max, s.max_brightness);
    } else {
      min_white = s.min_brightness;
      max_white = s.max_brightness;
    }
  } else {
    compensation_settings = 1.0;
    compensation_curve = 1.0;
  }
  min_white = std::min(min_white, max_white);

  const double scale = 1.0 / (log_max - log_min);
  const double bias = -log_min * scale;

  const double start_distance = s.exponential_transition_distance;
  const double start_time_up = start_distance / std::max(s.speed_up, 0.001);
  const double start_time_down = start_distance / std::max(s.speed_down, 0.001);
  const double frame_eps = 1.0 / 60.0;  // kFrameTimeEps

  const bool valid_range = s.min_brightness < s.max_brightness;
  const bool valid_speeds = s.speed_down >= 0.0 && s.speed_up >= 0.0;

  EyeAdaptationParameters p;
  p.exposure_low_percent = low;
  p.exposure_high_percent = high;
  p.min_average_luminance = min_white * kMiddleGrey;
  p.max_average_luminance = max_white * kMiddleGrey;
  p.exposure_compensation_settings = compensation_settings;
  p.exposure_compensation_curve = compensation_curve;
  p.histogram_log_min = log_min;
  p.histogram_log_max = log_max;
  p.histogram_scale = scale;
  p.histogram_bias = bias;
  p.luminance_min = method == AutoExposureMethod::kBasic ? 0.0001 : std::exp2(log_min);
  p.luminance_max = luminance_max;
  p.black_histogram_bucket_influence = s.black_histogram_bucket_influence;
  p.grey_mult = grey_mult;
  p.exponential_up_m = frame_eps / ((1.0 - std::exp2(-frame_eps * s.speed_up)) * start_time_up);
  p.exponential_down_m =
      frame_eps / ((1.0 - std::exp2(-frame_eps * s.speed_down)) * start_time_down);
  p.start_distance = start_distance;
  p.force_target =
      (s.camera_cut || method == AutoExposureMethod::kManual || !valid_range || !valid_speeds)
          ? 1.0
          : 0.0;
  p.visualize_debug_type = s.visualize_debug_type;
  p.method = method;
  return p;
}

double histogram_position_from_log_luminance(double log2_luminance,
                                             const EyeAdaptationParameters& p) {
  return log2_luminance * p.histogram_scale + p.histogram_bias;
}
double histogram_position_from_luminance(double luminance, const EyeAdaptationParameters& p) {
  return histogram_position_from_log_luminance(std::log2(luminance), p);
}
double log_luminance_from_histogram_position(double position, const EyeAdaptationParameters& p) {
  return (position - p.histogram_bias) / p.histogram_scale;
}
double luminance_from_histogram_position(double position, const EyeAdaptationParameters& p) {
  return std::exp2(log_luminance_from_histogram_position(position, p));
}

double eye_adaptation_luminance(const Vec3& rgb, const EyeAdaptationParameters& p) {
  return std::fmax(dot(rgb, Vec3{1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0}), p.luminance_min);
}

namespace {

// Histogram.usf: PackFloatToUINT32 — (uint)(w · 2^19), truncation; w is in [0, 1].
constexpr double kFixedPointOne = 524288.0;  // 1 << 19
std::uint64_t pack_weight(double w) {
  return static_cast<std::uint64_t>(w * kFixedPointOne);
}

}  // namespace

Histogram build_histogram(const Image& hdr, const EyeAdaptationParameters& p,
                          double one_over_pre_exposure) {
  std::array<std::uint64_t, kHistogramSize> fixed{};
  for (int y = 0; y < hdr.height; ++y) {
    for (int x = 0; x < hdr.width; ++x) {
      const double* c = hdr.px(x, y);
      const Vec3 rgb{c[0] * one_over_pre_exposure, c[1] * one_over_pre_exposure,
                     c[2] * one_over_pre_exposure};
      const double luminance = eye_adaptation_luminance(rgb, p);
      // CalculateBucketsAndWeights.
      const double f =
          d3d::saturate(histogram_position_from_luminance(luminance, p)) * (kHistogramSize - 1);
      const int b0 = std::min(static_cast<int>(f), kHistogramSize - 1);
      const int b1 = std::min(b0 + 1, kHistogramSize - 1);
      const double w1 = f - std::floor(f);
      double w0 = 1.0 - w1;
      if (b0 == 0) w0 *= p.black_histogram_bucket_influence;
      // ScatterWeightsToLDS with ScreenWeight 1 (no meter mask).
      fixed[b0] += pack_weight(w0);
      fixed[b1] += pack_weight(w1);
    }
  }
  // HistogramConvertCS: Unpack (· 2^−19), · 0.5, · InvViewSize.x · InvViewSize.y.
  const double normalize = (1.0 / hdr.width) * (1.0 / hdr.height);
  Histogram h{};
  for (int i = 0; i < kHistogramSize; ++i) {
    h[i] = static_cast<double>(fixed[i]) / kFixedPointOne * 0.5 * normalize;
  }
  return h;
}

double bucket_centre_position(int bucket) {
  return static_cast<double>(bucket) / (kHistogramSize - 1);
}

double histogram_sum(const Histogram& h) {
  double sum = 0.0;
  for (double v : h) sum += v;
  return sum;
}

double histogram_max(const Histogram& h) {
  double m = 0.0;
  for (double v : h) m = std::fmax(m, v);
  return m;
}

double place_in_histogram(const Vec3& rgb, const Histogram& h, const EyeAdaptationParameters& p) {
  const double log_luminance = std::log2(dot(rgb, Vec3{1.0, 1.0, 1.0}) / 3.0);
  double sum_total = 0.0;
  double sum_below = 0.0;
  for (int i = 0; i < kHistogramSize; ++i) {
    const double lo = log_luminance_from_histogram_position(bucket_centre_position(i), p);
    const double hi = log_luminance_from_histogram_position(bucket_centre_position(i + 1), p);
    const double t = d3d::saturate((log_luminance - lo) / (hi - lo));
    sum_below += h[i] * t;
    sum_total += h[i];
  }
  return sum_below / sum_total;
}

double average_luminance_without_outliers(const Histogram& h, const EyeAdaptationParameters& p) {
  const double sum = histogram_sum(h);
  double min_fraction = sum * p.exposure_low_percent;
  double max_fraction = sum * p.exposure_high_percent;
  double weighted_log = 0.0;
  double weight = 0.0;
  for (int i = 0; i < kHistogramSize; ++i) {
    double value = h[i];
    const double sub = std::fmin(value, min_fraction);  // drop the low outliers
    value -= sub;
    min_fraction -= sub;
    max_fraction -= sub;
    value = std::fmin(value, max_fraction);  // drop the high outliers
    max_fraction -= value;
    weighted_log += log_luminance_from_histogram_position(bucket_centre_position(i), p) * value;
    weight += value;
  }
  return std::exp2(weighted_log / std::fmax(0.0001, weight));
}

}  // namespace hdrc::ref::visualize
