// CombineLUTs against hand-derived values (docs/spec/ue55.md §13), UE's quirks and properties over
// every output device × gamut.
#include "reference/ue/combine_luts.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "color/st2084.h"
#include "reference/ue/cpp/resolve.h"
#include "reference/ue/lut_shaper.h"
#include "reference/ue/ue_pixel_device.h"

namespace {

using hdrc::ref::Vec3;
namespace spirv = hdrc::ref::spirv;
using spirv::Interval;

hdrc::ParamBlock params(int device, int gamut, bool hdr = true) {
  hdrc::Case c;
  c.cvars.set("r.HDR.EnableHDROutput", hdr ? 1 : 0);
  c.cvars.set("r.HDR.Display.OutputDevice", device);
  c.cvars.set("r.HDR.Display.ColorGamut", gamut);
  return *hdrc::ref::resolve_params(c, 1, 1);
}

Vec3 grey_texel(const hdrc::ParamBlock& p, double scene, hdrc::ref::CombineLutsTrace* t) {
  const double e = hdrc::ref::lut_encode(p.output_device, scene);
  return hdrc::ref::combine_luts_texel(p, {e, e, e}, t);
}

// Spec §13: SDR sRGB code for scene grey 0.18 ≈ 0.4613561 and for 1.0 ≈ 0.8668283, ignoring the
// blue-correction grey drift (measured 2.7e-6 by the grading tests) and the LUT.
TEST(CombineLuts, SdrGreyMatchesHandDerived) {
  const auto p = params(0, 0, false);
  hdrc::ref::CombineLutsTrace t;
  grey_texel(p, 0.18, &t);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(t.device[c], 0.4613561, 5e-6) << c;
  grey_texel(p, 1.0, &t);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(t.device[c], 0.8668283, 5e-6) << c;
  EXPECT_NEAR(t.stored[1], t.device[1] / 1.05, 1e-15);
}

// Spec §13 HDR grey chain (SCM 1.5, GC 0, max 1000): scene 0.18 → 25.497585 nits → PQ 0.378296436
// (LUT stores 0.360282320), "ignoring gamut-matrix grey drift"; with AP1 output (gamut 4) there is
// no drift beyond the WCS matrices.
TEST(CombineLuts, HdrGreyChainMatchesHandDerived) {
  const auto p = params(3, 4);
  hdrc::ref::CombineLutsTrace t;
  grey_texel(p, 0.18, &t);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(t.aces_nits[c], 25.497585, 25.497585 * 2e-6) << c;
    EXPECT_NEAR(t.device[c], 0.378296436, 2e-6) << c;
    EXPECT_NEAR(t.stored[c], 0.360282320, 2e-6) << c;
  }
  grey_texel(p, 1.0, &t);
  EXPECT_NEAR(t.device[1], 0.552035909, 2e-6);
  grey_texel(p, 10.0, &t);
  EXPECT_NEAR(t.aces_nits[1], 606.611787, 606.611787 * 2e-6);
  grey_texel(p, 100.0, &t);
  EXPECT_NEAR(t.aces_nits[1], 930.719800, 930.719800 * 2e-6);
}

// The black lattice point decodes to exactly 0; UE's 0/0 in the fake wide gamut is decided to give
// the ordinary black result (docs/ue55-decisions.md D-NaN): no device stores NaN there.
TEST(CombineLuts, BlackLatticeIsFiniteOnEveryDevice) {
  for (int device = 0; device <= 9; ++device)
    for (int gamut = 0; gamut < 5; ++gamut) {
      const Vec3 v = hdrc::ref::combine_luts_texel(params(device, gamut), {0, 0, 0});
      for (int c = 0; c < 3; ++c)
        EXPECT_TRUE(std::isfinite(v[c])) << "device " << device << " gamut " << gamut;
    }
}

TEST(CombineLuts, StorageQuantisation) {
  using hdrc::ref::quantize_lut_value;
  EXPECT_EQ(quantize_lut_value(0, 0.5), 512.0 / 1023.0);  // 511.5: round to nearest (even)
  EXPECT_EQ(quantize_lut_value(0, 1.2), 1.0);
  EXPECT_EQ(quantize_lut_value(0, -0.1), 0.0);
  EXPECT_EQ(quantize_lut_value(0, std::nan("")), 0.0);
  EXPECT_EQ(quantize_lut_value(1, 1.0 / 3.0), 0.333251953125);  // nearest half
  EXPECT_TRUE(std::isinf(quantize_lut_value(1, 70000.0)));
  EXPECT_EQ(quantize_lut_value(2, 0.1), static_cast<double>(0.1f));
}

