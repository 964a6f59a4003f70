// pq_grading's reference against numbers from outside our code: ST 2084's published code values,
// OpenColorIO's FileTransform on the same .cube files (trilinear and tetrahedral), and values of
// the formulas derived by hand (the derivation beside each).
#include "reference/pq_grading/pq_grading.h"

#include <OpenColorIO/OpenColorIO.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/case.h"
#include "core/cube/cube.h"
#include "core/cube/ocio_oracle.h"
#include "core/settings.h"
#include "reference/color/strip_device_range.h"
#include "reference/pq_grading/pq_grading_pipeline.h"

namespace {

namespace OCIO = OCIO_NAMESPACE;
using hdrc::ParamBlock;
using hdrc::ref::Vec3;
using namespace hdrc::ref::pq_grading;

const std::string kCubeDir = std::string(HDRC_SOURCE_DIR) + "/cases/lut/cube/";

// A LUT as the loader hands it to the engines: the .cube's table as the strip texture, and the
// parameters of the given settings.
struct Loaded {
  hdrc::UserLut lut;
  hdrc::Image strip;
  ParamBlock p;
};

Loaded load(const std::string& file, double amplify, Display display, BackBuffer bb) {
  Loaded l;
  auto cube = hdrc::cube::read_cube_file(kCubeDir + file);
  EXPECT_TRUE(cube.ok()) << file;
  if (!cube.ok()) return l;
  l.lut.size = cube->size_3d;
  l.lut.domain_min = cube->domain_min_3d;
  l.lut.domain_max = cube->domain_max_3d;
  l.lut.table = cube->table_3d;
  l.strip = hdrc::user_lut_strip(l.lut);
  hdrc::SettingValues s(&pq_grading_setting_table(), &pq_grading_setting_choices);
  EXPECT_TRUE(bool(s.set("Amplify", {amplify, 0, 0, 0}, 1)));
  EXPECT_TRUE(bool(s.set("Display", {double(static_cast<int>(display)), 0, 0, 0}, 1)));
  EXPECT_TRUE(bool(s.set("BackBuffer", {double(static_cast<int>(bb)), 0, 0, 0}, 1)));
  derive_pq_grading(s, &l.p);
  l.p.user_lut_size = l.lut.size;
  for (int c = 0; c < 3; ++c) {
    l.p.user_lut_domain_min[c] = l.lut.domain_min[c];
    l.p.user_lut_domain_max[c] = l.lut.domain_max[c];
  }
  return l;
}

// ST 2084's published signal values (ITU-R BT.2100 / BT.2390 tables, as
// color/st2084_test.cpp cites them): 100 cd/m² → 0.508078 (10-bit full-range code 520),
// 1000 cd/m² → 0.751827 (769), 10000 → 1. With
// Amplify 1 (ExposureFract 1e-4) a scene value s reaches PQ as s · 1e-4 · 10000 = s nits.
TEST(PqGrading, PqEncodeMatchesPublishedValues) {
  const Loaded l = load("pq_identity_33.cube", 1.0, Display::kHdr, BackBuffer::kR10G10B10A2);
  const StripLut lut = strip_lut(l.strip, l.p);
  const Trace t = grade(l.p, lut, {100.0, 1000.0, 10000.0}, LutEval::kStrip);
  EXPECT_NEAR(t.pq[0], 0.508078, 1e-6);
  EXPECT_NEAR(t.pq[1], 0.751827, 1e-6);
  EXPECT_NEAR(t.pq[2], 1.0, 1e-12);
  EXPECT_EQ(std::lround(t.pq[0] * 1023), 520);
  EXPECT_EQ(std::lround(t.pq[1] * 1023), 769);
}

// The identity LUT sampled from its strip gives back its input, and the whole chain before the
// display mapping is the identity times Amplify: g = PQ⁻¹(PQ(s · 1e-4 A)) / (1e-4 A) · A = s · A.
TEST(PqGrading, IdentityLutRoundTripsToSceneTimesAmplify) {
  const Loaded l = load("pq_identity_33.cube", 3.0, Display::kHdr, BackBuffer::kRgba16f);
  const StripLut lut = strip_lut(l.strip, l.p);
  for (double s : {0.0, 0.015625, 0.5, 1.0, 7.25, 100.0, 3000.0}) {
    const Trace t = grade(l.p, lut, {s, s, s}, LutEval::kStrip);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(t.graded_pq[c], t.pq[c], 1e-12) << s;
      EXPECT_NEAR(t.graded[c], s * 3.0, 1e-9 * std::max(1.0, s)) << s;
    }
  }
}

