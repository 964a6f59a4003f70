// The Tonemap pass against hand-derived values (docs/spec/ue55.md §6, §13).
#include "reference/ue/tonemap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "reference/ue/cpp/resolve.h"

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
// float inverse of the float ToAP1, docs/spec/ue55.md §2.3).
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
// vignette, Tint = BloomDirtMaskTint · BloomDirtMaskIntensity / BloomIntensity (docs/spec/ue55.md
// §6.1 step 5). Device 8 with the vignette off: 0.1 + 0.05·(1 + 0.5·0.5·1/0.675), by hand.
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

// LazyBakedLut bakes only the texels the pass reads: the output, alpha and every admissible range
// must be bit for bit those of the whole LUT's bake, on every device, storage format and layout,
// over colours that reach the LUT's edges, the 10-bit rounding boundaries and the ambiguous texels
// (near-zero channels on the PQ devices), plus NaN and infinities.
TEST(Tonemap, LazyBakeIsBitIdenticalToTheWholeBake) {
  hdrc::Image scene(23, 11);
  uint64_t state = 0x9e3779b97f4a7c15ull;
  auto next = [&] {  // splitmix64 → [0, 1)
    state += 0x9e3779b97f4a7c15ull;
    uint64_t z = state;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  };
  for (size_t i = 0; i < scene.pixel_count(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const double u = next();
      scene.data[i * 4 + c] = u < 0.1   ? -u                              // negative
                              : u < 0.2 ? 1e-7 * u                        // near zero
                                        : std::pow(10.0, 8.0 * u - 5.0);  // 1e-5 … 1e3
    }
    scene.data[i * 4 + 3] = 1.0;
  }
  scene.data[0] = std::nan("");
  scene.data[5] = HUGE_VAL;
  size_t compared = 0, ranges = 0;
  for (int device = 0; device <= 9; ++device)
    for (int format = 0; format <= 2; ++format)
      for (int layout = 0; layout <= 1; ++layout) {
        hdrc::ParamBlock p = params(device, device % 5);
        p.lut_size = layout ? 16 : 17;
        p.lut_format = format;
        p.lut_layout = layout;
        p.width = scene.width;
        p.height = scene.height;
        const hdrc::ref::BakedLut whole = hdrc::ref::bake_lut(p);
        const hdrc::Image want = hdrc::ref::tonemap_image(p, scene, nullptr, nullptr, &whole);
        hdrc::ref::LazyBakedLut lazy(p);
        const hdrc::Image got =
            hdrc::ref::tonemap_image(p, scene, nullptr, nullptr, nullptr, &lazy);
        SCOPED_TRACE("device " + std::to_string(device) + " format " + std::to_string(format) +
                     " layout " + std::to_string(layout));
        EXPECT_LT(lazy.baked_texels(), whole.texels.size());
        ASSERT_EQ(got.data.size(), want.data.size());
        EXPECT_EQ(0, std::memcmp(got.data.data(), want.data.data(),
                                 want.data.size() * sizeof(want.data[0])));
        ASSERT_EQ(got.admissible.size(), want.admissible.size());
        for (size_t k = 0; k < want.admissible.size(); ++k) {
          const auto &a = got.admissible[k], &b = want.admissible[k];
          EXPECT_EQ(a.pixel, b.pixel);
          EXPECT_EQ(a.nan_ok, b.nan_ok);
          EXPECT_EQ(0, std::memcmp(a.lo.data(), b.lo.data(), sizeof(a.lo)));
          EXPECT_EQ(0, std::memcmp(a.hi.data(), b.hi.data(), sizeof(a.hi)));
        }
        ++compared;
        ranges += want.admissible.size();
      }
  EXPECT_EQ(compared, 60u);
  EXPECT_GT(ranges, 0u);  // the ambiguous texels' path was exercised
}
