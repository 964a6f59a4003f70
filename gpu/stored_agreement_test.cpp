// Acceptance check of issue 11: what `hdrconform probe --stage stored` prints (the reference, in
// double) against UE's CombineLUTs shader code evaluated in float32 — the suite's GLSL port of
// PostProcessCombineLUTs.usf: CombineLUTsCommon (lib/combine_luts.glsl, matrices from UE 5.5's
// ACES.ush literals through the generated interface) run on the GPU engine — for every output
// device 0–9 × output gamut 0–4, with the film, white-balance, colour-correction and ACES
// 1000/2000/4000-nit variations, over a grid of scene colours.
//
// Both sides get the same host-resolved parameters (ref::resolve, as the probe does) and the same
// lookup coordinate (the reference's shaper encoding of the scene colour, clamped as the sampler
// addresses it; the GPU reads it as float). The error is |GPU − reference| of the stored value in
// 10-bit code units (× 1023), with float LUT storage (no quantisation). A NaN is compared as the 0
// UE's default 10-bit UNORM LUT stores for it (D3D float→UNORM).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "color/d3d_math.h"
#include "gpu/shader_probe.h"
#include "reference/color/ue_matrices.h"
#include "reference/ue/combine_luts.h"
#include "reference/ue/cpp/resolve.h"
#include "reference/ue/tonemap.h"

