#include "raster/scene_geometry.h"

#include <algorithm>
#include <limits>

#include "core/cutouts.h"
#include "gpu/upload.h"

namespace penumbra::raster {
namespace {

std::size_t vertexCount(const Scene& scene) {
  std::size_t n = 0;
  for (const Mesh& m : scene.meshes) n += m.positions.size();
  return n;
}

bool textured(const Mesh& m) { return m.cutout || m.colorTexture >= 0; }

// Texture coordinates for every vertex when a mesh has cut-outs or a colour texture, else none.
std::vector<glm::vec2> textureCoordinates(const Scene& scene) {
  if (std::none_of(scene.meshes.begin(), scene.meshes.end(), textured)) return {};
  std::vector<glm::vec2> uvs;
  uvs.reserve(vertexCount(scene));
  for (const Mesh& m : scene.meshes) {
    if (textured(m))
      uvs.insert(uvs.end(), m.uvs.begin(), m.uvs.end());
    else uvs.resize(uvs.size() + m.positions.size(), glm::vec2(0.0f));
  }
  return uvs;
}

// Appends a draw of `count` indices from `first`, joining the previous run where it ends there.
void appendRun(std::vector<std::pair<std::uint32_t, std::uint32_t>>& runs, std::uint32_t first, std::uint32_t count) {
  if (!runs.empty() && runs.back().first + runs.back().second == first)
    runs.back().second += count;
  else
    runs.emplace_back(first, count);
}

}  // namespace

SceneGeometry::SceneGeometry(const gpu::Context& context, const Scene& scene)
    : SceneGeometry(context, scene, cutoutData(scene)) {}

SceneGeometry::SceneGeometry(const gpu::Context& context, const Scene& scene, const CutoutData& cutouts)
    : vertices_(context, vertexCount(scene) * sizeof(RasterVertex),
                vk::BufferUsageFlagBits::eVertexBuffer | vk::BufferUsageFlagBits::eStorageBuffer, "scene vertices"),
      indices_(context, scene.triangleCount() * 3 * sizeof(std::uint32_t),
               vk::BufferUsageFlagBits::eIndexBuffer | vk::BufferUsageFlagBits::eStorageBuffer, "scene indices"),
      uvs_(gpu::uploadedBuffer(context, std::span<const glm::vec2>(textureCoordinates(scene)),
                               vk::BufferUsageFlagBits::eVertexBuffer, "scene texture coordinates")),
      triangles_(gpu::uploadedBuffer(context, std::span(cutouts.triangles),
                                     vk::BufferUsageFlagBits::eShaderDeviceAddress, "scene cutout triangles")),
      texels_(gpu::uploadedBuffer(context, std::span(cutouts.texels), vk::BufferUsageFlagBits::eShaderDeviceAddress,
                                  "scene cutout texels")) {
  if (vertexCount(scene) > std::numeric_limits<std::uint32_t>::max()) {
    throw InputError("scene '" + scene.name + "' has more than 2^32 vertices; split it into smaller scenes");
  }
  auto* vertex = static_cast<RasterVertex*>(vertices_.data());
  auto* index = static_cast<std::uint32_t*>(indices_.data());
  std::uint32_t base = 0, first = 0, cutoutTriangle = 0;
  for (const Mesh& mesh : scene.meshes) {
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) *vertex++ = {mesh.positions[i], mesh.normals[i], mesh.baseColor};
    for (std::uint32_t i : mesh.indices) *index++ = base + i;
    base += std::uint32_t(mesh.positions.size());
    const auto count = std::uint32_t(mesh.indices.size());
    if (mesh.cutout) {
      const Texture& t = scene.textures.at(std::size_t(mesh.cutout->texture));
      cutouts_.push_back({first, count, mesh.colorTexture, cutoutTriangle,
                          cutouts.firstTexel.at(std::size_t(mesh.cutout->texture)), t.width, t.height,
                          mesh.cutout->factor, mesh.cutout->cutoff});
      cutoutTriangle += count / 3;
    } else {
      appendRun(opaque_, first, count);  // one draw for a run of opaque meshes
      if (mesh.colorTexture >= 0)
        textured_.push_back({first, count, mesh.colorTexture});
      else
        appendRun(plain_, first, count);
    }
    first += count;
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

void SceneGeometry::drawOpaque(const vk::raii::CommandBuffer& cmd) const {
  for (const auto& [first, count] : opaque_) cmd.drawIndexed(count, 1, first, 0, 0);
}

void SceneGeometry::drawPlain(const vk::raii::CommandBuffer& cmd) const {
  for (const auto& [first, count] : plain_) cmd.drawIndexed(count, 1, first, 0, 0);
}

namespace {

// Each of `draws` (meshes drawn one by one, with texture coordinates at binding 1): `push`, then its indices.
template <typename Draw>
void drawEach(const vk::raii::CommandBuffer& cmd, const gpu::Buffer& uvs, const std::vector<Draw>& draws,
              const std::function<void(const Draw&)>& push) {
  if (draws.empty()) return;
  cmd.bindVertexBuffers(1, {uvs.handle()}, {vk::DeviceSize(0)});
  for (const Draw& draw : draws) {
    push(draw);
    cmd.drawIndexed(draw.indexCount, 1, draw.firstIndex, 0, 0);
  }
}

}  // namespace

void SceneGeometry::drawTextured(const vk::raii::CommandBuffer& cmd,
                                 const std::function<void(const TexturedDraw&)>& push) const {
  drawEach(cmd, uvs_, textured_, push);
}

void SceneGeometry::drawCutouts(const vk::raii::CommandBuffer& cmd,
                                const std::function<void(const CutoutDraw&)>& push) const {
  drawEach(cmd, uvs_, cutouts_, push);
}

glm::uvec2 SceneGeometry::cutoutTrianglesAddress() const { return gpu::addressHalves(triangles_); }
glm::uvec2 SceneGeometry::cutoutTexelsAddress() const { return gpu::addressHalves(texels_); }

shared::CutoutDrawPush SceneGeometry::cutoutPush(const glm::mat4& viewProj, const glm::vec4& camera,
                                                 const CutoutDraw& d) const {
  return {viewProj, camera, gpu::addressHalves(texels_), d.firstTexel, d.width, d.height, d.factor, d.cutoff, 0u};
}

}  // namespace penumbra::raster
