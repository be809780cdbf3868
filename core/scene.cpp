#include "core/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/gtc/matrix_transform.hpp>

namespace penumbra {

Bounds Scene::bounds() const {
  Bounds b;
  std::vector<bool> animated(meshes.size(), false);
  for (const MeshAnimation& animation : animations) {
    if (animation.mesh < animated.size()) animated[animation.mesh] = true;
  }
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    if (animated[m]) continue;  // bounded by its sweep below, the same at every time
    for (const glm::vec3& p : meshes[m].positions) b.extend(p);
  }
  // An animated mesh lies within radius r of its rest box centre c turned and moved by the pose.
  // The translation is linear between keys and the turned centre stays within |c| of it, so boxes
  // around the keys' translations, |c| + r wide, hold every pose in between.
  for (const MeshAnimation& animation : animations) {
    Bounds rest;
    for (const glm::vec3& p : animation.restPositions) rest.extend(p);
    if (rest.empty()) continue;
    const float reach = glm::length(rest.center()) + rest.radius();
    for (const RigidKey& key : animation.keys) {
      b.extend(key.translation - glm::vec3(reach));
      b.extend(key.translation + glm::vec3(reach));
    }
  }
  return b;
}

void WorldBounds::extend(const glm::dvec3& p) {
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return;
  lo = glm::min(lo, p);
  hi = glm::max(hi, p);
}

glm::dvec3 WorldBounds::origin() const {
  if (!(lo.x <= hi.x)) return glm::dvec3(0.0);
  const glm::dvec3 centre = 0.5 * (lo + hi);
  const double radius = 0.5 * glm::length(hi - lo);
  if (!(glm::length(centre) > 16.0 * radius)) return glm::dvec3(0.0);
  if (!(radius > 0.0)) return centre;
  const double step = std::exp2(std::floor(std::log2(radius)));
  return glm::round(centre / step) * step;
}

glm::dmat4 placeMeshes(Scene& scene, const std::vector<glm::dmat4>& meshWorld) {
  WorldBounds world;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    for (const glm::vec3& v : scene.meshes[m].positions) world.extend(glm::dvec3(meshWorld[m] * glm::dvec4(v, 1.0)));
  }
  scene.origin = world.origin();
  const glm::dmat4 toScene = glm::translate(glm::dmat4(1.0), -scene.origin);
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const glm::dmat4 place = toScene * meshWorld[m];
    for (glm::vec3& v : scene.meshes[m].positions) v = glm::vec3(place * glm::dvec4(v, 1.0));
  }
  return toScene;
}

std::size_t Scene::triangleCount() const {
  std::size_t n = 0;
  for (const Mesh& mesh : meshes) n += mesh.triangleCount();
  return n;
}

const char* lightTypeName(LightType type) {
  switch (type) {
    case LightType::Directional: return "dir";
    case LightType::Spot: return "spot";
    case LightType::Point: return "point";
    case LightType::Rect: return "rect";
    case LightType::Disk: return "disk";
  }
  return "unknown";
}

namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Keeps the triangles that are drawable; returns how many of each kind were dropped.
struct Dropped {
  std::size_t nonFinite = 0, badIndex = 0, degenerate = 0;
};

// A colour texture and a cut-out need their texture and a texture coordinate per vertex. Without
// them the colour is baseColor alone, and the cut-out's factor decides for the whole mesh: solid
// (an opaque mesh) or cut away (no triangles).
void cleanTextures(Mesh& mesh, std::size_t textures, std::vector<std::string>& warnings) {
  if (mesh.uvs.size() != mesh.positions.size()) mesh.uvs.clear();
  for (glm::vec2& uv : mesh.uvs) {
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = glm::vec2(0.0f);
  }
  if (mesh.colorTexture >= 0 && (std::size_t(mesh.colorTexture) >= textures || mesh.uvs.empty())) {
    warnings.push_back("mesh '" + mesh.name + "': its colour texture " +
                       (mesh.uvs.empty() ? "has no texture coordinates" : "is missing") +
                       "; its base colour alone is drawn");
    mesh.colorTexture = -1;
  }
  if (!mesh.cutout) return;
  Cutout& c = *mesh.cutout;
  if (c.texture >= 0 && (std::size_t(c.texture) >= textures || mesh.uvs.empty())) {
    warnings.push_back("mesh '" + mesh.name + "': its alpha texture " +
                       (mesh.uvs.empty() ? "has no texture coordinates" : "is missing") +
                       "; the material's alpha factor alone cuts it out");
    c.texture = -1;
  }
  if (c.texture >= 0) return;
  if (!(c.factor >= c.cutoff)) {
    warnings.push_back("mesh '" + mesh.name + "': alpha " + std::to_string(c.factor) + " is under its cutoff " +
                       std::to_string(c.cutoff) + " everywhere; it is cut away");
    mesh.indices.clear();
  }
  mesh.cutout.reset();
}

