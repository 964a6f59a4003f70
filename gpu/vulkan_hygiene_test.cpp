// The Vulkan engine's synchronisation and memory hygiene on lavapipe: the worst-case device
// model's poisoning (DeviceModel::kWorst: what a pass must not read before writing is NaN or a
// garbage pattern, and dispatches with no barrier between them run last to first), the engine
// defects it exposes where lavapipe (serial, zeroed memory) hides them (VulkanOptions::planted),
// and the guards after every storage buffer that make an out-of-bounds store a case ERROR
// (docs/gpu-interface.md, "Poisoning" and "Guards").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>

#include "gpu/device_bounds_test.h"
#include "gpu/engine_test_cases.h"
#include "gpu/shader_probe.h"
#include "gpu/vulkan_engine.h"
#include "reference/ue/cpp/resolve.h"
#include "reference/ue/ue55/ue55_pipeline.h"

namespace {

using hdrc::DeviceModel;
using hdrc::gpu::VulkanEngine;
using hdrc::gpu::VulkanOptions;
using Planted = hdrc::gpu::VulkanOptions::Planted;

hdrc::Image ramp(int w, int h, uint64_t seed) {
  return hdrc::gpu::testing::random_image(w, h, seed, -4.0);
}

hdrc::ResolvedCase make_case(const char* stage, int device, int size, int format, int layout,
                             hdrc::Image input) {
  return hdrc::gpu::testing::lut_stage_case("hygiene", stage, device, size, format, layout,
                                            std::move(input));
}

bool same(const hdrc::Image& a, const hdrc::Image& b) {
  return hdrc::gpu::testing::same_bits(a, b);
}

VulkanOptions options(DeviceModel model, Planted planted = Planted::kNone) {
  VulkanOptions o;
  o.pipeline_cache_path = "none";
  o.device_model = model;
  o.planted = planted;
  return o;
}

hdrc::Image run_one(const VulkanOptions& o, const hdrc::ResolvedCase& c) {
  VulkanEngine engine(o);
  const hdrc::Status st = engine.init();
  EXPECT_TRUE(st.ok()) << st.error().to_string();
  auto out = engine.run(c);
  EXPECT_TRUE(out.ok()) << out.error().to_string();
  return out.ok() ? *out : hdrc::Image{};
}

// The cases the planted defects are shown on: the LUT's own read back (combine_luts) and the
// Tonemap pass that samples it, in a UNORM and a float format, both layouts.
std::vector<hdrc::ResolvedCase> lut_cases() {
  return {make_case("combine_luts", 3, 16, 0, 0, {}), make_case("combine_luts", 0, 17, 2, 1, {}),
          make_case("tonemap", 3, 16, 0, 1, ramp(24, 8, 1)),
          make_case("tonemap", 7, 17, 2, 0, ramp(24, 8, 2))};
}

// (a) The barrier between the bake pass and the engine's store pass left out. lavapipe runs one
// dispatch after the other, as recorded, so the output is that of the correct engine: it hides the
// hazard. Under the worst-case model the two dispatches, no longer ordered, run last to first: the
// store pass copies the poisoned bake image into the LUT, and the output differs.
TEST(Hygiene, MissingBarrierHiddenByLavapipeExposedByTheModel) {
  int cases = 0;
  for (const auto& c : lut_cases()) {
    const std::string what = std::string(c.spec.stage->name) + " format " +
                             std::to_string(c.params.lut_format) + " layout " +
                             std::to_string(c.params.lut_layout);
    const hdrc::Image good = run_one(options(DeviceModel::kNone), c);
    const hdrc::Image planted =
        run_one(options(DeviceModel::kNone, Planted::kNoBarrierBeforeStore), c);
    if (hdrc::gpu::testing::lavapipe_device()) {
      EXPECT_TRUE(same(good, planted)) << "lavapipe hides the missing barrier: " << what;
    }
    const hdrc::Image good_worst = run_one(options(DeviceModel::kWorst), c);
    const hdrc::Image planted_worst =
        run_one(options(DeviceModel::kWorst, Planted::kNoBarrierBeforeStore), c);
    EXPECT_FALSE(same(good_worst, planted_worst)) << "the model exposes it: " << what;
    ++cases;
  }
  EXPECT_EQ(cases, 4);
  // The model's half ran on this device; the "hidden" half is lavapipe's serial execution.
  HDRC_SKIP_IF(hdrc::gpu::testing::not_lavapipe_reason(
      "only lavapipe runs the unbarriered dispatches in order (the model's half passed)"));
}

// The same planted defect under the validation layer: synchronisation validation names the
// hazard (the store pass samples the bake image the bake pass wrote, with no barrier between),
// model or not; the correct engine is clean.
TEST(Hygiene, MissingBarrierIsReportedByValidation) {
  HDRC_SKIP_IF(hdrc::gpu::testing::no_validation_layer_reason());
  VulkanOptions validated = options(DeviceModel::kNone, Planted::kNoBarrierBeforeStore);
  validated.validation = true;
  VulkanEngine engine(validated);
  ASSERT_TRUE(engine.init().ok());
  auto out = engine.run(lut_cases()[2]);
  ASSERT_FALSE(out.ok());
  EXPECT_NE(out.error().message.find("SYNC-HAZARD-READ"), std::string::npos) << out.error().message;
  // The same engine without the planted defect is clean (ValidationLayerIsClean covers more).
  validated.planted = Planted::kNone;
  VulkanEngine clean(validated);
  ASSERT_TRUE(clean.init().ok());
  auto ok = clean.run(lut_cases()[2]);
  EXPECT_TRUE(ok.ok()) << ok.error().to_string();
}

// The model's fills and clears are ordered before the passes that write over them (a barrier after
// each: a missing one is a SYNC-HAZARD-WRITE-AFTER-WRITE on the output buffer): every stage of the
// suite under the model and validation, in every LUT format and layout, with aux images, reports
// nothing. The whole suite under both: docs/gpu-interface.md, "Poisoning".
TEST(Hygiene, PoisoningIsCleanUnderValidation) {
  HDRC_SKIP_IF(hdrc::gpu::testing::no_validation_layer_reason());
  VulkanOptions o = options(DeviceModel::kWorst);
  o.validation = true;
  VulkanEngine engine(o);
  const hdrc::Status st = engine.init();
  ASSERT_TRUE(st.ok()) << st.error().to_string();
  int ran = 0;
  for (const auto& stage : hdrc::ref::ue55_stage_table()) {
    if (!hdrc::missing_shaders(stage, hdrc::gpu::default_shader_dir()).empty()) continue;
    for (int format : {0, 1, 2})
      for (int layout : {0, 1}) {
        auto c = make_case(std::string(stage.name).c_str(), 3, 17, format, layout, ramp(40, 3, 8));
        if (stage.id == hdrc::StageId::kUiComposite) c.ui = ramp(40, 3, 9);
        if (stage.id == hdrc::StageId::kTonemap) {
          c.bloom = ramp(10, 2, 10);
          c.bloom_dirt = ramp(4, 4, 11);
        }
        auto out = engine.run(c);
        EXPECT_TRUE(out.ok()) << stage.name << ": " << out.error().to_string();
        ++ran;
      }
  }
  EXPECT_GE(ran, 7 * 6);
}

// (b) The LUT image reused from the case before without being rewritten (the store pass left out
// when format, layout and size are unchanged). Cases that share their grading and differ in the
// image (most of the suite's tonemap cases) then sample the LUT the case before stored, which is
// the right one: the output equals the correct engine's, and the defect stays hidden. Under the
// worst-case model the LUT is poisoned before the (missing) store pass, and the output differs.
TEST(Hygiene, StaleReusedLutHiddenByReuseExposedByTheModel) {
  for (int format : {0, 1, 2}) {
    const hdrc::ResolvedCase first =
        make_case("tonemap", 3, 16, format, format % 2, ramp(20, 6, 3));
    const hdrc::ResolvedCase second =
        make_case("tonemap", 3, 16, format, format % 2, ramp(20, 6, 4));
    ASSERT_FALSE(same(first.input, second.input));
    for (DeviceModel model : {DeviceModel::kNone, DeviceModel::kWorst}) {
      const hdrc::Image alone = run_one(options(model), second);
      VulkanEngine engine(options(model, Planted::kStaleLutOnReuse));
      ASSERT_TRUE(engine.init().ok());
      ASSERT_TRUE(engine.run(first).ok());
      auto reused = engine.run(second);
      ASSERT_TRUE(reused.ok()) << reused.error().to_string();
      EXPECT_EQ(engine.reused_work_count(), 1);
      if (model == DeviceModel::kNone)
        EXPECT_TRUE(same(alone, *reused)) << "the stale LUT is the right one; format " << format;
      else
        EXPECT_FALSE(same(alone, *reused)) << "the poisoned LUT shows; format " << format;
    }
  }
}

// What poisoning does to a stage that relies on memory it did not write: a pass that writes only
// the even pixels leaves 0 in the others on lavapipe (the output is zeroed before the stage, as
// the interface says), NaN under the model; a bake pass that leaves out every other texel leaves 0
// in the LUT on lavapipe, and under the model NaN (float LUT) or the poison's codes (10-bit UNORM:
// 0.71 · 1023 = 726.33, so 726/1023 or 727/1023).
TEST(Hygiene, PoisonReachesWhatAPassLeavesUnwritten) {
  hdrc::gpu::testing::ShaderDirCopy dir("hygiene_poison");
  const std::string preamble =
      "#version 450\n#extension GL_GOOGLE_include_directive : require\n"
      "#include \"hdrc/interface.glsl\"\nlayout(local_size_x = HDRC_LOCAL_SIZE_X) in;\n";
  dir.write("stages/linear_device.comp", preamble + R"(
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height) || i % 2u == 1u) return;
  out_px[i] = vec4(1.0);
}
)");
  dir.write("stages/combine_luts.comp", preamble + R"(
void main() {
  int n = P.lut_size;
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(n * n * n) || i % 2u == 1u) return;
  ivec3 t = ivec3(int(i) % n, (int(i) / n) % n, int(i) / (n * n));
  if (P.lut_layout == 0) imageStore(lut_store_3d, t, vec4(0.25));
  else imageStore(lut_store_2d, ivec2(t.r + n * t.b, t.g), vec4(0.25));
}
)");
  for (DeviceModel model : {DeviceModel::kNone, DeviceModel::kWorst}) {
    VulkanOptions o = options(model);
    o.shader_dir = dir.path();
    const bool worst = model == DeviceModel::kWorst;
    const hdrc::Image px = run_one(o, make_case("linear_device", 8, 16, 0, 0, ramp(10, 3, 5)));
    ASSERT_EQ(px.pixel_count(), 30u);
    for (size_t i = 0; i < 30; ++i)
      for (int c = 0; c < 4; ++c) {
        const double v = px.data[i * 4 + c];
        if (i % 2 == 0)
          ASSERT_EQ(v, 1.0) << i;
        else if (worst)
          ASSERT_TRUE(std::isnan(v)) << i;
        else
          ASSERT_EQ(v, 0.0) << i;
      }
    for (int format : {0, 2})
      for (int layout : {0, 1}) {
        const hdrc::Image lut = run_one(o, make_case("combine_luts", 0, 16, format, layout, {}));
        ASSERT_EQ(lut.width, 256);
        for (int b = 0; b < 16; ++b)
          for (int g = 0; g < 16; ++g)
            for (int r = 0; r < 16; ++r) {
              const double v = lut.px(r + 16 * b, g)[0];
              const bool written = (r + 16 * (g + 16 * b)) % 2 == 0;
              const std::string at = "format " + std::to_string(format) + " layout " +
                                     std::to_string(layout) + " texel " + std::to_string(r) + "," +
                                     std::to_string(g) + "," + std::to_string(b);
              if (written && format == 0)  // 0.25 · 1023 = 255.75: code 256, or (the model's
                                           // stores round toward zero) 255
                ASSERT_EQ(v, (worst ? 255.0 : 256.0) / 1023.0) << at;
              else if (written)
                ASSERT_EQ(v, 0.25) << at;
              else if (!worst)
                ASSERT_EQ(v, 0.0) << at;
              else if (format == 0)
                ASSERT_TRUE(v == 726.0 / 1023.0 || v == 727.0 / 1023.0) << at << ": " << v;
              else
                ASSERT_TRUE(std::isnan(v)) << at << ": " << v;
            }
      }
  }
}