// Hand derivation, identity LUT, Amplify 4 (ExposureFract 4e-4), scene 0.25 (exact in half):
// e = 1e-4, PQ round trip exact, g = 1e-4 / 4e-4 · 4 = 1. SDR: Narkowicz(1) = (2.51 + 0.03) /
// (2.43 + 0.59 + 0.14) = 2.54 / 3.16 = 127/158. Then RGB8 (127/158)^(1/2.2); sRGB8
// 1.055 (127/158)^(1/2.4) − 0.055 (above 0.0031308); RGBA16F (SDR white 100 nits) 127/158 · 100 /
// 80; R10G10B10A2 PQ(127/158 · 100 nits).
TEST(PqGrading, HandDerivedSdrValues) {
  const double d = 127.0 / 158.0;
  struct Row {
    BackBuffer bb;
    double expected;
  };
  // PQ(80.379747 nits) from ST 2084's inverse EOTF with its constants (m1 = 2610/16384, m2 =
  // 2523/4096·128, c1 = 3424/4096, c2 = 2413/4096·32, c3 = 2392/4096·32), evaluated step by step
  // in a Python session: Y = 0.0080379747, Y^m1 = 0.46375241, c2 Y^m1 = 8.7424575, c3 Y^m1 =
  // 8.6663731, (c1 + 8.7424575) / (1 + 8.6663731) = 0.99089854, ^m2 = 0.48632465.
  const Row rows[] = {
      {BackBuffer::kRgb8, std::pow(d, 1.0 / 2.2)},
      {BackBuffer::kSrgb8, 1.055 * std::pow(d, 1.0 / 2.4) - 0.055},
      {BackBuffer::kRgba16f, d * 100.0 / 80.0},
      {BackBuffer::kR10G10B10A2, 0.48632465},
  };
  for (const Row& r : rows) {
    const Loaded l = load("pq_identity_33.cube", 4.0, Display::kSdr, r.bb);
    const Trace t = grade(l.p, strip_lut(l.strip, l.p), {0.25, 0.25, 0.25}, LutEval::kStrip);
    EXPECT_NEAR(t.graded[0], 1.0, 1e-9);
    EXPECT_NEAR(t.display[0], d, 1e-9);
    EXPECT_NEAR(t.out[0], r.expected, r.bb == BackBuffer::kR10G10B10A2 ? 1e-8 : 1e-9)
        << back_buffer_name(static_cast<int>(r.bb));
  }
}

// The RGBA16F lighting target: 1e5 clamps to 65504; 33.3333 rounds to the half 33.34375 (33 +
// 11/32; spacing 1/32 in [32, 64)); NaN stays NaN and then saturates to 0 (PQ(0) = c1^m2, decoded
// back to 0); +Inf clamps to 65504, then saturates to PQ 1.
TEST(PqGrading, LightingTargetIsRgba16fAndSaturateTakesNaNToBlack) {
  EXPECT_EQ(store_rgba16f(1e5), 65504.0);
  EXPECT_EQ(store_rgba16f(-1e5), -65504.0);
  EXPECT_EQ(store_rgba16f(std::numeric_limits<double>::infinity()), 65504.0);
  EXPECT_EQ(store_rgba16f(33.3333), 33.34375);
  // Ties go to the even half: halves near 1 are 2^-10 apart, so 1 + 2^-11 lies between 1 (even
  // mantissa) and 1 + 2^-10 (odd), and 1 + 3·2^-11 between 1 + 2^-10 (odd) and 1 + 2^-9 (even).
  EXPECT_EQ(store_rgba16f(1.0 + std::ldexp(1.0, -11)), 1.0);
  EXPECT_EQ(store_rgba16f(1.0 + 3 * std::ldexp(1.0, -11)), 1.0 + std::ldexp(1.0, -9));
  // Half subnormals (below 2^-14) are kept, in steps of 2^-24.
  EXPECT_EQ(store_rgba16f(3 * std::ldexp(1.0, -24)), 3 * std::ldexp(1.0, -24));
  EXPECT_TRUE(std::isnan(store_rgba16f(std::nan(""))));
  const Loaded l = load("pq_identity_33.cube", 3.0, Display::kSdr, BackBuffer::kRgb8);
  const StripLut lut = strip_lut(l.strip, l.p);
  const Trace t = grade(l.p, lut, {std::nan(""), std::numeric_limits<double>::infinity(), -5.0},
                        LutEval::kStrip);
  EXPECT_EQ(t.exposed[0], 0.0);
  EXPECT_EQ(t.exposed[1], 1.0);
  EXPECT_EQ(t.exposed[2], 0.0);
  EXPECT_NEAR(t.pq[0], std::pow(3424.0 / 4096.0, 2523.0 / 4096.0 * 128.0), 1e-15);  // c1^m2
  EXPECT_NEAR(t.graded[0], 0.0, 1e-12);
  EXPECT_EQ(t.out[1], 1.0);  // Narkowicz(10000 / 3e-4 · 3 ...) saturates
}

