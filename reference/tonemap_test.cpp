// The Tonemap pass against hand-derived values (spec §6, §13).
#include "reference/tonemap.h"

#include <gtest/gtest.h>

#include <cmath>

#include "reference/ue_cpp/resolve.h"

namespace {

using hdrc::ref::Vec3;

hdrc::ParamBlock params(int device, int gamut) {
  hdrc::Case c;
  c.cvars.set("r.HDR.EnableHDROutput", 1);
  c.cvars.set("r.HDR.Display.OutputDevice", device);
  c.cvars.set("r.HDR.Display.ColorGamut", gamut);
  return *hdrc::ref::resolve_params(c, 1, 1);
}

// Spec §13: scene 0.18 on device 5 (ACES 1000-nit scRGB) → PQ 0.378296436 → scRGB 0.318718600
// (the AP1→sRGB literal product keeps grey: row sums 1 ± 2e-10 with UE 5.5's literals).
TEST(Tonemap, ScRgbGreyMatchesHandDerived) {
  hdrc::ref::TonemapTrace t;
  const Vec3 out = hdrc::ref::tonemap_centre_pixel(params(5, 0), {0.18, 0.18, 0.18}, nullptr, &t);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(t.lut[c], 0.378296436, 2e-6);
    // 3.8e-7 relative measured with UE 5.5's 10-digit CATs (grey stays grey); the pre-5.3
    // literals drifted grey by up to 1.3e-4.
    EXPECT_NEAR(out[c], 0.318718600, 0.318718600 * 1e-6) << c;
  }
}

// Device 7: the tonemapper decodes the LUT's PQ: a grey in AP1 output stays the graded grey, up to
// the float working-colour-space round trip FromAP1·ToAP1 (≠ identity by ~3e-8: FromAP1 is the
// float inverse of the float ToAP1, spec §2.3).
TEST(Tonemap, LinearExrDecodesPq) {
  const Vec3 out = hdrc::ref::tonemap_centre_pixel(params(7, 4), {0.5, 0.5, 0.5}, nullptr);
  const auto p = params(7, 4);
  const Vec3 ap1 = p.wcs_to_ap1 * Vec3{0.5, 0.5, 0.5};
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[c], ap1[c], 1e-7 * ap1[c]) << c;
}

// Vignette: (1/(|V·I|² + 1))² with V = pos·(1, AR)·√2/√(1 + AR²); at the corner pixel centre of a
// 4×2 image, pos = (±0.75, ±0.5), AR = 0.5, I = 0.4 — computed here by hand.
TEST(Tonemap, VignetteAtCorner) {
  auto p = params(8, 0);
  hdrc::Image scene(4, 2);
  for (double& v : scene.data) v = 0.5;
  p.width = 4;
  p.height = 2;
  const hdrc::Image out = hdrc::ref::tonemap_image(p, scene, nullptr, nullptr, nullptr);
  const double k = std::sqrt(2.0) / std::sqrt(1.25);
  const double vx = 0.75 * k * 0.4, vy = 0.5 * 0.5 * k * 0.4;
  const double mask = std::pow(1.0 / (vx * vx + vy * vy + 1.0), 2.0);
  // Device 8 passes the graded colour: the same float WCS round trip bounds the match (1e-7).
  EXPECT_NEAR(out.px(0, 0)[0], 0.5 * mask, 1e-7 * mask);
  EXPECT_NEAR(out.px(3, 1)[1], 0.5 * mask, 1e-7 * mask);
}

// Dither: frame 0 has no grain offset (Halton(0, ·) = 0); the triangular noise stays within ±1
// step of the back buffer (1/1023 for HDR devices) and averages out.
TEST(Tonemap, DitherIsBoundedAndCentred) {
  const auto p = params(3, 2);
  EXPECT_EQ(p.grain_random[0], 0.0);
  EXPECT_DOUBLE_EQ(p.dither_amount, 1.0 / 1023.0);
  hdrc::Image flat(64, 64);
  for (double& v : flat.data) v = 0.5;
  const hdrc::Image d = hdrc::ref::dither_image(p, flat);
  double sum = 0;
  for (int i = 0; i < 64 * 64; ++i) {
    const double e = d.data[i * 4] - 0.5;
    EXPECT_LE(std::fabs(e), 1.0 / 1023.0 + 1e-15);
    sum += e;
  }
  EXPECT_LT(std::fabs(sum / (64 * 64)), 0.05 / 1023.0);
  EXPECT_EQ(params(8, 0).dither_amount, 0.0);  // devices 8/9: no dither
  EXPECT_NEAR(hdrc::ref::halton(1, 2), 0.5, 0);
  EXPECT_NEAR(hdrc::ref::halton(5, 3), 7.0 / 9.0, 1e-15);
}

}  // namespace

namespace {

// Bloom with a dirt mask: FinalLinear = S·exposure·vignette + Bloom·(1 + Dirt·Tint)·exposure·
// vignette, Tint = BloomDirtMaskTint · BloomDirtMaskIntensity / BloomIntensity (spec §6.1 step 5).
// Device 8 with the vignette off: 0.1 + 0.05·(1 + 0.5·0.5·1/0.675), by hand.
TEST(Tonemap, BloomWithDirtMask) {
  hdrc::Case c;
  c.cvars.set("r.HDR.EnableHDROutput", 1);
  c.cvars.set("r.HDR.Display.OutputDevice", 8);
  c.settings.set("VignetteIntensity", {0, 0, 0, 0}, 1);
  c.settings.set("BloomDirtMaskIntensity", {1, 0, 0, 0}, 1);
  const auto p = *hdrc::ref::resolve_params(c, 2, 2);
  hdrc::Image scene(2, 2), bloom(2, 2), dirt(2, 2);
  for (int i = 0; i < 16; ++i) {
    scene.data[i] = 0.1;
    bloom.data[i] = 0.05;
    dirt.data[i] = 0.5;
  }
  const double want = 0.1 + 0.05 * (1.0 + 0.5 * 0.5 / 0.675);
  const auto with_dirt = hdrc::ref::tonemap_image(p, scene, &bloom, &dirt, nullptr);
  const auto without = hdrc::ref::tonemap_image(p, scene, &bloom, nullptr, nullptr);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(with_dirt.px(1, 1)[k], want, 1e-7 * want) << k;  // float WCS round trip
    EXPECT_NEAR(without.px(0, 1)[k], 0.15, 1e-7 * 0.15) << k;
  }
}

}  // namespace
