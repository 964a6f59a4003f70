// UE 5.8's CombineLUTs (pipeline ue58) against facts from UE 5.8's source and the ACES 2.0 CTL,
// each derived by hand here: the host derivation's rules (PostProcessCombineLUTs.cpp), the shaper
// decode formulas (GammaCorrectionCommon.ush, ST 2084), the tonescale anchor (Lib.Academy.
// Tonescale.ctl: r_hit maps to the peak), the achromatic axis (JMh M = 0 lands on the limiting
// white), the magenta of Filmic + ACES 1.3 in HDR, and the inner LUT's sampling.
#include <gtest/gtest.h>

#include <cmath>

#include "core/pipeline.h"
#include "reference/ue/aces2/aces2.h"
#include "reference/ue/combine_luts.h"
#include "reference/ue/ue58/ue58_combine_luts.h"
#include "reference/ue/ue58/ue58_pipeline.h"

namespace {

using hdrc::ref::Vec3;
namespace ue58 = hdrc::ref::ue58;

const hdrc::Pipeline& pipeline() {
  return ue58::ue58_pipeline();
}

// A case of stage ue58_combine_luts with `settings` and `cvars` set (values by name).
hdrc::ParamBlock resolved(std::initializer_list<std::pair<const char*, double>> settings,
                          std::initializer_list<std::pair<const char*, double>> cvars = {},
                          std::string* degenerate = nullptr) {
  hdrc::Case c;
  c.stage = hdrc::find_stage(pipeline(), "ue58_combine_luts");
  c.settings = pipeline().new_settings();
  for (const auto& [k, v] : settings) {
    const auto st = c.settings.set(k, {v, 0, 0, 0}, 1);
    EXPECT_TRUE(st.ok()) << k << ": " << st.error().to_string();
  }
  for (const auto& [k, v] : cvars) {
    const auto st = c.cvars.set(k, v);
    EXPECT_TRUE(st.ok()) << k << ": " << st.error().to_string();
  }
  auto r = pipeline().resolve(c, 32 * 32, 32);
  EXPECT_TRUE(r.ok()) << r.error().to_string();
  if (degenerate) *degenerate = r->degenerate;
  return r->params;
}

// ST 2084 by hand (SMPTE ST 2084 constants): signal -> nits.
double pq_to_nits(double e) {
  const double m1 = 2610.0 / 16384, m2 = 2523.0 / 4096 * 128, c1 = 3424.0 / 4096,
               c2 = 2413.0 / 4096 * 32, c3 = 2392.0 / 4096 * 32;
  const double p = std::pow(e, 1 / m2);
  return 10000 * std::pow(std::max(p - c1, 0.0) / (c2 - c3 * p), 1 / m1);
}
double nits_to_pq(double y) {
  const double m1 = 2610.0 / 16384, m2 = 2523.0 / 4096 * 128, c1 = 3424.0 / 4096,
               c2 = 2413.0 / 4096 * 32, c3 = 2392.0 / 4096 * 32;
  const double l = std::pow(y / 10000, m1);
  return std::pow((c1 + c2 * l) / (1 + c3 * l), m2);
}
// GammaCorrectionCommon.ush: LogToLin — exp2((x - 444/1023) * 14) * 0.18.
double log_to_lin(double x) {
  return std::exp2((x - 444.0 / 1023.0) * 14.0) * 0.18;
}

// PostProcessCombineLUTs.cpp: GetTonemappingMax (1.05 for Filmic on devices 0, 1, 9, else 1),
// GetTonemappingMethod (the cvar wins when >= 0), TonemappingSDRInvEOTF's default keyed on the
// post-process setting, AddCombineLUTPass's bNeedsInnerTonemappingLUT and bUseFloatOutput.
TEST(Ue58Resolve, HostRulesOfPostProcessCombineLUTsCpp) {
  for (int device = 0; device <= 9; ++device)
    for (int method = 0; method <= 1; ++method) {
      SCOPED_TRACE("device " + std::to_string(device) + " method " + std::to_string(method));
      const auto p =
          resolved({{"TonemappingMethod", method}}, {{"r.HDR.Display.OutputDevice", device}});
      const bool max105 = method == 0 && (device == 0 || device == 1 || device == 9);
      EXPECT_EQ(p.ue58_lut_inv_max, max105 ? static_cast<double>(1.f / 1.05f) : 1.0);
      const bool hdr = device >= 3 && device <= 6;
      EXPECT_EQ(p.output_max_luminance, hdr ? 1000.0 : 100.0);
      EXPECT_EQ(p.ue58_inner_needed, (method == 1 || hdr) ? 1 : 0);
      EXPECT_EQ(p.ue58_sdr_inv_eotf, method);
      EXPECT_EQ(p.lut_format, (device == 5 || device == 6) ? 1 : 0);
      EXPECT_EQ(p.ue58_inner_format, p.lut_format);
      EXPECT_EQ(p.ue58_limiting_gamut, hdr ? 1 : 0);  // P3-D65 for HDR, sRGB for SDR
      EXPECT_EQ(p.ue58_aces_version, 2);              // r.HDR.Aces.Version's code default
    }
  // The cvar overrides the method, but TonemappingSDRInvEOTF's default follows the setting.
  auto p = resolved({{"TonemappingMethod", 0}, {"r.LUT.TonemappingMethod", 1}});
  EXPECT_EQ(p.ue58_tonemapping_method, 1);
  EXPECT_EQ(p.ue58_sdr_inv_eotf, 0);
  p = resolved({{"TonemappingMethod", 1}, {"r.LUT.TonemappingSDRInvEOTF", 0}});
  EXPECT_EQ(p.ue58_sdr_inv_eotf, 0);
  // TotalSceneColorMultiplier = PaperWhite / 203 * ACESSceneColorMultiplier, in float.
  p = resolved({{"r.HDR.PaperWhite", 406}});
  EXPECT_EQ(p.ue58_total_scene_color_multiplier, 3.0);
  p = resolved({});
  EXPECT_EQ(p.ue58_total_scene_color_multiplier, 1.5);
  // InverseGamma.y = 1 for device 9 (GetTonemapperOutputDeviceParameters).
  p = resolved({}, {{"r.HDR.Display.OutputDevice", 9}});
  EXPECT_EQ(p.inverse_gamma[1], 1.0);
}

// DoesGamutWhitePointMatch: D65 outputs with a D65 limit need no white scale; an ACES-white
// output (AP0, AP1) with a D65 limit does, and the SDR flag compares with the working space (sRGB).
TEST(Ue58Resolve, WhiteScaleFlagsAndTheTablesInTheBlock) {
  auto p = resolved({{"LimitingGamut", 1}},
                    {{"r.HDR.Display.OutputDevice", 3}, {"r.HDR.Display.ColorGamut", 2}});
  EXPECT_EQ(p.ue58_scale_white, 0);
  EXPECT_EQ(p.ue58_scale_white_sdr, 0);
  p = resolved({{"LimitingGamut", 1}},
               {{"r.HDR.Display.OutputDevice", 3}, {"r.HDR.Display.ColorGamut", 4}});
  EXPECT_EQ(p.ue58_scale_white, 1);
  EXPECT_EQ(p.ue58_scale_white_sdr, 1);
  p = resolved({{"LimitingGamut", 3}},
               {{"r.HDR.Display.OutputDevice", 3}, {"r.HDR.Display.ColorGamut", 4}});
  EXPECT_EQ(p.ue58_scale_white, 0);
  // The forward set is ACESUtils.cpp's for (peak, limiting); the SDR set for (100, working).
  p = resolved({{"LimitingGamut", 2}}, {{"r.HDR.Display.OutputDevice", 4},
                                        {"r.HDR.Display.MaxLuminance", 2000},
                                        {"r.HDR.Display.ColorGamut", 2}});
  const auto fwd = ue58::unpack_aces2_set(p, false);
  const auto sdr = ue58::unpack_aces2_set(p, true);
  namespace a2 = hdrc::ref::aces2;
  const auto want = a2::make_params(2000, a2::kRec2020, a2::kRec2020);
  const auto want_tables = a2::make_tables(want, a2::kRec2020);
  EXPECT_EQ(fwd.params.peak_luminance, 2000.0);
  EXPECT_EQ(fwd.params.limit_j_max, want.limit_j_max);
  EXPECT_EQ(fwd.tables.reach_m, want_tables.reach_m);
  EXPECT_EQ(fwd.tables.gamut_cusp, want_tables.gamut_cusp);
  EXPECT_EQ(fwd.tables.upper_hull_gamma, want_tables.upper_hull_gamma);
  EXPECT_EQ(sdr.params.peak_luminance, 100.0);
  EXPECT_EQ(sdr.tables.reach_m, a2::make_tables(sdr.params, a2::kRec709).reach_m);
  EXPECT_EQ(p.ue58_cusp_table[361][2], want_tables.gamut_cusp[361][2]);
  EXPECT_EQ(p.ue58_gamma_table[90][1], want_tables.upper_hull_gamma[361]);  // texel 361
}

// The outer lattice decode (r.LUT.Shaper, docs/ue58-differences.md L7): log for every device by
// default, PQ with the cvar. Device 8 (linear, no tone curve) with no grading shows it directly.
TEST(Ue58CombineLuts, ShaperDecodeOnDevice8) {
  for (int shaper = 0; shaper <= 1; ++shaper) {
    const auto p = resolved({{"r.LUT.Shaper", shaper}, {"ExpandGamut", 0}},
                            {{"r.HDR.Display.OutputDevice", 8}});
    const ue58::CombineLuts58 luts(p);
    for (double e : {0.0, 0.25, 444.0 / 1023.0, 0.8, 1.0}) {
      const double want = shaper ? pq_to_nits(e) / 100.0 : log_to_lin(e) - log_to_lin(0.0);
      const Vec3 t = luts.outer_texel({e, e, e});
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(t[c], want, 1e-6 * std::max(1.0, want)) << e;
    }
  }
}

// StandardACES, ACES 2.0: grey at the tonescale's r_hit reaches exactly the peak (Lib.Academy.
// Tonescale.ctl: r_hit = 128 + 768 log(peak/100)/log(100) maps to the peak), and an achromatic
// colour (M = 0) lands on the limiting white, so every channel of a D65 output is the peak in nits:
// the inner texel is PQ(1000) before storage. Here through TotalSceneColorMultiplier (paper white
// 10000: 10000/203 * 1.5) so that the graded value stays inside PQ's range.
TEST(Ue58CombineLuts, InnerTexelOfGreyAtRHitIsThePeak) {
  const auto p = resolved({{"TonemappingMethod", 1}, {"r.HDR.PaperWhite", 10000}},
                          {{"r.HDR.Display.OutputDevice", 3},
                           {"r.HDR.Display.ColorGamut", 2},
                           {"r.HDR.Display.MaxLuminance", 1000}});
  const double r_hit = 128 + 768 * std::log(1000.0 / 100) / std::log(100.0);  // 512
  const double x = r_hit / p.ue58_total_scene_color_multiplier;
  const ue58::CombineLuts58 luts(p);
  const double e = nits_to_pq(x * 100);  // the inner lattice coordinate of AP1 grey x
  const Vec3 t = luts.inner_texel({e, e, e});
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(t[c], nits_to_pq(1000.0), 2e-7) << c;
  // Stored as A2B10G10R10: the nearest 10-bit code.
  const Vec3 black = luts.inner_stored(0, 0, 0);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(black[c], 0.0);  // black in, black out
}

// Filmic + HDR + ACES 1.3: ComputeInvOutputACES returns (1, 0, 1) (no 1.3 inverse), so every inner
// texel is ACES 1.3 of that constant (docs/ue58-differences.md L4): the inner LUT is constant.
TEST(Ue58CombineLuts, FilmicHdrWithAces13IsConstantMagenta) {
  const auto p = resolved({{"r.HDR.Aces.Version", 1}, {"r.LUT.Inner.Size", 8}},
                          {{"r.HDR.Display.OutputDevice", 3}});
  const ue58::CombineLuts58 luts(p);
  ASSERT_EQ(luts.inner_lut().size(), 512u);
  const std::vector<Vec3> inner = luts.inner_lut();
  const Vec3 first = inner[0];
  for (const Vec3& t : inner) EXPECT_EQ(t, first);
  EXPECT_GT(first[0], first[1]);  // magenta: red and blue above green
  EXPECT_GT(first[2], first[1]);
}

// Filmic's automatic HDR at equal peaks is the identity: the SDR inverse at 100 nits followed by
// the forward transform at 100 nits with the same (working) limit, at paper white 203
// (TotalSceneColorMultiplier / ACESSceneColorMultiplier = 1), returns the display colour.
TEST(Ue58CombineLuts, InverseThenForwardAtEqualPeaksIsIdentity) {
  auto p = resolved({{"r.LUT.Inner.Size", 4}},
                    {{"r.HDR.Display.OutputDevice", 3}, {"r.HDR.Display.MaxLuminance", 1000}});
  // Make the forward set the SDR one (peak 100, sRGB limit, sRGB output): both directions match.
  namespace a2 = hdrc::ref::aces2;
  const auto sdr = ue58::unpack_aces2_set(p, true);
  ue58::pack_aces2_set(sdr.params, sdr.tables, false, &p);
  p.ue58_scale_white = p.ue58_scale_white_sdr;
  const ue58::CombineLuts58 luts(p);  // output_max_luminance 1000: the PQ branch of the inner LUT
  for (double nits : {0.5, 5.0, 18.0, 60.0, 95.0}) {
    const double e = nits_to_pq(nits) / 0.5080784215;  // the outer LUT's encoding x 1.9682001
    const Vec3 t = luts.inner_texel({e, e, e});
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(pq_to_nits(t[c]), nits, 2e-6 * nits) << nits;
  }
}

// InnerLookupTable: UVW = x (1 - 1/M) + 0.5/M puts lattice coordinate k/(M-1) on texel k's centre
// (the stored value exactly) and halfway between two on their mean (bilinear weights 1/2).
TEST(Ue58CombineLuts, InnerLookupIsExactTrilinear) {
  const auto p = resolved({{"TonemappingMethod", 1}, {"r.LUT.Inner.Size", 16}},
                          {{"r.HDR.Display.OutputDevice", 3}});
  const ue58::CombineLuts58 luts(p);
  auto at = [&](int r, int g, int b) { return luts.inner_stored(r, g, b); };
  for (int k : {0, 5, 15}) {
    const double e = k / 15.0;
    const Vec3 v = luts.inner_lookup({e, 7 / 15.0, 3 / 15.0}, true);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(v[c], at(k, 7, 3)[c], 1e-15);
  }
  const Vec3 mid = luts.inner_lookup({9.5 / 15.0, 2 / 15.0, 11 / 15.0}, true);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mid[c], (at(9, 2, 11)[c] + at(10, 2, 11)[c]) / 2, 1e-15);
  // Outside [0, 1]: clamp-to-edge.
  const Vec3 hi = luts.inner_lookup({1.7, 1.0, 1.0}, true);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(hi[c], at(15, 15, 15)[c], 1e-15);
}

