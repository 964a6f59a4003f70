// The Vulkan engine on lavapipe: device selection, the shared interface read back from the GPU,
// agreement with the reference, the multi-pass machinery (LUT images in every format and layout,
// scratch, aux images, dispatch domains), validation and recovery from a timeout.
#include "gpu/vulkan_engine.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <thread>

#include "core/shader_interface.h"
#include "gpu/device_bounds_test.h"
#include "gpu/shader_constants.h"
#include "reference/reference_engine.h"
#include "reference/ue/combine_luts.h"
#include "reference/ue/cpp/resolve.h"
#include "reference/ue/ue55/ue55_pipeline.h"

namespace fs = std::filesystem;

namespace {

hdrc::ResolvedCase make_case(const char* stage, int device, int gamut, hdrc::Image input) {
  hdrc::ResolvedCase rc;
  rc.spec.id = "test";
  rc.spec.stage = hdrc::find_stage(stage);
  rc.spec.cvars.set("r.HDR.Display.OutputDevice", device);
  rc.spec.cvars.set("r.HDR.Display.ColorGamut", gamut);
  rc.params = *hdrc::ref::resolve_params(rc.spec, input.width, input.height);
  rc.input = std::move(input);
  return rc;
}

TEST(VulkanEngine, SelectsLavapipeByDefault) {
  HDRC_SKIP_IF(hdrc::gpu::testing::not_lavapipe_reason(
      "HDRC_VK_DEVICE chose the default device, not the engine"));
  hdrc::gpu::VulkanEngine engine({});
  hdrc::Status st = engine.init();
  ASSERT_TRUE(st.ok()) << st.error().to_string();
  EXPECT_NE(engine.device().device.find("llvmpipe"), std::string::npos);
  EXPECT_FALSE(engine.device().driver.empty());
  EXPECT_FALSE(engine.device().api_version.empty());
}

TEST(VulkanEngine, UnknownDeviceIsUnavailableWithChoices) {
  hdrc::gpu::VulkanOptions o;
  o.device = "no-such-gpu";
  hdrc::gpu::VulkanEngine engine(o);
  hdrc::Status st = engine.init();
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().to_string().find("no Vulkan device matches"), std::string::npos);
  // The choices: the device the tests run on among them (llvmpipe on lavapipe).
  const std::string& here = hdrc::gpu::testing::test_device().device;
  ASSERT_FALSE(here.empty());
  EXPECT_NE(st.error().to_string().find(here), std::string::npos) << st.error().to_string();
  o.device = "99";
  hdrc::gpu::VulkanEngine by_index(o);
  EXPECT_FALSE(by_index.init().ok());
}

