// The GLSL HDR UI composite (gpu/shaders/lib/ui_composite.glsl and what it includes) against the
// double-precision reference (reference/ue/ui/composite.cpp), on lavapipe:
//  * every constant the shaders hard-code reads back as float(reference constant) (acceptance 4);
//  * the composite of every 10-bit PQ code (or the same numbers as scRGB) under the ui_overlay
//    stimulus's alpha ramps, for the configurations of cases/ui/*.json and more, within the
//    bounds measured in docs/precision.md ("GPU UI composite and VisualizeHDR");
//  * non-finite inputs are non-finite exactly where the reference's are;
//  * the ui_composite stage through the engine (the UI layer bound as aux0).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "gpu/device_bounds_test.h"
#include "gpu/shader_probe.h"
#include "color/gamma_correction.h"
#include "color/st2084.h"
#include "reference/reference_engine.h"
#include "reference/ue/ue_pixel_device.h"
#include "reference/ue/ui/color_deficiency.h"
#include "reference/ue/ui/composite.h"

namespace {

using hdrc::Image;
using hdrc::ResolvedCase;
using hdrc::gpu::testing::ErrorStats;
using hdrc::gpu::testing::make_case;
using hdrc::gpu::testing::read_back;
using hdrc::gpu::testing::run_probe;
namespace ui = hdrc::ref::ui;
namespace pq = hdrc::ref::st2084;

struct Expected {
  std::string glsl;
  double reference;
};

void add_matrix(std::vector<Expected>* out, const std::string& glsl_rows, int first_row,
                const hdrc::ref::Mat3& m) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      out->push_back(
          {glsl_rows + "[" + std::to_string(first_row + r) + "][" + std::to_string(c) + "]",
           m(r, c)});
}

// Acceptance 4: float(reference) == shader, for every constant of the UI composite's GLSL.
TEST(UiShader, ConstantsEqualTheReference) {
  std::vector<Expected> e;
  add_matrix(&e, "SRGB_TO_REC2020", 0, ui::srgb_to_rec2020());
  add_matrix(&e, "REC2020_TO_SRGB", 0, ui::rec2020_to_srgb());
  const struct {
    const char* glsl;
    ui::CvdType type;
    const char* daltonize;
  } tables[] = {{"cvd_deuteranomaly_rows", ui::CvdType::kDeuteranope, "CVD_DALTONIZE_GREEN_BLIND"},
                {"cvd_protanomaly_rows", ui::CvdType::kProtanope, "CVD_DALTONIZE_RED_BLIND"},
                {"cvd_tritanomaly_rows", ui::CvdType::kTritanope, "CVD_DALTONIZE_BLUE_BLIND"}};
  for (const auto& t : tables) {
    // The tables are switch statements over the severity (color_deficiency.glsl): row r of
    // severity s is cvd_*_rows(s)[r].
    for (int s = 0; s < ui::kCvdSeverityCount; ++s)
      add_matrix(&e, std::string(t.glsl) + "(" + std::to_string(s) + ")", 0,
                 ui::machado_matrix(t.type, s));
    add_matrix(&e, t.daltonize, 0, ui::daltonize_matrix(t.type));
  }
  e.push_back({"CVD_SEVERITY_COUNT", ui::kCvdSeverityCount});
  e.push_back({"CVD_DEUTERANOPE", static_cast<double>(ui::CvdType::kDeuteranope)});
  e.push_back({"CVD_PROTANOPE", static_cast<double>(ui::CvdType::kProtanope)});
  e.push_back({"CVD_TRITANOPE", static_cast<double>(ui::CvdType::kTritanope)});
  e.push_back({"UI_SCRGB_SCALE_FACTOR", ui::kScRgbScaleFactor});
  for (int c = 0; c < 3; ++c)
    e.push_back({"UI_REC2020_LUMA_WEIGHTS[" + std::to_string(c) + "]", ui::kRec2020LumaWeights[c]});
  e.push_back({"SRGB_MIN_NORMAL_CLAMP", hdrc::ref::kMinNormal});
  // sRGBToLinear's literals: color/gamma_correction.h srgb_to_linear writes them inline
  // (c > 0.04045 ? pow(c * (1.0 / 1.055) + 0.0521327, 2.4) : c * (1.0 / 12.92)); the functional
  // test below pins the function itself.
  e.push_back({"SRGB_DECODE_THRESHOLD", 0.04045});
  e.push_back({"SRGB_DECODE_SCALE", 1.0 / 1.055});
  e.push_back({"SRGB_DECODE_OFFSET", 0.0521327});
  e.push_back({"SRGB_DECODE_GAMMA", 2.4});
  e.push_back({"SRGB_LINEAR_SCALE", 1.0 / 12.92});

  std::vector<std::string> glsl;
  for (const auto& x : e) glsl.push_back(x.glsl);
  auto got = read_back(glsl, {"lib/ui_composite.glsl"});
  ASSERT_TRUE(got.ok()) << got.error().to_string();
  ASSERT_EQ(got->size(), e.size());
  for (size_t k = 0; k < e.size(); ++k)
    EXPECT_EQ((*got)[k], static_cast<float>(e[k].reference)) << e[k].glsl;
}

