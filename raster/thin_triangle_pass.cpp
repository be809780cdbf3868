#include "raster/thin_triangle_pass.h"
#include "raster/light_faces.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "shared/thin.h"
#include "thin_select_comp.h"
#include "thin_triangles_frag.h"
#include "thin_triangles_geom.h"
#include "thin_triangles_vert.h"

namespace penumbra::raster {
namespace {

static_assert(sizeof(shared::ThinTrianglePush) == 112, "ThinTrianglePush must match std430 in shared/thin.h");
static_assert(sizeof(shared::ThinSelectPush) == 128, "ThinSelectPush must match std430 in shared/thin.h");

const ThinTriangleSettings& checked(const gpu::Context& context, const ThinTriangleSettings& thin) {
  if (!context.physicalDevice().getFeatures().geometryShader) {
    throw std::runtime_error("the thin-triangle pass needs geometry shaders, which Vulkan device '" +
                             context.deviceName() + "' lacks; run without it or use lavapipe (mesa-vulkan-drivers)");
  }
  if (!std::isfinite(thin.maxWidthTexels) || thin.maxWidthTexels <= 0.0f) {
    throw InputError("thin-triangle max width " + std::to_string(thin.maxWidthTexels) +
                     " texels is not a positive number; use e.g. 1");
  }
  if (!std::isfinite(thin.minAspect) || thin.minAspect < 0.0f) {
    throw InputError("thin-triangle min aspect " + std::to_string(thin.minAspect) +
                     " is not a non-negative number; use e.g. 4 (0 makes every narrow triangle thin)");
  }
  return thin;
}

gpu::GraphicsPipelineDesc pipelineDesc() {
  gpu::GraphicsPipelineDesc d;
  d.vertexSpirv = thin_triangles_vert;
  d.geometrySpirv = thin_triangles_geom;
  d.fragmentSpirv = thin_triangles_frag;
  readPositions(d);
  d.depthBias = false;  // a bias would push the mask behind the triangle: not conservative
  d.pushConstantBytes = sizeof(shared::ThinTrianglePush);
  d.name = "thin triangle pipeline";
  return d;
}

constexpr gpu::Binding kSelectBindings[] = {{THIN_SELECT_BINDING_VERTICES, vk::DescriptorType::eStorageBuffer},
                                            {THIN_SELECT_BINDING_INDICES, vk::DescriptorType::eStorageBuffer},
                                            {THIN_SELECT_BINDING_DRAWS, vk::DescriptorType::eStorageBuffer},
                                            {THIN_SELECT_BINDING_LIST, vk::DescriptorType::eStorageBuffer}};
constexpr vk::DeviceSize kDrawStride = THIN_DRAW_WORDS * sizeof(std::uint32_t);
constexpr std::uint32_t kDrawCommandBytes = 5 * sizeof(std::uint32_t);  // VkDrawIndexedIndirectCommand

shared::ThinTrianglePush pushFor(const shared::ShadowMapInfo& info, std::uint32_t face, const ThinTriangleSettings& thin) {
  return {.viewProj = info.viewProj[face],
          .resolution = float(info.resolution),
          .maxWidthTexels = thin.maxWidthTexels,
          .minAspect = thin.minAspect,
          .texelWorld = info.texelWorld};
}

// The push constants of a cut-out mesh's draw.
shared::ThinTrianglePush cutoutPush(shared::ThinTrianglePush push, const SceneGeometry& geometry, const CutoutDraw& draw) {
  push.cutouts = 1u;
  push.firstCutout = draw.firstTriangle;
  push.cutoutTriangles = geometry.cutoutTrianglesAddress();
  push.cutoutTexels = geometry.cutoutTexelsAddress();
  return push;
}

}  // namespace

const Options<ThinTriangleSettings>& thinOptions() {
  static const Options<ThinTriangleSettings> options = [] {
    Options<ThinTriangleSettings> o("Selective ray tracing (srt)");
    o.number("--thin-width", "thin/width_texels", &ThinTriangleSettings::maxWidthTexels,
             "Thin triangle: smallest light-space altitude below this many texels", 0.0f);
    o.number("--thin-aspect", "thin/aspect", &ThinTriangleSettings::minAspect,
             "Thin triangle: and longest edge / altitude at least this", 0.0f);
    return o;
  }();
  return options;
}

ThinTrianglePass::ThinTrianglePass(const gpu::Context& context, const ShadowMapSettings& settings, std::uint32_t faceCount,
                                   ThinTriangleSettings thin)
    : settings_(settings),
      thin_(checked(context, thin)),
      // Transfer source too: tests and debugging dumps read the mask back.
      depth_(context, {vk::Format::eD32Sfloat, settings.resolution, settings.resolution, faceCount,
                       vk::ImageUsageFlagBits::eDepthStencilAttachment | vk::ImageUsageFlagBits::eSampled |
                           vk::ImageUsageFlagBits::eTransferSrc,
                       "thin triangle mask", true}),
      texels_(makeTexelBuffer(context, depth_, settings)),
      sampler_(gpu::makeNearestSampler(context, "thin triangle mask sampler")),
      pipeline_(context, pipelineDesc()),
      select_(context, thin_select_comp, kSelectBindings, sizeof(shared::ThinSelectPush), "thin triangle selection"),
      context_(context),
      draws_(context, faceCount * kDrawStride,
             vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eIndirectBuffer |
                 vk::BufferUsageFlagBits::eTransferDst,
             "thin triangle draws") {}

void ThinTrianglePass::recordSelection(const vk::raii::CommandBuffer& cmd, const SceneGeometry& geometry,
                                       const shared::ShadowMapInfo& info) {
  const std::uint32_t triangles = geometry.indexCount() / 3;
  const std::uint32_t faces = info.faceCount;
  // Thin triangles are usually a small share of a scene: a quarter fits most (settings). One
  // storage binding holds all faces' lists.
  const vk::DeviceSize maxRange = context_.storageBufferRange();
  const std::uint32_t wanted = thin_.listCapacity ? thin_.listCapacity : std::max<std::uint32_t>(65536, triangles / 4);
  const std::uint32_t capacity =
      std::max<std::uint32_t>(1, std::min<vk::DeviceSize>({triangles, wanted, maxRange / (12 * faces)}));
  if (!list_ || capacity_ != capacity) {
    capacity_ = capacity;
    list_ = std::make_unique<gpu::Buffer>(context_, vk::DeviceSize(faces) * capacity * 12,
                                          vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eIndexBuffer,
                                          "thin triangle list");
  }
  using Stage = vk::PipelineStageFlagBits2;
  using Access = vk::AccessFlagBits2;
  // A selection recorded earlier in the same command buffer may still be drawing from both.
  gpu::memoryBarrier(cmd, Stage::eDrawIndirect | Stage::eIndexInput, Access::eIndirectCommandRead | Access::eIndexRead,
                     Stage::eAllTransfer | Stage::eComputeShader, Access::eTransferWrite | Access::eShaderStorageWrite);
  std::vector<std::uint32_t> init(std::size_t(faces) * THIN_DRAW_WORDS, 0u);
  for (std::uint32_t face = 0; face < faces; ++face) {
    std::uint32_t* d = &init[std::size_t(face) * THIN_DRAW_WORDS];
    d[THIN_DRAW_LIST + 1] = 1;                      // instanceCount
    d[THIN_DRAW_LIST + 2] = face * capacity * 3;    // firstIndex
    d[THIN_DRAW_ALL + 1] = 1;
  }
  cmd.updateBuffer<std::uint32_t>(draws_.handle(), 0, init);
  gpu::memoryBarrier(cmd, Stage::eAllTransfer, Access::eTransferWrite, Stage::eComputeShader,
                     Access::eShaderStorageRead | Access::eShaderStorageWrite);
  if (triangles > 0) {
    select_.bind(cmd, gpu::Descriptors{}
                          .buffer(THIN_SELECT_BINDING_VERTICES, geometry.vertices())
                          .buffer(THIN_SELECT_BINDING_INDICES, geometry.indices())
                          .buffer(THIN_SELECT_BINDING_DRAWS, draws_)
                          .buffer(THIN_SELECT_BINDING_LIST, *list_));
    const std::uint32_t groups = (triangles + THIN_SELECT_GROUP_SIZE - 1) / THIN_SELECT_GROUP_SIZE;
    const std::uint32_t gx = std::min<std::uint32_t>(groups, 65535), gy = (groups + gx - 1) / gx;
    for (std::uint32_t face = 0; face < faces; ++face) {
      select_.pushConstants(cmd, shared::ThinSelectPush{.thin = pushFor(info, face, thin_),
                                                        .face = face,
                                                        .capacity = capacity,
                                                        .triangles = triangles,
                                                        .rowInvocations = gx * THIN_SELECT_GROUP_SIZE});
      cmd.dispatch(gx, gy, 1);
    }
  }
  gpu::memoryBarrier(cmd, Stage::eComputeShader, Access::eShaderStorageWrite, Stage::eDrawIndirect | Stage::eIndexInput,
                     Access::eIndirectCommandRead | Access::eIndexRead);
}

std::uint64_t ThinTrianglePass::thinTriangles() const {
  const auto words = draws_.download<std::uint32_t>(std::size_t(faceCount()) * THIN_DRAW_WORDS);
  std::uint64_t n = 0;
  for (std::uint32_t face = 0; face < faceCount(); ++face) n += words[std::size_t(face) * THIN_DRAW_WORDS + THIN_DRAW_COUNT];
  return n;
}

vk::DeviceSize ThinTrianglePass::bytes() const {
  return depth_.bytes() + texels_.size() + draws_.size() + (list_ ? list_->size() : 0);
}

void ThinTrianglePass::record(const vk::raii::CommandBuffer& cmd, const SceneGeometry& geometry,
                              const shared::ShadowMapInfo& info) {
  Selection key{&geometry, geometry.version(), info.texelWorld, {}};
  for (std::uint32_t face = 0; face < info.faceCount; ++face) key.viewProj[face] = info.viewProj[face];
  reused_ = selection_ == key;
  // The mask depends on nothing else: the last one (image and texel copy) still holds.
  if (reused_) return;
  recordSelection(cmd, geometry, info);
  selection_ = key;
  recordLightFaces(cmd, depth_, info, [&](std::uint32_t face) {
    pipeline_.bind(cmd, gpu::Descriptors{});
    pipeline_.pushConstants(cmd, pushFor(info, face, thin_));
    geometry.bind(cmd);
    cmd.bindIndexBuffer(list_->handle(), 0, vk::IndexType::eUint32);
    cmd.drawIndexedIndirect(draws_.handle(), face * kDrawStride + THIN_DRAW_LIST * 4, 1, kDrawCommandBytes);
    cmd.bindIndexBuffer(geometry.indices().handle(), 0, vk::IndexType::eUint32);
    cmd.drawIndexedIndirect(draws_.handle(), face * kDrawStride + THIN_DRAW_ALL * 4, 1, kDrawCommandBytes);
    // every cut-out triangle, thin or not (thin_cutout.glsl)
    geometry.drawCutouts(cmd, [&](const CutoutDraw& draw) {
      pipeline_.pushConstants(cmd, cutoutPush(pushFor(info, face, thin_), geometry, draw));
    });
  }, texelCopy(texels_, depth_));
}

}  // namespace penumbra::raster
