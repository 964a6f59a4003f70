// VisualizeHDR's device ranges (reference/ue/visualize_device.h) against values derived by hand from
// the Vulkan precision table (Vulkan spec, "Precision and Operation of SPIR-V Instructions":
// OpFAdd/OpFSub/OpFMul correctly rounded, OpFDiv 2.5 ULP, inversesqrt 2 ULP, sqrt inherited from
// 1.0 / inversesqrt).
#include "reference/ue/visualize_device.h"

#include <gtest/gtest.h>

#include <cmath>

#include "reference/ue/visualize/histogram.h"

namespace {

using hdrc::ref::spirv::Interval;
namespace vis = hdrc::ref::visualize;

// The frame's second lerp outside the panel, lerp(border, rgb, 1) = border + 1·(rgb − border), is
// not rgb in float32: with border 0.5 and rgb 1e-3, the subtraction rounds 0.499 by 0.5 ULP
// (ULP 2^-25 in [0.25, 0.5): 2^-26), the product by 1 carries it and rounds by another 2^-26,
// and the sum rounds 1e-3 by 0.5 ULP (ULP 2^-33 in [2^-10, 2^-9): 2^-34): 1e-3 ± 2.986e-8.
TEST(VisualizeDevice, FrameLerpOfANearBlackChannel) {
  const Interval r =
      vis::lerp_range(Interval::point(0.5), Interval::point(1e-3), Interval::point(1.0));
  EXPECT_DOUBLE_EQ(r.lo, 0.0009999701394699514);
  EXPECT_NEAR(r.hi - 1e-3, 2.986053004860878e-08, 1e-18);
}

// Inside the panel the frame lerps make the background black: 0 + 0·(rgb − 0) is 0 whatever rgb,
// up to the product's and the sum's 0.5 ULP at zero (2^-150 each).
TEST(VisualizeDevice, InteriorBlackStaysBlack) {
  const Interval r = vis::lerp_range(Interval::point(0.0), {0.2, 0.3}, Interval::point(0.0));
  EXPECT_EQ(r.lo, -0x1p-149);
  EXPECT_EQ(r.hi, 0x1p-149);
}

// ComputeDistanceToRect's sqrt(45) (6 px left, 3 px above the panel): 1/sqrt(45) =
// 0.149071198 ± 2 ULP (2^-26 in [0.125, 0.25)), its reciprocal ± 2.5 ULP (2^-21 in [4, 8)):
// [6.7082013993, 6.7082064657], sqrt(45) + 2.53e-6 at the top.
TEST(VisualizeDevice, RectDistanceSqrt) {
  const Interval d = vis::sqrt_range(45.0);
  EXPECT_DOUBLE_EQ(d.lo, 6.708201399302234);
  EXPECT_DOUBLE_EQ(d.hi, 6.70820646569704);
}

// The bar top: histogram[b] / max ≥ 1 − v. For the tallest bucket the quotient is h/h, which a
// device may return 2.5 ULP below 1 (OpFDiv); in the panel's top row 1 − v is 1 (v = 0/128), so
// the bar's top pixel may be drawn or not; one row lower 1 − v = 127/128 is far below any
// rounding of 1, so the row below has no such freedom. A uniform grey scene of 0.18 splats
// its whole weight on buckets 15 and 16 (position log2(0.18)/30 + 1/3 = 0.2509, f = 15.81).
TEST(VisualizeDevice, BarTopOfTheTallestBucketEitherWay) {
  const int w = 192, h = 168;
  hdrc::Image hdr(w, h), scene(w, h);
  for (size_t i = 0; i < hdr.pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) hdr.data[i * 4 + c] = 0.18;
  vis::VisualizeHdrInputs in;
  in.params = vis::compute_eye_adaptation_parameters(vis::default_settings(true));
  in.scene_color = &scene;
  in.hdr_scene_color = &hdr;
  in.histogram = vis::build_histogram(hdr, in.params, 1.0);
  in.eye.average_scene_luminance = vis::average_luminance_without_outliers(in.histogram, in.params);
  in.tone_curve = vis::per_channel([](double) { return -10.0; });  // no overlay in the panel
  ASSERT_GT(in.histogram[16], in.histogram[15]);
  const vis::VisualizeHdrResult ref = vis::visualize_hdr(in);
  const std::vector<hdrc::AdmissibleRange> none;
  vis::VisualizeDeviceInputs d;
  d.in = &in;
  d.reference = &ref.image;
  d.scene_ranges = &none;
  const std::vector<hdrc::AdmissibleRange> ranges = vis::visualize_hdr_device_ranges(d);
  const vis::PanelGeometry g = vis::panel_geometry(w, h);
  auto widest = [&](int x, int y) {
    double width = 0;
    for (const hdrc::AdmissibleRange& a : ranges)
      if (a.pixel == static_cast<size_t>(y) * w + x)
        for (int c = 0; c < 3; ++c) width = std::fmax(width, a.hi[c] - a.lo[c]);
    return width;
  };
  const int column = g.left + 16;  // bucket 16 = inset·64/width with width 64
  // The bar's colour lerp(tinted, Colorize(0.25), 0.5) = (0.1875, 0.45, 0.3125) or the tinted
  // black (0.25, 0.4, 0.25): 1/16 apart in R and B.
  EXPECT_NEAR(widest(column, g.top), 0.0625, 1e-5);
  EXPECT_LT(widest(column, g.top + 1), 1e-5);
  EXPECT_LT(widest(column - 1, g.top), 1e-5);  // bucket 15 is lower: no bar in the top row
}

}  // namespace
