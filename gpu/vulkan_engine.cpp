#include "gpu/vulkan_engine.h"

#include <sys/mman.h>
#include <vulkan/vulkan.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <thread>
#include <utility>
#include <vector>

#include "core/atomic_file.h"
#include "core/install_paths.h"
#include "core/shader_interface.h"
#include "gpu/shader_compiler.h"

#ifndef HDRC_SOURCE_SHADER_DIR
#error "HDRC_SOURCE_SHADER_DIR must be defined by the build"
#endif

namespace hdrc::gpu {

// A relocated binary (a bundle) reads <exe dir>/../share/hdrconform/shaders and keeps its cache in
// the user's cache folder: core/install_paths.h.
std::string default_shader_dir() {
  return data_dir(HDRC_SOURCE_SHADER_DIR, "shaders");
}

std::string default_pipeline_cache_path() {
#ifdef HDRC_PIPELINE_CACHE_FILE
  return pipeline_cache_file(HDRC_PIPELINE_CACHE_FILE);
#else
  return pipeline_cache_file("");
#endif
}

float decode_half(uint16_t h) {
  const bool negative = (h & 0x8000u) != 0;
  const int exponent = (h >> 10) & 0x1f;
  const int mantissa = h & 0x3ff;
  float v;
  if (exponent == 0) {
    v = std::ldexp(static_cast<float>(mantissa), -24);  // zero and subnormals: m · 2^-24
  } else if (exponent == 31) {
    v = mantissa ? std::numeric_limits<float>::quiet_NaN() : std::numeric_limits<float>::infinity();
  } else {
    v = std::ldexp(static_cast<float>(mantissa | 0x400), exponent - 25);  // 1.m · 2^(e − 15)
  }
  return negative ? -v : v;
}

std::array<double, 4> decode_a2b10g10r10(uint32_t texel) {
  return {(texel & 0x3ffu) / 1023.0, ((texel >> 10) & 0x3ffu) / 1023.0,
          ((texel >> 20) & 0x3ffu) / 1023.0, ((texel >> 30) & 0x3u) / 3.0};
}

namespace {

const char* vk_result_name(VkResult r) {
  switch (r) {
    case VK_SUCCESS:
      return "VK_SUCCESS";
    case VK_NOT_READY:
      return "VK_NOT_READY";
    case VK_TIMEOUT:
      return "VK_TIMEOUT";
    case VK_ERROR_OUT_OF_HOST_MEMORY:
      return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
      return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED:
      return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST:
      return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_MEMORY_MAP_FAILED:
      return "VK_ERROR_MEMORY_MAP_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT:
      return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT:
      return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT:
      return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER:
      return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_TOO_MANY_OBJECTS:
      return "VK_ERROR_TOO_MANY_OBJECTS";
    case VK_ERROR_FORMAT_NOT_SUPPORTED:
      return "VK_ERROR_FORMAT_NOT_SUPPORTED";
    case VK_ERROR_FRAGMENTED_POOL:
      return "VK_ERROR_FRAGMENTED_POOL";
    case VK_ERROR_OUT_OF_POOL_MEMORY:
      return "VK_ERROR_OUT_OF_POOL_MEMORY";
    default:
      return "VkResult error";
  }
}

Error vk_error(const char* call, VkResult r) {
  return Error{"", "",
               std::string(call) + " failed: " + vk_result_name(r) + " (" +
                   std::to_string(static_cast<int>(r)) + ")",
               ""};
}

// Every failed Vulkan call is reported with the call's text (STYLE.md: errors name what failed).
#define HDRC_VK(call)                                         \
  do {                                                        \
    const VkResult hdrc_r = (call);                           \
    if (hdrc_r != VK_SUCCESS) return vk_error(#call, hdrc_r); \
  } while (0)

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string version_string(uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) +
         "." + std::to_string(VK_API_VERSION_PATCH(v));
}

struct DeviceDescription {
  VkPhysicalDevice handle;
  std::string name, driver, type;
  uint32_t api_version;
};

const char* type_name(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "CPU";
    default:
      return "other";
  }
}

// Validation messages collected by the debug-utils messenger (the layer may call from any thread).
struct Messages {
  std::mutex mutex;
  std::vector<std::string> list;
  void clear() {
    std::lock_guard<std::mutex> lock(mutex);
    list.clear();
  }
  std::vector<std::string> take() {
    std::lock_guard<std::mutex> lock(mutex);
    return std::exchange(list, {});
  }
};

VKAPI_ATTR VkBool32 VKAPI_CALL on_debug_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                VkDebugUtilsMessageTypeFlagsEXT /*types*/,
                                                const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                void* user) {
  auto* messages = static_cast<Messages*>(user);
  std::string text =
      severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning";
  if (data && data->pMessageIdName) text += std::string(" [") + data->pMessageIdName + "]";
  text += ": ";
  text += data && data->pMessage ? data->pMessage : "(no message)";
  std::lock_guard<std::mutex> lock(messages->mutex);
  messages->list.push_back(std::move(text));
  return VK_FALSE;  // never abort the call: the case is failed by the engine instead
}

VkDebugUtilsMessengerCreateInfoEXT messenger_info(Messages* messages) {
  VkDebugUtilsMessengerCreateInfoEXT mi{};
  mi.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
  mi.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                   VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                   VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  mi.pfnUserCallback = on_debug_message;
  mi.pUserData = messages;
  return mi;
}