// DOMAIN is honoured in the lookup: pq_domain_33 holds pq_look on the lattice of [0.05, 0.9] x
// [0, 0.85] x [0.1, 0.95]; a lattice point's input gives that row exactly, and inputs outside the
// domain clamp to its edge.
TEST(PqGrading, DomainMapsInputsOntoTheLattice) {
  const Loaded l = load("pq_domain_33.cube", 3.0, Display::kHdr, BackBuffer::kR10G10B10A2);
  const StripLut lut = strip_lut(l.strip, l.p);
  auto lattice = [](int i, double lo, double hi) { return lo + (hi - lo) * i / 32.0; };
  const Vec3 at = {lattice(5, 0.05, 0.9), lattice(20, 0.0, 0.85), lattice(31, 0.1, 0.95)};
  const Vec3 out = lookup(lut, at, LutEval::kStrip);
  const auto& row = l.lut.table[5 + 33 * (20 + 33 * 31)];
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[c], row[c], 1e-6) << c;
  const Vec3 below = lookup(lut, {0.0, 0.0, 0.0}, LutEval::kStrip);
  const auto& first = l.lut.table[0];
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(below[c], first[c], 1e-12) << c;
}

using hdrc::cube::testing::ocio_processor;  // core/cube/ocio_oracle.h

// The LUT step against OpenColorIO's FileTransform on the same .cube files and PQ colours: the
// strip sampling (two bilinear taps lerped across slices, evaluated exactly) is trilinear
// interpolation, so it agrees with OCIO's INTERP_LINEAR; core/cube's tetrahedral with OCIO's
// INTERP_TETRAHEDRAL. OCIO evaluates in float32: bound 2e-6 relative + 1e-6 (core/cube's test).
// The colours: a 17-point grid over [-0.05, 1.05] per channel (off the 33-point lattice, with
// the domain's edges and beyond), so clamping is exercised too.
TEST(PqGrading, LutStepMatchesOpenColorIO) {
  for (const char* file : {"pq_identity_33.cube", "pq_look_33.cube", "pq_hue_33.cube",
                           "pq_clip_33.cube", "pq_domain_33.cube"}) {
    const Loaded l = load(file, 3.0, Display::kHdr, BackBuffer::kR10G10B10A2);
    const StripLut lut = strip_lut(l.strip, l.p);
    for (auto [eval, interp] : {std::pair{LutEval::kStrip, OCIO::INTERP_LINEAR},
                                std::pair{LutEval::kTrilinear, OCIO::INTERP_LINEAR},
                                std::pair{LutEval::kTetrahedral, OCIO::INTERP_TETRAHEDRAL}}) {
      auto proc = ocio_processor(kCubeDir + file, interp);
      int failures = 0;
      for (int b = 0; b < 17; ++b)
        for (int g = 0; g < 17; ++g)
          for (int r = 0; r < 17; ++r) {
            const float in[3] = {float(-0.05 + 1.1 * r / 16), float(-0.05 + 1.1 * g / 16),
                                 float(-0.05 + 1.1 * b / 16)};
            float px[3] = {in[0], in[1], in[2]};
            proc->applyRGB(px);
            const Vec3 ours = lookup(lut, {in[0], in[1], in[2]}, eval);
            for (int c = 0; c < 3; ++c) {
              const double d = std::fabs(ours[c] - px[c]);
              if (!(d <= 2e-6 * std::fabs(ours[c]) + 1e-6) && failures++ < 3)
                ADD_FAILURE() << file << " eval " << static_cast<int>(eval) << " at (" << in[0]
                              << ", " << in[1] << ", " << in[2] << ") channel " << c << ": ours "
                              << ours[c] << ", OCIO " << px[c];
            }
          }
    }
  }
}

