#include "hybrid/patch_visibility.h"

#include <bit>
#include <string>

#include "raster/bitmask_pass.h"
#include "raster/scene_geometry.h"

namespace penumbra {
namespace {

glm::vec3 normalOf(const Patch& p) { return glm::normalize(glm::cross(p.u, p.v)); }
glm::vec3 centreOf(const Patch& p) { return p.corner + 0.5f * (p.u + p.v); }

// The source patch as a rect light facing the target: its samples are the shared pattern's.
shared::GpuLight sourceLight(const Patch& from, const Patch& to) {
  shared::GpuLight light{};
  glm::vec3 direction = normalOf(from);
  if (glm::dot(direction, centreOf(to) - centreOf(from)) < 0.0f) direction = -direction;
  light.type = LIGHT_RECT;
  light.position = glm::vec4(centreOf(from), 0.0f);
  light.direction = glm::vec4(direction, 0.0f);
  light.tangent = glm::vec4(glm::normalize(from.u), 0.0f);
  light.size = glm::length(from.u);
  light.sharedPattern = 1;
  return light;
}

}  // namespace

float patchMargin(const Scene& scene) { return 1e-4f * std::max(scene.bounds().radius(), 1e-6f); }

glm::vec3 sourceSample(const Patch& from, const Patch& to, std::uint32_t n, std::uint32_t s) {
  const shared::GpuLight light = sourceLight(from, to);
  const glm::vec2 q = shared::lightSampleOnLight(light, 0, s, n * n);
  const glm::vec3 t(light.tangent), b = glm::cross(glm::vec3(light.direction), t);
  return centreOf(from) + q.x * glm::length(from.u) * t + q.y * glm::length(from.v) * b;
}

glm::vec3 targetSample(const Patch& to, std::uint32_t n, std::uint32_t i) {
  return to.corner + (float(i % n) + 0.5f) / float(n) * to.u + (float(i / n) + 0.5f) / float(n) * to.v;
}

PatchVisibility patchVisibility(const gpu::Context& context, const Scene& scene, const Patch& from, const Patch& to,
                                std::uint32_t n) {
  if (n < 1 || n > 32) throw InputError("visibility: --samples " + std::to_string(n) + " per side is outside 1..32 (32x32 = 1024 samples per patch)");
  const shared::GpuLight light = sourceLight(from, to);
  glm::vec3 normal = normalOf(to);
  float offset = -glm::dot(normal, to.corner);
  if (glm::dot(normal, centreOf(from)) + offset < 0.0f) {  // the map's side is the source's
    normal = -normal;
    offset = -offset;
  }
  const glm::vec3 t(light.tangent), b = glm::cross(glm::vec3(light.direction), t);
  const float margin = patchMargin(scene);
  float beyond = -INFINITY;  // of the target's corners along the source's direction, past its plane
  for (const glm::vec3& c : {to.corner, to.corner + to.u, to.corner + to.v, to.corner + to.u + to.v}) {
    beyond = std::max(beyond, -glm::dot(glm::vec3(light.direction), c - glm::vec3(light.position)));
  }
  shared::BitmaskFrame frame{};
  frame.plane = glm::vec4(normal, offset);
  frame.origin = glm::vec4(to.corner, 1.0f);
  frame.axisU = glm::vec4(glm::normalize(to.u), glm::length(to.u));
  frame.axisV = glm::vec4(glm::normalize(to.v), glm::length(to.v));
  frame.lightCentre = glm::vec4(centreOf(from), light.size);
  frame.lightT = glm::vec4(t, 0.0f);
  frame.lightB = glm::vec4(b, margin);
  frame.samples = n * n;
  frame.words = (n * n + 31) / 32;
  frame.resolution = n;
  frame.onPlane = glm::vec4(0.0f, 0.0f, glm::length(from.v), 0.0f);
  float lowest = INFINITY;  // of the source's corners over the target's plane
  for (int i = 0; i < 4; ++i) lowest = std::min(lowest, glm::dot(normal, shared::lightSquareCorner(frame, i)) + offset);
  frame.lightT.w = lowest;
  if (!(lowest > 2.0f * margin) || !(beyond < -2.0f * margin)) {
    throw InputError("visibility: each patch must lie wholly on the other's front side (they cross or touch each other's plane)");
  }

  const raster::SceneGeometry geometry(context, scene);
  raster::BitmaskTable table(context);
  raster::BitmaskPass pass(context, n);
  context.submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
    table.record(cmd, light, frame.samples);
    pass.recordHidden(cmd, table, geometry, frame);
  });
  PatchVisibility result;
  result.n = n;
  result.words = frame.words;
  result.hidden = pass.hidden().download<std::uint32_t>(std::size_t(n) * n * frame.words);
  result.pairs = std::uint64_t(n) * n * n * n;
  std::uint64_t blocked = 0;
  for (std::uint32_t word : result.hidden) blocked += std::popcount(word);
  result.unblockedPairs = result.pairs - blocked;
  return result;
}

}  // namespace penumbra