// A Vulkan instance named `name`; `messages` as for create_instance. The drivers are not anchored
// (keep_drivers_loaded makes its anchor with this).
Result<VkInstance> create_instance_unanchored(Messages* messages, const char* name) {
  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = name;
  app.apiVersion = VK_API_VERSION_1_1;
  VkInstanceCreateInfo ci{};
  ci.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  ci.pApplicationInfo = &app;
  const char* layers[] = {"VK_LAYER_KHRONOS_validation"};
  const char* extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
  VkDebugUtilsMessengerCreateInfoEXT mi{};
  const VkValidationFeatureEnableEXT enables[] = {
      VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  VkValidationFeaturesEXT features{};
  if (messages) {
    ci.enabledLayerCount = 1;
    ci.ppEnabledLayerNames = layers;
    ci.enabledExtensionCount = 1;
    ci.ppEnabledExtensionNames = extensions;
    mi = messenger_info(messages);
    features.sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT;
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = enables;
    mi.pNext = &features;
    ci.pNext = &mi;
  }
  VkInstance instance = VK_NULL_HANDLE;
  const VkResult r = vkCreateInstance(&ci, nullptr, &instance);
  // The loader answers VK_ERROR_INCOMPATIBLE_DRIVER when it loaded no driver at all: no manifest
  // found, or the library a manifest names failed to load. Measured on an NVIDIA H200 container
  // (docs/precision.md, "The default suite on a real GPU"): NVIDIA's Vulkan library needs
  // libglvnd's libGLdispatch.so.0, and without it every vkCreateInstance in the process fails so.
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
    return Error{"", "",
                 "vkCreateInstance failed: VK_ERROR_INCOMPATIBLE_DRIVER (-9): the Vulkan loader "
                 "could load no driver. Install one (lavapipe: mesa-vulkan-drivers); with a "
                 "vendor driver, its library may lack a dependency (NVIDIA's needs libglvnd: "
                 "libGLX.so.0, libGLdispatch.so.0) or its manifest may not be found "
                 "(VK_DRIVER_FILES=/path/to/icd.json names it). VK_LOADER_DEBUG=driver shows "
                 "which manifests were read and why each driver was rejected",
                 ""};
  if (r != VK_SUCCESS) return vk_error("vkCreateInstance(&ci, nullptr, &instance)", r);
  return instance;
}

// Keeps the Vulkan drivers loaded for the rest of the process. The loader unloads a driver's
// library when the process's last instance is destroyed and loads it again for the next one.
// NVIDIA's (580.159, H200, measured 2026-11-27: docs/precision.md, "The default suite on a real
// GPU") then fails: in gpu_tests, which makes and destroys engines test after test, the first nine
// tests ran and every vkCreateInstance after them returned VK_ERROR_INCOMPATIBLE_DRIVER (105 tests
// failed); with this anchor the same binary ran all 130 in one process. (A three-cycle probe in a
// small process did not fail: the reload's failure depends on the process.) One instance that is
// never destroyed keeps every driver mapped. It enumerates no physical device, so lavapipe starts
// no threads for it; the handle stays reachable from this static, so LeakSanitizer ignores it.
void keep_drivers_loaded() {
  // A failure here is reported by the real instance's creation, which follows.
  static const VkInstance anchor = [] {
    auto handle = create_instance_unanchored(nullptr, "hdrconform (driver anchor)");
    return handle ? *handle : VK_NULL_HANDLE;
  }();
  (void)anchor;
}

// `messages` non-null: the validation layer, synchronisation validation and the debug-utils
// extension are enabled, and instance creation itself is reported to `messages`.
Result<VkInstance> create_instance(Messages* messages) {
  keep_drivers_loaded();
  return create_instance_unanchored(messages, "hdrconform");
}

// The precision properties the device allowances are derived from (core/device_precision.h):
// the device's own, or those of the worst-case model when it is on (which runs on this device but
// filters with kWorstModelSubTexelBits and rounds float16 toward zero).
DevicePrecision device_precision(VkPhysicalDevice physical, uint32_t api_version,
                                 DeviceModel model) {
  DevicePrecision p;
  VkPhysicalDeviceProperties props;
  vkGetPhysicalDeviceProperties(physical, &props);
  p.sub_texel_bits = static_cast<int>(props.limits.subTexelPrecisionBits);
  p.mipmap_bits = static_cast<int>(props.limits.mipmapPrecisionBits);
  if (api_version >= VK_API_VERSION_1_2) {  // VkPhysicalDeviceFloatControlsProperties is 1.2 core
    VkPhysicalDeviceFloatControlsProperties fc{};
    fc.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FLOAT_CONTROLS_PROPERTIES;
    VkPhysicalDeviceProperties2 p2{};
    p2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
    p2.pNext = &fc;
    vkGetPhysicalDeviceProperties2(physical, &p2);
    p.fp16_rte = fc.shaderRoundingModeRTEFloat16 == VK_TRUE;
    p.fp32_denorm = fc.shaderDenormPreserveFloat32 == VK_TRUE;
  }
  if (model == DeviceModel::kWorst) {
    p.sub_texel_bits = kWorstModelSubTexelBits;
    p.fp16_rte = false;
    p.model = device_model_name(model);
  }
  return p;
}

Result<std::vector<DeviceDescription>> describe_devices(VkInstance instance) {
  uint32_t count = 0;
  HDRC_VK(vkEnumeratePhysicalDevices(instance, &count, nullptr));
  std::vector<VkPhysicalDevice> handles(count);
  HDRC_VK(vkEnumeratePhysicalDevices(instance, &count, handles.data()));
  std::vector<DeviceDescription> out;
  for (VkPhysicalDevice h : handles) {
    VkPhysicalDeviceDriverProperties driver{};
    driver.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES;
    VkPhysicalDeviceProperties2 props{};
    props.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
    props.pNext = &driver;
    vkGetPhysicalDeviceProperties2(h, &props);
    out.push_back({h, props.properties.deviceName,
                   std::string(driver.driverName) + " " + driver.driverInfo,
                   type_name(props.properties.deviceType), props.properties.apiVersion});
  }
  return out;
}

// ---- RAII holders. Each keeps the VkDevice it was created on; a Gpu (below) outlives them. ----

template <typename T, void (*Destroy)(VkDevice, T, const VkAllocationCallbacks*)>
struct Owned {
  VkDevice device = VK_NULL_HANDLE;
  T handle = VK_NULL_HANDLE;
  Owned() = default;
  Owned(const Owned&) = delete;
  Owned& operator=(const Owned&) = delete;
  ~Owned() {
    if (handle) Destroy(device, handle, nullptr);
  }
};

// A host-visible, coherent buffer, mapped for its lifetime.
struct Buffer {
  VkDevice device = VK_NULL_HANDLE;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* mapped = nullptr;
  VkDeviceSize size = 0;
  Buffer() = default;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  ~Buffer() {
    if (mapped) vkUnmapMemory(device, memory);
    if (buffer) vkDestroyBuffer(device, buffer, nullptr);
    if (memory) vkFreeMemory(device, memory, nullptr);
  }
};

// An optimally tiled image with one view, in device-local memory where the device has it.
struct Texture {
  VkDevice device = VK_NULL_HANDLE;
  VkImage image = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  Texture() = default;
  Texture(const Texture&) = delete;
  Texture& operator=(const Texture&) = delete;
  ~Texture() {
    if (view) vkDestroyImageView(device, view, nullptr);
    if (image) vkDestroyImage(device, image, nullptr);
    if (memory) vkFreeMemory(device, memory, nullptr);
  }
};

uint32_t find_memory_type(const VkPhysicalDeviceMemoryProperties& mem, uint32_t allowed,
                          VkMemoryPropertyFlags want) {
  for (uint32_t i = 0; i < mem.memoryTypeCount; ++i)
    if ((allowed & (1u << i)) && (mem.memoryTypes[i].propertyFlags & want) == want) return i;
  return UINT32_MAX;
}

Status make_buffer(VkDevice device, const VkPhysicalDeviceMemoryProperties& mem, VkDeviceSize size,
                   VkBufferUsageFlags usage, Buffer* b) {
  b->device = device;
  b->size = size;
  VkBufferCreateInfo ci{};
  ci.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  ci.size = size;
  ci.usage = usage;
  ci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  HDRC_VK(vkCreateBuffer(device, &ci, nullptr, &b->buffer));
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(device, b->buffer, &req);
  const uint32_t type =
      find_memory_type(mem, req.memoryTypeBits,
                       VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  if (type == UINT32_MAX) return Error{"", "", "no host-visible coherent memory type", ""};
  VkMemoryAllocateInfo ai{};
  ai.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = type;
  HDRC_VK(vkAllocateMemory(device, &ai, nullptr, &b->memory));
  HDRC_VK(vkBindBufferMemory(device, b->buffer, b->memory, 0));
  HDRC_VK(vkMapMemory(device, b->memory, 0, VK_WHOLE_SIZE, 0, &b->mapped));
  std::memset(b->mapped, 0, size);  // deterministic contents for every binding
  return {};
}

constexpr VkImageUsageFlags kLutUsage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                        VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                        VK_IMAGE_USAGE_TRANSFER_DST_BIT;

Status make_texture(VkDevice device, const VkPhysicalDeviceMemoryProperties& mem, VkImageType type,
                    VkFormat format, VkExtent3D extent, Texture* t) {
  t->device = device;
  VkImageCreateInfo ci{};
  ci.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO;
  ci.imageType = type;
  ci.format = format;
  ci.extent = extent;
  ci.mipLevels = 1;
  ci.arrayLayers = 1;
  ci.samples = VK_SAMPLE_COUNT_1_BIT;
  ci.tiling = VK_IMAGE_TILING_OPTIMAL;
  ci.usage = kLutUsage;
  ci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  ci.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  HDRC_VK(vkCreateImage(device, &ci, nullptr, &t->image));
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(device, t->image, &req);
  uint32_t mt = find_memory_type(mem, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  if (mt == UINT32_MAX) mt = find_memory_type(mem, req.memoryTypeBits, 0);
  if (mt == UINT32_MAX) return Error{"", "", "no memory type for a LUT image", ""};
  VkMemoryAllocateInfo ai{};
  ai.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = mt;
  HDRC_VK(vkAllocateMemory(device, &ai, nullptr, &t->memory));
  HDRC_VK(vkBindImageMemory(device, t->image, t->memory, 0));
  VkImageViewCreateInfo vi{};
  vi.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO;
  vi.image = t->image;
  vi.viewType = type == VK_IMAGE_TYPE_3D ? VK_IMAGE_VIEW_TYPE_3D : VK_IMAGE_VIEW_TYPE_2D;
  vi.format = format;
  vi.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  HDRC_VK(vkCreateImageView(device, &vi, nullptr, &t->view));
  return {};
}

// The worst-case device model's poison (DeviceModel::kWorst; docs/gpu-interface.md, "Poisoning"):
// what a buffer holds before a pass writes it on a device that hands out memory as it finds it
// (lavapipe's fresh memory is zeroed, and it reuses nothing between cases unless told to). A quiet
// NaN as float32, so that a value read before it is written spreads to the output.
constexpr uint32_t kPoisonWord = 0x7fc0deadu;
// The guard after every storage buffer's data (canaries, always on): kGuardBytes of this word, a
// quiet NaN told apart from the poison, inside the binding's range (lavapipe discards a store past
// the range, llvmpipe's bounds check, so a guard outside it would never change), checked after
// each case: a changed word is an out-of-bounds write, and a read of the guard returns NaN.
constexpr uint32_t kCanaryWord = 0x7fc0c0deu;
constexpr VkDeviceSize kGuardBytes = 4096;

// The clear value that poisons an image (or the bake image of a LUT) of `format`: NaN for a float
// format; for a UNORM format, where a NaN stores as 0 (Vulkan spec, "Conversion from
// Floating-Point to Normalized Fixed-Point": NaN → 0) and would look like a zeroed image, a
// pattern of codes in the middle of the range.
VkClearColorValue poison_color(VkFormat format) {
  VkClearColorValue v{};
  if (format == VK_FORMAT_A2B10G10R10_UNORM_PACK32 || format == VK_FORMAT_R8G8B8A8_UNORM) {
    v.float32[0] = 0.71f;
    v.float32[1] = 0.29f;
    v.float32[2] = 0.53f;
    v.float32[3] = 0.67f;
  } else {
    for (float& c : v.float32) c = std::numeric_limits<float>::quiet_NaN();
  }
  return v;
}

// `bytes` bytes of `word`, repeated, from `at` (byte-wise: `at` need not be word-aligned).
void fill_words(void* at, VkDeviceSize bytes, uint32_t word) {
  auto* p = static_cast<uint8_t*>(at);
  for (VkDeviceSize i = 0; i < bytes; ++i) p[i] = static_cast<uint8_t>(word >> (8 * (i % 4)));
}

// Records: UNDEFINED → GENERAL, cleared to `value` (0 by default, so a texel a shader fails to
// write reads back as 0, never as stale memory; the poison under the worst-case model), visible to
// compute shaders.
void record_clear_to_general(VkCommandBuffer cmd, VkImage image,
                             const VkClearColorValue& value = {}) {
  VkImageMemoryBarrier to_general{};
  to_general.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
  to_general.srcAccessMask = 0;
  to_general.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  to_general.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  to_general.newLayout = VK_IMAGE_LAYOUT_GENERAL;
  to_general.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  to_general.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  to_general.image = image;
  to_general.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0,
                       nullptr, 0, nullptr, 1, &to_general);
  const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdClearColorImage(cmd, image, VK_IMAGE_LAYOUT_GENERAL, &value, 1, &range);
  VkImageMemoryBarrier to_shader = to_general;
  to_shader.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  to_shader.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
  to_shader.oldLayout = VK_IMAGE_LAYOUT_GENERAL;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0,
                       0, nullptr, 0, nullptr, 1, &to_shader);
}

// Records: UNDEFINED → GENERAL (contents discarded), for compute shaders' reads and writes.
void record_to_general(VkCommandBuffer cmd, VkImage image) {
  VkImageMemoryBarrier b{};
  b.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
  b.srcAccessMask = 0;
  b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
  b.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  b.newLayout = VK_IMAGE_LAYOUT_GENERAL;
  b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = image;
  b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       0, 0, nullptr, 0, nullptr, 1, &b);
}

// Records: UNDEFINED → TRANSFER_DST, `staging` copied into the whole of `image` (tightly packed
// texels), then GENERAL, visible to compute shaders' reads.
void record_upload_to_general(VkCommandBuffer cmd, VkBuffer staging, VkImage image,
                              VkExtent3D extent) {
  VkImageMemoryBarrier to_dst{};
  to_dst.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
  to_dst.srcAccessMask = 0;
  to_dst.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  to_dst.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  to_dst.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  to_dst.srcQueueFamilyIndex = to_dst.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  to_dst.image = image;
  to_dst.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0,
                       nullptr, 0, nullptr, 1, &to_dst);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = extent;
  vkCmdCopyBufferToImage(cmd, staging, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
  VkImageMemoryBarrier to_shader = to_dst;
  to_shader.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  to_shader.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
  to_shader.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  to_shader.newLayout = VK_IMAGE_LAYOUT_GENERAL;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0,
                       0, nullptr, 0, nullptr, 1, &to_shader);
}

// The LUT storage formats (P.lut_format), as UE creates them: PF_A2B10G10R10 is UE's default for
// the volume LUT (PostProcessCombineLUTs.cpp: the LUT's render-target format), RGBA16F and RGBA32F
// are the higher-precision choices.
struct LutFormat {
  VkFormat format;
  const char* name;
  uint32_t texel_bytes;
};
constexpr LutFormat kLutFormats[] = {
    {VK_FORMAT_A2B10G10R10_UNORM_PACK32, "VK_FORMAT_A2B10G10R10_UNORM_PACK32", 4},
    {VK_FORMAT_R16G16B16A16_SFLOAT, "VK_FORMAT_R16G16B16A16_SFLOAT", 8},
    {VK_FORMAT_R32G32B32A32_SFLOAT, "VK_FORMAT_R32G32B32A32_SFLOAT", 16},
    // Unity URP's LDR grading LUT (ColorGradingLutPass: R8G8B8A8_UNorm).
    {VK_FORMAT_R8G8B8A8_UNORM, "VK_FORMAT_R8G8B8A8_UNORM", 4},
};
// The format of the intermediate image a LUT bake pass writes (bake_format_ok): every float32 value
// the pass stores is kept as it is, and the store pass (kLutStoreShader) then writes it to the LUT
// image of the case's format.
constexpr VkFormat kBakeFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
// The shader of that store pass: the engine's own, always compiled from the built-in shader
// directory (a --shader-dir port provides only the stage passes).
constexpr const char* kLutStoreShader = "engine/lut_store.comp";

}  // namespace

Result<std::string> list_devices() {
  auto instance = create_instance(nullptr);
  if (!instance) return instance.error();
  auto devices = describe_devices(*instance);
  vkDestroyInstance(*instance, nullptr);
  if (!devices) return devices.error();
  std::string out;
  for (size_t i = 0; i < devices->size(); ++i) {
    const auto& d = (*devices)[i];
    out += std::to_string(i) + ": " + d.name + " (" + d.type + ", " + d.driver + ", Vulkan " +
           version_string(d.api_version) + ")\n";
  }
  if (out.empty()) out = "no Vulkan physical devices\n";
  return out;
}