// sRGBToLinear with the D3 clamp, on the GPU vs the reference, over every 8-bit code and the
// clamp's and threshold's neighbourhood.
TEST(UiShader, SrgbToLinearMatchesReference) {
  std::vector<double> xs;
  for (int k = 0; k <= 255; ++k) xs.push_back(static_cast<float>(k / 255.0));
  for (double x : {0.0, -1.0, 6.10352e-5, 6.1e-5, 0.04045, 0.0404501, 0.0404499, 1.5})
    xs.push_back(static_cast<float>(x));
  Image in(static_cast<int>(xs.size()), 1);
  for (size_t i = 0; i < xs.size(); ++i) in.data[i * 4] = xs[i];
  const std::string src = hdrc::gpu::testing::probe_preamble() +
                          "#include \"lib/srgb_to_linear.glsl\"\n"
                          "void main() {\n  uint i = gl_GlobalInvocationID.x;\n"
                          "  if (i >= uint(P.width * P.height)) return;\n"
                          "  out_px[i] = vec4(srgb_to_linear(in_px[i].x), 0, 0, 0);\n}\n";
  auto out = run_probe(src, make_case("shaper", 3, in));
  ASSERT_TRUE(out.ok()) << out.error().to_string();
  for (size_t i = 0; i < xs.size(); ++i) {
    const double want = hdrc::ref::srgb_to_linear(xs[i]);
    // float32 pow: a few ulp (measured max 2.4e-7 relative on lavapipe).
    EXPECT_NEAR(out->data[i * 4], want, 1e-6 * std::fabs(want)) << "x = " << xs[i];
  }
}

// The inputs of cases/ui/*.json, rounded to float as the engine uploads them: the back buffer is
// the pq_codes stimulus (x / (W − 1) on rows (v,v,v), (v,0,0), (0,v,0), (0,0,v)) and the UI is the
// ui_overlay stimulus (premultiplied sRGB-encoded colours under alpha ramps, a hard-edged checker,
// alpha 0 and 1 rows) — the formulas of runner/stimuli.cpp.
void make_inputs(int width, int height, Image* scene, Image* ui_layer) {
  *scene = Image(width, height);
  *ui_layer = Image(width, height);
  static const double colours[5][3] = {{1, 1, 1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.5, 0.5, 0.5}};
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double v = static_cast<float>(x * 1023.0 / (width - 1) / 1023.0);
      double* s = scene->px(x, y);
      for (int c = 0; c < 3; ++c) s[c] = (y % 4 == 0 || y % 4 == c + 1) ? v : 0.0;
      s[3] = 1.0;
      const int row = y % 8;
      double a = static_cast<float>(static_cast<double>(x) / (width - 1));
      const double* col = colours[row < 5 ? row : 0];
      if (row == 5) a = ((x / 8) % 2) ? 1.0 : 0.0;
      if (row == 6) a = 0.0;
      if (row == 7) a = 1.0;
      double* u = ui_layer->px(x, y);
      for (int c = 0; c < 3; ++c) u[c] = static_cast<float>(col[c] * a);
      u[3] = a;
    }
}

