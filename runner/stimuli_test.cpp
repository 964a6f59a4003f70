// The stimuli against numbers from outside the code: published ColorChecker values, the PQ and
// sRGB standards, the BT.709 luminance, splitmix64's published first output.
#include "runner/stimuli.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <tuple>

#include "color/st2084.h"
#include "reference/color/ue_matrices.h"

namespace {

using hdrc::Image;
using hdrc::make_stimulus;

Image make(const std::string& name, int w, int h, const hdrc::StimulusParams& p = {}) {
  auto img = make_stimulus(name, w, h, p);
  EXPECT_TRUE(img.ok()) << (img ? "" : img.error().to_string());
  return img ? *img : Image();
}

TEST(Stimuli, EveryTableEntryBuildsAtItsDefaultSize) {
  for (const auto& s : hdrc::stimulus_table()) {
    auto img = make_stimulus(s.name, 0, 0);
    ASSERT_TRUE(img.ok()) << s.name;
    EXPECT_GT(img->width, 0) << s.name;
    EXPECT_GT(img->height, 0) << s.name;
    for (const auto& p : s.params) EXPECT_FALSE(p.description.empty()) << s.name << p.name;
  }
}

// Every 10-bit code exactly once per 1024 pixels, as the exact value code / 1023, whatever the
// image's shape; the second block of 1024 is red only.
TEST(Stimuli, PqCodesHitEveryCodeExactlyOnce) {
  for (auto [w, h] : {std::pair{32, 32}, std::pair{1024, 1}, std::pair{64, 16}}) {
    const Image img = make("pq_codes", w, h);
    std::multiset<int> codes;
    for (size_t i = 0; i < img.pixel_count(); ++i) {
      const double v = img.data[i * 4];
      const double code = v * 1023.0;
      ASSERT_EQ(code, std::round(code)) << i;
      ASSERT_EQ(v, std::round(code) / 1023.0);
      EXPECT_EQ(img.data[i * 4 + 1], v);
      EXPECT_EQ(img.data[i * 4 + 2], v);
      codes.insert(static_cast<int>(code));
    }
    ASSERT_EQ(codes.size(), 1024u);
    for (int c = 0; c < 1024; ++c) EXPECT_EQ(codes.count(c), 1u) << c;
  }
  const Image two = make("pq_codes", 64, 32);
  EXPECT_EQ(two.data[(1024 + 5) * 4 + 0], 5.0 / 1023.0);
  EXPECT_EQ(two.data[(1024 + 5) * 4 + 1], 0.0);
  auto small = make_stimulus("pq_codes", 16, 16);
  ASSERT_FALSE(small.ok());
  EXPECT_NE(small.error().message.find("needs at least 1024 pixels"), std::string::npos);
}

TEST(Stimuli, LogRampSpansItsRangeEvenlyInLog10) {
  const Image img = make("log_ramp", 9, 4);
  // 1e-4 nits .. 1e4 nits in 8 steps of one decade; 1.0 = 100 nits.
  for (int x = 0; x < 9; ++x)
    EXPECT_NEAR(img.px(x, 0)[0], std::pow(10.0, x - 6.0), 1e-15 * std::pow(10.0, x - 6.0) * 8);
  EXPECT_EQ(img.px(3, 1)[1], 0.0);  // the red row
  const Image custom = make("log_ramp", 2, 1, {{"min_nits", {1.0}}, {"max_nits", {100.0}}});
  EXPECT_DOUBLE_EQ(custom.px(0, 0)[0], 0.01);
  EXPECT_DOUBLE_EQ(custom.px(1, 0)[0], 1.0);
  auto bad = make_stimulus("log_ramp", 8, 1, {{"min_nits", {10.0}}, {"max_nits", {1.0}}});
  EXPECT_FALSE(bad.ok());
}

// The table as published (Pascale 2006; the same values as the hex codes of the ColorChecker
// article's sRGB column), typed here independently of runner/stimuli.cpp.
TEST(Stimuli, ColorCheckerMatchesThePublishedSrgbValues) {
  const char* kHex[24] = {"735244", "c29682", "627a9d", "576c43", "8580b1", "67bdaa",
                          "d67e2c", "505ba6", "c15a63", "5e3c6c", "9dbc40", "e0a32e",
                          "383d96", "469449", "af363c", "e7c71f", "bb5695", "0885a1",
                          "f3f3f2", "c8c8c8", "a0a0a0", "7a7a79", "555555", "343434"};
  const auto& table = hdrc::stimulus_data::colorchecker24();
  ASSERT_EQ(table.size(), 24u);
  // One pixel per patch, exposures -2, 0, +3 stops.
  const Image img = make("colorchecker", 24, 3, {{"exposures", {-2.0, 0.0, 3.0}}});
  for (int i = 0; i < 24; ++i) {
    const long rgb = std::strtol(kHex[i], nullptr, 16);
    const int want[3] = {static_cast<int>(rgb >> 16), static_cast<int>((rgb >> 8) & 255),
                         static_cast<int>(rgb & 255)};
    EXPECT_EQ(table[i].r, want[0]) << table[i].name;
    EXPECT_EQ(table[i].g, want[1]) << table[i].name;
    EXPECT_EQ(table[i].b, want[2]) << table[i].name;
    for (int c = 0; c < 3; ++c) {
      // IEC 61966-2-1 decode written out: ((V + 0.055) / 1.055)^2.4 above 0.04045.
      const double v = want[c] / 255.0;
      const double lin = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
      EXPECT_DOUBLE_EQ(img.px(i, 1)[c], lin) << table[i].name << " channel " << c;
      EXPECT_DOUBLE_EQ(img.px(i, 0)[c], lin / 4.0);
      EXPECT_DOUBLE_EQ(img.px(i, 2)[c], lin * 8.0);
    }
  }
  // Independent plausibility check of the neutral row against the Munsell values the patch names
  // give (N9.5, N8, N6.5, N5, N3.5, N2): luminous reflectance from ASTM D1535's quintic
  // Y = 1.1914 V - 0.22533 V^2 + 0.23352 V^3 - 0.020484 V^4 + 0.00081939 V^5 (%). Measured charts
  // sit near, not on, their nominal notation: the largest gap is the white patch, 0.896 measured
  // against 0.878 for N9.5; a wrong table entry or decode would be off by far more.
  const double munsell[6] = {9.5, 8.0, 6.5, 5.0, 3.5, 2.0};
  for (int k = 0; k < 6; ++k) {
    const double v = munsell[k];
    const double y = (1.1914 * v - 0.22533 * v * v + 0.23352 * v * v * v -
                      0.020484 * v * v * v * v + 0.00081939 * v * v * v * v * v) /
                     100.0;
    const double* p = img.px(18 + k, 1);
    EXPECT_NEAR(hdrc::stimulus_data::rec709_luminance(p[0], p[1], p[2]), y, 0.02)
        << table[18 + k].name;
  }
}

TEST(Stimuli, PrimariesAreThePrimariesOfTheirGamut) {
  using namespace hdrc::ref;
  const Image srgb = make("primaries", 6, 2, {{"scales", {1.0, 10.0}}});
  EXPECT_EQ(srgb.px(0, 0)[0], 1.0);  // R
  EXPECT_EQ(srgb.px(0, 0)[1], 0.0);
  EXPECT_EQ(srgb.px(3, 1)[0], 0.0);  // C x 10
  EXPECT_EQ(srgb.px(3, 1)[1], 10.0);
  EXPECT_EQ(srgb.px(5, 1)[2], 0.0);  // Y x 10
  // AP1 primaries, read back through UE's working colour space ToAP1 (the float-cast matrices):
  // (k, 0, 0) up to float rounding of the pair.
  const Image ap1 = make("primaries", 6, 1, {{"gamut", {1}}, {"scales", {2.0}}});
  const WorkingColorSpace wcs = make_working_color_space(standard::kSrgb);
  const Vec3 expected[6] = {{2, 0, 0}, {0, 2, 0}, {0, 0, 2}, {0, 2, 2}, {2, 0, 2}, {2, 2, 0}};
  for (int x = 0; x < 6; ++x) {
    const double* p = ap1.px(x, 0);
    const Vec3 back = wcs.to_ap1 * Vec3{p[0], p[1], p[2]};
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(back[c], expected[x][c], 2e-6) << x << c;
  }
  EXPECT_LT(ap1.px(1, 0)[0], 0.0) << "AP1 green lies outside sRGB: negative red";
  // Rec.2020 via the standard (primaries-derived) matrix, checked against its inverse.
  const Image bt2020 = make("primaries", 6, 1, {{"gamut", {2}}, {"scales", {1.0}}});
  const Mat3 to_2020 = standard::rgb_to_rgb(standard::kSrgb, standard::kRec2020);
  for (int x = 0; x < 6; ++x) {
    const double* p = bt2020.px(x, 0);
    const Vec3 back = to_2020 * Vec3{p[0], p[1], p[2]};
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(back[c], expected[x][c] / 2.0, 1e-12);
  }
  // BT.2020 red in BT.709: the first column of the BT.2020 → BT.709 matrix of ITU-R BT.2087-0
  // (1.6605, −0.1246, −0.0182).
  EXPECT_NEAR(bt2020.px(0, 0)[0], 1.6605, 1e-4);
  EXPECT_NEAR(bt2020.px(0, 0)[1], -0.1246, 1e-4);
  EXPECT_NEAR(bt2020.px(0, 0)[2], -0.0182, 1e-4);
}

TEST(Stimuli, HueSweepRowsHaveTheirLuminance) {
  const Image img = make("hue_sweep", 12, 4, {{"luminances", {10.0, 1000.0}}});
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 12; ++x) {
      const double* p = img.px(x, y);
      EXPECT_NEAR(hdrc::stimulus_data::rec709_luminance(p[0], p[1], p[2]), y < 2 ? 0.1 : 10.0,
                  1e-12);
    }
  // Hue 0 is red, 120 green, 240 blue (x = 0, 4, 8 of 12).
  EXPECT_EQ(img.px(0, 0)[1], 0.0);
  EXPECT_EQ(img.px(4, 0)[0], 0.0);
  EXPECT_EQ(img.px(8, 0)[1], 0.0);
  EXPECT_NEAR(img.px(4, 0)[1], 0.1 / 0.7152, 1e-12);
}