// With correct shaders the model's poisoning changes nothing: a multi-pass stage (a LUT bake,
// a pass to scratch, one workgroup writing scratch's free part, a pass combining them) gives the
// same bits with and without it, in sequence on one engine with reuse.
TEST(Hygiene, PoisoningLeavesCorrectPassesAlone) {
  hdrc::gpu::testing::ShaderDirCopy dir("hygiene_correct");
  const std::string preamble =
      "#version 450\n#extension GL_GOOGLE_include_directive : require\n"
      "#include \"hdrc/interface.glsl\"\nlayout(local_size_x = HDRC_LOCAL_SIZE_X) in;\n";
  dir.write("stages/combine_luts.comp", preamble + R"(
void main() {
  int n = P.lut_size;
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(n * n * n)) return;
  ivec3 t = ivec3(int(i) % n, (int(i) / n) % n, int(i) / (n * n));
  // Values every LUT format holds exactly and no arithmetic of the model's shaders (perturbed
  // division, stores toward zero, fused multiply-adds) moves: the comparison isolates the
  // poisoning.
  vec4 v = vec4(float(i % 2u), 1.0, 0.0, 1.0);
  if (P.lut_layout == 0) imageStore(lut_store_3d, t, v);
  else imageStore(lut_store_2d, ivec2(t.r + n * t.b, t.g), v);
}
)");
  dir.write("stages/tonemap.comp", preamble + R"(
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  ivec3 t = ivec3(int(i) % P.lut_size, 0, 1);
  vec4 lut = P.lut_layout == 0 ? texelFetch(lut_3d, t, 0)
                               : texelFetch(lut_2d, ivec2(t.r + P.lut_size, 0), 0);
  out_px[i] = in_px[i] * 2.0 + lut;
}
)");
  dir.write("stages/visualize_histogram.comp", preamble + R"(
void main() {
  uint base = uint(P.width * P.height);
  scratch_px[base + gl_LocalInvocationIndex] = vec4(float(gl_LocalInvocationIndex));
}
)");
  dir.write("stages/visualize_hdr.comp", preamble + R"(
void main() {
  uint i = gl_GlobalInvocationID.x;
  uint count = uint(P.width * P.height);
  if (i >= count) return;
  out_px[i] = scratch_px[i] + scratch_px[count + i % 64u];
}
)");
  std::vector<hdrc::Image> outputs[2];
  for (DeviceModel model : {DeviceModel::kNone, DeviceModel::kWorst}) {
    VulkanOptions o = options(model);
    o.shader_dir = dir.path();
    VulkanEngine engine(o);
    ASSERT_TRUE(engine.init().ok());
    for (int format : {0, 1, 2})
      for (int layout : {0, 1}) {
        auto out = engine.run(make_case("visualize_hdr", 3, 16 + format, format, layout,
                                        ramp(70 - 10 * format, 3, format)));
        ASSERT_TRUE(out.ok()) << out.error().to_string();
        for (double v : out->data) ASSERT_FALSE(std::isnan(v)) << format << layout;
        outputs[model == DeviceModel::kWorst].push_back(*out);
      }
  }
  for (size_t i = 0; i < outputs[0].size(); ++i)
    EXPECT_TRUE(same(outputs[0][i], outputs[1][i])) << "case " << i;
}

