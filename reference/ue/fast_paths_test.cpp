// The reference's fast paths (reference/color/fast_paths.h, TexelEvaluator) against the plain
// evaluation of the same build, bit for bit: 1e5 colours over every output device × gamut, with
// grading at its defaults (where the shortcuts fire) and away from them, through the analytic
// tonemapper (what `probe` prints) and the bake. Comparing the two paths of one build keeps the
// test valid while the formulas themselves change.
#include "reference/color/fast_paths.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "reference/ue/combine_luts.h"
#include "reference/ue/tonemap.h"
#include "reference/ue/cpp/resolve.h"

namespace {

using hdrc::ref::Vec3;

struct FastPathsOff {
  FastPathsOff() { hdrc::ref::set_fast_paths(false); }
  ~FastPathsOff() { hdrc::ref::set_fast_paths(true); }
};

uint64_t bits(double v) {
  uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

bool same_bits(const Vec3& a, const Vec3& b) {
  for (int c = 0; c < 3; ++c)
    if (bits(a[c]) != bits(b[c])) return false;
  return true;
}

hdrc::ParamBlock params(int device, int gamut, bool graded) {
  hdrc::Case c;
  c.stage = hdrc::find_stage("tonemap");
  c.cvars.set("r.HDR.EnableHDROutput", 1);
  c.cvars.set("r.HDR.Display.OutputDevice", device);
  c.cvars.set("r.HDR.Display.ColorGamut", gamut);
  if (graded) {  // every zone different, exponents away from 1, gamut compression on
    c.cvars.set("r.HDR.Aces.GamutCompression", 0.5);
    c.cvars.set("r.TonemapperGamma", 2.4);
    c.settings.set("ColorGamma", {1.2, 0.9, 1.0, 1.1}, 4);
    c.settings.set("ColorContrastShadows", {1.1, 1.0, 0.8, 1.0}, 4);
    c.settings.set("ColorSaturationHighlights", {0.5, 1.5, 1.0, 1.0}, 4);
    c.settings.set("ColorGainMidtones", {1.0, 1.2, 0.9, 1.0}, 4);
    c.settings.set("DisplayGamma", {2.4, 0, 0, 0}, 1);
  }
  return *hdrc::ref::resolve_params(c, 1, 1);
}

// Log-uniform colours over 1e-6 … 1e3 (scene-linear, 1 = 100 nits), with negative channels,
// zeros and NaN mixed in every 97th colour.
std::vector<Vec3> colours(size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-6.0, 3.0);
  std::vector<Vec3> out;
  for (size_t i = 0; i < n; ++i) {
    Vec3 c{std::pow(10.0, u(rng)), std::pow(10.0, u(rng)), std::pow(10.0, u(rng))};
    if (i % 97 == 1) c[i % 3] = -c[i % 3];
    if (i % 97 == 2) c[i % 3] = 0.0;
    if (i % 97 == 3) c[i % 3] = std::nan("");
    if (i % 5 == 0) c = {c[0], c[0], c[0]};  // greys: every zone and the film path's neutral axis
    out.push_back(c);
  }
  return out;
}

// 1e5 colours in all: 1000 per device × gamut, at default grading and graded.
TEST(FastPaths, AnalyticTonemapIsBitIdenticalOverEveryDeviceAndGamut) {
  size_t compared = 0, differing = 0;
  std::string first;
  for (int device = 0; device <= 9; ++device)
    for (int gamut = 0; gamut <= 4; ++gamut)
      for (bool graded : {false, true}) {
        const hdrc::ParamBlock p = params(device, gamut, graded);
        const auto in = colours(1000, 1000 * device + 10 * gamut + graded);
        std::vector<Vec3> fast;
        const hdrc::ref::TexelEvaluator texel(p);
        for (const Vec3& c : in)
          fast.push_back(hdrc::ref::tonemap_centre_pixel(p, c, nullptr, nullptr, &texel));
        FastPathsOff off;
        for (size_t i = 0; i < in.size(); ++i) {
          const Vec3 plain = hdrc::ref::tonemap_centre_pixel(p, in[i], nullptr);
          ++compared;
          if (!same_bits(plain, fast[i]) && differing++ == 0)
            first = "device " + std::to_string(device) + " gamut " + std::to_string(gamut) +
                    (graded ? " graded" : "") + " colour " + std::to_string(i);
        }
      }
  EXPECT_EQ(compared, 100000u);
  EXPECT_EQ(differing, 0u) << "first at " << first;
}

TEST(FastPaths, BakeIsBitIdentical) {
  for (int device : {0, 2, 3, 5, 7, 9})
    for (bool graded : {false, true}) {
      hdrc::ParamBlock p = params(device, 2, graded);
      p.lut_size = 9;
      p.lut_format = 2;
      const auto fast = hdrc::ref::bake_lut(p);
      FastPathsOff off;
      const auto plain = hdrc::ref::bake_lut(p);
      ASSERT_EQ(fast.texels.size(), plain.texels.size());
      for (size_t i = 0; i < plain.texels.size(); ++i)
        ASSERT_TRUE(same_bits(fast.texels[i], plain.texels[i]))
            << "device " << device << (graded ? " graded" : "") << " texel " << i;
    }
}

// The exponent-1 shortcut's premise: glibc's pow(x, 1) is x for every non-negative x, over 1e6
// random bit patterns (denormals, huge values and +Inf included).
TEST(FastPaths, PowOfOneIsTheBase) {
  std::mt19937_64 rng(7);
  for (int i = 0; i < 1000000; ++i) {
    double x;
    const uint64_t b = rng() >> 1;  // sign bit clear
    std::memcpy(&x, &b, sizeof x);
    if (std::isnan(x)) continue;
    ASSERT_EQ(bits(hdrc::ref::d3d::pow(x, 1.0)), bits(x)) << x;
    ASSERT_EQ(bits(hdrc::ref::pow_exp1_shortcut(x, 1.0)), bits(x)) << x;
  }
  // Negative, NaN and zero-exponent cases keep d3d::pow's rules.
  EXPECT_TRUE(std::isnan(hdrc::ref::pow_exp1_shortcut(-2.0, 1.0)));
  EXPECT_TRUE(std::isnan(hdrc::ref::pow_exp1_shortcut(std::nan(""), 1.0)));
  EXPECT_EQ(bits(hdrc::ref::pow_exp1_shortcut(-0.0, 1.0)), bits(hdrc::ref::d3d::pow(-0.0, 1.0)));
}

}  // namespace
