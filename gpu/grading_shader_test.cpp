// The GLSL CombineLUTs texel function (gpu/shaders/lib/combine_luts.glsl and the files it
// includes) against the double-precision reference (reference/ue/combine_luts.cpp), on lavapipe.
//
// Probe pattern (as gpu/vulkan_engine_test.cpp): a copy of the suite's shaders in a temporary
// directory whose stages/shaper.comp is replaced by a probe that includes the libraries and
// evaluates them on in_px; the Vulkan engine runs it as the "shaper" stage.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "color/gamma_correction.h"
#include "color/st2084.h"
#include "core/shader_interface.h"
#include "gpu/device_bounds_test.h"
#include "gpu/shader_probe.h"
#include "gpu/vulkan_engine.h"
#include "reference/color/ue_matrices.h"
#include "reference/ue/aces/aces_common.h"
#include "reference/ue/combine_luts.h"
#include "reference/ue/cpp/resolve.h"
#include "reference/ue/grading/expand_gamut.h"
#include "reference/ue/grading/film_tonemap.h"
#include "reference/ue/lut_shaper.h"

namespace fs = std::filesystem;
using hdrc::ref::Mat3;
using hdrc::ref::Vec3;

namespace {

// ---------------------------------------------------------------------------------------------
// Probe plumbing

using hdrc::gpu::testing::ShaderDirCopy;

// Replaces the single occurrence of `from` in lib/<file> of `dir` by `to` (a planted defect).
// False when `from` does not occur exactly once.
bool plant(const ShaderDirCopy& dir, const std::string& file, const std::string& from,
           const std::string& to) {
  const fs::path p = fs::path(dir.path()) / "lib" / file;
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  std::string text = s.str();
  const size_t at = text.find(from);
  if (at == std::string::npos || text.find(from, at + 1) != std::string::npos) return false;
  text.replace(at, from.size(), to);
  dir.write("lib/" + file, text);
  return true;
}

// A shader directory copy whose stages/shaper.comp is `probe`.
std::unique_ptr<ShaderDirCopy> probe_dir(const std::string& tag, const std::string& probe) {
  auto dir = std::make_unique<ShaderDirCopy>("grading_" + tag);
  dir->write("stages/shaper.comp", probe);
  return dir;
}

std::string probe_source(const std::string& includes, const std::string& body) {
  return hdrc::gpu::testing::probe_preamble() + includes +
         "void main() {\n"
         "  uint i = gl_GlobalInvocationID.x;\n"
         "  if (i >= uint(P.width * P.height)) return;\n" +
         body + "}\n";
}

// combine_luts_texel of the lattice coordinate in in_px[i].rgb.
const char* kTexelProbeIncludes = "#include \"../lib/combine_luts.glsl\"\n";
const char* kTexelProbeBody = "  out_px[i] = vec4(combine_luts_texel(in_px[i].rgb), 0.0);\n";

// The case's parameters with default (UE) grading or with every grading control moved away from
// its default, so that no stage of the texel function is an identity.
enum class Grading { kDefault, kAllControls };

hdrc::ParamBlock make_params(int device, int gamut, Grading grading, int width) {
  hdrc::Case c;
  c.id = "grading_shader_test";
  c.stage = hdrc::find_stage("combine_luts");
  auto cv = [&](const char* name, double v) {
    const hdrc::Status st = c.cvars.set(name, v);
    EXPECT_TRUE(st.ok()) << name << ": " << st.error().to_string();
  };
  auto set = [&](const char* name, hdrc::Vec4d v, int components) {
    const hdrc::Status st = c.settings.set(name, v, components);
    EXPECT_TRUE(st.ok()) << name << ": " << st.error().to_string();
  };
  cv("r.HDR.Display.OutputDevice", device);
  cv("r.HDR.Display.ColorGamut", gamut);
  if (device >= 3 && device <= 7) {
    cv("r.HDR.EnableHDROutput", 1);
    cv("r.HDR.Display.MaxLuminance", 1000);
  }
  if (grading == Grading::kAllControls) {
    set("WhiteTemp", {5000, 0, 0, 0}, 1);
    set("WhiteTint", {0.2, 0, 0, 0}, 1);
    set("ExpandGamut", {0.7, 0, 0, 0}, 1);
    set("BlueCorrection", {0.45, 0, 0, 0}, 1);
    set("ToneCurveAmount", {0.9, 0, 0, 0}, 1);
    set("FilmSlope", {0.91, 0, 0, 0}, 1);
    set("FilmToe", {0.6, 0, 0, 0}, 1);
    set("FilmShoulder", {0.3, 0, 0, 0}, 1);
    set("FilmBlackClip", {0.01, 0, 0, 0}, 1);
    set("FilmWhiteClip", {0.05, 0, 0, 0}, 1);
    set("ColorCorrectionShadowsMax", {0.12, 0, 0, 0}, 1);
    set("ColorCorrectionHighlightsMin", {0.4, 0, 0, 0}, 1);
    set("ColorCorrectionHighlightsMax", {1.5, 0, 0, 0}, 1);
    set("ColorSaturation", {1.1, 0.9, 1.0, 1.05}, 4);
    set("ColorContrast", {1.05, 1.0, 0.97, 1.0}, 4);
    set("ColorGamma", {1.0, 1.04, 0.98, 1.0}, 4);
    set("ColorGain", {1.02, 1.0, 0.97, 1.01}, 4);
    set("ColorOffset", {0.002, 0.0, 0.001, 0.0}, 4);
    set("ColorSaturationShadows", {0.9, 1.0, 1.1, 1.0}, 4);
    set("ColorContrastShadows", {1.1, 1.0, 0.95, 1.0}, 4);
    set("ColorGainShadows", {1.0, 1.1, 1.0, 0.95}, 4);
    set("ColorGammaMidtones", {1.0, 1.1, 0.9, 1.0}, 4);
    set("ColorOffsetMidtones", {0.0, 0.001, 0.002, 0.0}, 4);
    set("ColorSaturationHighlights", {1.0, 1.0, 0.9, 0.95}, 4);
    set("ColorGainHighlights", {0.9, 1.0, 1.1, 1.0}, 4);
    set("ViewColorScale", {0.9, 0.95, 1.0, 1.0}, 4);
    set("ViewOverlayColor", {0.1, 0.05, 0.0, 0.1}, 4);
    set("DisplayGamma", {2.4, 0, 0, 0}, 1);
    cv("r.Color.Min", 0.02);
    cv("r.Color.Mid", 0.52);
    cv("r.Color.Max", 0.98);
    if (device == 2) cv("r.TonemapperGamma", 2.4);
  }
  auto p = hdrc::ref::resolve_params(c, width, 1);
  EXPECT_TRUE(p.ok()) << p.error().to_string();
  EXPECT_EQ(p->output_device, device);
  return *p;
}

// Runs the probe of `dir` over `inputs` (one RGBA value each) with the parameter block `params`.
std::vector<std::array<double, 4>> run_on_gpu(hdrc::gpu::VulkanEngine& engine,
                                              hdrc::ParamBlock params,
                                              const std::vector<std::array<double, 4>>& inputs) {
  hdrc::ResolvedCase rc;
  rc.spec.id = "grading_probe";
  rc.spec.stage = hdrc::find_stage("shaper");
  rc.input = hdrc::Image(static_cast<int>(inputs.size()), 1);
  for (size_t i = 0; i < inputs.size(); ++i)
    for (int c = 0; c < 4; ++c) rc.input.data[i * 4 + c] = inputs[i][c];
  params.width = rc.input.width;
  params.height = 1;
  rc.params = params;
  auto out = engine.run(rc);
  EXPECT_TRUE(out.ok()) << out.error().to_string();
  std::vector<std::array<double, 4>> result(inputs.size());
  if (!out.ok()) return result;
  for (size_t i = 0; i < inputs.size(); ++i)
    for (int c = 0; c < 4; ++c) result[i][c] = out->data[i * 4 + c];
  return result;
}

// `follow_model`: under HDRC_DEVICE_MODEL (device_bounds_test.h test_options), for a test whose
// bounds have a derived branch; false: the device as it is.
std::unique_ptr<hdrc::gpu::VulkanEngine> make_engine(const ShaderDirCopy& dir,
                                                     bool follow_model = false) {
  hdrc::gpu::VulkanOptions o =
      follow_model ? hdrc::gpu::testing::test_options() : hdrc::gpu::VulkanOptions{};
  o.shader_dir = dir.path();
  auto engine = std::make_unique<hdrc::gpu::VulkanEngine>(o);
  const hdrc::Status st = engine->init();
  EXPECT_TRUE(st.ok()) << st.error().to_string();
  return st.ok() ? std::move(engine) : nullptr;
}

// ---------------------------------------------------------------------------------------------
// Lattice grids (each coordinate rounded to float32, the value both engines then see)

Vec3 to_float(const Vec3& v) {
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

// The volume LUT's lattice, N³ points, r fastest.
std::vector<Vec3> volume_grid(int n) {
  std::vector<Vec3> out;
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r)
        out.push_back(to_float(hdrc::ref::lattice_coordinate(0, n, r, g, b)));
  return out;
}

// Uniform in the PQ signal of the scene value: for every 10-bit PQ code k, the scene-linear value
// nits_from_pq(k/1023)/100 encoded by the device's shaper, along eight directions (neutral, the
// primaries, the secondaries and an orange). For the PQ-shaper devices (3-9) this is the lattice
// coordinate k/1023 itself; for the log-shaper devices 0-2 the coordinate saturates at 1 above
// the log range (~LogToLin(1)).
std::vector<Vec3> pq_uniform_grid(int device) {
  static const Vec3 kDirections[] = {{1, 1, 1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1},
                                     {1, 1, 0}, {0, 1, 1}, {1, 0, 1}, {1, 0.7, 0.3}};
  std::vector<Vec3> out;
  for (const Vec3& d : kDirections)
    for (int k = 0; k < 1024; ++k) {
      Vec3 lattice;
      for (int c = 0; c < 3; ++c) {
        const double pq = k / 1023.0 * d[c];
        const double linear = hdrc::ref::st2084::nits_from_pq(pq) / hdrc::ref::kLinearToNitsScale;
        lattice[c] = hdrc::ref::lut_encode(device, linear);
      }
      out.push_back(to_float(lattice));
    }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Error measures

// The display value a stored texel encodes: OutDeviceColor = stored · 1.05.
double device_value(double stored) {
  return stored * 1.05;
}

// The reference's linear value before the device's encode (the "linear light" of the texel):
// the input of LinearToSrgb / LinearTo709Branchless (after UE's min-normal clamp) / the explicit
// gamma for 0-2, nits of the PQ encode for 3-7 (negative where the encode gives NaN), the stored
// colour itself for 8 and 9. From the reference's own trace.
Vec3 reference_linear(const hdrc::ParamBlock& p, const hdrc::ref::CombineLutsTrace& t) {
  auto mul = [](const Mat3& m, const Vec3& v) { return m * v; };
  auto to_output = [&](const Vec3& v) { return mul(p.ap1_to_output, mul(p.wcs_to_ap1, v)); };
  Vec3 film_gamma;
  for (int c = 0; c < 3; ++c)
    film_gamma[c] = hdrc::ref::d3d::pow(std::fmax(t.film[c], 0.0), p.inverse_gamma[1]);
  switch (p.output_device) {
    case 0:
      return p.wcs_is_srgb ? film_gamma : to_output(film_gamma);
    case 1: {
      Vec3 x = to_output(film_gamma);
      for (double& v : x) v = std::fmax(hdrc::ref::kMinNormal, v);
      return x;
    }
    case 2:
      return to_output(film_gamma);
    case 3:
    case 4:
      return mul(p.ap1_to_output, t.aces_nits);
    case 5:
    case 6:
      return t.aces_nits;
    case 7:
      return to_output(t.graded);
    case 8:
      return t.graded;
    default:
      return to_output(t.film);
  }
}

// A device value decoded back to that linear value, in double; NaN stays NaN. The SDR encodes
// are piecewise: LinearToSrgb is discontinuous at its threshold (the two pieces overlap on
// [0.040421, 0.040448]) and LinearTo709Branchless is the min of its two pieces, so both pieces'
// inverses are taken and the one nearer the reference's linear value `hint` is used (each is
// exact on its own piece, so this never hides an error larger than the piece's).
double decode_device(const hdrc::ParamBlock& p, double v, double hint) {
  auto nearer = [&](double a, double b) {
    if (std::isnan(a)) return b;
    if (std::isnan(b)) return a;
    return std::fabs(a - hint) <= std::fabs(b - hint) ? a : b;
  };
  switch (p.output_device) {
    case 0:
      return nearer(v / 12.92, v < 0.0 ? std::nan("") : std::pow((v + 0.055) / 1.055, 2.4));
    case 1:
      return nearer(v / 4.5, v < 0.0 ? std::nan("") : std::pow((v + 0.099) / 1.099, 1.0 / 0.45));
    case 2:
      return v < 0.0 ? std::nan("") : std::pow(v, 1.0 / p.inverse_gamma[2]);
    case 8:
    case 9:
      return v;
    default:
      return hdrc::ref::st2084::nits_from_pq(v);
  }
}

// GPU vs reference statistics over a set of texels, per channel.
//  code: |Δ OutDeviceColor| in full-scale units (a 10-bit code is 1/1023), where both are numbers;
//  rel:  |Δ linear| / max(max_k |reference linear_k|, floor), "pixel-relative" in linear light.
//        The dark channel of a bright saturated texel is a difference of large terms (the gamut
//        matrices), so its float32 error scales with the texel's largest channel, not its own.
// NaN: the encodes of devices 2-7 give NaN for negative linear values. A channel is NaN on one
// side only is accepted when the reference linear value is within the rel bound of 0 (its sign
// is float32 noise); otherwise it is an inconsistency.
struct ErrorStats {
  size_t count = 0;
  size_t nan_both = 0;
  size_t nan_sign_noise = 0;    // NaN on one side, |reference linear| within the bound of 0
  size_t nan_inconsistent = 0;  // NaN on one side, anything else (must be 0)
  double max_code = 0.0, p999_code = 0.0;
  double max_rel = 0.0, p999_rel = 0.0;
  Vec3 worst_code_lattice{}, worst_rel_lattice{};
  int worst_code_channel = 0, worst_rel_channel = 0;
  double worst_code_ref = 0.0, worst_code_gpu = 0.0;  // stored values
  std::vector<size_t> over_rel;                       // texels over the rel bound given
  std::vector<double> codes, rels;                    // every channel's errors
};

constexpr double kRelFloor = 1e-6;  // linear units of the device (nits for 3-7)

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(std::ceil(q * v.size())) - 1);
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return v[k];
}

