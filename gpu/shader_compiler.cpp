#include "gpu/shader_compiler.h"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "core/shader_interface.h"
#include "core/stage.h"
#include "gpu/hlsl_interface.h"
#include "gpu/shader_constants.h"
#include "gpu/spirv_device_model.h"

namespace hdrc::gpu {

namespace fs = std::filesystem;

GlslangProcess::GlslangProcess() {
  glslang::InitializeProcess();
}
GlslangProcess::~GlslangProcess() {
  glslang::FinalizeProcess();
}
void GlslangProcess::ensure() {
  static GlslangProcess instance;
}

std::string generated_interface_glsl() {
  return glsl_param_block() + glsl_shared_constants();
}

namespace {

constexpr const char* kGeneratedInclude = "hdrc/interface.glsl";
constexpr const char* kGeneratedIncludeHlsl = "hdrc/interface.hlsl";

bool read_text(const fs::path& p, std::string* out) {
  std::ifstream f(p, std::ios::binary);
  if (!f) return false;
  std::ostringstream s;
  s << f.rdbuf();
  *out = s.str();
  return true;
}

constexpr size_t kMaxIncludeDepth = 32;

// Resolves includes against the shader root (and the including file's folder first).
class Includer final : public glslang::TShader::Includer {
 public:
  explicit Includer(fs::path root) : root_(std::move(root)) {}

  IncludeResult* includeLocal(const char* name, const char* includer, size_t depth) override {
    // A file that includes itself (directly or in a cycle) would recurse without end.
    if (depth > kMaxIncludeDepth)
      return make("", "#include nested more than " + std::to_string(kMaxIncludeDepth) +
                          " levels deep at \"" + std::string(name) + "\" (an include cycle?)");
    if (std::string(name) == kGeneratedInclude) return make(name, generated_interface_glsl());
    if (std::string(name) == kGeneratedIncludeHlsl) return make(name, generated_interface_hlsl());
    const fs::path from = fs::path(includer).parent_path();
    for (const fs::path& candidate : {root_ / from / name, root_ / name}) {
      std::string text;
      if (read_text(candidate, &text)) {
        return make(fs::relative(candidate, root_).generic_string(), std::move(text));
      }
    }
    return nullptr;
  }
  IncludeResult* includeSystem(const char* name, const char* includer, size_t depth) override {
    return includeLocal(name, includer, depth);
  }
  void releaseInclude(IncludeResult* r) override {
    if (!r) return;
    delete static_cast<std::string*>(r->userData);
    delete r;
  }

 private:
  IncludeResult* make(const std::string& name, std::string text) {
    auto* owned = new std::string(std::move(text));
    return new IncludeResult(name, owned->data(), owned->size(), owned);
  }
  fs::path root_;
};

// glslang reports "ERROR: file:line: message"; rewrite to "dir/file:line: error: message".
std::string format_log(const std::string& log, const fs::path& root) {
  static const std::regex line_re(R"(^(ERROR|WARNING): ([^:]+):(\d+): (.*)$)");
  std::istringstream in(log);
  std::string line, out;
  while (std::getline(in, line)) {
    std::smatch m;
    if (std::regex_match(line, m, line_re)) {
      const std::string kind = m[1] == "ERROR" ? "error" : "warning";
      out += (root / m[2].str()).generic_string() + ":" + m[3].str() + ": " + kind + ": " +
             m[4].str() + "\n";
    } else if (!line.empty() && line.find("compilation terminated") == std::string::npos &&
               line.find("compilation errors") == std::string::npos) {
      out += line + "\n";
    }
  }
  if (!out.empty() && out.back() == '\n') out.pop_back();
  return out;
}

}  // namespace

Result<std::vector<uint32_t>> compile_compute(const std::string& shader_dir,
                                              const std::string& relative_path, DeviceModel model) {
  GlslangProcess::ensure();
  const fs::path root(shader_dir);
  // An HLSL port: stages/X.hlsl in place of stages/X.comp (docs/gpu-interface.md, "HLSL").
  const std::string path = pass_shader_file(shader_dir, relative_path);
  const bool hlsl = path != relative_path;
  const char* language = hlsl ? "HLSL" : "GLSL";
  std::string source;
  if (!read_text(root / path, &source)) {
    return Error{(root / path).generic_string(), "", "cannot read shader source", ""};
  }
  glslang::TShader shader(EShLangCompute);
  const char* strings[] = {source.c_str()};
  const int lengths[] = {static_cast<int>(source.size())};
  const char* names[] = {path.c_str()};
  shader.setStringsWithLengthsAndNames(strings, lengths, names, 1);
  shader.setEnvInput(hlsl ? glslang::EShSourceHlsl : glslang::EShSourceGlsl, EShLangCompute,
                     glslang::EShClientVulkan, 100);
  shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_1);
  shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_3);
  if (hlsl) {
    shader.setEntryPoint("main");
    shader.setSourceEntryPoint("main");
    // Texture + SamplerState pairs become the interface's combined image samplers.
    shader.setTextureSamplerTransformMode(EShTexSampTransUpgradeTextureRemoveSampler);
  }
  // The worst-case device (gpu/spirv_device_model.h): GLSL gets the in-shader filter in place of
  // textureLod and HDRC_DEVICE_MODEL_WORST (engine/lut_store.comp's toward-zero stores); an HLSL
  // port gets only the define (its SampleLevel keeps the hardware filter). Both get the SPIR-V
  // rewrite below.
  const bool worst = model == DeviceModel::kWorst;
  const std::string preamble = !worst ? std::string()
                               : hlsl ? "#define HDRC_DEVICE_MODEL_WORST 1\n"
                                      : worst_device_glsl_preamble();
  if (worst) shader.setPreamble(preamble.c_str());
  Includer includer(root);
  const int hlsl_rules = hlsl ? static_cast<int>(EShMsgReadHlsl) : 0;
  const auto messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules | hlsl_rules);
  if (!shader.parse(GetDefaultResources(), hlsl ? 100 : 450, false, messages, includer)) {
    return Error{
        (root / path).generic_string(), "",
        std::string(language) + " compile failed:\n" + format_log(shader.getInfoLog(), root), ""};
  }
  glslang::TProgram program;
  program.addShader(&shader);
  if (!program.link(messages)) {
    return Error{(root / path).generic_string(), "",
                 std::string(language) + " link failed:\n" + format_log(program.getInfoLog(), root),
                 ""};
  }
  std::vector<uint32_t> spirv;
  glslang::SpvOptions options;
  options.validate = true;
  glslang::GlslangToSpv(*program.getIntermediate(EShLangCompute), spirv, &options);
  if (worst) {
    auto rewritten = apply_worst_device_model(&spirv);
    if (!rewritten) {
      Error e = rewritten.error();
      e.file = (root / path).generic_string();
      e.message = "device model rewrite failed: " + e.message;
      return e;
    }
  }
  return spirv;
}

}  // namespace hdrc::gpu
