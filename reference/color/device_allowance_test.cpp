// The derived device intervals against hand-computed examples (issue 24): a 2-texel lookup at 4
// and 8 sub-texel bits, a PQ encode with the specification's transcendental bounds, an fma pair,
// and the storage neighbours.
#include "reference/color/device_allowance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace hdrc::ref {
namespace {

// Two texels 0 and 1 of a 2-texel row, sampled at u = 0.4: t = u·2 − 0.5 = 0.3, taps (0, 1),
// exact weight 0.3. 8 bits: 0.3·256 = 76.8, so the weight is 76/256 = 0.296875 or
// 77/256 = 0.30078125. 4 bits: 0.3·16 = 4.8, so 4/16 = 0.25 or 5/16 = 0.3125. The filtered value
// of texels (0, 1) is the weight itself.
TEST(DeviceAllowance, TwoTexelLookupAtFourAndEightBits) {
  const TapBox b8 = linear_tap_box(0.4 * 2 - 0.5, 2, 8, 0.0);
  EXPECT_EQ(b8.i0, 0);
  EXPECT_EQ(b8.i1, 1);
  EXPECT_DOUBLE_EQ(b8.f_lo, 0.296875);
  EXPECT_DOUBLE_EQ(b8.f_hi, 0.30078125);
  const TapBox b4 = linear_tap_box(0.4 * 2 - 0.5, 2, 4, 0.0);
  EXPECT_DOUBLE_EQ(b4.f_lo, 0.25);
  EXPECT_DOUBLE_EQ(b4.f_hi, 0.3125);
  // On the grid (t = 0.25 at 4 bits) the weight is exact; the coordinate's own noise opens it.
  const TapBox exact = linear_tap_box(0.25, 2, 4, 0.0);
  EXPECT_DOUBLE_EQ(exact.f_lo, 0.25);
  EXPECT_DOUBLE_EQ(exact.f_hi, 0.25);
  const TapBox noisy = linear_tap_box(0.25, 2, 4, 1e-6);
  EXPECT_DOUBLE_EQ(noisy.f_lo, 0.1875);
  EXPECT_DOUBLE_EQ(noisy.f_hi, 0.3125);
  // Clamp to edge: past the last texel both taps are the last one.
  const TapBox edge = linear_tap_box(1.7, 2, 8, 0.0);
  EXPECT_EQ(edge.i0, 1);
  EXPECT_EQ(edge.i1, 1);
}

// The filter's arithmetic at VK-GL-CTS's precision (FilterArithmetic, filter_taps), by hand.
// 2-texel row, 8-bit UNORM (grid 1/255): texels 51/255 = 0.2 and 153/255 = 0.6 at α = 1/2 (on the
// sub-texel grid). Each weight 1/2 rounds outward to [127, 128]/255 (127.5). Tap 0: [127, 128] ·
// 51/255 / 255 = [25.4, 25.6]/255, rounded outward [25, 26]/255. Tap 1 adds [127, 128] · 153/255
// = [76.2, 76.8]/255: [101.2, 102.8]/255, rounded outward [101, 103]/255. Exact: 0.4 = 102/255.
// RGBA16F (10 fraction bits): 1/2, 0.2·1/2 and the sum are within a float16 ulp of the exact ones;
// float32 likewise; exact arithmetic gives 0.4 exactly.
TEST(DeviceAllowance, TwoTexelFilterAtTheCtsPrecision) {
  const double alpha[1] = {0.5};
  const double t[2] = {51.0 / 255, 153.0 / 255};
  const FilteredRange u8 = filter_taps(1, alpha, t, t, FilterArithmetic::unorm(8));
  EXPECT_DOUBLE_EQ(u8.lo, 101.0 / 255);
  EXPECT_DOUBLE_EQ(u8.hi, 103.0 / 255);
  const FilteredRange exact = filter_taps(1, alpha, t, t, FilterArithmetic::exact());
  EXPECT_DOUBLE_EQ(exact.lo, 0.5 * t[0] + 0.5 * t[1]);
  EXPECT_DOUBLE_EQ(exact.hi, exact.lo);
  // float16: 0.5·0.2 = 0.1 lies in [2^-4, 2^-3): quantum 2^-14; the sum 0.4 in [2^-2, 2^-1):
  // quantum 2^-12. Lower end: floor(0.1·2^14)/2^14 = 1638/16384, then 1638/16384 + 0.3 =
  // 0.39998 → floor(·4096)/4096 = 1638/4096; upper: ceil(0.1·2^14) = 1639, 1639/16384 + 0.3 →
  // ceil(·4096) = 1639/4096.
  const FilteredRange f16 = filter_taps(1, alpha, t, t, FilterArithmetic::float16());
  EXPECT_DOUBLE_EQ(f16.lo, 1638.0 / 4096);
  EXPECT_DOUBLE_EQ(f16.hi, 1639.0 / 4096);
  const FilteredRange f32 = filter_taps(1, alpha, t, t, FilterArithmetic::float32());
  EXPECT_LE(f32.lo, 0.4);
  EXPECT_GE(f32.hi, 0.4);
  EXPECT_LE(f32.hi - f32.lo, 2 * 0x1p-25);
}

// A 2×2 lookup at α = β = 1/2, texel (1, 0) = 1 and the others 0 (tap 1: bit 0 the upper x). The
// weight of tap 1 is (1 − β)·α, formed as the CTS does: 1 − β rounded outward, [127, 128]/255,
// times α = 1/2: [63.5, 64]/255, rounded outward [63, 64]/255. So a UNORM8 texture's filter may
// weigh the texel by 63/255 = 0.24706 where the exact product is 0.25 (and the sub-texel weights
// are exact): per-product rounding, on the format's grid. With 10 bits (A2B10G10R10) the grid
// is 1/1023: [511.5 → 511, 512]/1023 · 1/2 = [255.5, 256]/1023 → [255, 256]/1023. Float32: exact.
TEST(DeviceAllowance, TwoByTwoFilterRoundsEachProductWeightInTheFormat) {
  const double alpha[2] = {0.5, 0.5};
  const double t[4] = {0, 1, 0, 0};
  const FilteredRange u8 = filter_taps(2, alpha, t, t, FilterArithmetic::unorm(8));
  EXPECT_DOUBLE_EQ(u8.lo, 63.0 / 255);
  EXPECT_DOUBLE_EQ(u8.hi, 64.0 / 255);
  const FilteredRange u10 = filter_taps(2, alpha, t, t, FilterArithmetic::unorm(10));
  EXPECT_DOUBLE_EQ(u10.lo, 255.0 / 1023);
  EXPECT_DOUBLE_EQ(u10.hi, 256.0 / 1023);
  const FilteredRange f32 = filter_taps(2, alpha, t, t, FilterArithmetic::float32());
  EXPECT_DOUBLE_EQ(f32.lo, 0.25);
  EXPECT_DOUBLE_EQ(f32.hi, 0.25);
  // The H200's graded-look weight (docs/precision.md, unity_urp): the box corner α = 163/256,
  // 1 − β = 12/256 gives the product 1956/65536 = 0.029846, a float16 value (quantum 2^-16 in
  // [2^-6, 2^-5)): an RGBA16F texture's filter may not round it to 8/256 = 0.03125.
  const double h200[2] = {163.0 / 256, 244.0 / 256};
  const double one[4] = {0, 1, 0, 0};
  const FilteredRange w = filter_taps(2, h200, one, one, FilterArithmetic::float16());
  EXPECT_DOUBLE_EQ(w.lo, 1956.0 / 65536);
  EXPECT_DOUBLE_EQ(w.hi, 1956.0 / 65536);
  EXPECT_LT(w.hi, 8.0 / 256);
  // With the tap's weight on the 8-bit grid as well (weight_bits: the specification's "sub-texel
  // values ... will snap to these locations"): 1956/65536 = 7.64/256 snaps to 8/256, the H200's.
  // The range holds both, the product (a device that does not snap it) and the snap.
  const FilteredRange snapped = filter_taps(2, h200, one, one, FilterArithmetic::float16(), 8);
  EXPECT_DOUBLE_EQ(snapped.lo, 1956.0 / 65536);
  EXPECT_DOUBLE_EQ(snapped.hi, 8.0 / 256);
}

// Each tap's weight snapped to the nearest 2^-bits point or not, by hand (filter_taps, weight_bits
// 8): α = 77/256 along x, β = 1/2 along y. Tap 1 (upper x, lower y) weighs α(1 − β) = 38.5/256,
// a tie: 38/256 up to 39/256. Tap 0 weighs (1 − α)(1 − β) = 89.5/256, also a tie. At α = β =
// 7/256 the taps weigh 249²/65536 = 242.19/256 (snapped 242/256), 249·7/65536 = 6.81/256 (7/256)
// and 49/65536 = 0.19/256 (0): each range from the snap to the product (one texel read: the
// filters with and without snapping give the two ends). One axis: the weight is the fraction.
TEST(DeviceAllowance, TapWeightsSnapToTheNearestGridPoint) {
  const double alpha[2] = {77.0 / 256, 0.5};
  const double tap1[4] = {0, 1, 0, 0}, tap0[4] = {1, 0, 0, 0};
  FilteredRange r = filter_taps(2, alpha, tap1, tap1, FilterArithmetic::exact(), 8);
  EXPECT_DOUBLE_EQ(r.lo, 38.0 / 256);
  EXPECT_DOUBLE_EQ(r.hi, 39.0 / 256);
  r = filter_taps(2, alpha, tap0, tap0, FilterArithmetic::exact(), 8);
  EXPECT_DOUBLE_EQ(r.lo, 89.0 / 256);
  EXPECT_DOUBLE_EQ(r.hi, 90.0 / 256);
  const double seven[2] = {7.0 / 256, 7.0 / 256};
  const double tap3[4] = {0, 0, 0, 1}, tap2[4] = {0, 0, 1, 0};
  r = filter_taps(2, seven, tap0, tap0, FilterArithmetic::exact(), 8);
  EXPECT_DOUBLE_EQ(r.lo, 242.0 / 256);
  EXPECT_DOUBLE_EQ(r.hi, 249.0 * 249 / 65536);
  r = filter_taps(2, seven, tap2, tap2, FilterArithmetic::exact(), 8);
  EXPECT_DOUBLE_EQ(r.lo, 249.0 * 7 / 65536);
  EXPECT_DOUBLE_EQ(r.hi, 7.0 / 256);
  r = filter_taps(2, seven, tap3, tap3, FilterArithmetic::exact(), 8);
  EXPECT_EQ(r.lo, 0.0);
  EXPECT_DOUBLE_EQ(r.hi, 49.0 / 65536);
  // Without weight_bits the exact products.
  r = filter_taps(2, seven, tap3, tap3, FilterArithmetic::exact());
  EXPECT_DOUBLE_EQ(r.hi, 49.0 / 65536);
  const double one_axis[1] = {0.3};
  const double t01[2] = {0, 1};
  r = filter_taps(1, one_axis, t01, t01, FilterArithmetic::exact(), 8);
  EXPECT_DOUBLE_EQ(r.hi, 0.3);
}

// The CTS's unnormalised coordinate (cts_texel_range: u, then u·size, rounded outward to 16
// fraction bits), by hand. Along a 1024-texel strip at t = 1000.3: u = 1000.8/1024 = 0.97734375,
// in [1/2, 1) the quantum 2^-17: u·2^17 = 128102.4, so u in [128102, 128103]/2^17; times 1024:
// [1000.796875, 1000.8046875], multiples of 2^-7, the quantum of the product in [512, 1024). So t
// in [1000.296875, 1000.3046875]: the 8-bit box of the fraction 0.3 (76.8/256) is [76, 78]/256,
// not [76, 77]/256. Along 17 texels at t = 4.72 (the fraction 184.32/256) the widening is about
// 1.3e-4 texel: the box stays [184, 185]/256.
TEST(DeviceAllowance, CtsCoordinateRoundingWidensALongStripsBox) {
  const CoordRange r = cts_texel_range(1000.3, 1000.3, 1024);
  EXPECT_DOUBLE_EQ(r.lo, 1000.296875);
  EXPECT_DOUBLE_EQ(r.hi, 1000.3046875);
  // linear_tap_boxes: one box of taps (1000, 1001), the fraction from 76/256 to 78/256.
  const std::vector<TapBox> strip = linear_tap_boxes(1000.3, 1024, 8, 0.0);
  ASSERT_EQ(strip.size(), 1u);
  EXPECT_EQ(strip[0].i0, 1000);
  EXPECT_DOUBLE_EQ(strip[0].f_lo, 76.0 / 256);
  EXPECT_DOUBLE_EQ(strip[0].f_hi, 78.0 / 256);
  const std::vector<TapBox> lut = linear_tap_boxes(4.72, 17, 8, 0.0);
  ASSERT_FALSE(lut.empty());
  EXPECT_DOUBLE_EQ(lut.front().f_lo, 184.0 / 256);
  EXPECT_DOUBLE_EQ(lut.back().f_hi, 185.0 / 256);
  // A coordinate the format holds exactly stays a point (u = 1/2 on 2 texels: t = 0.5).
  const CoordRange exact = cts_texel_range(0.5, 0.5, 2);
  EXPECT_EQ(exact.lo, 0.5);
  EXPECT_EQ(exact.hi, 0.5);
}

// filter_round by hand: UNORM b on the grid 1/(2^b − 1), floats on their significand, the
// exponent's floor keeping subnormal quanta (float16: 2^-24).
TEST(DeviceAllowance, FilterRoundOnTheFormatsGrid) {
  EXPECT_DOUBLE_EQ(filter_round(0.5, false, FilterArithmetic::unorm(8)), 127.0 / 255);
  EXPECT_DOUBLE_EQ(filter_round(0.5, true, FilterArithmetic::unorm(8)), 128.0 / 255);
  EXPECT_DOUBLE_EQ(filter_round(1.0 / 3, false, FilterArithmetic::float16()), 1365.0 / 4096);
  EXPECT_DOUBLE_EQ(filter_round(1.0 / 3, true, FilterArithmetic::float16()), 1366.0 / 4096);
  EXPECT_DOUBLE_EQ(filter_round(3e-8, true, FilterArithmetic::float16()), 0x1p-24);
  EXPECT_DOUBLE_EQ(filter_round(-1.0 / 3, false, FilterArithmetic::float16()), -1366.0 / 4096);
  // float32: 1/3 lies between 0x3eaaaaaa and 0x3eaaaaab, one ulp (2^-25) apart.
  const double f_lo = filter_round(1.0 / 3, false, FilterArithmetic::float32());
  const double f_hi = filter_round(1.0 / 3, true, FilterArithmetic::float32());
  EXPECT_LT(f_lo, 1.0 / 3);
  EXPECT_GT(f_hi, 1.0 / 3);
  EXPECT_DOUBLE_EQ(f_hi - f_lo, 0x1p-25);
  EXPECT_EQ(static_cast<double>(static_cast<float>(f_lo)), f_lo);
  EXPECT_EQ(filter_round(0.7, true, FilterArithmetic::exact()), 0.7);
}

// A coordinate at a texel centre with noise: t = 3 ± 0.001 in a row of 8 at 8 bits. Below the
// centre (t = 2.999) the taps are (2, 3) with fraction 0.999: 0.999·256 = 255.744, box
// [255/256, 1]; at the plane t = 3, taps (3, 4) with weight exactly 0; above (t = 3.001), taps
// (3, 4) with fraction 0.001: 0.256, box [0, 1/256]. Inside one cell (t = 2.5 ± 0.001): the ends
// 2.499 (0.499·256 = 127.744: [127/256, 128/256]) and 2.501 ([128/256, 129/256]), one box of the
// same taps: [127/256, 129/256].
TEST(DeviceAllowance, TapBoxesAcrossATexelPlane) {
  const std::vector<TapBox> c = linear_tap_boxes(3.0, 8, 8, 0.001);
  // The plane's box (taps 3, 4 at weight 0) and the upper end's (taps 3, 4) merge into one.
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].i0, 2);
  EXPECT_EQ(c[0].i1, 3);
  EXPECT_DOUBLE_EQ(c[0].f_lo, 255.0 / 256);
  EXPECT_DOUBLE_EQ(c[0].f_hi, 1.0);
  EXPECT_EQ(c[1].i0, 3);
  EXPECT_EQ(c[1].i1, 4);
  EXPECT_DOUBLE_EQ(c[1].f_lo, 0.0);
  EXPECT_DOUBLE_EQ(c[1].f_hi, 1.0 / 256);
  const std::vector<TapBox> in = linear_tap_boxes(2.5, 8, 8, 0.001);
  ASSERT_EQ(in.size(), 1u);
  EXPECT_EQ(in[0].i0, 2);
  EXPECT_DOUBLE_EQ(in[0].f_lo, 127.0 / 256);
  EXPECT_DOUBLE_EQ(in[0].f_hi, 129.0 / 256);
}

