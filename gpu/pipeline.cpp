#include "gpu/pipeline.h"

#include <type_traits>

namespace penumbra::gpu {
namespace {

// Every stage the pipeline runs sees the push constants and the descriptor set.
vk::ShaderStageFlags graphicsStages(const GraphicsPipelineDesc& desc) {
  vk::ShaderStageFlags stages = vk::ShaderStageFlagBits::eVertex;
  if (!desc.geometrySpirv.empty()) stages |= vk::ShaderStageFlagBits::eGeometry;
  if (!desc.fragmentSpirv.empty()) stages |= vk::ShaderStageFlagBits::eFragment;
  return stages;
}

vk::raii::ShaderModule shaderModule(const Context& context, std::span<const std::uint32_t> spirv) {
  return vk::raii::ShaderModule(context.device(), {.codeSize = spirv.size_bytes(), .pCode = spirv.data()});
}

// The bytes of a pipeline's description, for Context::shared: equal bytes, the same pipeline.
class Key {
 public:
  explicit Key(const std::string& kind) { text(kind); }
  template <typename T>
  Key& add(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof(T));
    return *this;
  }
  template <typename Range>
  Key& all(const Range& values) {
    add(std::size(values));
    for (const auto& value : values) add(value);
    return *this;
  }
  Key& text(const std::string& value) {
    add(value.size());
    bytes_ += value;
    return *this;
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

Key& addBindings(Key& key, std::span<const Binding> bindings) {
  key.add(bindings.size());
  for (const Binding& b : bindings) key.add(b.binding).add(b.type);
  return key;
}

}  // namespace

PipelineLayout::PipelineLayout(const Context& context, std::span<const Binding> bindings, vk::ShaderStageFlags stages,
                               std::uint32_t pushConstantBytes)
    : stages_(stages), setLayout_([&] {
        std::vector<vk::DescriptorSetLayoutBinding> layoutBindings;
        for (const Binding& b : bindings) {
          layoutBindings.push_back({.binding = b.binding, .descriptorType = b.type, .descriptorCount = 1, .stageFlags = stages});
        }
        return vk::raii::DescriptorSetLayout(context.device(),
                                             {.flags = vk::DescriptorSetLayoutCreateFlagBits::ePushDescriptorKHR,
                                              .bindingCount = std::uint32_t(layoutBindings.size()),
                                              .pBindings = layoutBindings.data()});
      }()) {
  const vk::PushConstantRange range{.stageFlags = stages, .offset = 0, .size = pushConstantBytes};
  const vk::DescriptorSetLayout setLayout = *setLayout_;
  layout_ = vk::raii::PipelineLayout(context.device(), {.setLayoutCount = 1,
                                                        .pSetLayouts = &setLayout,
                                                        .pushConstantRangeCount = pushConstantBytes ? 1u : 0u,
                                                        .pPushConstantRanges = &range});
}

Descriptors& Descriptors::buffer(std::uint32_t binding, const Buffer& buffer) {
  buffers_.push_back({.buffer = buffer.handle(), .offset = 0, .range = VK_WHOLE_SIZE});
  writes_.push_back({.dstBinding = binding, .descriptorCount = 1, .descriptorType = vk::DescriptorType::eStorageBuffer,
                     .pBufferInfo = &buffers_.back()});
  return *this;
}

Descriptors& Descriptors::accelerationStructure(std::uint32_t binding, vk::AccelerationStructureKHR structure) {
  structureHandles_.push_back(structure);
  structures_.push_back({.accelerationStructureCount = 1, .pAccelerationStructures = &structureHandles_.back()});
  writes_.push_back({.pNext = &structures_.back(),
                     .dstBinding = binding,
                     .descriptorCount = 1,
                     .descriptorType = vk::DescriptorType::eAccelerationStructureKHR});
  return *this;
}

Descriptors& Descriptors::storageImage(std::uint32_t binding, vk::ImageView view) {
  images_.push_back({.imageView = view, .imageLayout = vk::ImageLayout::eGeneral});
  writes_.push_back({.dstBinding = binding, .descriptorCount = 1, .descriptorType = vk::DescriptorType::eStorageImage,
                     .pImageInfo = &images_.back()});
  return *this;
}

Descriptors& Descriptors::sampledImage(std::uint32_t binding, vk::ImageView view, vk::Sampler sampler, vk::ImageLayout layout) {
  images_.push_back({.sampler = sampler, .imageView = view, .imageLayout = layout});
  writes_.push_back({.dstBinding = binding, .descriptorCount = 1, .descriptorType = vk::DescriptorType::eCombinedImageSampler,
                     .pImageInfo = &images_.back()});
  return *this;
}

void Descriptors::push(const vk::raii::CommandBuffer& cmd, vk::PipelineBindPoint point, const PipelineLayout& layout) const {
  if (!writes_.empty()) cmd.pushDescriptorSetKHR(point, layout.handle(), 0, writes_);
}

ComputePipeline::ComputePipeline(const Context& context, std::span<const std::uint32_t> spirv,
                                 std::span<const Binding> bindings, std::uint32_t pushConstantBytes,
                                 const std::string& name, std::span<const std::uint32_t> specialization) {
  Key key("compute");
  key.text(name).all(spirv).add(pushConstantBytes).all(specialization);
  addBindings(key, bindings);
  built_ = std::static_pointer_cast<const BuiltPipeline>(context.shared(key.bytes(), [&] {
    auto built =
        std::make_shared<BuiltPipeline>(context, bindings, vk::ShaderStageFlagBits::eCompute, pushConstantBytes);
    const auto module = shaderModule(context, spirv);
    std::vector<vk::SpecializationMapEntry> entries;
    for (std::uint32_t i = 0; i < specialization.size(); ++i) entries.push_back({i, 4 * i, 4});
    const vk::SpecializationInfo constants{.mapEntryCount = std::uint32_t(entries.size()),
                                           .pMapEntries = entries.data(),
                                           .dataSize = specialization.size_bytes(),
                                           .pData = specialization.data()};
    built->pipeline = vk::raii::Pipeline(
        context.device(), nullptr,
        vk::ComputePipelineCreateInfo{.stage = {.stage = vk::ShaderStageFlagBits::eCompute,
                                                .module = *module,
                                                .pName = "main",
                                                .pSpecializationInfo = entries.empty() ? nullptr : &constants},
                                      .layout = built->layout.handle()});
    context.name(*built->pipeline, name);
    return std::shared_ptr<const void>(std::move(built));
  }));
}

SpecializedComputePipeline::SpecializedComputePipeline(const Context& context, std::span<const std::uint32_t> spirv,
                                                       std::span<const Binding> bindings,
                                                       std::uint32_t pushConstantBytes, std::string name)
    : context_(context), spirv_(spirv), bindings_(bindings), pushConstantBytes_(pushConstantBytes), name_(std::move(name)) {}

const ComputePipeline& SpecializedComputePipeline::operator()(bool value, bool second, bool third) const {
  std::optional<ComputePipeline>& variant = variants_[(value ? 1 : 0) + (second ? 2 : 0) + (third ? 4 : 0)];
  const std::array<std::uint32_t, 3> constants{value ? 1u : 0u, second ? 1u : 0u, third ? 1u : 0u};
  const std::size_t given = third ? 3 : second ? 2 : 1;
  if (!variant) {
    std::string name = name_ + " (";
    for (std::size_t i = 0; i < given; ++i) name += (i ? ", " : "") + std::to_string(constants[i]);
    variant.emplace(context_, spirv_, bindings_, pushConstantBytes_, name + ")",
                    std::span<const std::uint32_t>(constants.data(), given));
  }
  return *variant;
}

void ComputePipeline::bind(const vk::raii::CommandBuffer& cmd, const Descriptors& descriptors) const {
  cmd.bindPipeline(vk::PipelineBindPoint::eCompute, *built_->pipeline);
  descriptors.push(cmd, vk::PipelineBindPoint::eCompute, built_->layout);
}

GraphicsPipeline::GraphicsPipeline(const Context& context, const GraphicsPipelineDesc& desc) {
  Key key("graphics");
  key.text(desc.name).all(desc.vertexSpirv).all(desc.fragmentSpirv).all(desc.geometrySpirv);
  key.all(desc.vertexBindings).all(desc.vertexAttributes).all(desc.colorFormats);
  key.add(desc.depthFormat).add(desc.depthBias).add(desc.depthCompare).add(desc.pushConstantBytes);
  addBindings(key, desc.bindings);
  built_ = std::static_pointer_cast<const BuiltPipeline>(context.shared(key.bytes(), [&] {
    auto built = std::make_shared<BuiltPipeline>(context, desc.bindings, graphicsStages(desc), desc.pushConstantBytes);
    const auto vertexModule = shaderModule(context, desc.vertexSpirv);
    std::optional<vk::raii::ShaderModule> geometryModule;
    std::optional<vk::raii::ShaderModule> fragmentModule;
    std::vector<vk::PipelineShaderStageCreateInfo> stages{
        {.stage = vk::ShaderStageFlagBits::eVertex, .module = *vertexModule, .pName = "main"}};
    if (!desc.geometrySpirv.empty()) {
      geometryModule.emplace(shaderModule(context, desc.geometrySpirv));
      stages.push_back({.stage = vk::ShaderStageFlagBits::eGeometry, .module = **geometryModule, .pName = "main"});
    }
    if (!desc.fragmentSpirv.empty()) {
      fragmentModule.emplace(shaderModule(context, desc.fragmentSpirv));
      stages.push_back({.stage = vk::ShaderStageFlagBits::eFragment, .module = **fragmentModule, .pName = "main"});
    }
    const vk::PipelineVertexInputStateCreateInfo vertexInput{
        .vertexBindingDescriptionCount = std::uint32_t(desc.vertexBindings.size()),
        .pVertexBindingDescriptions = desc.vertexBindings.data(),
        .vertexAttributeDescriptionCount = std::uint32_t(desc.vertexAttributes.size()),
        .pVertexAttributeDescriptions = desc.vertexAttributes.data()};
    const vk::PipelineInputAssemblyStateCreateInfo inputAssembly{.topology = vk::PrimitiveTopology::eTriangleList};
    const vk::PipelineViewportStateCreateInfo viewport{.viewportCount = 1, .scissorCount = 1};
    const vk::PipelineRasterizationStateCreateInfo rasterization{.polygonMode = vk::PolygonMode::eFill,
                                                                 .cullMode = vk::CullModeFlagBits::eNone,
                                                                 .frontFace = vk::FrontFace::eCounterClockwise,
                                                                 .depthBiasEnable = desc.depthBias,
                                                                 .lineWidth = 1.0f};
    const vk::PipelineMultisampleStateCreateInfo multisample{.rasterizationSamples = vk::SampleCountFlagBits::e1};
    const vk::PipelineDepthStencilStateCreateInfo depth{
        .depthTestEnable = VK_TRUE, .depthWriteEnable = VK_TRUE, .depthCompareOp = desc.depthCompare};
    const std::vector<vk::PipelineColorBlendAttachmentState> blend(
        desc.colorFormats.size(), {.blendEnable = VK_FALSE,
                                   .colorWriteMask = vk::ColorComponentFlagBits::eR | vk::ColorComponentFlagBits::eG |
                                                     vk::ColorComponentFlagBits::eB | vk::ColorComponentFlagBits::eA});
    const vk::PipelineColorBlendStateCreateInfo colorBlend{.attachmentCount = std::uint32_t(blend.size()),
                                                           .pAttachments = blend.data()};
    std::vector<vk::DynamicState> dynamic{vk::DynamicState::eViewport, vk::DynamicState::eScissor};
    if (desc.depthBias) dynamic.push_back(vk::DynamicState::eDepthBias);
    const vk::PipelineDynamicStateCreateInfo dynamicState{.dynamicStateCount = std::uint32_t(dynamic.size()),
                                                          .pDynamicStates = dynamic.data()};
    const vk::PipelineRenderingCreateInfo rendering{.colorAttachmentCount = std::uint32_t(desc.colorFormats.size()),
                                                    .pColorAttachmentFormats = desc.colorFormats.data(),
                                                    .depthAttachmentFormat = desc.depthFormat};
    built->pipeline = vk::raii::Pipeline(context.device(), nullptr,
                                         vk::GraphicsPipelineCreateInfo{.pNext = &rendering,
                                                                        .stageCount = std::uint32_t(stages.size()),
                                                                        .pStages = stages.data(),
                                                                        .pVertexInputState = &vertexInput,
                                                                        .pInputAssemblyState = &inputAssembly,
                                                                        .pViewportState = &viewport,
                                                                        .pRasterizationState = &rasterization,
                                                                        .pMultisampleState = &multisample,
                                                                        .pDepthStencilState = &depth,
                                                                        .pColorBlendState = &colorBlend,
                                                                        .pDynamicState = &dynamicState,
                                                                        .layout = built->layout.handle()});
    context.name(*built->pipeline, desc.name);
    return std::shared_ptr<const void>(std::move(built));
  }));
}

void GraphicsPipeline::bind(const vk::raii::CommandBuffer& cmd, const Descriptors& descriptors) const {
  cmd.bindPipeline(vk::PipelineBindPoint::eGraphics, *built_->pipeline);
  pushDescriptors(cmd, descriptors);
}

void GraphicsPipeline::pushDescriptors(const vk::raii::CommandBuffer& cmd, const Descriptors& descriptors) const {
  descriptors.push(cmd, vk::PipelineBindPoint::eGraphics, built_->layout);
}

vk::raii::Sampler makeNearestSampler(const Context& context, const std::string& name) {
  vk::raii::Sampler sampler(context.device(), {.magFilter = vk::Filter::eNearest,
                                               .minFilter = vk::Filter::eNearest,
                                               .mipmapMode = vk::SamplerMipmapMode::eNearest,
                                               .addressModeU = vk::SamplerAddressMode::eClampToEdge,
                                               .addressModeV = vk::SamplerAddressMode::eClampToEdge,
                                               .addressModeW = vk::SamplerAddressMode::eClampToEdge,
                                               .maxLod = 0.0f});
  context.name(*sampler, name);
  return sampler;
}

}  // namespace penumbra::gpu
