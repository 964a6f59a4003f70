// Tests for the VisualizeHDR reference. Expected values are derived by hand in the comments (or
// re-computed independently where noted), never read back from the code under test. Every
// tolerance carries the residual measured when it was set.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "reference/ue/visualize/histogram.h"
#include "reference/ue/visualize/visualize_hdr.h"

namespace {

namespace v = hdrc::ref::visualize;
using hdrc::Image;
using hdrc::ref::Vec3;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Image uniform_image(int w, int h, double r, double g, double b, double a = 1.0) {
  Image img(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      double* p = img.px(x, y);
      p[0] = r;
      p[1] = g;
      p[2] = b;
      p[3] = a;
    }
  }
  return img;
}

void set_grey(Image& img, int x, int y, double value) {
  double* p = img.px(x, y);
  p[0] = p[1] = p[2] = value;
  p[3] = 1.0;
}

void expect_pixel(const Image& img, int x, int y, double r, double g, double b, double tol) {
  const double* p = img.px(x, y);
  EXPECT_NEAR(p[0], r, tol) << "R at (" << x << ", " << y << ")";
  EXPECT_NEAR(p[1], g, tol) << "G at (" << x << ", " << y << ")";
  EXPECT_NEAR(p[2], b, tol) << "B at (" << x << ", " << y << ")";
}

// A stand-in for FilmToneMap whose values are easy by hand: half the input, per channel.
v::ToneCurve half_curve() {
  return v::per_channel([](double x) { return 0.5 * x; });
}

// ---------------------------------------------------------------------------------------------
// Colorize: x = saturate(x); lerp(green, lerp(blue, red, x), |0.5 − x|·2).

TEST(Colorize, HandValues) {
  // 0: t = 1, lerp(blue, red, 0) = blue.  0.5: t = 0, green.  1: t = 1, red.
  // 0.25: t = 0.5, cold/heat = (0.25, 0, 0.75) → (0.125, 0.5, 0.375).  Residual 0 (exact).
  const struct {
    double x;
    Vec3 want;
  } cases[] = {{0.0, {0, 0, 1}},
               {0.5, {0, 1, 0}},
               {1.0, {1, 0, 0}},
               {0.25, {0.125, 0.5, 0.375}},
               {0.75, {0.375, 0.5, 0.125}},
               {-3.0, {0, 0, 1}},
               {7.0, {1, 0, 0}},
               {kNaN, {0, 0, 1}}};  // saturate(NaN) = 0 on D3D → blue
  for (const auto& c : cases) {
    const Vec3 got = v::colorize(c.x);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(got[i], c.want[i]) << "x = " << c.x << " channel " << i;
  }
}

// ---------------------------------------------------------------------------------------------
// GetEyeAdaptationParameters.

TEST(EyeAdaptationParameters, ExtendedRangeDefaults) {
  const v::EyeAdaptationParameters p =
      v::compute_eye_adaptation_parameters(v::default_settings(true));
  // LuminanceMax = 0.78/0.78 = 1; LogMax = 20 + log2(1) = 20, LogMin = −10;
  // Scale = 1/30, Bias = 10/30 = 1/3, LuminanceMin = 2^−10. Residuals 0.
  EXPECT_DOUBLE_EQ(p.luminance_max, 1.0);
  EXPECT_DOUBLE_EQ(p.histogram_log_max, 20.0);
  EXPECT_DOUBLE_EQ(p.histogram_log_min, -10.0);
  EXPECT_NEAR(p.histogram_scale, 1.0 / 30.0, 1e-16);
  EXPECT_NEAR(p.histogram_bias, 1.0 / 3.0, 1e-16);
  EXPECT_EQ(p.luminance_min, 1.0 / 1024.0);
  // Percent 10/90 → 0.1/0.9; white points EV100 −10/20 → 2^−10 and 2^20, times 0.18.
  EXPECT_NEAR(p.exposure_low_percent, 0.1, 1e-16);
  EXPECT_NEAR(p.exposure_high_percent, 0.9, 1e-16);
  EXPECT_NEAR(p.min_average_luminance, 0.00017578125, 1e-19);
  EXPECT_NEAR(p.max_average_luminance, 188743.68, 1e-10);
  // AutoExposureBias 1 → 2^1; no curve; histogram mode → GreyMult 0.18; not forced.
  EXPECT_EQ(p.exposure_compensation_settings, 2.0);
  EXPECT_EQ(p.exposure_compensation_curve, 1.0);
  EXPECT_EQ(p.grey_mult, 0.18);
  EXPECT_EQ(p.force_target, 0.0);
  // ExponentialUpM = (1/60)/((1 − 2^(−3/60))·(1.5/3)): 2^−0.05 = 0.96593633, so
  // (1/60)/(0.03406367·0.5) = 0.97855963; down (speed 1): (1/60)/(0.01148597·1.5) = 0.96736295
  // (re-computed in Python). Residuals 0.
  EXPECT_NEAR(p.exponential_up_m, 0.9785596291072172, 1e-12);
  EXPECT_NEAR(p.exponential_down_m, 0.967362946173489, 1e-12);
}

