#include "core/cutouts.h"

#include <algorithm>

namespace penumbra {

namespace {

// Appends a texture's alpha from a word's start, four texels a word; returns its first texel.
std::uint32_t appendAlpha(std::vector<std::uint32_t>& words, const Texture& texture) {
  const std::size_t first = words.size();
  const std::size_t count = std::size_t(texture.width) * texture.height;
  words.resize(first + (count + 3) / 4, 0u);
  for (std::size_t i = 0; i < count; ++i) words[first + i / 4] |= std::uint32_t(texture.rgba[4 * i + 3]) << (8 * (i % 4));
  return std::uint32_t(4 * first);
}

// Appends a texture's alpha ranges (shared/alpha.h) from a word's start; returns the half word of
// level 1 (0 for a texture of one texel, which has none).
std::uint32_t appendRanges(std::vector<std::uint32_t>& words, const Texture& texture) {
  const std::uint32_t w = texture.width, h = texture.height;
  if (w * h <= 1) return 0;
  // cells of the level below: (least, greatest) per cell, starting from the texels
  std::vector<std::uint8_t> lo(std::size_t(w) * h), hi(lo.size());
  for (std::size_t i = 0; i < lo.size(); ++i) lo[i] = hi[i] = texture.rgba[4 * i + 3];
  const std::uint32_t first = std::uint32_t(2 * words.size());
  std::vector<std::uint16_t> cells;
  for (std::uint32_t level = 1, bw = w, bh = h; bw > 1 || bh > 1; ++level) {
    const std::uint32_t cw = shared::cutoutLevelSize(w, level), ch = shared::cutoutLevelSize(h, level);
    std::vector<std::uint8_t> nlo(std::size_t(cw) * ch, 255), nhi(nlo.size(), 0);
    for (std::uint32_t y = 0; y < bh; ++y) {
      for (std::uint32_t x = 0; x < bw; ++x) {
        const std::size_t below = std::size_t(y) * bw + x, cell = std::size_t(y / 2) * cw + x / 2;
        nlo[cell] = std::min(nlo[cell], lo[below]);
        nhi[cell] = std::max(nhi[cell], hi[below]);
      }
    }
    for (std::size_t i = 0; i < nlo.size(); ++i) cells.push_back(std::uint16_t(nlo[i] | (nhi[i] << 8)));
    lo = std::move(nlo), hi = std::move(nhi), bw = cw, bh = ch;
  }
  const std::size_t at = words.size();
  words.resize(at + (cells.size() + 1) / 2, 0u);
  for (std::size_t i = 0; i < cells.size(); ++i) words[at + i / 2] |= std::uint32_t(cells[i]) << (16 * (i % 2));
  return first;
}

}  // namespace

CutoutData cutoutData(const Scene& scene) {
  CutoutData data;
  data.firstTexel.assign(scene.textures.size(), 0u);
  data.firstRange.assign(scene.textures.size(), 0u);
  std::vector<char> packed(scene.textures.size(), 0);
  for (const Mesh& mesh : scene.meshes) {
    if (!mesh.cutout) continue;
    const Cutout& c = *mesh.cutout;
    const std::size_t k = std::size_t(c.texture);
    const Texture& texture = scene.textures.at(k);
    if (!packed[k]) {
      packed[k] = 1;
      data.firstTexel[k] = appendAlpha(data.texels, texture);
      data.firstRange[k] = appendRanges(data.texels, texture);
      if (data.texels.size() >= (std::size_t(1) << 30)) {  // texel indices are 32-bit
        throw InputError("scene '" + scene.name + "': its cut-out textures hold over 4 GiB of alpha; use smaller images");
      }
    }
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      const std::uint32_t* i = &mesh.indices[3 * t];
      data.triangles.push_back({mesh.uvs[i[0]], mesh.uvs[i[1]], mesh.uvs[i[2]], data.firstTexel[k], texture.width,
                                texture.height, c.factor, c.cutoff, data.firstRange[k]});
    }
  }
  return data;
}

std::uint64_t cutoutDataBytes(const Scene& scene) {
  std::vector<char> counted(scene.textures.size(), 0);
  std::uint64_t bytes = 0;
  for (const Mesh& mesh : scene.meshes) {
    if (!mesh.cutout) continue;
    bytes += mesh.triangleCount() * sizeof(shared::CutoutTriangle);
    const std::size_t k = std::size_t(mesh.cutout->texture);
    if (counted.at(k)) continue;
    counted[k] = 1;
    const Texture& t = scene.textures[k];
    std::uint64_t cells = 0;  // the alpha ranges' (shared/alpha.h)
    for (std::uint32_t level = 1, w = t.width, h = t.height; w > 1 || h > 1; ++level) {
      w = shared::cutoutLevelSize(t.width, level), h = shared::cutoutLevelSize(t.height, level);
      cells += std::uint64_t(w) * h;
    }
    bytes += (std::uint64_t(t.width) * t.height + 3) / 4 * 4 + (cells + 1) / 2 * 4;
  }
  return bytes;
}

bool hasCutouts(const Scene& scene) {
  return std::any_of(scene.meshes.begin(), scene.meshes.end(), [](const Mesh& m) { return m.cutout.has_value(); });
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
