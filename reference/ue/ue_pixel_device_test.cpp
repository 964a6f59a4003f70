// reference/ue/ue_pixel_device.h: the device ranges of UE 5.5's shaper and linear-device stages.
#include "reference/ue/ue_pixel_device.h"

#include <gtest/gtest.h>

#include <cmath>

#include "color/st2084.h"
#include "reference/ue/lut_shaper.h"

namespace hdrc::ref::ue_device {
namespace {

// float32 neighbours of 0.1, by hand: 0.1 = 0x1.99999999...p-4; the float32 significand keeps
// 23 fraction bits: 0x1.99999ap-4 (rounded up) and 0x1.999998p-4 below.
TEST(UePixelDevice, ConstantIsTheFloat32Neighbours) {
  const spirv::Interval c = constant(0.1);
  EXPECT_EQ(c.lo, 0x1.999998p-4);
  EXPECT_EQ(c.hi, 0x1.99999ap-4);
  EXPECT_EQ(constant(0.5).lo, 0.5);  // exact in float32: a point
  EXPECT_EQ(constant(0.5).hi, 0.5);
}

// pow(4, 0.5) = exp2(0.5 · log2 4), by hand from the precision table:
//   log2(4) = 2, outside [0.5, 2]: ± 3 ulp(2) = 3·2^-22;
//   × 0.5: [1 − 3·2^-23, 1 + 3·2^-23], rounded 0.5 ulp: below 1 ulp is 2^-24, above 2^-23:
//     t in [1 − 3.25·2^-23, 1 + 3.5·2^-23];
//   exp2: 2^t = 2(1 + ln2·δ) to first order, then ± (3 + 2|t|) = 5 ulp of the result
//     (2^-23 below 2, 2^-22 above):
//     lo = 2 − (6.5 ln2 + 5)·2^-23 = 2 − 9.5055·2^-23, hi = 2 + (7 ln2 + 10)·2^-23 = 2
//     + 14.852·2^-23.
TEST(UePixelDevice, PowConstBoundsByHand) {
  const spirv::Interval r = pow_const(spirv::Interval::point(4.0), 0.5);
  EXPECT_NEAR((2.0 - r.lo) / 0x1p-23, 6.5 * std::log(2.0) + 5.0, 1e-3);
  EXPECT_NEAR((r.hi - 2.0) / 0x1p-23, 7.0 * std::log(2.0) + 10.0, 1e-3);
  // pow(0, y) = 0 (pow_d3d) on every device.
  EXPECT_EQ(pow_const(spirv::Interval::point(0.0), 0.5).hi, 0.0);
}

// The PQ shaper round trip of 1.0 (100 nits): the range holds the exact value, is wider than
// float32 rounding (the encode's pow(·, m2 = 78.84) amplifies log2's 2^-21 absolute error:
// 78.84 · 2^-21 · ln2 = 2.6e-5 relative in the PQ signal, about 2.6e-5 · (d ln N / d ln PQ) in
// nits), and a planted 0.1 % gain (LinearToNitsScale 100.1) lies outside it.
TEST(UePixelDevice, PqShaperRangeHoldsExactAndRejectsPlantedGain) {
  const ChannelRanges r = shaper_device_range(/*output_device=*/3, {1.0, 0.5, 0.0});
  for (int c = 0; c < 3; ++c) ASSERT_TRUE(r.valid[c]);
  EXPECT_TRUE(r.c[0].contains(1.0));
  EXPECT_TRUE(r.c[1].contains(0.5));
  EXPECT_GT(r.c[0].width(), 64 * 0x1p-23);  // beyond float32 rounding
  EXPECT_LT(r.c[0].width(), 1e-3);
  const double planted = ref::lut_decode(3, st2084::pq_from_nits(100.1));
  EXPECT_FALSE(r.c[0].contains(planted)) << r.c[0].lo << " " << r.c[0].hi << " " << planted;
  // 0 stays 0 within the device's error of PQ at black (pow(c1, m2) · 1e4 / 100 ≈ 7e-5 is the
  // exact round trip's floor on a device: the range may dip below and above 0).
  EXPECT_TRUE(r.c[2].contains(0.0));
  EXPECT_GE(r.c[2].lo, 0.0);
  // A negative input under PQ: NaN on every device (the point value alone).
  EXPECT_FALSE(shaper_device_range(3, {-0.5, 0, 0}).valid[0]);
}

// The log shaper: lattice 0 decodes to 0 (lut_shaper.glsl), and the grey point round-trips
// within a range that holds it.
TEST(UePixelDevice, LogShaperRange) {
  const ChannelRanges r = shaper_device_range(/*output_device=*/0, {0.18, 0.0, -1.0});
  EXPECT_TRUE(r.c[0].contains(0.18));
  EXPECT_LT(r.c[0].width(), 1e-5);
  EXPECT_TRUE(r.c[1].contains(0.0));
  EXPECT_EQ(r.c[2].lo, 0.0);  // saturated to lattice 0, decoded as 0
  EXPECT_EQ(r.c[2].hi, 0.0);
}

// Linear device 7: an output-gamut channel that is exactly 0 (here r − g of a grey, a planted
// matrix row (1, −1, 0)) straddles 0 on a device: NaN admissible (pow of a negative base), and
// the range's non-negative part starts at 0; a clearly negative one (g − 2r) is NaN alone.
TEST(UePixelDevice, LinearDevice7NegativeOutputGamut) {
  ParamBlock p;
  p.output_device = 7;
  p.ap1_to_output = Mat3{{1, -1, 0, -2, 1, 0, 0, 0, 1}};
  const ChannelRanges r = linear_device_range(p, {0.5, 0.5, 0.5});
  ASSERT_TRUE(r.valid[0]);
  EXPECT_TRUE(r.nan[0]);
  EXPECT_EQ(r.c[0].lo, 0.0);
  EXPECT_LT(r.c[0].hi, 1e-3);
  EXPECT_FALSE(r.valid[1]);
  EXPECT_TRUE(r.c[2].contains(0.5));
  EXPECT_FALSE(r.nan[2]);
}

// The UI composite on an scRGB back buffer (device 5, every step linear): kShaderNoise × the
// largest |channel| either side of the reference, by hand: (1, 0.5, 0) → ±2^-15 on each channel.
TEST(UePixelDevice, UiCompositeScRgbIsShaderNoise) {
  ParamBlock p;
  p.output_device = 5;
  p.ui_composite_mode = 1;
  p.ui_level = 1;
  p.ui_luminance = 300;
  Image scene(1, 1), ui(1, 1), ref(1, 1);
  const double v[4] = {1.0, 0.5, 0.0, 1.0};
  for (int c = 0; c < 4; ++c) ref.data[c] = v[c];
  const auto r = ui_composite_device_ranges(p, scene, ui, ref);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].lo[0], 1.0 - 0x1p-15);
  EXPECT_EQ(r[0].hi[1], 0.5 + 0x1p-15);
  EXPECT_EQ(r[0].lo[2], -0x1p-15);
  EXPECT_EQ(r[0].lo[3], 1.0);  // alpha: the point value
}

// The UI composite on a PQ back buffer with no UI (alpha 0: the scene passes, decode then encode):
// the range holds the input code, and a planted 0.1 % gain in nits lies outside it.
TEST(UePixelDevice, UiCompositePqRoundTrip) {
  ParamBlock p;
  p.output_device = 3;
  p.ui_composite_mode = 1;
  p.ui_level = 1;
  p.ui_luminance = 300;
  Image scene(1, 1), ui(1, 1), ref(1, 1);
  const double code = st2084::pq_from_nits(100.0);
  for (int c = 0; c < 3; ++c) scene.data[c] = ref.data[c] = code;
  ref.data[3] = 1.0;
  const auto r = ui_composite_device_ranges(p, scene, ui, ref);
  ASSERT_EQ(r.size(), 1u);
  const double planted = st2084::pq_from_nits(100.1);
  for (int c = 0; c < 3; ++c) {
    EXPECT_LE(r[0].lo[c], code);
    EXPECT_GE(r[0].hi[c], code);
    EXPECT_LT(r[0].hi[c], planted) << c;
  }
}

}  // namespace
}  // namespace hdrc::ref::ue_device
