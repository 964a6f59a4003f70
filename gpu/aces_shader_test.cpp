// The GLSL ACES 1.3 HDR output transform (gpu/shaders/lib/aces_*.glsl, float32) against the
// double-precision reference (reference/ue/aces/aces_output.h), through probe shaders: a temporary
// shader directory holds a copy of lib/ and, in place of the "shaper" stage, a probe that calls
// one library function per pixel. The parameters are resolved from cvars by ref::resolve and reach
// the reference through the same float packing reference/ue/combine_luts.cpp uses (aces_params()).
//
// Tolerances are measured on lavapipe (llvmpipe, LLVM 15, Mesa 22.3.6) with a margin of about 2×
// and explained beside each bound; docs/precision.md ("GPU ACES output transform") has the table.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/case.h"
#include "core/shader_interface.h"
#include "gpu/vulkan_engine.h"
#include "reference/ue/aces/aces_common.h"
#include "reference/ue/aces/aces_output.h"
#include "reference/ue/aces/aces_params.h"
#include "color/st2084.h"
#include "reference/color/ue_matrices.h"
#include "reference/ue/combine_luts.h"
#include "reference/ue/cpp/resolve.h"

namespace fs = std::filesystem;
namespace aces = hdrc::ref::aces;
using hdrc::ref::Mat3;
using hdrc::ref::Vec3;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

double to_float(double v) {
  return static_cast<double>(static_cast<float>(v));
}

// ---------------------------------------------------------------------------------------------
// Probe shaders.

// A shader directory: lib/ copied from `lib_src`, stages/shaper.comp = the probe.
class ProbeDir {
 public:
  ProbeDir(const fs::path& lib_src, const std::string& body) {
    static int counter = 0;
    dir_ = fs::temp_directory_path() /
           ("hdrc_aces_probe_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "stages");
    fs::copy(lib_src, dir_ / "lib", fs::copy_options::recursive);
    std::ofstream f(dir_ / "stages/shaper.comp");
    f << "#version 450\n#extension GL_GOOGLE_include_directive : require\n"
         "#include \"hdrc/interface.glsl\"\n#include \"../lib/aces_output.glsl\"\n"
         "layout(local_size_x = HDRC_LOCAL_SIZE_X) in;\n"
         "void main() {\n  uint i = gl_GlobalInvocationID.x;\n"
         "  if (i >= uint(P.width * P.height)) return;\n"
      << body << "\n}\n";
  }
  ~ProbeDir() { fs::remove_all(dir_); }
  ProbeDir(const ProbeDir&) = delete;
  ProbeDir& operator=(const ProbeDir&) = delete;
  const fs::path& path() const { return dir_; }

 private:
  fs::path dir_;
};

fs::path suite_lib() {
  return fs::path(hdrc::gpu::default_shader_dir()) / "lib";
}

// The cvars of one ACES configuration: device 3 (ACES 1000 nits, PQ), HDR on.
struct AcesConfig {
  int max_nits = 1000;
  double gamut_compression = 0.0;
  double scene_color_multiplier = 1.5;
  std::string name() const {
    std::ostringstream s;
    s << "MaxLuminance " << max_nits << ", GamutCompression " << gamut_compression
      << ", SceneColorMultiplier " << scene_color_multiplier;
    return s.str();
  }
};

hdrc::ParamBlock resolve_block(const AcesConfig& cfg, int width) {
  hdrc::Case c;
  c.id = "aces_probe";
  c.stage = hdrc::find_stage("shaper");
  EXPECT_TRUE(c.cvars.set("r.HDR.EnableHDROutput", 1).ok());
  EXPECT_TRUE(c.cvars.set("r.HDR.Display.OutputDevice", 3).ok());
  EXPECT_TRUE(c.cvars.set("r.HDR.Display.MaxLuminance", cfg.max_nits).ok());
  EXPECT_TRUE(c.cvars.set("r.HDR.Aces.GamutCompression", cfg.gamut_compression).ok());
  EXPECT_TRUE(c.cvars.set("r.HDR.Aces.SceneColorMultiplier", cfg.scene_color_multiplier).ok());
  auto r = hdrc::ref::resolve(c, width, 1);
  EXPECT_TRUE(r.ok()) << r.error().to_string();
  return r->params;
}

// The reference reads the float-packed block exactly as CombineLUTs does.
aces::AcesShaderParams reference_params(const hdrc::ParamBlock& p) {
  return hdrc::ref::aces_params(p);
}

// Runs `body` over `inputs` (each already a float value) for the parameters of `cfg`.
// One engine per probe: its pipeline is compiled once for all configurations.
class Probe {
 public:
  Probe(const fs::path& lib, const std::string& body) : dir_(lib, body) {
    hdrc::gpu::VulkanOptions o;
    o.shader_dir = dir_.path().string();
    engine_ = std::make_unique<hdrc::gpu::VulkanEngine>(o);
    const hdrc::Status st = engine_->init();
    init_error_ = st.ok() ? "" : st.error().to_string();
  }
  const std::string& init_error() const { return init_error_; }

  // Returns the RGBA outputs, or an error text in `error`.
  std::vector<std::array<double, 4>> run(const AcesConfig& cfg,
                                         const std::vector<std::array<double, 4>>& inputs,
                                         std::string* error) {
    hdrc::ResolvedCase rc;
    rc.spec.id = "aces_probe";
    rc.spec.stage = hdrc::find_stage("shaper");
    rc.params = resolve_block(cfg, static_cast<int>(inputs.size()));
    rc.input = hdrc::Image(static_cast<int>(inputs.size()), 1);
    for (size_t i = 0; i < inputs.size(); ++i)
      for (int c = 0; c < 4; ++c) rc.input.data[i * 4 + c] = inputs[i][c];
    auto out = engine_->run(rc);
    std::vector<std::array<double, 4>> result;
    if (!out.ok()) {
      *error = out.error().to_string();
      return result;
    }
    result.resize(inputs.size());
    for (size_t i = 0; i < inputs.size(); ++i)
      for (int c = 0; c < 4; ++c) result[i][c] = out->data[i * 4 + c];
    return result;
  }