// Spec §4.2: the 2-D layout biases r and g by +1e-5/(N−1); b is exact; the volume layout is exact.
TEST(CombineLuts, LatticeCoordinateQuirkOf2DLayout) {
  for (int n : {16, 32, 33, 64}) {
    for (int i : {0, 1, n / 2, n - 1}) {
      const Vec3 v = hdrc::ref::lattice_coordinate(0, n, i, i, i);
      EXPECT_DOUBLE_EQ(v[0], i / (n - 1.0));
      const Vec3 u = hdrc::ref::lattice_coordinate(1, n, i, n - 1 - i, i);
      EXPECT_NEAR(u[0], (i + 1e-5) / (n - 1.0), 1e-12) << n << " " << i;
      EXPECT_NEAR(u[1], (n - 1 - i + 1e-5) / (n - 1.0), 1e-12);
      EXPECT_NEAR(u[2], i / (n - 1.0), 1e-12);
    }
  }
}

hdrc::ParamBlock lut_params(int device, int gamut, int size, int format, int layout) {
  hdrc::Case c;
  c.cvars.set("r.HDR.EnableHDROutput", 1);
  c.cvars.set("r.HDR.Display.OutputDevice", device);
  c.cvars.set("r.HDR.Display.ColorGamut", gamut);
  c.cvars.set("r.LUT.Size", size);
  c.settings.set("LUTFormat", {static_cast<double>(format), 0, 0, 0}, 1);
  c.settings.set("LUTLayout", {static_cast<double>(layout), 0, 0, 0}, 1);
  return *hdrc::ref::resolve_params(c, 1, 1);
}

// Sampling exactly at a lattice point returns that texel × 1.05 (float storage), for both layouts;
// between lattice points the volume and 2-D lookups agree up to the 2-D layout's 1e-5 bias.
TEST(CombineLuts, SamplingAtLatticeAndBetween) {
  const auto vol = hdrc::ref::bake_lut(lut_params(3, 4, 16, 2, 0));
  const auto two_d = hdrc::ref::bake_lut(lut_params(3, 4, 16, 2, 1));
  for (const auto* lut : {&vol, &two_d}) {
    const Vec3 s = hdrc::ref::sample_lut(*lut, {3 / 15.0, 7 / 15.0, 11 / 15.0});
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(s[k], lut->at(3, 7, 11)[k] * 1.05, 1e-12);
  }
  const Vec3 a = hdrc::ref::sample_lut(vol, {0.31, 0.52, 0.77});
  const Vec3 b = hdrc::ref::sample_lut(two_d, {0.31, 0.52, 0.77});
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-5 * a[k]) << k;
}

// ACES output converted to sRGB is negative for saturated texels: PQ of a negative is NaN, which a
// float LUT keeps and the default 10-bit UNORM LUT stores as 0 (D3D float→UNORM).
TEST(CombineLuts, OutOfGamutTexelsAreNaNInFloatAndZeroInUnorm) {
  const auto flt = hdrc::ref::bake_lut(lut_params(3, 0, 16, 2, 0));
  const auto unorm = hdrc::ref::bake_lut(lut_params(3, 0, 16, 0, 0));
  EXPECT_TRUE(std::isnan(flt.at(3, 7, 11)[0]) || std::isnan(flt.at(3, 7, 11)[2]));
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(std::isfinite(unorm.at(3, 7, 11)[k]));
}

