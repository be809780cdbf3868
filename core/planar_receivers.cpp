#include "core/planar_receivers.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace penumbra {
namespace {

// The rectangle in r's plane that holds the mesh's vertices (projected): axes along the world axis
// least aligned with the normal, made orthogonal to it; nullopt when it has no area.
std::optional<PlanarReceiver> spanned(const Mesh& mesh, PlanarReceiver r) {
  const glm::vec3 n = glm::abs(r.normal);
  const glm::vec3 helper = n.x <= n.y && n.x <= n.z ? glm::vec3(1, 0, 0) : n.y <= n.z ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1);
  r.axisU = glm::normalize(helper - r.normal * glm::dot(r.normal, helper));
  r.axisV = glm::cross(r.normal, r.axisU);
  glm::vec2 lo(INFINITY), hi(-INFINITY);
  for (const glm::vec3& p : mesh.positions) {
    const glm::vec2 uv(glm::dot(p, r.axisU), glm::dot(p, r.axisV));
    lo = glm::min(lo, uv);
    hi = glm::max(hi, uv);
  }
  r.origin = lo.x * r.axisU + lo.y * r.axisV - r.offset * r.normal;
  r.extentU = hi.x - lo.x;
  r.extentV = hi.y - lo.y;
  if (!(r.extentU > 0.0f && r.extentV > 0.0f)) return std::nullopt;
  return r;
}

std::optional<PlanarReceiver> planeOf(const Mesh& mesh, float tolerance) {
  // The largest triangle sets the plane; every vertex must lie on it.
  double largest = 0.0;
  glm::vec3 normal{0.0f}, point{0.0f};
  double area = 0.0;
  for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const glm::vec3 a = mesh.positions[mesh.indices[i]], b = mesh.positions[mesh.indices[i + 1]],
                    c = mesh.positions[mesh.indices[i + 2]];
    const glm::vec3 n = glm::cross(b - a, c - a);
    const double twice = glm::length(n);
    area += 0.5 * twice;
    if (twice > largest) {
      largest = twice;
      normal = n / float(twice);
      point = a;
    }
  }
  if (!(largest > 0.0)) return std::nullopt;
  const float offset = -glm::dot(normal, point);
  for (const glm::vec3& p : mesh.positions) {
    if (!(std::abs(glm::dot(normal, p) + offset) <= tolerance)) return std::nullopt;
  }
  PlanarReceiver r{.mesh = mesh.name, .normal = normal, .offset = offset, .area = area};
  return spanned(mesh, r);
}

}  // namespace

std::optional<PlanarReceiver> findHeightField(const Scene& scene, const std::string& name) {
  for (const Mesh& mesh : scene.meshes) {
    if (mesh.name != name || mesh.dynamic || mesh.indices.size() < 3) continue;
    // Face normals (length: twice the area) turned to the largest triangle's side, summed.
    std::vector<glm::vec3> faces;
    glm::vec3 largest{0.0f};
    for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
      const glm::vec3 a = mesh.positions[mesh.indices[i]], b = mesh.positions[mesh.indices[i + 1]],
                      c = mesh.positions[mesh.indices[i + 2]];
      faces.push_back(glm::cross(b - a, c - a));
      if (glm::length(faces.back()) > glm::length(largest)) largest = faces.back();
    }
    glm::vec3 sum{0.0f};
    double area = 0.0;
    for (glm::vec3& f : faces) {
      if (glm::dot(f, largest) < 0.0f) f = -f;
      sum += f;
      area += 0.5 * glm::length(f);
    }
    if (!(glm::length(sum) > 0.0f)) return std::nullopt;
    const glm::vec3 up = glm::normalize(sum);
    for (const glm::vec3& f : faces) {
      const float len = glm::length(f);
      if (len > 0.0f && glm::dot(f, up) < 0.05f * len) return std::nullopt;  // an overhang or a wall
    }
    float lo = INFINITY, hi = -INFINITY;
    for (const glm::vec3& p : mesh.positions) {
      lo = std::min(lo, glm::dot(up, p));
      hi = std::max(hi, glm::dot(up, p));
    }
    auto r = spanned(mesh, PlanarReceiver{.mesh = mesh.name, .normal = up, .offset = -lo, .area = area});
    if (!r) return std::nullopt;
    r->heightField = true;
    r->top = hi - lo;
    return r;
  }
  return std::nullopt;
}

std::vector<PlanarReceiver> findPlanarReceivers(const Scene& scene, float tolerance) {
  std::vector<PlanarReceiver> found;
  for (const Mesh& mesh : scene.meshes) {
    if (mesh.dynamic) continue;  // a map laid once per frame on a moving plane: not supported yet
    if (auto r = planeOf(mesh, tolerance)) found.push_back(std::move(*r));
  }
  std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.area > b.area; });
  return found;
}

}  // namespace penumbra
