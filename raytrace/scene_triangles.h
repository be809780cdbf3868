// The scene's triangles by scene-order index (shared/scene_triangles.h), for kernels that shade
// hits or intersect a stored triangle's plane.
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "core/scene.h"
#include "shared/scene_triangles.h"

namespace penumbra {

static_assert(sizeof(shared::SceneTriangle) == 64, "SceneTriangle must match std430");

// One entry per triangle of every mesh (static and dynamic, current pose).
std::vector<shared::SceneTriangle> sceneTriangles(const Scene& scene);

// Octahedral snorm16x2 of a unit vector, as GLSL's packSnorm2x16(octahedralEncode(n)), and back.
std::uint32_t packNormal(const glm::vec3& n);
glm::vec3 unpackNormal(std::uint32_t packed);

}  // namespace penumbra