// Every constant shared with the reference reaches the shader as float(reference value), and
// every parameter-block field is read at the offset the host writes it: a probe shader (put in a
// shader directory in place of the "shaper" stage) copies them to the output.
TEST(VulkanEngine, SharedConstantsAndParamBlockReadBack) {
  const auto& constants = hdrc::gpu::shared_constants();
  const fs::path dir = fs::temp_directory_path() / ("hdrc_probe_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "stages");
  {
    std::ofstream f(dir / "stages/shaper.comp");
    f << "#version 450\n#extension GL_GOOGLE_include_directive : require\n#include "
         "\"hdrc/interface.glsl\"\n"
         "layout(local_size_x = HDRC_LOCAL_SIZE_X) in;\nvoid main() {\n"
         "  if (gl_GlobalInvocationID.x != 0u) return;\n";
    for (size_t i = 0; i < constants.size(); ++i)
      f << "  out_px[" << i << "] = vec4(" << constants[i].name << ", 0.0, 0.0, 0.0);\n";
    const size_t k = constants.size();
    f << "  out_px[" << k
      << "] = vec4(float(P.width), float(P.height), float(P.output_device), "
         "float(P.output_gamut));\n";
    for (int r = 0; r < 3; ++r) {
      f << "  out_px[" << k + 1 + r << "] = P.wcs_to_ap1[" << r << "];\n";
      f << "  out_px[" << k + 4 + r << "] = P.ap1_to_output[" << r << "];\n";
    }
    // A table field (V4A): its last element and one read at a dynamic index.
    f << "  out_px[" << k + 7 << "] = P.ue58_cusp_table[361];\n";
    f << "  out_px[" << k + 8 << "] = P.ue58_gamma_table[P.width % 91];\n";
    f << "}\n";
  }
  hdrc::gpu::VulkanOptions o;
  o.shader_dir = dir.string();
  hdrc::gpu::VulkanEngine engine(o);
  ASSERT_TRUE(engine.init().ok());
  hdrc::Image input(static_cast<int>(constants.size()) + 9, 1);
  auto rc = make_case("shaper", 7, 2, input);
  rc.params.ue58_cusp_table[361] = {1.0 / 3.0, -2.5, 361.25, 0.0};
  const size_t dynamic = static_cast<size_t>(rc.params.width % 91);
  rc.params.ue58_gamma_table[dynamic] = {0.1, 0.2, 0.3, 0.4};
  auto out = engine.run(rc);
  ASSERT_TRUE(out.ok()) << out.error().to_string();
  for (size_t i = 0; i < constants.size(); ++i) {
    EXPECT_EQ(static_cast<float>(out->data[i * 4]), static_cast<float>(constants[i].value))
        << constants[i].name;
  }
  const size_t k = constants.size();
  EXPECT_EQ(out->data[k * 4 + 0], rc.params.width);
  EXPECT_EQ(out->data[k * 4 + 1], 1);
  EXPECT_EQ(out->data[k * 4 + 2], 7);
  EXPECT_EQ(out->data[k * 4 + 3], 2);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(out->data[(k + 1 + r) * 4 + c], static_cast<float>(rc.params.wcs_to_ap1(r, c)));
      EXPECT_EQ(out->data[(k + 4 + r) * 4 + c], static_cast<float>(rc.params.ap1_to_output(r, c)));
    }
  for (int c = 0; c < 4; ++c) {
    EXPECT_EQ(out->data[(k + 7) * 4 + c], static_cast<float>(rc.params.ue58_cusp_table[361][c]));
    EXPECT_EQ(out->data[(k + 8) * 4 + c],
              static_cast<float>(rc.params.ue58_gamma_table[dynamic][c]));
  }
  fs::remove_all(dir);
}

// One pipeline per stage shader, however many cases run.
TEST(VulkanEngine, PipelinesAreCachedAcrossCases) {
  hdrc::gpu::VulkanEngine engine({});
  ASSERT_TRUE(engine.init().ok());
  hdrc::Image input(16, 1);
  for (int device : {7, 8, 7, 8})
    ASSERT_TRUE(engine.run(make_case("linear_device", device, 1, input)).ok());
  ASSERT_TRUE(engine.run(make_case("shaper", 0, 0, input)).ok());
  EXPECT_EQ(engine.compiled_pipeline_count(), 2);
}

TEST(VulkanEngine, AgreesWithReferenceOnARamp) {
  hdrc::Image input(512, 1);
  for (int x = 0; x < 512; ++x) {
    const double v = static_cast<float>(std::pow(10.0, -6.0 + 8.0 * x / 511.0));
    double* p = input.px(x, 0);
    p[0] = v;
    p[1] = v * 0.5;
    p[2] = v * 0.25;
    p[3] = 1;
  }
  hdrc::gpu::VulkanEngine gpu({});
  ASSERT_TRUE(gpu.init().ok());
  hdrc::ref::ReferenceEngine ref;
  // The tolerances of cases/tonemap/shaper_log.json and shaper_pq.json (measured on lavapipe).
  struct Bound {
    int device;
    double rel, floor;
  };
  for (const Bound b : {Bound{0, 5e-6, 1e-3}, Bound{3, 2.5e-4, 1e-4}}) {
    auto rc = make_case("shaper", b.device, 0, input);
    auto want = ref.run(rc);
    auto got = gpu.run(rc);
    ASSERT_TRUE(got.ok());
    for (size_t i = 0; i < want->data.size(); ++i)
      EXPECT_NEAR(got->data[i], want->data[i], b.rel * std::fmax(std::fabs(want->data[i]), b.floor))
          << "device " << b.device << " value " << i;
  }
}

}  // namespace