void cleanMesh(Mesh& mesh, float areaEpsilon, Dropped& dropped) {
  const std::size_t vertexCount = mesh.positions.size();
  std::vector<std::uint32_t> kept;
  kept.reserve(mesh.indices.size());
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const std::uint32_t i0 = mesh.indices[t], i1 = mesh.indices[t + 1], i2 = mesh.indices[t + 2];
    if (i0 >= vertexCount || i1 >= vertexCount || i2 >= vertexCount) {
      ++dropped.badIndex;
      continue;
    }
    const glm::vec3 &a = mesh.positions[i0], &b = mesh.positions[i1], &c = mesh.positions[i2];
    if (!finite(a) || !finite(b) || !finite(c)) {
      ++dropped.nonFinite;
      continue;
    }
    if (glm::length(glm::cross(b - a, c - a)) <= areaEpsilon) {
      ++dropped.degenerate;
      continue;
    }
    kept.insert(kept.end(), {i0, i1, i2});
  }
  mesh.indices = std::move(kept);

  // Normals: keep given finite ones, otherwise area-weighted face normals.
  bool normalsUsable = mesh.normals.size() == vertexCount;
  for (std::size_t i = 0; normalsUsable && i < vertexCount; ++i) {
    normalsUsable = finite(mesh.normals[i]) && glm::length(mesh.normals[i]) > 0.0f;
  }
  if (!normalsUsable) {
    mesh.normals.assign(vertexCount, glm::vec3(0.0f));
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
      const std::uint32_t i0 = mesh.indices[t], i1 = mesh.indices[t + 1], i2 = mesh.indices[t + 2];
      const glm::vec3 n = glm::cross(mesh.positions[i1] - mesh.positions[i0], mesh.positions[i2] - mesh.positions[i0]);
      mesh.normals[i0] += n;
      mesh.normals[i1] += n;
      mesh.normals[i2] += n;
    }
  }
  for (glm::vec3& n : mesh.normals) {
    const float len = glm::length(n);
    n = len > 0.0f ? n / len : glm::vec3(0.0f, 1.0f, 0.0f);
  }
  // Non-finite positions of unused vertices must not leak into bounds: pin them to a used vertex.
  if (!mesh.indices.empty()) {
    const glm::vec3 anchor = mesh.positions[mesh.indices[0]];
    for (glm::vec3& p : mesh.positions) {
      if (!finite(p)) p = anchor;
    }
  }
}

}  // namespace

void cleanScene(Scene& scene, const std::string& source) {
  // Degenerate = area below a tiny fraction of the finite extent squared (scale independent).
  Bounds finiteBounds;
  for (const Mesh& mesh : scene.meshes) {
    for (const glm::vec3& p : mesh.positions) {
      if (finite(p)) finiteBounds.extend(p);
    }
  }
  const float extent = finiteBounds.empty() ? 0.0f : glm::length(finiteBounds.hi - finiteBounds.lo);
  const float areaEpsilon = 1e-12f * extent * extent;

  Dropped dropped;
  for (Mesh& mesh : scene.meshes) {
    cleanMesh(mesh, areaEpsilon, dropped);
    cleanTextures(mesh, scene.textures.size(), scene.warnings);
  }
  // Meshes left without triangles go; animations follow their meshes' new indices.
  std::vector<std::size_t> newIndex(scene.meshes.size());
  std::size_t kept = 0;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) newIndex[m] = scene.meshes[m].indices.empty() ? SIZE_MAX : kept++;
  std::erase_if(scene.animations, [&](const MeshAnimation& a) { return a.mesh >= newIndex.size() || newIndex[a.mesh] == SIZE_MAX; });
  for (MeshAnimation& a : scene.animations) a.mesh = newIndex[a.mesh];
  std::erase_if(scene.meshes, [](const Mesh& m) { return m.indices.empty(); });
  // Loaders leave animated meshes at their rest pose with the rest left to take here, after the
  // normals were filled in.
  for (MeshAnimation& a : scene.animations) {
    if (!a.restPositions.empty()) continue;
    a.restPositions = scene.meshes[a.mesh].positions;
    a.restNormals = scene.meshes[a.mesh].normals;
  }

  auto report = [&](std::size_t n, const char* what) {
    if (n > 0) scene.warnings.push_back(std::to_string(n) + " triangles dropped: " + what);
  };
  report(dropped.nonFinite, "non-finite (NaN or infinite) vertex positions");
  report(dropped.badIndex, "vertex index out of range");
  report(dropped.degenerate, "degenerate (zero area)");
  if (scene.meshes.empty()) {
    throw InputError("scene '" + source + "' has no drawable triangles" +
                     (scene.warnings.empty() ? std::string() : " (" + scene.warnings.back() + ")") +
                     "; give a scene with at least one non-degenerate triangle");
  }
}

namespace {

// The point of triangle abc nearest to p (Ericson, Real-Time Collision Detection, 5.1.5).
glm::vec3 closestOnTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
  const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0f && d2 <= 0.0f) return a;
  const glm::vec3 bp = p - b;
  const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0f && d4 <= d3) return b;
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return a + ab * (d1 / (d1 - d3));
  const glm::vec3 cp = p - c;
  const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0f && d5 <= d6) return c;
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return a + ac * (d2 / (d2 - d6));
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && d4 - d3 >= 0.0f && d5 - d6 >= 0.0f) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const float denom = 1.0f / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

}  // namespace

float distanceToNearestTriangle(const Scene& scene, const glm::vec3& p) {
  float nearest2 = std::numeric_limits<float>::infinity();
  for (const Mesh& mesh : scene.meshes) {
    for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
      const glm::vec3 a = mesh.positions[mesh.indices[i]], b = mesh.positions[mesh.indices[i + 1]],
                      c = mesh.positions[mesh.indices[i + 2]];
      const glm::vec3 d = closestOnTriangle(p, a, b, c) - p;
      nearest2 = std::min(nearest2, glm::dot(d, d));
    }
  }
  return std::sqrt(nearest2);
}

}  // namespace penumbra
