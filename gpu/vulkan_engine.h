// The Vulkan engine: runs each stage as a GLSL compute shader (float32) on an explicitly selected
// Vulkan device — lavapipe (Mesa's CPU driver) by default, any other device by name or index.
// Lifecycle as in core/engine.h; init() fails with the reason when no suitable device exists.
#pragma once

#include <map>
#include <memory>
#include <string>

#include "core/engine.h"

namespace hdrc::gpu {

struct VulkanOptions {
  // "" = lavapipe (the physical device whose name contains "llvmpipe"); a number = that index in
  // vkEnumeratePhysicalDevices order; otherwise a case-insensitive substring of the device name.
  std::string device;
  std::string shader_dir;       // where stages/*.comp and lib/*.glsl are read from
  bool validation = false;      // enable VK_LAYER_KHRONOS_validation (must be installed)
  double fence_timeout_s = 60;  // a dispatch taking longer marks that case as an error
};

// The shader directory of this build (the source tree's gpu/shaders).
std::string default_shader_dir();

// "index: name (type, driver)" for every physical device, or the reason there are none.
Result<std::string> list_devices();

class VulkanEngine final : public Engine {
 public:
  explicit VulkanEngine(VulkanOptions options);
  ~VulkanEngine() override;
  std::string name() const override { return "vulkan"; }
  Status init() override;
  DeviceInfo device() const override;
  Result<Image> run(const ResolvedCase& c) override;

  // Pipelines compiled so far (a run of many cases compiles each stage shader once).
  int compiled_pipeline_count() const;

 private:
  struct State;
  VulkanOptions options_;
  std::unique_ptr<State> state_;
};

}  // namespace hdrc::gpu