 private:
  ProbeDir dir_;
  std::unique_ptr<hdrc::gpu::VulkanEngine> engine_;
  std::string init_error_;
};

// ---------------------------------------------------------------------------------------------
// Error statistics.

double pq10(double nits) {
  return hdrc::ref::st2084::pq_from_nits(nits) * 1023.0;
}

struct Worst {
  double value = 0.0;
  size_t index = 0;
  int channel = 0;
};

// Per compared channel: `rel` = |gpu − ref| / max(|ref|, floor) (the suite's linear metric),
// `pix` = |gpu − ref| / (the pixel's largest reference channel, at least the floor), `pq` = the
// difference of the PQ signals in 10-bit code values (for nits).
struct Stats {
  std::vector<double> rel, pix, pq;
  Worst worst_rel, worst_pix, worst_pq;
  size_t nonfinite = 0;  // GPU channels that are NaN/Inf where the reference is finite
  std::string first_nonfinite;

  void add(size_t index, int channel, double ref, double gpu, double floor, bool nits,
           double pixel_scale = 0.0) {
    if (!std::isfinite(gpu)) {
      if (nonfinite++ == 0) {
        std::ostringstream s;
        s << "input " << index << " channel " << channel << ": reference " << ref << ", GPU "
          << gpu;
        first_nonfinite = s.str();
      }
      return;
    }
    const double r = std::fabs(gpu - ref) / std::max(std::fabs(ref), floor);
    rel.push_back(r);
    if (r > worst_rel.value) worst_rel = {r, index, channel};
    if (pixel_scale > 0.0) {
      const double q = std::fabs(gpu - ref) / std::max(pixel_scale, floor);
      pix.push_back(q);
      if (q > worst_pix.value) worst_pix = {q, index, channel};
    }
    if (nits) {
      const double q = std::fabs(pq10(std::max(gpu, 0.0)) - pq10(std::max(ref, 0.0)));
      pq.push_back(q);
      if (q > worst_pq.value) worst_pq = {q, index, channel};
    }
  }
  void merge(const Stats& o) {
    rel.insert(rel.end(), o.rel.begin(), o.rel.end());
    pix.insert(pix.end(), o.pix.begin(), o.pix.end());
    pq.insert(pq.end(), o.pq.begin(), o.pq.end());
    nonfinite += o.nonfinite;
    if (first_nonfinite.empty()) first_nonfinite = o.first_nonfinite;
  }
  static double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    const size_t k = std::min(v.size() - 1, static_cast<size_t>(std::ceil(q * v.size())) - 1);
    std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
    return v[k];
  }
  double max_rel() const { return rel.empty() ? 0.0 : *std::max_element(rel.begin(), rel.end()); }
  double max_pix() const { return pix.empty() ? 0.0 : *std::max_element(pix.begin(), pix.end()); }
  double max_pq() const { return pq.empty() ? 0.0 : *std::max_element(pq.begin(), pq.end()); }
};

std::string describe(const Vec3& v) {
  std::ostringstream s;
  s.precision(9);
  s << "(" << v[0] << ", " << v[1] << ", " << v[2] << ")";
  return s.str();
}

// ---------------------------------------------------------------------------------------------
// Inputs.

using Inputs = std::vector<std::array<double, 4>>;

std::array<double, 4> px(double r, double g, double b) {
  return {to_float(r), to_float(g), to_float(b), 1.0};
}

// Scene-linear colours in the working colour space: a grey ramp 1e-4 … 1e4, the primaries and
// secondaries at 17 levels 1e-4 … 1e4, a few out-of-gamut (negative) colours, and 4 000 seeded
// random colours, each channel log-uniform over 1e-5 … 1e3 with 10 % exact zeros.
Inputs output_inputs() {
  Inputs in;
  for (int i = 0; i <= 400; ++i) {
    const double v = std::pow(10.0, -4.0 + 8.0 * i / 400.0);
    in.push_back(px(v, v, v));
  }
  const Vec3 hues[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}, {1, 0, 1}};
  for (const Vec3& h : hues)
    for (int i = 0; i <= 16; ++i) {
      const double v = std::pow(10.0, -4.0 + 0.5 * i);
      in.push_back(px(h[0] * v, h[1] * v, h[2] * v));
    }
  for (const double v : {0.01, 1.0, 100.0}) {
    in.push_back(px(v, -0.1 * v, 0.0));
    in.push_back(px(-0.05 * v, v, 0.2 * v));
    in.push_back(px(0.3 * v, 0.2 * v, -0.5 * v));
  }
  std::mt19937 rng(20240605);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 4000; ++i) {
    double c[3];
    for (double& x : c) x = u(rng) < 0.1 ? 0.0 : std::pow(10.0, -5.0 + 8.0 * u(rng));
    in.push_back(px(c[0], c[1], c[2]));
  }
  return in;
}

const std::vector<AcesConfig>& sweep_configs() {
  static const std::vector<AcesConfig> configs = [] {
    std::vector<AcesConfig> v;
    for (const int nits : {400, 1000, 2000, 4000, 10000})
      for (const double gc : {0.0, 1.0})
        for (const double scm : {1.5, 4.0}) v.push_back({nits, gc, scm});
    return v;
  }();
  return configs;
}

// ---------------------------------------------------------------------------------------------
// Checks. Each returns what it measured and "" when within its bound, else where it failed; the
// planted-defect test runs the same checks against a broken copy of the library.