// A host-side planted defect: the reach-M table at 2 degrees instead of 1 (each odd hue holding its
// even neighbour's entry, as a table sampled every 2 degrees and held) moves the stored LUT of a
// StandardACES HDR case (cases/ue58/devices.json, device 3, Rec.2020, ACES 2.0) beyond the
// ue58_combine_luts tolerance (cases/defaults.json: more than 1 % of values off by more than 2e-5,
// or any by more than 9.8e-4, one 10-bit code): the golden of that case would fail.
TEST(Ue58CombineLuts, PlantedReachTableAtTwoDegreesMovesTheLut) {
  auto p = resolved(
      {{"TonemappingMethod", 1}, {"r.HDR.Aces.Version", 2}},
      {{"r.HDR.Display.OutputDevice", 3}, {"r.HDR.Display.ColorGamut", 2}, {"r.LUT.Size", 16}});
  const auto good = ue58::bake_outer_lut(p);
  for (int i = 1; i < 360; i += 2)
    p.ue58_reach_table[i / 4][i % 4] = p.ue58_reach_table[(i - 1) / 4][(i - 1) % 4];
  const auto bad = ue58::bake_outer_lut(p);
  ASSERT_EQ(good.size(), bad.size());
  size_t off = 0;
  double worst = 0;
  for (size_t i = 0; i < good.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double d = std::fabs(good[i][c] - bad[i][c]);
      off += d > 2e-5;
      worst = std::max(worst, d);
    }
  EXPECT_TRUE(off > good.size() * 3 / 100 || worst > 0.00098) << off << " values, worst " << worst;
}