namespace {

using hdrc::gpu::VulkanEngine;
using hdrc::gpu::VulkanOptions;
using ref_interval = hdrc::ref::spirv::Interval;

// A temporary shader directory (a copy of the suite's, or empty), removed on destruction.
class TempShaderDir {
 public:
  TempShaderDir(const std::string& tag, bool copy_suite) {
    dir_ = fs::temp_directory_path() / ("hdrc_vk_" + tag + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    if (copy_suite) fs::copy(hdrc::gpu::default_shader_dir(), dir_, fs::copy_options::recursive);
    fs::create_directories(dir_ / "stages");
  }
  ~TempShaderDir() { fs::remove_all(dir_); }
  void write(const std::string& relative, const std::string& body) const {
    std::ofstream(dir_ / relative, std::ios::trunc)
        << "#version 450\n#extension GL_GOOGLE_include_directive : require\n"
           "#include \"hdrc/interface.glsl\"\nlayout(local_size_x = HDRC_LOCAL_SIZE_X) in;\n"
        << body;
  }
  void remove(const std::string& relative) const { fs::remove(dir_ / relative); }
  std::string path() const { return dir_.string(); }

 private:
  fs::path dir_;
};

hdrc::ResolvedCase lut_case(const char* stage, int size, int format, int layout,
                            hdrc::Image input = hdrc::Image(1, 1)) {
  hdrc::ResolvedCase rc;
  rc.spec.id = "test";
  rc.spec.stage = hdrc::find_stage(stage);
  rc.spec.cvars.set("r.HDR.EnableHDROutput", 1);
  rc.spec.cvars.set("r.HDR.Display.OutputDevice", 3);
  rc.spec.cvars.set("r.HDR.Display.ColorGamut", 2);
  rc.spec.cvars.set("r.LUT.Size", size);
  rc.spec.settings.set("LUTFormat", {static_cast<double>(format), 0, 0, 0}, 1);
  rc.spec.settings.set("LUTLayout", {static_cast<double>(layout), 0, 0, 0}, 1);
  EXPECT_EQ(rc.spec.cvars.get_int("r.LUT.Size"), size) << "r.LUT.Size is 16-64";
  if (std::string(stage) == "combine_luts") input = hdrc::Image(size * size, size);
  rc.params = *hdrc::ref::resolve_params(rc.spec, input.width, input.height);
  rc.input = std::move(input);
  return rc;
}

// The test pattern a probe CombineLUTs pass writes at texel index i = r + N(g + N b), channel c:
// values each storage format holds exactly (or, for 10-bit UNORM, a quarter code above k/1023, so
// that round-to-nearest and round-toward-zero agree), so the read back is exact.
const char* kPatternGlsl = R"(
int pattern_k(int i, int c) { return (i * 7 + c * 101) % (c == 3 ? 4 : 1024); }
vec4 pattern(int i) {
  vec4 v;
  for (int c = 0; c < 4; ++c) {
    int k = pattern_k(i, c);
    if (P.lut_format == 0) v[c] = (float(k) + 0.25) / (c == 3 ? 3.0 : 1023.0);
    else if (P.lut_format == 1) v[c] = float(k - 512) / 64.0;
    else v[c] = float(k - 512) / 3.0;
  }
  return v;
}
)";

double pattern_expected(int format, int i, int c) {
  const int k = (i * 7 + c * 101) % (c == 3 ? 4 : 1024);
  if (format == 0) return k / (c == 3 ? 3.0 : 1023.0);
  if (format == 1) return (k - 512) / 64.0;
  return static_cast<float>((k - 512) / 3.0f);
}

// What a device may read back for pattern_expected: the value itself on a float32-exact device;
// elsewhere the shader's division within OpFDiv's 2.5 ULP ("Precision and Operation of SPIR-V
// Instructions"; the numerator and the divisor are exact floats), then the store's either
// neighbour ("Fixed-Point Data Conversions", the float16 rounding mode). A 10-bit code may then
// be k or k + 1: the quarter code above k/1023 decides only for round to nearest or toward zero.
ref_interval pattern_on_device(int format, int i, int c) {
  if (hdrc::gpu::testing::exact_device())
    return ref_interval::point(pattern_expected(format, i, c));
  const int k = (i * 7 + c * 101) % (c == 3 ? 4 : 1024);
  const double levels = c == 3 ? 3.0 : 1023.0;
  const float num = format == 0 ? static_cast<float>(k) + 0.25f : static_cast<float>(k - 512);
  const float den = format == 0 ? static_cast<float>(levels) : format == 1 ? 64.0f : 3.0f;
  return hdrc::gpu::testing::stored_on_device(
      hdrc::gpu::testing::quotient_on_device(num, den, false), format, levels);
}

const char* kProbeBake = R"(
void main() {
  int n = P.lut_size;
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(n * n * n)) return;
  ivec3 t = ivec3(int(i) % n, (int(i) / n) % n, int(i) / (n * n));
  if (P.lut_layout == 0) imageStore(lut_store_3d, t, pattern(int(i)));
  else imageStore(lut_store_2d, ivec2(t.r + n * t.b, t.g), pattern(int(i)));
}
)";