namespace {

// One Vulkan instance, its logical device and everything created on them. Destroyed (members in
// reverse order, the device and then the instance last) only when no submission is pending. A new
// instance per device: on lavapipe the instance's physical device owns the compute thread pool, so
// a device made on a fresh instance runs while abandoned work still occupies the old pool.
struct Gpu {
  struct InstanceHandle {
    VkInstance handle = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    PFN_vkDestroyDebugUtilsMessengerEXT destroy_messenger = nullptr;
    ~InstanceHandle() {
      if (messenger && destroy_messenger) destroy_messenger(handle, messenger, nullptr);
      if (handle) vkDestroyInstance(handle, nullptr);
    }
  } instance;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkPhysicalDeviceMemoryProperties memory{};
  VkPhysicalDeviceLimits limits{};
  struct DeviceHandle {
    VkDevice handle = VK_NULL_HANDLE;
    ~DeviceHandle() {
      if (handle) vkDestroyDevice(handle, nullptr);
    }
  } device;
  VkQueue queue = VK_NULL_HANDLE;
  Owned<VkCommandPool, vkDestroyCommandPool> command_pool;
  Owned<VkDescriptorSetLayout, vkDestroyDescriptorSetLayout> set_layout;
  Owned<VkPipelineLayout, vkDestroyPipelineLayout> pipeline_layout;
  Owned<VkSampler, vkDestroySampler> sampler;
  // 1 texel each, bound where a pass has no LUT image (or user LUT), in kBakeFormat where the
  // device can sample and filter it, else RGBA16F (Vulkan spec, "Mandatory format support").
  // llvmpipe compiles a variant of a shader for each format, target and power-of-two-ness of the
  // images and textures it uses (lp_state_cs.c, make_variant_key): dummies in the format of the
  // bake image and of the user LUTs (RGBA32F) let a bake pass bound to either keep one variant.
  Texture dummy_3d, dummy_2d;
  // Per LUT format (kLutFormats), a 1-texel 3-D and 2-D image in that format, made on first use:
  // bound in place of the LUT of the layout a case does not use, so that the shaders reading or
  // writing the LUT see the same state on both bindings for a power-of-two LUT of either layout
  // (one variant instead of two).
  std::array<Texture, 4> format_dummy_3d, format_dummy_2d;
  Buffer dummy_buffer;  // 16 bytes, bound where a pass has no aux image
  struct Pipelines {
    VkDevice device = VK_NULL_HANDLE;
    std::map<std::string, VkPipeline> by_shader;
    ~Pipelines() {
      for (auto& [name, p] : by_shader) vkDestroyPipeline(device, p, nullptr);
    }
  } pipelines;
  Owned<VkPipelineCache, vkDestroyPipelineCache> pipeline_cache;
  int pipeline_creations = 0;  // vkCreateComputePipelines calls on this device
};

// Everything one case uses. Kept for the next case on the same device (buffers grow as needed,
// the LUT image is kept while its format, layout and size stay the same, the descriptor pool is
// reset): fresh allocations at 4K cost page faults and zeroing of hundreds of megabytes per case.
// After a timeout it stays with its abandoned device until the work finishes.
struct CaseWork {
  Buffer params, input, output, aux0, aux1, scratch, readback;
  Texture lut;
  int lut_format = -1, lut_layout = -1, lut_size = -1;  // what `lut` holds
  // The bake pass's images, per layout (kBakeFormat, each extent rounded up to a power of two so
  // that the bake shader's variant is the same for every r.LUT.Size, and only ever grown: a case
  // with a smaller LUT uses the corner it needs); the store pass copies N³ texels into `lut`.
  std::array<Texture, 2> bake;
  std::array<VkExtent3D, 2> bake_extent{};
  // The case's user LUTs (binding kBindingUserLut, one per slot): strips N^2 x N, RGBA32F or
  // 8-bit UNORM (StageInfo::user_lut_unorm8), uploaded from `user_lut_staging` at the start of
  // every case that has them.
  std::array<Texture, kUserLutSlots> user_lut;
  std::array<Buffer, kUserLutSlots> user_lut_staging;
  std::array<int, kUserLutSlots> user_lut_size{-1, -1, -1, -1};  // the N each was made for
  std::array<VkFormat, kUserLutSlots> user_lut_format{};         // and its format
  uint32_t descriptor_capacity = 0;                              // sets the pool holds
  Owned<VkDescriptorPool, vkDestroyDescriptorPool> descriptor_pool;
  Owned<VkFence, vkDestroyFence> fence;
  struct Commands {
    VkDevice device = VK_NULL_HANDLE;
    VkCommandPool pool = VK_NULL_HANDLE;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    ~Commands() {
      if (cmd) vkFreeCommandBuffers(device, pool, 1, &cmd);
    }
  } commands;
};

struct Abandoned {
  std::unique_ptr<Gpu> gpu;
  std::unique_ptr<CaseWork> work;  // declared after gpu: destroyed first
};

enum class Fate { kOk, kTimeout, kLost };

// SPIR-V per (shader directory, pass shader), compiled once per process and shared by every
// engine (each worker has its own engine).
Result<std::shared_ptr<const std::vector<uint32_t>>> shared_spirv(const std::string& shader_dir,
                                                                  const std::string& shader,
                                                                  DeviceModel model) {
  static std::mutex mu;
  static std::map<std::string, std::shared_ptr<const std::vector<uint32_t>>> cache;
  const std::string key = shader_dir + '\n' + shader + '\n' + device_model_name(model);
  {
    std::lock_guard<std::mutex> lock(mu);
    if (auto it = cache.find(key); it != cache.end()) return it->second;
  }
  auto compiled = compile_compute(shader_dir, shader, model);
  if (!compiled) return compiled.error();
  auto code = std::make_shared<const std::vector<uint32_t>>(std::move(*compiled));
  std::lock_guard<std::mutex> lock(mu);
  return cache.emplace(key, std::move(code)).first->second;
}

// The specialisation constant ids (OpDecorate ... SpecId) a SPIR-V module declares, ascending.
std::vector<uint32_t> spec_ids(const std::vector<uint32_t>& code) {
  constexpr uint32_t kOpDecorate = 71, kDecorationSpecId = 1;
  std::vector<uint32_t> ids;
  for (size_t at = 5; at < code.size();) {  // after the 5-word header
    const uint32_t words = code[at] >> 16;
    if (words == 0) break;
    if ((code[at] & 0xffffu) == kOpDecorate && words >= 4 && at + 3 < code.size() &&
        code[at + 2] == kDecorationSpecId)
      ids.push_back(code[at + 3]);
    at += words;
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

// Whether a SPIR-V module uses the variable bound at `binding` (set 0): an instruction other than
// a name, a decoration, the declaration or the entry point's interface list names its id. A
// literal operand that happens to equal the id counts as a use (the answer errs towards true).
bool uses_binding(const std::vector<uint32_t>& code, uint32_t binding) {
  constexpr uint32_t kOpName = 5, kOpMemberName = 6, kOpEntryPoint = 15, kOpVariable = 59,
                     kOpDecorate = 71, kOpMemberDecorate = 72, kDecorationBinding = 33;
  std::vector<uint32_t> vars;
  auto each = [&](auto f) {
    for (size_t at = 5; at < code.size();) {
      const uint32_t words = code[at] >> 16;
      if (words == 0 || at + words > code.size()) return;
      f(code[at] & 0xffffu, &code[at], words);
      at += words;
    }
  };
  each([&](uint32_t op, const uint32_t* w, uint32_t words) {
    if (op == kOpDecorate && words >= 4 && w[2] == kDecorationBinding && w[3] == binding)
      vars.push_back(w[1]);
  });
  bool used = false;
  each([&](uint32_t op, const uint32_t* w, uint32_t words) {
    if (used || op == kOpName || op == kOpMemberName || op == kOpEntryPoint || op == kOpVariable ||
        op == kOpDecorate || op == kOpMemberDecorate)
      return;
    for (uint32_t k = 1; k < words && !used; ++k)
      used = std::find(vars.begin(), vars.end(), w[k]) != vars.end();
  });
  return used;
}

// Cold-cache compiles shared by the engines of one process (each worker has its own engine and
// device, and llvmpipe keeps a pipeline's compiled variants per device): the first submission that
// needs a shader variant compiles it and puts it in Mesa's disk cache (lp_state_cs.c,
// generate_variant: lp_disk_cache_insert_shader); a second engine that needs the same variant while
// that submission runs would compile it again, in parallel, on a cold cache. It waits for the
// first instead and then finds the variant in the disk cache. A variant is named by the pass's
// shader and the state of what is bound to it that llvmpipe compiles into the variant
// (make_variant_key: format, target and power-of-two extents of the images and textures); `done`
// holds the names submitted in this process, `running` those whose first submission runs now.
// Only a wait, never a different result: at worst (cache disabled or full) the engine compiles
// the variant itself after the wait.
class VariantGate {
 public:
  // Waits (at most `timeout`) while another engine runs the first submission of any of `names`,
  // then claims those not yet submitted; the returned list is passed to release().
  std::vector<std::string> acquire(const std::vector<std::string>& names,
                                   std::chrono::duration<double> timeout) {
    std::unique_lock<std::mutex> lock(mu_);
    cv_.wait_for(lock, timeout, [&] {
      return std::none_of(names.begin(), names.end(),
                          [&](const std::string& n) { return running_.count(n) > 0; });
    });
    std::vector<std::string> claimed;
    for (const std::string& n : names)
      if (!done_.count(n) && running_.insert(n).second) claimed.push_back(n);
    return claimed;
  }
  void release(const std::vector<std::string>& claimed) {
    if (claimed.empty()) return;
    {
      std::lock_guard<std::mutex> lock(mu_);
      for (const std::string& n : claimed) {
        running_.erase(n);
        done_.insert(n);
      }
    }
    cv_.notify_all();
  }

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  std::set<std::string> done_, running_;
};

VariantGate& variant_gate() {
  static VariantGate gate;
  return gate;
}

// Frees a buffer so that make_buffer can create it again.
void release(Buffer* b) {
  if (b->mapped) vkUnmapMemory(b->device, b->memory);
  if (b->buffer) vkDestroyBuffer(b->device, b->buffer, nullptr);
  if (b->memory) vkFreeMemory(b->device, b->memory, nullptr);
  b->mapped = nullptr;
  b->buffer = VK_NULL_HANDLE;
  b->memory = VK_NULL_HANDLE;
  b->size = 0;
}

void release(Texture* t) {
  if (t->view) vkDestroyImageView(t->device, t->view, nullptr);
  if (t->image) vkDestroyImage(t->device, t->image, nullptr);
  if (t->memory) vkFreeMemory(t->device, t->memory, nullptr);
  t->view = VK_NULL_HANDLE;
  t->image = VK_NULL_HANDLE;
  t->memory = VK_NULL_HANDLE;
}

// Clears `images` to `value` (0 by default) and moves them to GENERAL in a submission of their own,
// waited for.
Status clear_images_now(Gpu& g, std::initializer_list<VkImage> images,
                        const VkClearColorValue& value = {}) {
  const VkDevice d = g.device.handle;
  VkCommandBufferAllocateInfo cbai{};
  cbai.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  cbai.commandPool = g.command_pool.handle;
  cbai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cbai.commandBufferCount = 1;
  CaseWork::Commands cmds;
  cmds.device = d;
  cmds.pool = g.command_pool.handle;
  HDRC_VK(vkAllocateCommandBuffers(d, &cbai, &cmds.cmd));
  VkCommandBufferBeginInfo bi{};
  bi.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  HDRC_VK(vkBeginCommandBuffer(cmds.cmd, &bi));
  for (VkImage image : images) record_clear_to_general(cmds.cmd, image, value);
  HDRC_VK(vkEndCommandBuffer(cmds.cmd));
  VkSubmitInfo si{};
  si.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmds.cmd;
  HDRC_VK(vkQueueSubmit(g.queue, 1, &si, VK_NULL_HANDLE));
  HDRC_VK(vkQueueWaitIdle(g.queue));
  return {};
}

// A buffer of at least `size` bytes: the existing one when it is large enough, else a new one.
// Contents are left as they are (callers overwrite or clear what they use).
Status ensure_buffer(VkDevice device, const VkPhysicalDeviceMemoryProperties& mem,
                     VkDeviceSize size, VkBufferUsageFlags usage, Buffer* b) {
  if (b->buffer && b->size >= size) return {};
  release(b);
  return make_buffer(device, mem, size, usage, b);
}

// The header Vulkan puts at the start of pipeline cache data (Vulkan spec, "Pipeline Cache"):
// data from another device or driver is dropped before it reaches the driver.
bool pipeline_cache_matches(const std::string& data, const VkPhysicalDeviceProperties& props) {
  struct Header {
    uint32_t length, version, vendor, device;
    uint8_t uuid[VK_UUID_SIZE];
  } h;
  if (data.size() < sizeof h) return false;
  std::memcpy(&h, data.data(), sizeof h);
  return h.length >= sizeof h && h.version == VK_PIPELINE_CACHE_HEADER_VERSION_ONE &&
         h.vendor == props.vendorID && h.device == props.deviceID &&
         std::memcmp(h.uuid, props.pipelineCacheUUID, VK_UUID_SIZE) == 0;
}

std::string join_messages(const std::vector<std::string>& m) {
  std::string out;
  for (const auto& s : m) out += (out.empty() ? "" : "\n") + s;
  return out;
}

}  // namespace

// Owns every Vulkan object of the engine.
struct VulkanEngine::State {
  std::unique_ptr<Messages> messages;  // non-null with validation
  size_t physical_index = 0;           // the chosen device in vkEnumeratePhysicalDevices order
  uint32_t queue_family = 0;
  DeviceInfo info;
  double fence_timeout_s = 60;
  DeviceModel device_model = DeviceModel::kNone;
  VulkanOptions::Planted planted = VulkanOptions::Planted::kNone;  // tests only
  // SPIR-V per pass shader: compiled once for the whole run, kept across device re-creation.
  std::map<std::string, std::vector<uint32_t>> spirv;
  std::map<std::string, std::vector<uint32_t>> spec_ids_of;  // per shader: spec_ids(spirv)
  std::map<std::string, bool> uses_scratch_of;  // per shader: uses_binding(kBindingScratch)
  std::unique_ptr<Gpu> gpu;
  std::vector<Abandoned> abandoned;
  int generation = 0;
  std::string pipeline_cache_path;  // "" = no disk cache
  // The previous case's resources on the current device, for the next case.
  std::unique_ptr<CaseWork> spare;
  int reused = 0;

  // Writes the device's pipeline cache to disk (atomically; failures are ignored: the cache
  // only saves time).
  void save_pipeline_cache() {
    if (!gpu || !gpu->pipeline_cache.handle || pipeline_cache_path.empty() ||
        gpu->pipeline_creations == 0)
      return;
    size_t size = 0;
    const VkDevice d = gpu->device.handle;
    if (vkGetPipelineCacheData(d, gpu->pipeline_cache.handle, &size, nullptr) != VK_SUCCESS) return;
    std::string data(size, '\0');
    if (vkGetPipelineCacheData(d, gpu->pipeline_cache.handle, &size, data.data()) != VK_SUCCESS)
      return;
    data.resize(size);
    (void)write_file_atomic(pipeline_cache_path, data);
  }

  // Frees abandoned devices whose work has finished (or was lost).
  void reap() {
    std::erase_if(abandoned, [](Abandoned& a) {
      return vkGetFenceStatus(a.gpu->device.handle, a.work->fence.handle) != VK_NOT_READY;
    });
  }

  ~State() {
    if (gpu) vkDeviceWaitIdle(gpu->device.handle);
    save_pipeline_cache();
    spare.reset();
    gpu.reset();
    // Give abandoned work one more fence timeout to finish. A device whose work still runs after
    // that cannot be destroyed (its memory is in use): it is deliberately leaked, with its
    // instance, until the process exits.
    const uint64_t wait_ns = static_cast<uint64_t>(std::max(fence_timeout_s, 10.0) * 1e9);
    for (Abandoned& a : abandoned) {
      VkFence f = a.work->fence.handle;
      if (vkWaitForFences(a.gpu->device.handle, 1, &f, VK_TRUE, wait_ns) == VK_TIMEOUT) {
        (void)a.work.release();
        (void)a.gpu.release();
      }
    }
    abandoned.clear();
  }

  Status create_gpu();
  // The validation messages collected so far, as an error about `what` (empty message: none).
  Error validation_error(const std::string& what) {
    if (!messages) return {};
    const auto m = messages->take();
    if (m.empty()) return {};
    return Error{"", "",
                 "Vulkan validation reported " + std::to_string(m.size()) + " message(s) for " +
                     what + ":\n" + join_messages(m),
                 ""};
  }
  // The pipeline of `shader` with the values of `spec` for the specialisation constants it
  // declares (core/shader_interface.h kSpec*); `*variant` is set to what names that
  // specialisation ("" for a shader that declares none).
  Result<VkPipeline> pipeline(const std::string& shader_dir, const std::string& shader,
                              const std::array<uint32_t, kSpecCount>& spec, std::string* variant);
  Result<Image> run_passes(const ResolvedCase& c, const std::string& shader_dir, Gpu& g,
                           CaseWork& w, Fate* fate);
};

Status VulkanEngine::State::create_gpu() {
  auto g = std::make_unique<Gpu>();
  auto instance = create_instance(messages.get());
  if (!instance) {
    Error e = instance.error();
    e.message = "no Vulkan instance: " + e.message +
                (messages ? " (is vulkan-validationlayers installed?)" : "");
    return e;
  }
  g->instance.handle = *instance;
  if (messages) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(g->instance.handle, "vkCreateDebugUtilsMessengerEXT"));
    g->instance.destroy_messenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(g->instance.handle, "vkDestroyDebugUtilsMessengerEXT"));
    if (!create || !g->instance.destroy_messenger)
      return Error{"", "",
                   "VK_EXT_debug_utils is enabled but vkCreateDebugUtilsMessengerEXT is missing",
                   ""};
    const VkDebugUtilsMessengerCreateInfoEXT mi = messenger_info(messages.get());
    HDRC_VK(create(g->instance.handle, &mi, nullptr, &g->instance.messenger));
  }
  auto devices = describe_devices(g->instance.handle);
  if (!devices) return devices.error();
  if (physical_index >= devices->size() || (*devices)[physical_index].name != info.device)
    return Error{"", "", "the Vulkan device '" + info.device + "' is no longer available", ""};
  g->physical = (*devices)[physical_index].handle;
  vkGetPhysicalDeviceMemoryProperties(g->physical, &g->memory);
  VkPhysicalDeviceProperties props;
  vkGetPhysicalDeviceProperties(g->physical, &props);
  g->limits = props.limits;
  const VkPhysicalDeviceMemoryProperties& memory = g->memory;
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo qci{};
  qci.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  qci.queueFamilyIndex = queue_family;
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
  // The LUT store images are declared without a format (core/shader_interface.cpp), so that one
  // shader writes whichever storage format the case selects.
  VkPhysicalDeviceFeatures features{};
  features.shaderStorageImageWriteWithoutFormat = VK_TRUE;
  VkDeviceCreateInfo dci{};
  dci.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  dci.pEnabledFeatures = &features;
  HDRC_VK(vkCreateDevice(g->physical, &dci, nullptr, &g->device.handle));
  const VkDevice d = g->device.handle;
  vkGetDeviceQueue(d, queue_family, 0, &g->queue);
  g->command_pool.device = g->set_layout.device = g->pipeline_layout.device = g->sampler.device =
      g->pipelines.device = g->pipeline_cache.device = d;

  // The pipeline cache, seeded from disk when the file was written by this device and driver.
  {
    std::string data;
    if (!pipeline_cache_path.empty()) {
      std::ifstream in(pipeline_cache_path, std::ios::binary);
      if (in) data.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
      if (!pipeline_cache_matches(data, props)) data.clear();
    }
    VkPipelineCacheCreateInfo pcci{};
    pcci.sType = VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO;
    pcci.initialDataSize = data.size();
    pcci.pInitialData = data.empty() ? nullptr : data.data();
    if (vkCreatePipelineCache(d, &pcci, nullptr, &g->pipeline_cache.handle) != VK_SUCCESS) {
      pcci.initialDataSize = 0;  // data the driver rejects: start empty
      pcci.pInitialData = nullptr;
      HDRC_VK(vkCreatePipelineCache(d, &pcci, nullptr, &g->pipeline_cache.handle));
    }
  }

  VkCommandPoolCreateInfo pci{};
  pci.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pci.queueFamilyIndex = queue_family;
  HDRC_VK(vkCreateCommandPool(d, &pci, nullptr, &g->command_pool.handle));

  // One layout for every pass of every stage: bindings 0–10 of core/shader_interface.h.
  VkDescriptorSetLayoutBinding bindings[kBindingCount] = {};
  for (uint32_t i = 0; i < kBindingCount; ++i) {
    bindings[i].binding = i;
    bindings[i].descriptorCount = i == kBindingUserLut ? kUserLutSlots : 1;
    bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    bindings[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  }
  bindings[kBindingLutStore3d].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
  bindings[kBindingLutStore2d].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
  bindings[kBindingLut3d].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  bindings[kBindingLut2d].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  bindings[kBindingUserLut].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  VkDescriptorSetLayoutCreateInfo lci{};
  lci.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
  lci.bindingCount = kBindingCount;
  lci.pBindings = bindings;
  HDRC_VK(vkCreateDescriptorSetLayout(d, &lci, nullptr, &g->set_layout.handle));
  VkPipelineLayoutCreateInfo plci{};
  plci.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
  plci.setLayoutCount = 1;
  plci.pSetLayouts = &g->set_layout.handle;
  HDRC_VK(vkCreatePipelineLayout(d, &plci, nullptr, &g->pipeline_layout.handle));

  // The Tonemap pass samples the LUT as UE does (PostProcessTonemap.usf: ColorLookupTable, with
  // the bilinear clamped sampler of PostProcessTonemap.cpp): linear filtering, clamp to edge,
  // normalised coordinates, one mip level.
  VkSamplerCreateInfo sci{};
  sci.sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO;
  sci.magFilter = VK_FILTER_LINEAR;
  sci.minFilter = VK_FILTER_LINEAR;
  sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  sci.maxLod = 0.0f;
  sci.unnormalizedCoordinates = VK_FALSE;
  HDRC_VK(vkCreateSampler(d, &sci, nullptr, &g->sampler.handle));

  VkFormat dummy_format = VK_FORMAT_R16G16B16A16_SFLOAT;
  {
    VkFormatProperties fp;
    vkGetPhysicalDeviceFormatProperties(g->physical, kBakeFormat, &fp);
    const VkFormatFeatureFlags want =
        VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT |
        VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT | VK_FORMAT_FEATURE_TRANSFER_DST_BIT;
    if ((fp.optimalTilingFeatures & want) == want) dummy_format = kBakeFormat;
  }
  if (auto st = make_texture(d, memory, VK_IMAGE_TYPE_3D, dummy_format, {1, 1, 1}, &g->dummy_3d);
      !st)
    return st;
  if (auto st = make_texture(d, memory, VK_IMAGE_TYPE_2D, dummy_format, {1, 1, 1}, &g->dummy_2d);
      !st)
    return st;
  if (auto st = make_buffer(d, memory, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, &g->dummy_buffer);
      !st)
    return st;

  // The dummies go to GENERAL, cleared, once per device: to 0, or under the worst-case model
  // poisoned (no pass may depend on what a dummy holds: a stage reads an aux image only when its
  // size in the block is not 0 × 0, a user LUT only when P.user_lut_size is not 0, and the LUT of
  // the layout the case does not use not at all).
  const bool worst = device_model == DeviceModel::kWorst;
  if (worst) fill_words(g->dummy_buffer.mapped, g->dummy_buffer.size, kPoisonWord);
  if (Status st = clear_images_now(*g, {g->dummy_3d.image, g->dummy_2d.image},
                                   worst ? poison_color(dummy_format) : VkClearColorValue{});
      !st)
    return st;

  gpu = std::move(g);
  ++generation;
  return {};
}