// The probe: back buffer in in_px[0, n), UI in in_px[n, 2n), the composite to out_px[0, n).
std::string composite_probe() {
  return hdrc::gpu::testing::probe_preamble() +
         "#include \"lib/ui_composite.glsl\"\n"
         "void main() {\n"
         "  uint n = uint(P.width * P.height) / 2u;\n"
         "  uint i = gl_GlobalInvocationID.x;\n"
         "  if (i >= n) return;\n"
         "  out_px[i] = ui_composite_pixel(in_px[i], in_px[n + i], "
         "ui_composite_params_from_block());\n"
         "}\n";
}

struct Config {
  const char* name;
  int device;
  double level, luminance;
  int mode;
  int cvd_type, cvd_severity, cvd_correct, cvd_show;
  double bound_pq10;  // max |ΔPQ| in 10-bit codes (docs/precision.md)
};

double to_nits(double v, int device) {
  return (device == 5 || device == 6) ? v * 80.0 : pq::nits_from_pq(v);
}
double pq10(double nits) {
  return pq::pq_from_nits(std::fmax(nits, 0.0)) * 1023.0;
}

struct Measured {
  ErrorStats pq, rel, rel_e3, abs;  // rel: floor 1e-6; rel_e3: floor 1e-3
  int nonfinite_mismatch = 0;
  int nonfinite_consistent = 0;
  // The value with the largest PQ error: pixel, channel, reference, candidate.
  int worst_pixel = -1, worst_channel = -1;
  double worst_reference = 0, worst_candidate = 0;
};

// Runs `c` on the GPU (probe) and the reference over scene/ui; returns the error statistics.
Measured measure(hdrc::gpu::testing::Probe& probe, const Config& c, const Image& scene,
                 const Image& ui_layer) {
  const int n = scene.width * scene.height;
  Image packed(2 * n, 1);
  std::copy(scene.data.begin(), scene.data.end(), packed.data.begin());
  std::copy(ui_layer.data.begin(), ui_layer.data.end(), packed.data.begin() + 4 * n);
  ResolvedCase rc = make_case("shaper", c.device, packed);
  rc.params.ui_level = c.level;
  rc.params.ui_luminance = c.luminance;
  rc.params.ui_composite_mode = c.mode;
  rc.params.cvd_type = c.cvd_type;
  rc.params.cvd_severity = c.cvd_severity;
  rc.params.cvd_correct = c.cvd_correct;
  rc.params.cvd_show_correction = c.cvd_show;
  const ui::UiCompositeParams up = hdrc::ref::ui_composite_params(rc.params);
  Measured m;
  auto got = probe.run(rc);
  EXPECT_TRUE(got.ok()) << got.error().to_string();
  if (!got.ok()) return m;
  Image reference(scene.width, scene.height);
  for (int i = 0; i < n; ++i) {
    const double* s = &scene.data[i * 4];
    const double* u = &ui_layer.data[i * 4];
    const ui::Vec4 want =
        ui::composite_pixel({s[0], s[1], s[2], s[3]}, {u[0], u[1], u[2], u[3]}, up);
    for (int ch = 0; ch < 4; ++ch) reference.data[i * 4 + ch] = want[ch];
  }
  // Elsewhere than on a float32-exact device: within the composite's device ranges
  // (reference/ue/ue_pixel_device.h ui_composite_device_ranges: the back buffer's PQ decode and the
  // encode within the precision table's bounds, kShaderNoise for the steps between), nearest the
  // GPU's value; the bounds below then measure what lies outside them.
  if (!hdrc::gpu::testing::exact_device()) {
    reference.device_admissible =
        hdrc::ref::ue_device::ui_composite_device_ranges(rc.params, scene, ui_layer, reference);
    reference = hdrc::gpu::testing::nearest_admissible(reference, *got);
  }
  for (int i = 0; i < n; ++i) {
    for (int ch = 0; ch < 4; ++ch) {
      const double g = got->data[i * 4 + ch];
      const double r = reference.data[i * 4 + ch];
      if (!std::isfinite(r) || !std::isfinite(g)) {
        const bool same = (std::isnan(r) && std::isnan(g)) || (std::isinf(r) && g == r);
        ++(same ? m.nonfinite_consistent : m.nonfinite_mismatch);
        continue;
      }
      if (ch == 3) continue;
      const double e = std::fabs(pq10(to_nits(g, c.device)) - pq10(to_nits(r, c.device)));
      if (e > m.pq.max()) {
        m.worst_pixel = i;
        m.worst_channel = ch;
        m.worst_reference = r;
        m.worst_candidate = g;
      }
      m.pq.add(e);
      m.rel.add(std::fabs(g - r) / std::fmax(std::fabs(r), 1e-6));
      m.rel_e3.add(std::fabs(g - r) / std::fmax(std::fabs(r), 1e-3));
      m.abs.add(std::fabs(g - r));
    }
  }
  return m;
}