// Over every device × gamut: grey stays (nearly) neutral and the device value rises along a grey
// ramp wherever UE's curve is monotonic. Bounds measured: see docs/precision.md.
TEST(CombineLuts, GreyRampPropertiesOnEveryDeviceAndGamut) {
  for (int device = 0; device <= 9; ++device) {
    for (int gamut = 0; gamut < 5; ++gamut) {
      const auto p = params(device, gamut);
      double prev = -1.0;
      double worst_spread = 0.0;
      for (int i = 1; i <= 64; ++i) {
        const double e = i / 64.0;
        const Vec3 v = hdrc::ref::combine_luts_texel(p, {e, e, e});
        const double mid = v[1];
        EXPECT_GE(mid, prev - 1e-12) << "device " << device << " gamut " << gamut << " e " << e;
        prev = mid;
        worst_spread =
            std::fmax(worst_spread, std::fmax(std::fabs(v[0] - mid), std::fabs(v[2] - mid)));
      }
      // Neutral in, neutral out, up to the literal matrices' drift. Measured worst |channel − G|
      // over the grey lattice: device 9 / P3 1.41e-4, devices 1–2 / P3 6.8e-5, 3/4 1.45e-5,
      // 7 1.34e-5, 0 4.5e-6, 8 3.2e-6, 5/6 5.5e-9 (the D60→D65 CAT literals and the float WCS).
      EXPECT_LT(worst_spread, 2e-4) << "device " << device << " gamut " << gamut;
    }
  }
}

}  // namespace

// Admissible ranges (reference/color/noise_range.h), values derived by hand.
TEST(NoiseRange, WidensOnlyChannelsWithinTheNoiseOfZero) {
  using hdrc::ref::kShaderNoise;
  hdrc::ref::Range3 r = hdrc::ref::Range3::point({1000.0, 0.01, 5.0});
  EXPECT_TRUE(hdrc::ref::widen_near_zero({1000.0, 0.01, 5.0}, kShaderNoise, &r));
  const double e = kShaderNoise * 1000.0;  // 0.0305
  EXPECT_DOUBLE_EQ(r.lo[1], 0.01 - e);
  EXPECT_DOUBLE_EQ(r.hi[1], 0.01 + e);
  EXPECT_EQ(r.lo[2], 5.0);  // 5 > e: not widened
  EXPECT_EQ(r.hi[2], 5.0);
  // PQ is NaN below zero: the negative part becomes an admissible NaN, the rest [PQ(0), PQ(hi)].
  const auto pq = hdrc::ref::map_nonnegative(
      r, [](double v) { return v < 0 ? std::nan("") : hdrc::ref::st2084::pq_from_nits(v); });
  EXPECT_TRUE(pq.nan[1]);
  EXPECT_FALSE(pq.nan[0]);
  EXPECT_DOUBLE_EQ(pq.lo[1], hdrc::ref::st2084::pq_from_nits(0.0));
  EXPECT_DOUBLE_EQ(pq.hi[1], hdrc::ref::st2084::pq_from_nits(0.01 + e));
  // A matrix with a negative coefficient swaps the bounds it multiplies; NaN reaches every row
  // with a non-zero coefficient on the channel.
  const hdrc::ref::Mat3 m{{1, -2, 0, 0, 1, 0, 0, 0, 1}};
  const auto mr = hdrc::ref::apply_matrix(m, r);
  EXPECT_DOUBLE_EQ(mr.lo[0], 1000.0 - 2 * (0.01 + e));
  EXPECT_DOUBLE_EQ(mr.hi[0], 1000.0 - 2 * (0.01 - e));
  const auto mn = hdrc::ref::apply_matrix(m, pq);
  EXPECT_TRUE(mn.nan[0] && mn.nan[1] && !mn.nan[2]);
  // An all-zero colour has no noise scale: nothing is widened.
  hdrc::ref::Range3 z = hdrc::ref::Range3::point({0, 0, 0});
  EXPECT_FALSE(hdrc::ref::widen_near_zero({0, 0, 0}, kShaderNoise, &z));
}

TEST(NoiseRange, RoundingBoundaryAdmitsBothNeighbours) {
  // 10-bit: 100.5 / 1023 lies on the boundary between codes 100 and 101.
  const double v = 100.5 / 1023.0;
  hdrc::ref::Range3 r = hdrc::ref::Range3::point({v, 0.9, 0.9});
  EXPECT_TRUE(
      hdrc::ref::widen_near_rounding_boundary({v, 0.9, 0.9}, 1023.0, hdrc::ref::kShaderNoise, &r));
  EXPECT_EQ(hdrc::ref::quantize_lut_value(0, r.lo[0]), 100.0 / 1023.0);
  EXPECT_EQ(hdrc::ref::quantize_lut_value(0, r.hi[0]), 101.0 / 1023.0);
  EXPECT_EQ(r.lo[1], 0.9);  // 920.7 codes: 0.2 codes from a boundary, far beyond the noise
  EXPECT_EQ(r.hi[1], 0.9);
  hdrc::ref::Range3 far = hdrc::ref::Range3::point({100.2 / 1023.0, 0.9, 0.9});
  EXPECT_FALSE(hdrc::ref::widen_near_rounding_boundary({100.2 / 1023.0, 0.9, 0.9}, 1023.0,
                                                       hdrc::ref::kShaderNoise, &far));
}

