#include "raster/thin_triangle_pass.h"
#include "raster/light_faces.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "shared/thin.h"
#include "thin_triangles_frag.h"
#include "thin_triangles_geom.h"
#include "thin_triangles_vert.h"

namespace penumbra::raster {
namespace {

static_assert(sizeof(shared::ThinTrianglePush) == 80, "ThinTrianglePush must match std430 in shared/thin.h");

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
  d.vertexBindings = {{.binding = 0, .stride = sizeof(RasterVertex), .inputRate = vk::VertexInputRate::eVertex}};
  d.vertexAttributes = {{0, 0, vk::Format::eR32G32B32Sfloat, offsetof(RasterVertex, position)}};
  d.depthBias = false;  // a bias would push the mask behind the triangle: not conservative
  d.pushConstantBytes = sizeof(shared::ThinTrianglePush);
  d.name = "thin triangle pipeline";
  return d;
}

}  // namespace

ThinTrianglePass::ThinTrianglePass(const gpu::Context& context, const ShadowMapSettings& settings, std::uint32_t faceCount,
                                   ThinTriangleSettings thin)
    : settings_(settings),
      thin_(checked(context, thin)),
      // Transfer source too: tests and debugging dumps read the mask back.
      depth_(context, {vk::Format::eD32Sfloat, settings.resolution, settings.resolution, faceCount,
                       vk::ImageUsageFlagBits::eDepthStencilAttachment | vk::ImageUsageFlagBits::eSampled |
                           vk::ImageUsageFlagBits::eTransferSrc,
                       "thin triangle mask", true}),
      sampler_(gpu::makeNearestSampler(context, "thin triangle mask sampler")),
      pipeline_(context, pipelineDesc()) {}

void ThinTrianglePass::record(const vk::raii::CommandBuffer& cmd, const SceneGeometry& geometry,
                              const shared::ShadowMapInfo& info) const {
  recordLightFaces(cmd, depth_, info, [&](std::uint32_t face) {
    pipeline_.bind(cmd, gpu::Descriptors{});
    pipeline_.pushConstants(cmd, shared::ThinTrianglePush{.viewProj = info.viewProj[face],
                                                          .resolution = float(info.resolution),
                                                          .maxWidthTexels = thin_.maxWidthTexels,
                                                          .minAspect = thin_.minAspect,
                                                          .texelWorld = info.texelWorld});
    geometry.bind(cmd);
    geometry.draw(cmd);
  });
}

}  // namespace penumbra::raster
