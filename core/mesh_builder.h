// Geometry primitives for the built-in scenes. Every primitive appends to a Mesh, gives each vertex
// a unit normal and winds triangles counter-clockwise seen from the side the normals point to
// (outside, or inside for `inward` boxes). None emits a zero-area triangle, so cleanScene keeps all.
#pragma once
#include <glm/glm.hpp>

#include "core/scene.h"

namespace penumbra::mesh {

// Quad p0..p3 (in order around its edge) with a flat normal; wound to face `facing`.
void addQuad(Mesh& m, const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, const glm::vec3& p3,
             const glm::vec3& facing);

// Flat grid of nu x nv cells spanning origin + [0,1]*u + [0,1]*v, facing `facing`.
void addGrid(Mesh& m, const glm::vec3& origin, const glm::vec3& u, const glm::vec3& v, int nu, int nv,
             const glm::vec3& facing);

// Box with centre and three orthogonal half-axes; flat normals (4 vertices per face, 24 in all),
// pointing outward, or inward when `inward` (a room seen from inside).
void addBox(Mesh& m, const glm::vec3& centre, const glm::vec3& halfX, const glm::vec3& halfY,
            const glm::vec3& halfZ, bool inward = false);
// Box of half sizes `half` rotated by `yawDeg` about the vertical axis through its centre.
void addYawedBox(Mesh& m, const glm::vec3& centre, const glm::vec3& half, float yawDeg);

// Capped cylinder from `base` to `top`; smooth sides, flat caps (fans around a centre vertex).
void addCylinder(Mesh& m, const glm::vec3& base, const glm::vec3& top, float radius, int segments);

// UV sphere: `segments` around the vertical axis, `rings` latitude bands; the pole bands are
// triangles around a single pole vertex, so nothing degenerates there.
void addSphere(Mesh& m, const glm::vec3& centre, float radius, int segments, int rings);

// Torus around `axis` through `centre`: ring radius `major`, tube radius `minor`.
void addTorus(Mesh& m, const glm::vec3& centre, const glm::vec3& axis, float major, float minor,
              int majorSegments, int minorSegments);

// Triangle counts of the primitives above, so scenes can document and test their budgets.
constexpr std::size_t gridTriangles(int nu, int nv) { return 2u * std::size_t(nu) * std::size_t(nv); }
constexpr std::size_t boxTriangles() { return 12u; }
constexpr std::size_t cylinderTriangles(int segments) { return 4u * std::size_t(segments); }
constexpr std::size_t sphereTriangles(int segments, int rings) {
  return 2u * std::size_t(segments) * std::size_t(rings - 1);
}
constexpr std::size_t torusTriangles(int majorSegments, int minorSegments) {
  return 2u * std::size_t(majorSegments) * std::size_t(minorSegments);
}

}  // namespace penumbra::mesh
