#include "apps/device_command.h"

#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>

#include "gpu/context.h"
#include "gpu/timer.h"
#include "raster/shadow_map_pass.h"
#include "raytrace/acceleration_structures.h"

namespace penumbra {
namespace {

std::string versionText(std::uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
         std::to_string(VK_API_VERSION_PATCH(v));
}

// Every device the loader lists, each with the reason Penumbra cannot use it (null when it can).
nlohmann::json listDevices() {
  vk::raii::Context context;
  const vk::ApplicationInfo app{.pApplicationName = "penumbra device", .apiVersion = VK_API_VERSION_1_3};
  const vk::raii::Instance instance(context, vk::InstanceCreateInfo{.pApplicationInfo = &app});
  nlohmann::json list = nlohmann::json::array();
  for (const auto& d : vk::raii::PhysicalDevices(instance)) {
    const auto p = d.getProperties();
    const std::string why = gpu::unusableReason(d);
    list.push_back({{"name", p.deviceName.data()},
                    {"type", vk::to_string(p.deviceType)},
                    {"api_version", versionText(p.apiVersion)},
                    {"unusable", why.empty() ? nlohmann::json(nullptr) : nlohmann::json(why)}});
  }
  return list;
}

nlohmann::json describe(const gpu::Context& context) {
  const auto& physical = context.physicalDevice();
  const auto chain =
      physical.getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceDriverProperties,
                              vk::PhysicalDeviceSubgroupProperties, vk::PhysicalDeviceVulkan13Properties>();
  const auto& p = chain.get<vk::PhysicalDeviceProperties2>().properties;
  const auto& driver = chain.get<vk::PhysicalDeviceDriverProperties>();
  const auto& subgroup = chain.get<vk::PhysicalDeviceSubgroupProperties>();
  const auto& v13 = chain.get<vk::PhysicalDeviceVulkan13Properties>();
  const auto features = physical.getFeatures();
  const auto conformance = driver.conformanceVersion;

  nlohmann::json extensions = nlohmann::json::object();
  for (const char* e : {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME, VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME,
                        VK_KHR_RAY_QUERY_EXTENSION_NAME, VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME}) {
    extensions[e] = gpu::hasDeviceExtension(physical, e);
  }
  nlohmann::json stages = nlohmann::json::array(), operations = nlohmann::json::array();
  for (auto s : {vk::ShaderStageFlagBits::eVertex, vk::ShaderStageFlagBits::eGeometry,
                 vk::ShaderStageFlagBits::eFragment, vk::ShaderStageFlagBits::eCompute}) {
    if (subgroup.supportedStages & s) stages.push_back(vk::to_string(s));
  }
  for (auto o : {vk::SubgroupFeatureFlagBits::eBasic, vk::SubgroupFeatureFlagBits::eVote,
                 vk::SubgroupFeatureFlagBits::eArithmetic, vk::SubgroupFeatureFlagBits::eBallot,
                 vk::SubgroupFeatureFlagBits::eShuffle}) {
    if (subgroup.supportedOperations & o) operations.push_back(vk::to_string(o));
  }
  nlohmann::json heaps = nlohmann::json::array();
  const auto memory = physical.getMemoryProperties();
  for (std::uint32_t i = 0; i < memory.memoryHeapCount; ++i) {
    heaps.push_back({{"bytes", memory.memoryHeaps[i].size},
                     {"device_local", bool(memory.memoryHeaps[i].flags & vk::MemoryHeapFlagBits::eDeviceLocal)}});
  }
  const auto& limits = p.limits;
  return {{"name", p.deviceName.data()},
          {"type", vk::to_string(p.deviceType)},
          {"vendor_id", p.vendorID},
          {"device_id", p.deviceID},
          {"api_version", versionText(p.apiVersion)},
          {"driver", context.driverInfo()},
          {"driver_id", vk::to_string(driver.driverID)},
          {"conformance_version", std::to_string(conformance.major) + "." + std::to_string(conformance.minor) + "." +
                                      std::to_string(conformance.subminor) + "." + std::to_string(conformance.patch)},
          {"extensions", extensions},
          {"ray_query", context.rayQuery()},  // enabled: extensions and features present, not turned off
          {"features",
           {{"geometry_shader", bool(features.geometryShader)},
            {"fragment_stores_and_atomics", bool(features.fragmentStoresAndAtomics)}}},
          {"subgroup",
           {{"size", subgroup.subgroupSize},
            {"min_size", v13.minSubgroupSize},
            {"max_size", v13.maxSubgroupSize},
            {"stages", stages},
            {"operations", operations}}},
          {"limits",
           {{"max_storage_buffer_range", limits.maxStorageBufferRange},
            {"max_buffer_bytes", context.maxBufferBytes()},
            {"max_image_dimension_2d", limits.maxImageDimension2D},
            {"max_image_array_layers", limits.maxImageArrayLayers},
            {"max_compute_workgroup_invocations", limits.maxComputeWorkGroupInvocations},
            {"max_push_constants_size", limits.maxPushConstantsSize},
            {"timestamp_period_ns", limits.timestampPeriod},
            {"timestamp_compute_and_graphics", bool(limits.timestampComputeAndGraphics)}}},
          {"memory_heaps", heaps},
          {"auto",
           {{"tracer", defaultTracer(context)},
            {"shadow_reads", raster::bufferReads(context, {}) ? "buffer" : "texture"},
            {"timer", gpu::toString(gpu::defaultTimerMode(context))}}}};
}

}  // namespace

DeviceCommand::DeviceCommand(CLI::App& app) {
  command_ = app.add_subcommand("device",
                                "Print the Vulkan devices found, the one Penumbra uses, its driver, extensions, limits "
                                "and what each `auto` setting chooses on it (JSON)");
  command_->add_option("--out", out_, "Also write the JSON to this file");
  command_->add_flag("--validate", validate_, "Create the device with the Vulkan validation layers");
}

int DeviceCommand::run() {
  nlohmann::json info{{"devices", listDevices()}};
  int code = 0;
  try {
    gpu::Context context({.validate = validate_});
    info["device"] = describe(context);
    info["validation_messages"] = context.validationMessages();
    if (!context.validationMessages().empty()) code = 3;
  } catch (const std::exception& e) {  // no usable device: the list says what was found
    info["device"] = nullptr;
    info["error"] = e.what();
    code = 2;
  }
  const std::string text = info.dump(2);
  std::cout << text << "\n";
  if (!out_.empty()) {
    std::ofstream file(out_);
    file << text << "\n";
    if (!file) throw std::runtime_error("cannot write '" + out_ + "'");
  }
  return code;
}

}  // namespace penumbra
