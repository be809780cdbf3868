#include "gpu/resources.h"

#include <algorithm>
#include <stdexcept>

namespace penumbra::gpu {

Buffer::Buffer(const Context& context, vk::DeviceSize size, vk::BufferUsageFlags usage, const std::string& name)
    : size_(std::max<vk::DeviceSize>(size, 16)),
      buffer_(context.device(), vk::BufferCreateInfo{.size = size_, .usage = usage}) {
  const auto requirements = buffer_.getMemoryRequirements();
  const vk::MemoryAllocateFlagsInfo addressable{.flags = vk::MemoryAllocateFlagBits::eDeviceAddress};
  memory_ = vk::raii::DeviceMemory(
      context.device(),
      {.pNext = (usage & vk::BufferUsageFlagBits::eShaderDeviceAddress) ? &addressable : nullptr,
       .allocationSize = requirements.size,
       .memoryTypeIndex = context.memoryType(requirements.memoryTypeBits, vk::MemoryPropertyFlagBits::eHostVisible |
                                                                              vk::MemoryPropertyFlagBits::eHostCoherent)});
  buffer_.bindMemory(*memory_, 0);
  mapped_ = memory_.mapMemory(0, VK_WHOLE_SIZE);
  context.name(*buffer_, name);
  if (usage & vk::BufferUsageFlagBits::eShaderDeviceAddress) address_ = context.device().getBufferAddress({.buffer = *buffer_});
}

vk::DeviceAddress Buffer::address() const {
  if (address_ == 0) throw std::logic_error("Buffer::address: the buffer was made without eShaderDeviceAddress usage");
  return address_;
}

void Buffer::checkFits(std::size_t bytes) const {
  if (bytes > size_) {
    throw std::out_of_range("buffer access of " + std::to_string(bytes) + " bytes exceeds its size " + std::to_string(size_));
  }
}

std::uint32_t bytesPerTexel(vk::Format format) {
  switch (format) {
    case vk::Format::eR32G32B32A32Sfloat: return 16;
    case vk::Format::eR8G8B8A8Unorm: return 4;
    case vk::Format::eR8G8B8A8Srgb:
      return 4;
    case vk::Format::eD32Sfloat: return 4;
    case vk::Format::eR32Sfloat: return 4;
    case vk::Format::eR32Uint: return 4;
    default: throw std::invalid_argument("bytesPerTexel: format not used by Penumbra");
  }
}

Image::Image(const Context& context, const ImageDesc& desc)
    : desc_(desc),
      image_(context.device(), vk::ImageCreateInfo{.imageType = vk::ImageType::e2D,
                                                   .format = desc.format,
                                                   .extent = {desc.width, desc.height, 1},
                                                   .mipLevels = desc.mipLevels,
                                                   .arrayLayers = desc.layers,
                                                   .samples = vk::SampleCountFlagBits::e1,
                                                   .tiling = vk::ImageTiling::eOptimal,
                                                   .usage = desc.usage,
                                                   .initialLayout = vk::ImageLayout::eUndefined}) {
  const auto requirements = image_.getMemoryRequirements();
  memory_ = vk::raii::DeviceMemory(
      context.device(),
      {.allocationSize = requirements.size,
       .memoryTypeIndex = context.memoryType(requirements.memoryTypeBits, vk::MemoryPropertyFlagBits::eDeviceLocal)});
  image_.bindMemory(*memory_, 0);
  auto makeView = [&](vk::ImageViewType type, std::uint32_t base, std::uint32_t count) {
    return vk::raii::ImageView(context.device(), {.image = *image_,
                                                  .viewType = type,
                                                  .format = desc.format,
                                                  .subresourceRange = {aspect(), 0, desc.mipLevels, base, count}});
  };
  view_ = makeView(desc.layers == 1 && !desc.arrayView ? vk::ImageViewType::e2D : vk::ImageViewType::e2DArray, 0, desc.layers);
  for (std::uint32_t layer = 0; layer < desc.layers; ++layer) layerViews_.push_back(makeView(vk::ImageViewType::e2D, layer, 1));
  context.name(*image_, desc.name);
  context.name(*view_, desc.name + " view");
}

vk::ImageAspectFlags Image::aspect() const {
  return desc_.format == vk::Format::eD32Sfloat ? vk::ImageAspectFlagBits::eDepth : vk::ImageAspectFlagBits::eColor;
}

vk::DeviceSize Image::bytes() const {
  vk::DeviceSize texels = 0;
  for (std::uint32_t level = 0; level < desc_.mipLevels; ++level) {
    texels += vk::DeviceSize(std::max(desc_.width >> level, 1u)) * std::max(desc_.height >> level, 1u);
  }
  return texels * desc_.layers * bytesPerTexel(desc_.format);
}

void transition(const vk::raii::CommandBuffer& cmd, const Image& image, const Transition& t) {
  const vk::ImageMemoryBarrier2 barrier{
      .srcStageMask = t.srcStage,
      .srcAccessMask = t.srcAccess,
      .dstStageMask = t.dstStage,
      .dstAccessMask = t.dstAccess,
      .oldLayout = t.from,
      .newLayout = t.to,
      .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
      .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
      .image = image.handle(),
      .subresourceRange = {image.aspect(), 0, image.desc().mipLevels, 0, image.desc().layers}};
  cmd.pipelineBarrier2({.imageMemoryBarrierCount = 1, .pImageMemoryBarriers = &barrier});
}

void computeToComputeAndHost(const vk::raii::CommandBuffer& cmd) {
  const vk::MemoryBarrier2 barrier{.srcStageMask = vk::PipelineStageFlagBits2::eComputeShader,
                                   .srcAccessMask = vk::AccessFlagBits2::eShaderStorageWrite,
                                   .dstStageMask = vk::PipelineStageFlagBits2::eComputeShader | vk::PipelineStageFlagBits2::eHost,
                                   .dstAccessMask = vk::AccessFlagBits2::eShaderStorageRead | vk::AccessFlagBits2::eHostRead};
  cmd.pipelineBarrier2({.memoryBarrierCount = 1, .pMemoryBarriers = &barrier});
}

void memoryBarrier(const vk::raii::CommandBuffer& cmd, vk::PipelineStageFlags2 srcStage, vk::AccessFlags2 srcAccess,
                   vk::PipelineStageFlags2 dstStage, vk::AccessFlags2 dstAccess) {
  const vk::MemoryBarrier2 barrier{
      .srcStageMask = srcStage, .srcAccessMask = srcAccess, .dstStageMask = dstStage, .dstAccessMask = dstAccess};
  cmd.pipelineBarrier2({.memoryBarrierCount = 1, .pMemoryBarriers = &barrier});
}

void copyImageToBuffer(const vk::raii::CommandBuffer& cmd, const Image& image, const Buffer& buffer) {
  if (buffer.size() < image.bytes()) throw std::out_of_range("readback buffer smaller than image " + image.desc().name);
  const vk::BufferImageCopy region{.bufferOffset = 0,
                                   .imageSubresource = {image.aspect(), 0, 0, image.desc().layers},
                                   .imageExtent = {image.desc().width, image.desc().height, 1}};
  using Stage = vk::PipelineStageFlagBits2;
  using Access = vk::AccessFlagBits2;
  transition(cmd, image, {vk::ImageLayout::eGeneral, vk::ImageLayout::eTransferSrcOptimal, Stage::eAllCommands,
                          Access::eMemoryWrite, Stage::eCopy, Access::eTransferRead});
  cmd.copyImageToBuffer(image.handle(), vk::ImageLayout::eTransferSrcOptimal, buffer.handle(), region);
  transition(cmd, image, {vk::ImageLayout::eTransferSrcOptimal, vk::ImageLayout::eGeneral, Stage::eCopy, Access::eTransferRead,
                          Stage::eAllCommands, Access::eMemoryRead | Access::eMemoryWrite});
  const vk::MemoryBarrier2 toHost{.srcStageMask = vk::PipelineStageFlagBits2::eCopy,
                                  .srcAccessMask = vk::AccessFlagBits2::eTransferWrite,
                                  .dstStageMask = vk::PipelineStageFlagBits2::eHost,
                                  .dstAccessMask = vk::AccessFlagBits2::eHostRead};
  cmd.pipelineBarrier2({.memoryBarrierCount = 1, .pMemoryBarriers = &toHost});
}

}  // namespace penumbra::gpu