struct Outcome {
  std::string failure;  // "" = pass
  std::string report;   // measured numbers
};

// Output transform bounds, measured on lavapipe over the 20 configurations (docs/precision.md),
// each about 2× the measured maximum:
//  * relative to the pixel's largest channel: measured 3.8e-6 → bound 8e-6. This is the float32
//    bound of the transform: ssts' 2.5e-6 (float log2/exp2 in log space) plus rrt_sweeteners' 1e-6.
//  * per channel (|Δ| / max(|ref|, 1e-3 nits), the suite's linear metric): measured 8.1e-5 →
//    bound 1.6e-4. The excess over the pixel bound is cancellation: a channel 100–1000× smaller
//    than the pixel's largest (e.g. green of (1, −0.1, 0)) is a difference of large matrix terms
//    (AP0→AP1, AP1→XYZ→AP1 around limit_to_primaries), so it carries their absolute error.
//  * PQ: measured 0.0027 10-bit codes (that same green channel) → bound 0.006. Black (0, 0, 0)
//    leaves as 2.2e-11 nits instead of 0 (ssts(0) − Min.y in float: 10^(log10 Min.y) ≠ Min.y by
//    1 ulp), 0.002 codes.
constexpr double kOutputRelFloorNits = 1e-3;
constexpr double kOutputMaxRel = 1.6e-4;
constexpr double kOutputMaxPixelRel = 8e-6;
constexpr double kOutputMaxPq10 = 0.006;

struct SweepResult {
  std::vector<std::pair<AcesConfig, Stats>> per_config;
  std::vector<std::vector<Vec3>> want, got;  // per configuration, per input: nits (AP1)
  std::string error;
};

SweepResult run_output_sweep(const fs::path& lib, const std::string& entry = "1000") {
  SweepResult res;
  Probe probe(lib, "  out_px[i] = vec4(aces_output_transforms_" + entry + "(in_px[i].rgb), 0.0);");
  if (!probe.init_error().empty()) {
    res.error = probe.init_error();
    return res;
  }
  const Inputs in = output_inputs();
  for (const AcesConfig& cfg : sweep_configs()) {
    std::string error;
    const auto out = probe.run(cfg, in, &error);
    if (!error.empty()) {
      res.error = error;
      return res;
    }
    const hdrc::ParamBlock p = resolve_block(cfg, static_cast<int>(in.size()));
    const aces::AcesShaderParams params = reference_params(p);
    Stats st;
    std::vector<Vec3> wants, gots;
    for (size_t i = 0; i < in.size(); ++i) {
      const Vec3 x{in[i][0], in[i][1], in[i][2]};
      const Vec3 want = entry == "1000"
                            ? aces::aces_output_transforms_1000(x, p.wcs_to_ap0, params)
                            : aces::aces_output_transforms_2000(x, p.wcs_to_ap0, params);
      const double scale = std::max({std::fabs(want[0]), std::fabs(want[1]), std::fabs(want[2])});
      for (int c = 0; c < 3; ++c)
        st.add(i, c, want[c], out[i][c], kOutputRelFloorNits, true, scale);
      wants.push_back(want);
      gots.push_back({out[i][0], out[i][1], out[i][2]});
    }
    res.per_config.emplace_back(cfg, std::move(st));
    res.want.push_back(std::move(wants));
    res.got.push_back(std::move(gots));
  }
  return res;
}

Outcome judge_output_sweep(const SweepResult& r) {
  Outcome o;
  if (!r.error.empty()) {
    o.failure = r.error;
    return o;
  }
  const Inputs in = output_inputs();
  std::ostringstream rep, fail;
  rep.precision(3);
  fail.precision(9);
  for (size_t k = 0; k < r.per_config.size(); ++k) {
    const auto& [cfg, st] = r.per_config[k];
    rep << cfg.name() << ": max rel " << st.max_rel() << " (p99.9 "
        << Stats::percentile(st.rel, 0.999) << "), max pixel-rel " << st.max_pix() << " (p99.9 "
        << Stats::percentile(st.pix, 0.999) << "), max pq10 " << st.max_pq() << " (p99.9 "
        << Stats::percentile(st.pq, 0.999) << ")\n";
    const auto at = [&](const Worst& w) {
      const auto& x = in[w.index];
      std::ostringstream s;
      s.precision(9);
      s << "input " << w.index << " " << describe({x[0], x[1], x[2]}) << " channel " << w.channel
        << ": reference " << describe(r.want[k][w.index]) << " nits, GPU "
        << describe(r.got[k][w.index]);
      return s.str();
    };
    rep << "  worst per-channel rel at " << at(st.worst_rel) << "\n  worst pixel-rel at "
        << at(st.worst_pix) << "\n  worst pq10 at " << at(st.worst_pq) << "\n";
    if (st.nonfinite > 0)
      fail << cfg.name() << ": " << st.nonfinite << " non-finite GPU values, first "
           << st.first_nonfinite << "\n";
    if (!(st.max_rel() <= kOutputMaxRel))
      fail << cfg.name() << ": relative error " << st.max_rel() << " > " << kOutputMaxRel << " at "
           << at(st.worst_rel) << "\n";
    if (!(st.max_pix() <= kOutputMaxPixelRel))
      fail << cfg.name() << ": pixel-relative error " << st.max_pix() << " > " << kOutputMaxPixelRel
           << " at " << at(st.worst_pix) << "\n";
    if (!(st.max_pq() <= kOutputMaxPq10))
      fail << cfg.name() << ": PQ error " << st.max_pq() << " codes > " << kOutputMaxPq10 << " at "
           << at(st.worst_pq) << "\n";
  }
  o.report = rep.str();
  o.failure = fail.str();
  return o;
}