// Every configuration the ui cases run, plus level/luminance extremes, both CVD directions for
// every type and the mode-0 blend on both back buffers. Prints the table docs/precision.md holds.
TEST(UiShader, CompositeMatchesReference) {
  Image scene, ui_layer;
  make_inputs(1024, 8, &scene, &ui_layer);
  // Bounds: the measured maximum on lavapipe (docs/precision.md) with a 1.5x margin, rounded up.
  const Config configs[] = {
      // cases/ui/composite.json: devices 3 and 5, UI luminance 300 / 203, UI level 1 / 2.
      {"dev3 L300 lvl1", 3, 1, 300, 1, 0, 0, 0, 0, 0.03},
      {"dev3 L300 lvl2", 3, 2, 300, 1, 0, 0, 0, 0, 0.03},
      {"dev3 L203 lvl1", 3, 1, 203, 1, 0, 0, 0, 0, 0.03},
      {"dev3 L203 lvl2", 3, 2, 203, 1, 0, 0, 0, 0, 0.03},
      {"dev5 L300 lvl1", 5, 1, 300, 1, 0, 0, 0, 0, 0.25},
      {"dev5 L300 lvl2", 5, 2, 300, 1, 0, 0, 0, 0, 0.25},
      {"dev5 L203 lvl1", 5, 1, 203, 1, 0, 0, 0, 0, 0.25},
      {"dev5 L203 lvl2", 5, 2, 203, 1, 0, 0, 0, 0, 0.25},
      // cases/ui/color_deficiency.json: protanope, severity 10, corrected.
      {"dev3 protan10 correct", 3, 1, 300, 1, 2, 10, 1, 0, 0.4},
      // cases/ui/composite_mode0.json.
      {"dev3 mode0", 3, 1, 300, 0, 0, 0, 0, 0, 1e-4},
      // Beyond the case files: devices 4 and 6, extreme level / luminance, every CVD type and
      // direction, CVD on scRGB, mode 0 on scRGB.
      {"dev4 L300 lvl1", 4, 1, 300, 1, 0, 0, 0, 0, 0.03},
      {"dev6 L203 lvl2", 6, 2, 203, 1, 0, 0, 0, 0, 0.25},
      {"dev3 L1000 lvl0.5", 3, 0.5, 1000, 1, 0, 0, 0, 0, 0.03},
      {"dev3 deutan10 simulate", 3, 1, 300, 1, 1, 10, 0, 0, 0.4},
      {"dev3 tritan5 correct+show", 3, 1, 300, 1, 3, 5, 1, 1, 0.4},
      {"dev3 protan1 simulate", 3, 1, 300, 1, 2, 1, 0, 0, 0.4},
      {"dev5 tritan10 correct", 5, 1, 300, 1, 3, 10, 1, 0, 2e-4},
      {"dev5 mode0", 5, 1, 300, 0, 0, 0, 0, 0, 1e-4},
  };

  hdrc::gpu::testing::Probe probe(composite_probe());
  for (const Config& c : configs) {
    const Measured m = measure(probe, c, scene, ui_layer);
    std::printf(
        "[ ui ] %-26s pq10 max %.3g p99.9 %.3g | rel max %.3g p99.9 %.3g | rel(1e-3) max %.3g | "
        "abs max %.3g | NaN %d "
        "| worst (%d, %d) ch %d ref %.9g gpu %.9g\n",
        c.name, m.pq.max(), m.pq.percentile(0.999), m.rel.max(), m.rel.percentile(0.999),
        m.rel_e3.max(), m.abs.max(), m.nonfinite_consistent, m.worst_pixel % 1024,
        m.worst_pixel / 1024, m.worst_channel, m.worst_reference, m.worst_candidate);
    EXPECT_EQ(m.nonfinite_mismatch, 0) << c.name;
    // Every colour value is either compared or non-finite on both sides.
    EXPECT_EQ(m.pq.errors.size() + m.nonfinite_consistent, 3u * 1024 * 8) << c.name;
    EXPECT_LE(m.pq.max(), c.bound_pq10) << c.name;
  }
}