TEST(Stimuli, NearBlackAndAbovePeak) {
  const Image nb = make("near_black", 11, 4);
  EXPECT_EQ(nb.px(0, 0)[0], 0.0);
  EXPECT_DOUBLE_EQ(nb.px(10, 0)[0], 1e-4);  // 0.01 nits
  EXPECT_DOUBLE_EQ(nb.px(5, 0)[0], 0.5e-4);
  const Image ap = make("above_peak", 4, 1);
  EXPECT_DOUBLE_EQ(ap.px(0, 0)[0], 10.0);     // 1000 nits
  EXPECT_DOUBLE_EQ(ap.px(3, 0)[0], 10000.0);  // 1e6 nits
  EXPECT_GT(ap.px(2, 0)[0], 100.0) << "above PQ's 10 000 nits";
}

// n^3 points, each exactly once, uniform in PQ: PQ(value x 100 nits) = k / (n - 1).
TEST(Stimuli, PqLatticeIsUniformInPq) {
  const int n = 5;
  const Image img = make("pq_lattice", 0, 0, {{"n", {n}}});
  ASSERT_EQ(img.width, n * n);
  ASSERT_EQ(img.height, n);
  std::set<std::tuple<int, int, int>> points;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n * n; ++x) {
      const double* p = img.px(x, y);
      int k[3];
      for (int c = 0; c < 3; ++c) {
        // Code 0 decodes to exactly 0 nits (PQ of 0 nits is c1^m2 = 7.3e-7, not 0).
        const double pq = p[c] == 0.0 ? 0.0 : hdrc::ref::st2084::pq_from_nits(p[c] * 100.0);
        k[c] = static_cast<int>(std::lround(pq * (n - 1)));
        EXPECT_NEAR(pq, k[c] / double(n - 1), 1e-12);
      }
      // The LUT layout: (r + n b, g).
      EXPECT_EQ(k[0], x % n);
      EXPECT_EQ(k[2], x / n);
      EXPECT_EQ(k[1], y);
      points.emplace(k[0], k[1], k[2]);
    }
  EXPECT_EQ(points.size(), static_cast<size_t>(n * n * n));
  EXPECT_FALSE(make_stimulus("pq_lattice", 10, 10, {{"n", {n}}}).ok()) << "100 < 125 pixels";
}