// ssts: measured max 2.5e-6 relative (nits) on lavapipe over 1e-12 … 1e6 ACES; bound 5e-6. The
// worst inputs (x ≈ 0.002 … 0.04) are on the low spline near Mid: logy = t²a + tb + c sums terms
// of magnitude ≈ 3 into ≈ 0.7 log10 nits (a few ulp(3) = 2.4e-7 each), and t comes from the
// float log2 of x (≤ 1.5 ulp on lavapipe) times the spline's slope ≤ 2; ln 10 · 1e-6 ≈ 2.5e-6.
constexpr double kSstsMaxRel = 5e-6;

Outcome check_ssts(const fs::path& lib) {
  Outcome o;
  Probe probe(lib,
              "  FACESTonemapParams a = aces_tonemap_params_from_block();\n"
              "  out_px[i] = vec4(ssts(in_px[i].r, a.AcesParams), 0.0, 0.0, 0.0);");
  if (!probe.init_error().empty()) return {probe.init_error(), ""};
  std::ostringstream rep, fail;
  rep.precision(3);
  for (const int nits : {400, 1000, 2000, 4000, 10000}) {
    const AcesConfig cfg{nits, 0.0, 1.5};
    const hdrc::ParamBlock p0 = resolve_block(cfg, 1);
    const aces::TsParams ts = reference_params(p0).aces_params;
    Inputs in;
    for (int i = 0; i <= 3000; ++i)
      in.push_back(px(std::pow(10.0, -12.0 + 18.0 * i / 3000.0), 0, 0));
    // The knots and the segment boundaries, and the inputs D3D maps to Min.y.
    for (const double x : {ts.min.x, ts.mid.x, ts.max.x}) {
      in.push_back(px(x, 0, 0));
      in.push_back(px(std::nextafter(static_cast<float>(x), 0.0f), 0, 0));
      in.push_back(px(std::nextafter(static_cast<float>(x), 1e30f), 0, 0));
    }
    for (const double x : {0.0, -1.0, -kInf, kNaN}) in.push_back({x, 0, 0, 0});
    std::string error;
    const auto out = probe.run(cfg, in, &error);
    if (!error.empty()) return {error, ""};
    Stats st;
    for (size_t i = 0; i < in.size(); ++i)
      st.add(i, 0, aces::ssts(in[i][0], ts), out[i][0], 0.0, false);
    rep << "ssts MaxLuminance " << nits << ": max rel " << st.max_rel()
        << " at x = " << in[st.worst_rel.index][0] << "\n";
    if (st.nonfinite > 0)
      fail << "ssts MaxLuminance " << nits << ": " << st.first_nonfinite << "\n";
    if (!(st.max_rel() <= kSstsMaxRel)) {
      fail.precision(9);
      fail << "ssts MaxLuminance " << nits << ": relative error " << st.max_rel() << " > "
           << kSstsMaxRel << " at x = " << in[st.worst_rel.index][0] << " (reference "
           << aces::ssts(in[st.worst_rel.index][0], ts) << " nits, GPU "
           << out[st.worst_rel.index][0] << ")\n";
    }
  }
  o.report = rep.str();
  o.failure = fail.str();
  return o;
}

// AP0 test colours for rrt_sweeteners and compress_color: greys, AP1 primaries/secondaries mapped
// to AP0 at several levels, colours far outside AP1 (the gamut compression's domain), colours with
// a negative AP0 channel, and 3 000 seeded random AP1 colours (channels in [-0.3, 1] times a
// log-uniform level 1e-4 … 1e3) converted to AP0.
Inputs ap0_inputs() {
  namespace lit = hdrc::ref::ue_literal;
  Inputs in;
  const auto ap0 = [&](const Vec3& ap1) {
    const Vec3 v = lit::kAp1ToAp0 * ap1;
    return px(v[0], v[1], v[2]);
  };
  for (int i = 0; i <= 200; ++i) {
    const double v = std::pow(10.0, -6.0 + 10.0 * i / 200.0);
    in.push_back(px(v, v, v));
  }
  const Vec3 hues[] = {{1, 0, 0}, {0, 1, 0},       {0, 0, 1},      {1, 1, 0},       {0, 1, 1},
                       {1, 0, 1}, {1, -0.2, -0.1}, {-0.3, 1, 0.1}, {0.05, -0.2, 1}, {1, 0.5, 0}};
  for (const Vec3& h : hues)
    for (int i = 0; i <= 12; ++i) {
      const double v = std::pow(10.0, -4.0 + 0.5 * i);
      in.push_back(ap0({h[0] * v, h[1] * v, h[2] * v}));
    }
  for (const double v : {0.001, 0.5, 20.0}) {
    in.push_back(px(-0.1 * v, v, 0.5 * v));
    in.push_back(px(v, 0.2 * v, -0.01 * v));
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 3000; ++i) {
    const double level = std::pow(10.0, -4.0 + 7.0 * u(rng));
    in.push_back(ap0({level * (-0.3 + 1.3 * u(rng)), level * (-0.3 + 1.3 * u(rng)),
                      level * (-0.3 + 1.3 * u(rng))}));
  }
  return in;
}

// rrt_sweeteners (AP1 out): measured max 1.13e-6 relative to the largest output channel, bound
// 2.5e-6: the glow gain's saturation (max − min)/max and rgb_2_yc's sqrt cancel for low-chroma
// colours, and the AP0→AP1 product adds a few ulps. compress_color (AP0 out): measured 2.9e-7
// relative to the largest |channel|, bound 6e-7: two matrix products and the pow chain of
// compress() (ratio form, well conditioned).
constexpr double kRrtMaxRel = 2.5e-6;
constexpr double kCompressMaxRel = 6e-7;