TEST(VulkanEngine, HalfDecoderIsExact) {
  using hdrc::gpu::decode_half;
  EXPECT_EQ(decode_half(0x0000), 0.0f);
  EXPECT_TRUE(std::signbit(decode_half(0x8000)));
  EXPECT_EQ(decode_half(0x3c00), 1.0f);
  EXPECT_EQ(decode_half(0xc000), -2.0f);
  EXPECT_EQ(decode_half(0x3555), 0.333251953125f);          // nearest half to 1/3
  EXPECT_EQ(decode_half(0x7bff), 65504.0f);                 // largest finite half
  EXPECT_EQ(decode_half(0x0400), 6.103515625e-05f);         // smallest normal, 2^-14
  EXPECT_EQ(decode_half(0x0001), 5.9604644775390625e-08f);  // smallest subnormal, 2^-24
  EXPECT_EQ(decode_half(0x03ff), 6.097555160522461e-05f);   // largest subnormal, 1023 · 2^-24
  EXPECT_EQ(decode_half(0x7c00), std::numeric_limits<float>::infinity());
  EXPECT_EQ(decode_half(0xfc00), -std::numeric_limits<float>::infinity());
  EXPECT_TRUE(std::isnan(decode_half(0x7e00)));
  EXPECT_TRUE(std::isnan(decode_half(0x7c01)));
  // Every positive finite half is larger than the one before, by the ulp of its binade.
  for (uint32_t h = 1; h < 0x7c00; ++h) {
    const float a = decode_half(static_cast<uint16_t>(h - 1)),
                b = decode_half(static_cast<uint16_t>(h));
    const int e = std::max(static_cast<int>((h - 1) >> 10), 1);  // the binade of h - 1
    ASSERT_EQ(b - a, std::ldexp(1.0f, e - 25)) << h;
    ASSERT_EQ(decode_half(static_cast<uint16_t>(h | 0x8000)), -b) << h;
  }
}

TEST(VulkanEngine, A2B10G10R10DecoderIsExact) {
  // R in the low bits, A in the top two (Vulkan: VK_FORMAT_A2B10G10R10_UNORM_PACK32).
  const uint32_t texel = (2u << 30) | (1023u << 20) | (512u << 10) | 1u;
  const auto v = hdrc::gpu::decode_a2b10g10r10(texel);
  EXPECT_EQ(v[0], 1.0 / 1023.0);
  EXPECT_EQ(v[1], 512.0 / 1023.0);
  EXPECT_EQ(v[2], 1.0);
  EXPECT_EQ(v[3], 2.0 / 3.0);
}

// The LUT image in each storage format and layout: what the bake pass stores at texel (r, g, b)
// comes back at (r + N b, g) of the N² × N result, decoded exactly.
TEST(VulkanEngine, LutReadBackEveryFormatAndLayout) {
  TempShaderDir dir("lut", false);
  dir.write("stages/combine_luts.comp", std::string(kPatternGlsl) + kProbeBake);
  VulkanOptions o;
  o.shader_dir = dir.path();
  VulkanEngine engine(o);
  ASSERT_TRUE(engine.init().ok());
  for (int format : {0, 1, 2})
    for (int layout : {0, 1})
      for (int n : {16, 17, 33}) {
        auto out = engine.run(lut_case("combine_luts", n, format, layout));
        ASSERT_TRUE(out.ok()) << out.error().to_string();
        ASSERT_EQ(out->width, n * n);
        ASSERT_EQ(out->height, n);
        int wrong = 0;
        for (int b = 0; b < n; ++b)
          for (int g = 0; g < n; ++g)
            for (int r = 0; r < n; ++r) {
              const int i = r + n * (g + n * b);
              for (int c = 0; c < 4; ++c) {
                const double got = out->px(r + n * b, g)[c];
                const auto admitted = pattern_on_device(format, i, c);
                if (!admitted.contains(got) && wrong++ < 5)
                  ADD_FAILURE() << "format " << format << " layout " << layout << " N " << n
                                << " texel (" << r << "," << g << "," << b << ") channel " << c
                                << ": " << got << " != " << pattern_expected(format, i, c)
                                << " (admitted [" << admitted.lo << ", " << admitted.hi << "])";
              }
            }
        EXPECT_EQ(wrong, 0);
      }
  // One pipeline whatever the case's parameters, and the engine's store pass.
  EXPECT_EQ(engine.compiled_pipeline_count(), 2);
}

