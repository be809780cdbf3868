#include "raster/bitmask_pass.h"

#include <stdexcept>

#include "bitmask_fit_comp.h"
#include "bitmask_height_frag.h"
#include "bitmask_height_vert.h"
#include "bitmask_hidden_frag.h"
#include "bitmask_hidden_geom.h"
#include "bitmask_hidden_vert.h"
#include "bitmask_resolve_comp.h"
#include "bitmask_table_comp.h"

namespace penumbra::raster {
namespace {

static_assert(sizeof(shared::BitmaskFrame) == 176, "BitmaskFrame must match std430 in shared/bitmask.h");

using Type = vk::DescriptorType;
constexpr gpu::Binding kTableBindings[] = {{BITMASK_TABLE_BINDING_LIGHT, Type::eStorageBuffer},
                                           {BITMASK_TABLE_BINDING_TABLE, Type::eStorageBuffer}};
constexpr gpu::Binding kFitBindings[] = {{BITMASK_FIT_BINDING_POSITION, Type::eStorageImage},
                                         {BITMASK_FIT_BINDING_NORMAL, Type::eStorageImage},
                                         {BITMASK_FIT_BINDING_FRAME, Type::eStorageBuffer},
                                         {BITMASK_FIT_BINDING_BOUNDS, Type::eStorageBuffer}};
constexpr gpu::Binding kResolveBindings[] = {{BITMASK_RESOLVE_BINDING_POSITION, Type::eStorageImage},
                                             {BITMASK_RESOLVE_BINDING_NORMAL, Type::eStorageImage},
                                             {BITMASK_RESOLVE_BINDING_FRAME_DATA, Type::eStorageBuffer},
                                             {BITMASK_RESOLVE_BINDING_FRAME, Type::eStorageBuffer},
                                             {BITMASK_RESOLVE_BINDING_HIDDEN, Type::eStorageBuffer},
                                             {BITMASK_RESOLVE_BINDING_VISIBILITY, Type::eStorageBuffer},
                                             {BITMASK_RESOLVE_BINDING_TRACE_FLAGS, Type::eStorageBuffer},
                                             {BITMASK_RESOLVE_BINDING_HEIGHTS, Type::eStorageBuffer}};

const gpu::Context& checked(const gpu::Context& context) {
  const auto features = context.physicalDevice().getFeatures();
  if (!features.geometryShader || !features.fragmentStoresAndAtomics) {
    throw std::runtime_error("method bitmask needs geometry shaders and fragment-shader atomics, which Vulkan device '" +
                             context.deviceName() + "' lacks; use another method or lavapipe (mesa-vulkan-drivers)");
  }
  return context;
}

gpu::GraphicsPipelineDesc hiddenDesc() {
  gpu::GraphicsPipelineDesc d;
  d.vertexSpirv = bitmask_hidden_vert;
  d.geometrySpirv = bitmask_hidden_geom;
  d.fragmentSpirv = bitmask_hidden_frag;
  readPositions(d);
  d.depthFormat = vk::Format::eUndefined;  // no attachments: fragments OR into a storage buffer
  d.bindings = {{BITMASK_DRAW_BINDING_FRAME, Type::eStorageBuffer},
                {BITMASK_DRAW_BINDING_TABLE, Type::eStorageBuffer},
                {BITMASK_DRAW_BINDING_HIDDEN, Type::eStorageBuffer},
                {BITMASK_DRAW_BINDING_FILL, Type::eStorageBuffer},
                {BITMASK_DRAW_BINDING_HEIGHTS, Type::eStorageBuffer}};
  d.name = "bitmask hidden-samples pipeline";
  return d;
}

gpu::GraphicsPipelineDesc heightDesc() {
  gpu::GraphicsPipelineDesc d;
  d.vertexSpirv = bitmask_height_vert;
  d.fragmentSpirv = bitmask_height_frag;
  readPositions(d);
  d.depthFormat = vk::Format::eUndefined;  // fragments take the greatest height with atomics
  d.bindings = {{BITMASK_DRAW_BINDING_FRAME, Type::eStorageBuffer},
                {BITMASK_DRAW_BINDING_HEIGHTS, Type::eStorageBuffer}};
  d.name = "bitmask height-field pipeline";
  return d;
}

constexpr auto kStorage = vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eTransferDst;

}  // namespace

const Options<BitmaskSettings>& bitmaskOptions() {
  static const Options<BitmaskSettings> options = [] {
    using S = BitmaskSettings;
    Options<S> o("Baselines: pcf, msm, bitmask");
    o.number("--bitmask-res", "bitmask/resolution", &S::resolution,
             "Method bitmask: texels per side of the receiver's hidden-samples map", 16u, 4096u);
    o.list("--bitmask-receivers", "bitmask/receivers", &S::receivers,
           "Method bitmask: the planar meshes that receive its shadows, comma-separated, at most 4 (default: the "
           "planar meshes of at least 1% of the largest one's area)",
           kMaxBitmaskReceivers);
    o.choice("--bitmask-fallback", "bitmask/fallback", &S::fallback,
             "Method bitmask: how pixels off the receiver are answered: srt (classified, only doubtful ones traced) or "
             "frt (all traced)",
             {{"srt", std::string("srt")}, {"frt", std::string("frt")}});
    o.flag("--bitmask-watertight", "bitmask/watertight", &S::watertight,
           "Method bitmask: the casters are closed surfaces wound counter-clockwise seen from outside; their triangles "
           "that face the whole light are dropped (about half the fill; wrong shadows for open surfaces)");
    o.flag("--bitmask-decorrelate", "bitmask/decorrelate", &S::decorrelate,
           "Method bitmask: each map texel sees the light samples under one of the square's 8 symmetries (noise "
           "instead of aliasing; the reference no longer has the same samples)");
    return o;
  }();
  return options;
}

BitmaskTable::BitmaskTable(const gpu::Context& context)
    : context_(context),
      pipeline_(context, bitmask_table_comp, kTableBindings, sizeof(shared::BitmaskTablePush), "bitmask Hough table"),
      light_(context, sizeof(shared::GpuLight), kStorage, "bitmask light") {}

void BitmaskTable::record(const vk::raii::CommandBuffer& cmd, const shared::GpuLight& light, std::uint32_t samples) {
  const std::uint32_t words = (samples + 31) / 32;
  if (words_ != words) {
    words_ = words;
    table_.emplace(context_, vk::DeviceSize(BITMASK_THETA_BINS) * BITMASK_R_BINS * words * 4, kStorage, "bitmask Hough table");
    built_.reset();
  }
  const Key key{light.type, samples, light.sampleFrame};
  reused_ = built_ == key;
  if (reused_) return;
  // The previous frame's passes may still read this host-written buffer: submitAndWait ran them.
  light_.upload(std::span<const shared::GpuLight>(&light, 1));
  pipeline_.bind(
      cmd, gpu::Descriptors{}.buffer(BITMASK_TABLE_BINDING_LIGHT, light_).buffer(BITMASK_TABLE_BINDING_TABLE, *table_));
  pipeline_.pushConstants(cmd, shared::BitmaskTablePush{samples, words});
  const std::uint32_t groups =
      (BITMASK_THETA_BINS * BITMASK_R_BINS * words + BITMASK_TABLE_GROUP_SIZE - 1) / BITMASK_TABLE_GROUP_SIZE;
  const std::uint32_t gx = std::min<std::uint32_t>(groups, 65535), gy = (groups + gx - 1) / gx;
  cmd.dispatch(gx, gy, 1);
  gpu::computeToComputeAndHost(cmd);
  built_ = key;
}

BitmaskPass::BitmaskPass(const gpu::Context& context, std::uint32_t resolution)
    : context_(checked(context)),
      resolution_(resolution),
      fitPipeline_(context, bitmask_fit_comp, kFitBindings, sizeof(std::uint32_t), "bitmask map fit"),
      hiddenPipeline_(context, hiddenDesc()),
      heightPipeline_(context, heightDesc()),
      resolvePipeline_(context, bitmask_resolve_comp, kResolveBindings, 0, "bitmask resolve"),
      frame_(context, sizeof(shared::BitmaskFrame), kStorage, "bitmask frame"),
      bounds_(context, 4 * sizeof(std::uint32_t), kStorage, "bitmask map bounds"),
      fill_(context, 3 * sizeof(std::uint32_t), kStorage, "bitmask fill") {}

vk::DeviceSize BitmaskPass::bytes() const {
  return frame_.size() + bounds_.size() + fill_.size() + (hidden_ ? hidden_->size() : 0) + (heights_ ? heights_->size() : 0);
}

void BitmaskPass::upload(const shared::BitmaskFrame& frame) {
  if (frame.resolution != resolution_) throw std::logic_error("BitmaskPass: the frame's resolution is not the pass's");
  if (words_ != frame.words) {
    words_ = frame.words;
    hidden_.emplace(context_, vk::DeviceSize(resolution_) * resolution_ * words_ * 4, kStorage, "bitmask hidden samples");
  }
  const vk::DeviceSize heightBytes = frame.field.x != 0.0f ? vk::DeviceSize(resolution_) * resolution_ * 4 : 4;
  if (!heights_ || heights_->size() != heightBytes) heights_.emplace(context_, heightBytes, kStorage, "bitmask heights");
  // The previous frame's passes may still read this host-written buffer: submitAndWait ran them.
  frame_.upload(std::span<const shared::BitmaskFrame>(&frame, 1));
}

void BitmaskPass::recordFit(const vk::raii::CommandBuffer& cmd, const GBufferPass& gbuffer) {
  using Stage = vk::PipelineStageFlagBits2;
  using Access = vk::AccessFlagBits2;
  const std::uint32_t empty[4] = {0x7f7fffffu, 0x7f7fffffu, 0u, 0u};  // min at FLT_MAX, max at 0
  cmd.updateBuffer<std::uint32_t>(bounds_.handle(), 0, empty);
  gpu::memoryBarrier(cmd, Stage::eAllTransfer, Access::eTransferWrite, Stage::eComputeShader,
                     Access::eShaderStorageRead | Access::eShaderStorageWrite);
  fitPipeline_.bind(cmd, gpu::Descriptors{}
                             .storageImage(BITMASK_FIT_BINDING_POSITION, gbuffer.position().view())
                             .storageImage(BITMASK_FIT_BINDING_NORMAL, gbuffer.normal().view())
                             .buffer(BITMASK_FIT_BINDING_FRAME, frame_)
                             .buffer(BITMASK_FIT_BINDING_BOUNDS, bounds_));
  fitPipeline_.pushConstants(cmd, 0u);
  cmd.dispatch((gbuffer.width() + BITMASK_GROUP_SIZE - 1) / BITMASK_GROUP_SIZE,
               (gbuffer.height() + BITMASK_GROUP_SIZE - 1) / BITMASK_GROUP_SIZE, 1);
  gpu::memoryBarrier(cmd, Stage::eComputeShader, Access::eShaderStorageWrite, Stage::eComputeShader,
                     Access::eShaderStorageRead | Access::eShaderStorageWrite);
  fitPipeline_.pushConstants(cmd, 1u);
  cmd.dispatch(1, 1, 1);
}

void BitmaskPass::drawOverMap(const vk::raii::CommandBuffer& cmd, const gpu::GraphicsPipeline& pipeline,
                              const gpu::Descriptors& descriptors, const SceneGeometry& geometry) const {
  const vk::Rect2D area{{0, 0}, {resolution_, resolution_}};
  cmd.beginRendering({.renderArea = area, .layerCount = 1});  // no attachments: the shaders write buffers
  cmd.setViewport(0, vk::Viewport{0.0f, 0.0f, float(resolution_), float(resolution_), 0.0f, 1.0f});
  cmd.setScissor(0, area);
  pipeline.bind(cmd, descriptors);
  geometry.bind(cmd);
  geometry.draw(cmd);
  cmd.endRendering();
}

void BitmaskPass::recordDraw(const vk::raii::CommandBuffer& cmd, const BitmaskTable& table, const SceneGeometry& geometry) {
  using Stage = vk::PipelineStageFlagBits2;
  using Access = vk::AccessFlagBits2;
  if (table.words() != words_) throw std::logic_error("BitmaskPass: the table is for another sample count");
  cmd.fillBuffer(hidden_->handle(), 0, VK_WHOLE_SIZE, 0u);
  cmd.fillBuffer(fill_.handle(), 0, VK_WHOLE_SIZE, 0u);
  gpu::memoryBarrier(cmd, Stage::eComputeShader | Stage::eClear, Access::eShaderStorageWrite | Access::eTransferWrite,
                     Stage::eGeometryShader | Stage::eFragmentShader, Access::eShaderStorageRead | Access::eShaderStorageWrite);
  drawOverMap(cmd, hiddenPipeline_,
              gpu::Descriptors{}
                  .buffer(BITMASK_DRAW_BINDING_FRAME, frame_)
                  .buffer(BITMASK_DRAW_BINDING_TABLE, table.buffer())
                  .buffer(BITMASK_DRAW_BINDING_HIDDEN, *hidden_)
                  .buffer(BITMASK_DRAW_BINDING_FILL, fill_)
                  .buffer(BITMASK_DRAW_BINDING_HEIGHTS, *heights_),
              geometry);
  gpu::memoryBarrier(cmd, Stage::eFragmentShader, Access::eShaderStorageWrite, Stage::eComputeShader | Stage::eHost,
                     Access::eShaderStorageRead | Access::eHostRead);
}

void BitmaskPass::recordHidden(const vk::raii::CommandBuffer& cmd, const BitmaskTable& table, const SceneGeometry& geometry,
                               const shared::BitmaskFrame& frame) {
  upload(frame);
  recordDraw(cmd, table, geometry);
}

void BitmaskPass::record(const vk::raii::CommandBuffer& cmd, const BitmaskTable& table, const SceneGeometry& geometry,
                         const SceneGeometry* field, const GBufferPass& gbuffer, const gpu::Buffer& frameData,
                         const shared::BitmaskFrame& frame, const gpu::Buffer& visibility, const gpu::Buffer& traceFlags) {
  using Stage = vk::PipelineStageFlagBits2;
  using Access = vk::AccessFlagBits2;
  upload(frame);
  // The map fitted to the receiver's visible part, on the GPU: the frame buffer the later passes
  // read holds the fitted rectangle.
  recordFit(cmd, gbuffer);
  if (frame.field.x != 0.0f) {  // the field's height over each texel centre of the fitted map
    if (!field) throw std::logic_error("BitmaskPass: a height field without its mesh");
    cmd.fillBuffer(heights_->handle(), 0, VK_WHOLE_SIZE, 0u);
    gpu::memoryBarrier(cmd, Stage::eComputeShader | Stage::eClear, Access::eShaderStorageWrite | Access::eTransferWrite,
                       Stage::eVertexShader | Stage::eFragmentShader, Access::eShaderStorageRead | Access::eShaderStorageWrite);
    drawOverMap(
        cmd, heightPipeline_,
        gpu::Descriptors{}.buffer(BITMASK_DRAW_BINDING_FRAME, frame_).buffer(BITMASK_DRAW_BINDING_HEIGHTS, *heights_),
        *field);
    gpu::memoryBarrier(cmd, Stage::eFragmentShader, Access::eShaderStorageWrite,
                       Stage::eFragmentShader | Stage::eComputeShader, Access::eShaderStorageRead);
  }
  recordDraw(cmd, table, geometry);
  resolvePipeline_.bind(cmd, gpu::Descriptors{}
                                 .storageImage(BITMASK_RESOLVE_BINDING_POSITION, gbuffer.position().view())
                                 .storageImage(BITMASK_RESOLVE_BINDING_NORMAL, gbuffer.normal().view())
                                 .buffer(BITMASK_RESOLVE_BINDING_FRAME_DATA, frameData)
                                 .buffer(BITMASK_RESOLVE_BINDING_FRAME, frame_)
                                 .buffer(BITMASK_RESOLVE_BINDING_HIDDEN, *hidden_)
                                 .buffer(BITMASK_RESOLVE_BINDING_VISIBILITY, visibility)
                                 .buffer(BITMASK_RESOLVE_BINDING_TRACE_FLAGS, traceFlags)
                                 .buffer(BITMASK_RESOLVE_BINDING_HEIGHTS, *heights_));
  cmd.dispatch((gbuffer.width() + BITMASK_GROUP_SIZE - 1) / BITMASK_GROUP_SIZE,
               (gbuffer.height() + BITMASK_GROUP_SIZE - 1) / BITMASK_GROUP_SIZE, 1);
  gpu::computeToComputeAndHost(cmd);
}

}  // namespace penumbra::raster