Outcome check_vector_function(const fs::path& lib, const std::string& name, double bound,
                              const std::function<Vec3(const Vec3&)>& reference) {
  Probe probe(lib, "  out_px[i] = vec4(" + name + "(in_px[i].rgb), 0.0);");
  if (!probe.init_error().empty()) return {probe.init_error(), ""};
  const Inputs in = ap0_inputs();
  std::string error;
  const auto out = probe.run(AcesConfig{}, in, &error);
  if (!error.empty()) return {error, ""};
  Stats st;
  for (size_t i = 0; i < in.size(); ++i) {
    const Vec3 want = reference({in[i][0], in[i][1], in[i][2]});
    // Relative to the largest channel: both functions mix channels, so a small channel carries
    // the absolute error of the large ones. Floor 1e-9 for black.
    const double scale =
        std::max({std::fabs(want[0]), std::fabs(want[1]), std::fabs(want[2]), 1e-9});
    for (int c = 0; c < 3; ++c) st.add(i, c, want[c], out[i][c], scale, false);
  }
  Outcome o;
  std::ostringstream rep, fail;
  rep.precision(3);
  rep << name << ": max rel " << st.max_rel() << " (p99.9 " << Stats::percentile(st.rel, 0.999)
      << ")\n";
  fail.precision(9);
  if (st.nonfinite > 0) fail << name << ": non-finite GPU value at " << st.first_nonfinite << "\n";
  if (!(st.max_rel() <= bound)) {
    const size_t i = st.worst_rel.index;
    const Vec3 x{in[i][0], in[i][1], in[i][2]};
    fail << name << ": relative error " << st.max_rel() << " > " << bound << " at input " << i
         << " " << describe(x) << " channel " << st.worst_rel.channel << ": reference "
         << describe(reference(x)) << ", GPU " << describe({out[i][0], out[i][1], out[i][2]})
         << "\n";
  }
  o.report = rep.str();
  o.failure = fail.str();
  return o;
}

Outcome check_rrt(const fs::path& lib) {
  return check_vector_function(lib, "rrt_sweeteners", kRrtMaxRel, aces::rrt_sweeteners);
}

Outcome check_compress(const fs::path& lib) {
  return check_vector_function(lib, "compress_color", kCompressMaxRel, aces::compress_color);
}

// Every constant the library hard-codes, with the reference's value: float(reference) must equal
// the shader's value exactly (issue 6, acceptance 4).
struct ConstantRef {
  std::string glsl;  // a GLSL float expression
  double reference;
  std::string source;
};

std::vector<ConstantRef> constant_table() {
  namespace lit = hdrc::ref::ue_literal;
  std::vector<ConstantRef> t = {
      {"RRT_GLOW_GAIN", aces::kRrtGlowGain, "aces_common.h kRrtGlowGain"},
      {"RRT_GLOW_MID", aces::kRrtGlowMid, "aces_common.h kRrtGlowMid"},
      {"RRT_RED_SCALE", aces::kRrtRedScale, "aces_common.h kRrtRedScale"},
      {"RRT_RED_PIVOT", aces::kRrtRedPivot, "aces_common.h kRrtRedPivot"},
      {"RRT_RED_HUE", aces::kRrtRedHue, "aces_common.h kRrtRedHue"},
      {"RRT_RED_WIDTH", aces::kRrtRedWidth, "aces_common.h kRrtRedWidth"},
      {"ACES_RAD_TO_DEG", 180.0 / std::numbers::pi, "aces_common.h rgb_2_hue: 180 / pi"},
      {"ACES_SQRT3", std::sqrt(3.0), "aces_common.h rgb_2_hue: sqrt(3)"},
      {"LOG10_OF_2", std::log10(2.0), "DXC log10 lowering constant ln2/ln10"},
      {"LOG2_OF_10", std::log2(10.0), "DXC pow(10, y) lowering constant log2(10)"},
      // The following are private to reference/ue/aces/aces_output.cpp (anonymous namespace), so
      // their values are repeated here from that file: kHalfPosInf, kHalfMax, kRrtSatFactor,
      // kCompressLimit, kCompressThreshold, kCompressPower, and spline_half's M1 arithmetic.
      {"HALF_POS_INF", 65535.0, "aces_output.cpp kHalfPosInf"},
      {"HALF_MAX", 65504.0, "aces_output.cpp kHalfMax"},
      {"RRT_SAT_FACTOR", 0.96, "aces_output.cpp kRrtSatFactor"},
      {"GAMUT_COMPRESS_LIM.r", 1.147, "aces_output.cpp kCompressLimit[0]"},
      {"GAMUT_COMPRESS_LIM.g", 1.264, "aces_output.cpp kCompressLimit[1]"},
      {"GAMUT_COMPRESS_LIM.b", 1.312, "aces_output.cpp kCompressLimit[2]"},
      {"GAMUT_COMPRESS_THR.r", 0.815, "aces_output.cpp kCompressThreshold[0]"},
      {"GAMUT_COMPRESS_THR.g", 0.803, "aces_output.cpp kCompressThreshold[1]"},
      {"GAMUT_COMPRESS_THR.b", 0.880, "aces_output.cpp kCompressThreshold[2]"},
      {"GAMUT_COMPRESS_PWR", 1.2, "aces_output.cpp kCompressPower"},
  };
  // M1 (spline_half: a = 0.5c0 − c1 + 0.5c2, b = −c0 + c1, c = 0.5c0 + 0.5c1), HLSL rows.
  const double m1[3][3] = {{0.5, -1.0, 0.5}, {-1.0, 1.0, 0.5}, {0.5, 0.0, 0.0}};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      t.push_back({"M1[" + std::to_string(r) + "][" + std::to_string(c) + "]", m1[r][c],
                   "aces_output.cpp spline_half M1"});
  // cubic_basis_shaper's M (aces_common.h kM, (1/6)·integers).
  const double m[4][4] = {{-1.0 / 6, 3.0 / 6, -3.0 / 6, 1.0 / 6},
                          {3.0 / 6, -6.0 / 6, 3.0 / 6, 0.0 / 6},
                          {-3.0 / 6, 0.0 / 6, 3.0 / 6, 0.0 / 6},
                          {1.0 / 6, 4.0 / 6, 1.0 / 6, 0.0 / 6}};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      t.push_back({"CUBIC_BASIS_M[" + std::to_string(r * 4 + c) + "]", m[r][c],
                   "aces_common.h cubic_basis_shaper kM"});
  // GLSL M[r] is the HLSL row r (the row-major literal fills columns; aces_common.glsl).
  const std::pair<std::string, const Mat3*> mats[] = {{"AP1_2_XYZ_MAT", &lit::kAp1ToXyz},
                                                      {"XYZ_2_AP1_MAT", &lit::kXyzToAp1},
                                                      {"AP0_2_AP1_MAT", &lit::kAp0ToAp1},
                                                      {"AP1_2_AP0_MAT", &lit::kAp1ToAp0}};
  for (const auto& [name, mat] : mats)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        t.push_back({name + "[" + std::to_string(r) + "][" + std::to_string(c) + "]", (*mat)(r, c),
                     "ue_matrices.h ue_literal"});
  for (int c = 0; c < 3; ++c)
    t.push_back(
        {"AP1_RGB2Y[" + std::to_string(c) + "]", lit::kAp1RgbToY[c], "ue_matrices.h kAp1RgbToY"});
  return t;
}

