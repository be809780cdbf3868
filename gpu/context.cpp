#include "gpu/context.h"

#include "core/scene.h"

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <stdexcept>

namespace penumbra::gpu {
namespace {

bool hasLayer(const vk::raii::Context& context, const char* name) {
  for (const auto& layer : context.enumerateInstanceLayerProperties()) {
    if (std::string(layer.layerName.data()) == name) return true;
  }
  return false;
}

bool hasInstanceExtension(const vk::raii::Context& context, const char* name) {
  for (const auto& ext : context.enumerateInstanceExtensionProperties()) {
    if (std::string(ext.extensionName.data()) == name) return true;
  }
  return false;
}

// A discrete GPU beats an integrated one beats anything else; the CPU (lavapipe) is the fallback.
int deviceRank(const vk::raii::PhysicalDevice& device) {
  switch (device.getProperties().deviceType) {
    case vk::PhysicalDeviceType::eDiscreteGpu: return 4;
    case vk::PhysicalDeviceType::eIntegratedGpu: return 3;
    case vk::PhysicalDeviceType::eVirtualGpu: return 2;
    case vk::PhysicalDeviceType::eCpu: return 1;
    default: return 0;
  }
}

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

}  // namespace

bool hasDeviceExtension(const vk::raii::PhysicalDevice& device, const char* name) {
  for (const auto& ext : device.enumerateDeviceExtensionProperties()) {
    if (std::string(ext.extensionName.data()) == name) return true;
  }
  return false;
}

std::string unusableReason(const vk::raii::PhysicalDevice& device) {
  if (device.getProperties().apiVersion < VK_API_VERSION_1_3) return "Vulkan older than 1.3";
  if (!hasDeviceExtension(device, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME)) return "no VK_KHR_push_descriptor";
  return "";
}

Context::Context(const ContextOptions& options) : validate_(options.validate), printMessages_(options.printMessages) {
  if (validate_ && !hasLayer(context_, kValidationLayer)) {
    throw std::runtime_error(std::string("Vulkan validation requested but ") + kValidationLayer +
                             " is not installed; install the Debian package vulkan-validationlayers");
  }
  debugUtils_ = hasInstanceExtension(context_, VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  std::vector<const char*> layers;
  std::vector<const char*> extensions;
  if (validate_) layers.push_back(kValidationLayer);
  if (debugUtils_) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);

  const vk::ApplicationInfo app{.pApplicationName = "penumbra", .apiVersion = VK_API_VERSION_1_3};
  const vk::DebugUtilsMessengerCreateInfoEXT messengerInfo{
      .messageSeverity = vk::DebugUtilsMessageSeverityFlagBitsEXT::eWarning | vk::DebugUtilsMessageSeverityFlagBitsEXT::eError,
      .messageType = vk::DebugUtilsMessageTypeFlagBitsEXT::eGeneral | vk::DebugUtilsMessageTypeFlagBitsEXT::eValidation |
                     vk::DebugUtilsMessageTypeFlagBitsEXT::ePerformance,
      .pfnUserCallback = &Context::onMessage,
      .pUserData = this};
  vk::InstanceCreateInfo instanceInfo{.pApplicationInfo = &app,
                                      .enabledLayerCount = std::uint32_t(layers.size()),
                                      .ppEnabledLayerNames = layers.data(),
                                      .enabledExtensionCount = std::uint32_t(extensions.size()),
                                      .ppEnabledExtensionNames = extensions.data()};
  if (validate_ && debugUtils_) instanceInfo.pNext = &messengerInfo;  // also catches create/destroy
  instance_ = vk::raii::Instance(context_, instanceInfo);
  if (validate_ && debugUtils_) messenger_ = vk::raii::DebugUtilsMessengerEXT(instance_, messengerInfo);

  vk::raii::PhysicalDevices devices(instance_);
  std::vector<vk::raii::PhysicalDevice> usable;
  for (auto& d : devices) {
    if (unusableReason(d).empty()) usable.push_back(std::move(d));
  }
  if (usable.empty()) {
    throw std::runtime_error("no Vulkan 1.3 device with VK_KHR_push_descriptor found; install mesa-vulkan-drivers "
                             "for the lavapipe CPU device (and set XDG_RUNTIME_DIR if the loader complains)");
  }
  auto best = std::max_element(usable.begin(), usable.end(),
                               [](const auto& a, const auto& b) { return deviceRank(a) < deviceRank(b); });
  physical_ = std::move(*best);

  const auto families = physical_.getQueueFamilyProperties();
  const auto wanted = vk::QueueFlagBits::eGraphics | vk::QueueFlagBits::eCompute;
  auto family = std::find_if(families.begin(), families.end(), [&](const auto& f) {
    return (f.queueFlags & wanted) == wanted && f.timestampValidBits > 0;
  });
  if (family == families.end()) throw std::runtime_error("Vulkan device has no graphics+compute queue with timestamps");
  queueFamily_ = std::uint32_t(family - families.begin());
  timestampPeriodNs_ = physical_.getProperties().limits.timestampPeriod;
  const auto limits = physical_.getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceMaintenance3Properties,
                                               vk::PhysicalDeviceMaintenance4Properties>();
  storageBufferRange_ = limits.get<vk::PhysicalDeviceProperties2>().properties.limits.maxStorageBufferRange;
  if (options.storageBufferRangeLimit != 0) storageBufferRange_ = std::min(storageBufferRange_, options.storageBufferRangeLimit);
  maxBufferBytes_ = std::min<std::uint64_t>(limits.get<vk::PhysicalDeviceMaintenance3Properties>().maxMemoryAllocationSize,
                                            limits.get<vk::PhysicalDeviceMaintenance4Properties>().maxBufferSize);
  if (options.bufferBytesLimit != 0) maxBufferBytes_ = std::min(maxBufferBytes_, options.bufferBytesLimit);

  // Features of an extension may only be queried where the device has it.
  const char* noRayQuery = std::getenv("PENUMBRA_NO_RAY_QUERY");
  rayQueryTurnedOff_ = noRayQuery && std::string(noRayQuery) == "1";
  rayQuery_ = !rayQueryTurnedOff_ &&
              hasDeviceExtension(physical_, VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME) &&
              hasDeviceExtension(physical_, VK_KHR_RAY_QUERY_EXTENSION_NAME) &&
              hasDeviceExtension(physical_, VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME);
  if (rayQuery_) {
    const auto rt = physical_.getFeatures2<vk::PhysicalDeviceFeatures2, vk::PhysicalDeviceVulkan12Features,
                                           vk::PhysicalDeviceAccelerationStructureFeaturesKHR,
                                           vk::PhysicalDeviceRayQueryFeaturesKHR>();
    rayQuery_ = rt.get<vk::PhysicalDeviceVulkan12Features>().bufferDeviceAddress &&
                rt.get<vk::PhysicalDeviceAccelerationStructureFeaturesKHR>().accelerationStructure &&
                rt.get<vk::PhysicalDeviceRayQueryFeaturesKHR>().rayQuery;
  }

  const float priority = 1.0f;
  const vk::DeviceQueueCreateInfo queueInfo{.queueFamilyIndex = queueFamily_, .queueCount = 1, .pQueuePriorities = &priority};
  const auto supported = physical_.getFeatures();
  vk::PhysicalDeviceRayQueryFeaturesKHR rayQueryFeatures{.rayQuery = VK_TRUE};
  vk::PhysicalDeviceAccelerationStructureFeaturesKHR accelerationFeatures{.pNext = &rayQueryFeatures,
                                                                          .accelerationStructure = VK_TRUE};
  vk::PhysicalDeviceVulkan13Features features13{.pNext = rayQuery_ ? &accelerationFeatures : nullptr,
                                                .synchronization2 = VK_TRUE,
                                                .dynamicRendering = VK_TRUE};
  vk::PhysicalDeviceVulkan12Features features12{
      .pNext = &features13, .hostQueryReset = VK_TRUE, .bufferDeviceAddress = VK_TRUE};  // required by Vulkan 1.3
  vk::PhysicalDeviceFeatures2 features{
      .pNext = &features12,
      .features = {.geometryShader = supported.geometryShader, .fragmentStoresAndAtomics = supported.fragmentStoresAndAtomics}};
  std::vector<const char*> deviceExtensions{VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
  if (rayQuery_) {
    for (const char* e : {VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME, VK_KHR_RAY_QUERY_EXTENSION_NAME,
                          VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME})
      deviceExtensions.push_back(e);
  }
  device_ = vk::raii::Device(physical_, vk::DeviceCreateInfo{.pNext = &features,
                                                            .queueCreateInfoCount = 1,
                                                            .pQueueCreateInfos = &queueInfo,
                                                            .enabledExtensionCount = std::uint32_t(deviceExtensions.size()),
                                                            .ppEnabledExtensionNames = deviceExtensions.data()});
  queue_ = vk::raii::Queue(device_, queueFamily_, 0);
  commandPool_ = vk::raii::CommandPool(
      device_, {.flags = vk::CommandPoolCreateFlagBits::eResetCommandBuffer, .queueFamilyIndex = queueFamily_});
  fence_ = vk::raii::Fence(device_, vk::FenceCreateInfo{});
}

std::string Context::deviceName() const { return physical_.getProperties().deviceName.data(); }

std::string Context::driverInfo() const {
  const auto props = physical_.getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceDriverProperties>();
  const auto& driver = props.get<vk::PhysicalDeviceDriverProperties>();
  return std::string(driver.driverName.data()) + " " + driver.driverInfo.data();
}

void Context::submitAndWait(const std::function<void(const vk::raii::CommandBuffer&)>& record) const {
  vk::raii::CommandBuffers buffers(device_, {.commandPool = *commandPool_, .level = vk::CommandBufferLevel::ePrimary, .commandBufferCount = 1});
  const vk::raii::CommandBuffer& cmd = buffers.front();
  cmd.begin({.flags = vk::CommandBufferUsageFlagBits::eOneTimeSubmit});
  record(cmd);
  cmd.end();
  const vk::CommandBuffer handle = *cmd;
  device_.resetFences({*fence_});
  queue_.submit(vk::SubmitInfo{.commandBufferCount = 1, .pCommandBuffers = &handle}, *fence_);
  if (device_.waitForFences({*fence_}, VK_TRUE, UINT64_MAX) != vk::Result::eSuccess) {
    throw std::runtime_error("Vulkan queue wait failed");
  }
}

std::uint32_t Context::memoryType(std::uint32_t typeBits, vk::MemoryPropertyFlags wanted) const {
  const auto memory = physical_.getMemoryProperties();
  for (std::uint32_t i = 0; i < memory.memoryTypeCount; ++i) {
    if ((typeBits & (1u << i)) && (memory.memoryTypes[i].propertyFlags & wanted) == wanted) return i;
  }
  throw std::runtime_error("no Vulkan memory type with the requested properties");
}

void Context::nameObject(vk::ObjectType type, std::uint64_t handle, const std::string& text) const {
  if (!debugUtils_) return;
  device_.setDebugUtilsObjectNameEXT({.objectType = type, .objectHandle = handle, .pObjectName = text.c_str()});
}

std::vector<std::string> Context::validationMessages() const {
  std::lock_guard lock(messagesMutex_);
  return messages_;
}

void Context::clearValidationMessages() {
  std::lock_guard lock(messagesMutex_);
  messages_.clear();
}

std::shared_ptr<const void> Context::shared(const std::string& key,
                                            const std::function<std::shared_ptr<const void>()>& make) const {
  {
    std::lock_guard lock(sharedMutex_);
    if (std::shared_ptr<const void> alive = shared_[key].lock()) return alive;
  }
  std::shared_ptr<const void> made = make();  // unlocked: making may take long (another thread may make it too)
  std::lock_guard lock(sharedMutex_);
  std::erase_if(shared_, [](const auto& entry) { return entry.second.expired(); });
  std::weak_ptr<const void>& entry = shared_[key];
  if (std::shared_ptr<const void> alive = entry.lock()) return alive;
  entry = made;
  return made;
}

VKAPI_ATTR VkBool32 VKAPI_CALL Context::onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                                  VkDebugUtilsMessageTypeFlagsEXT,
                                                  const VkDebugUtilsMessengerCallbackDataEXT* data, void* self) {
  auto* context = static_cast<Context*>(self);
  const std::string text = data && data->pMessage ? data->pMessage : "(no message)";
  {
    std::lock_guard lock(context->messagesMutex_);
    context->messages_.push_back(text);
  }
  if (context->printMessages_) std::cerr << "vulkan validation: " << text << "\n";
  return VK_FALSE;
}

void Context::requireRayQuery(const std::string& user) const {
  if (rayQuery_) return;
  throw InputError(user + ": " + deviceName() + " (" + driverInfo() + ") " +
                           (rayQueryTurnedOff_ ? "has ray queries turned off by PENUMBRA_NO_RAY_QUERY=1"
                                                           : "lacks VK_KHR_ray_query / VK_KHR_acceleration_structure") +
                           "; lavapipe has them from Mesa 25 (scripts/setup.sh installs it from bookworm-backports), or use "
                           "--tracer bvh");
}

void Context::requireSubgroupArithmetic(const std::string& user) const {
  const auto chain = physicalDevice().getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceSubgroupProperties>();
  const auto& subgroup = chain.get<vk::PhysicalDeviceSubgroupProperties>();
  if (!(subgroup.supportedStages & vk::ShaderStageFlagBits::eCompute) ||
      !(subgroup.supportedOperations & vk::SubgroupFeatureFlagBits::eArithmetic) ||
      !(subgroup.supportedOperations & vk::SubgroupFeatureFlagBits::eBasic)) {
    throw std::runtime_error(user + ": " + deviceName() + " lacks subgroup arithmetic in compute shaders, which its counters use");
  }
}

}  // namespace penumbra::gpu
