// Pipelines with push descriptors (no pools to manage): one set, bound per dispatch or draw.
#pragma once
#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gpu/context.h"
#include "gpu/resources.h"

namespace penumbra::gpu {

struct Binding {
  std::uint32_t binding;
  vk::DescriptorType type;
};

// Descriptor set layout + pipeline layout shared by compute and graphics pipelines.
class PipelineLayout {
 public:
  PipelineLayout(const Context& context, std::span<const Binding> bindings, vk::ShaderStageFlags stages,
                 std::uint32_t pushConstantBytes);
  vk::PipelineLayout handle() const { return *layout_; }
  vk::ShaderStageFlags stages() const { return stages_; }

 private:
  vk::ShaderStageFlags stages_;
  vk::raii::DescriptorSetLayout setLayout_;
  vk::raii::PipelineLayout layout_{nullptr};
};

// Collects descriptor writes for one push; keeps the infos alive until pushed.
class Descriptors {
 public:
  Descriptors& buffer(std::uint32_t binding, const Buffer& buffer);
  Descriptors& storageImage(std::uint32_t binding, vk::ImageView view);
  Descriptors& sampledImage(std::uint32_t binding, vk::ImageView view, vk::Sampler sampler,
                            vk::ImageLayout layout = vk::ImageLayout::eShaderReadOnlyOptimal);
  Descriptors& accelerationStructure(std::uint32_t binding, vk::AccelerationStructureKHR structure);
  void push(const vk::raii::CommandBuffer& cmd, vk::PipelineBindPoint point, const PipelineLayout& layout) const;

 private:
  std::deque<vk::DescriptorBufferInfo> buffers_;
  std::deque<vk::AccelerationStructureKHR> structureHandles_;
  std::deque<vk::WriteDescriptorSetAccelerationStructureKHR> structures_;
  std::deque<vk::DescriptorImageInfo> images_;
  std::vector<vk::WriteDescriptorSet> writes_;
};

// A pipeline and its layout: every pass made with the same description shares one (Context::shared).
struct BuiltPipeline {
  BuiltPipeline(const Context& context, std::span<const Binding> bindings, vk::ShaderStageFlags stages,
                std::uint32_t pushConstantBytes)
      : layout(context, bindings, stages, pushConstantBytes) {}
  PipelineLayout layout;
  vk::raii::Pipeline pipeline{nullptr};
};

class ComputePipeline {
 public:
  // specialization: the values of the shader's specialization constants 0, 1, ... (4 bytes each).
  ComputePipeline(const Context& context, std::span<const std::uint32_t> spirv, std::span<const Binding> bindings,
                  std::uint32_t pushConstantBytes, const std::string& name,
                  std::span<const std::uint32_t> specialization = {});
  void bind(const vk::raii::CommandBuffer& cmd, const Descriptors& descriptors) const;
  template <typename T>
  void pushConstants(const vk::raii::CommandBuffer& cmd, const T& value) const {
    cmd.pushConstants<T>(built_->layout.handle(), vk::ShaderStageFlagBits::eCompute, 0, value);
  }

 private:
  std::shared_ptr<const BuiltPipeline> built_;
};

// A compute shader with one boolean specialization constant (constant_id 0), and optionally a
// second and a third (constant_id 1, 2, given only where set, so that shaders without them keep
// their pipeline): a
// choice fixed for a whole dispatch that would otherwise be made in every invocation (where that
// compiles to a select, lavapipe pays for both sides). One pipeline per value, each created when
// first used.
class SpecializedComputePipeline {
 public:
  SpecializedComputePipeline(const Context& context, std::span<const std::uint32_t> spirv,
                             std::span<const Binding> bindings, std::uint32_t pushConstantBytes, std::string name);
  const ComputePipeline& operator()(bool value, bool second = false, bool third = false) const;

 private:
  const Context& context_;
  std::span<const std::uint32_t> spirv_;
  std::span<const Binding> bindings_;
  std::uint32_t pushConstantBytes_;
  std::string name_;
  mutable std::array<std::optional<ComputePipeline>, 8> variants_;
};

struct GraphicsPipelineDesc {
  std::span<const std::uint32_t> vertexSpirv;
  std::span<const std::uint32_t> fragmentSpirv;  // empty: depth-only
  std::span<const std::uint32_t> geometrySpirv;  // empty: no geometry stage (needs the geometryShader feature)
  std::vector<vk::VertexInputBindingDescription> vertexBindings;
  std::vector<vk::VertexInputAttributeDescription> vertexAttributes;
  std::vector<vk::Format> colorFormats;
  vk::Format depthFormat = vk::Format::eD32Sfloat;
  bool depthBias = false;  // slope-scaled bias set per draw with setDepthBias
  vk::CompareOp depthCompare = vk::CompareOp::eLess;  // eGreater for reversed depth
  std::vector<Binding> bindings;
  std::uint32_t pushConstantBytes = 0;
  std::string name;
};

// Triangle-list pipeline, no culling (scenes are drawn two-sided), depth test LESS (or as set), dynamic
// viewport/scissor (and depth bias when enabled); used with dynamic rendering.
class GraphicsPipeline {
 public:
  GraphicsPipeline(const Context& context, const GraphicsPipelineDesc& desc);
  void bind(const vk::raii::CommandBuffer& cmd, const Descriptors& descriptors) const;
  // New descriptors for the next draws, the pipeline staying bound (per-draw textures).
  void pushDescriptors(const vk::raii::CommandBuffer& cmd, const Descriptors& descriptors) const;
  template <typename T>
  void pushConstants(const vk::raii::CommandBuffer& cmd, const T& value) const {
    cmd.pushConstants<T>(built_->layout.handle(), built_->layout.stages(), 0, value);
  }

 private:
  std::shared_ptr<const BuiltPipeline> built_;
};

vk::raii::Sampler makeNearestSampler(const Context& context, const std::string& name);

}  // namespace penumbra::gpu
