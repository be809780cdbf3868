#include "raster/pip_classify_pass.h"

#include <algorithm>

#include "pip_classify_comp.h"

namespace penumbra::raster {
namespace {

constexpr gpu::Binding kBindings[] = {{PIP_BINDING_POSITION, vk::DescriptorType::eStorageImage},
                                      {PIP_BINDING_NORMAL, vk::DescriptorType::eStorageImage},
                                      {PIP_BINDING_SHADOW_MAP, vk::DescriptorType::eCombinedImageSampler},
                                      {PIP_BINDING_THIN_MASK, vk::DescriptorType::eCombinedImageSampler},
                                      {PIP_BINDING_FRAME, vk::DescriptorType::eStorageBuffer},
                                      {PIP_BINDING_VISIBILITY, vk::DescriptorType::eStorageBuffer},
                                      {PIP_BINDING_SM_VISIBILITY, vk::DescriptorType::eStorageBuffer},
                                      {PIP_BINDING_TRACE_FLAGS, vk::DescriptorType::eStorageBuffer},
                                      {PIP_BINDING_RAY_MAX, vk::DescriptorType::eStorageBuffer},
                                      {PIP_BINDING_COUNT, vk::DescriptorType::eStorageBuffer},
                                      {PIP_BINDING_WHY, vk::DescriptorType::eStorageBuffer},
                                      {PIP_BINDING_FACE_NORMAL, vk::DescriptorType::eStorageImage},
                                      {PIP_BINDING_MASK_TILES, vk::DescriptorType::eStorageBuffer},
                                      {PIP_BINDING_TILE_DOUBT_LAST, vk::DescriptorType::eStorageBuffer},
                                      {PIP_BINDING_TILE_DOUBT, vk::DescriptorType::eStorageBuffer}};

}  // namespace

const Options<PipSettings>& pipOptions() {
  static const Options<PipSettings> options = [] {
    Options<PipSettings> o("Selective ray tracing (srt)");
    o.number("--pip-delta", "pip/delta", &PipSettings::deltaFraction,
             "PIP depth-edge threshold, fraction of the light's depth range", 0.0f)
        .sweep("delta", {"srt"});
    o.number("--pip-margin", "pip/margin_texels", &PipSettings::marginTexels,
             "PIP receiver depth interval widened by this many texels", 0.0f)
        .sweep("margin", {"srt"});
    o.choice("--penumbra-maps", "pip/penumbra_maps", &PipSettings::penumbraMaps,
             "Area lights: penumbra mask from the centre's shadow map (1) or also the four corners' (5)",
             {{"1", 1u}, {"5", 5u}})
        .sweep("pmaps", {"srt"}, true);
    o.flag("--no-thin", "pip/thin_pass", &PipSettings::thinPass, "Turn off the thin-triangle conservative pass of srt",
           false);
    o.choice("--tile-test", "pip/tile_test", &PipSettings::tileTest,
             "Area lights: search the penumbra mask once for each 8x8 tile of pixels first; where that finds no "
             "blocker, none of the tile's pixels searches (off: every pixel searches; the same mask). auto: per light, "
             "with or without it by its own timings of both (the light's first frame warms with it, the next two "
             "time each, every 32nd the other again)",
             {{"auto", TileTest::Auto}, {"on", TileTest::On}, {"off", TileTest::Off}});
    o.choice("--tile-choice", "pip/tile_choice", &PipSettings::tileChoice,
             "Area lights: trace every pixel of an 8x8 tile, without classifying or searching any, where the last "
             "frame found so many of them doubtful that the frame's cost model (the classification's time per tile, "
             "the trace's per traced pixel, both timed on this device) predicts it cheaper; each such tile is "
             "classified again every 8th frame. off: the paper's per-pixel classification everywhere",
             {{"on", true}, {"off", false}});
    o.choice("--ray-intervals", "pip/ray_intervals", &PipSettings::rayIntervals,
             "Bound srt's hard-shadow rays by the shadow map's blocker depths", {{"on", true}, {"off", false}});
    return o;
  }();
  return options;
}

PipClassifyPass::PipClassifyPass(const gpu::Context& context)
    : pipeline_(context, pip_classify_comp, kBindings, sizeof(shared::PipPush), "pip classify pipeline") {}

shared::PipPush PipClassifyPass::pushFor(const PipSettings& settings, const shared::ShadowMapInfo& info, bool thinMaskBound,
                                         float sceneRadius) {
  shared::PipPush push{};
  push.deltaThreshold = settings.deltaFraction * (info.farPlane - info.nearPlane);
  // A texel's world size at the scene's far side bounds the depth error of one texel.
  const float texel = info.kind == SHADOW_ORTHO ? info.texelWorld : info.texelWorld * info.farPlane;
  push.depthMargin = settings.marginTexels * std::min(texel, sceneRadius);
  push.useThin = thinMaskBound ? 1u : 0u;
  push.useIntervals = settings.rayIntervals ? 1u : 0u;
  return push;
}

void PipClassifyPass::recordTileTest(const vk::raii::CommandBuffer& cmd, const GBufferPass& gbuffer,
                                     const ShadowMapPass& shadowMap, const ThinTrianglePass* thin,
                                     const DepthPyramidPass& pyramid, const gpu::Buffer& frame, const PipBuffers& out,
                                     shared::PipPush push, bool explain) const {
  gpu::Descriptors descriptors;  // built in place: it holds pointers into itself
  complete(descriptors, push, gbuffer, shadowMap, thin, pyramid, frame, out);
  const gpu::ComputePipeline& pipeline = pipeline_(texelReads(shadowMap, thin), explain, true);
  pipeline.bind(cmd, descriptors);
  pipeline.pushConstants(cmd, push);
  const std::uint32_t tilesX = (gbuffer.width() + PIP_MASK_TILE_SIZE - 1) / PIP_MASK_TILE_SIZE;
  const std::uint32_t tilesY = (gbuffer.height() + PIP_MASK_TILE_SIZE - 1) / PIP_MASK_TILE_SIZE;
  cmd.dispatch((tilesX + PIP_GROUP_SIZE - 1) / PIP_GROUP_SIZE, (tilesY + PIP_GROUP_SIZE - 1) / PIP_GROUP_SIZE, 1);
  gpu::memoryBarrier(cmd, vk::PipelineStageFlagBits2::eComputeShader, vk::AccessFlagBits2::eShaderStorageWrite,
                     vk::PipelineStageFlagBits2::eComputeShader, vk::AccessFlagBits2::eShaderStorageRead);
}

void PipClassifyPass::record(const vk::raii::CommandBuffer& cmd, const GBufferPass& gbuffer,
                             const ShadowMapPass& shadowMap, const ThinTrianglePass* thin,
                             const DepthPyramidPass& pyramid, const gpu::Buffer& frame, const PipBuffers& out,
                             shared::PipPush push, bool explain) const {
  if (explain) cmd.fillBuffer(out.why.handle(), 0, VK_WHOLE_SIZE, PIP_WHY_NONE);
  if (push.tileTraceBelow != 0u) cmd.fillBuffer(out.tileDoubt.handle(), 0, VK_WHOLE_SIZE, 0u);
  if (explain || push.tileTraceBelow != 0u) {
    gpu::memoryBarrier(cmd, vk::PipelineStageFlagBits2::eClear, vk::AccessFlagBits2::eTransferWrite,
                       vk::PipelineStageFlagBits2::eComputeShader,
                       vk::AccessFlagBits2::eShaderStorageWrite | vk::AccessFlagBits2::eShaderStorageRead);
  }
  gpu::Descriptors descriptors;
  complete(descriptors, push, gbuffer, shadowMap, thin, pyramid, frame, out);
  const gpu::ComputePipeline& pipeline = pipeline_(texelReads(shadowMap, thin), explain);
  pipeline.bind(cmd, descriptors);
  pipeline.pushConstants(cmd, push);
  cmd.dispatch((gbuffer.width() + PIP_GROUP_SIZE - 1) / PIP_GROUP_SIZE,
               (gbuffer.height() + PIP_GROUP_SIZE - 1) / PIP_GROUP_SIZE, 1);
  gpu::computeToComputeAndHost(cmd);
}

void PipClassifyPass::complete(gpu::Descriptors& descriptors, shared::PipPush& push, const GBufferPass& gbuffer,
                               const ShadowMapPass& shadowMap, const ThinTrianglePass* thin,
                               const DepthPyramidPass& pyramid, const gpu::Buffer& frame, const PipBuffers& out) {
  push.pyramidLevels = pyramid.levels();
  push.shadowTexelsAt = gpu::addressHalves(shadowMap.texels());
  push.thinTexelsAt = gpu::addressHalves(thin ? thin->texels() : shadowMap.texels());
  push.tilesAt = gpu::addressHalves(pyramid.tiles());
  // Without a thin mask the bindings still need an image and a buffer: the shadow map's stand in, unread.
  const vk::ImageView thinView = thin ? thin->depth().view() : shadowMap.depth().view();
  descriptors.storageImage(PIP_BINDING_POSITION, gbuffer.position().view())
      .storageImage(PIP_BINDING_NORMAL, gbuffer.normal().view())
      .sampledImage(PIP_BINDING_SHADOW_MAP, shadowMap.depth().view(), shadowMap.sampler())
      .sampledImage(PIP_BINDING_THIN_MASK, thinView, thin ? thin->sampler() : shadowMap.sampler())
      .buffer(PIP_BINDING_FRAME, frame)
      .buffer(PIP_BINDING_VISIBILITY, out.visibility)
      .buffer(PIP_BINDING_SM_VISIBILITY, out.smVisibility)
      .buffer(PIP_BINDING_TRACE_FLAGS, out.traceFlags)
      .buffer(PIP_BINDING_RAY_MAX, out.rayMax)
      .buffer(PIP_BINDING_COUNT, out.count)
      .buffer(PIP_BINDING_WHY, out.why)
      .storageImage(PIP_BINDING_FACE_NORMAL, gbuffer.faceNormal().view())
      .buffer(PIP_BINDING_MASK_TILES, out.maskTiles)
      .buffer(PIP_BINDING_TILE_DOUBT_LAST, out.tileDoubtLast)
      .buffer(PIP_BINDING_TILE_DOUBT, out.tileDoubt);
}

}  // namespace penumbra::raster