// ulp as the specification defines it.
TEST(DeviceAllowance, UlpOfFloat32) {
  EXPECT_EQ(spirv::ulp32(1.0), 0x1p-23);
  EXPECT_EQ(spirv::ulp32(1.5), 0x1p-23);
  EXPECT_EQ(spirv::ulp32(0.75), 0x1p-24);
  EXPECT_EQ(spirv::ulp32(-8.0), 0x1p-20);
  EXPECT_EQ(spirv::ulp32(1e-40), 0x1p-149);
}

// a·b + c with a = b = 1 + 2^-12, c = −1. Exactly a·b = 1 + 2^-11 + 2^-24: a tie between the
// floats 1 + 2^-11 and 1 + 2^-11 + 2^-23, which round-to-nearest-even resolves to 1 + 2^-11, so
// the unfused result is 2^-11; fused, one rounding of 2^-11 + 2^-24 (exact in float32) gives
// 2^-11 + 2^-24. A conformant device may return either: the interval holds both.
TEST(DeviceAllowance, FusedAndUnfusedMultiplyAddAreBothAdmitted) {
  const float a = 1.0f + 0x1p-12f, c = -1.0f;
  const volatile float product = a * a;  // rounded to float32 before the add
  const float unfused = product + c;
  const float fused = std::fma(a, a, c);
  EXPECT_EQ(unfused, 0x1p-11f);
  EXPECT_EQ(fused, 0x1p-11f + 0x1p-24f);
  const spirv::Interval r = spirv::mul_add(spirv::Interval::point(a), spirv::Interval::point(a),
                                           spirv::Interval::point(c));
  EXPECT_TRUE(r.contains(unfused));
  EXPECT_TRUE(r.contains(fused));
  // And no wider than the two roundings: 0.5 ulp(1) of the product plus 0.5 ulp(2^-11) of the sum.
  EXPECT_LE(r.width(), 2 * (0.5 * 0x1p-23 + 0.5 * 0x1p-34) + 1e-18);
}