// GPU values (stored texels) vs the reference on `lattice` points for one parameter block;
// `rel_bound` decides which NaN mismatches are sign noise and which texels are listed in
// over_rel. `derived` (a device that is not float32-exact): the reference value is first moved to
// the value of its device range nearest the GPU's (combine_luts.h
// combine_luts_texel_device_range: what a conformant device may compute there, as
// device_bounds_test.h nearest_admissible does for a whole stage), so the measures are the GPU
// value's distance outside that range; a NaN the range admits counts as NaN on both sides.
ErrorStats compare_values(const hdrc::ParamBlock& p, const std::vector<Vec3>& lattice,
                          const std::vector<std::array<double, 4>>& gpu, double rel_bound,
                          bool derived = false) {
  ErrorStats s;
  std::vector<double>& codes = s.codes;
  std::vector<double>& rels = s.rels;
  for (size_t i = 0; i < lattice.size(); ++i) {
    hdrc::ref::CombineLutsTrace trace;
    const Vec3 ref = hdrc::ref::combine_luts_texel(p, lattice[i], &trace);
    const Vec3 ref_lin = reference_linear(p, trace);
    hdrc::ref::Range3 range;
    if (derived) range = hdrc::ref::combine_luts_texel_device_range(p, lattice[i]);
    double magnitude = kRelFloor;
    for (double v : ref_lin) magnitude = std::fmax(magnitude, std::fabs(v));
    bool over = false;
    for (int c = 0; c < 3; ++c) {
      ++s.count;
      const double g = gpu[i][c];
      double r = ref[c], r_lin = ref_lin[c];
      if (derived) {
        if (std::isnan(g) && range.nan[c]) {
          r = g;
        } else if (!std::isnan(g) && range.lo[c] <= range.hi[c]) {
          r = std::clamp(g, range.lo[c], range.hi[c]);
          if (r != ref[c]) r_lin = decode_device(p, device_value(r), ref_lin[c]);
        }
      }
      if (std::isnan(r) && std::isnan(g)) {
        ++s.nan_both;
        continue;
      }
      if (std::isnan(r) || std::isnan(g)) {
        if (std::fabs(ref_lin[c]) <= rel_bound * magnitude) {
          ++s.nan_sign_noise;
        } else {
          ++s.nan_inconsistent;
          over = true;
        }
        continue;
      }
      const double code = std::fabs(device_value(g) - device_value(r));
      const double rel =
          std::fabs(decode_device(p, device_value(g), ref_lin[c]) - r_lin) / magnitude;
      codes.push_back(code);
      rels.push_back(rel);
      if (!(rel <= rel_bound)) over = true;
      if (code > s.max_code) {
        s.max_code = code;
        s.worst_code_lattice = lattice[i];
        s.worst_code_channel = c;
        s.worst_code_ref = r;
        s.worst_code_gpu = g;
      }
      if (rel > s.max_rel) {
        s.max_rel = rel;
        s.worst_rel_lattice = lattice[i];
        s.worst_rel_channel = c;
      }
    }
    if (over) s.over_rel.push_back(i);
  }
  s.p999_code = percentile(codes, 0.999);
  s.p999_rel = percentile(rels, 0.999);
  return s;
}

