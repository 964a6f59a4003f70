// The first stages of the reference against hand-derived values (docs/spec/ue55.md §13) and UE's
// semantics.
#include "reference/reference_engine.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "reference/ue/cpp/resolve.h"
#include "reference/ue/lut_shaper.h"

namespace {

using hdrc::ParamBlock;
using hdrc::StageId;
using hdrc::ref::Vec3;

ParamBlock params(int device, int gamut) {
  hdrc::Case c;
  c.cvars.set("r.HDR.Display.OutputDevice", device);
  c.cvars.set("r.HDR.Display.ColorGamut", gamut);
  return *hdrc::ref::resolve_params(c, 1, 1);
}

// Spec §13 lattice decode for N = 32: i=1, 16, 31 for both shapers.
TEST(LutShaper, LatticeDecodeMatchesHandDerived) {
  EXPECT_NEAR(hdrc::ref::lut_decode(0, 1.0 / 31), 9.80569014e-4, 1e-12);
  EXPECT_NEAR(hdrc::ref::lut_decode(0, 16.0 / 31), 0.396655517, 1e-9);
  EXPECT_NEAR(hdrc::ref::lut_decode(0, 1.0), 43.7052419, 1e-7);
  EXPECT_NEAR(hdrc::ref::lut_decode(3, 1.0 / 31), 2.30185106e-4, 1e-12);
  EXPECT_NEAR(hdrc::ref::lut_decode(3, 16.0 / 31), 1.08328736, 1e-8);
  EXPECT_NEAR(hdrc::ref::lut_decode(3, 1.0), 100.0, 1e-10);
}

// Spec §13 encodes: SDR 0.18 → 0.435533652, 1 → 0.611001507; HDR 0.18 → PQ(18) = 0.347966662.
TEST(LutShaper, EncodeMatchesHandDerived) {
  EXPECT_NEAR(hdrc::ref::lut_encode(0, 0.18), 0.435533652, 1e-9);
  EXPECT_NEAR(hdrc::ref::lut_encode(0, 1.0), 0.611001507, 1e-9);
  EXPECT_EQ(hdrc::ref::lut_encode(0, 0.0), 0.0);
  EXPECT_NEAR(hdrc::ref::lut_encode(3, 0.18), 0.347966662, 1e-9);
  EXPECT_NEAR(hdrc::ref::lut_encode(3, 1.0), 0.508078422, 1e-9);
}

TEST(ShaperStage, RoundTripIsIdentityInsideRangeAndClampsOutside) {
  for (int device : {0, 3}) {
    const ParamBlock p = params(device, 0);
    const double top = device == 0 ? 43.7052419 : 100.0;
    for (double x : {1e-5, 0.01, 0.18, 1.0, 10.0}) {
      const Vec3 out = hdrc::ref::run_pixel(StageId::kShaper, p, {x, x, x});
      EXPECT_NEAR(out[0], x, 1e-12 * x + 1e-15) << "device " << device;
    }
    const Vec3 above = hdrc::ref::run_pixel(StageId::kShaper, p, {1e3, 1e3, 1e3});
    EXPECT_NEAR(above[0], top, 1e-6) << "sampler clamp at the top lattice";
  }
}

TEST(ShaperStage, NonFiniteFollowsD3D) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  // Log shaper: saturate(NaN) = 0 → black. −x → log2(<LogToLin(0)) saturates to 0 → black.
  const ParamBlock sdr = params(0, 0);
  EXPECT_EQ(hdrc::ref::run_pixel(StageId::kShaper, sdr, {nan, -1, inf})[0], 0.0);
  EXPECT_EQ(hdrc::ref::run_pixel(StageId::kShaper, sdr, {nan, -1, inf})[1], 0.0);
  EXPECT_NEAR(hdrc::ref::run_pixel(StageId::kShaper, sdr, {nan, -1, inf})[2], 43.7052419, 1e-7);
  // PQ shaper: no clamp before the encode; negatives, NaN and +Inf are NaN.
  const Vec3 hdr = hdrc::ref::run_pixel(StageId::kShaper, params(3, 0), {nan, -1, inf});
  EXPECT_TRUE(std::isnan(hdr[0]) && std::isnan(hdr[1]) && std::isnan(hdr[2]));
}

TEST(LinearDeviceStage, Device8IsTheWorkingColourSpace) {
  const Vec3 out = hdrc::ref::run_pixel(StageId::kLinearDevice, params(8, 2), {0.5, 0.25, 2.0});
  EXPECT_NEAR(out[0], 0.5, 1e-12);
  EXPECT_NEAR(out[1], 0.25, 1e-12);
  EXPECT_NEAR(out[2], 2.0, 1e-12);
}

// Device 7: PQ in the output gamut and back, i.e. AP1_2_Output · ToAP1 · x; out-of-gamut
// negatives become NaN (pow of a negative base on D3D).
TEST(LinearDeviceStage, Device7IsTheOutputGamut) {
  for (int gamut = 0; gamut < 5; ++gamut) {
    const ParamBlock p = params(7, gamut);
    const Vec3 grey = hdrc::ref::run_pixel(StageId::kLinearDevice, p, {0.18, 0.18, 0.18});
    const Vec3 want = p.ap1_to_output * (p.wcs_to_ap1 * Vec3{0.18, 0.18, 0.18});
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(grey[c], want[c], 1e-12) << "gamut " << gamut;
  }
  // Pure sRGB green in AP1 then to sRGB: ~0 red from the literal-product drift; pure green in
  // Rec.2020 → AP1 → sRGB has negative red: NaN.
  const Vec3 red_neg = hdrc::ref::run_pixel(StageId::kLinearDevice, params(7, 0), {0.0, 1.0, 0.0});
  const ParamBlock p0 = params(7, 0);
  const Vec3 lin = p0.ap1_to_output * (p0.wcs_to_ap1 * Vec3{0.0, 1.0, 0.0});
  for (int c = 0; c < 3; ++c) {
    if (lin[c] < 0)
      EXPECT_TRUE(std::isnan(red_neg[c]));
    else
      EXPECT_NEAR(red_neg[c], lin[c], 1e-12);
  }
}

}  // namespace