// PQ encode of 100 nits with the specification's bounds (by hand, first order):
//   Y = 0.01; log2 Y = −6.6439, outside [0.5, 2]: 3 ulp(6.64) = 3·2^-21 = 1.43e-6;
//   x = m1·log2 Y = −1.05838, error m1·1.43e-6 + 0.5 ulp(1.06) = 2.28e-7 + 5.96e-8 = 2.88e-7;
//   P = 2^x = 0.48037, error ln2·P·2.88e-7 + (3 + 2·1.06)·ulp(0.48) = 9.6e-8 + 1.53e-7 = 2.49e-7
//       (the multiply Y = nits·1e-4 adds 0.5 ulp(0.01): 4.7e-10 · m1/Y·P ≈ 3.6e-9, negligible);
//   num = c1 + c2·P = 9.89169, error c2·2.49e-7 + two half-ulps (0.5 ulp(9.06) + 0.5 ulp(9.89)) =
//       4.69e-6 + 9.5e-7 = 5.64e-6; den = 1 + c3·P = 9.97692, error c3·2.49e-7 + 9.5e-7 = 5.6e-6;
//   ratio = 0.991457, relative error 5.64e-6/9.89 + 5.6e-6/9.98 + 2.5 ulp(0.99)/0.99 =
//       5.70e-7 + 5.61e-7 + 1.50e-7 = 1.28e-6;
//   log2 ratio = −0.012378 inside [0.5, 2]: 2^-21 + 1.28e-6/ln2 = 4.77e-7 + 1.85e-6 = 2.32e-6;
//   z = m2·log2 ratio = −0.97593, error 78.84·2.32e-6 + 0.5 ulp(0.98) = 1.830e-4 + 3e-8;
//   PQ = 2^z = 0.508078, error ln2·PQ·1.830e-4 + (3 + 2·0.976)·ulp(0.508) = 6.446e-5 + 2.95e-7.
// Half-width ≈ 6.48e-5 (0.066 10-bit codes): the amplification by m2 of the ratio's few roundings
// dominates, not exp2's own ULPs.
TEST(DeviceAllowance, PqEncodeWithinTheSpecificationsBounds) {
  const spirv::Interval r = pq_encode_on_device(100.0);
  const double exact = st2084::pq_from_nits(100.0);
  EXPECT_NEAR(exact, 0.508078, 1e-6);
  EXPECT_TRUE(r.contains(exact));
  const double half_width = 0.5 * r.width();
  EXPECT_NEAR(half_width, 6.48e-5, 0.04 * 6.48e-5);
  EXPECT_NEAR(r.hi - exact, exact - r.lo, 1e-6);
  // A float32 evaluation with the host's libm lies inside, by a wide margin.
  const float y = 100.0f * 1e-4f;
  const float p = std::pow(y, float(st2084::kM1));
  const float ratio =
      (float(st2084::kC1) + float(st2084::kC2) * p) / (1.0f + float(st2084::kC3) * p);
  EXPECT_TRUE(r.contains(std::pow(ratio, float(st2084::kM2))));
  // Black: P = 0 exactly, then c1^m2 = 7.3e-7 with pow's bound; the interval is increasing.
  EXPECT_TRUE(pq_encode_on_device(0.0).contains(st2084::pq_from_nits(0.0)));
  EXPECT_LT(pq_encode_on_device(99.0).hi, pq_encode_on_device(101.0).lo);
}