// Strip sampling vs the analytic .cube evaluation, in double: the strip scheme is trilinear (the
// same weights), so they agree to rounding; tetrahedral differs by the interpolation's own error,
// measured here for docs/precision.md (largest |strip − tetra| over a 41³ grid of PQ inputs). The
// bounds pin the measurement from both sides: a change of scheme shows.
TEST(PqGrading, StripSamplingIsTrilinearAndDiffersFromTetrahedralByTheMeasuredAmount) {
  struct Row {
    const char* file;
    double tetra_max;  // the measured |strip − tetrahedral|, rounded up
  };
  // The identity and the per-channel clip interpolate alike in both schemes (a function of one
  // channel, or a linear one, is reproduced exactly by either).
  for (const Row& row : {Row{"pq_identity_33.cube", 1e-12}, Row{"pq_clip_33.cube", 1e-12},
                         Row{"pq_look_33.cube", 8e-4}, Row{"pq_hue_33.cube", 3.4e-3},
                         Row{"pq_domain_33.cube", 6e-4}}) {
    const char* file = row.file;
    const Loaded l = load(file, 3.0, Display::kHdr, BackBuffer::kR10G10B10A2);
    const StripLut lut = strip_lut(l.strip, l.p);
    double tri = 0, tet = 0;
    for (int b = 0; b <= 40; ++b)
      for (int g = 0; g <= 40; ++g)
        for (int r = 0; r <= 40; ++r) {
          const Vec3 x = {r / 40.0, g / 40.0, b / 40.0};
          const Vec3 s = lookup(lut, x, LutEval::kStrip);
          const Vec3 t3 = lookup(lut, x, LutEval::kTrilinear);
          const Vec3 t4 = lookup(lut, x, LutEval::kTetrahedral);
          for (int c = 0; c < 3; ++c) {
            tri = std::max(tri, std::fabs(s[c] - t3[c]));
            tet = std::max(tet, std::fabs(s[c] - t4[c]));
          }
        }
    EXPECT_LT(tri, 1e-12) << file;
    RecordProperty(std::string(file) + "_strip_vs_tetrahedral", std::to_string(tet));
    std::printf("%s: max |strip - trilinear| %.3g, max |strip - tetrahedral| %.3g (PQ)\n", file,
                tri, tet);
    EXPECT_LT(tet, row.tetra_max) << file;
    if (row.tetra_max > 1e-12) {
      EXPECT_GT(tet, 0.5 * row.tetra_max) << file;
    }
  }
}

// --- Device allowances -----------------------------------------------------------------------

// One lookup's device range by hand, N = 2 (a 4 x 2 strip), t = (0.3, 0, 0), no coordinate noise:
// texel-space x = 0.3 (i0 = 0, i1 = 1, weight 0.3), y = 0 and the slice 0 (weights 0), so two
// texels carry the value: A = strip(0, 0), B = strip(1, 0). With 4 sub-texel bits the weight may
// be either grid value around 0.3: [4/16, 5/16] = [0.25, 0.3125]. Channel 0, A in [0.2, 0.2],
// B in [0.6, 0.61] (the bounds' lo and hi images): min 0.2 + 0.4 * 0.25 = 0.3, max 0.2 + 0.41 *
// 0.3125 = 0.328125, each widened by the lerp's rounding.
// Row 1 (weight 0) and slice 1 (lerp weight 0) hold values that must not reach the range but its
// rounding allowance (2.5 ulp32 of the largest filtered sample, 0.5: 2^-24); a planted weight of
// 0.35 (0.34) lies outside.
TEST(PqGradingDevice, OneLookupRangeByHand) {
  hdrc::Image lo(4, 2), hi(4, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x)
      for (int c = 0; c < 3; ++c) lo.px(x, y)[c] = hi.px(x, y)[c] = y == 1 ? 0.9 : 0.5;
  lo.px(0, 0)[0] = hi.px(0, 0)[0] = 0.2;
  lo.px(1, 0)[0] = 0.6;
  hi.px(1, 0)[0] = 0.61;
  hdrc::ref::Range3 t = hdrc::ref::Range3::point({0.3, 0.0, 0.0});
  const hdrc::ref::Range3 r = hdrc::ref::strip_lookup_device_range({&lo, &hi, 2}, t, 4, 0.0);
  const double e = 2.5 * std::ldexp(1.0, -24);
  EXPECT_DOUBLE_EQ(r.lo[0], 0.3 - e);
  EXPECT_DOUBLE_EQ(r.hi[0], 0.2 + 0.41 * 0.3125 + e);
  EXPECT_FALSE(r.nan[0]);
  EXPECT_GT(0.2 + 0.4 * 0.35, r.hi[0]);  // a weight outside the box
  EXPECT_LT(0.2 + 0.4 * 0.3, r.hi[0]);   // the exact weight inside
  // Channels 1, 2: both texels 0.5, any weight: 0.5 within the lerp's allowance.
  EXPECT_DOUBLE_EQ(r.lo[1], 0.5 - 2.5 * std::ldexp(1.0, -24));
  EXPECT_DOUBLE_EQ(r.hi[2], 0.5 + 2.5 * std::ldexp(1.0, -24));
  // 8 sub-texel bits: the box shrinks to [76/256, 77/256] around 0.3 (76.8/256).
  const hdrc::ref::Range3 r8 = hdrc::ref::strip_lookup_device_range({&lo, &hi, 2}, t, 8, 0.0);
  EXPECT_DOUBLE_EQ(r8.lo[0], 0.2 + 0.4 * 76.0 / 256 - e);
  EXPECT_DOUBLE_EQ(r8.hi[0], 0.2 + 0.41 * 77.0 / 256 + e);
  // A coordinate range across the lattice plane x = 1 (t.r in [0.9, 1.0] of N − 1 = 1: x in
  // [0.9, 1]): the plane's texel B alone is a candidate, so the range reaches B's bounds.
  t.lo[0] = 0.9;
  t.hi[0] = 1.0;
  const hdrc::ref::Range3 rr = hdrc::ref::strip_lookup_device_range({&lo, &hi, 2}, t, 4, 0.0);
  EXPECT_DOUBLE_EQ(rr.hi[0], 0.61 + e);
  EXPECT_DOUBLE_EQ(rr.lo[0], 0.2 + 0.4 * (14.0 / 16) - e);  // x = 0.9: weight box [14/16, 15/16]
}