// The pipeline's registration: its stage, its settings' named values, a degenerate peak.
TEST(Ue58Pipeline, StageSettingsAndDegeneratePeak) {
  ASSERT_NE(hdrc::find_pipeline("ue58"), nullptr);
  const auto* stage = hdrc::find_stage("ue58_combine_luts");
  ASSERT_NE(stage, nullptr);
  EXPECT_EQ(stage->pipeline, "ue58");
  EXPECT_FALSE(stage->takes_input);
  auto s = pipeline().new_settings();
  EXPECT_TRUE(s.set_choice("TonemappingMethod", "StandardACES").ok());
  EXPECT_EQ(s.get("TonemappingMethod"), 1.0);
  const auto bad = s.set_choice("LimitingGamut", "P3");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().to_string().find("DCIP3"), std::string::npos) << bad.error().to_string();
  std::string degenerate;
  resolved({{"TonemappingMethod", 1}},
           {{"r.HDR.Display.OutputDevice", 3}, {"r.HDR.Display.MaxLuminance", 50}}, &degenerate);
  EXPECT_NE(degenerate.find("ACES 2.0 at OutputMaxLuminance"), std::string::npos) << degenerate;
}

// Device allowances (docs/ue58-decisions.md E8). The black inner texel of StandardACES: ACES of
// black is 0 nits, whose PQ is c1^m2 = 0.8359375^78.84375 = 7.29e-7 (ln 0.8359375 = -0.179206,
// x 78.84375 = -14.1293). A 10-bit store may give either neighbouring code: 7.29e-7 x 1023 =
// 7.5e-4 codes, so code 0 or code 1 (Vulkan, Fixed-Point Data Conversions). A float16 store
// without RTE either neighbouring half: 7.29e-7 / 2^-24 = 12.23 subnormal steps, so 12 or 13
// x 2^-24; with RTE only the nearest, 12 x 2^-24. The device's PQ of 0 nits (pow(c1, m2) with
// log2's 2^-21 absolute bound times m2 = 78.84: 2.6e-5 relative) stays inside those steps.
TEST(Ue58DeviceRanges, BlackInnerTexelEitherNeighbour) {
  hdrc::DevicePrecision device;
  device.sub_texel_bits = 8;
  {
    const auto p = resolved({{"TonemappingMethod", 1}, {"r.LUT.Inner.Size", 17}},
                            {{"r.HDR.Display.OutputDevice", 3}});
    ASSERT_EQ(p.ue58_inner_format, 0);
    const ue58::CombineLuts58 luts(p);
    const auto& r = luts.inner_stored_range(0, 0, 0, device);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(r.lo[c], 0.0) << c;
      EXPECT_DOUBLE_EQ(r.hi[c], 1.0 / 1023) << c;
      EXPECT_FALSE(r.nan[c]);
    }
  }
  const auto p = resolved({{"TonemappingMethod", 1}, {"r.LUT.Inner.Size", 17}},
                          {{"r.HDR.Display.OutputDevice", 5}});
  ASSERT_EQ(p.ue58_inner_format, 1);
  for (const bool rte : {false, true}) {
    device.fp16_rte = rte;
    const ue58::CombineLuts58 luts(p);
    const auto& r = luts.inner_stored_range(0, 0, 0, device);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(r.lo[c], std::ldexp(12.0, -24)) << c << " rte " << rte;
      EXPECT_EQ(r.hi[c], std::ldexp(rte ? 12.0 : 13.0, -24)) << c << " rte " << rte;
    }
  }
}

