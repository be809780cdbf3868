#include "core/camera.h"

#include <algorithm>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

namespace penumbra {

ViewMatrices cameraMatrices(const Camera& camera, const Bounds& bounds, int width, int height) {
  ViewMatrices m;
  const glm::vec3 forward = glm::normalize(camera.target - camera.eye);
  const float radius = std::max(bounds.radius(), 1e-6f);
  const float centreDepth = glm::dot(bounds.center() - camera.eye, forward);
  m.farPlane = std::max(centreDepth + radius * 1.01f, radius * 1e-3f);
  // Keep far/near <= 1e4 so 32-bit depth stays precise; a camera inside the scene gets a small near.
  m.nearPlane = std::max(centreDepth - radius * 1.01f, m.farPlane * 1e-4f);
  m.view = glm::lookAt(camera.eye, camera.target, camera.up);
  m.proj = glm::perspective(glm::radians(camera.fovYDeg), float(width) / float(height), m.nearPlane,
                            m.farPlane);
  m.proj[1][1] *= -1.0f;  // Vulkan NDC has y pointing down
  m.viewProj = m.proj * m.view;
  // z' = w - z of the projection above, written directly (n / (f - n) and f n / (f - n)) rather
  // than subtracted in float, where it would cancel.
  glm::mat4 reversed = m.proj;
  reversed[2][2] = m.nearPlane / (m.farPlane - m.nearPlane);
  reversed[3][2] = m.farPlane * m.nearPlane / (m.farPlane - m.nearPlane);
  m.reversedDepthViewProj = reversed * m.view;
  m.invViewProj = glm::inverse(m.viewProj);
  return m;
}

Ray pixelRay(const ViewMatrices& m, int x, int y, int width, int height) {
  const glm::vec2 ndc{(2.0f * (float(x) + 0.5f)) / float(width) - 1.0f,
                      (2.0f * (float(y) + 0.5f)) / float(height) - 1.0f};
  glm::vec4 nearPoint = m.invViewProj * glm::vec4(ndc, 0.0f, 1.0f);
  glm::vec4 farPoint = m.invViewProj * glm::vec4(ndc, 1.0f, 1.0f);
  const glm::vec3 a = glm::vec3(nearPoint) / nearPoint.w;
  const glm::vec3 b = glm::vec3(farPoint) / farPoint.w;
  return {a, glm::normalize(b - a)};
}

bool sphereInView(const ViewMatrices& m, const glm::vec3& c, float r) {
  const glm::mat4& v = m.viewProj;  // planes from its rows (Gribb & Hartmann); Vulkan depth 0..1
  const auto row = [&](int i) { return glm::vec4(v[0][i], v[1][i], v[2][i], v[3][i]); };
  const glm::vec4 planes[6] = {row(3) + row(0), row(3) - row(0), row(3) + row(1),
                               row(3) - row(1), row(2),          row(3) - row(2)};
  for (const glm::vec4& p : planes) {
    const float length = glm::length(glm::vec3(p));
    if (length > 0.0f && (glm::dot(glm::vec3(p), c) + p.w) / length < -r) return false;
  }
  return true;
}

glm::uvec4 screenRect(const ViewMatrices& m, const glm::vec3& c, float r, std::uint32_t width, std::uint32_t height) {
  const glm::uvec4 whole(0u, 0u, width, height);
  glm::vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 corner = c + r * glm::vec3(i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f);
    const glm::vec4 clip = m.viewProj * glm::vec4(corner, 1.0f);
    if (clip.w <= m.nearPlane) return whole;
    const glm::vec2 uv = (glm::vec2(clip) / clip.w * 0.5f + 0.5f) * glm::vec2(float(width), float(height));
    lo = glm::min(lo, uv);
    hi = glm::max(hi, uv);
  }
  const glm::vec2 size{float(width), float(height)};
  lo = glm::clamp(glm::floor(lo) - 1.0f, glm::vec2(0.0f), size);
  hi = glm::clamp(glm::ceil(hi) + 1.0f, glm::vec2(0.0f), size);
  return glm::uvec4(glm::uvec2(lo), glm::uvec2(hi));
}

}  // namespace penumbra