// Out-of-bounds accesses (docs/gpu-interface.md, "Guards"): a store past out_px's data is a case
// ERROR naming the binding and the byte (lavapipe alone would discard it, and the case would pass);
// a read past in_px's data reads the guard's NaN, which shows in the output (lavapipe alone reads
// 0). With the model or without.
TEST(Hygiene, OutOfBoundsStoreIsAnErrorAndReadIsNaN) {
  hdrc::gpu::testing::ShaderDirCopy dir("hygiene_oob");
  const std::string preamble =
      "#version 450\n#extension GL_GOOGLE_include_directive : require\n"
      "#include \"hdrc/interface.glsl\"\nlayout(local_size_x = HDRC_LOCAL_SIZE_X) in;\n";
  // Writes every pixel, and also 64 vec4 past the end (the last 64 invocations).
  dir.write("stages/linear_device.comp", preamble + R"(
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  out_px[i] = in_px[i];
  if (i + 64u >= uint(P.width * P.height)) out_px[i + 64u] = vec4(7.0);
}
)");
  // Reads one pixel ahead: the last invocation reads in_px[W·H], past the data.
  dir.write("stages/shaper.comp", preamble + R"(
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  out_px[i] = in_px[i + 1u];
}
)");
  // The scratch buffer's free part is 1024 vec4: one more is past it.
  dir.write("stages/visualize_histogram.comp", preamble + R"(
void main() {
  if (gl_LocalInvocationIndex == 0u) scratch_px[P.width * P.height + 1024] = vec4(1.0);
}
)");
  dir.write("stages/tonemap.comp", preamble + R"(
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < uint(P.width * P.height)) out_px[i] = in_px[i];
}
)");
  dir.write("stages/visualize_hdr.comp", preamble + R"(
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < uint(P.width * P.height)) out_px[i] = scratch_px[i];
}
)");
  for (DeviceModel model : {DeviceModel::kNone, DeviceModel::kWorst}) {
    VulkanOptions o = options(model);
    o.shader_dir = dir.path();
    VulkanEngine engine(o);
    ASSERT_TRUE(engine.init().ok());
    const hdrc::Image input = ramp(30, 5, 6);  // 150 pixels, 2400 bytes
    auto write = engine.run(make_case("linear_device", 8, 16, 0, 0, input));
    ASSERT_FALSE(write.ok());
    EXPECT_NE(write.error().message.find("out-of-bounds write to out_px (binding 2): byte 2400 (0 "
                                         "past the end of its 2400-byte data)"),
              std::string::npos)
        << write.error().message;
    auto read = engine.run(make_case("shaper", 3, 16, 0, 0, input));
    ASSERT_TRUE(read.ok()) << read.error().to_string();
    for (size_t i = 0; i + 1 < 150; ++i)
      ASSERT_EQ(read->data[i * 4], static_cast<float>(input.data[(i + 1) * 4])) << i;
    for (int c = 0; c < 4; ++c) EXPECT_TRUE(std::isnan(read->data[149 * 4 + c])) << c;
    auto scratch = engine.run(make_case("visualize_hdr", 3, 16, 0, 0, input));
    ASSERT_FALSE(scratch.ok());
    EXPECT_NE(scratch.error().message.find("out-of-bounds write to scratch_px (binding 9): byte " +
                                           std::to_string((150 + 1024) * 16)),
              std::string::npos)
        << scratch.error().message;
    // The engine goes on: the next case's guards are fresh.
    auto after = engine.run(make_case("tonemap", 3, 16, 0, 0, input));
    EXPECT_TRUE(after.ok()) << after.error().to_string();
  }
}