// A four-pass stage (visualize_hdr's pass list, with probe shaders): the LUT baked by pass 1 is
// sampled (3-D and 2-D) by the later passes; pass 2 writes its image to scratch; pass 3 runs as
// one workgroup and writes the free part of scratch; pass 4 combines them into the output.
TEST(VulkanEngine, PassesScratchAndOneGroup) {
  TempShaderDir dir("passes", false);
  dir.write("stages/combine_luts.comp", std::string(kPatternGlsl) + kProbeBake);
  dir.write("stages/tonemap.comp", R"(
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  out_px[i] = in_px[i] * 2.0;
}
)");
  dir.write("stages/visualize_histogram.comp", R"(
void main() {
  uint base = uint(P.width * P.height);
  scratch_px[base + gl_LocalInvocationIndex] = vec4(float(gl_WorkGroupID.x) * 1000.0 +
                                                    float(gl_LocalInvocationIndex));
}
)");
  // The LUT sampled at texel centres (weights 1 and 0: the stored value) of texel (1, 0, 1).
  dir.write("stages/visualize_hdr.comp", R"(
void main() {
  uint i = gl_GlobalInvocationID.x;
  uint count = uint(P.width * P.height);
  if (i >= count) return;
  int n = P.lut_size;
  vec4 lut;
  if (P.lut_layout == 0) lut = texture(lut_3d, (vec3(1.0, 0.0, 1.0) + 0.5) / float(n));
  else lut = texture(lut_2d, (vec2(1.0 + float(n), 0.0) + 0.5) / vec2(n * n, n));
  out_px[i] = vec4(scratch_px[i].r, scratch_px[count + i % 64u].r, lut.r, lut.a);
}
)");
  VulkanOptions o;
  o.shader_dir = dir.path();
  VulkanEngine engine(o);
  ASSERT_TRUE(engine.init().ok());
  hdrc::Image input(300, 1);
  for (int x = 0; x < 300; ++x) input.px(x, 0)[0] = x;
  for (int format : {0, 1, 2})
    for (int layout : {0, 1}) {
      auto out = engine.run(lut_case("visualize_hdr", 16, format, layout, input));
      ASSERT_TRUE(out.ok()) << out.error().to_string();
      const int texel = 1 + 16 * (0 + 16 * 1);
      // Sampled: the stored value converted to float32 by the texture unit. Elsewhere than on a
      // float32-exact device the coordinate (1.5 / 16: an OpFDiv, 2.5 ULP) lands a few 2^-24
      // texels off the centre, and the sampler's weight keeps subTexelPrecisionBits fraction bits
      // ("Texel Filtering"; device_allowance.h linear_tap_box): up to 2^-bits of each axis's
      // neighbour (r ± 1, g + 1, and b ± 1 in the volume) may blend in.
      auto sampled = [&](int c) {
        if (hdrc::gpu::testing::exact_device())
          return ref_interval::point(static_cast<float>(pattern_expected(format, texel, c)));
        const ref_interval centre = pattern_on_device(format, texel, c);
        const double w = hdrc::gpu::testing::weight_precision(
            hdrc::gpu::testing::test_device().precision.sub_texel_bits);
        double spread = 0;
        for (int step : {1, 16, 256}) {
          if (step == 256 && layout == 1) continue;  // the strip's slices are not filtered
          double axis = 0;
          for (int nb : {texel - step, texel + step}) {
            if (step == 16 && nb < texel) continue;  // g = 0: clamped to the texel itself
            const ref_interval v = pattern_on_device(format, nb, c);
            axis = std::max({axis, std::fabs(v.hi - centre.lo), std::fabs(centre.hi - v.lo)});
          }
          spread += w * axis;
        }
        return ref_interval{centre.lo - spread, centre.hi + spread};
      };
      const ref_interval red = sampled(0), alpha = sampled(3);
      for (int x = 0; x < 300; ++x) {
        ASSERT_EQ(out->px(x, 0)[0], 2.0 * x) << "scratch image, pixel " << x;
        ASSERT_EQ(out->px(x, 0)[1], x % 64) << "one workgroup wrote scratch[W*H + i]";
        ASSERT_TRUE(red.contains(out->px(x, 0)[2]))
            << format << layout << ": " << out->px(x, 0)[2] << " outside [" << red.lo << ", "
            << red.hi << "]";
        ASSERT_TRUE(alpha.contains(out->px(x, 0)[3]))
            << format << layout << ": " << out->px(x, 0)[3] << " outside [" << alpha.lo << ", "
            << alpha.hi << "]";
      }
    }
}