// The inner lookup at an inner lattice point (UVW on a texel centre, encoded = 8/16 at M = 17):
// a hardware filter with b sub-texel bits may give the neighbouring texel of each axis a weight
// of 2^-b (the coordinate's float32 rounding carries it either side of the centre: weight box
// [1 - 2^-b, 1] of the texel below, or [0, 2^-b] of the one above; Vulkan, Texel Filtering), on
// top of each texel's either-way store. So at 8 bits the low end reaches (255 lo(8,8,8) +
// lo(7,8,8)) / 256 and no lower than the 27 neighbours' lowest stored bound; at 4 bits
// (15 lo(8,8,8) + lo(7,8,8)) / 16.
TEST(Ue58DeviceRanges, InnerLookupAtALatticePointAdmitsTheNeighboursSubTexelWeight) {
  const auto p = resolved({{"TonemappingMethod", 1}, {"r.LUT.Inner.Size", 17}},
                          {{"r.HDR.Display.OutputDevice", 3}});
  for (const int bits : {8, 4}) {
    SCOPED_TRACE(bits);
    hdrc::DevicePrecision device;
    device.sub_texel_bits = bits;
    const ue58::CombineLuts58 luts(p);
    hdrc::ref::Range3 at;
    at.lo = at.hi = {0.5, 0.5, 0.5};
    const hdrc::ref::Range3 r = luts.inner_lookup_range(at, /*inv_eotf_pq=*/true, device);
    const auto& centre = luts.inner_stored_range(8, 8, 8, device);
    const double w = std::ldexp(1.0, -bits);
    for (int c = 0; c < 3; ++c) {
      double lowest = HUGE_VAL, highest = -HUGE_VAL;
      for (int k = 0; k < 27; ++k) {
        const auto& t = luts.inner_stored_range(7 + k % 3, 7 + k / 3 % 3, 7 + k / 9, device);
        lowest = std::fmin(lowest, t.lo[c]);
        highest = std::fmax(highest, t.hi[c]);
      }
      for (int a = 0; a < 3; ++a) {
        int below[3] = {8, 8, 8}, above[3] = {8, 8, 8};
        below[a] = 7;
        above[a] = 9;
        const auto& lo_n = luts.inner_stored_range(below[0], below[1], below[2], device);
        const auto& hi_n = luts.inner_stored_range(above[0], above[1], above[2], device);
        EXPECT_LE(r.lo[c], (1 - w) * centre.lo[c] + w * lo_n.lo[c] + 1e-12) << c << " " << a;
        EXPECT_GE(r.hi[c], (1 - w) * centre.hi[c] + w * hi_n.hi[c] - 1e-12) << c << " " << a;
      }
      EXPECT_GE(r.lo[c], lowest - 1e-6) << c;
      EXPECT_LE(r.hi[c], highest + 1e-6) << c;
    }
  }
}