Result<VkPipeline> VulkanEngine::State::pipeline(const std::string& shader_dir,
                                                 const std::string& shader,
                                                 const std::array<uint32_t, kSpecCount>& spec,
                                                 std::string* variant) {
  auto code = spirv.find(shader);
  if (code == spirv.end()) {
    auto compiled = shared_spirv(shader_dir, shader, device_model);
    if (!compiled) return compiled.error();
    code = spirv.emplace(shader, **compiled).first;
  }
  // A shader that declares specialisation constants has a pipeline per combination of their
  // values (by_shader's key: the shader and "spec id=value ..."); the others one pipeline.
  auto ids = spec_ids_of.find(shader);
  if (ids == spec_ids_of.end()) ids = spec_ids_of.emplace(shader, spec_ids(code->second)).first;
  if (!uses_scratch_of.count(shader))
    uses_scratch_of.emplace(shader, uses_binding(code->second, kBindingScratch));
  std::vector<VkSpecializationMapEntry> entries;
  std::vector<uint32_t> values;
  variant->clear();
  for (uint32_t id : ids->second) {
    if (id >= kSpecCount) continue;  // not one of the engine's: the shader's default
    entries.push_back(
        {id, static_cast<uint32_t>(values.size() * sizeof(uint32_t)), sizeof(uint32_t)});
    values.push_back(spec[id]);
    *variant +=
        (variant->empty() ? " spec " : " ") + std::to_string(id) + '=' + std::to_string(spec[id]);
  }
  const std::string key = shader + *variant;
  if (auto it = gpu->pipelines.by_shader.find(key); it != gpu->pipelines.by_shader.end())
    return it->second;
  const VkDevice d = gpu->device.handle;
  VkShaderModuleCreateInfo mci{};
  mci.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
  mci.codeSize = code->second.size() * sizeof(uint32_t);
  mci.pCode = code->second.data();
  VkShaderModule module = VK_NULL_HANDLE;
  HDRC_VK(vkCreateShaderModule(d, &mci, nullptr, &module));
  VkComputePipelineCreateInfo cpci{};
  cpci.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
  // Dispatch base: a domain larger than maxComputeWorkGroupCount[0] is split into several
  // dispatches with a group offset, invisible to the shader (gl_GlobalInvocationID includes it).
  cpci.flags = VK_PIPELINE_CREATE_DISPATCH_BASE_BIT;
  cpci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  cpci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  cpci.stage.module = module;
  cpci.stage.pName = "main";
  VkSpecializationInfo si{};
  si.mapEntryCount = static_cast<uint32_t>(entries.size());
  si.pMapEntries = entries.data();
  si.dataSize = values.size() * sizeof(uint32_t);
  si.pData = values.data();
  if (!entries.empty()) cpci.stage.pSpecializationInfo = &si;
  cpci.layout = gpu->pipeline_layout.handle;
  VkPipeline p = VK_NULL_HANDLE;
  const VkResult r = vkCreateComputePipelines(d, gpu->pipeline_cache.handle, 1, &cpci, nullptr, &p);
  ++gpu->pipeline_creations;
  vkDestroyShaderModule(d, module, nullptr);
  if (r != VK_SUCCESS) return vk_error("vkCreateComputePipelines", r);
  // A pipeline the validation layer objects to is not used (dispatching it is undefined
  // behaviour) nor cached: every case that needs it reports the messages.
  if (Error e = validation_error(shader); !e.message.empty()) {
    vkDestroyPipeline(d, p, nullptr);
    return e;
  }
  gpu->pipelines.by_shader.emplace(key, p);
  return p;
}