ErrorStats compare_texels(hdrc::gpu::VulkanEngine& engine, const hdrc::ParamBlock& p,
                          const std::vector<Vec3>& lattice, double rel_bound, bool derived) {
  std::vector<std::array<double, 4>> inputs;
  for (const Vec3& l : lattice) inputs.push_back({l[0], l[1], l[2], 0.0});
  return compare_values(p, lattice, run_on_gpu(engine, p, inputs), rel_bound, derived);
}

std::string describe(const ErrorStats& s) {
  char buf[600];
  std::snprintf(buf, sizeof buf,
                "code max %.3g (10-bit %.3g, 8-bit %.3g) p99.9 %.3g (10-bit %.3g) at lattice "
                "(%.9g, %.9g, %.9g) ch %d stored ref %.9g gpu %.9g; rel max %.3g p99.9 %.3g at "
                "(%.9g, %.9g, %.9g) ch %d; NaN both %zu, sign noise %zu, inconsistent %zu",
                s.max_code, s.max_code * 1023, s.max_code * 255, s.p999_code, s.p999_code * 1023,
                s.worst_code_lattice[0], s.worst_code_lattice[1], s.worst_code_lattice[2],
                s.worst_code_channel, s.worst_code_ref, s.worst_code_gpu, s.max_rel, s.p999_rel,
                s.worst_rel_lattice[0], s.worst_rel_lattice[1], s.worst_rel_lattice[2],
                s.worst_rel_channel, s.nan_both, s.nan_sign_noise, s.nan_inconsistent);
  return buf;
}