// A dark channel of a bright texel on the PQ path carries the noise of its texel's brightest
// channel through PQ's steep foot. Device 3 (1000-nit ACES, sRGB), 64^3 10-bit UNORM, lattice
// (20, 40, 41): lavapipe stored R as code 34 where the reference stores 36 (measured in the
// exhaustive tier, 2026-11-24); the range admits both. G and B (about 300 nits) stay exact.
TEST(CombineLuts, DarkChannelOfABrightTexelCarriesTheTexelsNoiseThroughPq) {
  const auto lut = hdrc::ref::bake_lut(lut_params(3, 0, 64, 0, 0));
  ASSERT_TRUE(lut.has_ranges());
  const size_t i = lut.index(20, 40, 41);
  EXPECT_EQ(lut.texels[i][0], 36.0 / 1023.0);
  ASSERT_TRUE(lut.flags[i] & hdrc::ref::BakedLut::kAmbiguous);
  EXPECT_LE(lut.lo[i][0], 34.0 / 1023.0);
  EXPECT_GE(lut.hi[i][0], 36.0 / 1023.0);
  EXPECT_EQ(lut.lo[i][1], lut.texels[i][1]);
  EXPECT_EQ(lut.hi[i][1], lut.texels[i][1]);
  // widen_noise: every finite channel by noise x the largest |channel|.
  hdrc::ref::Range3 r = hdrc::ref::Range3::point({300.0, 0.03, -250.0});
  ASSERT_TRUE(hdrc::ref::widen_noise({300.0, 0.03, -250.0}, 0.001, &r));
  EXPECT_DOUBLE_EQ(r.lo[0], 299.7);
  EXPECT_DOUBLE_EQ(r.hi[1], 0.33);
  EXPECT_DOUBLE_EQ(r.lo[2], -250.3);
  hdrc::ref::Range3 z = hdrc::ref::Range3::point({0, 0, 0});
  EXPECT_FALSE(hdrc::ref::widen_noise({0, 0, 0}, 0.001, &z));
}

// combine_luts_texel_device_range is the range bake_lut_device stores from: for every texel of an
// RGBA32F LUT (whose store adds only either float neighbour) on an SDR, a PQ and a linear device,
// the stored range holds it, it holds the texel function's own value, and it is wider than a point
// wherever the texel has a finite non-zero channel (kShaderNoise of the largest channel).
TEST(CombineLuts, TexelDeviceRangeIsWhatTheDeviceLutStoresFrom) {
  hdrc::DevicePrecision device;
  device.sub_texel_bits = 8;
  for (int d : {0, 3, 9}) {
    const hdrc::ParamBlock p = lut_params(d, 2, 16, 2, 0);
    const hdrc::ref::BakedLut lut = hdrc::ref::bake_lut_device(p, device);
    ASSERT_TRUE(lut.has_ranges());
    const int n = lut.size;
    ASSERT_EQ(n, 16);
    for (int b = 0; b < n; ++b)
      for (int g = 0; g < n; ++g)
        for (int r = 0; r < n; ++r) {
          const Vec3 lattice = hdrc::ref::lattice_coordinate(0, n, r, g, b);
          const hdrc::ref::Range3 range = hdrc::ref::combine_luts_texel_device_range(p, lattice);
          const Vec3 v = hdrc::ref::combine_luts_texel(p, lattice);
          const size_t i = lut.index(r, g, b);
          for (int c = 0; c < 3; ++c) {
            if (std::isnan(v[c])) {
              EXPECT_TRUE(range.nan[c]) << d << " " << r << " " << g << " " << b << " " << c;
              continue;
            }
            EXPECT_LE(range.lo[c], v[c]) << d << " " << r << " " << g << " " << b << " " << c;
            EXPECT_GE(range.hi[c], v[c]) << d << " " << r << " " << g << " " << b << " " << c;
            EXPECT_LE(lut.lo[i][c], range.lo[c]) << d << " " << r << " " << g << " " << b;
            EXPECT_GE(lut.hi[i][c], range.hi[c]) << d << " " << r << " " << g << " " << b;
            if (v[c] != 0) {
              EXPECT_LT(range.lo[c], range.hi[c]) << d << " " << r << " " << g << " " << b;
            }
          }
        }
  }
}