TEST(EyeAdaptationParameters, LegacyRangeDefaults) {
  const v::EyeAdaptationParameters p =
      v::compute_eye_adaptation_parameters(v::default_settings(false));
  // Legacy: LuminanceMax fixed 1; LogMin/Max −8/4 used as log2 directly: Scale = 1/12,
  // Bias = 8/12 = 2/3, LuminanceMin = 2^−8; white points 0.03 and 8 (luminance) × 0.18.
  // Residuals ≤ 8.7e-19.
  EXPECT_EQ(p.luminance_max, 1.0);
  EXPECT_NEAR(p.histogram_scale, 1.0 / 12.0, 1e-16);
  EXPECT_NEAR(p.histogram_bias, 2.0 / 3.0, 1e-16);
  EXPECT_EQ(p.luminance_min, 1.0 / 256.0);
  EXPECT_NEAR(p.min_average_luminance, 0.0054, 1e-17);
  EXPECT_NEAR(p.max_average_luminance, 1.44, 1e-15);
  // The region tints change at pos(0.03) = log2(0.03)/12 + 2/3 = −5.0588937/12 + 0.6666667 =
  // 0.2450922 and pos(8) = 3/12 + 2/3 = 0.9166667. Residuals 0.
  EXPECT_NEAR(v::histogram_position_from_luminance(p.min_average_luminance / 0.18, p),
              0.24509219257886927, 1e-12);
  EXPECT_NEAR(v::histogram_position_from_luminance(p.max_average_luminance / 0.18, p), 11.0 / 12.0,
              1e-15);
}

TEST(EyeAdaptationParameters, LensAttenuationAndClamps) {
  v::EyeAdaptationSettings s = v::default_settings(true);
  s.lens_attenuation = 0.65;  // "0.65 to match previous versions (1 cd/m² → 1.2 at EV100)"
  v::EyeAdaptationParameters p = v::compute_eye_adaptation_parameters(s);
  // LuminanceMax = 0.78/0.65 = 1.2; log2 1.2 = ln 1.2/ln 2 = 0.18232156/0.69314718 = 0.26303441.
  // Scale unchanged (1/30); Bias = (10 − 0.26303441)/30 = 0.32456552. Residuals ≤ 5.6e-17
  // (Bias), 0 (the rest).
  EXPECT_NEAR(p.luminance_max, 1.2, 1e-15);
  EXPECT_NEAR(p.histogram_log_max, 20.263034405833794, 1e-13);
  EXPECT_NEAR(p.histogram_scale, 1.0 / 30.0, 1e-16);
  EXPECT_NEAR(p.histogram_bias, 0.3245655198055402, 1e-13);

  s.lens_attenuation = 0.0;  // max(q, 0.01) → 78
  EXPECT_NEAR(v::compute_eye_adaptation_parameters(s).luminance_max, 78.0, 1e-13);

  // Percent clamps [1, 99], then Low = min(Low, High).
  s = v::default_settings(true);
  s.low_percent = 95.0;
  s.high_percent = 150.0;
  p = v::compute_eye_adaptation_parameters(s);
  EXPECT_NEAR(p.exposure_high_percent, 0.99, 2e-16);  // residual 0
  EXPECT_NEAR(p.exposure_low_percent, 0.95, 2e-16);   // residual 1.1e-16 (95·0.01)
  s.low_percent = 0.0;
  s.high_percent = 40.0;
  p = v::compute_eye_adaptation_parameters(s);
  EXPECT_NEAR(p.exposure_low_percent, 0.01, 1e-17);
  s.low_percent = 60.0;
  EXPECT_NEAR(v::compute_eye_adaptation_parameters(s).exposure_low_percent, 0.4, 1e-16);

  // LogMin = min(LogMin, LogMax − 1): legacy −5/−5.5 → LogMin −6.5, Scale 1.
  s = v::default_settings(false);
  s.histogram_log_min = -5.0;
  s.histogram_log_max = -5.5;
  p = v::compute_eye_adaptation_parameters(s);
  EXPECT_EQ(p.histogram_log_min, -6.5);
  EXPECT_EQ(p.histogram_scale, 1.0);
  EXPECT_EQ(p.histogram_bias, 6.5);

  // Manual mode: white points EV100ToLuminance(1, 0) = 1, GreyMult 1, forced to target.
  s = v::default_settings(true);
  s.method = v::AutoExposureMethod::kManual;
  p = v::compute_eye_adaptation_parameters(s);
  EXPECT_EQ(p.min_average_luminance, 0.18);
  EXPECT_EQ(p.max_average_luminance, 0.18);
  EXPECT_EQ(p.grey_mult, 1.0);
  EXPECT_EQ(p.force_target, 1.0);
  // Basic mode: LuminanceMin is the 0.0001 epsilon, not 2^LogMin.
  s.method = v::AutoExposureMethod::kBasic;
  EXPECT_EQ(v::compute_eye_adaptation_parameters(s).luminance_min, 0.0001);
}