// ---------------------------------------------------------------------------------------------
// Tolerances, measured on lavapipe (llvmpipe, Mesa) over this test's grids (17³ lattice and the
// PQ-uniform grid), every gamut, default and all-controls grading; each bound is the measured
// maximum with a margin of about 2x. The whole texel function runs in float32 on the GPU (as UE's
// shader does) and in double in the reference; docs/precision.md, "GPU CombineLUTs texel",
// gives the measurements and the causes.
//  rel (pixel-relative, linear light):
//   0-2: 1.4e-5 measured → 3e-5 (float32 film path: ~10 roundings of ~6e-8, the FilmToneMap
//        exp/log and the sRGB/709/gamma pow, each a few ulp on lavapipe).
//   3-7: 1.5e-4 → 3e-4. The PQ decode of the lattice near its top (c2 − c3·Np cancels ~100x, and
//        the 1/m1 power multiplies relative error by 6.3) and the PQ encode's 78.84 power: the
//        shaper stage's float32 bound (cases/tonemap/shaper_pq.json) in both directions.
//   8:   9.5e-5 → 2e-4 (the same PQ decode; no encode).
//   9:   7e-5 → 1.5e-4 with default grading; 1.6e-3 → 3e-3 with every control moved: the r.Color
//        polynomial (a = −0.08) cancels a·x² against b·x for the film values ~10 that the PQ
//        lattice's top reaches with ToneCurveAmount 0.9, magnifying the decode's 3e-5 ~50x.
//  code (|Δ OutDeviceColor|, full scale; devices 0-7):
//   0, 1: 7e-6 → 1.5e-5 (0.015 10-bit, 0.004 8-bit codes).
//   2:    5.2e-5 → 1e-4 (0.1 10-bit, 0.026 8-bit codes): pow(x, 1/2.2) near 0 (gamut 0 and 1).
//   3/4 in gamuts 2-4, 5/6 (AP1), 7 in gamuts 3/4: 1.5e-5 → 3e-5 (0.03 10-bit codes).
//   3/4 in gamuts 0/1 (sRGB, P3): 1.5e-3 → 3e-3 (3 codes); 7 in gamuts 0/1: 7.7e-4 → 1.5e-3,
//        in gamut 2 (Rec.2020): 3.4e-5 → 7e-5 — on this test's grid; the N = 33 lattice reaches
//        3.9 codes (StageMatchesReferenceBake), so for these the rel bound is the general one.
//        AP1 colours outside the output gamut have a channel that is a difference of large terms
//        of OuputGamutMappingMatrix; its absolute error is that of the pixel's largest channel
//        (the rel bound holds), and PQ is steepest near 0, where that channel lands.
struct DeviceBound {
  double rel;   // pixel-relative error in linear light (see ErrorStats)
  double code;  // |Δ OutDeviceColor| in full-scale units; infinity: not a display code (8, 9)
};
DeviceBound bound_for(int device, int gamut, Grading grading) {
  constexpr double kNoCode = std::numeric_limits<double>::infinity();
  switch (device) {
    case 0:
    case 1:
      // Code: 1.68e-5 measured with every control moved after the UE 5.5 literal update (the
      // 10-digit ExpandMat), at lattice (0.8125, 1, 1) R: the dark channel of a saturated cyan,
      // where the sRGB encode is steep (rel 2.1e-6, inside the rel bound); 6.97e-6 before.
      return {grading == Grading::kDefault ? 3e-5 : 3e-6,
              grading == Grading::kDefault ? 1.5e-5 : 2.5e-5};
    case 2:
      // Code: 2.6e-4 measured after the UE 5.5 literal update (5.2e-5 before), at channels the film
      // path clamps to 0: ToAP1 then AP1_2_Output of the 10-digit literals leave only float32
      // noise there (~1e-8, either sign; the 6-digit CATs left ±1.5e-6 of one sign), which
      // pow(x, 1/2.2) lifts to 2.6e-4 or NaN (the "sign noise" counts; docs/precision.md).
      return {grading == Grading::kDefault ? 3e-5 : 3e-6, 4e-4};
    case 3:
    case 4:
      return {3e-4, gamut <= 1 ? 3e-3 : 3e-5};
    case 5:
    case 6:
      return {3e-4, 3e-5};
    case 7:
      return {3e-4, gamut <= 1 ? 1.5e-3 : (gamut == 2 ? 7e-5 : 3e-5)};
    case 8:
      return {2e-4, kNoCode};
    default:
      return {grading == Grading::kDefault ? 1.5e-4 : 3e-3, kNoCode};
  }
}

