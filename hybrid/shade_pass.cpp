#include "hybrid/shade_pass.h"

#include <algorithm>

#include "shade_comp.h"
#include "shared/raster.h"

namespace penumbra {
namespace {

constexpr gpu::Binding kBindings[] = {{SHADE_BINDING_POSITION, vk::DescriptorType::eStorageImage},
                                      {SHADE_BINDING_NORMAL, vk::DescriptorType::eStorageImage},
                                      {SHADE_BINDING_ALBEDO, vk::DescriptorType::eStorageImage},
                                      {SHADE_BINDING_FRAME, vk::DescriptorType::eStorageBuffer},
                                      {SHADE_BINDING_VISIBILITY, vk::DescriptorType::eStorageBuffer},
                                      {SHADE_BINDING_COLOR, vk::DescriptorType::eStorageBuffer},
                                      {SHADE_BINDING_INDIRECT, vk::DescriptorType::eStorageBuffer},
                                      {SHADE_BINDING_DIRECT, vk::DescriptorType::eStorageBuffer},
                                      {SHADE_BINDING_LIGHTS, vk::DescriptorType::eStorageBuffer},
                                      {SHADE_BINDING_TILES, vk::DescriptorType::eStorageBuffer}};

}  // namespace

ShadePass::ShadePass(const gpu::Context& context)
    : context_(context), pipeline_(context, shade_comp, kBindings, sizeof(shared::ShadePush), "shade pipeline") {}

void ShadePass::record(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer, const gpu::Buffer& frame,
                       const gpu::Buffer& visibility, const gpu::Buffer& indirect, const gpu::Buffer& color,
                       Term term) const {
  shared::ShadePush push{};
  push.term = std::uint32_t(term);
  push.last = 1u;
  // one light: the shader touches neither the direct sum nor a batch's lists (any buffer will do)
  dispatch(cmd, gbuffer, frame, visibility, indirect, indirect, color, indirect, indirect, push,
           {0u, 0u, gbuffer.width(), gbuffer.height()});
}

void ShadePass::beginLights(std::uint32_t count, std::uint32_t width, std::uint32_t height) {
  const vk::DeviceSize bytes = vk::DeviceSize(width) * height * std::min(count, kBatchImages) * sizeof(float);
  if (!batchVisibility_ || batchVisibility_->size() < bytes) {
    batchVisibility_ = std::make_unique<gpu::Buffer>(
        context_, bytes, vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eTransferDst,
        "light visibilities");
  }
  imageWidth_ = width;
  batch_.clear();
  batchFloats_ = 0;
  batches_ = 0;
  shaded_ = nullptr;
}

namespace {
std::uint64_t area(const glm::uvec4& rect) {
  return rect.z > rect.x && rect.w > rect.y ? std::uint64_t(rect.z - rect.x) * (rect.w - rect.y) : 0u;
}
}  // namespace

bool ShadePass::fits(const glm::uvec4& rect) const {
  return (batchFloats_ + area(rect)) * sizeof(float) <= batchVisibility_->size();
}

void ShadePass::add(const shared::GpuLight& light, const glm::uvec4& rect, std::uint32_t index, bool traced) {
  shared::ShadeLight shaded{};
  shaded.light = light;
  shaded.rect = rect;
  shaded.offset = std::uint32_t(batchFloats_);
  shaded.traced = traced ? 1u : 0u;
  shaded.index = index;
  batch_.push_back(shaded);
  batchFloats_ += area(rect);
}

void ShadePass::recordLight(const vk::raii::CommandBuffer& cmd, const gpu::Buffer& visibility,
                            const shared::GpuLight& light, const glm::uvec4& rect, std::uint32_t index) {
  if (area(rect) == 0) return;  // an empty rectangle: the light reaches no pixel
  // its visibility over its rectangle, row by row (one copy where the rows are whole)
  rows_.clear();
  const std::uint32_t rectWidth = rect.z - rect.x;
  const std::uint32_t rowsPerCopy = rectWidth == imageWidth_ ? rect.w - rect.y : 1u;
  for (std::uint32_t y = rect.y; y < rect.w; y += rowsPerCopy) {
    rows_.push_back({(std::uint64_t(y) * imageWidth_ + rect.x) * sizeof(float),
                     (batchFloats_ + std::uint64_t(y - rect.y) * rectWidth) * sizeof(float),
                     std::uint64_t(rectWidth) * rowsPerCopy * sizeof(float)});
  }
  cmd.copyBuffer(visibility.handle(), batchVisibility_->handle(), rows_);
  add(light, rect, index, false);
}

void ShadePass::addTracedLight(const shared::GpuLight& light, const glm::uvec4& rect, std::uint32_t index) {
  if (area(rect) > 0) add(light, rect, index, true);
}

bool ShadePass::batchTraces() const {
  return std::any_of(batch_.begin(), batch_.end(), [](const shared::ShadeLight& l) { return l.traced != 0u; });
}

ShadePass::BatchLists ShadePass::prepareBatch(std::uint32_t width, std::uint32_t height) {
  // Each tile lists the batch's lights whose rectangle meets it: tiles + 1 starts, then the lists.
  tilesX_ = (width + SHADE_TILE - 1) / SHADE_TILE;
  const std::uint32_t tilesY = (height + SHADE_TILE - 1) / SHADE_TILE;
  tiles_.assign(std::size_t(tilesX_) * tilesY + 1, 0u);
  for (std::uint32_t ty = 0, t = 0; ty < tilesY; ++ty) {
    for (std::uint32_t tx = 0; tx < tilesX_; ++tx, ++t) {
      tiles_[t] = std::uint32_t(tiles_.size());
      const glm::uvec4 tile(tx * SHADE_TILE, ty * SHADE_TILE, (tx + 1) * SHADE_TILE, (ty + 1) * SHADE_TILE);
      for (std::uint32_t k = 0; k < batch_.size(); ++k) {
        const glm::uvec4& r = batch_[k].rect;
        if (r.x < tile.z && tile.x < r.z && r.y < tile.w && tile.y < r.w) tiles_.push_back(k);
      }
    }
  }
  tiles_[std::size_t(tilesX_) * tilesY] = std::uint32_t(tiles_.size());
  if (batches_ == lists_.size()) lists_.push_back(nullptr);
  std::unique_ptr<Lists>& lists = lists_[batches_];
  const vk::DeviceSize lightBytes = std::max<std::size_t>(batch_.size(), 1) * sizeof(shared::ShadeLight);
  const vk::DeviceSize tileBytes = tiles_.size() * sizeof(std::uint32_t);
  if (!lists || lists->lights.size() < lightBytes || lists->tiles.size() < tileBytes) {
    constexpr auto kUsage = vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eShaderDeviceAddress;
    lists = std::make_unique<Lists>(Lists{gpu::Buffer(context_, lightBytes, kUsage, "shade batch lights"),
                                          gpu::Buffer(context_, tileBytes, kUsage, "shade batch tiles")});
  }
  lists->lights.upload(std::span<const shared::ShadeLight>(batch_));
  lists->tiles.upload(std::span<const std::uint32_t>(tiles_));
  // the traced lights' tiles
  glm::uvec4 traced = reach(width, height, true);
  constexpr std::uint32_t kTile = SHADE_TILE;
  traced = traced.z > traced.x ? glm::uvec4(glm::uvec2(traced) / kTile * kTile,
                                            (glm::uvec2(traced.z, traced.w) + (kTile - 1u)) / kTile * kTile)
                               : glm::uvec4(0u);
  return {*lists, tilesX_, traced};
}

glm::uvec4 ShadePass::reach(std::uint32_t width, std::uint32_t height, bool tracedOnly) const {
  glm::uvec4 rect(width, height, 0u, 0u);  // empty
  for (const shared::ShadeLight& light : batch_) {
    if (tracedOnly && light.traced == 0u) continue;
    rect = glm::uvec4(glm::min(glm::uvec2(rect), glm::uvec2(light.rect)),
                      glm::max(glm::uvec2(rect.z, rect.w), glm::uvec2(light.rect.z, light.rect.w)));
  }
  return rect;
}

void ShadePass::recordBatch(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer,
                            const gpu::Buffer& frame, const gpu::Buffer& color, bool last) {
  const std::uint32_t width = gbuffer.width(), height = gbuffer.height();
  const Lists& lists = *lists_.at(batches_);
  const bool sum = batches_ > 0;
  if (!last && !direct_) {
    direct_ = std::make_unique<gpu::Buffer>(context_, vk::DeviceSize(width) * height * sizeof(glm::vec4),
                                            vk::BufferUsageFlagBits::eStorageBuffer, "direct light");
  }
  // The first batch writes every pixel's sum, a later one adds over its lights' rectangles only,
  // the last writes the image.
  const glm::uvec4 rect = sum && !last ? reach(width, height, false) : glm::uvec4(0u, 0u, width, height);
  if (rect.z > rect.x && rect.w > rect.y) {
    shared::ShadePush push{};
    push.origin = glm::uvec2(rect);
    push.term = std::uint32_t(Term::Shadow);  // the methods that take several lights
    push.batched = 1u;
    push.last = last ? 1u : 0u;
    push.sum = sum ? 1u : 0u;
    push.tilesX = tilesX_;
    // no indirect term; the direct sum only where a batch before wrote it (any buffer will do else)
    const gpu::Buffer& direct = direct_ ? *direct_ : *batchVisibility_;
    dispatch(cmd, gbuffer, frame, *batchVisibility_, direct, direct, color, lists.lights, lists.tiles, push, rect);
  }
  shaded_ = &lists;
  shadedLights_ = batch_.size();
  ++batches_;
  batch_.clear();
  batchFloats_ = 0;
  if (!last) {  // the next lights' copies overwrite what this pass reads
    gpu::memoryBarrier(cmd, vk::PipelineStageFlagBits2::eComputeShader, vk::AccessFlagBits2::eShaderStorageRead,
                       vk::PipelineStageFlagBits2::eAllTransfer | vk::PipelineStageFlagBits2::eComputeShader,
                       vk::AccessFlagBits2::eTransferWrite | vk::AccessFlagBits2::eShaderStorageWrite);
  }
}

std::vector<ShadePass::TracedLight> ShadePass::tracedLights() const {
  std::vector<TracedLight> out;
  if (!shaded_) return out;
  const auto* lights = static_cast<const shared::ShadeLight*>(shaded_->lights.data());
  for (std::size_t k = 0; k < shadedLights_; ++k) {
    const shared::ShadeLight& light = lights[k];
    if (light.traced != 0u) out.push_back({light.index, light.rect, light.rays, light.offset});
  }
  return out;
}

void ShadePass::dispatch(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer,
                         const gpu::Buffer& frame, const gpu::Buffer& visibility, const gpu::Buffer& indirect,
                         const gpu::Buffer& direct, const gpu::Buffer& color, const gpu::Buffer& lights,
                         const gpu::Buffer& tiles, const shared::ShadePush& push, const glm::uvec4& rect) const {
  pipeline_.bind(cmd, gpu::Descriptors{}
                          .storageImage(SHADE_BINDING_POSITION, gbuffer.position().view())
                          .storageImage(SHADE_BINDING_NORMAL, gbuffer.normal().view())
                          .storageImage(SHADE_BINDING_ALBEDO, gbuffer.albedo().view())
                          .buffer(SHADE_BINDING_FRAME, frame)
                          .buffer(SHADE_BINDING_VISIBILITY, visibility)
                          .buffer(SHADE_BINDING_COLOR, color)
                          .buffer(SHADE_BINDING_INDIRECT, indirect)
                          .buffer(SHADE_BINDING_DIRECT, direct)
                          .buffer(SHADE_BINDING_LIGHTS, lights)
                          .buffer(SHADE_BINDING_TILES, tiles));
  pipeline_.pushConstants(cmd, push);
  cmd.dispatch((rect.z - rect.x + LOOKUP_GROUP_SIZE - 1) / LOOKUP_GROUP_SIZE,
               (rect.w - rect.y + LOOKUP_GROUP_SIZE - 1) / LOOKUP_GROUP_SIZE, 1);
  gpu::computeToComputeAndHost(cmd);
}

}  // namespace penumbra