// Bloom goes to aux0 and the dirt mask to aux1 (tonemap), the UI layer to aux0 (ui_composite),
// with their sizes in the parameter block; unbound aux images are 0 × 0.
TEST(VulkanEngine, AuxImagesAndTheirSizes) {
  TempShaderDir dir("aux", false);
  dir.write("stages/combine_luts.comp", "void main() {}\n");
  const char* body = R"(
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  if (i == 0u) { out_px[0] = vec4(P.aux0_width, P.aux0_height, P.aux1_width, P.aux1_height); return; }
  float a0 = P.aux0_width > 0 ? aux0_px[min(i, uint(P.aux0_width * P.aux0_height) - 1u)].g : -1.0;
  float a1 = P.aux1_width > 0 ? aux1_px[min(i, uint(P.aux1_width * P.aux1_height) - 1u)].b : -1.0;
  out_px[i] = vec4(a0, a1, 0.0, 0.0);
}
)";
  dir.write("stages/tonemap.comp", body);
  dir.write("stages/ui_composite.comp", body);
  VulkanOptions o;
  o.shader_dir = dir.path();
  VulkanEngine engine(o);
  ASSERT_TRUE(engine.init().ok());
  auto rc = lut_case("tonemap", 16, 0, 0, hdrc::Image(8, 2));
  rc.bloom = hdrc::Image(4, 3);
  rc.bloom_dirt = hdrc::Image(5, 1);
  for (size_t i = 0; i < rc.bloom.pixel_count(); ++i) rc.bloom.data[i * 4 + 1] = 10.0 + i;
  for (size_t i = 0; i < rc.bloom_dirt.pixel_count(); ++i) rc.bloom_dirt.data[i * 4 + 2] = 20.0 + i;
  auto out = engine.run(rc);
  ASSERT_TRUE(out.ok()) << out.error().to_string();
  EXPECT_EQ(out->data[0], 4);
  EXPECT_EQ(out->data[1], 3);
  EXPECT_EQ(out->data[2], 5);
  EXPECT_EQ(out->data[3], 1);
  for (size_t i = 1; i < 16; ++i) {
    EXPECT_EQ(out->data[i * 4 + 0], 10.0 + std::min<size_t>(i, 11)) << i;
    EXPECT_EQ(out->data[i * 4 + 1], 20.0 + std::min<size_t>(i, 4)) << i;
  }
  rc.bloom = {};
  rc.bloom_dirt = {};
  out = engine.run(rc);
  ASSERT_TRUE(out.ok()) << out.error().to_string();
  EXPECT_EQ(out->data[0] + out->data[1] + out->data[2] + out->data[3], 0);
  EXPECT_EQ(out->data[4], -1.0);

  auto ui = lut_case("ui_composite", 16, 0, 0, hdrc::Image(8, 2));
  ui.ui = hdrc::Image(8, 2);
  for (size_t i = 0; i < ui.ui.pixel_count(); ++i) ui.ui.data[i * 4 + 1] = 30.0 + i;
  out = engine.run(ui);
  ASSERT_TRUE(out.ok()) << out.error().to_string();
  EXPECT_EQ(out->data[0], 8);
  EXPECT_EQ(out->data[1], 2);
  EXPECT_EQ(out->data[2], 0);
  EXPECT_EQ(out->data[5 * 4], 35.0);
}