// One (device, gamut, grading) comparison of a sweep.
struct SweepResult {
  int device = 0, gamut = 0;
  Grading grading = Grading::kDefault;
  DeviceBound bound{};
  ErrorStats stats;
  bool pass() const {
    return stats.nan_inconsistent == 0 && stats.max_rel <= bound.rel &&
           stats.max_code <= bound.code;
  }
  std::string where() const {
    return "device " + std::to_string(device) + " gamut " + std::to_string(gamut) +
           (grading == Grading::kDefault ? " default" : " all-controls") + ": " + describe(stats);
  }
};

// Devices 0-9 × gamuts 0-4 × `gradings` on the 17³ lattice plus the PQ-uniform grid; `derived`:
// each texel's distance outside its device range (compare_values).
std::vector<SweepResult> sweep(hdrc::gpu::VulkanEngine& engine,
                               const std::vector<Grading>& gradings, bool derived) {
  std::vector<SweepResult> out;
  const std::vector<Vec3> grid17 = volume_grid(17);
  for (int device = 0; device <= 9; ++device) {
    std::vector<Vec3> lattice = grid17;
    const std::vector<Vec3> pq = pq_uniform_grid(device);
    lattice.insert(lattice.end(), pq.begin(), pq.end());
    for (int gamut = 0; gamut <= 4; ++gamut)
      for (Grading grading : gradings) {
        SweepResult r;
        r.device = device;
        r.gamut = gamut;
        r.grading = grading;
        r.bound = bound_for(device, gamut, grading);
        r.stats = compare_texels(engine, make_params(device, gamut, grading, 1), lattice,
                                 r.bound.rel, derived);
        out.push_back(std::move(r));
      }
  }
  return out;
}

}  // namespace

// Every device 0-9 × gamut 0-4, default grading and every grading control moved: the GPU texel
// equals the reference texel within the float32 bounds above, and a channel is NaN on both sides
// or on neither (PQ and gamma encodes of negative values), except where the sign itself is
// float32 noise. Prints the per-device summary docs/precision.md records.
TEST(GradingShader, TexelMatchesReferenceEveryDeviceAndGamut) {
  const auto dir = probe_dir("texel", probe_source(kTexelProbeIncludes, kTexelProbeBody));
  auto engine = make_engine(*dir, /*follow_model=*/true);
  ASSERT_TRUE(engine);
  // On a device that is not float32-exact: the distance outside the texel's device range.
  const auto results = sweep(*engine, {Grading::kDefault, Grading::kAllControls},
                             !hdrc::gpu::testing::exact_device());
  for (const SweepResult& r : results) {
    std::printf("[ measured ] %s\n", r.where().c_str());
    EXPECT_EQ(r.stats.nan_inconsistent, 0u) << r.where();
    EXPECT_LE(r.stats.max_rel, r.bound.rel) << r.where();
    EXPECT_LE(r.stats.max_code, r.bound.code) << r.where();
  }
  // Per device over every gamut and both gradings (docs/precision.md).
  std::printf(
      "| device | rel max | rel p99.9 | code max (10-bit) | code p99.9 (10-bit) | "
      "code max (8-bit) | NaN both / sign noise |\n");
  for (int device = 0; device <= 9; ++device) {
    std::vector<double> rels, codes;
    size_t nan_both = 0, noise = 0;
    for (const SweepResult& r : results) {
      if (r.device != device) continue;
      rels.insert(rels.end(), r.stats.rels.begin(), r.stats.rels.end());
      codes.insert(codes.end(), r.stats.codes.begin(), r.stats.codes.end());
      nan_both += r.stats.nan_both;
      noise += r.stats.nan_sign_noise;
    }
    const double code_max = *std::max_element(codes.begin(), codes.end());
    std::printf("| %d | %.2g | %.2g | %.3g | %.3g | %.3g | %zu / %zu |\n", device,
                *std::max_element(rels.begin(), rels.end()), percentile(rels, 0.999),
                code_max * 1023, percentile(codes, 0.999) * 1023, code_max * 255, nan_both, noise);
  }
}

