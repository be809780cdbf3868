#include "core/cutouts.h"

namespace penumbra {

CutoutData cutoutData(const Scene& scene) {
  CutoutData data;
  data.firstTexel.assign(scene.textures.size(), 0u);
  std::vector<char> packed(scene.textures.size(), 0);
  std::uint64_t texelCount = 0;
  for (const Mesh& mesh : scene.meshes) {
    if (!mesh.cutout) continue;
    const Cutout& c = *mesh.cutout;
    const std::size_t k = std::size_t(c.texture);
    const Texture& texture = scene.textures.at(k);
    if (!packed[k]) {
      packed[k] = 1;
      data.firstTexel[k] = std::uint32_t(texelCount);
      const std::uint64_t count = std::uint64_t(texture.width) * texture.height;
      data.texels.resize((texelCount + count + 3) / 4, 0u);
      for (std::uint64_t i = 0; i < count; ++i) {
        const std::uint64_t at = texelCount + i;
        data.texels[at / 4] |= std::uint32_t(texture.rgba[4 * i + 3]) << (8 * (at % 4));
      }
      texelCount += count;
    }
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      const std::uint32_t* i = &mesh.indices[3 * t];
      data.triangles.push_back({mesh.uvs[i[0]], mesh.uvs[i[1]], mesh.uvs[i[2]], data.firstTexel[k], texture.width,
                                texture.height, c.factor, c.cutoff, 0u});
    }
  }
  return data;
}

std::vector<std::uint32_t> cutoutIndices(const Scene& scene) {
  std::vector<std::uint32_t> first(scene.meshes.size(), 0u);
  std::uint32_t next = 1;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    if (!scene.meshes[m].cutout) continue;
    first[m] = next;
    next += std::uint32_t(scene.meshes[m].triangleCount());
  }
  return first;
}

}  // namespace penumbra
