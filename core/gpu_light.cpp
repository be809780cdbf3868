#include "core/gpu_light.h"

#include <cmath>

namespace penumbra {

shared::GpuLight toGpuLight(const Light& light, const Bounds& bounds, float rayEpsilonFraction) {
  shared::GpuLight g{};
  const glm::vec3 dir = glm::normalize(light.direction);
  // Any unit vector orthogonal to dir spans the rect/disk together with cross(dir, tangent).
  const glm::vec3 helper = std::abs(dir.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  const glm::vec3 tangent = glm::normalize(glm::cross(helper, dir));
  g.position = glm::vec4(light.position, 0.0f);
  g.direction = glm::vec4(dir, 0.0f);
  g.tangent = glm::vec4(tangent, 0.0f);
  g.color = glm::vec4(light.color * light.intensity, light.inverseSquare ? 1.0f : 0.0f);
  switch (light.type) {
    case LightType::Directional: g.type = LIGHT_DIRECTIONAL; break;
    case LightType::Spot: g.type = LIGHT_SPOT; break;
    case LightType::Point: g.type = LIGHT_POINT; break;
    case LightType::Rect: g.type = LIGHT_RECT; break;
    case LightType::Disk: g.type = LIGHT_DISK; break;
  }
  g.size = light.size;
  g.cosHalfAngle = light.type == LightType::Spot ? std::cos(glm::radians(0.5f * light.spotAngleDeg)) : -1.0f;
  g.range = light.range;
  g.cosInnerHalfAngle = light.type == LightType::Spot && light.innerAngleDeg >= 0.0f
                            ? std::cos(glm::radians(0.5f * light.innerAngleDeg))
                            : -1.0f;
  g.rayEpsilon = rayEpsilonFraction * std::max(bounds.radius(), 1e-6f);
  return g;
}

}  // namespace penumbra