VulkanEngine::VulkanEngine(VulkanOptions options) : options_(std::move(options)) {
  if (options_.shader_dir.empty()) options_.shader_dir = default_shader_dir();
}
VulkanEngine::~VulkanEngine() = default;

int VulkanEngine::compiled_pipeline_count() const {
  return state_ && state_->gpu ? static_cast<int>(state_->gpu->pipelines.by_shader.size()) : 0;
}
int VulkanEngine::pipeline_creations() const {
  return state_ && state_->gpu ? state_->gpu->pipeline_creations : 0;
}
int VulkanEngine::reused_work_count() const {
  return state_ ? state_->reused : 0;
}
int VulkanEngine::abandoned_device_count() const {
  return state_ ? static_cast<int>(state_->abandoned.size()) : 0;
}
int VulkanEngine::device_generation() const {
  return state_ ? state_->generation : 0;
}

Status VulkanEngine::init() {
  auto s = std::make_unique<State>();
  s->fence_timeout_s = options_.fence_timeout_s;
  s->device_model = options_.device_model;
  s->planted = options_.planted;
  s->pipeline_cache_path = options_.pipeline_cache_path.empty()     ? default_pipeline_cache_path()
                           : options_.pipeline_cache_path == "none" ? ""
                                                                    : options_.pipeline_cache_path;
  if (options_.validation) s->messages = std::make_unique<Messages>();
  // Device selection on a temporary instance; create_gpu() then makes the engine's own.
  auto instance = create_instance(nullptr);
  if (!instance) {
    Error e = instance.error();
    e.message = "no Vulkan instance: " + e.message;
    return e;
  }
  struct TemporaryInstance {
    VkInstance handle;
    ~TemporaryInstance() { vkDestroyInstance(handle, nullptr); }
  } temporary{*instance};
  auto devices = describe_devices(temporary.handle);
  if (!devices) return devices.error();
  if (devices->empty()) return Error{"", "", "no Vulkan physical devices found", ""};

  std::string known;
  for (size_t i = 0; i < devices->size(); ++i)
    known += (known.empty() ? "" : ", ") + std::to_string(i) + " '" + (*devices)[i].name + "'";
  const DeviceDescription* chosen = nullptr;
  // HDRC_VK_DEVICE: the default device where none is given (the whole test suite on a GPU).
  const char* env_device = std::getenv("HDRC_VK_DEVICE");
  const bool from_env = options_.device.empty() && env_device;
  const std::string want = from_env ? std::string(env_device) : options_.device;
  const std::string named = from_env ? "HDRC_VK_DEVICE=" : "--device ";  // where `want` came from
  if (want.empty()) {
    for (const auto& d : *devices)
      if (lower(d.name).find("llvmpipe") != std::string::npos) chosen = &d;
    if (!chosen)
      return Error{"", "",
                   "lavapipe (llvmpipe) not found among the Vulkan devices; install "
                   "mesa-vulkan-drivers or choose one with --device",
                   known};
  } else if (std::all_of(want.begin(), want.end(), ::isdigit)) {
    const size_t index = std::stoul(want);
    if (index >= devices->size())
      return Error{"", "", named + want + ": no Vulkan device with that index", known};
    chosen = &(*devices)[index];
  } else {
    for (const auto& d : *devices)
      if (lower(d.name).find(lower(want)) != std::string::npos) {
        chosen = &d;
        break;
      }
    if (!chosen) return Error{"", "", named + "'" + want + "': no Vulkan device matches", known};
  }
  const VkPhysicalDevice physical = chosen->handle;
  s->physical_index = static_cast<size_t>(chosen - devices->data());
  s->info = {"vulkan", chosen->name, chosen->driver, version_string(chosen->api_version),
             device_precision(physical, chosen->api_version, options_.device_model)};
  VkPhysicalDeviceFeatures features;
  vkGetPhysicalDeviceFeatures(physical, &features);
  if (!features.shaderStorageImageWriteWithoutFormat)
    return Error{"", "",
                 "device '" + chosen->name +
                     "' lacks the shaderStorageImageWriteWithoutFormat feature (the LUT store "
                     "images are declared without a format)",
                 ""};

  uint32_t nq = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical, &nq, nullptr);
  std::vector<VkQueueFamilyProperties> families(nq);
  vkGetPhysicalDeviceQueueFamilyProperties(physical, &nq, families.data());
  bool found = false;
  for (uint32_t i = 0; i < nq && !found; ++i)
    if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
      s->queue_family = i;
      found = true;
    }
  if (!found) return Error{"", "", "device '" + chosen->name + "' has no compute queue", ""};
  if (Status st = s->create_gpu(); !st) return st;
  if (s->messages) {
    const auto m = s->messages->take();
    if (!m.empty())
      return Error{"", "",
                   "Vulkan validation reported " + std::to_string(m.size()) +
                       " message(s) while starting:\n" + join_messages(m),
                   ""};
  }
  state_ = std::move(s);
  return {};
}

DeviceInfo VulkanEngine::device() const {
  return state_ ? state_->info : DeviceInfo{"vulkan", "(not initialised)", "", "", {}};
}

namespace {

// Checks that the device can hold the LUT in `f` as the stages use it; the error names the format
// and what is missing.
Status check_lut_format(VkPhysicalDevice physical, const std::string& device_name,
                        const LutFormat& f, VkImageType type, VkExtent3D extent) {
  VkFormatProperties props;
  vkGetPhysicalDeviceFormatProperties(physical, f.format, &props);
  const VkFormatFeatureFlags have = props.optimalTilingFeatures;
  std::string missing;
  const std::pair<VkFormatFeatureFlags, const char*> needed[] = {
      {VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT, "storage image (CombineLUTs writes it)"},
      {VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT, "sampled image (the Tonemap pass reads it)"},
      {VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT,
       "linear filtering (the Tonemap pass's trilinear lookup)"},
      {VK_FORMAT_FEATURE_TRANSFER_SRC_BIT, "transfer source (read back)"},
      {VK_FORMAT_FEATURE_TRANSFER_DST_BIT, "transfer destination (cleared before the bake)"},
  };
  for (const auto& [bit, what] : needed)
    if (!(have & bit)) missing += (missing.empty() ? "" : ", ") + std::string(what);
  if (!missing.empty())
    return Error{"", "",
                 std::string("LUT format ") + f.name + " is not usable on '" + device_name +
                     "': it lacks " + missing,
                 ""};
  VkImageFormatProperties ip;
  const VkResult r = vkGetPhysicalDeviceImageFormatProperties(
      physical, f.format, type, VK_IMAGE_TILING_OPTIMAL, kLutUsage, 0, &ip);
  const char* shape = type == VK_IMAGE_TYPE_3D ? "3-D" : "2-D";
  if (r == VK_ERROR_FORMAT_NOT_SUPPORTED)
    return Error{"", "",
                 std::string("LUT format ") + f.name + " is not supported for a " + shape +
                     " storage/sampled image on '" + device_name + "'",
                 ""};
  if (r != VK_SUCCESS) return vk_error("vkGetPhysicalDeviceImageFormatProperties", r);
  if (extent.width > ip.maxExtent.width || extent.height > ip.maxExtent.height ||
      extent.depth > ip.maxExtent.depth)
    return Error{"", "",
                 std::string("a ") + shape + " LUT of " + std::to_string(extent.width) + "x" +
                     std::to_string(extent.height) + "x" + std::to_string(extent.depth) + " in " +
                     f.name + " exceeds the device's maximum " +
                     std::to_string(ip.maxExtent.width) + "x" +
                     std::to_string(ip.maxExtent.height) + "x" + std::to_string(ip.maxExtent.depth),
                 ""};
  return {};
}

// The LUT read back from its image into ref::lut_image's layout: N² × N, texel (r, g, b) at
// (r + N·b, g), every stored bit decoded exactly.
Image decode_lut(const void* bytes, const LutFormat& f, int layout, int n) {
  Image out(n * n, n);
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) {
        // Tightly packed copy: volume texel (x, y, z) = (r, g, b); 2-D texel (r + N·b, g).
        const size_t index = layout == 0 ? (static_cast<size_t>(b) * n + g) * n + r
                                         : static_cast<size_t>(g) * n * n + r + n * b;
        const auto* p = static_cast<const uint8_t*>(bytes) + index * f.texel_bytes;
        double* o = out.px(r + n * b, g);
        if (f.format == VK_FORMAT_A2B10G10R10_UNORM_PACK32) {
          uint32_t t;
          std::memcpy(&t, p, 4);
          const auto v = decode_a2b10g10r10(t);
          for (int c = 0; c < 4; ++c) o[c] = v[c];
        } else if (f.format == VK_FORMAT_R8G8B8A8_UNORM) {
          for (int c = 0; c < 4; ++c) o[c] = p[c] / 255.0;
        } else if (f.format == VK_FORMAT_R16G16B16A16_SFLOAT) {
          for (int c = 0; c < 4; ++c) {
            uint16_t h;
            std::memcpy(&h, p + 2 * c, 2);
            o[c] = decode_half(h);
          }
        } else {
          for (int c = 0; c < 4; ++c) {
            float v;
            std::memcpy(&v, p + 4 * c, 4);
            o[c] = v;
          }
        }
      }
  return out;
}

uint64_t invocations(Dispatch domain, size_t pixels, int lut_size) {
  switch (domain) {
    case Dispatch::kPixels:
      return pixels;
    case Dispatch::kLutTexels:
      return static_cast<uint64_t>(lut_size) * lut_size * lut_size;
    case Dispatch::kOneGroup:
      return kLocalSizeX;
  }
  return 0;
}

// From this many pixels on, the host's work on a case's buffers is split over two threads.
constexpr size_t kParallelHostPixels = size_t{1} << 20;