TEST(Ev100, Helpers) {
  // EV100ToLog2(1.2, 0) = log2 1.2; EV100ToLuminance(1, 3) = 8; LuminanceToEV100(1, 1/1024) = −10;
  // Log2ToEV100 inverts EV100ToLog2. Residuals 0.
  EXPECT_NEAR(v::ev100_to_log2(1.2, 0.0), 0.2630344058337938, 1e-15);
  EXPECT_EQ(v::ev100_to_luminance(1.0, 3.0), 8.0);
  EXPECT_EQ(v::luminance_to_ev100(1.0, 1.0 / 1024.0), -10.0);
  EXPECT_NEAR(v::log2_to_ev100(1.2, v::ev100_to_log2(1.2, -7.25)), -7.25, 1e-15);
}

// ---------------------------------------------------------------------------------------------
// Histogram.

// A range with binary-exact Scale and Bias: legacy, log2 range [−16, 16] → Scale 1/32, Bias 1/2,
// position = log2(L)/32 + 1/2, bucket coordinate f = 63·position.
v::EyeAdaptationParameters binary_range_params(double black_influence) {
  v::EyeAdaptationSettings s = v::default_settings(false);
  s.histogram_log_min = -16.0;
  s.histogram_log_max = 16.0;
  s.black_histogram_bucket_influence = black_influence;
  return v::compute_eye_adaptation_parameters(s);
}

TEST(Histogram, SyntheticImageBucketsByHand) {
  const v::EyeAdaptationParameters p = binary_range_params(0.0);
  ASSERT_EQ(p.histogram_scale, 1.0 / 32.0);
  ASSERT_EQ(p.histogram_bias, 0.5);
  // 4×2 image, grey values (mean RGB = the value):
  //   1, 1   → log2 0  → f = 31.5  → buckets 31, 32 get 0.5 each (twice)
  //   256    → log2 8  → f = 47.25 → 47: 0.75, 48: 0.25
  //   2^−8   → f = 15.75 → 15: 0.25, 16: 0.75
  //   0      → L = LuminanceMin = 2^−16 → f = 0 → bucket 0 with weight 1·influence(0) = 0
  //   NaN    → max(NaN, LuminanceMin) = LuminanceMin on D3D → same as black
  //   2^16   → f = 63 → bucket 63: 1;  2^20 → saturate → f = 63 → bucket 63: 1
  // Stored = raw sum · 0.5/(4·2) = raw/16.
  Image img(4, 2);
  const double values[8] = {1.0, 1.0, 256.0, 1.0 / 256.0, 0.0, kNaN, 65536.0, 1048576.0};
  for (int i = 0; i < 8; ++i) set_grey(img, i % 4, i / 4, values[i]);
  const v::Histogram h = v::build_histogram(img, p);
  v::Histogram want{};
  want[31] = 1.0 / 16;
  want[32] = 1.0 / 16;
  want[47] = 0.75 / 16;
  want[48] = 0.25 / 16;
  want[15] = 0.25 / 16;
  want[16] = 0.75 / 16;
  want[63] = 2.0 / 16;
  // Residual 0: every weight is a multiple of 2^−19.
  for (int i = 0; i < v::kHistogramSize; ++i) EXPECT_EQ(h[i], want[i]) << "bucket " << i;
  EXPECT_EQ(v::histogram_sum(h), 6.0 / 16);
  EXPECT_EQ(v::histogram_max(h), 2.0 / 16);
}

TEST(Histogram, BlackBucketInfluenceAndPreExposure) {
  // Influence 1: the black and NaN pixels put weight 1 each on bucket 0.
  const v::EyeAdaptationParameters p = binary_range_params(1.0);
  Image img(2, 1);
  set_grey(img, 0, 0, 0.0);
  set_grey(img, 1, 0, kNaN);
  v::Histogram h = v::build_histogram(img, p);
  EXPECT_EQ(h[0], 2.0 * 0.5 / 2.0);
  EXPECT_EQ(v::histogram_sum(h), h[0]);

  // Pre-exposure: a pixel stored as 4 with OneOverPreExposure 1/4 is luminance 1 → f = 31.5.
  Image one(1, 1);
  set_grey(one, 0, 0, 4.0);
  h = v::build_histogram(one, p, 0.25);
  EXPECT_EQ(h[31], 0.25);
  EXPECT_EQ(h[32], 0.25);
}

TEST(Histogram, EyeAdaptationLuminanceIsMeanRgbClamped) {
  const v::EyeAdaptationParameters p =
      v::compute_eye_adaptation_parameters(v::default_settings(true));
  // mean(0.3, 0.6, 0.9) = 0.6 (not 0.3·0.3 + 0.59·0.6 + 0.11·0.9). Residual 0.
  EXPECT_NEAR(v::eye_adaptation_luminance({0.3, 0.6, 0.9}, p), 0.6, 1e-15);
  EXPECT_EQ(v::eye_adaptation_luminance({0, 0, 0}, p), 1.0 / 1024.0);
  EXPECT_EQ(v::eye_adaptation_luminance({kNaN, 1, 1}, p), 1.0 / 1024.0);
  EXPECT_EQ(v::eye_adaptation_luminance({-5, -5, -5}, p), 1.0 / 1024.0);
}