// Every stored texel is a value of its storage format: RGBA32F texels are float32 values, RGBA16F
// texels half values, UNORM texels k/1023. GCC 12's SLP vectoriser dropped the float round trip of
// two channels at -O3 (CMakeLists.txt, -fno-tree-slp-vectorize); this is the test that saw it.
TEST(CombineLuts, StoredTexelsAreValuesOfTheirFormat) {
  for (int device : {0, 3, 7, 8}) {
    for (int format : {0, 1, 2}) {
      const auto lut = hdrc::ref::bake_lut(lut_params(device, 2, 16, format, 0));
      size_t wrong = 0;
      for (const auto& t : lut.texels)
        for (int c = 0; c < 3; ++c) {
          const double v = t[c];
          if (std::isnan(v)) continue;
          const bool ok = format == 0   ? std::nearbyint(v * 1023.0) == v * 1023.0
                          : format == 1 ? hdrc::ref::quantize_lut_value(1, v) == v
                                        : static_cast<double>(static_cast<float>(v)) == v;
          if (!ok) ++wrong;
        }
      EXPECT_EQ(wrong, 0u) << "device " << device << " format " << format;
    }
  }
}

// Device 7 (PQ of linear output) at the black lattice corner of a wide-gamut working space: the
// float LUT's ambiguous texels admit NaN, the UNORM LUT's admit 0 (NaN stored as 0); every texel's
// stored value lies in its range, and sampling at a lattice point gives that texel's range.
TEST(CombineLuts, AmbiguousTexelsCarryTheirAdmissibleRange) {
  for (int format : {0, 2}) {
    const auto lut = hdrc::ref::bake_lut(lut_params(7, 0, 16, format, 0));
    ASSERT_TRUE(lut.has_ranges()) << format;
    size_t ambiguous = 0, nan_ok = 0;
    for (size_t i = 0; i < lut.texels.size(); ++i) {
      for (int c = 0; c < 3; ++c) {
        const double v = lut.texels[i][c];
        if (std::isnan(v)) {
          EXPECT_TRUE(lut.flags[i] & (1u << c));
          continue;
        }
        EXPECT_LE(lut.lo[i][c], v) << i;
        EXPECT_GE(lut.hi[i][c], v) << i;
        if (lut.flags[i] & (1u << c)) ++nan_ok;
      }
      if (lut.flags[i] & hdrc::ref::BakedLut::kAmbiguous) ++ambiguous;
    }
    EXPECT_GT(ambiguous, 0u);
    if (format == 0) {
      EXPECT_EQ(nan_ok, 0u);  // UNORM stores no NaN
    }
    // At a lattice point the sample is the texel itself (× 1.05).
    for (size_t i = 0; i < lut.texels.size(); ++i) {
      if (!(lut.flags[i] & hdrc::ref::BakedLut::kAmbiguous)) continue;
      const int n = lut.size, r = static_cast<int>(i % n), g = static_cast<int>(i / n % n),
                b = static_cast<int>(i / n / n);
      hdrc::ref::Range3 s;
      ASSERT_TRUE(
          hdrc::ref::sample_lut_range(lut, {r / (n - 1.0), g / (n - 1.0), b / (n - 1.0)}, &s));
      for (int c = 0; c < 3; ++c) {
        if (std::isnan(lut.lo[i][c])) continue;
        EXPECT_NEAR(s.lo[c], lut.lo[i][c] * 1.05, 1e-12);
        EXPECT_NEAR(s.hi[c], lut.hi[i][c] * 1.05, 1e-12);
      }
      break;
    }
  }
}

