#include "raster/shadow_map_pass.h"
#include "raster/light_faces.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "shadow_map_cutout_frag.h"
#include "shadow_map_cutout_vert.h"
#include "shadow_map_vert.h"
#include "shared/raster.h"

namespace penumbra::raster {
namespace {

glm::vec3 upFor(const glm::vec3& forward) {
  return std::abs(forward.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
}

glm::mat4 perspectiveVk(float fovY, float nearPlane, float farPlane) {
  glm::mat4 p = glm::perspective(fovY, 1.0f, nearPlane, farPlane);
  p[1][1] *= -1.0f;  // Vulkan NDC y points down
  return p;
}

constexpr float kMaxSingleFaceFov = glm::radians(120.0f);
static_assert(sizeof(shared::ShadowMapInfo) == 448, "std430 layout of shared/frame.h");

}  // namespace

const Options<ShadowMapSettings>& shadowMapOptions() {
  static const Options<ShadowMapSettings> options = [] {
    using S = ShadowMapSettings;
    Options<S> o("Shadow maps");
    o.number("--shadow-map-res", "shadow_map_res", &S::resolution, "Shadow map texels per side (per cube face)", 16u,
             16384u)
        .sweep("res", {"sm", "pcf", "pcss", "msm", "srt"}, false, false, "--sm-res");
    o.number("--depth-bias", "shadow_map/depth_bias", &S::depthBiasConstant,
             "Shadow map constant depth bias (rasterizer units)");
    o.number("--slope-bias", "shadow_map/slope_bias", &S::depthBiasSlope, "Shadow map slope-scaled depth bias");
    o.number("--normal-offset", "shadow_map/normal_offset", &S::normalOffsetTexels,
             "Receiver offset along the normal, in shadow-map texels", 0.0f);
    o.choice("--shadow-reads", "shadow_map/reads", &S::reads,
             "How passes read shadow maps: texture (sampled image, right on a GPU), buffer (a storage-buffer copy, far "
             "cheaper on lavapipe), or auto (buffer on CPU devices)",
             {{"auto", S::Reads::Auto}, {"texture", S::Reads::Texture}, {"buffer", S::Reads::Buffer}});
    return o;
  }();
  return options;
}

shared::ShadowMapInfo makeShadowMapInfo(const shared::GpuLight& light, const Bounds& bounds, const ShadowMapSettings& settings,
                                        bool forceCube, float clearance) {
  shared::ShadowMapInfo info{};
  const glm::vec3 centre = bounds.center();
  const float radius = std::max(bounds.radius(), 1e-6f) * 1.01f;
  const float res = float(settings.resolution);
  info.resolution = settings.resolution;
  info.normalOffset = settings.normalOffsetTexels;
  info.slopeBias = settings.depthBiasSlope;
  info.faceCount = 1;

  if (light.type == LIGHT_DIRECTIONAL) {
    const glm::vec3 dir = glm::normalize(glm::vec3(light.direction));
    const glm::vec3 eye = centre - dir * (2.0f * radius);
    info.nearPlane = radius * 0.5f;
    info.farPlane = radius * 3.5f;
    glm::mat4 proj = glm::ortho(-radius, radius, -radius, radius, info.nearPlane, info.farPlane);
    proj[1][1] *= -1.0f;
    info.kind = SHADOW_ORTHO;
    info.viewProj[0] = proj * glm::lookAt(eye, centre, upFor(dir));
    info.texelWorld = 2.0f * radius / res;
    return info;
  }

  const glm::vec3 pos = glm::vec3(light.position);
  info.lightPosition = glm::vec4(pos, 1.0f);
  const float distance = glm::length(centre - pos);
  // Beyond its range a light reaches nothing and nothing there can shadow what it reaches (both ends
  // of such a shadow ray lie within the range's sphere): its maps end there.
  const float reach = light.range > 0.0f ? 1.001f * light.range : std::numeric_limits<float>::max();
  const float farPlane = std::min(distance + radius, reach);
  // The half-angle under which the bounding sphere is seen; a spot never needs more than its cone.
  float halfFov = distance > radius ? std::asin(radius / distance) : kMaxSingleFaceFov;
  glm::vec3 forward = distance > 0.0f ? (centre - pos) / distance : glm::vec3(0, -1, 0);
  if (light.type == LIGHT_SPOT) {
    const float coneHalf = std::acos(std::clamp(light.cosHalfAngle, -1.0f, 1.0f));
    if (distance <= radius || coneHalf < halfFov) {
      halfFov = coneHalf;
      forward = glm::normalize(glm::vec3(light.direction));
    }
  }
  if (2.0f * halfFov < kMaxSingleFaceFov && !forceCube) {
    info.nearPlane = std::max(distance - radius, farPlane * 1e-4f);
    if (info.nearPlane >= farPlane)
      info.nearPlane = 0.5f * farPlane;  // the range ends before the scene: it reaches nothing
    info.farPlane = farPlane;
    info.kind = SHADOW_PERSPECTIVE;
    info.viewProj[0] = perspectiveVk(2.0f * halfFov, info.nearPlane, info.farPlane) * glm::lookAt(pos, pos + forward, upFor(forward));
    info.texelWorld = 2.0f * std::tan(halfFov) / res;
    return info;
  }

  // Cube: faces +X,-X,+Y,-Y,+Z,-Z in the order shadowFace() returns them.
  const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const float farCube = std::min(distance + radius, reach);
  // Depth precision: a stored depth's float step grows as w^2 / near, so a near plane at 1e-4 of the
  // far one made it about a texel at the room's walls (4 steps of it, the layer test's tolerance,
  // hid a wall 0.86 texels over a floor point). Out to half the clearance, it is ~100x finer.
  info.nearPlane = std::max(farCube * kCubeNearFraction, std::min(0.5f * clearance, farCube * 1e-2f));
  info.farPlane = farCube;
  const glm::mat4 proj = perspectiveVk(glm::radians(90.0f), info.nearPlane, info.farPlane);
  info.kind = SHADOW_CUBE;
  info.faceCount = 6;
  for (int f = 0; f < 6; ++f) info.viewProj[f] = proj * glm::lookAt(pos, pos + axes[f], upFor(axes[f]));
  info.texelWorld = 2.0f / res;  // tan(45 deg) = 1
  return info;
}

bool bufferReads(const gpu::Context& context, const ShadowMapSettings& settings) {
  using Reads = ShadowMapSettings::Reads;
  if (settings.reads != Reads::Auto) return settings.reads == Reads::Buffer;
  return context.physicalDevice().getProperties().deviceType == vk::PhysicalDeviceType::eCpu;
}

gpu::Buffer makeTexelBuffer(const gpu::Context& context, const gpu::Image& depth, const ShadowMapSettings& settings) {
  const vk::DeviceSize bytes = bufferReads(context, settings) ? depth.bytes() : 4;
  return gpu::Buffer(context, bytes, vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eTransferDst | vk::BufferUsageFlagBits::eShaderDeviceAddress,
                     depth.desc().name + " texels");
}

ShadowMapPass::ShadowMapPass(const gpu::Context& context, const ShadowMapSettings& settings, std::uint32_t faceCount)
    : settings_(settings),
      depth_(context, {vk::Format::eD32Sfloat, settings.resolution, settings.resolution, faceCount,
                       vk::ImageUsageFlagBits::eDepthStencilAttachment | vk::ImageUsageFlagBits::eSampled |
                           vk::ImageUsageFlagBits::eTransferSrc,  // readable by tests and debugging dumps
                       "shadow map", true}),
      texels_(makeTexelBuffer(context, depth_, settings)),
      sampler_(gpu::makeNearestSampler(context, "shadow map sampler")),
      pipeline_(context, [] {
        gpu::GraphicsPipelineDesc d;
        d.vertexSpirv = shadow_map_vert;
        readPositions(d);
        d.depthBias = true;
        d.pushConstantBytes = sizeof(shared::ShadowMapPush);
        d.name = "shadow map pipeline";
        return d;
      }()),
      cutoutPipeline_(context, [] {
        gpu::GraphicsPipelineDesc d;
        d.vertexSpirv = shadow_map_cutout_vert;
        d.fragmentSpirv = shadow_map_cutout_frag;
        readPositions(d);
        readTextureCoordinates(d);
        d.depthBias = true;
        d.pushConstantBytes = sizeof(shared::CutoutDrawPush);
        d.name = "shadow map cutout pipeline";
        return d;
      }()) {}

void ShadowMapPass::record(const vk::raii::CommandBuffer& cmd, const SceneGeometry& geometry,
                           const shared::ShadowMapInfo& info) const {
  // The constant bias counts steps of the stored depth; a cube map whose near plane moved out
  // (clearance) has finer steps, so it takes more of them: the same bias in world units as at the
  // default near plane, which sm's acne was tuned for (room 512^2: 14 acne pixels, 35 without this).
  const float steps = info.kind == SHADOW_CUBE ? info.nearPlane / (info.farPlane * kCubeNearFraction) : 1.0f;
  recordLightFaces(cmd, depth_, info, [&](std::uint32_t face) {
    cmd.setDepthBias(settings_.depthBiasConstant * steps, 0.0f, settings_.depthBiasSlope);
    pipeline_.bind(cmd, gpu::Descriptors{});
    pipeline_.pushConstants(cmd, shared::ShadowMapPush{info.viewProj[face]});
    geometry.bind(cmd);
    geometry.drawOpaque(cmd);
    if (!geometry.hasCutouts()) return;
    cutoutPipeline_.bind(cmd, gpu::Descriptors{});
    geometry.drawCutouts(cmd, [&](const CutoutDraw& draw) {
      cutoutPipeline_.pushConstants(cmd, geometry.cutoutPush(info.viewProj[face], glm::vec4(0.0f), draw));
    });
  }, texelCopy(texels_, depth_));
}

}  // namespace penumbra::raster
