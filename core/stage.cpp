#include "core/stage.h"

#include <filesystem>

namespace hdrc {

std::string pass_shader_file(const std::string& shader_dir, std::string_view shader) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path glsl(shader);
  if (glsl.extension() != ".comp" || fs::is_regular_file(fs::path(shader_dir) / glsl, ec))
    return std::string(shader);
  fs::path hlsl = glsl;
  hlsl.replace_extension(".hlsl");
  return fs::is_regular_file(fs::path(shader_dir) / hlsl, ec) ? hlsl.generic_string()
                                                              : std::string(shader);
}

std::vector<std::string> missing_shaders(const StageInfo& stage, const std::string& shader_dir) {
  std::vector<std::string> out;
  for (const StagePass& pass : stage.passes) {
    std::error_code ec;
    const std::string file = pass_shader_file(shader_dir, pass.shader);
    if (!std::filesystem::is_regular_file(std::filesystem::path(shader_dir) / file, ec))
      out.emplace_back(pass.shader);
  }
  return out;
}

}  // namespace hdrc