// The unwrapped LUT (layout 1) at a slice's first texel, where the coordinate's noise crosses into
// the previous slice's last texel. N = 2, every texel 0 but (r 1, g 0, b 0) = 1 (slice 0's last,
// strip x = 1). Encoded (0, 0, 1): uvw = e·(1/2) + 1/4 = (0.25, 0.25, 0.75); w = 0.75·2 − 0.5 = 1,
// floor 1, fraction 0; u = (0.25 + 1)/2 = 0.625, strip x = 0.625·4 − 0.5 = 2 (slice 1's first
// texel), y = 0. The coordinate noise kShaderNoise·N = 2^-14 (2^-13 texels along the strip's x)
// carries x to 2 − 2^-13: taps (1, 2), fraction 1 − 2^-13, whose 8-bit box is [255/256, 1], so
// texel x = 1 may weigh 1/256 (the worst-case device model's truncated weight does exactly that).
// The slice coordinate w = 1 − 2^-14 reads slices 0 and 1 with fraction ≈ 1: slice 0's tap at
// x ≈ 0 weighs texel 1 up to 1/256 too. Upper end: 1/256 · 1.05 (LUTScale), plus the lerp's
// rounding (2.5 ulp of 1/256); lower end 0 (non-negative texels). Without the crossing the range
// was [0, 0].
TEST(SampleLutDeviceRange, UnwrappedSliceEdgeReadsThePreviousSlicesLastTexel) {
  hdrc::ref::BakedLut lut;
  lut.size = 2;
  lut.layout = 1;
  lut.texels.assign(8, Vec3{0, 0, 0});
  lut.texels[lut.index(1, 0, 0)] = Vec3{1, 1, 1};
  lut.lo = lut.texels;
  lut.hi = lut.texels;
  lut.flags.assign(8, hdrc::ref::BakedLut::kAmbiguous);
  hdrc::ref::Range3 r;
  ASSERT_TRUE(hdrc::ref::sample_lut_device_range(lut, Vec3{0, 0, 1}, 8, &r));
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(r.lo[c], 0.0);
    EXPECT_NEAR(r.hi[c], 1.05 / 256, 2.5 * 0x1p-31 * 1.05);
    EXPECT_GE(r.hi[c], 1.05 / 256);
  }
}

// The volume LUT at a texel centre (a lattice stimulus): N = 2, texel (0, 0, 0) = 1, the rest 0.
// Encoded (1, 0, 0): uvw = e·(1/2) + 1/4, t = uvw·2 − 0.5 = e, so t.r = 1 exactly: the exact
// lookup reads texel r = 1 (0). The noise 2^-15·2 = 2^-14 texels carries t.r to 1 − 2^-14: taps
// (0, 1), fraction 1 − 2^-14 (·256 = 255.98), box [255/256, 1]: texel 0 weighs up to 1/256 (g and
// b at t = 0 weigh it up to 1). Upper end 1.05/256; before the crossing was enumerated, 0.
TEST(SampleLutDeviceRange, VolumeLatticePointReadsTheLowerNeighbour) {
  hdrc::ref::BakedLut lut;
  lut.size = 2;
  lut.layout = 0;
  lut.texels.assign(8, Vec3{0, 0, 0});
  lut.texels[lut.index(0, 0, 0)] = Vec3{1, 1, 1};
  lut.lo = lut.texels;
  lut.hi = lut.texels;
  lut.flags.assign(8, hdrc::ref::BakedLut::kAmbiguous);
  hdrc::ref::Range3 r;
  ASSERT_TRUE(hdrc::ref::sample_lut_device_range(lut, Vec3{1, 0, 0}, 8, &r));
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(r.lo[c], 0.0);
    EXPECT_DOUBLE_EQ(r.hi[c], 1.05 / 256);
  }
}

