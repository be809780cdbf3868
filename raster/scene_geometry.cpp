#include "raster/scene_geometry.h"

#include <limits>

namespace penumbra::raster {
namespace {

std::size_t vertexCount(const Scene& scene) {
  std::size_t n = 0;
  for (const Mesh& m : scene.meshes) n += m.positions.size();
  return n;
}

}  // namespace

SceneGeometry::SceneGeometry(const gpu::Context& context, const Scene& scene)
    : vertices_(context, vertexCount(scene) * sizeof(RasterVertex), vk::BufferUsageFlagBits::eVertexBuffer | vk::BufferUsageFlagBits::eStorageBuffer,
                "scene vertices"),
      indices_(context, scene.triangleCount() * 3 * sizeof(std::uint32_t), vk::BufferUsageFlagBits::eIndexBuffer | vk::BufferUsageFlagBits::eStorageBuffer,
               "scene indices") {
  if (vertexCount(scene) > std::numeric_limits<std::uint32_t>::max()) {
    throw InputError("scene '" + scene.name + "' has more than 2^32 vertices; split it into smaller scenes");
  }
  auto* vertex = static_cast<RasterVertex*>(vertices_.data());
  auto* index = static_cast<std::uint32_t*>(indices_.data());
  std::uint32_t base = 0;
  for (const Mesh& mesh : scene.meshes) {
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) *vertex++ = {mesh.positions[i], mesh.normals[i], mesh.baseColor};
    for (std::uint32_t i : mesh.indices) *index++ = base + i;
    base += std::uint32_t(mesh.positions.size());
  }
  indexCount_ = std::uint32_t(scene.triangleCount() * 3);
}

void SceneGeometry::update(const Scene& scene) {
  auto* vertex = static_cast<RasterVertex*>(vertices_.data());
  for (const Mesh& mesh : scene.meshes) {
    if (mesh.dynamic) {
      for (std::size_t i = 0; i < mesh.positions.size(); ++i) vertex[i] = {mesh.positions[i], mesh.normals[i], mesh.baseColor};
    }
    vertex += mesh.positions.size();
  }
  ++version_;
}

void SceneGeometry::bind(const vk::raii::CommandBuffer& cmd) const {
  cmd.bindVertexBuffers(0, {vertices_.handle()}, {vk::DeviceSize(0)});
  cmd.bindIndexBuffer(indices_.handle(), 0, vk::IndexType::eUint32);
}

void SceneGeometry::draw(const vk::raii::CommandBuffer& cmd) const { cmd.drawIndexed(indexCount_, 1, 0, 0, 0); }

}  // namespace penumbra::raster