TEST(Stimuli, SpecialRampHoldsEverySpecialValue) {
  const Image img = make("special_ramp", 64, 1);
  bool nan = false, pinf = false, ninf = false, nzero = false, denorm = false, neg = false;
  for (int x = 0; x < 64; ++x) {
    const double v = img.px(x, 0)[0];
    nan |= std::isnan(v);
    pinf |= v == INFINITY;
    ninf |= v == -INFINITY;
    nzero |= v == 0.0 && std::signbit(v);
    denorm |= std::fpclassify(static_cast<float>(v)) == FP_SUBNORMAL;
    neg |= v < 0 && std::isfinite(v);
  }
  EXPECT_TRUE(nan && pinf && ninf && nzero && denorm && neg);
}

// splitmix64 seeded with 0: first output 0xE220A8397B1DCDAF (Vigna's reference splitmix64.c).
TEST(Stimuli, RandomIsSplitMix64AndSeeded) {
  const Image a = make("random", 8, 2, {{"seed", {0}}, {"min_nits", {1.0}}, {"max_nits", {1e4}}});
  const double u = static_cast<double>(0xE220A8397B1DCDAFull >> 11) * 0x1.0p-53;
  EXPECT_DOUBLE_EQ(a.data[0], std::exp(std::log(1.0) + (std::log(1e4) - std::log(1.0)) * u) / 100);
  const Image b = make("random", 8, 2, {{"seed", {0}}, {"min_nits", {1.0}}, {"max_nits", {1e4}}});
  EXPECT_EQ(a.data, b.data);
  const Image c = make("random", 8, 2, {{"seed", {7}}, {"min_nits", {1.0}}, {"max_nits", {1e4}}});
  EXPECT_NE(a.data, c.data);
  for (size_t i = 0; i < a.pixel_count(); ++i)
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_GE(a.data[i * 4 + ch], 0.01);
      EXPECT_LE(a.data[i * 4 + ch], 100.0);
    }
}