Outcome check_constants(const fs::path& lib) {
  const auto table = constant_table();
  std::string body = "  if (i != 0u) return;\n";
  for (size_t k = 0; k < table.size(); ++k)
    body += "  out_px[" + std::to_string(k) + "] = vec4(" + table[k].glsl + ", 0.0, 0.0, 0.0);\n";
  Probe probe(lib, body);
  if (!probe.init_error().empty()) return {probe.init_error(), ""};
  std::string error;
  const auto out = probe.run(AcesConfig{}, Inputs(table.size(), {0, 0, 0, 0}), &error);
  if (!error.empty()) return {error, ""};
  std::ostringstream fail;
  fail.precision(9);
  for (size_t k = 0; k < table.size(); ++k) {
    const float want = static_cast<float>(table[k].reference);
    const float got = static_cast<float>(out[k][0]);
    if (got != want)
      fail << table[k].glsl << " = " << got << " on the GPU, float(reference) = " << want << " ("
           << table[k].source << ")\n";
  }
  return {fail.str(), std::to_string(table.size()) + " constants compared\n"};
}

// ---------------------------------------------------------------------------------------------
// Tests.

TEST(AcesShader, ConstantsEqualFloatOfReference) {
  const Outcome o = check_constants(suite_lib());
  EXPECT_EQ(o.failure, "");
  std::printf("%s", o.report.c_str());
}

TEST(AcesShader, SstsMatchesReference) {
  const Outcome o = check_ssts(suite_lib());
  EXPECT_EQ(o.failure, "");
  std::printf("%s", o.report.c_str());
}

TEST(AcesShader, RrtSweetenersMatchReference) {
  const Outcome o = check_rrt(suite_lib());
  EXPECT_EQ(o.failure, "");
  std::printf("%s", o.report.c_str());
}

TEST(AcesShader, CompressColorMatchesReference) {
  const Outcome o = check_compress(suite_lib());
  EXPECT_EQ(o.failure, "");
  std::printf("%s", o.report.c_str());
}

// The whole transform for MaxLuminance 400 … 10 000, GamutCompression 0/1 and two
// SceneColorMultipliers, over greys, primaries/secondaries, negatives and random colours.
TEST(AcesShader, OutputTransformsMatchReference) {
  const SweepResult r = run_output_sweep(suite_lib());
  const Outcome o = judge_output_sweep(r);
  EXPECT_EQ(o.failure, "");
  std::printf("%s", o.report.c_str());
  // The table of docs/precision.md: per MaxLuminance over every configuration of that luminance.
  for (const int nits : {400, 1000, 2000, 4000, 10000}) {
    Stats all;
    for (const auto& [cfg, st] : r.per_config)
      if (cfg.max_nits == nits) all.merge(st);
    std::printf("| %d | %.2g | %.2g | %.2g | %.2g | %.2g | %.2g |\n", nits, all.max_rel(),
                Stats::percentile(all.rel, 0.999), all.max_pix(), Stats::percentile(all.pix, 0.999),
                all.max_pq(), Stats::percentile(all.pq, 0.999));
  }
}