// Acceptance 4: every constant the grading libraries hard-code reaches the GPU as
// float(reference constant), read back through a probe. Matrices are the reference's products of
// UE's literals (evaluated in double); scalars are the reference's named constants where it has
// them, otherwise the literal as the cited reference function writes it.
TEST(GradingShader, ConstantsEqualFloatOfReference) {
  namespace ue = hdrc::ref::ue_literal;
  namespace g = hdrc::ref::grading;
  struct Shared {
    std::string glsl;
    double reference;
    std::string source;
  };
  std::vector<Shared> table = {
      {"FILM_PRE_DESATURATE", 0.96, "film_tonemap.cpp kPreDesaturate"},
      {"FILM_POST_DESATURATE", 0.93, "film_tonemap.cpp kPostDesaturate"},
      {"FILM_MATCH", 0.18, "film_tonemap.cpp kMatch"},
      {"CC_CONTRAST_PIVOT", 0.18, "color_correct.cpp color_correct (· 0.18)"},
      {"CC_ONE_OVER_CONTRAST_PIVOT", 1.0 / 0.18, "color_correct.cpp color_correct (1.0 / 0.18)"},
      {"SRGB_ENCODE_THRESHOLD", 0.00313067, "gamma_correction.h linear_to_srgb"},
      {"SRGB_ENCODE_LINEAR_SCALE", 12.92, "gamma_correction.h linear_to_srgb"},
      {"SRGB_ENCODE_EXPONENT", 1.0 / 2.4, "gamma_correction.h linear_to_srgb"},
      {"SRGB_ENCODE_SCALE", 1.055, "gamma_correction.h linear_to_srgb"},
      {"SRGB_ENCODE_OFFSET", 0.055, "gamma_correction.h linear_to_srgb"},
      {"REC709_MIN_NORMAL_CLAMP", hdrc::ref::kMinNormal, "gamma_correction.h kMinNormal"},
      {"REC709_LINEAR_SCALE", 4.5, "gamma_correction.h linear_to_rec709_branchless"},
      {"REC709_THRESHOLD", 0.018, "gamma_correction.h linear_to_rec709_branchless"},
      {"REC709_EXPONENT", 0.45, "gamma_correction.h linear_to_rec709_branchless"},
      {"REC709_SCALE", 1.099, "gamma_correction.h linear_to_rec709_branchless"},
      {"REC709_OFFSET", 0.099, "gamma_correction.h linear_to_rec709_branchless"},
      {"LUT_SCALE", 1.05, "combine_luts.cpp kLutScale"},
      {"LOG2_OF_E", std::numbers::log2e, "DXC TranslateExp: M_LOG2E"},
      {"LN_OF_2", std::numbers::ln2, "DXC TranslateLog: M_LN2"},
      {"LOG10_OF_2", std::numbers::ln2 / std::numbers::ln10, "DXC TranslateLog10"},
  };
  auto add_matrix = [&](const std::string& name, const Mat3& m, const std::string& source) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        table.push_back(
            {name + "[" + std::to_string(r) + "][" + std::to_string(c) + "]", m(r, c), source});
  };
  add_matrix("EXPAND_GAMUT_MAT", g::expand_gamut_matrix(), "grading::expand_gamut_matrix()");
  add_matrix("FILM_AP1_TO_AP0", ue::kXyzToAp0 * ue::kAp1ToXyz, "XYZ_2_AP0_MAT · AP1_2_XYZ_MAT");
  add_matrix("BLUE_CORRECT_AP1", g::blue_correct_ap1(), "grading::blue_correct_ap1()");
  add_matrix("BLUE_CORRECT_INV_AP1", g::blue_correct_inv_ap1(), "grading::blue_correct_inv_ap1()");
  std::vector<std::string> expressions;
  for (const Shared& s : table) expressions.push_back(s.glsl);
  auto values = hdrc::gpu::testing::read_back(expressions, {"../lib/combine_luts.glsl"});
  ASSERT_TRUE(values.ok()) << values.error().to_string();
  for (size_t i = 0; i < table.size(); ++i)
    EXPECT_EQ((*values)[i], static_cast<float>(table[i].reference))
        << table[i].glsl << " (" << table[i].source << ")";
}