// The outer store: every stored 10-bit value may be either neighbouring code of the exact one,
// so each texel's range holds floor(v·1023)/1023 and ceil(v·1023)/1023 of outer_texel's v, and
// the tight bake's texel.
TEST(Ue58DeviceRanges, OuterTexelsAdmitBothNeighbouringCodes) {
  const auto p = resolved({{"TonemappingMethod", 1}, {"r.LUT.Inner.Size", 17}},
                          {{"r.HDR.Display.OutputDevice", 3}, {"r.LUT.Size", 16}});
  ASSERT_EQ(p.lut_format, 0);
  hdrc::DevicePrecision device;
  device.sub_texel_bits = 8;
  const ue58::DeviceLutRanges d = ue58::bake_outer_lut_device(p, device);
  const std::vector<Vec3> tight = ue58::bake_outer_lut(p);
  const ue58::CombineLuts58 luts(p);
  const int n = p.lut_size;
  ASSERT_EQ(d.lo.size(), tight.size());
  for (size_t i = 0; i < tight.size(); ++i) {
    const Vec3 e{double(i % n) / (n - 1), double(i / n % n) / (n - 1), double(i / n / n) / (n - 1)};
    const Vec3 v = luts.outer_texel(e);
    for (int c = 0; c < 3; ++c) {
      const double x = std::clamp(v[c], 0.0, 1.0) * 1023;
      EXPECT_LE(d.lo[i][c], std::floor(x) / 1023) << i << " " << c;
      EXPECT_GE(d.hi[i][c], std::ceil(x) / 1023) << i << " " << c;
      EXPECT_LE(d.lo[i][c], tight[i][c]);
      EXPECT_GE(d.hi[i][c], tight[i][c]);
    }
  }
}

