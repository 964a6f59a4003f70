#include "gpu/shader_compiler.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/stage.h"
#include "gpu/vulkan_engine.h"
#include "reference/ue/ue55/ue55_pipeline.h"

namespace fs = std::filesystem;

namespace {

fs::path temp_dir(const std::string& name) {
  fs::path p = fs::temp_directory_path() / ("hdrc_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

TEST(ShaderCompiler, EveryStageShaderCompiles) {
  int compiled = 0;
  for (const auto& stage : hdrc::ref::ue55_stage_table()) {
    // A stage whose shaders are not all written yet is listed in cases/known_limits.json.
    if (!hdrc::missing_shaders(stage, hdrc::gpu::default_shader_dir()).empty()) continue;
    for (const auto& pass : stage.passes) {
      ++compiled;
      auto spirv =
          hdrc::gpu::compile_compute(hdrc::gpu::default_shader_dir(), std::string(pass.shader));
      ASSERT_TRUE(spirv.ok()) << spirv.error().to_string();
      EXPECT_EQ((*spirv)[0], 0x07230203u) << "SPIR-V magic";
    }
  }
  EXPECT_GE(compiled, 2);
}

// A compile error names the file and line where it is, also inside an included file.
TEST(ShaderCompiler, ErrorsShowFileAndLine) {
  const fs::path dir = temp_dir("broken");
  fs::copy(hdrc::gpu::default_shader_dir(), dir, fs::copy_options::recursive);
  int lines = 0;
  {
    std::ifstream in(dir / "lib/matrix.glsl");
    for (std::string l; std::getline(in, l);) ++lines;
  }
  {
    std::ofstream f(dir / "lib/matrix.glsl", std::ios::app);
    f << "\nfloat broken() { return undeclared_thing; }\n";  // at line lines + 2
  }
  auto spirv = hdrc::gpu::compile_compute(dir.string(), "stages/linear_device.comp");
  ASSERT_FALSE(spirv.ok());
  const std::string msg = spirv.error().to_string();
  EXPECT_NE(msg.find((dir / "lib/matrix.glsl").generic_string() + ":" + std::to_string(lines + 2) +
                     ": error: 'undeclared_thing' : undeclared identifier"),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find("undeclared_thing"), std::string::npos) << msg;
  fs::remove_all(dir);
}

TEST(ShaderCompiler, MissingShaderIsAnError) {
  auto spirv = hdrc::gpu::compile_compute("/nonexistent", "stages/shaper.comp");
  ASSERT_FALSE(spirv.ok());
  EXPECT_NE(spirv.error().to_string().find("/nonexistent/stages/shaper.comp"), std::string::npos);
}

}  // namespace
