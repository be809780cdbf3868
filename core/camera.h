// Camera and light-independent view math shared by the rasterizer and the Embree tracer, so that
// a pixel centre maps to the same ray in both. Vulkan conventions: depth 0..1, y down in NDC,
// pixel (0,0) at the top left.
#pragma once
#include <glm/glm.hpp>

#include "core/scene.h"

namespace penumbra {

struct ViewMatrices {
  glm::mat4 view{1.0f};
  glm::mat4 proj{1.0f};
  glm::mat4 viewProj{1.0f};
  glm::mat4 invViewProj{1.0f};
  // The same projection with depth reversed (near 1, far 0): the camera pass draws with it, so a
  // 32-bit float depth keeps ~24 bits of relative precision over the whole range and orders
  // surfaces a hair apart (a decal over a deck) instead of z-fighting between them.
  glm::mat4 reversedDepthViewProj{1.0f};
  float nearPlane = 0.1f;
  float farPlane = 100.0f;
};

// Perspective view of `camera` with near/far fitted to `bounds` (never clipping the scene).
ViewMatrices cameraMatrices(const Camera& camera, const Bounds& bounds, int width, int height);

// Whether any of the sphere (centre c, radius r) lies inside the view's frustum (conservative: a
// sphere near a frustum corner may pass).
bool sphereInView(const ViewMatrices& m, const glm::vec3& c, float r);

// The pixels [xy, zw) of a width x height image the sphere may cover: the bounds of its box's
// corners projected, one pixel wider; the whole image when a corner lies behind the camera.
glm::uvec4 screenRect(const ViewMatrices& m, const glm::vec3& c, float r, std::uint32_t width, std::uint32_t height);

// World-space ray through the centre of pixel (x, y).
struct Ray {
  glm::vec3 origin;
  glm::vec3 direction;  // unit
};
Ray pixelRay(const ViewMatrices& m, int x, int y, int width, int height);

}  // namespace penumbra