// GLSL has no log10: log10_d3d(x) = log2(x) · float(ln 2 / ln 10), which is how DXC lowers HLSL
// log10 (so UE on D3D rounds the same way), and pow10_d3d(y) = exp2(y · float(log2 10)). Measured
// on lavapipe over x in 1e-12 … 1e6 and y in −5 … 4.5: log2 ≤ 1.45 ulp (1.6e-7 absolute near 1),
// log10_d3d ≤ 2.3 ulp of the result (a correctly rounded log10 would be ≤ 0.5 ulp: the product
// form costs ≈ 1.8 ulp, ≤ 1.6e-6 absolute at |log10 x| = 12 in ssts' flat tails, ≤ 5e-7 in the
// spline range), pow10_d3d ≤ 1.44e-6 relative (the exp2 argument y·3.32 rounded to float: ulp
// 1.9e-6 at 16). Bounds: Vulkan's log2 precision (3 ulp; 2^-21 absolute in [0.5, 2]) and about 2×
// the measured values for the others.
TEST(AcesShader, D3dLog10AndPow10Precision) {
  Probe probe(suite_lib(),
              "  out_px[i] = vec4(log10_d3d(in_px[i].r), log2(in_px[i].r), "
              "pow10_d3d(in_px[i].g), 0.0);");
  ASSERT_EQ(probe.init_error(), "");
  Inputs in;
  for (int i = 0; i <= 4000; ++i)
    in.push_back(px(std::pow(10.0, -12.0 + 18.0 * i / 4000.0), -5.0 + 9.5 * i / 4000.0, 0));
  std::string error;
  const auto out = probe.run(AcesConfig{}, in, &error);
  ASSERT_EQ(error, "");
  // Errors in units of the float result's ulp (outside x in [0.5, 2], where the results approach 0
  // and the Vulkan bound for log2 is absolute, 2^-21), and absolute inside it.
  const auto ulp_of = [](double v) {
    const float f = std::fabs(static_cast<float>(v));
    return static_cast<double>(std::nextafter(f, INFINITY) - f);
  };
  double log10_ulps = 0, log2_ulps = 0, log10_abs_near1 = 0, log2_abs_near1 = 0, pow10_rel = 0;
  for (size_t i = 0; i < in.size(); ++i) {
    const double x = in[i][0], y = in[i][1];
    const double e10 = std::fabs(out[i][0] - std::log10(x)),
                 e2 = std::fabs(out[i][1] - std::log2(x));
    if (x >= 0.5 && x <= 2.0) {
      log10_abs_near1 = std::max(log10_abs_near1, e10);
      log2_abs_near1 = std::max(log2_abs_near1, e2);
    } else {
      log10_ulps = std::max(log10_ulps, e10 / ulp_of(std::log10(x)));
      log2_ulps = std::max(log2_ulps, e2 / ulp_of(std::log2(x)));
    }
    const double p10 = std::pow(10.0, y);
    pow10_rel = std::max(pow10_rel, std::fabs(out[i][2] - p10) / p10);
  }
  std::printf(
      "log2: max %.3g ulp (|error| %.3g near 1); log10_d3d: max %.3g ulp (|error| %.3g near "
      "1); pow10_d3d: max relative error %.3g\n",
      log2_ulps, log2_abs_near1, log10_ulps, log10_abs_near1, pow10_rel);
  EXPECT_LE(log2_ulps, 3.0);                        // Vulkan's bound for log2
  EXPECT_LE(log2_abs_near1, std::ldexp(1.0, -21));  // Vulkan's bound near 1
  EXPECT_LE(log10_ulps, 4.0);
  EXPECT_LE(log10_abs_near1, 1.5e-7);  // 2^-21 · log10(2)
  EXPECT_LE(pow10_rel, 3e-6);
}

// ACESOutputTransforms2000 has the same body as ACESOutputTransforms1000 (TonemapCommon.ush).
TEST(AcesShader, OutputTransforms2000MatchesReference) {
  const Outcome o = judge_output_sweep(run_output_sweep(suite_lib(), "2000"));
  EXPECT_EQ(o.failure, "");
}

// A NaN or ±Inf channel leaves as black, negative channels are clamped: the reference's
// documented behaviour (reference/ue/aces/aces_output.h) holds on the GPU. After rrt_sweeteners'
// clamp such a pixel is AP1 (0, 0, 0), exactly what a black input becomes, so its output must equal
// the GPU's output for black bit for bit. Black itself is ≥ 0 and ≤ 1e-10 nits: float32 leaves
// 10^(log10 Min.y) − Min.y ≈ 2.2e-11 nits (measured on lavapipe; 0.002 10-bit PQ codes) where the
// reference gives ≈ 0.
Outcome check_nonfinite(const fs::path& lib) {
  Probe probe(lib, "  out_px[i] = vec4(aces_output_transforms_1000(in_px[i].rgb), 0.0);");
  if (!probe.init_error().empty()) return {probe.init_error(), ""};
  const Inputs nonfinite = {{0, 0, 0, 1},  // black, the expected output of every other row
                            {kNaN, 0.5, 0.5, 1},   {0.5, kNaN, 0.5, 1},  {0.5, 0.5, kNaN, 1},
                            {kNaN, kNaN, kNaN, 1}, {kInf, 0.5, 0.5, 1},  {0.5, kInf, 0.5, 1},
                            {0.5, 0.5, kInf, 1},   {-kInf, 0.5, 0.5, 1}, {kInf, kInf, kInf, 1},
                            {kInf, -kInf, 0, 1},   {kNaN, kInf, 1e4, 1}, {-kInf, -kInf, -kInf, 1}};
  const Inputs negative = {{-1, -1, -1, 1},
                           {-1, 0.5, 0.5, 1},
                           {0.5, -1e-3, 0.5, 1},
                           {-0.0, -0.0, -0.0, 1},
                           {100, -50, 0, 1}};
  std::ostringstream fail;
  fail.precision(9);
  for (const double gc : {0.0, 1.0}) {
    const AcesConfig cfg{1000, gc, 1.5};
    std::string error;
    const auto out = probe.run(cfg, nonfinite, &error);
    if (!error.empty()) return {error, ""};
    for (int c = 0; c < 3; ++c)
      if (!(out[0][c] >= 0.0 && out[0][c] <= 1e-10))
        fail << "GamutCompression " << gc << ": black gives " << out[0][c] << " nits in channel "
             << c << "\n";
    for (size_t i = 1; i < nonfinite.size(); ++i)
      for (int c = 0; c < 3; ++c)
        if (!(out[i][c] == out[0][c]))
          fail << "GamutCompression " << gc << ": input "
               << describe({nonfinite[i][0], nonfinite[i][1], nonfinite[i][2]}) << " channel " << c
               << " gives " << out[i][c] << " nits, black gives " << out[0][c] << "\n";
    const auto neg = probe.run(cfg, negative, &error);
    if (!error.empty()) return {error, ""};
    const hdrc::ParamBlock p = resolve_block(cfg, static_cast<int>(negative.size()));
    for (size_t i = 0; i < negative.size(); ++i) {
      const Vec3 x{negative[i][0], negative[i][1], negative[i][2]};
      const Vec3 want = aces::aces_output_transforms_1000(x, p.wcs_to_ap0, reference_params(p));
      for (int c = 0; c < 3; ++c)
        if (!(neg[i][c] >= 0.0 && std::fabs(neg[i][c] - want[c]) <=
                                      kOutputMaxRel * std::max(want[c], kOutputRelFloorNits)))
          fail << "GamutCompression " << gc << ": negative input " << describe(x) << " channel "
               << c << " gives " << neg[i][c] << " nits, reference " << want[c] << "\n";
    }
  }
  return {fail.str(), ""};
}