// A stage whose pass shaders are not all there fails per case, naming the missing file.
TEST(VulkanEngine, MissingPassShaderIsACaseErrorNamingTheFile) {
  TempShaderDir dir("missing", true);
  dir.remove("stages/tonemap.comp");
  VulkanOptions o;
  o.shader_dir = dir.path();
  VulkanEngine engine(o);
  ASSERT_TRUE(engine.init().ok());
  auto out = engine.run(lut_case("tonemap", 16, 0, 0, hdrc::Image(4, 4)));
  ASSERT_FALSE(out.ok());
  EXPECT_NE(out.error().message.find("missing stages/tonemap.comp"), std::string::npos)
      << out.error().message;
  EXPECT_NE(out.error().message.find(dir.path()), std::string::npos);
  // The engine still runs the stages that are there.
  EXPECT_TRUE(engine.run(make_case("shaper", 3, 0, hdrc::Image(4, 4))).ok());
}

// Validation on: every stage whose shaders exist runs with zero messages, in every LUT format and
// layout; a shader that breaks the interface is reported as the case's error.
TEST(VulkanEngine, ValidationLayerIsClean) {
  HDRC_SKIP_IF(hdrc::gpu::testing::no_validation_layer_reason());
  VulkanOptions o;
  o.validation = true;
  o.fence_timeout_s = 20;  // a stage that hangs fails here instead of stalling the suite
  VulkanEngine engine(o);
  const hdrc::Status st = engine.init();
  ASSERT_TRUE(st.ok()) << st.error().to_string();
  hdrc::Image ramp(64, 4);
  for (size_t i = 0; i < ramp.pixel_count(); ++i)
    for (int c = 0; c < 4; ++c) ramp.data[i * 4 + c] = std::pow(10.0, -4.0 + 6.0 * i / 256.0);
  int ran = 0;
  std::string stages;
  for (const auto& stage : hdrc::ref::ue55_stage_table()) {
    if (!hdrc::missing_shaders(stage, hdrc::gpu::default_shader_dir()).empty()) continue;
    stages += " " + std::string(stage.name);
    for (int format : {0, 1, 2})
      for (int layout : {0, 1}) {
        auto rc = lut_case(std::string(stage.name).c_str(), 17, format, layout, ramp);
        if (stage.id == hdrc::StageId::kUiComposite) rc.ui = ramp;
        if (stage.id == hdrc::StageId::kTonemap) {
          rc.bloom = hdrc::Image(16, 1);
          rc.bloom_dirt = hdrc::Image(8, 8);
        }
        auto out = engine.run(rc);
        EXPECT_TRUE(out.ok()) << stage.name << ": " << out.error().to_string();
        ++ran;
        if (stage.passes.size() == 1 && stage.passes[0].domain != hdrc::Dispatch::kLutTexels)
          break;  // the LUT parameters do not matter to this stage
      }
  }
  EXPECT_GE(ran, 2);
  std::printf("validation clean on %d cases of:%s\n", ran, stages.c_str());

  // The multi-pass probe (scratch, one group, both LUT samplers) under validation too.
  TempShaderDir dir("validation", false);
  dir.write("stages/combine_luts.comp", std::string(kPatternGlsl) + kProbeBake);
  dir.write("stages/tonemap.comp",
            "void main() { uint i = gl_GlobalInvocationID.x;\n"
            "  if (i < uint(P.width * P.height)) out_px[i] = texture(lut_3d, vec3(0.5)) +\n"
            "      texture(lut_2d, vec2(0.5)) + aux0_px[0]; }\n");
  dir.write("stages/visualize_histogram.comp",
            "void main() { scratch_px[P.width * P.height + int(gl_LocalInvocationIndex)] = "
            "vec4(1.0); }\n");
  dir.write("stages/visualize_hdr.comp",
            "void main() { uint i = gl_GlobalInvocationID.x;\n"
            "  if (i < uint(P.width * P.height)) out_px[i] = scratch_px[i] + scratch_px[i + 1u]; "
            "}\n");
  // Breaks the interface: a storage buffer at a binding the layout does not have.
  dir.write("stages/shaper.comp",
            "layout(std430, set = 0, binding = 12) buffer Extra { vec4 extra[]; };\n"
            "void main() { out_px[0] = extra[0]; }\n");
  VulkanOptions probe = o;
  probe.shader_dir = dir.path();
  VulkanEngine probed(probe);
  ASSERT_TRUE(probed.init().ok());
  for (int layout : {0, 1}) {
    auto out = probed.run(lut_case("visualize_hdr", 16, 0, layout, ramp));
    EXPECT_TRUE(out.ok()) << out.error().to_string();
  }
  auto bad = probed.run(make_case("shaper", 3, 0, ramp));
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("Vulkan validation reported"), std::string::npos)
      << bad.error().message;
}