// The Tonemap lookup's coordinate takes the shader's encode op by op (issue 25: the device-3
// VisualizeHDR cases' saturated red, 3143 nits, missed its range by 0.76 PQ codes with kShaderNoise
// alone). The PQ encode of 1000 nits (x = 10) as lut_shaper.glsl writes it, by hand: the
// quotient (c1 + c2·lm)·(1/(1 + c3·lm)) at lm = 0.1^m1 = 0.6933 carries four roundings of ~3.4e-8
// relative (the multiply-adds, unfused), the reciprocal's 2.5 ULP of 0.0717 (2.6e-7) and the
// product's 3e-8: 4.3e-7 relative (lm's own error enters with d ln q / d lm = 0.0167 only); pow(q,
// m2) multiplies that by m2 = 78.84 (3.4e-5) and adds log2's 2^-21 absolute inside [0.5, 2] times
// m2·ln 2 (2.6e-5) and exp2's 3.8 ULP: 6.0e-5 relative of 0.7518, ±4.5e-5 — 1.49× kShaderNoise.
// A LUT that is the identity in red (texel r holds r/(N − 1)) looked up at N = 32 gives back the
// coordinate: uvw·N − 0.5 = e·(N − 1), so red = e·1.05 over the coordinate's range (24 sub-texel
// bits: the boxes and the weight snap within 1e-7). Without the derived range the red range is
// kShaderNoise·N/(N − 1) = 3.15e-5 wide each side, plus the CTS's 16-bit coordinate rounding (at
// most 2^-12 texel, 7.9e-6 of e): under 4.2e-5.
TEST(SampleLutDeviceRange, CoordinateTakesTheEncodesDeviceRange) {
  const spirv::Interval enc = hdrc::ref::ue_device::lut_encode_clamped(3, Interval::point(10.0));
  const double e = hdrc::ref::lut_encode(3, 10.0);
  EXPECT_NEAR(e, 0.7518271, 1e-7);
  EXPECT_NEAR(e - enc.lo, 4.55e-5, 0.1e-5);
  EXPECT_NEAR(enc.hi - e, 4.55e-5, 0.1e-5);
  const int n = 32;
  hdrc::ref::BakedLut lut;
  lut.size = n;
  lut.layout = 0;
  lut.lut_format = 2;
  lut.texels.resize(static_cast<size_t>(n) * n * n);
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) lut.texels[lut.index(r, g, b)] = Vec3{r / (n - 1.0), 0, 0};
  lut.lo = lut.texels;
  lut.hi = lut.texels;
  lut.flags.assign(lut.texels.size(), hdrc::ref::BakedLut::kAmbiguous);
  const Vec3 encoded{e, 0.5, 0.5};
  const Interval ranges[3] = {enc, Interval::point(0.5), Interval::point(0.5)};
  hdrc::ref::Range3 with, without;
  ASSERT_TRUE(hdrc::ref::sample_lut_device_range(lut, encoded, 24, &with, 1.05, ranges));
  ASSERT_TRUE(hdrc::ref::sample_lut_device_range(lut, encoded, 24, &without));
  EXPECT_LE(with.lo[0], 1.05 * (e - 4.5e-5));
  EXPECT_GE(with.hi[0], 1.05 * (e + 4.5e-5));
  EXPECT_GT(with.lo[0], 1.05 * (e - 5.4e-5));  // plus the CTS rounding's 7.9e-6 at most
  EXPECT_LT(with.hi[0], 1.05 * (e + 5.4e-5));
  EXPECT_GT(without.lo[0], 1.05 * (e - 4.2e-5));
  EXPECT_LT(without.hi[0], 1.05 * (e + 4.2e-5));
}

// The bake's texel range takes the PQ lattice decode's device error (issue 25: the model's bake of
// tonemap/working_color_space/hdr1_dev8_gamut2_lut32_workingcolorspace3_fmt0_log_ramp stored
// texel (15, 0, 0) red as code 825 where the range was codes [826, 827]). The decode of lattice
// 15/31 (texel/(N − 1), 2.5 ULP, widened to 3) as ST2084ToLinear, by hand: np = e^(1/m2) = 0.99084
// within exp2's 3.03 ULP (1.8e-7); the ratio (np − c1)/(c2 − c3·np) = 0.1549/0.3353 moves by
// (1/0.1549 + 18.69/0.3353)·1.8e-7 = 62.2·1.8e-7 = 1.1e-5 relative, plus c3·np's rounding
// (9.5e-7 of the 0.3353 difference, 2.8e-6) and the division's 2.5 ULP (1.6e-7): 1.4e-5; pow(·,
// 1/m1 = 6.2773) multiplies that (8.9e-5) and adds its own log2 (3 ULP outside [0.5, 2]) and exp2
// (17 ULP) errors, 3.6e-6, and the lattice's division 1.4e-6: 9.4e-5, against 2^-15 = 3.05e-5 of
// noise_range.h's convention. Device 8 stores GradedColor (the working colour space, sRGB, through
// AP1 and back; with ExpandGamut 0 the stored red's derivative in its own decoded channel is 1,
// the default 1 makes it 1.063 for this saturated red), so the stored red's range is the
// convention's 2^-15 of the largest channel (red itself) plus the decode's 9.55e-5, relative.
TEST(CombineLuts, TexelDeviceRangeTakesThePqLatticeDecodesError) {
  hdrc::ParamBlock p = lut_params(8, 2, 32, 0, 0);
  p.expand_gamut = 0.0;
  const double lattice = 15.0 / 31.0;
  const Interval d =
      hdrc::ref::ue_device::lut_decode(8, spirv::widen_ulp(Interval::point(lattice), 3.0));
  const double decoded = hdrc::ref::lut_decode(8, lattice);
  EXPECT_NEAR(decoded, 0.784067, 1e-6);
  EXPECT_NEAR((decoded - d.lo) / decoded, 9.55e-5, 0.2e-5);
  EXPECT_NEAR((d.hi - decoded) / decoded, 9.55e-5, 0.2e-5);
  hdrc::ref::CombineLutsTrace t;
  const Vec3 v = hdrc::ref::combine_luts_texel(p, {lattice, 0, 0}, &t);
  const hdrc::ref::Range3 r = hdrc::ref::combine_luts_texel_device_range(p, {lattice, 0, 0});
  const double largest =
      std::fmax(std::fabs(t.graded[0]), std::fmax(std::fabs(t.graded[1]), std::fabs(t.graded[2])));
  EXPECT_NEAR(largest, std::fabs(t.graded[0]), 0.0);  // red is the largest channel
  EXPECT_NEAR((v[0] - r.lo[0]) / v[0], 0x1p-15 + 9.55e-5, 0.3e-5);
  EXPECT_NEAR((r.hi[0] - v[0]) / v[0], 0x1p-15 + 9.55e-5, 0.3e-5);
}