TEST(AcesShader, NonFiniteInputLeavesAsBlack) {
  EXPECT_EQ(check_nonfinite(suite_lib()).failure, "");
}

// Planted defects: one constant or coefficient changed in a copy of the library must make the
// checks fail, and the failure names where.
struct Defect {
  std::string file, from, to, why;
};

fs::path planted_lib(const fs::path& root, const Defect& d) {
  fs::remove_all(root);
  fs::copy(suite_lib(), root, fs::copy_options::recursive);
  const fs::path f = root / d.file;
  std::ifstream in(f);
  std::stringstream s;
  s << in.rdbuf();
  std::string text = s.str();
  const size_t at = text.find(d.from);
  EXPECT_NE(at, std::string::npos) << d.file << ": '" << d.from << "' not found";
  EXPECT_EQ(text.find(d.from, at + 1), std::string::npos)
      << d.file << ": '" << d.from << "' is not unique";
  if (at != std::string::npos) text.replace(at, d.from.size(), d.to);
  std::ofstream(f) << text;
  return root;
}

TEST(AcesShader, PlantedDefectsAreCaughtAndLocated) {
  const Defect defects[] = {
      {"aces_common.glsl", "RRT_GLOW_GAIN = 0.05;", "RRT_GLOW_GAIN = 0.0501;",
       "RRT glow gain 0.2 % off"},
      // (The literal comes from the generated interface; planted where the RRT reads it.)
      {"aces_rrt.glsl", "aces_mul(AP0_2_AP1_MAT, aces)",
       "aces_mul(AP0_2_AP1_MAT + mat3(0.0, 0.0, 0.0, -1e-5, 0.0, 0.0, 0.0, 0.0, 0.0), aces)",
       "AP0_2_AP1_MAT[1][0] off in the 5th decimal"},
      {"aces_gamut_compress.glsl", "vec3(0.815, 0.803, 0.880)", "vec3(0.815, 0.8031, 0.880)",
       "THR_MAGENTA off in the 4th decimal"},
      {"aces_tonescale.glsl", "coefs_low_0.z, coefs_low_0.w,",
       "coefs_low_0.z + 1e-4, coefs_low_0.w,",
       "ACESCoefsLow_0.z (coefsLow[2]) 1e-4 off in log10 nits"},
      {"aces_tonescale.glsl", "-1.0, 1.0, 0.5,", "-1.0, 1.0, 0.50001,", "M1[1][2] 2e-5 off"},
      // A port whose max() propagates NaN (GLSL leaves max(NaN, x) undefined): clamp and ssts'
      // max(x, 1e-10) then keep the NaN that D3D's maxNum removes. (A NaN-propagating clamp alone
      // is masked: ssts' max(x, 1e-10) maps NaN to Min.y.)
      {"d3d_math.glsl",
       "float max_d3d(float a, float b) { return isnan(a) ? b : (isnan(b) ? a : max(a, b)); }",
       "float max_d3d(float a, float b) { return (isnan(a) || isnan(b)) ? hdrc_nan() : max(a, b); "
       "}",
       "max_d3d propagating NaN"},
  };
  const fs::path root =
      fs::temp_directory_path() / ("hdrc_aces_defect_" + std::to_string(::getpid()));
  for (const Defect& d : defects) {
    const fs::path lib = planted_lib(root, d);
    const Outcome constants = check_constants(lib);
    const Outcome ssts = check_ssts(lib);
    const Outcome rrt = check_rrt(lib);
    const Outcome compress = check_compress(lib);
    const Outcome output = judge_output_sweep(run_output_sweep(lib));
    const Outcome nonfinite = check_nonfinite(lib);
    const std::string all = constants.failure + ssts.failure + rrt.failure + compress.failure;
    EXPECT_NE(output.failure + nonfinite.failure, "")
        << d.why << ": neither the output-transform nor the non-finite check failed";
    EXPECT_NE(all + nonfinite.failure, "") << d.why << ": no function-level check failed";
    const auto first_line = [](const Outcome& o) {
      return o.failure.empty() ? std::string("pass\n")
                               : o.failure.substr(0, o.failure.find('\n') + 1);
    };
    std::printf(
        "planted defect: %s\n  constants: %s  ssts: %s  rrt_sweeteners: %s"
        "  compress_color: %s  output: %s  non-finite: %s",
        d.why.c_str(), first_line(constants).c_str(), first_line(ssts).c_str(),
        first_line(rrt).c_str(), first_line(compress).c_str(), first_line(output).c_str(),
        first_line(nonfinite).c_str());
  }
  fs::remove_all(root);
}

}  // namespace