// Histogram with weight 1 in bucket 10, 8 in bucket 20, 1 in bucket 50 (total 10).
v::Histogram three_bucket_histogram() {
  v::Histogram h{};
  h[10] = 1.0;
  h[20] = 8.0;
  h[50] = 1.0;
  return h;
}

// Grey whose log2 sits at histogram position q under the extended defaults: log2 L = 30q − 10.
double grey_at_position(double q) {
  return std::exp2(30.0 * q - 10.0);
}

TEST(Histogram, PlaceInHistogramByHand) {
  const v::EyeAdaptationParameters p =
      v::compute_eye_adaptation_parameters(v::default_settings(true));
  const v::Histogram h = three_bucket_histogram();
  // Bucket i counts between positions i/63 and (i+1)/63.
  //   q = 5/63:    below everything → 0
  //   q = 10.5/63: half of bucket 10 → 0.5/10 = 0.05
  //   q = 20.5/63: bucket 10 + half of bucket 20 → (1 + 4)/10 = 0.5
  //   q = 21/63:   buckets 10 and 20 → 0.9
  //   q = 60/63:   all → 1
  // Residuals ≤ 1.4e-15 (the positions are not binary-exact).
  const struct {
    double q, want;
  } cases[] = {
      {5.0 / 63, 0.0}, {10.5 / 63, 0.05}, {20.5 / 63, 0.5}, {21.0 / 63, 0.9}, {60.0 / 63, 1.0}};
  for (const auto& c : cases) {
    const double g = grey_at_position(c.q);
    EXPECT_NEAR(v::place_in_histogram({g, g, g}, h, p), c.want, 1e-12) << "q = " << c.q;
  }
  // No LuminanceMin clamp here: black → log2 0 = −∞ → 0; NaN and negative means → log2 = NaN →
  // every saturate(NaN) = 0 → 0. An empty histogram → 0/0 = NaN.
  EXPECT_EQ(v::place_in_histogram({0, 0, 0}, h, p), 0.0);
  EXPECT_EQ(v::place_in_histogram({kNaN, 1, 1}, h, p), 0.0);
  EXPECT_EQ(v::place_in_histogram({-1, -1, -1}, h, p), 0.0);
  EXPECT_EQ(v::place_in_histogram({INFINITY, 1, 1}, h, p), 1.0);
  EXPECT_TRUE(std::isnan(v::place_in_histogram({1, 1, 1}, v::Histogram{}, p)));
}

TEST(Histogram, AverageLuminanceWithoutOutliersByHand) {
  const v::EyeAdaptationParameters p =
      v::compute_eye_adaptation_parameters(v::default_settings(true));
  // Buckets 21: 1, 42: 8, 63: 1; Low 10 % of 10 = 1 removes bucket 21, High 90 % = 9 keeps 8 of
  // bucket 42 and nothing of 63. Bucket 42 ↔ position 2/3 ↔ log2 = 30·2/3 − 10 = 10 → 1024.
  // Residual 0.
  v::Histogram h{};
  h[21] = 1.0;
  h[42] = 8.0;
  h[63] = 1.0;
  EXPECT_NEAR(v::average_luminance_without_outliers(h, p), 1024.0, 1e-9);
}

// ---------------------------------------------------------------------------------------------
// Panel geometry and the frame, 1920×1080.

TEST(Panel, GeometryFor1920x1080) {
  const v::PanelGeometry g = v::panel_geometry(1920, 1080);
  // LeftTop = (0 + 64, 1080 − 128 − 32) = (64, 920); Size = (1920 − 128, 128) = (1792, 128);
  // last interior pixel (64 + 1791, 920 + 127) = (1855, 1047).
  EXPECT_EQ(g.left, 64);
  EXPECT_EQ(g.top, 920);
  EXPECT_EQ(g.width, 1792);
  EXPECT_EQ(g.height, 128);
  EXPECT_EQ(g.right(), 1855);
  EXPECT_EQ(g.bottom(), 1047);
  EXPECT_EQ(v::distance_to_rect(64, 920, g), 0.0);
  EXPECT_EQ(v::distance_to_rect(1855, 1047, g), 0.0);
  EXPECT_EQ(v::distance_to_rect(1856, 1047, g), 1.0);
  EXPECT_EQ(v::distance_to_rect(60, 916, g), std::sqrt(32.0));  // (4, 4) past the corner
}