void upload(const Image& img, Buffer* b) {
  float* dst = static_cast<float*>(b->mapped);
  for (size_t i = 0; i < img.data.size(); ++i) dst[i] = static_cast<float>(img.data[i]);
}

// The output image, each float widened exactly to double. The vector is filled from the floats
// directly (no zero-filling pass first), and a large one is backed by transparent huge pages where
// the kernel offers them (MADV_HUGEPAGE; "madvise" mode): a 4K image of doubles is 265 MB of fresh
// memory per case, whose 4 KiB page faults cost more than the copy.
Image widen_output(const float* src, int width, int height) {
  Image out;
  out.width = width;
  out.height = height;
  const size_t n = out.pixel_count() * Image::kChannels;
  out.data.reserve(n);
  constexpr size_t kHuge = size_t{2} << 20;
  std::thread faulting;
  if (n * sizeof(double) >= 4 * kHuge) {
    const auto begin = reinterpret_cast<uintptr_t>(out.data.data());
    const uintptr_t first = (begin + kHuge - 1) & ~(kHuge - 1);
    const uintptr_t last = (begin + n * sizeof(double)) & ~(kHuge - 1);
    if (last > first) (void)madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#ifdef MADV_POPULATE_WRITE
    // A large image's page faults (the kernel zeroing each page) are split over two threads: a
    // second thread has the kernel populate the upper half (MADV_POPULATE_WRITE, Linux 5.14; an
    // older kernel refuses it and the copy faults those pages itself) while the copy faults in
    // the lower half. Only the kernel writes to the vector's capacity there.
    if (out.pixel_count() >= kParallelHostPixels) {
      const uintptr_t mid = (first + (last - first) / 2) & ~(kHuge - 1);
      if (last > mid)
        faulting = std::thread([mid, last] {
          (void)madvise(reinterpret_cast<void*>(mid), last - mid, MADV_POPULATE_WRITE);
        });
    }
#endif
  }
  out.data.assign(src, src + n);
  if (faulting.joinable()) faulting.join();
  return out;
}

#define HDRC_VK_CASE(call)                                     \
  do {                                                         \
    const VkResult hdrc_r = (call);                            \
    if (hdrc_r != VK_SUCCESS) {                                \
      if (hdrc_r == VK_ERROR_DEVICE_LOST) *fate = Fate::kLost; \
      return vk_error(#call, hdrc_r);                          \
    }                                                          \
  } while (0)

}  // namespace

