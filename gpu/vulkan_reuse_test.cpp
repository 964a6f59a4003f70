// The Vulkan engine's reuse across cases (resources kept from case to case, pipelines created once
// per device, the on-disk pipeline cache): the output of a case never depends on the cases run
// before it, and the work really is shared.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>
#include <string>

#include "gpu/device_bounds_test.h"
#include "gpu/engine_test_cases.h"
#include "gpu/shader_probe.h"
#include "gpu/vulkan_engine.h"
#include "reference/ue/cpp/resolve.h"

namespace fs = std::filesystem;

namespace {

hdrc::Image ramp(int w, int h, uint64_t seed) {
  return hdrc::gpu::testing::random_image(w, h, seed, -5.0);
}

hdrc::ResolvedCase make_case(const char* stage, int device, int size, int format, int layout,
                             hdrc::Image input) {
  return hdrc::gpu::testing::lut_stage_case("reuse", stage, device, size, format, layout,
                                            std::move(input));
}

bool same(const hdrc::Image& a, const hdrc::Image& b) {
  return hdrc::gpu::testing::same_bits(a, b);
}

hdrc::gpu::VulkanOptions no_disk_cache() {
  hdrc::gpu::VulkanOptions o;
  o.pipeline_cache_path = "none";
  return o;
}

// Each case alone on a fresh engine against the same cases run in sequence on one engine, big
// before small and with LUT shapes changing: identical to the bit.
TEST(VulkanReuse, OutputDoesNotDependOnTheCasesBefore) {
  const std::vector<hdrc::ResolvedCase> cases = {
      make_case("tonemap", 3, 32, 0, 0, ramp(64, 48, 1)),
      make_case("tonemap", 0, 16, 1, 1, ramp(17, 5, 2)),
      make_case("combine_luts", 5, 16, 2, 0, {}),
      make_case("tonemap", 7, 33, 2, 1, ramp(9, 3, 3)),
      make_case("visualize_hdr", 3, 32, 0, 0, ramp(192, 168, 4)),
      make_case("shaper", 3, 32, 0, 0, ramp(5, 1, 5)),
  };
  hdrc::gpu::VulkanEngine shared(no_disk_cache());
  ASSERT_TRUE(shared.init().ok());
  std::vector<hdrc::Image> in_sequence;
  for (const auto& c : cases) {
    auto out = shared.run(c);
    ASSERT_TRUE(out.ok()) << out.error().to_string();
    in_sequence.push_back(*out);
  }
  EXPECT_EQ(shared.reused_work_count(), static_cast<int>(cases.size()) - 1);
  for (size_t i = 0; i < cases.size(); ++i) {
    hdrc::gpu::VulkanEngine fresh(no_disk_cache());
    ASSERT_TRUE(fresh.init().ok());
    auto alone = fresh.run(cases[i]);
    ASSERT_TRUE(alone.ok()) << alone.error().to_string();
    EXPECT_TRUE(same(*alone, in_sequence[i])) << "case " << i;
  }
}

// One pipeline per pass shader and specialisation per device, whatever the number of cases.
TEST(VulkanReuse, PipelinesAreCreatedOncePerShader) {
  hdrc::gpu::VulkanEngine engine(no_disk_cache());
  ASSERT_TRUE(engine.init().ok());
  for (int round = 0; round < 2; ++round) {
    for (int format : {0, 1, 2})
      for (int device : {0, 3, 8})
        ASSERT_TRUE(
            engine.run(make_case("tonemap", device, 16, format, format % 2, ramp(8, 2, 9))).ok());
    // combine_luts.comp, the engine's store pass (engine/lut_store.comp) and tonemap.comp once
    // per LUT layout (kSpecTonemapLutLayout; the other specialisation constants are the same for
    // these cases: no fringe, sharpen, bloom or post conversion); the second round adds none.
    EXPECT_EQ(engine.pipeline_creations(), 4) << "round " << round;
    EXPECT_EQ(engine.compiled_pipeline_count(), 4) << "round " << round;
  }
}

// The Tonemap pass specialised on the case (kSpecTonemap*: fringe, sharpen, bloom, bloom dirt,
// post conversion, LUT layout) gives the same bits as the pass with every branch compiled and
// decided by the uniforms (the suite's shaders with the constants made plain constants at their
// defaults, which the engine then cannot specialise), for each effect on and off, each LUT layout
// and devices with each shaper and post conversion.
TEST(VulkanReuse, SpecialisedTonemapEqualsTheUnspecialisedPass) {
  // Bit equality of two compilations holds on a float32-exact device only: elsewhere a compiler
  // that folds the specialisation constants may fuse a·b + c where the other compilation did not
  // ("Precision and Operation of SPIR-V Instructions": fused or not unless NoContraction). Each
  // compilation is judged against the reference's device ranges there (TonemapEndToEnd).
  HDRC_SKIP_IF(hdrc::gpu::testing::not_exact_reason(
      "two compilations of one pass are bit-equal only where no a*b + c may be fused"));
  hdrc::gpu::testing::ShaderDirCopy plain("unspecialised");
  {
    std::ifstream in(fs::path(hdrc::gpu::default_shader_dir()) / "lib/tonemap_variant.glsl");
    std::stringstream text;
    text << in.rdbuf();
    const std::string plain_text =
        std::regex_replace(text.str(), std::regex(R"(layout\(constant_id = \w+\) )"), "");
    ASSERT_NE(plain_text, text.str());
    plain.write("lib/tonemap_variant.glsl", plain_text);
  }
  hdrc::gpu::VulkanOptions plain_options = no_disk_cache();
  plain_options.shader_dir = plain.path();
  hdrc::gpu::VulkanEngine specialised(no_disk_cache()), unspecialised(plain_options);
  ASSERT_TRUE(specialised.init().ok());
  ASSERT_TRUE(unspecialised.init().ok());
  int cases = 0;
  for (int device : {0, 3, 5, 7})
    for (int layout : {0, 1})
      for (bool effects : {false, true}) {
        hdrc::ResolvedCase c = make_case("tonemap", device, 16, 1, layout, ramp(24, 10, 11));
        if (effects) {
          c.spec.settings.set("SceneFringeIntensity", {3, 0, 0, 0}, 1);
          c.spec.settings.set("Sharpen", {2, 0, 0, 0}, 1);
          c.spec.settings.set("BloomDirtMaskIntensity", {1, 0, 0, 0}, 1);
          c.params = *hdrc::ref::resolve_params(c.spec, c.input.width, c.input.height);
          c.bloom = ramp(12, 5, 12);
          c.bloom_dirt = ramp(6, 3, 13);
        }
        auto a = specialised.run(c);
        auto b = unspecialised.run(c);
        ASSERT_TRUE(a.ok()) << a.error().to_string();
        ASSERT_TRUE(b.ok()) << b.error().to_string();
        EXPECT_TRUE(same(*a, *b)) << "device " << device << " layout " << layout << " effects "
                                  << effects;
        ++cases;
      }
  EXPECT_EQ(cases, 16);
  // The specialised engine made a pipeline per specialisation, the other one for every case.
  EXPECT_GT(specialised.compiled_pipeline_count(), unspecialised.compiled_pipeline_count());
}

// The pipeline cache is written to the path given when the engine ends, with Vulkan's header
// (VK_PIPELINE_CACHE_HEADER_VERSION_ONE), and a second engine starts from it.
TEST(VulkanReuse, PipelineCacheIsSavedAndReloaded) {
  const fs::path dir =
      fs::temp_directory_path() / ("hdrc_pipeline_cache_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  hdrc::gpu::VulkanOptions o;
  o.pipeline_cache_path = (dir / "cache.bin").string();
  {
    hdrc::gpu::VulkanEngine engine(o);
    ASSERT_TRUE(engine.init().ok());
    ASSERT_TRUE(engine.run(make_case("shaper", 3, 16, 0, 0, ramp(4, 1, 1))).ok());
  }
  ASSERT_TRUE(fs::exists(o.pipeline_cache_path));
  std::ifstream in(o.pipeline_cache_path, std::ios::binary);
  uint32_t header[2] = {0, 0};
  in.read(reinterpret_cast<char*>(header), sizeof header);
  EXPECT_GE(header[0], 16u + 16u);  // header length: 4 words + the UUID
  EXPECT_EQ(header[1], 1u);         // VK_PIPELINE_CACHE_HEADER_VERSION_ONE
  {
    hdrc::gpu::VulkanEngine engine(o);
    ASSERT_TRUE(engine.init().ok());
    EXPECT_TRUE(engine.run(make_case("shaper", 3, 16, 0, 0, ramp(4, 1, 1))).ok());
  }
  fs::remove_all(dir);
}

}  // namespace