// One 1920×1080 render shared by the panel tests: type 0 over a uniform scene (0.3, 0.6, 0.9, 1),
// extended defaults, EyeAdaptationResult 1/64, bias-only 2, average scene luminance 0.18,
// histogram bucket 16 = 0.5 and bucket 20 = 1, tone curve x/2.
class Panel1080 : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new Image(uniform_image(1920, 1080, 0.3, 0.6, 0.9));
    hdr_ = new Image(uniform_image(1920, 1080, 1.0, 1.0, 1.0));
    v::VisualizeHdrInputs in;
    in.scene_color = scene_;
    in.hdr_scene_color = hdr_;
    in.params = v::compute_eye_adaptation_parameters(v::default_settings(true));
    in.eye.exposure = 1.0 / 64;
    in.eye.exposure_bias_only = 2.0;
    in.eye.average_scene_luminance = 0.18;
    in.histogram[16] = 0.5;
    in.histogram[20] = 1.0;
    in.tone_curve = half_curve();
    result_ = new v::VisualizeHdrResult(v::visualize_hdr(in));
  }
  static void TearDownTestSuite() {
    delete result_;
    delete scene_;
    delete hdr_;
  }
  static const Image& out() { return result_->image; }
  static Image* scene_;
  static Image* hdr_;
  static v::VisualizeHdrResult* result_;
};
Image* Panel1080::scene_ = nullptr;
Image* Panel1080::hdr_ = nullptr;
v::VisualizeHdrResult* Panel1080::result_ = nullptr;

TEST_F(Panel1080, FrameRingsAndRoundCorners) {
  // Above the left edge (x = 64, u = 0 → Colorize blue): distance 1 black, 2…5 blue, 6 black,
  // 7 scene. Residual 0.
  expect_pixel(out(), 64, 919, 0, 0, 0, 0);
  expect_pixel(out(), 64, 918, 0, 0, 1, 0);
  expect_pixel(out(), 64, 915, 0, 0, 1, 0);
  expect_pixel(out(), 64, 914, 0, 0, 0, 0);
  expect_pixel(out(), 64, 913, 0.3, 0.6, 0.9, 0);
  // Below the middle (u = 896/1792 = 0.5 → green), distance 3.
  expect_pixel(out(), 960, 1050, 0, 1, 0, 0);
  // Past the bottom-right corner by (2, 2): distance 2.83, u > 1 → saturate → red.
  expect_pixel(out(), 1857, 1049, 1, 0, 0, 0);
  // Corner (60, 916): distance √32 = 5.657: black ring t = 0, band t = 0.657 →
  // lerp(blue, black, 0.657) = blue · (6 − √32) = 0.3431458. Residual 0.
  expect_pixel(out(), 60, 916, 0, 0, 0.3431457505076194, 1e-15);
  // (6, 6) past the corner: distance 8.49 → scene.
  expect_pixel(out(), 58, 914, 0.3, 0.6, 0.9, 0);
}

TEST_F(Panel1080, InteriorTintAndBars) {
  // Extended defaults: pos(2^−10) = 0 and pos(2^20) = 1, so the whole interior is the green
  // tint: lerp(black, (0.5, 0.8, 0.5), 0.5) = (0.25, 0.4, 0.25). Residual 0.
  expect_pixel(out(), 100, 1000, 0.25, 0.4, 0.25, 0);
  // Bucket 16 spans inset x 16·28 … 16·28 + 27 (1792/64 = 28 px per bucket) = x 512…539. Its
  // value 0.5 of the maximum draws where 0.5 ≥ 1 − y/128, i.e. inset y ≥ 64 (y ≥ 984).
  // Bar colour: lerp(tint, Colorize(448/1792 = 0.25), 0.5) = lerp((0.25, 0.4, 0.25),
  // (0.125, 0.5, 0.375), 0.5) = (0.1875, 0.45, 0.3125). Residual 0.
  expect_pixel(out(), 512, 984, 0.1875, 0.45, 0.3125, 0);
  expect_pixel(out(), 512, 983, 0.25, 0.4, 0.25, 0);
  // Bucket 20 (the maximum) fills its whole column, top row included (1 ≥ 1 − 0).
  // u = 560/1792 = 0.3125: t = |0.5 − 0.3125|·2 = 0.375, cold/heat = (0.3125, 0, 0.6875) →
  // Colorize = (0.1171875, 0.625, 0.2578125); bar = (0.18359375, 0.5125, 0.25390625).
  // Residual 0.
  expect_pixel(out(), 64 + 20 * 28, 920, 0.18359375, 0.5125, 0.25390625, 1e-15);
}

TEST_F(Panel1080, ToneCurveOverlay) {
  // Inset x 896 → u = 0.5 → log2 L = 30·0.5 − 10 = 5, L = 32; mapped = (32/64)/2 = 0.25, which
  // equals 1 − v at inset y 96 (y = 1016): mask 1 → white. One row up, 1 − 95/128 = 0.2578125:
  // mask = 1 − 100·0.0078125 = 0.21875 → tint + (1 − tint)·0.21875 = (0.4140625, 0.53125,
  // 0.4140625). Residuals ≤ 1.3e-14 (exp2 of a rounded position, times 100).
  expect_pixel(out(), 960, 1016, 1, 1, 1, 1e-12);
  expect_pixel(out(), 960, 1015, 0.4140625, 0.53125, 0.4140625, 1e-12);
  expect_pixel(out(), 960, 1010, 0.25, 0.4, 0.25, 0);
}