// Runs every pass of the case's stage in one submission. `fate` tells the caller whether the
// device can be reused.
Result<Image> VulkanEngine::State::run_passes(const ResolvedCase& c, const std::string& shader_dir,
                                              Gpu& g, CaseWork& w, Fate* fate) {
  State& s = *this;
  const StageInfo& stage = *c.spec.stage;
  const VkDevice d = g.device.handle;
  const std::string stage_name(stage.name);

  // The dispatches: the stage's passes, each LUT bake pass (domain lut_texels) followed by the
  // engine's store pass. The bake pass writes the float32 values it stores to the bake image
  // (kBakeFormat); the store pass writes each of them with imageStore to the LUT image of the
  // case's format and layout, the store that does the format's conversion, as the bake pass's
  // own store would. llvmpipe compiles a shader variant per format, target and
  // power-of-two-ness of the images a shader uses (make_variant_key): the large bake shader
  // then has one variant for every format, layout and size, and only the small store shader one
  // per LUT image.
  enum class Role { kPass, kBake, kStore };
  struct Run {
    std::string shader;  // shader_dir/shader and its specialisation, naming its variants for the
                         // VariantGate
    VkPipeline pipeline;
    Dispatch domain;
    bool output_to_scratch;
    Role role;
  };
  // Parameters: the case's block; only the aux image sizes are filled in here, from what is bound.
  ParamBlock params = c.params;
  const Image* aux0 = nullptr;
  const Image* aux1 = nullptr;
  if (stage.bloom_inputs) {
    if (!c.bloom.data.empty()) aux0 = &c.bloom;
    if (!c.bloom_dirt.data.empty()) aux1 = &c.bloom_dirt;
  } else if (stage.id == StageId::kUiComposite) {
    if (c.ui.pixel_count() != c.input.pixel_count())
      return Error{"", "",
                   "ui_composite: the UI layer is " + std::to_string(c.ui.width) + "x" +
                       std::to_string(c.ui.height) + ", the back buffer " +
                       std::to_string(c.input.width) + "x" + std::to_string(c.input.height),
                   ""};
    aux0 = &c.ui;
  }
  params.aux0_width = aux0 ? aux0->width : 0;
  params.aux0_height = aux0 ? aux0->height : 0;
  params.aux1_width = aux1 ? aux1->width : 0;
  params.aux1_height = aux1 ? aux1->height : 0;

  // The specialisation of each pass's shader: from the block as the shaders will read it.
  const std::array<uint32_t, kSpecCount> spec = specialisation_constants(params);
  std::vector<Run> runs;
  bool uses_scratch = false;  // whether a pass reads or writes the scratch buffer
  for (const StagePass& pass : stage.passes) {
    std::string variant;
    auto p = s.pipeline(shader_dir, std::string(pass.shader), spec, &variant);
    if (!p) return p.error();
    uses_scratch =
        uses_scratch || pass.output_to_scratch || s.uses_scratch_of[std::string(pass.shader)];
    const bool bake = pass.domain == Dispatch::kLutTexels;
    runs.push_back({shader_dir + '/' + std::string(pass.shader) + variant, *p, pass.domain,
                    pass.output_to_scratch, bake ? Role::kBake : Role::kPass});
    if (!bake) continue;
    auto store = s.pipeline(default_shader_dir(), kLutStoreShader, spec, &variant);
    if (!store) return store.error();
    uses_scratch = uses_scratch || s.uses_scratch_of[kLutStoreShader];
    runs.push_back({default_shader_dir() + '/' + kLutStoreShader + variant, *store,
                    Dispatch::kLutTexels, false, Role::kStore});
  }

  const size_t pixels = c.input.pixel_count();
  const int n = params.lut_size;
  const bool bakes_lut =
      std::any_of(stage.passes.begin(), stage.passes.end(),
                  [](const StagePass& p) { return p.domain == Dispatch::kLutTexels; });
  const LutFormat* fmt = nullptr;
  bool lut_reused = false;  // the LUT image is the case before's (for Planted::kStaleLutOnReuse)
  if (bakes_lut) {
    if (params.lut_format < 0 || params.lut_format > 3)
      return Error{"", "", "LUT format " + std::to_string(params.lut_format) + " is not supported",
                   "0 (A2B10G10R10), 1 (RGBA16F), 2 (RGBA32F), 3 (RGBA8)"};
    if (params.lut_layout != 0 && params.lut_layout != 1)
      return Error{"", "", "LUT layout " + std::to_string(params.lut_layout) + " is not supported",
                   "0 (volume), 1 (2-D unwrapped)"};
    if (n < 2 || n > 256)
      return Error{"", "", "LUT size " + std::to_string(n) + " is out of range", "2-256"};
    fmt = &kLutFormats[params.lut_format];
    const VkImageType type = params.lut_layout == 0 ? VK_IMAGE_TYPE_3D : VK_IMAGE_TYPE_2D;
    const VkExtent3D extent = params.lut_layout == 0
                                  ? VkExtent3D{uint32_t(n), uint32_t(n), uint32_t(n)}
                                  : VkExtent3D{uint32_t(n * n), uint32_t(n), 1};
    if (Status st = check_lut_format(g.physical, s.info.device, *fmt, type, extent); !st)
      return st.error();
    if (w.lut.image &&
        (w.lut_format != params.lut_format || w.lut_layout != params.lut_layout || w.lut_size != n))
      release(&w.lut);
    lut_reused = w.lut.image != VK_NULL_HANDLE;
    if (!w.lut.image) {
      w.lut_format = w.lut_layout = w.lut_size = -1;
      if (Status st = make_texture(d, g.memory, type, fmt->format, extent, &w.lut); !st)
        return st.error();
      w.lut_format = params.lut_format;
      w.lut_layout = params.lut_layout;
      w.lut_size = n;
    }
    // An extent rounded up past the device's maximum image dimension stays as it is (a
    // variant more, never a failure).
    const uint32_t max_dim =
        params.lut_layout == 0 ? g.limits.maxImageDimension3D : g.limits.maxImageDimension2D;
    auto rounded = [&](uint32_t v) { return std::bit_ceil(v) <= max_dim ? std::bit_ceil(v) : v; };
    Texture& bake = w.bake[params.lut_layout];
    VkExtent3D& have = w.bake_extent[params.lut_layout];
    // Per dimension: what the image has if that will do, else what is needed, grown to the
    // larger of the two where both are powers of two.
    auto dim = [&](uint32_t has, uint32_t need) {
      const uint32_t want = rounded(need);
      if (has == want || (has > want && std::has_single_bit(has) && std::has_single_bit(want)))
        return has;
      return std::has_single_bit(has) && std::has_single_bit(want) ? std::max(has, want) : want;
    };
    const VkExtent3D bake_extent{dim(have.width, extent.width), dim(have.height, extent.height),
                                 dim(have.depth, extent.depth)};
    if (bake.image && (bake_extent.width != have.width || bake_extent.height != have.height ||
                       bake_extent.depth != have.depth))
      release(&bake);
    if (!bake.image) {
      have = {};
      if (Status st = make_texture(d, g.memory, type, kBakeFormat, bake_extent, &bake); !st)
        return st.error();
      have = bake_extent;
    }
  }

  // The user LUTs: the strip textures the loader made from the case's .cube files
  // (ResolvedCase::user_luts), RGBA32F so that every float32 value of a .cube reaches the sampler
  // unchanged. A stage that stores its LUTs 8-bit (StageInfo::user_lut_unorm8, UE's BGRA8) gets
  // values the loader rounded to k/255 already: the texels a UNORM texture holds. They are bound
  // as RGBA32F all the same because lavapipe filters UNORM8 textures in 8-bit fixed point and
  // rounds the filtered result to 8 bits (up to 1/255 off; docs/precision.md), which UE's sampler
  // on desktop hardware does not.
  const LutFormat& user_lut_fmt = kLutFormats[2];
  std::array<bool, kUserLutSlots> has_user_lut{};
  for (size_t slot = 0; slot < kUserLutSlots; ++slot) {
    const Image& strip = c.user_luts[slot];
    has_user_lut[slot] = !strip.data.empty();
    if (!has_user_lut[slot]) continue;
    const int un = params.user_lut_size;
    if (un < 2 || un > 256 || strip.width != un * un || strip.height != un)
      return Error{"", "",
                   "the user LUT texture in slot " + std::to_string(slot) + " is " +
                       std::to_string(strip.width) + "x" + std::to_string(strip.height) +
                       " for user_lut_size " + std::to_string(un),
                   "a strip N^2 x N, N 2-256"};
    const VkExtent3D extent{uint32_t(un * un), uint32_t(un), 1};
    if (Status st =
            check_lut_format(g.physical, s.info.device, user_lut_fmt, VK_IMAGE_TYPE_2D, extent);
        !st)
      return st.error();
    Texture& tex = w.user_lut[slot];
    if (tex.image &&
        (w.user_lut_size[slot] != un || w.user_lut_format[slot] != user_lut_fmt.format))
      release(&tex);
    if (!tex.image) {
      w.user_lut_size[slot] = -1;
      if (Status st =
              make_texture(d, g.memory, VK_IMAGE_TYPE_2D, user_lut_fmt.format, extent, &tex);
          !st)
        return st.error();
      w.user_lut_size[slot] = un;
      w.user_lut_format[slot] = user_lut_fmt.format;
    }
    const VkDeviceSize bytes = strip.pixel_count() * user_lut_fmt.texel_bytes;
    if (Status st = ensure_buffer(d, g.memory, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                  &w.user_lut_staging[slot]);
        !st)
      return st.error();
    float* dst = static_cast<float*>(w.user_lut_staging[slot].mapped);
    for (size_t i = 0; i < strip.data.size(); ++i) dst[i] = static_cast<float>(strip.data[i]);
  }

  // Buffers. Sizes are at least 16 bytes (a zero-sized buffer is invalid). Every storage buffer
  // holds its data and then kGuardBytes of canary words (kCanaryWord), both in the range bound.
  const std::vector<uint8_t> packed = pack_std430(params);
  const VkBufferUsageFlags storage =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  const VkDeviceSize image_bytes = std::max<VkDeviceSize>(pixels * 16, 16);
  const bool worst = s.device_model == DeviceModel::kWorst;
  // Buffers are reused across cases (grown when too small). What a shader may read before
  // writing is cleared to zero in the range this case uses, as a fresh buffer would be, so the
  // output never depends on the case before (under the worst-case model: poisoned instead, on the
  // device, below).
  if (Status st = ensure_buffer(d, g.memory, packed.size() + kGuardBytes, storage, &w.params); !st)
    return st.error();
  if (Status st = ensure_buffer(d, g.memory, image_bytes + kGuardBytes, storage, &w.input); !st)
    return st.error();
  if (Status st = ensure_buffer(d, g.memory, image_bytes + kGuardBytes, storage, &w.output); !st)
    return st.error();
  // Scratch: an image of the case's size for a pass with output_to_scratch, then 1024 vec4 of
  // free space (e.g. VisualizeHDR's histogram) at scratch_px[width·height ...].
  const VkDeviceSize scratch_bytes = (pixels + 1024) * 16;
  if (Status st = ensure_buffer(d, g.memory, scratch_bytes + kGuardBytes, storage, &w.scratch); !st)
    return st.error();
  std::memcpy(w.params.mapped, packed.data(), packed.size());
  {
    // A large image's conversion and the two clears (hundreds of MB at 4K) run side by side: the
    // device's threads are idle until the submission, and each part writes its own buffer. The
    // scratch buffer is cleared only for a stage that uses it: no pass of the others can see it.
    auto clear = [&] {
      if (worst) return;  // poisoned by the device instead
      std::memset(w.output.mapped, 0, image_bytes);
      if (uses_scratch) std::memset(w.scratch.mapped, 0, scratch_bytes);
    };
    if (pixels >= kParallelHostPixels) {
      std::thread clearing(clear);
      upload(c.input, &w.input);
      clearing.join();
    } else {
      upload(c.input, &w.input);
      clear();
    }
  }
  for (auto [img, buf] : {std::pair{aux0, &w.aux0}, std::pair{aux1, &w.aux1}}) {
    if (!img) continue;
    const VkDeviceSize bytes = std::max<VkDeviceSize>(img->pixel_count() * 16, 16);
    if (Status st = ensure_buffer(d, g.memory, bytes + kGuardBytes, storage, buf); !st)
      return st.error();
    upload(*img, buf);
  }
  // The guarded buffers of this case and how much data each binding's range holds before its
  // guard. The canaries are written now and checked after the submission.
  struct Guarded {
    const char* name;  // the GLSL name and binding
    Buffer* buffer;
    VkDeviceSize data_bytes;
  };
  std::vector<Guarded> guarded = {{"P (binding 0)", &w.params, packed.size()},
                                  {"in_px (binding 1)", &w.input, image_bytes},
                                  {"out_px (binding 2)", &w.output, image_bytes},
                                  {"scratch_px (binding 9)", &w.scratch, scratch_bytes}};
  if (aux0) guarded.push_back({"aux0_px (binding 7)", &w.aux0, aux0->pixel_count() * 16});
  if (aux1) guarded.push_back({"aux1_px (binding 8)", &w.aux1, aux1->pixel_count() * 16});
  for (Guarded& b : guarded) {
    b.data_bytes = std::max<VkDeviceSize>(b.data_bytes, 16);
    fill_words(static_cast<uint8_t*>(b.buffer->mapped) + b.data_bytes, kGuardBytes, kCanaryWord);
  }
  // A stage whose last pass bakes the LUT outputs the LUT itself (read back as N² × N).
  const bool reads_back = bakes_lut && stage.passes.back().domain == Dispatch::kLutTexels;
  if (reads_back) {
    const VkDeviceSize bytes = static_cast<VkDeviceSize>(n) * n * n * fmt->texel_bytes;
    if (Status st =
            ensure_buffer(d, g.memory, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, &w.readback);
        !st)
      return st.error();
  }

  // One descriptor set per dispatch (they differ in binding 2 for output_to_scratch and in the
  // LUT bindings of the bake and store passes).
  const uint32_t sets = static_cast<uint32_t>(runs.size());
  if (w.descriptor_pool.handle && w.descriptor_capacity < sets) {
    vkDestroyDescriptorPool(d, w.descriptor_pool.handle, nullptr);
    w.descriptor_pool.handle = VK_NULL_HANDLE;
  }
  if (w.descriptor_pool.handle) {
    HDRC_VK_CASE(vkResetDescriptorPool(d, w.descriptor_pool.handle, 0));
  } else {
    // Room for the largest stage (VisualizeHDR: 4 passes and the store pass), so one pool
    // serves every case.
    const uint32_t capacity = std::max<uint32_t>(sets, 5);
    const VkDescriptorPoolSize pool_sizes[] = {
        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 6 * capacity},
        {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 2 * capacity},
        {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, (2 + kUserLutSlots) * capacity}};
    VkDescriptorPoolCreateInfo dpci{};
    dpci.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
    dpci.maxSets = capacity;
    dpci.poolSizeCount = 3;
    dpci.pPoolSizes = pool_sizes;
    w.descriptor_pool.device = d;
    HDRC_VK_CASE(vkCreateDescriptorPool(d, &dpci, nullptr, &w.descriptor_pool.handle));
    w.descriptor_capacity = capacity;
  }
  std::vector<VkDescriptorSetLayout> layouts(sets, g.set_layout.handle);
  std::vector<VkDescriptorSet> descriptor_sets(sets);
  VkDescriptorSetAllocateInfo dsai{};
  dsai.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
  dsai.descriptorPool = w.descriptor_pool.handle;
  dsai.descriptorSetCount = sets;
  dsai.pSetLayouts = layouts.data();
  HDRC_VK_CASE(vkAllocateDescriptorSets(d, &dsai, descriptor_sets.data()));

  const bool volume = bakes_lut && params.lut_layout == 0;
  const bool unwrapped = bakes_lut && params.lut_layout == 1;
  // The LUT's format dummies, made on this device's first case in the format.
  if (bakes_lut && !g.format_dummy_3d[params.lut_format].image) {
    Texture& d3 = g.format_dummy_3d[params.lut_format];
    Texture& d2 = g.format_dummy_2d[params.lut_format];
    Status st = make_texture(d, g.memory, VK_IMAGE_TYPE_3D, fmt->format, {1, 1, 1}, &d3);
    if (st) st = make_texture(d, g.memory, VK_IMAGE_TYPE_2D, fmt->format, {1, 1, 1}, &d2);
    if (st)
      st = clear_images_now(
          g, {d3.image, d2.image},
          s.device_model == DeviceModel::kWorst ? poison_color(fmt->format) : VkClearColorValue{});
    if (!st) {
      release(&d3);
      release(&d2);
      return st.error();
    }
  }
  const VkImageView view_3d = volume      ? w.lut.view
                              : unwrapped ? g.format_dummy_3d[params.lut_format].view
                                          : g.dummy_3d.view;
  const VkImageView view_2d = unwrapped ? w.lut.view
                              : volume  ? g.format_dummy_2d[params.lut_format].view
                                        : g.dummy_2d.view;
  const VkImageView bake_3d = volume ? w.bake[0].view : g.dummy_3d.view;
  const VkImageView bake_2d = unwrapped ? w.bake[1].view : g.dummy_2d.view;
  // Each binding sees exactly this case's range and its guard (a reused buffer may be larger).
  auto aux_of = [&](const Image* img, const Buffer& b) -> VkDescriptorBufferInfo {
    if (!img) return {g.dummy_buffer.buffer, 0, VK_WHOLE_SIZE};
    return {b.buffer, 0, std::max<VkDeviceSize>(img->pixel_count() * 16, 16) + kGuardBytes};
  };
  for (uint32_t i = 0; i < sets; ++i) {
    const Role role = runs[i].role;
    const VkDeviceSize guard = kGuardBytes;
    const VkDescriptorBufferInfo out =
        runs[i].output_to_scratch
            ? VkDescriptorBufferInfo{w.scratch.buffer, 0, scratch_bytes + guard}
            : VkDescriptorBufferInfo{w.output.buffer, 0, image_bytes + guard};
    const VkDescriptorBufferInfo buffers[kBindingCount] = {
        {w.params.buffer, 0, packed.size() + guard},
        {w.input.buffer, 0, image_bytes + guard},
        out,
        {},
        {},
        {},
        {},
        aux_of(aux0, w.aux0),
        aux_of(aux1, w.aux1),
        {w.scratch.buffer, 0, scratch_bytes + guard},
        {}};
    // The bake pass stores to the bake image and samples no LUT; the store pass reads the bake
    // image (texelFetch) and stores to the LUT image; the other passes have the LUT image on
    // both.
    const VkImageView store_3d = role == Role::kBake ? bake_3d : view_3d;
    const VkImageView store_2d = role == Role::kBake ? bake_2d : view_2d;
    const VkImageView sampled_3d = role == Role::kBake    ? g.dummy_3d.view
                                   : role == Role::kStore ? bake_3d
                                                          : view_3d;
    const VkImageView sampled_2d = role == Role::kBake    ? g.dummy_2d.view
                                   : role == Role::kStore ? bake_2d
                                                          : view_2d;
    const VkDescriptorImageInfo images[kBindingCount] = {
        {},
        {},
        {},
        {VK_NULL_HANDLE, store_3d, VK_IMAGE_LAYOUT_GENERAL},
        {VK_NULL_HANDLE, store_2d, VK_IMAGE_LAYOUT_GENERAL},
        {g.sampler.handle, sampled_3d, VK_IMAGE_LAYOUT_GENERAL},
        {g.sampler.handle, sampled_2d, VK_IMAGE_LAYOUT_GENERAL},
        {},
        {},
        {},
        {g.sampler.handle, has_user_lut[0] ? w.user_lut[0].view : g.dummy_2d.view,
         VK_IMAGE_LAYOUT_GENERAL}};
    // The user-LUT slots (binding kBindingUserLut is an array): a 1-texel dummy where empty.
    VkDescriptorImageInfo user_luts[kUserLutSlots];
    for (size_t slot = 0; slot < kUserLutSlots; ++slot)
      user_luts[slot] = {g.sampler.handle,
                         has_user_lut[slot] ? w.user_lut[slot].view : g.dummy_2d.view,
                         VK_IMAGE_LAYOUT_GENERAL};
    VkWriteDescriptorSet writes[kBindingCount] = {};
    for (uint32_t b = 0; b < kBindingCount; ++b) {
      writes[b].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
      writes[b].dstSet = descriptor_sets[i];
      writes[b].dstBinding = b;
      writes[b].descriptorCount = 1;
      if (b == kBindingLutStore3d || b == kBindingLutStore2d) {
        writes[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
        writes[b].pImageInfo = &images[b];
      } else if (b == kBindingUserLut) {
        writes[b].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        writes[b].descriptorCount = kUserLutSlots;
        writes[b].pImageInfo = user_luts;
      } else if (b == kBindingLut3d || b == kBindingLut2d) {
        writes[b].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        writes[b].pImageInfo = &images[b];
      } else {
        writes[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        writes[b].pBufferInfo = &buffers[b];
      }
    }
    vkUpdateDescriptorSets(d, kBindingCount, writes, 0, nullptr);
  }

  // Commands.
  if (w.commands.cmd) {
    HDRC_VK_CASE(vkResetCommandBuffer(w.commands.cmd, 0));
  } else {
    w.commands.device = d;
    w.commands.pool = g.command_pool.handle;
    VkCommandBufferAllocateInfo cbai{};
    cbai.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    cbai.commandPool = g.command_pool.handle;
    cbai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cbai.commandBufferCount = 1;
    HDRC_VK_CASE(vkAllocateCommandBuffers(d, &cbai, &w.commands.cmd));
  }
  const VkCommandBuffer cmd = w.commands.cmd;
  VkCommandBufferBeginInfo bi{};
  bi.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  HDRC_VK_CASE(vkBeginCommandBuffer(cmd, &bi));
  if (bakes_lut) {
    // The store pass writes every texel of the LUT (0 where the bake pass wrote none: the bake
    // image is cleared), so the LUT itself only changes layout. The zero is no contract: a bake
    // pass writes every texel of its lut_texels domain (docs/gpu-interface.md), as UE's
    // CombineLUTs writes its whole render target; the clear only keeps a run on lavapipe
    // deterministic. Under the worst-case model both images are poisoned instead (in the LUT's
    // format: a texel the bake pass leaves out then shows in the LUT, whatever its format).
    if (worst) {
      const VkClearColorValue poison = poison_color(fmt->format);
      record_clear_to_general(cmd, w.lut.image, poison);
      record_clear_to_general(cmd, w.bake[params.lut_layout].image, poison);
    } else {
      record_to_general(cmd, w.lut.image);
      record_clear_to_general(cmd, w.bake[params.lut_layout].image);
    }
  }
  if (worst) {
    // Poison, on the device, what a pass may write but must not read before writing: the output
    // image, the scratch buffer (its passes write what a later pass reads) and the buffer the
    // LUT is copied to. The parameter block, the input and the aux images are written whole by
    // the host; the guards after them hold canaries.
    vkCmdFillBuffer(cmd, w.output.buffer, 0, image_bytes, kPoisonWord);
    if (uses_scratch) vkCmdFillBuffer(cmd, w.scratch.buffer, 0, scratch_bytes, kPoisonWord);
    if (reads_back) vkCmdFillBuffer(cmd, w.readback.buffer, 0, VK_WHOLE_SIZE, kPoisonWord);
    VkMemoryBarrier filled{};
    filled.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
    filled.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    filled.dstAccessMask =
        VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0,
                         1, &filled, 0, nullptr, 0, nullptr);
  }
  for (size_t slot = 0; slot < kUserLutSlots; ++slot)
    if (has_user_lut[slot])
      record_upload_to_general(
          cmd, w.user_lut_staging[slot].buffer, w.user_lut[slot].image,
          {uint32_t(c.user_luts[slot].width), uint32_t(c.user_luts[slot].height), 1});

  // The dispatches in segments, a barrier between consecutive segments: pass i reads what pass
  // i−1 wrote (buffers and the LUT image, which stays GENERAL), so each pass is a segment of its
  // own, after a global memory barrier that covers both. (A planted defect may leave a barrier
  // out, joining two passes in one segment, or leave the store pass out.)
  std::vector<std::vector<size_t>> segments;
  for (size_t i = 0; i < runs.size(); ++i) {
    if (runs[i].role == Role::kStore && lut_reused &&
        s.planted == VulkanOptions::Planted::kStaleLutOnReuse)
      continue;
    const bool barrier = !(runs[i].role == Role::kStore &&
                           s.planted == VulkanOptions::Planted::kNoBarrierBeforeStore);
    if (segments.empty() || barrier)
      segments.push_back({i});
    else
      segments.back().push_back(i);
  }
  const uint32_t max_groups = std::max<uint32_t>(g.limits.maxComputeWorkGroupCount[0], 1);
  for (size_t k = 0; k < segments.size(); ++k) {
    if (k > 0) {
      VkMemoryBarrier between{};
      between.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
      between.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
      between.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
      vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                           VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &between, 0, nullptr, 0,
                           nullptr);
    }
    // Dispatches with no barrier between them are ordered in no way (Vulkan spec,
    // "Synchronization and Cache Control": without a dependency, commands may overlap and
    // complete out of order): the worst-case model records them last to first, one execution a
    // conformant device may choose; lavapipe runs commands one after the other as recorded.
    std::vector<size_t> order = segments[k];
    if (worst) std::reverse(order.begin(), order.end());
    for (const size_t i : order) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, runs[i].pipeline);
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, g.pipeline_layout.handle, 0, 1,
                              &descriptor_sets[i], 0, nullptr);
      const uint64_t count = invocations(runs[i].domain, pixels, n);
      const uint64_t groups = (count + kLocalSizeX - 1) / kLocalSizeX;
      for (uint64_t base = 0; base < groups; base += max_groups) {
        const uint32_t here = static_cast<uint32_t>(std::min<uint64_t>(max_groups, groups - base));
        // The first (usually only) dispatch of a pass is a vkCmdDispatch, the same as
        // vkCmdDispatchBase with a zero base (Vulkan spec, vkCmdDispatchBase): the validation
        // layer's synchronisation validation checks vkCmdDispatch's accesses and not
        // vkCmdDispatchBase's (Vulkan-ValidationLayers issue #9851; 1.3.239 here). It takes
        // each dispatch to access every descriptor's whole range, so the first one carries the
        // pass's hazards.
        if (base == 0)
          vkCmdDispatch(cmd, here, 1, 1);
        else
          vkCmdDispatchBase(cmd, static_cast<uint32_t>(base), 0, 0, here, 1, 1);
      }
    }
  }
  VkMemoryBarrier to_host{};
  to_host.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  to_host.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                       &to_host, 0, nullptr, 0, nullptr);
  if (reads_back) {
    VkImageMemoryBarrier to_copy{};
    to_copy.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
    to_copy.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    to_copy.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    to_copy.oldLayout = VK_IMAGE_LAYOUT_GENERAL;
    to_copy.newLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    to_copy.srcQueueFamilyIndex = to_copy.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    to_copy.image = w.lut.image;
    to_copy.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         0, 0, nullptr, 0, nullptr, 1, &to_copy);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = params.lut_layout == 0 ? VkExtent3D{uint32_t(n), uint32_t(n), uint32_t(n)}
                                                : VkExtent3D{uint32_t(n * n), uint32_t(n), 1};
    vkCmdCopyImageToBuffer(cmd, w.lut.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                           w.readback.buffer, 1, &region);
    VkBufferMemoryBarrier copied{};
    copied.sType = VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER;
    copied.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    copied.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    copied.srcQueueFamilyIndex = copied.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    copied.buffer = w.readback.buffer;
    copied.size = VK_WHOLE_SIZE;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 0,
                         nullptr, 1, &copied, 0, nullptr);
  }
  HDRC_VK_CASE(vkEndCommandBuffer(cmd));
  // Recording errors found by the validation layer: the command buffer is not submitted.
  if (Error e = s.validation_error("stage " + stage_name); !e.message.empty()) return e;

  if (w.fence.handle) {
    HDRC_VK_CASE(vkResetFences(d, 1, &w.fence.handle));
  } else {
    VkFenceCreateInfo fci{};
    fci.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
    w.fence.device = d;
    HDRC_VK_CASE(vkCreateFence(d, &fci, nullptr, &w.fence.handle));
  }
  VkSubmitInfo si{};
  si.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  // The variants this submission compiles (VariantGate): per pass, its shader and the state of
  // the LUT images bound to it (the bake pass has the bake image and dummies, whose state never
  // changes) and of the user-LUT textures (RGBA32F like the dummies: only whether the strip's
  // extents are powers of two differs).
  auto pot = [](int v) { return v > 0 && std::has_single_bit(static_cast<unsigned>(v)); };
  std::string user_lut_state;
  for (size_t slot = 0; slot < kUserLutSlots; ++slot)
    user_lut_state += !has_user_lut[slot] || pot(params.user_lut_size) ? 'p' : 'n';
  // A power-of-two LUT binds the same state for either layout (the format dummies).
  std::string lut_state = " no lut";
  if (bakes_lut) {
    lut_state = " lut " + std::to_string(params.lut_format);
    lut_state += pot(n) ? " pot" : " npot layout " + std::to_string(params.lut_layout);
  }
  std::vector<std::string> variants;
  for (const Run& r : runs)
    variants.push_back(r.shader + (r.role == Role::kBake ? std::string(" bake") : lut_state) +
                       (r.role == Role::kStore ? "" : " user " + user_lut_state));
  const std::vector<std::string> claimed =
      variant_gate().acquire(variants, std::chrono::duration<double>(s.fence_timeout_s));
  struct Release {
    const std::vector<std::string>& claimed;
    ~Release() { variant_gate().release(claimed); }
  } release_claimed{claimed};

  HDRC_VK_CASE(vkQueueSubmit(g.queue, 1, &si, w.fence.handle));
  const uint64_t timeout_ns = static_cast<uint64_t>(s.fence_timeout_s * 1e9);
  const VkResult waited = vkWaitForFences(d, 1, &w.fence.handle, VK_TRUE, timeout_ns);
  if (waited == VK_TIMEOUT) {
    *fate = Fate::kTimeout;
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%g", s.fence_timeout_s);
    return Error{"", "",
                 "stage " + stage_name + ": vkWaitForFences timed out after " + seconds +
                     " s (fence_timeout_s); the device is abandoned and a new one created for the "
                     "next case",
                 ""};
  }
  HDRC_VK_CASE(waited);

  // The canaries: a word of a guard that changed is a store past the data of that binding.
  for (const Guarded& b : guarded) {
    const auto* guard = static_cast<const uint8_t*>(b.buffer->mapped) + b.data_bytes;
    for (VkDeviceSize at = 0; at < kGuardBytes; at += 4) {
      uint32_t word = 0, want = 0;
      std::memcpy(&word, guard + at, 4);
      fill_words(&want, 4, kCanaryWord);
      if (word == want) continue;
      char found[16];
      std::snprintf(found, sizeof found, "0x%08x", word);
      return Error{"", "",
                   "stage " + stage_name + ": out-of-bounds write to " + b.name + ": byte " +
                       std::to_string(b.data_bytes + at) + " (" + std::to_string(at) +
                       " past the end of its " + std::to_string(b.data_bytes) +
                       "-byte data) holds " + found + ", not the guard's canary",
                   ""};
    }
  }

  if (reads_back) return decode_lut(w.readback.mapped, *fmt, params.lut_layout, n);
  return widen_output(static_cast<const float*>(w.output.mapped), c.input.width, c.input.height);
}

