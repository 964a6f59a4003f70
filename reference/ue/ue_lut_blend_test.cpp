// UE 5.5's user-LUT blend (reference/ue/ue_lut_blend.h) against numbers from outside this code:
//  * docs/ue55-lut-blend-spec.md §4's hand-derived worked examples (9 significant digits): the
//    LUT samples at one colour and the blended FilmColor for T1-T12, T2q/T3q (8-bit texels);
//  * OpenColorIO's FileTransform (INTERP_LINEAR) on the 16-point .cube files of cases/lut/cube/
//    (scripts/gen_cube_samples.py) for the lookup: UE's two-tap strip sampling is trilinear on the
//    16³ lattice;
//  * the channel-swap LUT's formula (out = (b, g, r)) at lattice points, which pins the strip's
//    orientation (red along x within a tile, blue across tiles, green down the rows).
#include "reference/ue/ue_lut_blend.h"

#include <OpenColorIO/OpenColorIO.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "color/gamma_correction.h"
#include "core/cube/cube.h"
#include "core/cube/ocio_oracle.h"

namespace {

namespace OCIO = OCIO_NAMESPACE;
using hdrc::ref::UeLutTexture;
using hdrc::ref::Vec3;

const std::string kCubeDir = std::string(HDRC_SOURCE_DIR) + "/cases/lut/cube/";

// A 16-point LUT from a per-channel formula, laid out as docs/ue55-lut-blend-spec.md §2.9 describes
// the strip (texel (r + 16 b, g) holds f((r, g, b)/15)), in double: the spec's "float-exact"
// texels.
UeLutTexture strip_of(const std::function<Vec3(const Vec3&)>& f) {
  UeLutTexture t;
  t.texels.resize(256 * 16);
  for (int b = 0; b < 16; ++b)
    for (int g = 0; g < 16; ++g)
      for (int r = 0; r < 16; ++r)
        t.texels[g * 256 + r + 16 * b] = f({r / 15.0, g / 15.0, b / 15.0});
  return t;
}

// The same table as .cube rows (float32), for ue_lut_texture.
std::vector<std::array<float, 3>> rows_of(const std::function<Vec3(const Vec3&)>& f) {
  std::vector<std::array<float, 3>> rows;
  for (int b = 0; b < 16; ++b)
    for (int g = 0; g < 16; ++g)
      for (int r = 0; r < 16; ++r) {
        const Vec3 v = f({r / 15.0, g / 15.0, b / 15.0});
        rows.push_back({float(v[0]), float(v[1]), float(v[2])});
      }
  return rows;
}

Vec3 square(const Vec3& c) {
  return {c[0] * c[0], c[1] * c[1], c[2] * c[2]};
}
Vec3 root(const Vec3& c) {
  return {std::sqrt(c[0]), std::sqrt(c[1]), std::sqrt(c[2])};
}
Vec3 invert(const Vec3& c) {
  return {1 - c[0], 1 - c[1], 1 - c[2]};
}
Vec3 identity(const Vec3& c) {
  return c;
}
Vec3 constant(const Vec3&) {
  return {0.25, 0.25, 0.25};
}

void expect_near(const Vec3& got, const Vec3& want, double tol, const char* what) {
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(got[c], want[c], tol) << what << " channel " << c << ": " << got[c];
}

// 9 significant digits of values in (0, 1): 5e-10 of rounding, plus the reference's own.
constexpr double kTol9 = 1e-9;

Vec3 uvw_of(const Vec3& film) {
  const Vec3 g = hdrc::ref::linear_to_srgb(film);
  Vec3 uvw;
  for (int c = 0; c < 3; ++c) uvw[c] = g[c] * (15.0 / 16.0) + 0.5 / 16.0;
  return uvw;
}

const Vec3 kF = {0.2, 0.5, 0.8};

TEST(UeLutBlend, SamplesAtTheWorkedExampleColour) {
  const Vec3 uvw = uvw_of(kF);
  expect_near(uvw, {0.485496129, 0.720647172, 0.880936019}, kTol9, "UVW");
  using hdrc::ref::unwrapped_texture3d_sample;
  expect_near(unwrapped_texture3d_sample(strip_of(square), uvw),
              {0.235640316, 0.540880707, 0.822508267}, kTol9, "A");
  expect_near(unwrapped_texture3d_sample(strip_of(root), uvw),
              {0.695767803, 0.857504697, 0.951858259}, kTol9, "B");
  expect_near(unwrapped_texture3d_sample(strip_of(invert), uvw),
              {0.515470796, 0.264643017, 0.0936682467}, kTol9, "C");
  expect_near(unwrapped_texture3d_sample(strip_of(identity), uvw),
              {0.484529204, 0.735356983, 0.906331753}, kTol9, "D");
  expect_near(unwrapped_texture3d_sample(strip_of(constant), uvw), {0.25, 0.25, 0.25}, kTol9, "E");
  // A stored 8-bit (T2q's A8 sample).
  const UeLutTexture a8 = hdrc::ref::ue_lut_texture(rows_of(square), true);
  expect_near(unwrapped_texture3d_sample(a8, uvw), {0.237470381, 0.540349896, 0.822938388}, kTol9,
              "A8");
}

TEST(UeLutBlend, WorkedExamples) {
  const UeLutTexture a = strip_of(square), b = strip_of(root), c = strip_of(invert),
                     d = strip_of(identity), e = strip_of(constant);
  const UeLutTexture a8 = hdrc::ref::ue_lut_texture(rows_of(square), true);
  struct Row {
    const char* name;
    Vec3 film;
    int count;
    std::array<double, 5> w;
    std::array<const UeLutTexture*, 4> luts;
    Vec3 out;
  };
  const Row rows[] = {
      {"T1", kF, 1, {1, 0, 0, 0, 0}, {&a}, {0.2, 0.5, 0.8}},
      {"T2", kF, 2, {0.5, 0.5}, {&a}, {0.106591454, 0.364865324, 0.718832292}},
      {"T2q", kF, 2, {0.5, 0.5}, {&a8}, {0.107156265, 0.364530104, 0.719235897}},
      {"T3", kF, 2, {0, 1}, {&a}, {0.0453156430, 0.253849594, 0.642683300}},
      {"T3q", kF, 2, {0, 1}, {&a8}, {0.0460034740, 0.253307221, 0.643439605}},
      {"T4", kF, 3, {0.25, 0.5, 0.25}, {&b, &a}, {0.240805733, 0.519119151, 0.803614504}},
      {"T5",
       kF,
       4,
       {0.125, 0.5, 0.25, 0.125},
       {&c, &b, &a},
       {0.234677437, 0.219850451, 0.214878534}},
      {"T6",
       kF,
       5,
       {0.0625, 0.5, 0.25, 0.125, 0.0625},
       {&d, &c, &b, &a},
       {0.216934614, 0.343356835, 0.453157588}},
      {"T7",
       kF,
       5,
       {1 / 31., 16 / 31., 8 / 31., 4 / 31., 2 / 31.},
       {&e, &d, &c, &b},
       {0.120007115, 0.156404556, 0.183619473}},
      {"T8", kF, 3, {0, 0.5, 0.5}, {&b, &a}, {0.183659081, 0.446839623, 0.762287889}},
      {"T9", kF, 2, {0.25, 0.75}, {&a}, {0.0721850764, 0.306428210, 0.680136197}},
      {"T10", {1.02, 0.5, 0}, 1, {1}, {&d}, {1.02, 0.5, 0}},
      {"T11", {1.02, 0.5, 0}, 2, {0, 1}, {&d}, {0.999999997, 0.499999998, 4.72408669e-6}},
      {"T12", {1.02, 0.5, 0}, 2, {0.5, 0.5}, {&d}, {0.999999997, 0.499999998, 4.72408669e-6}},
  };
  for (const Row& r : rows) {
    const Vec3 out = hdrc::ref::blend_user_luts(r.film, r.count, r.w, r.luts);
    // Relative for the 4.72e-6 black floor, absolute elsewhere.
    for (int ch = 0; ch < 3; ++ch)
      EXPECT_NEAR(out[ch], r.out[ch], std::max(kTol9, 1e-8 * std::fabs(r.out[ch])))
          << r.name << " channel " << ch;
  }
}

// BLENDCOUNT 1 compiles the block out: no saturate, no sRGB round trip, exactly F.
TEST(UeLutBlend, BlendCountOneIsExactlyTheInput) {
  const UeLutTexture a = strip_of(square);
  for (const Vec3& f : {Vec3{1.5, -0.25, 0.0}, Vec3{0.2, 0.5, 0.8}, Vec3{1e-9, 1.04, 37.0}}) {
    const Vec3 out = hdrc::ref::blend_user_luts(f, 1, {1, 0, 0, 0, 0}, {&a});
    for (int c = 0; c < 3; ++c) EXPECT_EQ(out[c], f[c]);
  }
}

TEST(UeLutBlend, StripOrientationFromTheChannelSwapLut) {
  auto lut = hdrc::cube::read_cube_file(kCubeDir + "ue16_swap_rb.cube");
  ASSERT_TRUE(lut.ok()) << lut.error().to_string();
  const UeLutTexture t = hdrc::ref::ue_lut_texture(lut->table_3d, true);
  for (auto [r, g, b] : {std::array{3, 7, 12}, std::array{15, 0, 5}, std::array{0, 15, 15}}) {
    const Vec3 uvw = {(r + 0.5) / 16, (g + 0.5) / 16, (b + 0.5) / 16};  // lattice points
    const Vec3 s = hdrc::ref::unwrapped_texture3d_sample(t, uvw);
    // 8-bit j/15 = 17j/255 exactly.
    expect_near(s, {b / 15.0, g / 15.0, r / 15.0}, 1e-15, "swap");
  }
}

// OpenColorIO's trilinear FileTransform (core/cube/ocio_oracle.h).
OCIO::ConstCPUProcessorRcPtr ocio_linear(const std::string& path) {
  return hdrc::cube::testing::ocio_processor(path, OCIO::INTERP_LINEAR);
}

// The lookup at UVW = g·15/16 + 0.5/16 against OCIO's trilinear evaluation of the .cube at g, on
// a 17³ grid over [0, 1] (off the 16-point lattice, both ends included). Float texels (the
// .cube's values): OCIO evaluates in float32, so 2e-6 relative + 1e-6 (core/cube's bound).
TEST(UeLutBlend, LookupMatchesOpenColorIO) {
  for (const char* file : {"ue16_identity.cube", "ue16_square.cube", "ue16_contrast.cube",
                           "ue16_hue.cube", "ue16_swap_rb.cube"}) {
    auto lut = hdrc::cube::read_cube_file(kCubeDir + file);
    ASSERT_TRUE(lut.ok()) << lut.error().to_string();
    ASSERT_EQ(lut->size_3d, 16) << file;
    const UeLutTexture t = hdrc::ref::ue_lut_texture(lut->table_3d, false);
    auto proc = ocio_linear(kCubeDir + file);
    int failures = 0;
    for (int b = 0; b <= 16; ++b)
      for (int g = 0; g <= 16; ++g)
        for (int r = 0; r <= 16; ++r) {
          float px[3] = {r / 16.f, g / 16.f, b / 16.f};
          const Vec3 in = {px[0], px[1], px[2]};
          Vec3 uvw;
          for (int c = 0; c < 3; ++c) uvw[c] = in[c] * (15.0 / 16.0) + 0.5 / 16.0;
          proc->applyRGB(px);
          const Vec3 ours = hdrc::ref::unwrapped_texture3d_sample(t, uvw);
          for (int c = 0; c < 3; ++c) {
            const double dd = std::fabs(ours[c] - px[c]);
            if (!(dd <= 2e-6 * std::fabs(ours[c]) + 1e-6) && failures++ < 3)
              ADD_FAILURE() << file << " at (" << in[0] << ", " << in[1] << ", " << in[2]
                            << ") channel " << c << ": ours " << ours[c] << ", OCIO " << px[c];
          }
        }
  }
}

// The device lookup's sub-texel weight box (Vulkan spec, "Texel Filtering": the weight keeps
// subTexelPrecisionBits fraction bits, rounding unspecified) and each tap's weight snapped to the
// nearest grid point (a tie either way; device_allowance.h filter_taps), hand-computed on the
// identity strip (texel (r + 16 b, g) = (r, g, b)/15). UVW = (3.8/16, 6/16, 2.75/16): w = 2.75 −
// 0.5 = 2.25, so IntW = 2, FracW = 0.25; the first sample's x = (3.8/16 + 2)·256/16 − 0.5 = 35.3
// (texels 35, 36 = red 3 and 4 of slice 2, weight α = 0.3), the second's 51.3 (slice 3, the same
// weight); y = 6 − 0.5 = 5.5 (β = 0.5, on every grid; rows 5, 6 = green 5 and 6).
// 8 bits: α·256 = 76.8 → α in {76, 77}/256. The tap weights (1 − α)β and αβ, in 256ths: at 76, 90
// and 38 exactly; at 77, 89.5 and 38.5, ties: [89, 90] and [38, 39]. Red = Σ w·red over the two
// rows: at 77, 2·89·3 + 2·38·4 = 838 up to 2·90·3 + 2·39·4 = 852 (76 gives 844), over 256·15 =
// 3840. Green: (89 + 38)·(5 + 6) = 1397 up to (90 + 39)·11 = 1419. Blue (2/15 in slice 2, 3/15 in
// slice 3, lerped by FracW 0.25): the weights' sum 254 up to 258, times 2.25.
TEST(UeLutBlend, DeviceSampleBoxesTheSubTexelWeight) {
  using hdrc::ref::spirv::Interval;
  const UeLutTexture t = strip_of(identity);
  const std::array<Interval, 3> uvw = {Interval::point(3.8 / 16), Interval::point(6.0 / 16),
                                       Interval::point(2.75 / 16)};
  hdrc::ref::Range3 r = hdrc::ref::unwrapped_texture3d_sample_device(t, uvw, 8);
  constexpr double kArith = 1e-6;  // the shader's own add/sub/mul roundings (float32 ulps)
  EXPECT_NEAR(r.lo[0], 838.0 / 3840, kArith);
  EXPECT_NEAR(r.hi[0], 852.0 / 3840, kArith);
  EXPECT_NEAR(r.lo[1], 1397.0 / 3840, kArith);
  EXPECT_NEAR(r.hi[1], 1419.0 / 3840, kArith);
  EXPECT_NEAR(r.lo[2], 254 * 2.25 / 3840, kArith);
  EXPECT_NEAR(r.hi[2], 258 * 2.25 / 3840, kArith);
  // 4 bits (the core minimum): α·16 = 4.8 → α in {4, 5}/16; at 5 the tap weights 5.5 and 2.5
  // sixteenths, ties: [5, 6] and [2, 3]. Red: 2·5·3 + 2·2·4 = 46 up to 2·6·3 + 2·3·4 = 60, over
  // 16·15 = 240.
  r = hdrc::ref::unwrapped_texture3d_sample_device(t, uvw, 4);
  EXPECT_NEAR(r.lo[0], 46.0 / 240, kArith);
  EXPECT_NEAR(r.hi[0], 60.0 / 240, kArith);
  // The exact lookup lies inside.
  const Vec3 exact = hdrc::ref::unwrapped_texture3d_sample(t, {3.8 / 16, 6.0 / 16, 2.75 / 16});
  for (int c = 0; c < 3; ++c) {
    EXPECT_LE(r.lo[c], exact[c]);
    EXPECT_GE(r.hi[c], exact[c]);
  }
}

// A coordinate interval across a texel centre takes both texel pairs: UVW.x in 0.28125 ± 1e-6
// puts x at (0.28125 + 2)·16 − 0.5 = 36 ± 1.6e-5, texel 36 = red 4 of slice 2; β = 0.5 as above.
// Texels 35, 36 with α in [255/256, 1]: at 255/256 the tap weights (1 − α)β = 0.5/256 and αβ =
// 127.5/256 are ties, [0, 1] and [127, 128]: red down to 2·0·3 + 2·127·4 = 1016 (over 3840).
// Texels 36, 37 with α in [0, 1/256]: at 1/256 the ties [127, 128] and [0, 1]: red up to
// 2·128·4 + 2·1·5 = 1034.
TEST(UeLutBlend, DeviceSampleAcrossATexelCentreTakesBothPairs) {
  using hdrc::ref::spirv::Interval;
  const UeLutTexture t = strip_of(identity);
  const std::array<Interval, 3> uvw = {Interval{0.28125 - 1e-6, 0.28125 + 1e-6},
                                       Interval::point(6.0 / 16), Interval::point(2.75 / 16)};
  const hdrc::ref::Range3 r = hdrc::ref::unwrapped_texture3d_sample_device(t, uvw, 8);
  EXPECT_NEAR(r.lo[0], 1016.0 / 3840, 1e-6);
  EXPECT_NEAR(r.hi[0], 1034.0 / 3840, 1e-6);
}

// The whole blend on a device contains the exact blend. Its width, hand-computed at FilmColor
// 0.5 grey through the identity LUT at full weight: the upstream allowance e = 2^-15 · 0.5 =
// 1.53e-5 moves sRGB by e · 1.055/2.4 · 0.5^(1/2.4 − 1) = 1.01e-5 each way; UVW = 0.73535 · 15/16
// + 1/32 = 0.72064 puts red and green at texel 11.03 (weight 0.030 · 256 = 7.7: box [7, 8]/256;
// the four tap weights snapped to the nearest 1/256 sum, over texel 11 and texel 12, to 249 and 7
// at α = 7/256 (red 2823/3840) and to 248 and 8 at 8/256 (2824/3840): one 2^-8 step of the 1/15
// texel difference, 2.60e-4) and blue at slice weight 0.03 (no box: the shader's lerp). The pow
// pair's and the arithmetic's bounds add a few float32 ulps (5e-6).
TEST(UeLutBlend, DeviceRangeContainsTheBlendAndIsTheBoxWide) {
  const UeLutTexture d = strip_of(identity);
  const std::array<double, 5> w = {0.0, 1.0, 0.0, 0.0, 0.0};
  const std::array<const UeLutTexture*, 4> luts = {&d, nullptr, nullptr, nullptr};
  for (const Vec3& f : {kF, Vec3{0.001, 0.05, 0.97}, Vec3{0.0, 1.0, 0.3}, Vec3{0.5, 0.5, 0.5}}) {
    const Vec3 exact = hdrc::ref::blend_user_luts(f, 2, w, luts);
    const hdrc::ref::Range3 r = hdrc::ref::blend_user_luts_device_range(f, 2, w, luts, 8);
    for (int c = 0; c < 3; ++c) {
      EXPECT_LE(r.lo[c], exact[c]) << "channel " << c << " of " << f[c];
      EXPECT_GE(r.hi[c], exact[c]) << "channel " << c << " of " << f[c];
    }
  }
  const hdrc::ref::Range3 r =
      hdrc::ref::blend_user_luts_device_range({0.5, 0.5, 0.5}, 2, w, luts, 8);
  auto srgb_width = [&](int c) {
    return hdrc::ref::linear_to_srgb(r.hi[c]) - hdrc::ref::linear_to_srgb(r.lo[c]);
  };
  constexpr double kBox = 1.0 / (256 * 15), kUpstream = 2 * 1.01e-5, kUlps = 5e-6;
  for (int c = 0; c < 2; ++c) {
    EXPECT_GE(srgb_width(c), kBox) << "channel " << c;
    EXPECT_LE(srgb_width(c), kBox + kUpstream + kUlps) << "channel " << c;
  }
  EXPECT_GE(srgb_width(2), kUpstream - kUlps);
  EXPECT_LE(srgb_width(2), kUpstream + kUlps);
  // BLENDCOUNT 1: the input's point.
  const hdrc::ref::Range3 one = hdrc::ref::blend_user_luts_device_range(kF, 1, w, luts, 8);
  EXPECT_EQ(one.lo, kF);
  EXPECT_EQ(one.hi, kF);
}

TEST(UeLutBlend, Unorm8Storage) {
  EXPECT_EQ(hdrc::ref::unorm8_from_value(std::nan("")), 0);
  EXPECT_EQ(hdrc::ref::unorm8_from_value(-1.0), 0);
  EXPECT_EQ(hdrc::ref::unorm8_from_value(2.0), 255);
  EXPECT_EQ(hdrc::ref::unorm8_from_value(0.5), 128);  // 127.5: round to nearest, ties to even
  EXPECT_EQ(hdrc::ref::unorm8_from_value(7.0 / 15.0), 119);  // j/15 = 17j/255 exactly
}

}  // namespace
