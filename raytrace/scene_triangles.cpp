#include "raytrace/scene_triangles.h"

#include <glm/gtc/packing.hpp>
#include <optional>

#include "core/texture.h"
#include "shared/gbuffer.h"

namespace penumbra {

std::uint32_t packNormal(const glm::vec3& n) { return glm::packSnorm2x16(shared::octahedralEncode(n)); }

glm::vec3 unpackNormal(std::uint32_t packed) { return shared::octahedralDecode(glm::unpackSnorm2x16(packed)); }

std::vector<shared::SceneTriangle> sceneTriangles(const Scene& scene) {
  std::vector<shared::SceneTriangle> out;
  out.reserve(scene.triangleCount());
  std::vector<std::optional<glm::vec3>> means(scene.textures.size());  // each colour texture's, once
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    glm::vec3 color = mesh.baseColor;
    if (mesh.colorTexture >= 0) {
      std::optional<glm::vec3>& mean = means.at(std::size_t(mesh.colorTexture));
      if (!mean) mean = meanColor(scene.textures[std::size_t(mesh.colorTexture)]);
      color *= *mean;
    }
    const std::uint32_t albedo = glm::packUnorm4x8(glm::vec4(glm::clamp(color, 0.0f, 1.0f), 1.0f));
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      shared::SceneTriangle tri{};
      const std::uint32_t* idx = &mesh.indices[3 * t];
      tri.v0 = mesh.positions[idx[0]];
      tri.v1 = mesh.positions[idx[1]];
      tri.v2 = mesh.positions[idx[2]];
      tri.normal0 = packNormal(mesh.normals[idx[0]]);
      tri.normal1 = packNormal(mesh.normals[idx[1]]);
      tri.normal2 = packNormal(mesh.normals[idx[2]]);
      tri.mesh = std::uint32_t(m);
      tri.albedo = albedo;
      out.push_back(tri);
    }
  }
  return out;
}

}  // namespace penumbra