// ---- The dither (docs/ue58-decisions.md J, docs/spec/ue58.md §2) ----------------------------

// A case of stage ue58_dither with `settings` and `cvars`, resolved by 5.8's host derivation.
hdrc::ResolvedCase dither_case(std::initializer_list<std::pair<const char*, double>> settings,
                               std::initializer_list<std::pair<const char*, double>> cvars,
                               const hdrc::Image& input) {
  hdrc::ResolvedCase rc;
  rc.spec.stage = hdrc::find_stage(pipeline(), "ue58_dither");
  EXPECT_NE(rc.spec.stage, nullptr);
  rc.spec.settings = pipeline().new_settings();
  for (const auto& [k, v] : settings) EXPECT_TRUE(rc.spec.settings.set(k, {v, 0, 0, 0}, 1).ok());
  for (const auto& [k, v] : cvars) EXPECT_TRUE(rc.spec.cvars.set(k, v).ok());
  auto r = pipeline().resolve(rc.spec, input.width, input.height);
  EXPECT_TRUE(r.ok());
  rc.params = r->params;
  rc.degenerate = r->degenerate;
  rc.input = input;
  return rc;
}

// AddTonemapPass (5.8 = 5.5): BackbufferQuantizationDithering is 0 for HDR_LinearNoToneCurve (8)
// and HDR_LinearWithToneCurve (9), 1/(2^b - 1) under r.BackbufferQuantizationDitheringOverride b,
// else 1/1023, or 1/255 for an 8-bit back buffer (r.DefaultBackBufferPixelFormat 0, default 4 in
// 5.8's SceneTextures.cpp); GrainRandomFull = (Halton(i, 2), Halton(i, 3)) for i = the output frame
// index mod 8 (GrainRandomFromFrame). The ue58 block carries both (its other 5.5 fields reset).
TEST(Ue58Dither, HostAmountAndGrainOffsetOfAddTonemapPass) {
  const hdrc::Image img(8, 2);
  struct Row {
    int device, override_bits, format;
    double amount;
  };
  for (const Row& row :
       {Row{0, 0, 4, 1.0 / 1023}, Row{0, 0, 0, 1.0 / 255}, Row{1, 0, 0, 1.0 / 255},
        Row{2, 0, 0, 1.0 / 255}, Row{3, 0, 0, 1.0 / 1023}, Row{5, 0, 0, 1.0 / 1023},
        Row{7, 8, 4, 1.0 / 255}, Row{5, 12, 4, 1.0 / 4095}, Row{8, 0, 0, 0.0}, Row{9, 8, 0, 0.0}}) {
    SCOPED_TRACE("device " + std::to_string(row.device) + " bits " +
                 std::to_string(row.override_bits) + " format " + std::to_string(row.format));
    const auto rc = dither_case({},
                                {{"r.HDR.Display.OutputDevice", row.device},
                                 {"r.BackbufferQuantizationDitheringOverride", row.override_bits},
                                 {"r.DefaultBackBufferPixelFormat", row.format}},
                                img);
    EXPECT_EQ(rc.degenerate, "");
    EXPECT_DOUBLE_EQ(rc.params.dither_amount, row.amount);
  }
  // Frame 11: i = 3, Halton(3, 2) = 0.11 (binary) = 0.75, Halton(3, 3) = 0.01 (ternary) = 1/9.
  const auto f11 = dither_case({{"FrameIndex", 11}}, {}, img);
  EXPECT_DOUBLE_EQ(f11.params.grain_random[0], 0.75);
  EXPECT_DOUBLE_EQ(f11.params.grain_random[1], 1.0 / 9.0);
  const auto f0 = dither_case({{"FrameIndex", 0}}, {}, img);
  EXPECT_EQ(f0.params.grain_random[0], 0.0);
  EXPECT_EQ(f0.params.grain_random[1], 0.0);
}