// A store far past the guard (lavapipe discards it: the case would pass on its output alone) is
// what GPU-assisted validation catches: Debian 12's layer instruments the shader on lavapipe and
// reports the access, which makes the case an ERROR (docs/gpu-interface.md, "Guards"). Turned on
// for this engine's instance through the layer's environment variable.
TEST(Hygiene, GpuAssistedValidationCatchesAStoreBeyondTheGuard) {
  HDRC_SKIP_IF(hdrc::gpu::testing::no_validation_layer_reason());
  hdrc::gpu::testing::ShaderDirCopy dir("hygiene_gpuav");
  dir.write("stages/linear_device.comp", R"(#version 450
#extension GL_GOOGLE_include_directive : require
#include "hdrc/interface.glsl"
layout(local_size_x = HDRC_LOCAL_SIZE_X) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(P.width * P.height)) return;
  out_px[i] = in_px[i];
  out_px[i + 100000u] = vec4(1.0);
}
)");
  VulkanOptions o = options(DeviceModel::kNone);
  o.shader_dir = dir.path();
  const hdrc::ResolvedCase c = make_case("linear_device", 8, 16, 0, 0, ramp(30, 5, 7));
  {
    VulkanEngine plain(o);
    ASSERT_TRUE(plain.init().ok());
    auto out = plain.run(c);
    EXPECT_TRUE(out.ok()) << "discarded, past the guard: " << out.error().to_string();
  }
  o.validation = true;
  ASSERT_EQ(setenv("VK_LAYER_ENABLES", "VK_VALIDATION_FEATURE_ENABLE_GPU_ASSISTED_EXT", 1), 0);
  struct Unset {
    ~Unset() { unsetenv("VK_LAYER_ENABLES"); }
  } unset;
  VulkanEngine engine(o);
  const hdrc::Status st = engine.init();
  ASSERT_TRUE(st.ok()) << st.error().to_string();
  auto out = engine.run(c);
  ASSERT_FALSE(out.ok());
  EXPECT_NE(out.error().message.find("access out of bounds"), std::string::npos)
      << out.error().message;
}

}  // namespace
