// The GLSL VisualizeHDR (gpu/shaders/lib/visualize_*.glsl, stages/visualize_histogram.comp,
// stages/visualize_hdr.comp) against the double-precision reference (reference/ue/visualize/*), on
// lavapipe:
//  * every constant the shaders hard-code reads back as float(reference) (acceptance 4);
//  * the histogram splat, the outlier-free average and the place-in-histogram against the
//    reference functions (probe shaders);
//  * the stage's histogram and visualize passes through the engine with the tonemap pass replaced
//    by the identity (so only this stage's shaders are judged), against visualize::visualize_hdr
//    fed the same images;
//  * the whole stage (CombineLUTs, Tonemap, histogram, visualize) against the ReferenceEngine.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "gpu/device_bounds_test.h"
#include "gpu/shader_compiler.h"
#include "gpu/shader_probe.h"
#include "color/gamma_correction.h"
#include "color/st2084.h"
#include "reference/ue/grading/film_tonemap.h"
#include "reference/reference_engine.h"
#include "reference/ue/visualize/histogram.h"
#include "reference/ue/visualize/visualize_hdr.h"

namespace {

using hdrc::Image;
using hdrc::ResolvedCase;
using hdrc::gpu::testing::ErrorStats;
using hdrc::gpu::testing::make_case;
using hdrc::gpu::testing::Probe;
using hdrc::gpu::testing::read_back;
namespace vis = hdrc::ref::visualize;

vis::EyeAdaptationParameters default_parameters() {
  return vis::compute_eye_adaptation_parameters(vis::default_settings(true));
}

// The stage shaders of this file (and the UI composite's) compile as the engine compiles them.
TEST(VisualizeShader, StageShadersCompile) {
  for (const char* shader : {"stages/visualize_histogram.comp", "stages/visualize_hdr.comp",
                             "stages/ui_composite.comp"}) {
    auto spirv = hdrc::gpu::compile_compute(hdrc::gpu::default_shader_dir(), shader);
    EXPECT_TRUE(spirv.ok()) << shader << ": " << (spirv.ok() ? "" : spirv.error().to_string());
  }
}

// Acceptance 4: float(reference) == shader for every constant of the VisualizeHDR GLSL.
TEST(VisualizeShader, ConstantsEqualTheReference) {
  const vis::EyeAdaptationParameters p = default_parameters();
  const vis::PanelGeometry g = vis::panel_geometry(1000, 700);
  struct Expected {
    std::string glsl;
    double reference;
  };
  const std::vector<Expected> e = {
      {"EA_EXPOSURE_LOW_PERCENT", p.exposure_low_percent},
      {"EA_EXPOSURE_HIGH_PERCENT", p.exposure_high_percent},
      {"EA_MIN_AVERAGE_LUMINANCE", p.min_average_luminance},
      {"EA_MAX_AVERAGE_LUMINANCE", p.max_average_luminance},
      {"EA_HISTOGRAM_SCALE", p.histogram_scale},
      {"EA_HISTOGRAM_BIAS", p.histogram_bias},
      {"EA_LUMINANCE_MIN", p.luminance_min},
      {"EA_LUMINANCE_MAX", p.luminance_max},
      {"EA_BLACK_HISTOGRAM_BUCKET_INFLUENCE", p.black_histogram_bucket_influence},
      {"EA_MIDDLE_GREY", vis::kMiddleGrey},
      {"EA_ONE_THIRD", 1.0 / 3.0},  // eye_adaptation_luminance's weights
      // reference_engine.cpp visualize_hdr_stage: in.eye.exposure_bias_only.
      {"EA_EXPOSURE_BIAS_ONLY", 1.0},
      {"HISTOGRAM_SIZE", vis::kHistogramSize},
      {"HISTOGRAM_FIXED_POINT_ONE", 524288.0},   // histogram.cpp kFixedPointOne (file-local)
      {"HISTOGRAM_CONVERT_SCALE", 0.5},          // histogram.cpp build_histogram's 0.5
      {"HISTOGRAM_MIN_OUTLIER_WEIGHT", 0.0001},  // average_luminance_without_outliers' floor
      // Luminance() weights, read off the reference function itself.
      {"UE_LUMINANCE_WEIGHTS.r", vis::ue_luminance({1, 0, 0})},
      {"UE_LUMINANCE_WEIGHTS.g", vis::ue_luminance({0, 1, 0})},
      {"UE_LUMINANCE_WEIGHTS.b", vis::ue_luminance({0, 0, 1})},
      {"VIS_PI", std::numbers::pi},
      {"METER_SAMPLES", 21},          // visualize_hdr.cpp: offsets −10..10
      {"ILLUMINANCE_SAMPLES", 16},    // offsets −8..7
      {"ILLUMINANCE_OFFSET_Y", 100},  // cy − 100
      {"PANEL_MARGIN_X", static_cast<double>(g.left)},
      {"PANEL_BOTTOM", static_cast<double>(700 - g.top)},
      {"PANEL_HEIGHT", static_cast<double>(g.height)},
      {"1000 - 2 * PANEL_MARGIN_X", static_cast<double>(g.width)},
      {"VIS_LUMINANCE_SCALE", vis::VisualizeHdrInputs{}.luminance_scale},
      {"float(VIS_ILLUMINANCE_METER_ENABLED)",
       vis::VisualizeHdrInputs{}.illuminance_meter_enabled ? 1.0 : 0.0},
  };
  std::vector<std::string> glsl;
  for (const auto& x : e) glsl.push_back(x.glsl);
  auto got = read_back(glsl, {"lib/visualize_hdr.glsl"});
  ASSERT_TRUE(got.ok()) << got.error().to_string();
  for (size_t k = 0; k < e.size(); ++k)
    EXPECT_EQ((*got)[k], static_cast<float>(e[k].reference)) << e[k].glsl;
}

// A log-luminance ramp like the log_ramp stimulus: 1e-4 .. 1e4 nits (scene-linear / 100) along x,
// rows (v, v, v), (v, 0, 0), (0, v, 0), (0, 0, v); float-rounded as the engine uploads it.
Image log_ramp(int width, int height) {
  Image img(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double t = static_cast<double>(x) / (width - 1);
      const double v = static_cast<float>(std::pow(10.0, -4.0 + 8.0 * t) / 100.0);
      double* p = img.px(x, y);
      for (int c = 0; c < 3; ++c) p[c] = (y % 4 == 0 || y % 4 == c + 1) ? v : 0.0;
      p[3] = 1.0;
    }
  return img;
}

// The GPU's per-pixel splat (CalculateBucketsAndWeights), summed exactly on the host, equals the
// reference histogram to float32 rounding of the bucket position.
TEST(VisualizeShader, HistogramSplatMatchesReference) {
  Image in = log_ramp(480, 270);
  // Specials too: NaN and negative means land on LuminanceMin (bucket 0, weight 0), +Inf on the
  // top bucket.
  in.px(0, 1)[0] = std::numeric_limits<double>::quiet_NaN();
  in.px(1, 1)[0] = -1.0;
  in.px(2, 1)[1] = std::numeric_limits<double>::infinity();
  Probe probe(hdrc::gpu::testing::probe_preamble() +
              "#include \"lib/visualize_histogram.glsl\"\n"
              "void main() {\n  uint i = gl_GlobalInvocationID.x;\n"
              "  if (i >= uint(P.width * P.height)) return;\n"
              "  int b0, b1; uint w0, w1;\n"
              "  histogram_splat(in_px[i].rgb, b0, w0, b1, w1);\n"
              "  out_px[i] = vec4(float(b0), float(w0), float(b1), float(w1));\n}\n");
  auto out = probe.run(make_case("shaper", 3, in));
  ASSERT_TRUE(out.ok()) << out.error().to_string();
  std::vector<uint64_t> fixed(vis::kHistogramSize, 0);
  for (size_t i = 0; i < in.pixel_count(); ++i) {
    const double* s = &out->data[i * 4];
    fixed[static_cast<int>(s[0])] += static_cast<uint64_t>(s[1]);
    fixed[static_cast<int>(s[2])] += static_cast<uint64_t>(s[3]);
  }
  const vis::Histogram want = vis::build_histogram(in, default_parameters());
  double worst = 0;
  for (int b = 0; b < vis::kHistogramSize; ++b) {
    const double got = static_cast<double>(fixed[b]) / 524288.0 * 0.5 / in.width / in.height;
    // The float32 bucket position f ∈ [0, 63] is off by up to ~4e-6 (ulp(32) = 3.8e-6 plus log2's
    // error · Scale · 63), moving a weight of ~0.5 by as much; on a ramp the errors of one column's
    // pixels share their sign. Measured 5.7e-6 relative per bucket on lavapipe; bound 1e-5.
    EXPECT_NEAR(got, want[b], 1e-5 * want[b] + 1e-9) << "bucket " << b;
    if (want[b] > 0) worst = std::fmax(worst, std::fabs(got - want[b]) / want[b]);
  }
  std::printf("[ visualize ] histogram bucket max relative error %.3g\n", worst);
}

// ComputeAverageLuminanceWithoutOutlier and ComputePlaceInHistogram on the reference's histogram
// (rounded to float as the scratch buffer holds it).
TEST(VisualizeShader, AverageAndPlaceInHistogramMatchReference) {
  const vis::EyeAdaptationParameters p = default_parameters();
  const Image ramp = log_ramp(480, 270);
  const vis::Histogram h = vis::build_histogram(ramp, p);
  // in_px[0, 16): the histogram; in_px[16 + k]: a colour whose place is asked.
  std::vector<hdrc::ref::Vec3> colours;
  for (int k = 0; k <= 400; ++k) {
    const double v = static_cast<float>(std::pow(10.0, -7.0 + 10.0 * k / 400.0));
    colours.push_back({v, v, v});
    colours.push_back({v, 0.5 * v, 0.0});
  }
  colours.push_back({0, 0, 0});
  colours.push_back({-1, -1, -1});
  colours.push_back({std::numeric_limits<double>::quiet_NaN(), 1, 1});
  Image in(16 + static_cast<int>(colours.size()), 1);
  for (int b = 0; b < vis::kHistogramSize; ++b) in.data[b] = static_cast<float>(h[b]);
  for (size_t k = 0; k < colours.size(); ++k)
    for (int c = 0; c < 3; ++c) in.px(16 + static_cast<int>(k), 0)[c] = colours[k][c];
  vis::Histogram hf{};
  for (int b = 0; b < vis::kHistogramSize; ++b) hf[b] = static_cast<float>(h[b]);

  Probe probe(hdrc::gpu::testing::probe_preamble() +
              "#include \"lib/visualize_histogram.glsl\"\n"
              "void main() {\n  uint i = gl_GlobalInvocationID.x;\n"
              "  if (i >= uint(P.width * P.height)) return;\n"
              "  float h[HISTOGRAM_SIZE];\n"
              "  for (int b = 0; b < HISTOGRAM_SIZE; ++b) h[b] = in_px[b / 4][b % 4];\n"
              "  if (i == 0u) {\n"
              "    out_px[0] = vec4(average_luminance_without_outliers(h), histogram_max(h),\n"
              "                     histogram_sum(h), 0);\n"
              "    return;\n  }\n"
              "  if (i < 16u) return;\n"
              "  out_px[i] = vec4(place_in_histogram(in_px[i].rgb, h), 0, 0, 0);\n}\n");
  auto out = probe.run(make_case("shaper", 3, in));
  ASSERT_TRUE(out.ok()) << out.error().to_string();
  const double avg = vis::average_luminance_without_outliers(hf, p);
  // exp2 of a weighted mean of log2 luminances (|log2 L| up to 20) accumulated in float: an
  // absolute error of ~2e-6 in the exponent, ln 2 · that relative. Measured 1.6e-6; bound 4e-6.
  EXPECT_NEAR(out->data[0], avg, 4e-6 * avg);
  EXPECT_EQ(out->data[1], static_cast<float>(vis::histogram_max(hf)));
  EXPECT_NEAR(out->data[2], vis::histogram_sum(hf), 1e-6 * vis::histogram_sum(hf));
  double worst = 0;
  for (size_t k = 0; k < colours.size(); ++k) {
    const double want = vis::place_in_histogram(colours[k], hf, p);
    const double got = out->data[(16 + k) * 4];
    if (std::isnan(want)) {
      EXPECT_TRUE(std::isnan(got)) << "colour " << k;
      continue;
    }
    worst = std::fmax(worst, std::fabs(got - want));
    EXPECT_NEAR(got, want, 2e-6) << "colour " << k;
  }
  std::printf("[ visualize ] average %.9g (ref %.9g), place-in-histogram max abs error %.3g\n",
              out->data[0], avg, worst);
}

// Error statistics of a VisualizeHDR image against the reference's: values (RGB) compared in the
// image's own units; alpha only for debug type 0 (MainPS leaves it undefined for 1 and 2).
struct ImageDiff {
  ErrorStats abs, pq10;  // pq10: |PQ(nits(cand)) − PQ(nits(ref))| · 1023 as the runner measures
  int nonfinite_mismatch = 0;
  int over = 0;  // values off by more than `big`
  int worst = -1, worst_channel = -1;
  double worst_reference = 0, worst_candidate = 0;
};

// The runner's output-to-nits mapping for this stage (runner/diff.cpp OutputEncoding::to_nits):
// device 0 sRGB at a 100-nit white, devices 3/4 PQ.
double to_nits(double v, int device) {
  if (device == 0) return hdrc::ref::srgb_to_linear(v) * 100.0;
  return hdrc::ref::st2084::nits_from_pq(v);
}
double pq10(double nits) {
  return hdrc::ref::st2084::pq_from_nits(std::fmin(std::fmax(nits, 0.0), 10000.0)) * 1023.0;
}

ImageDiff diff(const Image& want, const Image& got, bool compare_alpha, double big,
               int device = 3) {
  ImageDiff d;
  for (size_t k = 0; k < want.data.size(); ++k) {
    if (k % 4 == 3 && !compare_alpha) continue;
    const double r = want.data[k], g = got.data[k];
    if (!std::isfinite(r) || !std::isfinite(g)) {
      if (!(std::isnan(r) && std::isnan(g)) && r != g) ++d.nonfinite_mismatch;
      continue;
    }
    const double e = std::fabs(g - r);
    if (e > d.abs.max()) {
      d.worst = static_cast<int>(k / 4);
      d.worst_channel = static_cast<int>(k % 4);
      d.worst_reference = r;
      d.worst_candidate = g;
    }
    if (e > big) ++d.over;
    d.abs.add(e);
    if (k % 4 != 3) d.pq10.add(std::fabs(pq10(to_nits(g, device)) - pq10(to_nits(r, device))));
  }
  return d;
}

void print(const char* what, const ImageDiff& d, int width) {
  std::printf(
      "[ visualize ] %-28s abs max %.3g p99.9 %.3g | pq10 max %.3g p99.9 %.3g | over %d | worst "
      "(%d, %d) ch %d ref %.9g gpu %.9g\n",
      what, d.abs.max(), d.abs.percentile(0.999), d.pq10.max(), d.pq10.percentile(0.999), d.over,
      d.worst % width, d.worst / width, d.worst_channel, d.worst_reference, d.worst_candidate);
}

// The histogram and visualize passes through the engine, with CombineLUTs replaced by an empty
// pass and the Tonemap pass by the identity (the "tonemapped" scene is the HDR scene): only this
// stage's shaders are judged, against visualize::visualize_hdr fed the same images.
TEST(VisualizeShader, PassesMatchReferenceWithIdentityTonemap) {
  hdrc::gpu::testing::ShaderDirCopy dir("vis");
  dir.write("stages/combine_luts.comp", hdrc::gpu::testing::probe_preamble() + "void main() {}\n");
  dir.write("stages/tonemap.comp",
            hdrc::gpu::testing::probe_preamble() +
                "void main() {\n  uint i = gl_GlobalInvocationID.x;\n"
                "  if (i < uint(P.width * P.height)) out_px[i] = in_px[i];\n}\n");
  hdrc::gpu::VulkanOptions o;
  o.shader_dir = dir.path();
  hdrc::gpu::VulkanEngine gpu(o);
  ASSERT_TRUE(gpu.init().ok());
  const Image ramp = log_ramp(480, 270);
  struct Run {
    int debug_type;
    double pre_exposure, exposure;
  };
  // Debug types 0-2; PreExposure and Exposure away from 1 move the histogram input, the meters
  // and the exposure lines.
  for (const Run run : {Run{0, 1.0, 1.0}, Run{1, 1.0, 1.0}, Run{2, 1.0, 1.0}, Run{0, 2.0, 0.25},
                        Run{1, 0.5, 3.0}}) {
    const int debug_type = run.debug_type;
    ResolvedCase rc = make_case("visualize_hdr", 3, ramp);
    rc.params.visualize_debug_type = debug_type;
    rc.params.pre_exposure = run.pre_exposure;
    rc.params.exposure = run.exposure;
    // reference_engine.cpp visualize_hdr_stage with the tonemapped scene = the HDR scene.
    vis::VisualizeHdrInputs in;
    in.params = hdrc::ref::eye_adaptation_parameters(rc.params);
    in.scene_color = &rc.input;
    in.hdr_scene_color = &rc.input;
    in.one_over_pre_exposure = 1.0 / rc.params.pre_exposure;
    in.histogram = vis::build_histogram(rc.input, in.params, in.one_over_pre_exposure);
    in.eye.exposure = rc.params.exposure * rc.params.pre_exposure;  // EyeAdaptationBuffer[0].x
    in.eye.average_scene_luminance =
        vis::average_luminance_without_outliers(in.histogram, in.params);
    const hdrc::ref::grading::FilmParams film{rc.params.film_slope, rc.params.film_toe,
                                              rc.params.film_shoulder, rc.params.film_black_clip,
                                              rc.params.film_white_clip};
    in.tone_curve = [film](const hdrc::ref::Vec3& c) {
      return hdrc::ref::grading::film_tone_map(c, film);
    };
    const vis::VisualizeHdrResult want = vis::visualize_hdr(in);
    auto got = gpu.run(rc);
    ASSERT_TRUE(got.ok()) << got.error().to_string();
    const ImageDiff d = diff(want.image, *got, debug_type == 0, 1e-3);
    char name[96];
    std::snprintf(name, sizeof name, "identity, debug %d pre %g exp %g", debug_type,
                  run.pre_exposure, run.exposure);
    print(name, d, ramp.width);
    EXPECT_EQ(d.nonfinite_mismatch, 0) << name;
    // The largest differences are the tone-curve overlay's mask saturate(1 − 100·|FilmToneMap −
    // (1 − v)|): float32 FilmToneMap (~1.5e-7) times 100. Measured 1.5e-5 on lavapipe; bound 5e-5.
    EXPECT_LE(d.abs.max(), 5e-5) << name;
  }
}

// The numbers the histogram pass leaves in scratch (lib/visualize_scratch.glsl) — the values
// MainPS prints and the runner records — against the reference's, with the tonemap pass replaced
// by the identity and the visualize pass by a copy of scratch_px[W·H, W·H + 22) to the output.
TEST(VisualizeShader, HistogramPassNumbersMatchReference) {
  hdrc::gpu::testing::ShaderDirCopy dir("visnum");
  dir.write("stages/combine_luts.comp", hdrc::gpu::testing::probe_preamble() + "void main() {}\n");
  dir.write("stages/tonemap.comp",
            hdrc::gpu::testing::probe_preamble() +
                "void main() {\n  uint i = gl_GlobalInvocationID.x;\n"
                "  if (i < uint(P.width * P.height)) out_px[i] = in_px[i];\n}\n");
  dir.write("stages/visualize_hdr.comp",
            hdrc::gpu::testing::probe_preamble() +
                "#include \"../lib/visualize_scratch.glsl\"\n"
                "void main() {\n  uint i = gl_GlobalInvocationID.x;\n"
                "  if (i < uint(VIS_SCRATCH_TEXELS)) out_px[i] = scratch_px[P.width * P.height + "
                "int(i)];\n}\n");
  hdrc::gpu::VulkanOptions o;
  o.shader_dir = dir.path();
  hdrc::gpu::VulkanEngine gpu(o);
  ASSERT_TRUE(gpu.init().ok());
  // A ramp with some texture at the meters so that their averages are not trivial.
  Image ramp = log_ramp(480, 270);
  for (int y = 0; y < ramp.height; ++y)
    for (int x = 0; x < ramp.width; ++x) ramp.px(x, y)[1] *= 1.0 + 0.25 * ((x + 3 * y) % 7);
  for (const auto& [pre, exposure] : {std::pair{1.0, 1.0}, std::pair{2.0, 0.25}}) {
    ResolvedCase rc = make_case("visualize_hdr", 3, ramp);
    rc.params.pre_exposure = pre;
    rc.params.exposure = exposure;
    vis::VisualizeHdrInputs in;
    in.params = hdrc::ref::eye_adaptation_parameters(rc.params);
    in.scene_color = &rc.input;
    in.hdr_scene_color = &rc.input;
    in.one_over_pre_exposure = 1.0 / pre;
    in.histogram = vis::build_histogram(rc.input, in.params, in.one_over_pre_exposure);
    // rc.params.exposure is Exposure / PreExposure (the Tonemap pass's); VisualizeHDR reads the
    // plain exposure (EyeAdaptationBuffer[0].x).
    in.eye.exposure = exposure * pre;
    in.eye.average_scene_luminance =
        vis::average_luminance_without_outliers(in.histogram, in.params);
    in.tone_curve = vis::per_channel([](double v) { return v; });
    const vis::VisualizeHdrText t = vis::visualize_hdr(in).text;
    auto got = gpu.run(rc);
    ASSERT_TRUE(got.ok()) << got.error().to_string();
    auto at = [&](int texel, int c) { return got->data[texel * 4 + c]; };
    for (int b = 0; b < vis::kHistogramSize; ++b)
      EXPECT_NEAR(at(b / 4, b % 4), in.histogram[b], 1e-5 * in.histogram[b] + 1e-9) << b;
    // Relative bounds: float32 sums of 441 / 256 samples and of 64 buckets (~1e-6), log2 of them.
    auto near = [](double got_v, double want, double rel, const char* what) {
      EXPECT_NEAR(got_v, want, rel * std::fabs(want) + 1e-7) << what;
    };
    near(at(16, 0), vis::histogram_max(in.histogram), 1e-5, "histogram max");
    near(at(16, 1), vis::histogram_sum(in.histogram), 1e-5, "histogram sum");
    near(at(16, 2), in.eye.average_scene_luminance, 1e-5, "average scene luminance");
    for (int c = 0; c < 3; ++c) {
      near(at(17, c), t.meter_hdr_average[c], 1e-6, "meter HDR mean");
      near(at(18, c), t.meter_scene_average[c], 1e-6, "meter swatch");
      near(at(19, c), t.illuminance_rgb[c], 1e-6, "illuminance rgb");
    }
    near(at(17, 3), t.meter_luminance, 1e-6, "meter_luminance");
    near(at(18, 3), t.meter_ev100, 1e-6, "meter_ev100");
    near(at(19, 3), t.illuminance_lux, 1e-6, "illuminance_lux");
    near(at(20, 0), t.exposure_without_bias_ev, 1e-6, "exposure_without_bias_ev");
    near(at(20, 1), t.exposure_without_bias_px, 1e-6, "exposure_without_bias_px");
    near(at(20, 2), t.exposure_ev100, 1e-6, "exposure_ev100");
    near(at(20, 3), t.exposure_px, 1e-6, "exposure_px");
    near(at(21, 0), t.average_luminance_px, 1e-5, "average_luminance_px");
    std::printf(
        "[ visualize ] numbers (pre %g exp %g): NIT %.9g/%.9g EV100 %.9g/%.9g LUX %.9g/%.9g "
        "avg %.9g/%.9g (gpu/ref)\n",
        pre, exposure, at(17, 3), t.meter_luminance, at(18, 3), t.meter_ev100, at(19, 3),
        t.illuminance_lux, at(16, 2), in.eye.average_scene_luminance);
  }
}

// The whole stage as the runner runs it (CombineLUTs, Tonemap into scratch, histogram, visualize)
// against the ReferenceEngine, on the case's configurations (cases/visualize/visualize_hdr.json:
// devices 0 and 3, debug types 0-2). Prints the measurement docs/precision.md records.
TEST(VisualizeShader, StageMatchesReferenceEngine) {
  hdrc::gpu::VulkanEngine gpu({});
  ASSERT_TRUE(gpu.init().ok());
  hdrc::ref::ReferenceEngine reference;
  const Image ramp = log_ramp(480, 270);
  for (int device : {0, 3}) {
    for (int debug_type : {0, 1, 2}) {
      ResolvedCase rc = make_case("visualize_hdr", device, ramp);
      rc.spec.cvars.set("r.EyeAdaptation.VisualizeDebugType", debug_type);
      rc.params = *hdrc::ref::resolve_params(rc.spec, ramp.width, ramp.height);
      auto got = gpu.run(rc);
      ASSERT_TRUE(got.ok()) << got.error().to_string();
      // Elsewhere than on a float32-exact device: within the stage's device ranges (the Tonemap
      // pass's, where the output is the tonemapped scene: reference_engine.cpp).
      auto want = hdrc::gpu::testing::stage_reference(reference, rc, *got);
      ASSERT_TRUE(want.ok()) << want.error().to_string();
      const ImageDiff d = diff(*want, *got, debug_type == 0, 1e-2, device);
      char name[64];
      std::snprintf(name, sizeof name, "stage, device %d debug %d", device, debug_type);
      print(name, d, ramp.width);
      EXPECT_EQ(d.nonfinite_mismatch, 0) << name;
      // No value off by 1e-2 (a flipped bar, line, tint or percentile band would be ≥ 0.25).
      EXPECT_EQ(d.over, 0) << name;
      // Dominated by the Tonemap pass (the background, meters and swatch show the tonemapped
      // scene): measured 0.0086 (device 0) and 0.143 (device 3) 10-bit PQ codes on lavapipe.
      EXPECT_LE(d.pq10.max(), device == 0 ? 0.02 : 0.25) << name;
    }
  }
}

}  // namespace