// The texel coordinates of the stage shader (lut_lattice_coordinate) against the reference's
// lattice_coordinate for both layouts and r.LUT.Size 16, 32, 33, 64. The volume layout is one
// float division, correctly rounded on lavapipe (bound: half an ulp of the result). The 2-D
// layout follows UE's pixel-shader UV arithmetic in float32 (frac of UV.x·N loses the low bits of
// UV.x): measured max 2.6e-6 (N = 33), bound 4 ulp of N, i.e. 4·N·2^-24 (7.9e-6 at N = 33).
TEST(GradingShader, LatticeCoordinateMatchesReference) {
  const auto dir =
      probe_dir("lattice", probe_source("#include \"../lib/combine_luts.glsl\"\n",
                                        "  out_px[i] = vec4(lut_lattice_coordinate(P.lut_layout, "
                                        "P.lut_size, ivec3(in_px[i].rgb)), 0.0);\n"));
  auto engine = make_engine(*dir);
  ASSERT_TRUE(engine);
  for (int layout : {0, 1}) {
    for (int n : {16, 32, 33, 64}) {
      hdrc::ParamBlock p = make_params(0, 0, Grading::kDefault, 1);
      p.lut_size = n;
      p.lut_layout = layout;
      std::vector<std::array<double, 4>> inputs;
      for (int b = 0; b < n; ++b)
        for (int g = 0; g < n; ++g)
          for (int r = 0; r < n; ++r) inputs.push_back({double(r), double(g), double(b), 0.0});
      const auto gpu = run_on_gpu(*engine, p, inputs);
      // Elsewhere than on a float32-exact device the volume layout's division may be 2.5 ULP off
      // ("Precision and Operation of SPIR-V Instructions", OpFDiv): 2.5 ulp of the result, under
      // 2.5·2^-24 for results below 1.
      const bool exact = hdrc::gpu::testing::exact_device();
      const double bound = layout == 1 ? 4.0 * n * std::ldexp(1.0, -24)
                           : exact     ? std::ldexp(1.0, -24)
                                       : 2.5 * std::ldexp(1.0, -24);
      double worst = 0.0;
      for (size_t i = 0; i < inputs.size(); ++i) {
        const Vec3 want = hdrc::ref::lattice_coordinate(layout, n, int(inputs[i][0]),
                                                        int(inputs[i][1]), int(inputs[i][2]));
        for (int c = 0; c < 3; ++c) {
          const double err = std::fabs(gpu[i][c] - want[c]);
          worst = std::fmax(worst, err);
          ASSERT_LE(err, bound) << "layout " << layout << " N " << n << " texel (" << inputs[i][0]
                                << ", " << inputs[i][1] << ", " << inputs[i][2] << ") channel " << c
                                << ": gpu " << gpu[i][c] << " reference " << want[c];
        }
      }
      std::printf("[ measured ] lattice layout %d N %d: max |gpu - reference| %.3g\n", layout, n,
                  worst);
    }
  }
}

// Planted defects: one constant changed in the 5th decimal in a copy of the libraries makes the
// texel comparison fail. The sweep uses the all-controls grading, whose SDR bound (3e-6, float32
// noise without near-black texels) is tight enough for a 1e-5 change; the PQ devices' float32
// noise (1.5e-4, the PQ shaper) hides changes of that size, so what must be caught is the SDR
// devices 0-2, and no device whose path does not read the constant may fail.
TEST(GradingShader, PlantedDefectsAreCaught) {
  struct Plant {
    const char* file;
    const char* from;
    const char* to;
    std::vector<int> must_fail;  // devices that must catch it
    std::vector<int> may_fail;   // devices whose path reads the constant
  };
  const std::vector<int> all = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  const Plant plants[] = {
      // FilmToneMap's match point (the toe/straight/shoulder solve): the SDR film path only.
      {"film_tonemap.glsl",
       "const float FILM_MATCH = 0.18;",
       "const float FILM_MATCH = 0.18001;",
       {0, 1, 2},
       {0, 1, 2, 9}},
      // One entry of the fake-wide-gamut matrix: every device's path reads it.
      // (The matrices come from the generated interface; the plant offsets the row where the
      // library reads it.)
      {"expand_gamut.glsl",
       "dot(EXPAND_GAMUT_MAT[0], v)",
       "dot(EXPAND_GAMUT_MAT[0] + vec3(1e-5, 0.0, 0.0), v)",
       {0, 1, 2},
       all},
      // One entry of the blue-correction matrix: the SDR film path only.
      {"film_path.glsl",
       "dot(BLUE_CORRECT_AP1[0], v)",
       "dot(BLUE_CORRECT_AP1[0] + vec3(1e-5, 0.0, 0.0), v)",
       {0, 1, 2},
       {0, 1, 2, 9}},
  };
  for (const Plant& defect : plants) {
    const auto dir = probe_dir("planted", probe_source(kTexelProbeIncludes, kTexelProbeBody));
    ASSERT_TRUE(plant(*dir, defect.file, defect.from, defect.to)) << defect.from;
    auto engine = make_engine(*dir);
    ASSERT_TRUE(engine);
    std::vector<int> failing;
    // The tight comparison on every device, on the device as it is (not under HDRC_DEVICE_MODEL):
    // a 1e-5 change lies within the device ranges of the SDR devices with every control moved
    // (kShaderNoise, 2^-15 of the texel's largest channel), so those ranges cannot show it, and
    // under the worst-case model the tight bounds of devices 3-7 fail unplanted; what this test
    // checks is the sweep's power to see the change.
    for (const SweepResult& r : sweep(*engine, {Grading::kAllControls}, /*derived=*/false)) {
      if (r.pass()) continue;
      if (failing.empty() || failing.back() != r.device) failing.push_back(r.device);
      std::printf("[ planted  ] %s in %s: caught on %s (%zu texels over the rel bound)\n",
                  defect.to, defect.file, r.where().c_str(), r.stats.over_rel.size());
    }
    for (int d : defect.must_fail)
      EXPECT_NE(std::find(failing.begin(), failing.end(), d), failing.end())
          << defect.to << " in " << defect.file << " not caught on device " << d;
    for (int d : failing)
      EXPECT_NE(std::find(defect.may_fail.begin(), defect.may_fail.end(), d), defect.may_fail.end())
          << defect.to << " in " << defect.file << " fails device " << d
          << ", whose path does not read it";
  }
}

