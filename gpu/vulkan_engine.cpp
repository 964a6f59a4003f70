#include "gpu/vulkan_engine.h"

#include <vulkan/vulkan.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <vector>

#include "core/shader_interface.h"
#include "gpu/shader_compiler.h"

#ifndef HDRC_SOURCE_SHADER_DIR
#error "HDRC_SOURCE_SHADER_DIR must be defined by the build"
#endif

namespace hdrc::gpu {

std::string default_shader_dir() {
  return HDRC_SOURCE_SHADER_DIR;
}

namespace {

const char* vk_result_name(VkResult r) {
  switch (r) {
    case VK_SUCCESS:
      return "VK_SUCCESS";
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

Result<VkInstance> create_instance(bool validation) {
  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = "hdrconform";
  app.apiVersion = VK_API_VERSION_1_1;
  VkInstanceCreateInfo ci{};
  ci.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  ci.pApplicationInfo = &app;
  const char* layers[] = {"VK_LAYER_KHRONOS_validation"};
  if (validation) {
    ci.enabledLayerCount = 1;
    ci.ppEnabledLayerNames = layers;
  }
  VkInstance instance = VK_NULL_HANDLE;
  HDRC_VK(vkCreateInstance(&ci, nullptr, &instance));
  return instance;
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

}  // namespace

Result<std::string> list_devices() {
  auto instance = create_instance(false);
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

// Owns every Vulkan object of the engine; destroyed in reverse order of creation.
struct VulkanEngine::State {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  uint32_t queue_family = 0;
  VkCommandPool command_pool = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout pipeline_layout = VK_NULL_HANDLE;
  std::map<std::string, VkPipeline> pipelines;  // by stage shader path
  VkPhysicalDeviceMemoryProperties memory{};
  DeviceInfo info;

  ~State() {
    if (device) {
      vkDeviceWaitIdle(device);
      for (auto& [name, p] : pipelines) vkDestroyPipeline(device, p, nullptr);
      if (pipeline_layout) vkDestroyPipelineLayout(device, pipeline_layout, nullptr);
      if (set_layout) vkDestroyDescriptorSetLayout(device, set_layout, nullptr);
      if (command_pool) vkDestroyCommandPool(device, command_pool, nullptr);
      vkDestroyDevice(device, nullptr);
    }
    if (instance) vkDestroyInstance(instance, nullptr);
  }
};

namespace {

// A host-visible, coherent storage buffer (RAII).
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

Status make_buffer(VkDevice device, const VkPhysicalDeviceMemoryProperties& mem, VkDeviceSize size,
                   Buffer* b) {
  b->device = device;
  b->size = size;
  VkBufferCreateInfo ci{};
  ci.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  ci.size = size;
  ci.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  ci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  HDRC_VK(vkCreateBuffer(device, &ci, nullptr, &b->buffer));
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(device, b->buffer, &req);
  const VkMemoryPropertyFlags want =
      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  uint32_t type = UINT32_MAX;
  for (uint32_t i = 0; i < mem.memoryTypeCount; ++i) {
    if ((req.memoryTypeBits & (1u << i)) && (mem.memoryTypes[i].propertyFlags & want) == want) {
      type = i;
      break;
    }
  }
  if (type == UINT32_MAX) return Error{"", "", "no host-visible coherent memory type", ""};
  VkMemoryAllocateInfo ai{};
  ai.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = type;
  HDRC_VK(vkAllocateMemory(device, &ai, nullptr, &b->memory));
  HDRC_VK(vkBindBufferMemory(device, b->buffer, b->memory, 0));
  HDRC_VK(vkMapMemory(device, b->memory, 0, VK_WHOLE_SIZE, 0, &b->mapped));
  return {};
}

}  // namespace

VulkanEngine::VulkanEngine(VulkanOptions options) : options_(std::move(options)) {
  if (options_.shader_dir.empty()) options_.shader_dir = default_shader_dir();
}
VulkanEngine::~VulkanEngine() = default;

int VulkanEngine::compiled_pipeline_count() const {
  return state_ ? static_cast<int>(state_->pipelines.size()) : 0;
}

Status VulkanEngine::init() {
  auto s = std::make_unique<State>();
  auto instance = create_instance(options_.validation);
  if (!instance) {
    Error e = instance.error();
    e.message = "no Vulkan instance: " + e.message +
                (options_.validation ? " (is vulkan-validationlayers installed?)" : "");
    return e;
  }
  s->instance = *instance;
  auto devices = describe_devices(s->instance);
  if (!devices) return devices.error();
  if (devices->empty()) return Error{"", "", "no Vulkan physical devices found", ""};

  std::string known;
  for (size_t i = 0; i < devices->size(); ++i)
    known += (known.empty() ? "" : ", ") + std::to_string(i) + " '" + (*devices)[i].name + "'";
  const DeviceDescription* chosen = nullptr;
  const std::string& want = options_.device;
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
      return Error{"", "", "--device " + want + ": no Vulkan device with that index", known};
    chosen = &(*devices)[index];
  } else {
    for (const auto& d : *devices)
      if (lower(d.name).find(lower(want)) != std::string::npos) {
        chosen = &d;
        break;
      }
    if (!chosen) return Error{"", "", "--device '" + want + "': no Vulkan device matches", known};
  }
  s->physical = chosen->handle;
  s->info = {"vulkan", chosen->name, chosen->driver, version_string(chosen->api_version)};
  vkGetPhysicalDeviceMemoryProperties(s->physical, &s->memory);

  uint32_t nq = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(s->physical, &nq, nullptr);
  std::vector<VkQueueFamilyProperties> families(nq);
  vkGetPhysicalDeviceQueueFamilyProperties(s->physical, &nq, families.data());
  bool found = false;
  for (uint32_t i = 0; i < nq && !found; ++i)
    if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
      s->queue_family = i;
      found = true;
    }
  if (!found) return Error{"", "", "device '" + chosen->name + "' has no compute queue", ""};

  const float priority = 1.0f;
  VkDeviceQueueCreateInfo qci{};
  qci.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  qci.queueFamilyIndex = s->queue_family;
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
  VkDeviceCreateInfo dci{};
  dci.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  HDRC_VK(vkCreateDevice(s->physical, &dci, nullptr, &s->device));
  vkGetDeviceQueue(s->device, s->queue_family, 0, &s->queue);

  VkCommandPoolCreateInfo pci{};
  pci.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pci.queueFamilyIndex = s->queue_family;
  HDRC_VK(vkCreateCommandPool(s->device, &pci, nullptr, &s->command_pool));

  VkDescriptorSetLayoutBinding bindings[3] = {};
  const uint32_t numbers[3] = {kBindingParams, kBindingInput, kBindingOutput};
  for (int i = 0; i < 3; ++i) {
    bindings[i].binding = numbers[i];
    bindings[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    bindings[i].descriptorCount = 1;
    bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  VkDescriptorSetLayoutCreateInfo lci{};
  lci.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
  lci.bindingCount = 3;
  lci.pBindings = bindings;
  HDRC_VK(vkCreateDescriptorSetLayout(s->device, &lci, nullptr, &s->set_layout));
  VkPipelineLayoutCreateInfo plci{};
  plci.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
  plci.setLayoutCount = 1;
  plci.pSetLayouts = &s->set_layout;
  HDRC_VK(vkCreatePipelineLayout(s->device, &plci, nullptr, &s->pipeline_layout));
  state_ = std::move(s);
  return {};
}

DeviceInfo VulkanEngine::device() const {
  return state_ ? state_->info : DeviceInfo{"vulkan", "(not initialised)", "", ""};
}

Result<Image> VulkanEngine::run(const ResolvedCase& c) {
  if (!state_) return Error{"", "", "Vulkan engine used before a successful init()", ""};
  State& s = *state_;
  const std::string shader(c.spec.stage->shader);
  if (shader.empty())
    return Error{
        "", "",
        "stage " + std::string(c.spec.stage->name) + " has no GPU implementation in this version",
        ""};

  // Pipelines are compiled once per stage shader and cached for the engine's lifetime.
  auto it = s.pipelines.find(shader);
  if (it == s.pipelines.end()) {
    auto spirv = compile_compute(options_.shader_dir, shader);
    if (!spirv) return spirv.error();
    VkShaderModuleCreateInfo mci{};
    mci.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
    mci.codeSize = spirv->size() * sizeof(uint32_t);
    mci.pCode = spirv->data();
    VkShaderModule module = VK_NULL_HANDLE;
    HDRC_VK(vkCreateShaderModule(s.device, &mci, nullptr, &module));
    VkComputePipelineCreateInfo cpci{};
    cpci.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
    cpci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    cpci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    cpci.stage.module = module;
    cpci.stage.pName = "main";
    cpci.layout = s.pipeline_layout;
    VkPipeline pipeline = VK_NULL_HANDLE;
    const VkResult r =
        vkCreateComputePipelines(s.device, VK_NULL_HANDLE, 1, &cpci, nullptr, &pipeline);
    vkDestroyShaderModule(s.device, module, nullptr);
    if (r != VK_SUCCESS) return vk_error("vkCreateComputePipelines", r);
    it = s.pipelines.emplace(shader, pipeline).first;
  }

  const size_t n = c.input.pixel_count();
  const std::vector<uint8_t> params = pack_std430(c.params);
  Buffer pbuf, ibuf, obuf;
  if (auto st = make_buffer(s.device, s.memory, params.size(), &pbuf); !st) return st.error();
  if (auto st = make_buffer(s.device, s.memory, n * 16, &ibuf); !st) return st.error();
  if (auto st = make_buffer(s.device, s.memory, n * 16, &obuf); !st) return st.error();
  std::memcpy(pbuf.mapped, params.data(), params.size());
  {
    float* dst = static_cast<float*>(ibuf.mapped);
    for (size_t i = 0; i < n * 4; ++i) dst[i] = static_cast<float>(c.input.data[i]);
    std::memset(obuf.mapped, 0, n * 16);
  }

  VkDescriptorPoolSize pool_size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 3};
  VkDescriptorPoolCreateInfo dpci{};
  dpci.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
  dpci.maxSets = 1;
  dpci.poolSizeCount = 1;
  dpci.pPoolSizes = &pool_size;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  HDRC_VK(vkCreateDescriptorPool(s.device, &dpci, nullptr, &pool));
  struct PoolGuard {
    VkDevice d;
    VkDescriptorPool p;
    ~PoolGuard() { vkDestroyDescriptorPool(d, p, nullptr); }
  } pool_guard{s.device, pool};
  VkDescriptorSetAllocateInfo dsai{};
  dsai.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
  dsai.descriptorPool = pool;
  dsai.descriptorSetCount = 1;
  dsai.pSetLayouts = &s.set_layout;
  VkDescriptorSet set = VK_NULL_HANDLE;
  HDRC_VK(vkAllocateDescriptorSets(s.device, &dsai, &set));
  VkDescriptorBufferInfo infos[3] = {{pbuf.buffer, 0, VK_WHOLE_SIZE},
                                     {ibuf.buffer, 0, VK_WHOLE_SIZE},
                                     {obuf.buffer, 0, VK_WHOLE_SIZE}};
  const uint32_t numbers[3] = {kBindingParams, kBindingInput, kBindingOutput};
  VkWriteDescriptorSet writes[3] = {};
  for (int i = 0; i < 3; ++i) {
    writes[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    writes[i].dstSet = set;
    writes[i].dstBinding = numbers[i];
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &infos[i];
  }
  vkUpdateDescriptorSets(s.device, 3, writes, 0, nullptr);

  VkCommandBufferAllocateInfo cbai{};
  cbai.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  cbai.commandPool = s.command_pool;
  cbai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cbai.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  HDRC_VK(vkAllocateCommandBuffers(s.device, &cbai, &cmd));
  struct CmdGuard {
    VkDevice d;
    VkCommandPool p;
    VkCommandBuffer c;
    ~CmdGuard() { vkFreeCommandBuffers(d, p, 1, &c); }
  } cmd_guard{s.device, s.command_pool, cmd};
  VkCommandBufferBeginInfo bi{};
  bi.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  HDRC_VK(vkBeginCommandBuffer(cmd, &bi));
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, it->second);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, s.pipeline_layout, 0, 1, &set, 0,
                          nullptr);
  const uint32_t groups = static_cast<uint32_t>((n + kLocalSizeX - 1) / kLocalSizeX);
  vkCmdDispatch(cmd, groups, 1, 1);
  VkMemoryBarrier barrier{};
  barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                       &barrier, 0, nullptr, 0, nullptr);
  HDRC_VK(vkEndCommandBuffer(cmd));

  VkFenceCreateInfo fci{};
  fci.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  VkFence fence = VK_NULL_HANDLE;
  HDRC_VK(vkCreateFence(s.device, &fci, nullptr, &fence));
  struct FenceGuard {
    VkDevice d;
    VkFence f;
    ~FenceGuard() { vkDestroyFence(d, f, nullptr); }
  } fence_guard{s.device, fence};
  VkSubmitInfo si{};
  si.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  HDRC_VK(vkQueueSubmit(s.queue, 1, &si, fence));
  const uint64_t timeout_ns = static_cast<uint64_t>(options_.fence_timeout_s * 1e9);
  HDRC_VK(vkWaitForFences(s.device, 1, &fence, VK_TRUE, timeout_ns));

  Image out(c.input.width, c.input.height);
  const float* src = static_cast<const float*>(obuf.mapped);
  for (size_t i = 0; i < n * 4; ++i) out.data[i] = src[i];
  return out;
}

}  // namespace hdrc::gpu
