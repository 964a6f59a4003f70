// The Vulkan engine: runs each stage as its list of GLSL compute passes (float32) on an explicitly
// selected Vulkan device — lavapipe (Mesa's CPU driver) by default, any other device by name or
// index. Lifecycle as in core/engine.h; init() fails with the reason when no suitable device
// exists. The interface the shaders see (bindings, LUT images, dispatch domains) is documented in
// docs/gpu-interface.md.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include "core/device_precision.h"
#include "core/engine.h"

namespace hdrc::gpu {

struct VulkanOptions {
  // "" = lavapipe (the physical device whose name contains "llvmpipe"), or the environment's
  // HDRC_VK_DEVICE where it is set; a number = that index in vkEnumeratePhysicalDevices order;
  // otherwise a case-insensitive substring of the device name.
  std::string device;
  std::string shader_dir;  // where stages/*.comp and lib/*.glsl are read from
  // Enable VK_LAYER_KHRONOS_validation (with synchronisation validation) and a VK_EXT_debug_utils
  // messenger: every warning or error it reports while a case runs makes that case an ERROR.
  bool validation = false;
  // A submission taking longer marks that case as an ERROR; the engine then abandons the device
  // (the work may still be running on it) and creates a fresh one for the next case.
  double fence_timeout_s = 60;
  // A VkPipelineCache kept on disk: read when a device is created, written back (atomically)
  // when the engine ends, so a fresh process does not pay the driver's compile per pipeline.
  // Default: vk_pipeline_cache.bin in the build folder; "" = default_pipeline_cache_path();
  // "none" = no disk cache.
  std::string pipeline_cache_path;
  // The worst-case conformant device model (core/device_precision.h): shaders compiled with every
  // freedom the Vulkan specification allows taken to its edge, images and buffers poisoned.
  DeviceModel device_model = DeviceModel::kNone;
  // FOR TESTS ONLY (gpu/vulkan_hygiene_test.cpp; no CLI option sets it): an engine defect planted
  // on purpose, to show what exposes it.
  //  kNoBarrierBeforeStore: the barrier between a LUT bake pass and the engine's store pass is left
  //    out (a read-after-write hazard: the store pass may read the bake image before the bake
  //    pass has written it).
  //  kStaleLutOnReuse: the store pass is left out when the LUT image is reused from the case before
  //    (same format, layout and size), so the LUT holds what that case stored.
  enum class Planted { kNone, kNoBarrierBeforeStore, kStaleLutOnReuse };
  Planted planted = Planted::kNone;
};

// The default on-disk VkPipelineCache: <build folder>/vk_pipeline_cache.bin; for a relocated binary
// (a bundle) $XDG_CACHE_HOME/hdrconform/vk_pipeline_cache.bin (core/install_paths.h).
std::string default_pipeline_cache_path();

// The shader directory of this build (the source tree's gpu/shaders); for a relocated binary
// <exe dir>/../share/hdrconform/shaders (core/install_paths.h).
std::string default_shader_dir();

// "index: name (type, driver)" for every physical device, or the reason there are none.
Result<std::string> list_devices();

// Exact decoders of the LUT storage formats, as the engine reads the baked LUT back.
// IEEE 754 binary16 → float (subnormals, ±Inf and NaN included).
float decode_half(uint16_t h);
// VK_FORMAT_A2B10G10R10_UNORM_PACK32 → (R, G, B, A): R in bits 0–9, G 10–19, B 20–29 (k/1023),
// A in bits 30–31 (k/3).
std::array<double, 4> decode_a2b10g10r10(uint32_t texel);

class VulkanEngine final : public Engine {
 public:
  explicit VulkanEngine(VulkanOptions options);
  ~VulkanEngine() override;
  std::string name() const override { return "vulkan"; }
  Status init() override;
  DeviceInfo device() const override;
  Result<Image> run(const ResolvedCase& c) override;

  // Pipelines on the current device (each pass shader is compiled to SPIR-V once per engine, and
  // made into a pipeline once per device).
  int compiled_pipeline_count() const;
  // Pipelines created on the current device (vkCreateComputePipelines calls: one per pass
  // shader per device, whatever the number of cases).
  int pipeline_creations() const;
  // Cases whose buffers, LUT image and descriptors were reused from an earlier case.
  int reused_work_count() const;
  // Devices given up after a timeout whose work has not finished yet (freed once it has).
  int abandoned_device_count() const;
  // Logical devices created so far (1 after init; one more after each loss or timeout).
  int device_generation() const;

 private:
  struct State;
  VulkanOptions options_;
  std::unique_ptr<State> state_;
};

}  // namespace hdrc::gpu