// The combine_luts stage through the engine (stages/combine_luts.comp: texel indexing, lattice
// coordinates, the texel function, imageStore) in RGBA32F with the volume layout, against the
// reference bake (ref::bake_lut, lattice coordinates in double) for every device, gamuts 0 and 2,
// N = 16 and 33: the texel test's bounds hold (the volume lattice is one correctly rounded float
// division, LatticeCoordinate test).
TEST(GradingShader, StageMatchesReferenceBake) {
  hdrc::gpu::VulkanEngine engine({});
  ASSERT_TRUE(engine.init().ok());
  for (int device = 0; device <= 9; ++device)
    for (int gamut : {0, 2})
      for (int n : {16, 33}) {
        hdrc::ResolvedCase rc;
        rc.spec.id = "grading_stage";
        rc.spec.stage = hdrc::find_stage("combine_luts");
        rc.params = make_params(device, gamut, Grading::kDefault, 1);
        rc.params.lut_size = n;
        rc.params.lut_format = 2;
        rc.params.lut_layout = 0;
        rc.input = hdrc::Image(1, 1);
        auto got = engine.run(rc);
        ASSERT_TRUE(got.ok()) << got.error().to_string();
        ASSERT_EQ(got->width, n * n);
        ASSERT_EQ(got->height, n);
        std::vector<Vec3> lattice;
        std::vector<std::array<double, 4>> values;
        for (int b = 0; b < n; ++b)
          for (int g = 0; g < n; ++g)
            for (int r = 0; r < n; ++r) {
              lattice.push_back(hdrc::ref::lattice_coordinate(0, n, r, g, b));
              const double* o = got->px(r + n * b, g);
              values.push_back({o[0], o[1], o[2], o[3]});
            }
        const DeviceBound bound = bound_for(device, gamut, Grading::kDefault);
        const ErrorStats s = compare_values(rc.params, lattice, values, bound.rel);
        const std::string where = "stage device " + std::to_string(device) + " gamut " +
                                  std::to_string(gamut) + " N " + std::to_string(n) + ": " +
                                  describe(s);
        std::printf("[ measured ] %s\n", where.c_str());
        EXPECT_EQ(s.nan_inconsistent, 0u) << where;
        EXPECT_LE(s.max_rel, bound.rel) << where;
      }
}

// The stage stores what the texel function computes at the stage's own lattice coordinate, in
// every storage format and layout: a probe evaluates combine_luts_texel(lut_lattice_coordinate)
// for each texel, and the stage's image holds that value after the format's conversion —
// float32 exactly, half to nearest (one half ulp allowed for the conversion's rounding mode), and
// 10-bit UNORM within one code of round(clamp(v)·1023) with NaN stored as 0 (D3D's rule).
TEST(GradingShader, StageStoresTexelFunctionInEveryFormatAndLayout) {
  const auto dir = probe_dir(
      "stage_texel",
      probe_source(kTexelProbeIncludes,
                   "  out_px[i] = vec4(combine_luts_texel(lut_lattice_coordinate(P.lut_layout, "
                   "P.lut_size, ivec3(in_px[i].rgb))), 0.0);\n"));
  auto probe = make_engine(*dir);
  ASSERT_TRUE(probe);
  hdrc::gpu::VulkanEngine engine({});
  ASSERT_TRUE(engine.init().ok());
  for (int device : {0, 2, 3, 7, 8, 9})
    for (int format = 0; format <= 2; ++format)
      for (int layout = 0; layout <= 1; ++layout) {
        const int n = 17;
        hdrc::ResolvedCase rc;
        rc.spec.id = "grading_stage";
        rc.spec.stage = hdrc::find_stage("combine_luts");
        rc.params = make_params(device, 0, Grading::kDefault, 1);
        rc.params.lut_size = n;
        rc.params.lut_format = format;
        rc.params.lut_layout = layout;
        rc.input = hdrc::Image(1, 1);
        auto got = engine.run(rc);
        ASSERT_TRUE(got.ok()) << got.error().to_string();
        std::vector<std::array<double, 4>> texels;
        for (int b = 0; b < n; ++b)
          for (int g = 0; g < n; ++g)
            for (int r = 0; r < n; ++r) texels.push_back({double(r), double(g), double(b), 0.0});
        const auto want = run_on_gpu(*probe, rc.params, texels);
        // Elsewhere than on a float32-exact device two compilations of the texel function (the
        // stage's and the probe's) may fuse different a·b + c ("Precision and Operation of SPIR-V
        // Instructions"): a float32 texel that is not the probe's bits is then held to what a
        // conformant device may store there (the reference's device range of the stage,
        // ResolvedCase::device_allowances).
        std::optional<hdrc::Image> ranged;
        if (format == 2 && !hdrc::gpu::testing::exact_device()) {
          hdrc::ref::ReferenceEngine reference;
          auto r = hdrc::gpu::testing::stage_reference(reference, rc, *got);
          ASSERT_TRUE(r.ok()) << r.error().to_string();
          ranged = std::move(*r);
        }
        for (size_t i = 0; i < texels.size(); ++i) {
          const int r = int(texels[i][0]), g = int(texels[i][1]), b = int(texels[i][2]);
          for (int c = 0; c < 3; ++c) {
            const double v = want[i][c], o = got->px(r + n * b, g)[c];
            bool ok;
            if (format == 2) {
              ok = (std::isnan(v) && std::isnan(o)) || o == v;
              if (!ok && ranged) {
                // nearest_admissible left o itself where o is inside the texel's range.
                const double in_range = ranged->px(r + n * b, g)[c];
                ok = (std::isnan(in_range) && std::isnan(o)) || o == in_range;
              }
            } else if (format == 1) {
              ok = (std::isnan(v) && std::isnan(o)) ||
                   std::fabs(o - v) <=
                       std::fmax(std::ldexp(std::fabs(v), -10), std::ldexp(1.0, -24));
            } else {
              const double q = std::isnan(v) ? 0.0 : std::nearbyint(std::clamp(v, 0.0, 1.0) * 1023);
              ok = std::fabs(o * 1023 - q) <= 1.0 + 1e-9;
            }
            ASSERT_TRUE(ok) << "device " << device << " format " << format << " layout " << layout
                            << " texel (" << r << ", " << g << ", " << b << ") channel " << c
                            << ": stage " << o << ", texel function " << v;
          }
        }
      }
}
