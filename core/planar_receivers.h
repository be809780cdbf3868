// Receivers for bitmask visibility sampling (Eisemann & Décoret 2007): meshes whose vertices all
// lie in one plane (a ground, a wall, a floor slab), or, named by the user, height fields over a
// plane (a terrain: every triangle facing one side of it; the paper's extension), with the
// rectangle they span in the plane, on which a hidden-samples map is laid.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/scene.h"

namespace penumbra {

struct PlanarReceiver {
  std::string mesh;       // its name in the scene
  glm::vec3 normal{0.0f}; // unit (either side for a plane: the caller turns it to the light)
  float offset = 0.0f;    // the plane: dot(normal, x) + offset = 0
  glm::vec3 origin{0.0f}; // the rectangle's corner at (0, 0)
  glm::vec3 axisU{0.0f}, axisV{0.0f};  // unit, orthogonal, in the plane
  float extentU = 0.0f, extentV = 0.0f;  // the rectangle's sides along them (world units)
  double area = 0.0;      // of its triangles
  // A height field: the mesh lies on the normal's side of the plane, up to `top` above it (the
  // normal is its up side, not to be turned).
  bool heightField = false;
  float top = 0.0f;
};

// Meshes with at least one triangle whose vertices all lie within `tolerance` of the plane of the
// mesh's largest triangle, largest area first.
std::vector<PlanarReceiver> findPlanarReceivers(const Scene& scene, float tolerance);

// The mesh called `name` as a height field over the plane of its mean normal: nullopt when a
// triangle faces sideways or away from that normal (an overhang or a wall), or no mesh is so called.
std::optional<PlanarReceiver> findHeightField(const Scene& scene, const std::string& name);

}  // namespace penumbra