// The log shaper's lattice decode near black (devices 0-2), by hand at lattice e = 0.00233034487:
// lin_from_log(e) = exp2(t)·0.18, t = (e − 444/1023)·14 = −6.0436, exp2 within 3 + 2|t| = 15.09
// ULP of 0.01517 (2^-30 each), times 0.18: 2.53e-9; LogToLin(0) (t = −6.0763) the same, 2.54e-9;
// t's roundings (the grey constant's float32 neighbours, the subtraction, the multiply by
// 14: 6.6e-7 and 4.5e-7 in t, times ln 2 and the values 0.00273 and 0.00266): 1.25e-9 and 0.83e-9;
// the 0.18 constant and its multiplies, 0.5e-9: 7.6e-9 to first order on a decoded value of 6.1e-5
// (the interval evaluation, which widens at each end, 8.0e-9): 1.3e-4 relative, where kShaderNoise
// of the texel's largest channel (all three equal) is 3.05e-5: the texel's range takes the decode's
// error (decode_device_spread) for the log shaper as for PQ.
TEST(CombineLuts, LogLatticeDecodeNearBlackOutgrowsTheConvention) {
  const double e = 0.00233034487;
  const Interval d = hdrc::ref::ue_device::lut_decode(0, spirv::widen_ulp(Interval::point(e), 3.0));
  const double decoded = hdrc::ref::lut_decode(0, e);
  EXPECT_NEAR(decoded, 6.10146e-5, 1e-10);
  EXPECT_NEAR(decoded - d.lo, 8.0e-9, 0.3e-9);
  EXPECT_NEAR(d.hi - decoded, 8.0e-9, 0.3e-9);
  EXPECT_GT((d.hi - decoded) / decoded, 4 * 0x1p-15);
  // Device 0 (sRGB, linear segment near black), a grey texel at e: the convention alone gives the
  // stored value 2^-15 (FilmColor's largest channel) plus the encode's 2^-17, 3.8e-5 relative; the
  // decode's 1.3e-4 through the film curve's toe (log-log slope about 2.5 here) adds 3.3e-4.
  const hdrc::ParamBlock p = lut_params(0, 0, 32, 2, 0);
  const Vec3 v = hdrc::ref::combine_luts_texel(p, {e, e, e});
  const hdrc::ref::Range3 r = hdrc::ref::combine_luts_texel_device_range(p, {e, e, e});
  std::printf("[ measured ] device 0 grey texel at %.9g: %.9g, range -%.3g +%.3g relative\n", e,
              v[0], (v[0] - r.lo[0]) / v[0], (r.hi[0] - v[0]) / v[0]);
  EXPECT_GT((v[0] - r.lo[0]) / v[0], 2 * 0x1p-15);
  EXPECT_GT((r.hi[0] - v[0]) / v[0], 2 * 0x1p-15);
}
