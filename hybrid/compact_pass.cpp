#include "hybrid/compact_pass.h"

#include <algorithm>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

#include "compact_blocks_comp.h"
#include "compact_scan_comp.h"
#include "compact_scatter_comp.h"
#include "shared/compact.h"
#include "shared/frame.h"
#include "shared/shading_point.h"
#include "shared/trace.h"

namespace penumbra {
namespace {

static_assert(sizeof(shared::CompactPush) == 16);
static_assert(sizeof(shared::ShadingPoint) == 48);
static_assert(sizeof(shared::TraceCount) == 16 && offsetof(shared::TraceCount, groupsX) == 4,
              "the VkDispatchIndirectCommand must sit at byte offset 4");

constexpr gpu::Binding kBindings[] = {{COMPACT_BINDING_POSITION, vk::DescriptorType::eStorageImage},
                                      {COMPACT_BINDING_NORMAL, vk::DescriptorType::eStorageImage},
                                      {COMPACT_BINDING_FLAGS, vk::DescriptorType::eStorageBuffer},
                                      {COMPACT_BINDING_RAYMAX, vk::DescriptorType::eStorageBuffer},
                                      {COMPACT_BINDING_FRAME, vk::DescriptorType::eStorageBuffer},
                                      {COMPACT_BINDING_MASK, vk::DescriptorType::eStorageBuffer},
                                      {COMPACT_BINDING_BLOCKS, vk::DescriptorType::eStorageBuffer},
                                      {COMPACT_BINDING_COUNT, vk::DescriptorType::eStorageBuffer}};

// Pixel indices, block offsets and `first + i` in the shaders are 32-bit.
constexpr std::uint64_t kMaxPixels = std::numeric_limits<std::uint32_t>::max() - COMPACT_BLOCK_PIXELS;

std::string sizeText(std::uint32_t width, std::uint32_t height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

// Checks what the pass needs of the device and the image size; returns the number of blocks.
std::uint32_t checkedBlockCount(const gpu::Context& context, std::uint32_t width, std::uint32_t height) {
  if (width == 0 || height == 0) {
    throw std::invalid_argument("CompactPass: image size " + sizeText(width, height) + " is empty; use at least 1x1");
  }
  // Items: whole tiles, so the last tile column and row count in full.
  // In 64 bits: shared::compactItems would wrap for absurd sizes.
  const std::uint64_t items =
      std::uint64_t(shared::compactTilesX(width)) * ((std::uint64_t(height) + COMPACT_TILE_H - 1) / COMPACT_TILE_H) * COMPACT_ITEMS;
  if (items > kMaxPixels) {
    throw std::invalid_argument("CompactPass: " + sizeText(width, height) + " has more than " +
                                std::to_string(kMaxPixels) + " pixels; render a smaller image");
  }
  const auto chain =
      context.physicalDevice().getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceSubgroupProperties>();
  const auto& subgroup = chain.get<vk::PhysicalDeviceSubgroupProperties>();
  const auto needed = vk::SubgroupFeatureFlagBits::eBasic | vk::SubgroupFeatureFlagBits::eArithmetic;
  if (!(subgroup.supportedStages & vk::ShaderStageFlagBits::eCompute) ||
      (subgroup.supportedOperations & needed) != needed) {
    throw std::runtime_error("CompactPass: the Vulkan device " + context.deviceName() +
                             " lacks basic/arithmetic subgroup operations in compute shaders, which compaction needs");
  }
  return std::uint32_t((items + COMPACT_BLOCK_PIXELS - 1) / COMPACT_BLOCK_PIXELS);
}

std::uint32_t maxGroupsX(const gpu::Context& context) {
  return context.physicalDevice().getProperties().limits.maxComputeWorkGroupCount[0];
}

// Orders every storage write of the previous dispatch before the next one's reads and writes.
void computeToCompute(const vk::raii::CommandBuffer& cmd) {
  const vk::MemoryBarrier2 barrier{
      .srcStageMask = vk::PipelineStageFlagBits2::eComputeShader,
      .srcAccessMask = vk::AccessFlagBits2::eShaderStorageWrite,
      .dstStageMask = vk::PipelineStageFlagBits2::eComputeShader,
      .dstAccessMask = vk::AccessFlagBits2::eShaderStorageRead | vk::AccessFlagBits2::eShaderStorageWrite};
  cmd.pipelineBarrier2({.memoryBarrierCount = 1, .pMemoryBarriers = &barrier});
}

void checkBufferSize(const gpu::Buffer& buffer, vk::DeviceSize needed, const char* what) {
  if (buffer.size() < needed) {
    throw std::invalid_argument(std::string("CompactPass::record: ") + what + " buffer has " +
                                std::to_string(buffer.size()) + " bytes, needs " + std::to_string(needed));
  }
}

}  // namespace

void CompactPass::describeList(shared::FrameData& frame) const {
  frame.tracePoints = gpu::addressHalves(points_);
  frame.traceCapacity = std::uint32_t(points_.size() / sizeof(shared::ShadingPoint));
}

CompactPass::CompactPass(const gpu::Context& context, std::uint32_t width, std::uint32_t height)
    : width_(width),
      height_(height),
      blockCount_(checkedBlockCount(context, width, height)),
      gridX_(std::min(blockCount_, maxGroupsX(context))),
      gridY_((blockCount_ + gridX_ - 1) / gridX_),
      maxListBytes_(context.maxBufferBytes()),
      mask_(context, vk::DeviceSize(blockCount_) * COMPACT_GROUP_SIZE * 4, vk::BufferUsageFlagBits::eStorageBuffer,
            "compact selection mask"),
      blocks_(context, vk::DeviceSize(blockCount_) * 4, vk::BufferUsageFlagBits::eStorageBuffer,
              "compact block offsets"),
      // One point per pixel, but no more than one buffer holds (read through its address, the list
      // is not bound): a frame larger than that still appends its flagged pixels (srt), and the
      // host refuses one that flags more (traced_method).
      points_(context,
              std::min<vk::DeviceSize>(vk::DeviceSize(width) * height, maxListBytes_ / sizeof(shared::ShadingPoint)) *
                  sizeof(shared::ShadingPoint),
              vk::BufferUsageFlagBits::eShaderDeviceAddress, "compact shading points"),
      count_(context, sizeof(shared::TraceCount),
             vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eIndirectBuffer |
                 vk::BufferUsageFlagBits::eTransferDst,
             "compact trace count"),
      scan_(context, compact_scan_comp, kBindings, sizeof(shared::CompactPush), "compact scan pipeline"),
      blockScan_(context, compact_blocks_comp, kBindings, sizeof(shared::CompactPush), "compact block scan pipeline"),
      scatter_(context, compact_scatter_comp, kBindings, sizeof(shared::CompactPush), "compact scatter pipeline") {}

void CompactPass::record(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer,
                         const gpu::Buffer& traceFlags, const gpu::Buffer& rayMax, const gpu::Buffer& frame,
                         std::uint32_t mode) const {
  // Checked here, not at construction: a renderer makes the pass for every image size, and only
  // the methods that trace need it to run.
  const std::uint64_t needed = std::uint64_t(width_) * height_ * sizeof(shared::ShadingPoint);
  if (needed > maxListBytes_) {
    throw std::invalid_argument("CompactPass: " + sizeText(width_, height_) + " needs a " + std::to_string(needed) +
                                "-byte shading-point buffer, over the " + std::to_string(maxListBytes_) +
                                " bytes one buffer of this device holds; trace images of at most " +
                                std::to_string(maxListBytes_ / sizeof(shared::ShadingPoint)) + " pixels");
  }
  if (gbuffer.width() != width_ || gbuffer.height() != height_) {
    throw std::invalid_argument("CompactPass::record: G-buffer is " + sizeText(gbuffer.width(), gbuffer.height()) +
                                " but the pass was made for " + sizeText(width_, height_));
  }
  const std::uint32_t kind = mode & COMPACT_MODE_MASK;
  if ((kind != COMPACT_FLAGGED && kind != COMPACT_ALL_COVERED) || (mode & ~(COMPACT_MODE_MASK | COMPACT_SHARED_SCAN))) {
    throw std::invalid_argument("CompactPass::record: unknown mode " + std::to_string(mode) +
                                "; use COMPACT_FLAGGED or COMPACT_ALL_COVERED, optionally | COMPACT_SHARED_SCAN");
  }
  checkBufferSize(traceFlags, inputBytes(width_, height_), "traceFlags");
  checkBufferSize(rayMax, inputBytes(width_, height_), "rayMax");
  checkBufferSize(frame, sizeof(shared::FrameData), "frame");
  // The scatter writes the list through the frame's address of it: it must be this pass's.
  const auto* data = static_cast<const shared::FrameData*>(frame.data());
  shared::FrameData mine{};
  describeList(mine);
  if (data->tracePoints != mine.tracePoints || data->traceCapacity != mine.traceCapacity) {
    throw std::invalid_argument("CompactPass::record: the frame's trace list is not this pass's points(); fill it with describeList");
  }

  // Execution-only: earlier readers of the mask/points/count in this command buffer (a previous
  // frame's trace, its indirect dispatch) finish before they are overwritten.
  const vk::MemoryBarrier2 warBarrier{
      .srcStageMask = vk::PipelineStageFlagBits2::eComputeShader | vk::PipelineStageFlagBits2::eDrawIndirect,
      .dstStageMask = vk::PipelineStageFlagBits2::eComputeShader};
  cmd.pipelineBarrier2({.memoryBarrierCount = 1, .pMemoryBarriers = &warBarrier});

  // Built in place: Descriptors holds pointers into itself, so it must not be copied.
  gpu::Descriptors descriptors;
  descriptors.storageImage(COMPACT_BINDING_POSITION, gbuffer.position().view())
      .storageImage(COMPACT_BINDING_NORMAL, gbuffer.normal().view())
      .buffer(COMPACT_BINDING_FLAGS, traceFlags)
      .buffer(COMPACT_BINDING_RAYMAX, rayMax)
      .buffer(COMPACT_BINDING_FRAME, frame)
      .buffer(COMPACT_BINDING_MASK, mask_)
      .buffer(COMPACT_BINDING_BLOCKS, blocks_)
      .buffer(COMPACT_BINDING_COUNT, count_);
  const shared::CompactPush push{mode, width_, height_, blockCount_};

  scan_.bind(cmd, descriptors);
  scan_.pushConstants(cmd, push);
  cmd.dispatch(gridX_, gridY_, 1);
  computeToCompute(cmd);

  blockScan_.bind(cmd, descriptors);
  blockScan_.pushConstants(cmd, push);
  cmd.dispatch(1, 1, 1);
  computeToCompute(cmd);

  scatter_.bind(cmd, descriptors);
  scatter_.pushConstants(cmd, push);
  cmd.dispatch(gridX_, gridY_, 1);

  // The trace kernel reads the points in compute and the count as its indirect dispatch; tests
  // and the CPU tracer read both on the host.
  const vk::MemoryBarrier2 done{
      .srcStageMask = vk::PipelineStageFlagBits2::eComputeShader,
      .srcAccessMask = vk::AccessFlagBits2::eShaderStorageWrite,
      .dstStageMask = vk::PipelineStageFlagBits2::eComputeShader | vk::PipelineStageFlagBits2::eDrawIndirect |
                      vk::PipelineStageFlagBits2::eHost,
      .dstAccessMask = vk::AccessFlagBits2::eShaderStorageRead | vk::AccessFlagBits2::eIndirectCommandRead |
                       vk::AccessFlagBits2::eHostRead};
  cmd.pipelineBarrier2({.memoryBarrierCount = 1, .pMemoryBarriers = &done});
}

}  // namespace penumbra