// The stage's reference adds the triangular grain of UE's hash to its input, with 5.8's values:
// each pixel by hand from GrainFromUV (float32: frac(sin(u + v 543.31) 493013)), the sign form of
// TonemapCommonPS and the amount; device 9 (amount 0) returns the input unchanged.
TEST(Ue58Dither, ReferenceAddsTheHashsTriangularGrain) {
  hdrc::Image flat(16, 4);
  for (double& v : flat.data) v = 0.5;
  const auto rc = dither_case(
      {{"FrameIndex", 11}},
      {{"r.HDR.Display.OutputDevice", 3}, {"r.BackbufferQuantizationDitheringOverride", 8}}, flat);
  auto out = pipeline().reference(rc, false);
  ASSERT_TRUE(out.ok()) << out.error().to_string();
  int nonzero = 0;
  for (int y = 0; y < flat.height; ++y)
    for (int x = 0; x < flat.width; ++x) {
      const float u = (static_cast<float>(x) + 0.5f) * (1.0f / 16.0f) + 0.75f;
      const float v =
          (static_cast<float>(y) + 0.5f) * (1.0f / 4.0f) + static_cast<float>(1.0 / 9.0);
      const float a = u + v * 543.31f;
      const float h = std::sin(a) * 493013.0f;
      const double n = 2.0 * (h - std::floor(h)) - 1.0;
      const double s = n > 0 ? 1.0 : (n < 0 ? -1.0 : 0.0);
      const double t = s - s * std::sqrt(std::max(0.0, 1.0 - std::fabs(n)));
      nonzero += t != 0.0;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(out->px(x, y)[c], 0.5 + t / 255.0, 1e-15);
      EXPECT_EQ(out->px(x, y)[3], 0.5);
    }
  EXPECT_GT(nonzero, 60);
  const auto d9 = dither_case({{"FrameIndex", 11}}, {{"r.HDR.Display.OutputDevice", 9}}, flat);
  auto same = pipeline().reference(d9, false);
  ASSERT_TRUE(same.ok());
  EXPECT_EQ(same->data, flat.data);
}

}  // namespace
