// In-process GLSL → SPIR-V compilation with glslang. Shaders are always compiled from source (no
// SPIR-V is ever committed). `#include "x.glsl"` resolves against the shader directory; the
// virtual include "hdrc/interface.glsl" is generated from core/shader_interface.h and the
// reference's constants (gpu/shader_constants.h), so both sides share one source.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/device_precision.h"
#include "core/result.h"

namespace hdrc::gpu {

// glslang's process-wide state, initialised once and finalised at exit (RAII).
class GlslangProcess {
 public:
  static void ensure();

 private:
  GlslangProcess();
  ~GlslangProcess();
};

// The generated virtual include: parameter block, bindings and shared constants.
std::string generated_interface_glsl();

// Compiles `shader_dir/relative_path` as a compute shader for Vulkan 1.1 / SPIR-V 1.3.
// Errors are "shader_dir/file:line: message" for every diagnostic glslang reports.
// `model` kWorst: the worst-case conformant device's shader (core/device_precision.h).
Result<std::vector<uint32_t>> compile_compute(const std::string& shader_dir,
                                              const std::string& relative_path,
                                              DeviceModel model = DeviceModel::kNone);

}  // namespace hdrc::gpu