Result<Image> VulkanEngine::run(const ResolvedCase& c) {
  if (!state_) return Error{"", "", "Vulkan engine used before a successful init()", ""};
  State& s = *state_;
  const StageInfo& stage = *c.spec.stage;
  const auto missing = missing_shaders(stage, options_.shader_dir);
  if (!missing.empty()) {
    std::string list;
    for (const auto& m : missing) list += (list.empty() ? "" : ", ") + m;
    return Error{"", "",
                 "stage " + std::string(stage.name) + " has no GPU implementation in " +
                     options_.shader_dir + ": missing " + list,
                 ""};
  }
  s.reap();
  if (!s.gpu) {
    if (Status st = s.create_gpu(); !st)
      return Error{"", "", "re-creating the Vulkan device failed: " + st.error().message, ""};
  }
  if (s.messages) s.messages->clear();

  std::unique_ptr<CaseWork> work = std::move(s.spare);  // the last case's, on this device
  if (work)
    ++s.reused;
  else
    work = std::make_unique<CaseWork>();
  Fate fate = Fate::kOk;
  Result<Image> out = s.run_passes(c, options_.shader_dir, *s.gpu, *work, &fate);
  if (fate == Fate::kOk) s.spare = std::move(work);
  if (fate == Fate::kTimeout) {
    // The submission may still be running: its device and resources stay alive until it ends.
    s.abandoned.push_back({std::move(s.gpu), std::move(work)});
  } else if (fate == Fate::kLost) {
    work.reset();
    s.gpu.reset();
  }
  if (fate != Fate::kOk) {
    // A fresh device for the next case, made now so that its failure is reported with this one.
    Error e = out.ok() ? Error{} : out.error();
    if (Status st = s.create_gpu(); !st)
      e.message += "; re-creating the device failed: " + st.error().message;
    if (fate == Fate::kLost) e.message += " (device lost; a new device was created)";
    return e;
  }
  if (Error e = s.validation_error("stage " + std::string(stage.name)); !e.message.empty())
    return e;
  return out;
}

}  // namespace hdrc::gpu