namespace {

using hdrc::ref::Mat3;
using hdrc::ref::Vec3;

struct Variation {
  const char* name;
  std::vector<std::pair<const char*, double>> cvars;
  std::vector<std::pair<const char*, hdrc::Vec4d>> settings;  // a scalar is {v, 0, 0, 0}
};

const std::vector<Variation>& variations() {
  static const std::vector<Variation> v = {
      {"default", {}, {}},
      {"film",
       {},
       {{"FilmSlope", {0.7, 0, 0, 0}},
        {"FilmToe", {0.4, 0, 0, 0}},
        {"FilmShoulder", {0.4, 0, 0, 0}},
        {"FilmBlackClip", {0.02, 0, 0, 0}},
        {"FilmWhiteClip", {0.08, 0, 0, 0}},
        {"ToneCurveAmount", {0.8, 0, 0, 0}},
        {"BlueCorrection", {0.3, 0, 0, 0}},
        {"ExpandGamut", {0.5, 0, 0, 0}}}},
      {"white_balance", {}, {{"WhiteTemp", {4500, 0, 0, 0}}, {"WhiteTint", {0.2, 0, 0, 0}}}},
      {"color_temperature",
       {},
       {{"WhiteTemp", {8000, 0, 0, 0}}, {"TemperatureType", {1, 0, 0, 0}}}},
      {"color_correction",
       {},
       {{"ColorSaturation", {1.1, 0.9, 1.2, 1.05}},
        {"ColorContrast", {1.1, 1.0, 0.95, 1.02}},
        {"ColorGamma", {1.05, 0.95, 1.0, 1.1}},
        {"ColorGain", {1.1, 0.95, 1.05, 1.0}},
        {"ColorOffset", {0.01, -0.005, 0.0, 0.002}},
        {"ColorSaturationShadows", {0.9, 1.0, 1.1, 1.0}},
        {"ColorGainHighlights", {0.95, 1.0, 1.1, 1.0}},
        {"ColorContrastMidtones", {1.05, 1.05, 1.05, 1.0}}}},
      {"aces_1000", {{"r.HDR.Display.MaxLuminance", 1000}}, {}},
      {"aces_2000", {{"r.HDR.Display.MaxLuminance", 2000}}, {}},
      {"aces_4000", {{"r.HDR.Display.MaxLuminance", 4000}}, {}},
  };
  return v;
}

// Scene-linear grid (working colour space): every channel over 0 (the zero channels device 2's
// pow turns NaN once a matrix makes them slightly negative), near black, mid grey and highlights.
std::vector<Vec3> grid() {
  const double levels[] = {0.0, 1e-4, 2e-3, 0.02, 0.18, 0.6, 1.5, 6.0, 40.0};
  std::vector<Vec3> g;
  for (double r : levels)
    for (double gr : levels)
      for (double b : levels) g.push_back({r, gr, b});
  return g;
}

hdrc::Case make_case(int device, int gamut, const Variation& v) {
  hdrc::Case c;
  c.id = std::string("stored_agreement_") + v.name;
  c.stage = hdrc::find_stage("tonemap");
  EXPECT_TRUE(c.cvars.set("r.HDR.EnableHDROutput", 1).ok());
  EXPECT_TRUE(c.cvars.set("r.HDR.Display.OutputDevice", device).ok());
  EXPECT_TRUE(c.cvars.set("r.HDR.Display.ColorGamut", gamut).ok());
  EXPECT_TRUE(c.settings.set("LUTFormat", {2, 0, 0, 0}, 1).ok());  // float: no quantisation
  for (const auto& [k, x] : v.cvars) EXPECT_TRUE(c.cvars.set(k, x).ok()) << k;
  for (const auto& [k, x] : v.settings) {
    const hdrc::SettingInfo* info = hdrc::find_setting(k);
    EXPECT_TRUE(info && c.settings.set(k, x, info->components).ok()) << k;
  }
  return c;
}

// Values at which no double-precision reference can agree with a float32 evaluation to 0.2 codes
// (docs/precision.md, GPU CombineLUTs texel): the dark channel of a colour outside the output
// gamut, whose absolute float32 error is that of the bright channels and whose PQ or gamma
// encode is steepest near 0 (below 1e-3 of the pixel's brightest channel in linear light), and a
// channel the film path clamps at exactly 0 (max(0, FromAP1 · AP1): float32 noise of either sign
// there, which device 2's pow turns into NaN or up to a code). Judged by the documented float32
// bound instead.
bool float32_limited(const hdrc::ParamBlock& p, const hdrc::ref::CombineLutsTrace& t, int k) {
  const int device = p.output_device;
  Vec3 lin{};
  if (device <= 2 || device == 9) {
    if (!(t.film[k] > 1e-6)) return true;
    lin = p.ap1_to_output * (p.wcs_to_ap1 * t.film);
  } else if (device == 3 || device == 4) {
    lin = p.ap1_to_output * t.aces_nits;
  } else if (device == 7) {
    lin = p.ap1_to_output * (p.wcs_to_ap1 * t.graded);
  } else {
    return false;
  }
  const double top = std::fmax(std::fabs(lin[0]), std::fmax(std::fabs(lin[1]), std::fabs(lin[2])));
  return !(lin[k] > 1e-3 * top);
}

// What UE's default 10-bit UNORM LUT holds of a stored value, before rounding to the code: NaN
// becomes 0 and the value is clamped to [0, 1] (D3D float→UNORM). Devices 8/9 store linear values
// above 1 that such a LUT clamps; their float32 agreement is reported relatively.
double unorm(double v) {
  return std::isnan(v) ? 0.0 : std::clamp(v, 0.0, 1.0);
}

// The pre-5.3 ACES.ush literals (UE 5.0, chenyong2github 09c29cbe; docs/spec/ue55.md §2.1), as
// data: the reference's AP1 → output gamut matrix as it was before issue 11.
Mat3 ap1_to_output_pre_ue53(int gamut) {
  const Mat3 d60_to_d65{{0.987224, -0.00611327, 0.0159533, -0.00759836, 1.00186, 0.00533002,
                         0.00307257, -0.00509595, 1.08168}};
  const Mat3 xyz_to_p3{{2.4933963, -0.9313459, -0.4026945, -0.8294868, 1.7626597, 0.0236246,
                        0.0358507, -0.0761827, 0.9570140}};
  const Mat3 xyz_to_rec2020{{1.7166084, -0.3556621, -0.2533601, -0.6666829, 1.6164776, 0.0157685,
                             0.0176422, -0.0427763, 0.94222867}};
  namespace lit = hdrc::ref::ue_literal;
  switch (gamut) {
    case 1:
      return xyz_to_p3 * d60_to_d65 * lit::kAp1ToXyz;
    case 2:
      return xyz_to_rec2020 * d60_to_d65 * lit::kAp1ToXyz;
    case 3:
    case 4:
      return hdrc::ref::ap1_to_output_gamut(gamut);
    default:
      return lit::kXyzToSrgb * d60_to_d65 * lit::kAp1ToXyz;
  }
}

TEST(StoredAgreement, ProbeStoredMatchesUeFloat32ShaderWithin0_2Codes) {
  namespace t = hdrc::gpu::testing;
  t::Probe probe(t::probe_preamble() +
                 "#include \"../lib/combine_luts.glsl\"\n"
                 "void main() {\n"
                 "  uint i = gl_GlobalInvocationID.x;\n"
                 "  if (i >= uint(P.width * P.height)) return;\n"
                 "  out_px[i] = vec4(combine_luts_texel(in_px[i].rgb), 0.0);\n"
                 "}\n");
  const std::vector<Vec3> colours = grid();
  const int n = static_cast<int>(colours.size());
  double worst_all = 0.0, worst_before_device2 = 0.0;
  std::printf(
      "[ measured ] max |GPU float32 - probe stored| in 10-bit codes, over %zu "
      "variations x %d colours (before: the pre-5.3 literals in the reference)\n",
      variations().size(), n);
  for (int device = 0; device <= 9; ++device) {
    for (int gamut = 0; gamut <= 4; ++gamut) {
      double worst = 0.0, worst_before = 0.0, worst_rel = 0.0, worst_limited = 0.0;
      std::string worst_where;
      for (const Variation& v : variations()) {
        const hdrc::Case c = make_case(device, gamut, v);
        auto resolved = hdrc::ref::resolve(c, n, 1);
        ASSERT_TRUE(resolved) << resolved.error().to_string();
        if (!resolved->degenerate.empty()) continue;
        hdrc::ResolvedCase rc;
        rc.spec = c;
        rc.params = resolved->params;
        rc.input = hdrc::Image(n, 1);
        std::vector<Vec3> lattice(colours.size());
        for (int i = 0; i < n; ++i) {
          hdrc::ref::TonemapTrace tr;
          hdrc::ref::tonemap_centre_pixel(rc.params, colours[i], nullptr, &tr);
          for (int k = 0; k < 3; ++k) {
            lattice[i][k] = hdrc::ref::d3d::clamp_address(tr.encoded[k]);
            rc.input.px(i, 0)[k] = lattice[i][k];
          }
        }
        hdrc::ParamBlock before = rc.params;
        before.ap1_to_output = ap1_to_output_pre_ue53(rc.params.output_gamut);
        auto gpu = probe.run(rc);
        ASSERT_TRUE(gpu) << gpu.error().to_string();
        for (int i = 0; i < n; ++i) {
          hdrc::ref::CombineLutsTrace ct, cb;
          hdrc::ref::combine_luts_texel(rc.params, lattice[i], &ct);
          hdrc::ref::combine_luts_texel(before, lattice[i], &cb);
          for (int k = 0; k < 3; ++k) {
            const double g = unorm(gpu->px(i, 0)[k]);
            const double e = std::fabs(g - unorm(ct.stored[k])) * 1023.0;
            const double eb = std::fabs(g - unorm(cb.stored[k])) * 1023.0;
            if (std::isfinite(ct.stored[k]) && std::fabs(ct.stored[k]) > 1.0)
              worst_rel = std::fmax(
                  worst_rel, std::fabs(gpu->px(i, 0)[k] - ct.stored[k]) / std::fabs(ct.stored[k]));
            worst_before = std::fmax(worst_before, eb);
            if (float32_limited(rc.params, ct, k)) {
              worst_limited = std::fmax(worst_limited, e);
              continue;
            }
            if (!(e <= worst)) {
              worst = e;
              char where[160];
              std::snprintf(where, sizeof where, "%s (%g, %g, %g) ch %d gpu %.9g ref %.9g", v.name,
                            colours[i][0], colours[i][1], colours[i][2], k, g, ct.stored[k]);
              worst_where = where;
            }
          }
        }
      }
      std::printf(
          "[ measured ] device %d gamut %d: max %.4f codes (before %.4f; float32-limited values "
          "%.4f), rel above 1: %.2g; worst: %s\n",
          device, gamut, worst, worst_before, worst_limited, worst_rel, worst_where.c_str());
      EXPECT_LE(worst, 0.2) << "device " << device << " gamut " << gamut << ": " << worst_where;
      // docs/precision.md: up to 1.53 codes on out-of-gamut dark channels (PQ devices) and the
      // film path's clamp at 0 (device 2's pow); 2 codes is the measured 1.30-1.53 with margin.
      EXPECT_LE(worst_limited, 2.0) << "device " << device << " gamut " << gamut;
      EXPECT_LE(worst_rel, 3e-4) << "device " << device << " gamut " << gamut;
      worst_all = std::fmax(worst_all, worst);
      if (device == 2) worst_before_device2 = std::fmax(worst_before_device2, worst_before);
    }
  }
  RecordProperty("max_codes", std::to_string(worst_all));
  RecordProperty("max_codes_before_device2", std::to_string(worst_before_device2));
  // The pre-5.3 literals put the reference several codes away from UE 5.5's shader on device 2
  // (6.9 codes measured): reverting the literal table fails here.
  EXPECT_GT(worst_before_device2, 2.0);
}

}  // namespace