// NaN, ±Inf and negative back-buffer codes and UI values: non-finite exactly where the reference
// is (D3D rules: maxNum in the clamp and the Reinhard, pow of negatives NaN, 0·Inf NaN).
TEST(UiShader, NonFiniteInputsFollowTheReference) {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double specials[] = {nan, inf, -inf, -0.5, 0.0, 0.5, 1.0, 2.0};
  const double alphas[] = {0.0, 0.5, 1.0, nan, -0.5, 1.5};
  Image scene(8 * 8 * 6, 1), ui_layer(8 * 8 * 6, 1);
  int i = 0;
  for (double s : specials)
    for (double u : specials)
      for (double a : alphas) {
        double* sp = scene.px(i, 0);
        double* up = ui_layer.px(i, 0);
        sp[0] = s;
        sp[1] = 0.25;
        sp[2] = s;
        sp[3] = 1.0;
        up[0] = u;
        up[1] = 0.1;
        up[2] = u;
        up[3] = a;
        ++i;
      }
  hdrc::gpu::testing::Probe probe(composite_probe());
  for (const Config& c :
       {Config{"dev3", 3, 1, 300, 1, 0, 0, 0, 0, 0}, Config{"dev5", 5, 1, 300, 1, 0, 0, 0, 0, 0},
        Config{"dev3 protan", 3, 1, 300, 1, 2, 10, 1, 1, 0},
        Config{"dev3 mode0", 3, 1, 300, 0, 0, 0, 0, 0, 0},
        Config{"dev5 mode0", 5, 1, 300, 0, 0, 0, 0, 0, 0}}) {
    const Measured m = measure(probe, c, scene, ui_layer);
    EXPECT_EQ(m.nonfinite_mismatch, 0) << c.name;
  }
}

// The ui_composite stage as the runner runs it: the engine binds the case's back buffer as in_px
// and its UI layer as aux0 (the stage's single pass, stages/ui_composite.comp).
TEST(UiShader, StageThroughTheEngineMatchesReference) {
  Image scene, ui_layer;
  make_inputs(256, 8, &scene, &ui_layer);
  hdrc::gpu::VulkanEngine gpu({});
  ASSERT_TRUE(gpu.init().ok());
  hdrc::ref::ReferenceEngine reference;
  for (const auto& [device, bound] : {std::pair{3, 0.03}, std::pair{5, 0.25}}) {
    ResolvedCase rc = make_case("ui_composite", device, scene);
    rc.ui = ui_layer;
    auto want = reference.run(rc);
    ASSERT_TRUE(want.ok()) << want.error().to_string();
    auto got = gpu.run(rc);
    ASSERT_TRUE(got.ok()) << got.error().to_string();
    ASSERT_EQ(got->data.size(), want->data.size());
    for (size_t k = 0; k < want->data.size(); ++k) {
      const double r = want->data[k], g = got->data[k];
      ASSERT_EQ(std::isfinite(r), std::isfinite(g)) << "value " << k;
      if (!std::isfinite(r) || k % 4 == 3) continue;
      EXPECT_LE(std::fabs(pq10(to_nits(g, device)) - pq10(to_nits(r, device))), bound)
          << "device " << device << " pixel " << k / 4 << " channel " << k % 4;
    }
  }
}

}  // namespace