// A submission that outlives fence_timeout_s makes that case an ERROR; the engine abandons the
// busy device, makes a new one, runs the next case, and frees the old device once its work ends.
TEST(VulkanEngine, TimeoutIsACaseErrorAndTheNextCaseRuns) {
  // The spin is sized by llvmpipe's loop limit and calibrated on its CPU cores; a GPU finishes
  // the 3 s of lavapipe work inside the 0.5 s fence timeout (the H200: the case ran, no timeout).
  HDRC_SKIP_IF(hdrc::gpu::testing::not_lavapipe_reason(
      "the spin is sized for llvmpipe's loop limit and its CPU speed"));
  TempShaderDir dir("timeout", true);
  // Each invocation spins through in_px[i].r steps of a dependent chain the compiler cannot
  // shorten (sin, fract). llvmpipe ends a loop after 65 535 iterations in all (gallivm's
  // LP_MAX_TGSI_LOOP_ITERATIONS), so the work is spread over many invocations instead.
  dir.write("stages/linear_device.comp", R"(
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  int count = int(in_px[i].r);
  float acc = 0.5 + float(i) * 1e-4;
  for (int k = 0; k < count; ++k) acc = fract(sin(acc + float(k) * 1e-3) * 43758.5453);
  out_px[i] = vec4(acc);
}
)");
  VulkanOptions o;
  o.shader_dir = dir.path();
  // Long enough for a trivial case while the abandoned work still occupies the CPU cores.
  o.fence_timeout_s = 0.5;
  VulkanEngine engine(o);
  ASSERT_TRUE(engine.init().ok());
  EXPECT_EQ(engine.device_generation(), 1);
  // Sized to take about 3 s on this machine: calibrated with 1024 invocations first.
  auto spin_image = [](int height) {
    hdrc::Image img(1024, height);
    for (size_t i = 0; i < img.pixel_count(); ++i) img.data[i * 4] = 60000;
    return img;
  };
  double calibration_s = 0;
  {
    VulkanOptions patient = o;
    patient.fence_timeout_s = 60;
    VulkanEngine calibrate(patient);
    ASSERT_TRUE(calibrate.init().ok());
    ASSERT_TRUE(calibrate.run(make_case("linear_device", 8, 0, spin_image(1))).ok());  // compile
    const auto c0 = std::chrono::steady_clock::now();
    ASSERT_TRUE(calibrate.run(make_case("linear_device", 8, 0, spin_image(1))).ok());
    calibration_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - c0).count();
  }
  const int rows = static_cast<int>(std::clamp(std::ceil(3.0 / calibration_s), 8.0, 4096.0));
  const hdrc::Image spin = spin_image(rows);
  const auto t0 = std::chrono::steady_clock::now();
  auto out = engine.run(make_case("linear_device", 8, 0, spin));
  ASSERT_FALSE(out.ok());
  EXPECT_NE(out.error().message.find("timed out"), std::string::npos) << out.error().message;
  EXPECT_EQ(engine.device_generation(), 2);
  EXPECT_EQ(engine.abandoned_device_count(), 1);
  // The next case runs on the new device while the old one is still busy.
  hdrc::Image grey(4, 1);
  for (double& v : grey.data) v = 0.18;
  auto next = engine.run(make_case("shaper", 3, 0, grey));
  ASSERT_TRUE(next.ok()) << next.error().to_string();
  EXPECT_NEAR(next->data[0], 0.18, 0.18 * 2.5e-4);  // cases/tonemap/shaper_pq.json's bound
  const double busy_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // Once the spinning shader is done, the abandoned device is freed at the next case.
  for (int i = 0; i < 600 && engine.abandoned_device_count() > 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    ASSERT_TRUE(engine.run(make_case("shaper", 3, 0, grey)).ok());
  }
  EXPECT_EQ(engine.abandoned_device_count(), 0);
  std::printf(
      "timeout test: 1024 x 60000 steps took %.3f s; the spin (%d rows) was abandoned "
      "and the next case done %.3f s after it began\n",
      calibration_s, rows, busy_s);
}

}  // namespace
