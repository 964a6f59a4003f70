// The GLSL of pipeline pq_grading (gpu/shaders/pq_grading/lib/pq_grading.glsl) against its
// double-precision reference (reference/pq_grading/pq_grading.h), function by function, on
// lavapipe:
//  * the constants the GLSL hard-codes read back as float(reference constant);
//  * the RGBA16F lighting-target model (clamp to ±65504, packHalf2x16) equals the reference's
//    (Imath half, round to nearest even) on ties, half subnormals, the clamp and NaN;
//  * the strip sampling of a .cube through binding user_lut against the reference's exact-weight
//    model: within the sampler's sub-texel precision (2^-8 of a weight,
//    gpu/tonemap_shader_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "core/cube/cube.h"
#include "gpu/device_bounds_test.h"
#include "gpu/shader_probe.h"
#include "reference/pq_grading/pq_grading.h"

namespace {

using hdrc::Image;
using hdrc::ResolvedCase;
using hdrc::gpu::testing::make_case;
using hdrc::gpu::testing::read_back;
using hdrc::ref::Vec3;
namespace pqg = hdrc::ref::pq_grading;

const std::string kInclude = "pq_grading/lib/pq_grading.glsl";

TEST(PqGradingShader, ConstantsEqualTheReference) {
  struct Expected {
    std::string glsl;
    double reference;
  };
  const std::vector<Expected> e = {
      {"PQG_DISPLAY_SDR", double(pqg::Display::kSdr)},
      {"PQG_DISPLAY_HDR", double(pqg::Display::kHdr)},
      {"PQG_BB_R10G10B10A2", double(pqg::BackBuffer::kR10G10B10A2)},
      {"PQG_BB_RGBA16F", double(pqg::BackBuffer::kRgba16f)},
      {"PQG_BB_SRGB8", double(pqg::BackBuffer::kSrgb8)},
      {"PQG_BB_RGB8", double(pqg::BackBuffer::kRgb8)},
      {"PQG_HALF_MAX", pqg::kHalfMax},
      {"PQG_SCRGB_WHITE_NITS", pqg::kScRgbWhiteNits},
      {"PQG_RGB8_GAMMA", pqg::kRgb8Gamma},
  };
  std::vector<std::string> glsl;
  for (const auto& x : e) glsl.push_back(x.glsl);
  auto got = read_back(glsl, {kInclude});
  ASSERT_TRUE(got.ok()) << got.error().to_string();
  for (size_t k = 0; k < e.size(); ++k)
    EXPECT_EQ((*got)[k], static_cast<float>(e[k].reference)) << e[k].glsl;
}

// Runs `body` (GLSL statements reading `vec4 px = in_px[i]` and writing out_px[i]) over `input`,
// with `rc`'s parameters and user LUT.
hdrc::Result<Image> run_body(const std::string& body, ResolvedCase rc) {
  const std::string src = hdrc::gpu::testing::probe_preamble() + "#include \"" + kInclude +
                          "\"\nvoid main() {\n  uint i = gl_GlobalInvocationID.x;\n"
                          "  if (i >= uint(P.width * P.height)) return;\n  vec4 px = in_px[i];\n" +
                          body + "}\n";
  return hdrc::gpu::testing::run_probe(src, std::move(rc));
}

// The lighting target: every value the GPU stores equals the reference's half, bit for bit, on
// values chosen where rounding decides: exact ties between neighbouring halves (round to even),
// just beside them, half subnormals (below 2^-14) and their ties, the clamp at 65504 (65519.99 and
// 65520 would round to 65504 and Inf), ±Inf and NaN.
TEST(PqGradingShader, Rgba16fStoreIsRoundToNearestEvenWithTheClamp) {
  std::vector<float> v = {0.0f,
                          -0.0f,
                          1.0f,
                          65504.0f,
                          65519.99f,
                          65520.0f,
                          70000.0f,
                          -1e30f,
                          std::numeric_limits<float>::infinity(),
                          -std::numeric_limits<float>::infinity(),
                          std::numeric_limits<float>::quiet_NaN()};
  for (int e = -24; e <= 15; ++e) {
    for (int m : {1, 3, 5, 1023, 1021}) {
      // Between the halves k·2^(e−10) and (k+1)·2^(e−10): the tie and its float neighbours.
      const float tie = std::ldexp(static_cast<float>(m) + 0.5f, e - 10);
      v.push_back(tie);
      v.push_back(std::nextafter(tie, 0.0f));
      v.push_back(std::nextafter(tie, 1e30f));
      v.push_back(-tie);
    }
  }
  Image in(static_cast<int>(v.size()), 1);
  for (size_t k = 0; k < v.size(); ++k) in.px(static_cast<int>(k), 0)[0] = v[k];
  ResolvedCase rc = make_case("shaper", 3, in);
  auto got = run_body("  out_px[i] = vec4(pqg_store_rgba16f(px.r), 0.0, 0.0, 0.0);\n", rc);
  ASSERT_TRUE(got.ok()) << got.error().to_string();
  // A device without shaderRoundingModeRTEFloat16 may round the conversion either way (Vulkan
  // spec, "Precision and Operation of SPIR-V Instructions": float16 conversions use the
  // implementation's rounding mode unless RTE is guaranteed): either neighbour of the clamped
  // value (device_allowance.h half_round_down/up). With RTE (lavapipe, the H200) bit for bit.
  // Whatever the mode, the result is a float16 value: PackHalf2x16 (GLSL.std.450) converts to the
  // 16-bit representation, as an RGBA16F image store must ("Texel Output Format Conversion").
  // A GPU that hands back the float32 value (the H200 for values below half's range) skipped the
  // conversion: a device (compiler) defect, reported here and not admitted.
  const hdrc::DevicePrecision& device = hdrc::gpu::testing::test_device().precision;
  const bool either_way = !hdrc::gpu::testing::exact_device() && !device.fp16_rte;
  int failures = 0, not_half = 0;
  for (size_t k = 0; k < v.size(); ++k) {
    const double want = pqg::store_rgba16f(v[k]);
    const double have = got->px(static_cast<int>(k), 0)[0];
    bool same = std::isnan(want) ? std::isnan(have) : have == want;
    if (!same && either_way && !std::isnan(want)) {
      const double clamped = std::clamp(static_cast<double>(v[k]), -pqg::kHalfMax, pqg::kHalfMax);
      same =
          have == hdrc::ref::half_round_down(clamped) || have == hdrc::ref::half_round_up(clamped);
    }
    const bool is_half =
        std::isnan(have) || std::isinf(have) ||
        (hdrc::ref::half_round_down(have) == have && std::fabs(have) <= pqg::kHalfMax);
    if (!same && !is_half) ++not_half;
    if (!same && failures++ < 10)
      ADD_FAILURE() << "store of " << v[k] << ": GPU " << have << ", reference " << want
                    << (is_half ? ""
                                : " (not a float16 value: the device skipped the conversion "
                                  "PackHalf2x16 requires, a device defect)");
  }
  EXPECT_EQ(failures, 0)
      << failures << " of " << v.size() << " stores differ on "
      << hdrc::gpu::testing::test_device().device << ": " << not_half
      << " are no float16 value at all (unpackHalf2x16(packHalf2x16(v)) gave back the float32 v: "
         "the device skipped the conversion GLSL.std.450 PackHalf2x16 requires, as an RGBA16F "
         "store must, a device (compiler) defect, not admitted by any device allowance; "
         "docs/precision.md, \"The GPU tests' bounds on a device that is not float32-exact\"), "
      << failures - not_half << " are a float16 value other than "
      << (either_way ? "either neighbour of the clamped value (float16 rounding either way)"
                     : "the reference's round-to-nearest-even half");
}

// The LUT lookup (domain, then the two-tap strip sampling) of pq_hue_33 and pq_domain_33 over a
// 21³ grid of PQ inputs plus off-lattice points: the GPU's hardware weights differ from the
// exact ones by at most 2^-8 each (two bilinear axes; the slice lerp is computed in float32), so
// |GPU − reference| ≤ 2 · 2^-8 · (the largest difference of neighbouring texels) + float32
// rounding. The largest error measured is printed for docs/precision.md.
TEST(PqGradingShader, StripSamplingIsTheReferenceWithinTheSamplersWeightPrecision) {
  for (const char* file : {"pq_hue_33.cube", "pq_domain_33.cube", "pq_look_33.cube"}) {
    auto cube =
        hdrc::cube::read_cube_file(std::string(HDRC_SOURCE_DIR) + "/cases/lut/cube/" + file);
    ASSERT_TRUE(cube.ok()) << file;
    auto lut = std::make_shared<hdrc::UserLut>();
    lut->size = cube->size_3d;
    lut->domain_min = cube->domain_min_3d;
    lut->domain_max = cube->domain_max_3d;
    lut->table = cube->table_3d;
    const int n = lut->size;
    double step = 0;  // the largest difference of neighbouring texels, any axis and channel
    for (int b = 0; b < n; ++b)
      for (int g = 0; g < n; ++g)
        for (int r = 0; r < n; ++r)
          for (int c = 0; c < 3; ++c) {
            const double t = lut->table[r + n * (g + n * b)][c];
            if (r + 1 < n)
              step = std::fmax(step, std::fabs(lut->table[r + 1 + n * (g + n * b)][c] - t));
            if (g + 1 < n)
              step = std::fmax(step, std::fabs(lut->table[r + n * (g + 1 + n * b)][c] - t));
            if (b + 1 < n)
              step = std::fmax(step, std::fabs(lut->table[r + n * (g + n * (b + 1))][c] - t));
          }
    const int k = 21;
    Image in(k * k * k + 4, 1);
    for (int b = 0; b < k; ++b)
      for (int g = 0; g < k; ++g)
        for (int r = 0; r < k; ++r) {
          double* px = in.px(r + k * (g + k * b), 0);
          px[0] = static_cast<float>(r / (k - 1.0));
          px[1] = static_cast<float>(g / (k - 1.0) * 0.999);
          px[2] = static_cast<float>(b / (k - 1.0) * 0.997 + 0.001);
        }
    const double extra[4][3] = {
        {-0.1, 0.5, 1.2}, {0.03, 0.97, 0.51}, {0.333, 0.666, 0.999}, {0.0001, 0.0002, 0.0003}};
    for (int e = 0; e < 4; ++e)
      for (int c = 0; c < 3; ++c) in.px(k * k * k + e, 0)[c] = static_cast<float>(extra[e][c]);
    ResolvedCase rc = make_case("shaper", 3, in);
    rc.spec.lut = lut;
    rc.user_luts[0] = hdrc::user_lut_strip(*lut);
    rc.params.user_lut_size = n;
    for (int c = 0; c < 3; ++c) {
      rc.params.user_lut_domain_min[c] = lut->domain_min[c];
      rc.params.user_lut_domain_max[c] = lut->domain_max[c];
    }
    auto got = run_body("  out_px[i] = vec4(pqg_lookup(px.rgb), 0.0);\n", rc);
    ASSERT_TRUE(got.ok()) << got.error().to_string();
    const pqg::StripLut ref = pqg::strip_lut(rc.user_luts[0], rc.params);
    const double bound = 2.0 * std::ldexp(step, -8) + 1e-6;
    double worst = 0;
    int failures = 0;
    for (int p = 0; p < in.width; ++p) {
      const double* x = in.px(p, 0);
      const Vec3 want = pqg::lookup(ref, {x[0], x[1], x[2]}, pqg::LutEval::kStrip);
      for (int c = 0; c < 3; ++c) {
        const double err = std::fabs(got->px(p, 0)[c] - want[c]);
        worst = std::fmax(worst, err);
        if (!(err <= bound) && failures++ < 5)
          ADD_FAILURE() << file << " at (" << x[0] << ", " << x[1] << ", " << x[2] << ") channel "
                        << c << ": GPU " << got->px(p, 0)[c] << ", reference " << want[c]
                        << ", bound " << bound;
      }
    }
    std::printf("%s: largest texel step %.4g, |GPU - reference| max %.3g (bound %.3g)\n", file,
                step, worst, bound);
    RecordProperty(std::string(file) + "_max_error", std::to_string(worst));
  }
}

}  // namespace