TEST_F(Panel1080, ExposureLinesAndLabels) {
  const v::VisualizeHdrText& t = result_->text;
  // Blue: pos(0.18/0.18) = pos(1) = 1/3 → 597.33 px; |inset − 597.33| < 3 → inset 595…600.
  // lerp(tint, blue, 0.5) = (0.125, 0.2, 0.625), alpha 1 → 0.5. Residuals 1.1e-13 (position),
  // 0 (colours); line positions residual 0.
  EXPECT_NEAR(t.average_luminance_px, 1792.0 / 3.0, 1e-12);
  expect_pixel(out(), 64 + 596, 1000, 0.125, 0.2, 0.625, 0);
  EXPECT_EQ(out().px(64 + 596, 1000)[3], 0.5);
  expect_pixel(out(), 64 + 594, 1000, 0.25, 0.4, 0.25, 0);
  // Purple: EyeAdaptationResult without bias = (1/64)/2 = 1/128; pos(128) = (7 + 10)/30 = 17/30 →
  // 1015.47 px; label EV = log2 128 = 7. Line for inset 1014…1017 below y = top + 9.
  EXPECT_EQ(t.exposure_without_bias_ev, 7.0);
  EXPECT_NEAR(t.exposure_without_bias_px, 1792.0 * 17.0 / 30.0, 1e-9);
  expect_pixel(out(), 64 + 1015, 1000, 0.5, 0, 0.5, 0);
  EXPECT_EQ(out().px(64 + 1015, 1000)[3], 0.0);
  expect_pixel(out(), 64 + 1015, 929, 0.25, 0.4, 0.25, 0);  // y = top + 9: not drawn
  // White: pos(64) = 16/30 → 955.73 px; EV100 = log2(64/1) = 6. Line below y = top + 18.
  EXPECT_EQ(t.exposure_ev100, 6.0);
  EXPECT_NEAR(t.exposure_px, 1792.0 * 16.0 / 30.0, 1e-9);
  expect_pixel(out(), 64 + 956, 1000, 1, 1, 1, 0);
  expect_pixel(out(), 64 + 956, 938, 0.25, 0.4, 0.25, 0);
  // Label glyph rectangles: HistogramLeftTop + (trunc(px − 51), 1), six 8-px cells:
  // purple 64 + trunc(964.47) = 1028, white 64 + trunc(904.73) = 968; y 921…928.
  bool purple = false, white = false;
  for (const v::GlyphRect& r : t.glyph_rects) {
    if (r.rect.x0 == 1028 && r.rect.x1 == 1076 && r.rect.y0 == 921 && r.rect.y1 == 929)
      purple = true;
    if (r.rect.x0 == 968 && r.rect.x1 == 1016 && r.rect.y0 == 921 && r.rect.y1 == 929) white = true;
  }
  EXPECT_TRUE(purple);
  EXPECT_TRUE(white);
  // Canvas axis labels: EV100 −10, −2.5, 5, 12.5, 20 at x = 72 + trunc(i·1772/4) − 5.
  const double want_ev[5] = {-10, -2.5, 5, 12.5, 20};
  const double want_x[5] = {67, 510, 953, 1396, 1839};
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(t.axis_ev100[i], want_ev[i]);
    EXPECT_EQ(t.axis_anchor[i][0], want_x[i]);
    EXPECT_EQ(t.axis_anchor[i][1], 1026.0);
  }
}

TEST(Labels, WhiteLabelDividesByLuminanceMaxPurpleDoesNot) {
  // LensAttenuation 0.65 → LuminanceMax 1.2: white EV100 = log2(64/1.2) = 6 − 0.2630344 =
  // 5.7369656; purple stays log2(1/EARwob) = 6 (bias-only 1). Residual 0.
  v::EyeAdaptationSettings s = v::default_settings(true);
  s.lens_attenuation = 0.65;
  const Image img = uniform_image(256, 256, 0.18, 0.18, 0.18);
  v::VisualizeHdrInputs in;
  in.scene_color = &img;
  in.hdr_scene_color = &img;
  in.params = v::compute_eye_adaptation_parameters(s);
  in.eye.exposure = 1.0 / 64;
  in.tone_curve = half_curve();
  const v::VisualizeHdrResult r = v::visualize_hdr(in);
  EXPECT_NEAR(r.text.exposure_ev100, 5.7369655941662066, 1e-14);
  EXPECT_EQ(r.text.exposure_without_bias_ev, 6.0);
  // Meter: L = 0.18 → EV100 = log2((0.18/0.18)/1.2) = −0.2630344. Residual 9.1e-15 (the
  // 441-sample mean of 0.18).
  EXPECT_NEAR(r.text.meter_ev100, -0.2630344058337938, 5e-14);
}

