// The Vulkan device every pass runs on: a real GPU when one is present, lavapipe otherwise.
// Validation messages are captured (and printed) so tests can require silence.
#pragma once
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan_raii.hpp>

namespace penumbra::gpu {

struct ContextOptions {
  bool validate = false;      // enable VK_LAYER_KHRONOS_validation and capture its messages
  bool printMessages = true;  // also print each validation message to stderr
  // Tests: a maxStorageBufferRange lower than the device's (0 = the device's), so that code which
  // splits or refuses at lavapipe's 128 MiB is exercised on small scenes.
  std::uint64_t storageBufferRangeLimit = 0;
  // Tests: likewise a limit on the bytes one buffer may hold (maxBufferBytes; 0 = the device's).
  std::uint64_t bufferBytesLimit = 0;
};

// Whether `device` offers the extension `name`.
bool hasDeviceExtension(const vk::raii::PhysicalDevice& device, const char* name);
// Why Penumbra cannot run on `device` ("" when it can): it needs Vulkan 1.3 and VK_KHR_push_descriptor.
std::string unusableReason(const vk::raii::PhysicalDevice& device);

class Context {
 public:
  explicit Context(const ContextOptions& options = {});
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  const vk::raii::Device& device() const { return device_; }
  const vk::raii::PhysicalDevice& physicalDevice() const { return physical_; }
  std::uint32_t queueFamily() const { return queueFamily_; }
  std::string deviceName() const;
  // Throws std::runtime_error naming `user` when compute shaders lack subgroup basic/arithmetic
  // operations (the trace kernels sum their counters per subgroup).
  void requireSubgroupArithmetic(const std::string& user) const;
  // The most bytes one storage-buffer binding may span (maxStorageBufferRange, or the test limit
  // of ContextOptions), and the most one buffer may hold (maxBufferSize, maxMemoryAllocationSize),
  // which is what kernels reading through buffer device addresses (always enabled: Vulkan 1.3
  // requires them) can reach.
  std::uint64_t storageBufferRange() const { return storageBufferRange_; }
  std::uint64_t maxBufferBytes() const { return maxBufferBytes_; }
  std::string driverInfo() const;  // driver name and version, for benchmark rows
  bool validationEnabled() const { return validate_; }
  // Inline ray queries on driver-built acceleration structures (VK_KHR_acceleration_structure +
  // VK_KHR_ray_query, buffer device addresses): enabled when the device has them, unless the
  // environment sets PENUMBRA_NO_RAY_QUERY=1 (to run the fallbacks on a device that has them).
  bool rayQuery() const { return rayQuery_; }
  // Throws InputError (an option this device cannot honour) naming `user` and the driver when
  // rayQuery() is false.
  void requireRayQuery(const std::string& user) const;
  float timestampPeriodNs() const { return timestampPeriodNs_; }

  // Records with `record`, submits and waits; the one way passes reach the queue.
  void submitAndWait(const std::function<void(const vk::raii::CommandBuffer&)>& record) const;

  std::uint32_t memoryType(std::uint32_t typeBits, vk::MemoryPropertyFlags wanted) const;

  // Debug name shown by validation messages and captures (no-op without debug utils).
  template <typename Handle>
  void name(const Handle& handle, const std::string& text) const {
    nameObject(Handle::objectType, reinterpret_cast<std::uint64_t>(static_cast<typename Handle::CType>(handle)), text);
  }

  std::vector<std::string> validationMessages() const;
  void clearValidationMessages();

  // The object made for `key` that is still alive, else make()'s, remembered while it lives: passes
  // made more than once (a light's own maps, a renderer per method) share their pipelines, and the
  // driver compiles each once (gpu/pipeline.cpp keys them by their whole description).
  std::shared_ptr<const void> shared(const std::string& key,
                                     const std::function<std::shared_ptr<const void>()>& make) const;

 private:
  void nameObject(vk::ObjectType type, std::uint64_t handle, const std::string& text) const;
  static VKAPI_ATTR VkBool32 VKAPI_CALL onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                  VkDebugUtilsMessageTypeFlagsEXT types,
                                                  const VkDebugUtilsMessengerCallbackDataEXT* data, void* self);

  bool validate_ = false;
  bool printMessages_ = true;
  bool debugUtils_ = false;
  bool rayQuery_ = false;
  bool rayQueryTurnedOff_ = false;  // by PENUMBRA_NO_RAY_QUERY=1
  std::uint64_t storageBufferRange_ = 0;
  std::uint64_t maxBufferBytes_ = 0;
  mutable std::mutex messagesMutex_;
  std::vector<std::string> messages_;
  mutable std::mutex sharedMutex_;
  mutable std::map<std::string, std::weak_ptr<const void>> shared_;
  vk::raii::Context context_;
  vk::raii::Instance instance_{nullptr};
  vk::raii::DebugUtilsMessengerEXT messenger_{nullptr};
  vk::raii::PhysicalDevice physical_{nullptr};
  vk::raii::Device device_{nullptr};
  vk::raii::Queue queue_{nullptr};
  vk::raii::CommandPool commandPool_{nullptr};
  vk::raii::Fence fence_{nullptr};
  std::uint32_t queueFamily_ = 0;
  float timestampPeriodNs_ = 1.0f;
};

}  // namespace penumbra::gpu
