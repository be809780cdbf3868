#include "apps/demo/camera_controller.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/quaternion.hpp>

#include "core/view.h"

namespace penumbra::demo {
namespace {

constexpr glm::vec3 kUp{0.0f, 1.0f, 0.0f};
// Cameras stay below 85 degrees of pitch: parseCamera picks world +Y as up only below ~87.4, and
// view files do not store the up vector. Lights only avoid the pole.
constexpr float kMaxCameraPitchDeg = 85.0f;
constexpr float kMaxLightElevationDeg = 89.0f;

// The rotation that turns `offset` by `azimuthDeg` about +Y and then tilts it by `elevationDeg`
// toward +Y, with the resulting elevation held within +-maxDeg (a pitch already beyond it is
// left, never snapped).
glm::quat turn(const glm::vec3& offset, float azimuthDeg, float elevationDeg, float maxDeg) {
  const float length = glm::length(offset);
  const float elevation = glm::degrees(std::asin(std::clamp(offset.y / length, -1.0f, 1.0f)));
  const float limit = std::max(maxDeg, std::abs(elevation));
  const float target = std::clamp(elevation + elevationDeg, -limit, limit);
  const glm::quat yaw = glm::angleAxis(glm::radians(azimuthDeg), kUp);
  const glm::vec3 turned = yaw * offset;
  glm::vec3 side = glm::cross(turned, kUp);  // horizontal, perpendicular to the offset
  if (glm::length(side) < 1e-6f * length) return yaw;  // straight up or down: only the azimuth applies
  side = glm::normalize(side);
  // side = offset x up: a positive angle about it turns the offset toward +Y.
  return glm::angleAxis(glm::radians(target - elevation), side) * yaw;
}

}  // namespace

CameraController::CameraController(const Camera& home, const Bounds& bounds)
    : home_(home), camera_(home), radius_(std::max(bounds.radius(), 1e-6f)) {
  home_.up = kUp;
  camera_.up = kUp;
}

void CameraController::setCamera(const Camera& camera) {
  camera_ = camera;
  camera_.up = kUp;
}

void CameraController::orbit(float yawDeg, float pitchDeg) {
  const glm::vec3 offset = camera_.eye - camera_.target;
  camera_.eye = camera_.target + turn(offset, yawDeg, pitchDeg, kMaxCameraPitchDeg) * offset;
}

void CameraController::zoom(float steps) {
  const glm::vec3 offset = camera_.eye - camera_.target;
  const float distance = glm::length(offset);
  const float wanted = std::clamp(distance * std::pow(0.9f, steps), 0.01f * radius_, 20.0f * radius_);
  camera_.eye = camera_.target + offset * (wanted / distance);
}

void CameraController::fly(const glm::vec3& move, float seconds) {
  const glm::vec3 forward = glm::normalize(camera_.target - camera_.eye);
  glm::vec3 right = glm::cross(forward, kUp);
  right = glm::length(right) > 1e-6f ? glm::normalize(right) : glm::vec3(1.0f, 0.0f, 0.0f);
  const glm::vec3 up = glm::cross(right, forward);
  const glm::vec3 delta = (move.x * right + move.y * up + move.z * forward) * (0.5f * radius_ * seconds);
  camera_.eye += delta;
  camera_.target += delta;
}

void moveLight(Light& light, const Bounds& bounds, float azimuthDeg, float elevationDeg) {
  if (light.type == LightType::Directional) {
    // Turn where the light comes from (the negated travel direction) like a position.
    const glm::vec3 from = -light.direction;
    light.direction = -glm::normalize(turn(from, azimuthDeg, elevationDeg, kMaxLightElevationDeg) * from);
    return;
  }
  const glm::vec3 centre = bounds.center();
  const glm::vec3 offset = light.position - centre;
  if (glm::length(offset) < 1e-6f) return;  // at the centre: nothing to turn about
  const glm::quat rotation = turn(offset, azimuthDeg, elevationDeg, kMaxLightElevationDeg);
  light.position = centre + rotation * offset;
  light.direction = glm::normalize(rotation * light.direction);
}

Light convertLight(const Light& light, LightType type, const Bounds& bounds, float sizeFraction) {
  const glm::vec3 centre = bounds.center();
  const glm::vec3 position =
      light.type == LightType::Directional ? centre - 2.0f * bounds.radius() * light.direction : light.position;
  Light converted = light;
  converted.type = type;
  converted.position = position;
  converted.size = 0.0f;
  const glm::vec3 toCentre = centre - position;
  if (glm::length(toCentre) > 1e-6f) converted.direction = glm::normalize(toCentre);
  const bool area = type == LightType::Rect || type == LightType::Disk;
  applyLightSize(converted, area ? sizeFraction : 0.0f, bounds);
  return converted;
}

}  // namespace penumbra::demo
