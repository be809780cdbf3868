// Planar receivers for bitmask visibility sampling (Eisemann & Décoret 2007): meshes whose
// vertices all lie in one plane (a ground, a wall, a floor slab), with the rectangle they span in
// it, on which a hidden-samples map is laid.
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/scene.h"

namespace penumbra {

struct PlanarReceiver {
  std::string mesh;       // its name in the scene
  glm::vec3 normal{0.0f}; // unit (either side: the caller turns it to the light)
  float offset = 0.0f;    // the plane: dot(normal, x) + offset = 0
  glm::vec3 origin{0.0f}; // the rectangle's corner at (0, 0)
  glm::vec3 axisU{0.0f}, axisV{0.0f};  // unit, orthogonal, in the plane
  float extentU = 0.0f, extentV = 0.0f;  // the rectangle's sides along them (world units)
  double area = 0.0;      // of its triangles
};

// Meshes with at least one triangle whose vertices all lie within `tolerance` of the plane of the
// mesh's largest triangle, largest area first.
std::vector<PlanarReceiver> findPlanarReceivers(const Scene& scene, float tolerance);

}  // namespace penumbra
