#include "hybrid/denoise_pass.h"

#include <algorithm>
#include <cmath>

#include "core/scene.h"
#include "denoise_accumulate_comp.h"
#include "denoise_spatial_comp.h"
#include "shared/denoise.h"

namespace penumbra {
namespace {

static_assert(sizeof(shared::DenoiseAccumulatePush) == 112 && sizeof(shared::DenoiseSpatialPush) == 32 &&
                  sizeof(shared::DenoiseHistory) == 16,
              "std430 layout of shared/denoise.h");

using Type = vk::DescriptorType;
constexpr gpu::Binding kAccumulateBindings[] = {{DENOISE_ACCUMULATE_BINDING_POSITION, Type::eStorageImage},
                                                {DENOISE_ACCUMULATE_BINDING_NORMAL, Type::eStorageImage},
                                                {DENOISE_ACCUMULATE_BINDING_FRAME, Type::eStorageBuffer},
                                                {DENOISE_ACCUMULATE_BINDING_VISIBILITY, Type::eStorageBuffer},
                                                {DENOISE_ACCUMULATE_BINDING_FLAGS, Type::eStorageBuffer},
                                                {DENOISE_ACCUMULATE_BINDING_HISTORY_IN, Type::eStorageBuffer},
                                                {DENOISE_ACCUMULATE_BINDING_HISTORY_OUT, Type::eStorageBuffer},
                                                {DENOISE_ACCUMULATE_BINDING_ACCUMULATED, Type::eStorageBuffer},
                                                {DENOISE_ACCUMULATE_BINDING_BLOCKERS, Type::eStorageBuffer},
                                                {DENOISE_ACCUMULATE_BINDING_RANGES, Type::eStorageBuffer}};
constexpr gpu::Binding kSpatialBindings[] = {{DENOISE_SPATIAL_BINDING_POSITION, Type::eStorageImage},
                                             {DENOISE_SPATIAL_BINDING_NORMAL, Type::eStorageImage},
                                             {DENOISE_SPATIAL_BINDING_FRAME, Type::eStorageBuffer},
                                             {DENOISE_SPATIAL_BINDING_ACCUMULATED, Type::eStorageBuffer},
                                             {DENOISE_SPATIAL_BINDING_FLAGS, Type::eStorageBuffer},
                                             {DENOISE_SPATIAL_BINDING_BLOCKERS, Type::eStorageBuffer},
                                             {DENOISE_SPATIAL_BINDING_VISIBILITY, Type::eStorageBuffer},
                                             {DENOISE_SPATIAL_BINDING_RANGES, Type::eStorageBuffer}};

vk::DeviceSize pixels(std::uint32_t width, std::uint32_t height) { return vk::DeviceSize(width) * height; }
std::uint32_t groups(std::uint32_t pixels) { return (pixels + DENOISE_GROUP_SIZE - 1) / DENOISE_GROUP_SIZE; }

gpu::Buffer historyBuffer(const gpu::Context& context, std::uint32_t width, std::uint32_t height, const char* name) {
  return gpu::Buffer(context, pixels(width, height) * sizeof(shared::DenoiseHistory), vk::BufferUsageFlagBits::eStorageBuffer,
                     name);
}

// Frames the history may span now: settings.maxHistory, or, when the light moved since `previous`,
// those over which it moves motionFraction of its size (seen from the scene, the angles' ratio).
float historyFrames(const shared::GpuLight& light, const shared::GpuLight& previous, const DenoiseSettings& settings) {
  if (light.type != previous.type || light.size != previous.size) return 1.0f;
  const float moved = glm::distance(glm::vec3(light.position), glm::vec3(previous.position));
  if (moved == 0.0f) return settings.maxHistory;
  return std::clamp(std::floor(settings.motionFraction * light.size / moved), 1.0f, settings.maxHistory);
}

}  // namespace

const Options<DenoiseSettings>& denoiseOptions() {
  static const Options<DenoiseSettings> options = [] {
    Options<DenoiseSettings> o("Soft shadows and denoising");
    o.choice("--denoise", "denoise", &DenoiseSettings::mode,
             "srt/frt with an area light: filter the shadow inside the penumbra (spatial) and over frames (temporal)",
             {{"off", DenoiseMode::Off}, {"spatial", DenoiseMode::Spatial}, {"temporal", DenoiseMode::Temporal}})
        .sweep("denoise", {"srt", "frt"}, true);
    return o;
  }();
  return options;
}

std::string denoiseModeName(DenoiseMode mode) {
  return mode == DenoiseMode::Spatial ? "spatial" : mode == DenoiseMode::Temporal ? "temporal" : "off";
}

DenoisePass::DenoisePass(const gpu::Context& context, std::uint32_t width, std::uint32_t height)
    : width_(width),
      height_(height),
      accumulate_(context, denoise_accumulate_comp, kAccumulateBindings, sizeof(shared::DenoiseAccumulatePush),
                  "denoise accumulate pipeline"),
      spatial_(context, denoise_spatial_comp, kSpatialBindings, sizeof(shared::DenoiseSpatialPush),
               "denoise spatial pipeline"),
      accumulated_(context, pixels(width, height) * 2 * sizeof(float), vk::BufferUsageFlagBits::eStorageBuffer,
                   "denoise accumulated"),
      history_{historyBuffer(context, width, height, "denoise history 0"),
               historyBuffer(context, width, height, "denoise history 1")},
      ranges_(context, pixels(groups(width), groups(height)) * 2 * sizeof(std::uint32_t),
              vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eTransferDst, "denoise tile ranges") {}

std::uint64_t DenoisePass::bytes() const {
  return accumulated_.size() + history_[0].size() + history_[1].size() + ranges_.size();
}

void DenoisePass::record(const vk::raii::CommandBuffer& cmd, const Inputs& in, const DenoiseSettings& settings) {
  const float pixelScale = 2.0f / (std::abs(in.view.proj[1][1]) * float(height_));
  const std::uint32_t groupsX = groups(width_), groupsY = groups(height_);
  const bool temporal = settings.mode == DenoiseMode::Temporal;
  const std::uint32_t next = 1u - current_;
  const float historyFramesNow = historyFrames(in.light, previousLight_, settings);
  // Clipped only where the image may have changed under the history: the light or the geometry moved,
  // or the camera (reprojection takes a neighbouring pixel's history).
  const bool cameraMoved = in.view.viewProj != previousViewProj_;
  const bool changed =
      historyFramesNow < settings.maxHistory || in.sceneVersion != previousSceneVersion_ || cameraMoved;
  using Stage = vk::PipelineStageFlagBits2;
  using Access = vk::AccessFlagBits2;
  gpu::memoryBarrier(cmd, Stage::eComputeShader, Access::eShaderStorageRead, Stage::eTransfer, Access::eTransferWrite);
  cmd.fillBuffer(ranges_.handle(), 0, VK_WHOLE_SIZE, 0u);  // empty tiles: ~lowest and highest 0
  gpu::memoryBarrier(cmd, Stage::eTransfer, Access::eTransferWrite, Stage::eComputeShader,
                     Access::eShaderStorageRead | Access::eShaderStorageWrite);
  gpu::computeToComputeAndHost(cmd);  // the trace's visibility and blocker distances
  accumulate_.bind(cmd, gpu::Descriptors{}
                            .storageImage(DENOISE_ACCUMULATE_BINDING_POSITION, in.gbuffer.position().view())
                            .storageImage(DENOISE_ACCUMULATE_BINDING_NORMAL, in.gbuffer.normal().view())
                            .buffer(DENOISE_ACCUMULATE_BINDING_FRAME, in.frameData)
                            .buffer(DENOISE_ACCUMULATE_BINDING_VISIBILITY, in.visibility)
                            .buffer(DENOISE_ACCUMULATE_BINDING_FLAGS, in.flags)
                            .buffer(DENOISE_ACCUMULATE_BINDING_HISTORY_IN, history_[current_])
                            .buffer(DENOISE_ACCUMULATE_BINDING_HISTORY_OUT, history_[next])
                            .buffer(DENOISE_ACCUMULATE_BINDING_ACCUMULATED, accumulated_)
                            .buffer(DENOISE_ACCUMULATE_BINDING_BLOCKERS, in.blockers)
                            .buffer(DENOISE_ACCUMULATE_BINDING_RANGES, ranges_));
  // The history follows the shadows of a light that moved (denoise_accumulate.comp's shadowBefore).
  const bool followLight = settings.followShadows && historyValid_ && in.light.type == previousLight_.type;
  accumulate_.pushConstants(
      cmd, shared::DenoiseAccumulatePush{
               .previousViewProj = previousViewProj_,
               .lightShift = followLight ? in.light.position - previousLight_.position : glm::vec4(0.0f),
               .pixelScale = pixelScale,
               .maxHistory = historyFramesNow,
               .useHistory = temporal && historyValid_ ? 1u : 0u,
               .useFlags = in.useFlags ? 1u : 0u,
               .clipSigmas = changed ? settings.clipSigmas : 0.0f,
               .followSpread = settings.followSpread,
               .stillCamera = cameraMoved ? 0u : 1u});
  cmd.dispatch(groupsX, groupsY, 1);
  gpu::computeToComputeAndHost(cmd);
  spatial_.bind(cmd, gpu::Descriptors{}
                         .storageImage(DENOISE_SPATIAL_BINDING_POSITION, in.gbuffer.position().view())
                         .storageImage(DENOISE_SPATIAL_BINDING_NORMAL, in.gbuffer.normal().view())
                         .buffer(DENOISE_SPATIAL_BINDING_FRAME, in.frameData)
                         .buffer(DENOISE_SPATIAL_BINDING_ACCUMULATED, accumulated_)
                         .buffer(DENOISE_SPATIAL_BINDING_FLAGS, in.flags)
                         .buffer(DENOISE_SPATIAL_BINDING_BLOCKERS, in.blockers)
                         .buffer(DENOISE_SPATIAL_BINDING_VISIBILITY, in.visibility)
                         .buffer(DENOISE_SPATIAL_BINDING_RANGES, ranges_));
  spatial_.pushConstants(cmd, shared::DenoiseSpatialPush{.pixelScale = pixelScale,
                                                         .maxRadius = settings.maxRadius,
                                                         .targetSamples = settings.targetSamples,
                                                         .useFlags = in.useFlags ? 1u : 0u,
                                                         .widthFraction = settings.widthFraction,
                                                         .skipAgreeing = settings.skipAgreeing ? 1u : 0u});
  cmd.dispatch(groupsX, groupsY, 1);
  gpu::computeToComputeAndHost(cmd);
  current_ = next;
  historyValid_ = temporal;
  previousViewProj_ = in.view.viewProj;
  previousLight_ = in.light;
  previousSceneVersion_ = in.sceneVersion;
}

}  // namespace penumbra
