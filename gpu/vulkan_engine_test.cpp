// The Vulkan engine on lavapipe: device selection, the shared interface read back from the GPU,
// and agreement with the reference.
#include "gpu/vulkan_engine.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/shader_interface.h"
#include "gpu/shader_constants.h"
#include "reference/reference_engine.h"
#include "reference/ue_cpp/resolve.h"

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
  EXPECT_NE(st.error().to_string().find("llvmpipe"), std::string::npos);  // the choices
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
    f << "}\n";
  }
  hdrc::gpu::VulkanOptions o;
  o.shader_dir = dir.string();
  hdrc::gpu::VulkanEngine engine(o);
  ASSERT_TRUE(engine.init().ok());
  hdrc::Image input(static_cast<int>(constants.size()) + 7, 1);
  auto rc = make_case("shaper", 7, 2, input);
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