// ---------------------------------------------------------------------------------------------
// Meters (400×300: centre (200, 150); illuminance centre (200, 50)).

v::VisualizeHdrInputs small_inputs(const Image* scene, const Image* hdr) {
  v::VisualizeHdrInputs in;
  in.scene_color = scene;
  in.hdr_scene_color = hdr;
  in.params = v::compute_eye_adaptation_parameters(v::default_settings(true));
  in.tone_curve = half_curve();
  return in;
}

TEST(Meter, BilinearBlockAverageAndEv100) {
  // Samples sit at texel coordinates (200 + o − 0.5, 150 + p − 0.5), o, p ∈ −10…10: each blends
  // texels 199 + o and 200 + o (½ each) and rows 149 + p, 150 + p. A texel in row 150 is read
  // with total weight ½ + ½ = 1 over the rows. Along x: texel 200 gets ½ (o = 0) + ½ (o = 1) = 1;
  // texel 210 only ½ (o = 10); texel 189 only ½ (o = −10); texels 211 and 188 none.
  // HDR zeros except 200: 441, 210: 882, 189: 882, 211 and 188: 1e6 →
  // mean = (441 + 441 + 441)/441 = 3; Luminance = 3·(0.3 + 0.59 + 0.11) = 3;
  // EV100 = log2((3/0.18)/1) = log2 16.667 = 4.0588937. Residuals 0.
  Image hdr(400, 300);
  set_grey(hdr, 200, 150, 441.0);
  set_grey(hdr, 210, 150, 882.0);
  set_grey(hdr, 189, 150, 882.0);
  set_grey(hdr, 211, 150, 1e6);
  set_grey(hdr, 188, 150, 1e6);
  const Image scene = uniform_image(400, 300, 0.2, 0.4, 0.6);
  const v::VisualizeHdrResult r = v::visualize_hdr(small_inputs(&scene, &hdr));
  EXPECT_NEAR(r.text.meter_luminance, 3.0, 1e-13);
  EXPECT_NEAR(r.text.meter_ev100, 4.058893689053568, 1e-13);
  EXPECT_EQ(r.text.meter_luminance_format, v::NumberFormat::kFraction);

  // Pre-exposure: the same HDR with OneOverPreExposure 1/4 reads 0.75.
  v::VisualizeHdrInputs in = small_inputs(&scene, &hdr);
  in.one_over_pre_exposure = 0.25;
  EXPECT_NEAR(v::visualize_hdr(in).text.meter_luminance, 0.75, 1e-13);
}

TEST(Meter, SwatchRingAndRegion) {
  const Image scene = uniform_image(400, 300, 0.2, 0.4, 0.6);
  const Image hdr = uniform_image(400, 300, 1.0, 1.0, 1.0);
  const v::VisualizeHdrResult r = v::visualize_hdr(small_inputs(&scene, &hdr));
  // Swatch (|dx|, |dy| ≤ 8) = the average scene colour = the uniform colour; ring at 9; scene
  // beyond. Residual 3.2e-15 (rounding of the 441-sample sums).
  expect_pixel(r.image, 203, 148, 0.2, 0.4, 0.6, 1e-14);
  expect_pixel(r.image, 209, 150, 1, 1, 1, 0);
  expect_pixel(r.image, 191, 150, 1, 1, 1, 0);
  expect_pixel(r.image, 200, 141, 1, 1, 1, 0);
  expect_pixel(r.image, 210, 150, 0.2, 0.4, 0.6, 0);
  // Luminance 1 → EV100 log2(1/0.18) = 2.4739312; glyph rectangles at centre + (11, 11) and
  // (11, 22).
  EXPECT_NEAR(r.text.meter_ev100, 2.4739311883324122, 1e-14);
  bool value = false, ev = false;
  for (const v::GlyphRect& g : r.text.glyph_rects) {
    if (g.rect.x0 == 211 && g.rect.y0 == 161 && g.rect.x1 == 211 + 84 && g.rect.y1 == 169)
      value = true;
    if (g.rect.x0 == 211 && g.rect.y0 == 172 && g.rect.x1 == 311 && g.rect.y1 == 180) ev = true;
  }
  EXPECT_TRUE(value);
  EXPECT_TRUE(ev);
}