// Storage neighbours: 10-bit UNORM (0.6 of a code: code 0 or 1), float16 (between 1 and its next
// half 1 + 2^-10), float32.
TEST(DeviceAllowance, StorageMayRoundEitherWay) {
  EXPECT_EQ(unorm_floor(0.6 / 1023, 1023), 0.0);
  EXPECT_EQ(unorm_ceil(0.6 / 1023, 1023), 1.0 / 1023);
  EXPECT_EQ(unorm_floor(5.0 / 1023, 1023), 5.0 / 1023);
  EXPECT_EQ(unorm_ceil(5.0 / 1023, 1023), 5.0 / 1023);
  EXPECT_EQ(unorm_ceil(1.7, 1023), 1.0);
  EXPECT_EQ(half_round_down(1.0 + 0x1p-12), 1.0);
  EXPECT_EQ(half_round_up(1.0 + 0x1p-12), 1.0 + 0x1p-10);
  EXPECT_EQ(half_round_down(-1.0 - 0x1p-12), -1.0 - 0x1p-10);
  EXPECT_EQ(half_round_up(-1.0 - 0x1p-12), -1.0);
  EXPECT_EQ(half_round_down(0.25), 0.25);
  EXPECT_EQ(half_round_up(0x1p-30), 0x1p-24);  // under the smallest subnormal
  EXPECT_EQ(half_round_down(0x1p-30), 0.0);
  EXPECT_EQ(half_round_down(70000.0), 65504.0);
  EXPECT_TRUE(std::isinf(half_round_up(70000.0)));
  EXPECT_EQ(float_round_down(0.1), double(std::nextafter(0.1f, 0.0f)));
  EXPECT_EQ(float_round_up(0.1), double(0.1f));
}

}  // namespace
}  // namespace hdrc::ref
