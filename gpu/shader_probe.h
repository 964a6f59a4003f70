// Test helpers for probing GLSL library code on the GPU engine (header-only, tests only).
//
// A probe is a compute shader put in place of stages/shaper.comp inside a temporary copy of the
// suite's shader directory, so it can include the suite's lib/*.glsl and the generated interface
// exactly as the stage shaders do; the engine then runs it as the "shaper" stage (one pass over
// width × height invocations, in_px / out_px bound). Used by gpu/ui_shader_test.cpp and
// gpu/visualize_shader_test.cpp.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/case.h"
#include "core/stage.h"
#include "gpu/vulkan_engine.h"
#include "reference/ue/cpp/resolve.h"

namespace hdrc::gpu::testing {

// A temporary copy of the suite's shader directory; removed on destruction.
class ShaderDirCopy {
 public:
  explicit ShaderDirCopy(const std::string& tag) {
    namespace fs = std::filesystem;
    dir_ = fs::temp_directory_path() /
           ("hdrc_" + tag + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter()++));
    fs::remove_all(dir_);
    fs::copy(default_shader_dir(), dir_, fs::copy_options::recursive);
  }
  ~ShaderDirCopy() { std::filesystem::remove_all(dir_); }
  ShaderDirCopy(const ShaderDirCopy&) = delete;
  ShaderDirCopy& operator=(const ShaderDirCopy&) = delete;

  // Replaces (or adds) `relative` with `source`.
  void write(const std::string& relative, const std::string& source) const {
    std::filesystem::create_directories((dir_ / relative).parent_path());
    std::ofstream(dir_ / relative, std::ios::trunc) << source;
  }
  std::string path() const { return dir_.string(); }

 private:
  static int& counter() {
    static int n = 0;
    return n;
  }
  std::filesystem::path dir_;
};

// The probe's preamble: the generated interface and the workgroup size.
inline std::string probe_preamble() {
  return "#version 450\n#extension GL_GOOGLE_include_directive : require\n"
         "#include \"hdrc/interface.glsl\"\n"
         "layout(local_size_x = HDRC_LOCAL_SIZE_X) in;\n";
}

// A case of `stage` with cvars resolved as the runner does, on `input`.
inline ResolvedCase make_case(const char* stage, int device, Image input) {
  ResolvedCase rc;
  rc.spec.id = "test";
  rc.spec.stage = find_stage(stage);
  rc.spec.cvars.set("r.HDR.EnableHDROutput", 1);
  rc.spec.cvars.set("r.HDR.Display.OutputDevice", device);
  rc.params = *ref::resolve_params(rc.spec, input.width, input.height);
  rc.input = std::move(input);
  return rc;
}

// A probe shader installed as the shaper stage of a shader-directory copy, with one engine (so the
// probe compiles once however many cases run through it), compiled for `model`.
class Probe {
 public:
  explicit Probe(const std::string& probe_source, DeviceModel model = DeviceModel::kNone)
      : dir_("probe") {
    dir_.write("stages/shaper.comp", probe_source);
    VulkanOptions o;
    o.shader_dir = dir_.path();
    o.device_model = model;
    engine_ = std::make_unique<VulkanEngine>(o);
    init_ = engine_->init();
  }
  // Runs the probe over `rc` (its input sets the invocation count, its params the block).
  Result<Image> run(ResolvedCase rc) {
    if (!init_) return init_.error();
    rc.spec.stage = find_stage("shaper");
    return engine_->run(rc);
  }

 private:
  ShaderDirCopy dir_;
  std::unique_ptr<VulkanEngine> engine_;
  Status init_;
};

inline Result<Image> run_probe(const std::string& probe_source, ResolvedCase rc) {
  return Probe(probe_source).run(std::move(rc));
}

// Reads GLSL constant expressions back from the GPU: out_px[k].x = float(expression k).
inline Result<std::vector<float>> read_back(const std::vector<std::string>& expressions,
                                            const std::vector<std::string>& includes) {
  std::string src = probe_preamble();
  for (const auto& inc : includes) src += "#include \"" + inc + "\"\n";
  src += "void main() {\n  if (gl_GlobalInvocationID.x != 0u) return;\n";
  for (size_t k = 0; k < expressions.size(); ++k)
    src += "  out_px[" + std::to_string(k) + "] = vec4(float(" + expressions[k] + "), 0, 0, 0);\n";
  src += "}\n";
  auto out = run_probe(src, make_case("shaper", 3, Image(static_cast<int>(expressions.size()), 1)));
  if (!out) return out.error();
  std::vector<float> values(expressions.size());
  for (size_t k = 0; k < values.size(); ++k) values[k] = static_cast<float>(out->data[k * 4]);
  return values;
}

// Error statistics of a candidate against a reference: max and 99.9th percentile.
struct ErrorStats {
  std::vector<double> errors;
  double largest = 0.0;
  void add(double e) {
    largest = errors.empty() ? e : std::fmax(largest, e);
    errors.push_back(e);
  }
  double max() const { return largest; }
  double percentile(double q) const {
    if (errors.empty()) return 0.0;
    std::vector<double> s = errors;
    const size_t k = static_cast<size_t>(std::floor(q * static_cast<double>(s.size() - 1)));
    std::nth_element(s.begin(), s.begin() + static_cast<long>(k), s.end());
    return s[k];
  }
};

}  // namespace hdrc::gpu::testing
