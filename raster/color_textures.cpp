#include "raster/color_textures.h"

#include <algorithm>
#include <bit>

#include "gpu/upload.h"

namespace penumbra::raster {
namespace {

constexpr vk::Format kFormat = vk::Format::eR8G8B8A8Srgb;

std::uint32_t mipLevels(std::uint32_t width, std::uint32_t height) {
  return std::bit_width(std::max({width, height, 1u}));
}

// Whether some mesh draws with scene texture `t` as its colour.
std::vector<char> colorTextures(const Scene& scene) {
  std::vector<char> used(scene.textures.size(), 0);
  for (const Mesh& m : scene.meshes) {
    if (m.colorTexture >= 0 && std::size_t(m.colorTexture) < used.size()) used[std::size_t(m.colorTexture)] = 1;
  }
  return used;
}

// A barrier moving `levels` of `image` between layouts, ordering the blits and the camera pass's reads.
void barrier(const vk::raii::CommandBuffer& cmd, const gpu::Image& image, std::uint32_t first, std::uint32_t count,
             vk::ImageLayout from, vk::ImageLayout to) {
  using Stage = vk::PipelineStageFlagBits2;
  using Access = vk::AccessFlagBits2;
  const bool toShader = to == vk::ImageLayout::eShaderReadOnlyOptimal;
  const vk::ImageMemoryBarrier2 b{
      .srcStageMask = Stage::eAllTransfer,
      .srcAccessMask = Access::eTransferWrite,
      .dstStageMask = toShader ? Stage::eFragmentShader : Stage::eAllTransfer,
      .dstAccessMask = toShader ? Access::eShaderSampledRead : Access::eTransferRead | Access::eTransferWrite,
      .oldLayout = from,
      .newLayout = to,
      .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
      .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
      .image = image.handle(),
      .subresourceRange = {vk::ImageAspectFlagBits::eColor, first, count, 0, 1}};
  cmd.pipelineBarrier2({.imageMemoryBarrierCount = 1, .pImageMemoryBarriers = &b});
}

// Records the upload of `staging` into level 0 and the blits down the chain; leaves every level
// readable by shaders.
void recordUpload(const vk::raii::CommandBuffer& cmd, const gpu::Image& image, const gpu::Buffer& staging) {
  const struct {
    std::uint32_t width, height, count;
  } levels{image.desc().width, image.desc().height, image.desc().mipLevels};
  barrier(cmd, image, 0, levels.count, vk::ImageLayout::eUndefined, vk::ImageLayout::eTransferDstOptimal);
  cmd.copyBufferToImage(staging.handle(), image.handle(), vk::ImageLayout::eTransferDstOptimal,
                        vk::BufferImageCopy{.imageSubresource = {vk::ImageAspectFlagBits::eColor, 0, 0, 1},
                                            .imageExtent = {levels.width, levels.height, 1}});
  for (std::uint32_t level = 1; level < levels.count; ++level) {
    barrier(cmd, image, level - 1, 1, vk::ImageLayout::eTransferDstOptimal, vk::ImageLayout::eTransferSrcOptimal);
    const auto corner = [&](std::uint32_t l) {
      return vk::Offset3D{std::int32_t(std::max(levels.width >> l, 1u)), std::int32_t(std::max(levels.height >> l, 1u)),
                          1};
    };
    const vk::ImageBlit blit{.srcSubresource = {vk::ImageAspectFlagBits::eColor, level - 1, 0, 1},
                             .srcOffsets = std::array{vk::Offset3D{0, 0, 0}, corner(level - 1)},
                             .dstSubresource = {vk::ImageAspectFlagBits::eColor, level, 0, 1},
                             .dstOffsets = std::array{vk::Offset3D{0, 0, 0}, corner(level)}};
    cmd.blitImage(image.handle(), vk::ImageLayout::eTransferSrcOptimal, image.handle(),
                  vk::ImageLayout::eTransferDstOptimal, blit, vk::Filter::eLinear);
  }
  if (levels.count > 1) {
    barrier(cmd, image, 0, levels.count - 1, vk::ImageLayout::eTransferSrcOptimal,
            vk::ImageLayout::eShaderReadOnlyOptimal);
  }
  barrier(cmd, image, levels.count - 1, 1, vk::ImageLayout::eTransferDstOptimal,
          vk::ImageLayout::eShaderReadOnlyOptimal);
}

}  // namespace

ColorTextures::ColorTextures(const gpu::Context& context, const Scene& scene)
    : imageOf_(scene.textures.size(), 0),
      sampler_(context.device(), vk::SamplerCreateInfo{.magFilter = vk::Filter::eLinear,
                                                       .minFilter = vk::Filter::eLinear,
                                                       .mipmapMode = vk::SamplerMipmapMode::eLinear,
                                                       .addressModeU = vk::SamplerAddressMode::eRepeat,
                                                       .addressModeV = vk::SamplerAddressMode::eRepeat,
                                                       .addressModeW = vk::SamplerAddressMode::eRepeat,
                                                       .maxLod = VK_LOD_CLAMP_NONE}) {
  context.name(*sampler_, "colour texture sampler");
  static const Texture white{"white", 1, 1, {255, 255, 255, 255}};
  const std::vector<char> used = colorTextures(scene);
  std::vector<const Texture*> sources{&white};
  for (std::size_t t = 0; t < used.size(); ++t) {
    if (!used[t]) continue;
    imageOf_[t] = std::uint32_t(sources.size());
    sources.push_back(&scene.textures[t]);
  }
  images_.reserve(sources.size());
  std::vector<gpu::Buffer> staging;
  staging.reserve(sources.size());
  for (const Texture* t : sources) {
    const vk::ImageUsageFlags usage =
        vk::ImageUsageFlagBits::eSampled | vk::ImageUsageFlagBits::eTransferDst | vk::ImageUsageFlagBits::eTransferSrc;
    images_.emplace_back(context, gpu::ImageDesc{.format = kFormat,
                                                 .width = t->width,
                                                 .height = t->height,
                                                 .usage = usage,
                                                 .name = "colour texture " + t->name,
                                                 .mipLevels = mipLevels(t->width, t->height)});
    staging.push_back(gpu::uploadedBuffer(context, std::span(t->rgba), vk::BufferUsageFlagBits::eTransferSrc,
                                          "colour texture staging"));
  }
  context.submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
    for (std::size_t i = 0; i < images_.size(); ++i) recordUpload(cmd, images_[i], staging[i]);
  });
}

vk::ImageView ColorTextures::view(std::int32_t texture) const {
  return images_[texture < 0 ? 0 : imageOf_.at(std::size_t(texture))].view();
}

vk::DeviceSize ColorTextures::bytes() const {
  vk::DeviceSize total = 0;
  for (const gpu::Image& image : images_) total += image.bytes();
  return total;
}

std::uint64_t colorTextureBytes(const Scene& scene) {
  const std::vector<char> used = colorTextures(scene);
  std::uint64_t total = 0;
  for (std::size_t t = 0; t < used.size(); ++t) {
    if (used[t]) total += scene.textures[t].rgba.size() * 7 / 3;  // the chain adds a third; staging a copy
  }
  return total;
}

}  // namespace penumbra::raster