TEST(Meter, IlluminanceMeter) {
  // HDR uniform 0.5 → E = 0.5·π per channel, lux = Luminance(E) = 0.5π. The ring is at
  // |dx| or |dy| = 9 around (200, 50); the region spans −20 < dx < 300, −20 < dy < 40.
  // Residuals 0.
  const Image scene = uniform_image(400, 300, 0.2, 0.4, 0.6);
  const Image hdr = uniform_image(400, 300, 0.5, 0.5, 0.5);
  v::VisualizeHdrInputs in = small_inputs(&scene, &hdr);
  in.params.visualize_debug_type = 2;  // background = mean RGB = 0.5, to tell regions apart
  const v::VisualizeHdrResult r = v::visualize_hdr(in);
  EXPECT_NEAR(r.text.illuminance_lux, 0.5 * std::numbers::pi, 1e-14);
  EXPECT_NEAR(r.text.illuminance_rgb[1], 0.5 * std::numbers::pi, 1e-14);
  expect_pixel(r.image, 209, 50, 1, 1, 1, 0);
  expect_pixel(r.image, 200, 50, 0.2, 0.4, 0.6, 0);  // no swatch: scene colour
  expect_pixel(r.image, 181, 50, 0.2, 0.4, 0.6, 0);  // dx = −19: inside
  expect_pixel(r.image, 180, 50, 0.5, 0.5, 0.5, 0);  // dx = −20: background (type 2)
  expect_pixel(r.image, 399, 89, 0.2, 0.4, 0.6, 0);  // dy = 39: inside
  expect_pixel(r.image, 399, 90, 0.5, 0.5, 0.5, 0);  // dy = 40: background

  in.illuminance_meter_enabled = false;
  expect_pixel(v::visualize_hdr(in).image, 209, 50, 0.5, 0.5, 0.5, 0);
}

// ---------------------------------------------------------------------------------------------
// VisualizeDebugType 1 and 2 backgrounds (pixels outside the meters and the panel: x < 58).

TEST(DebugType, PercentileColours) {
  Image hdr = uniform_image(400, 300, 1.0, 1.0, 1.0);
  const struct {
    int y;
    double q;
    Vec3 want;
  } cases[] = {
      {5, 5.0 / 63, {0.5, 0, 0}},        // percentile 0 < Low 0.1 → red 0.5
      {10, 10.5 / 63, {0.5, 0, 0}},      // 0.05 < 0.1 → red
      {15, 20.5 / 63, {0.5, 0.5, 0.5}},  // 0.5 → grey
      {20, 21.0 / 63, {0, 0, 0.5}},      // 0.9 ≥ High 0.9 → blue 0.5
      {25, 60.0 / 63, {0, 0, 0.5}},      // 1 → blue
  };
  for (const auto& c : cases) set_grey(hdr, 5, c.y, grey_at_position(c.q));
  set_grey(hdr, 5, 30, 0.0);   // black: log2 0 = −∞ → 0 → red
  set_grey(hdr, 5, 35, kNaN);  // NaN → every term 0 → 0 → red
  const Image scene = uniform_image(400, 300, 0.2, 0.4, 0.6);
  v::VisualizeHdrInputs in = small_inputs(&scene, &hdr);
  in.params.visualize_debug_type = 1;
  in.histogram = three_bucket_histogram();
  const v::VisualizeHdrResult r = v::visualize_hdr(in);
  // The 0.9 case sits on the High boundary: its computed percentile is within 1e-15 of 0.9 either
  // way, so it is only checked to be red-free; the rest are exact colour constants.
  for (const auto& c : cases) {
    if (c.y == 20) {
      EXPECT_EQ(r.image.px(5, c.y)[0], 0.0);
      continue;
    }
    expect_pixel(r.image, 5, c.y, c.want[0], c.want[1], c.want[2], 1e-12);
  }
  expect_pixel(r.image, 5, 30, 0.5, 0, 0, 0);
  expect_pixel(r.image, 5, 35, 0.5, 0, 0, 0);
  EXPECT_FALSE(r.alpha_defined);

  // An empty histogram: 0/0 → NaN background, and the NaN survives the frame's lerps with t = 0
  // into the panel interior (a + 0·(NaN − a) = NaN), while the tint is added on top.
  in.histogram = v::Histogram{};
  const v::VisualizeHdrResult empty = v::visualize_hdr(in);
  EXPECT_TRUE(std::isnan(empty.image.px(5, 5)[0]));
  const v::PanelGeometry g = v::panel_geometry(400, 300);  // interior y 140…267; meter to 191
  EXPECT_TRUE(std::isnan(empty.image.px(g.left + 10, g.top + 60)[1]));
}

TEST(DebugType, LuminanceTimesScale) {
  Image hdr = uniform_image(400, 300, 0.3, 0.6, 0.9);
  set_grey(hdr, 5, 10, 0.0);
  const Image scene = uniform_image(400, 300, 0.2, 0.4, 0.6);
  v::VisualizeHdrInputs in = small_inputs(&scene, &hdr);
  in.params.visualize_debug_type = 2;
  in.luminance_scale = 2.0;
  const v::VisualizeHdrResult r = v::visualize_hdr(in);
  // mean(0.3, 0.6, 0.9)·2 = 1.2; black → LuminanceMin·2 = 2^−9. Residual 0.
  expect_pixel(r.image, 5, 5, 1.2, 1.2, 1.2, 1e-15);
  expect_pixel(r.image, 5, 10, 1.0 / 512, 1.0 / 512, 1.0 / 512, 0);
  // Type 3 (no branch) → black.
  in.params.visualize_debug_type = 3;
  expect_pixel(v::visualize_hdr(in).image, 5, 5, 0, 0, 0, 0);
}

}  // namespace