// The pipeline's reference with device allowances: the tight output is unchanged (bit for bit,
// and no tight admissible range appears), every pixel has a device range holding its reference
// value, and the ranges are not all points (the weight boxes open them); without allowances no
// device range is made.
TEST(PqGradingDevice, TightOutputUnchangedAndEveryPixelHasARange) {
  for (const BackBuffer bb :
       {BackBuffer::kR10G10B10A2, BackBuffer::kRgba16f, BackBuffer::kSrgb8, BackBuffer::kRgb8})
    for (const Display disp : {Display::kHdr, Display::kSdr}) {
      const Loaded l = load("pq_look_33.cube", 3.0, disp, bb);
      hdrc::ResolvedCase rc;
      rc.params = l.p;
      rc.user_luts[0] = l.strip;
      rc.input = hdrc::Image(64, 4);
      for (size_t i = 0; i < rc.input.pixel_count(); ++i) {
        double* px = &rc.input.data[i * hdrc::Image::kChannels];
        // 1e-3 to 3e4 scene units, the three channels apart.
        const double k = std::pow(10.0, -3.0 + 7.5 * static_cast<double>(i % 64) / 63);
        px[0] = k;
        px[1] = k * (0.3 + 0.2 * static_cast<double>(i / 64));
        px[2] = k * 0.05;
        px[3] = 1.0;
      }
      const auto& ref = hdrc::ref::pq_grading::pq_grading_pipeline().reference;
      auto tight = ref(rc, false);
      rc.device_allowances = true;
      rc.device.sub_texel_bits = 8;
      auto dev = ref(rc, false);
      ASSERT_TRUE(tight && dev);
      EXPECT_EQ(tight->data, dev->data);
      EXPECT_TRUE(tight->device_admissible.empty());
      EXPECT_TRUE(dev->admissible.empty());
      ASSERT_EQ(dev->device_admissible.size(), rc.input.pixel_count());
      EXPECT_FALSE(dev->device_allowances.empty());
      int wider = 0;
      for (size_t i = 0; i < dev->device_admissible.size(); ++i) {
        const hdrc::AdmissibleRange& a = dev->device_admissible[i];
        EXPECT_EQ(a.pixel, i);
        for (int c = 0; c < 4; ++c) {
          const double v = dev->data[i * 4 + c];
          EXPECT_LE(a.lo[c], v) << i << " " << c;
          EXPECT_GE(a.hi[c], v) << i << " " << c;
          if (c < 3 && a.hi[c] > a.lo[c]) ++wider;
        }
      }
      EXPECT_GT(wider, 64) << int(bb) << " " << int(disp);
    }
}

}  // namespace