TEST(Stimuli, UiOverlayIsPremultipliedAndBloomIsSmooth) {
  const Image ui = make("ui_overlay", 32, 8);
  for (size_t i = 0; i < ui.pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) EXPECT_LE(ui.data[i * 4 + c], ui.data[i * 4 + 3]);
  const Image bloom = make("bloom", 64, 16, {{"intensity", {2.0}}});
  double max_step = 0, peak = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 64; ++x) {
      const double v = bloom.px(x, y)[2];
      EXPECT_GT(v, 0.0);
      peak = std::max(peak, v);
      if (x > 0) max_step = std::max(max_step, std::fabs(v - bloom.px(x - 1, y)[2]));
    }
  EXPECT_GT(peak, 2.0 * 4.0 * 0.8) << "the white glow peaks near intensity x 4";
  EXPECT_LT(max_step, peak * 0.25) << "no hard edges";
}

// Every 8-bit code once per 256 pixels, grey and opaque, whatever the image's shape: k / 255 for
// pixel k (mod 256), so code 11 (0.0431, the first above sRGB's 0.04045 threshold) is pixel 11;
// min_code and max_code select a range.
TEST(Stimuli, UiSrgbCodesHoldEveryEightBitCodeOpaque) {
  for (auto [w, h] : {std::pair{32, 32}, std::pair{256, 1}, std::pair{16, 17}}) {
    const Image img = make("ui_srgb_codes", w, h);
    std::multiset<int> codes;
    for (size_t i = 0; i < img.pixel_count(); ++i) {
      const double v = img.data[i * 4];
      ASSERT_EQ(v * 255.0, std::round(v * 255.0)) << i;
      EXPECT_EQ(static_cast<size_t>(std::round(v * 255.0)), i % 256) << i;
      EXPECT_EQ(img.data[i * 4 + 1], v);
      EXPECT_EQ(img.data[i * 4 + 2], v);
      EXPECT_EQ(img.data[i * 4 + 3], 1.0);
      if (i < 256) codes.insert(static_cast<int>(std::round(v * 255.0)));
    }
    EXPECT_EQ(codes.size(), 256u);
  }
  EXPECT_EQ(make("ui_srgb_codes", 32, 32).data[11 * 4], 11.0 / 255.0);
  auto small = make_stimulus("ui_srgb_codes", 15, 17);
  ASSERT_FALSE(small.ok());
  EXPECT_NE(small.error().message.find("needs at least 256 pixels"), std::string::npos);
  // The linear segment alone (codes 0-10, sRGB's threshold 0.04045 lies between 10 and 11).
  const Image seg = make("ui_srgb_codes", 32, 32, {{"max_code", {10.0}}});
  for (size_t i = 0; i < seg.pixel_count(); ++i) EXPECT_EQ(seg.data[i * 4], (i % 11) / 255.0);
  EXPECT_LT(seg.data[10 * 4], 0.04045);
  const Image dark = make("ui_srgb_codes", 8, 1, {{"min_code", {11.0}}, {"max_code", {14.0}}});
  EXPECT_GT(dark.data[0], 0.04045);
  EXPECT_EQ(dark.data[5 * 4], 12.0 / 255.0);
  EXPECT_FALSE(
      make_stimulus("ui_srgb_codes", 8, 1, {{"min_code", {12.0}}, {"max_code", {11.0}}}).ok());
  EXPECT_FALSE(
      make_stimulus("ui_srgb_codes", 3, 1, {{"min_code", {11.0}}, {"max_code", {14.0}}}).ok());
}

TEST(Stimuli, ParameterErrorsNameTheParameterAndTheChoices) {
  const auto* info = hdrc::find_stimulus("hue_sweep");
  ASSERT_NE(info, nullptr);
  const hdrc::Status st = hdrc::check_stimulus(*info, {{"luminance", {1.0}}}, 8, 8);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().message,
            "unknown parameter 'luminance' of stimulus hue_sweep, did you mean 'luminances'?");
  EXPECT_EQ(st.error().choices, "luminances, saturation");
  const hdrc::Status range = hdrc::check_stimulus(*info, {{"saturation", {2.0}}}, 8, 8);
  ASSERT_FALSE(range.ok());
  EXPECT_EQ(range.error().message, "parameter saturation = 2 is out of range");
  EXPECT_EQ(range.error().choices, "0 to 1");
}

}  // namespace
