// A scene's cut-outs as the GPU reads them (shared/alpha.h): one CutoutTriangle per triangle of a
// cut-out mesh, in scene order (BvhTriangle::cutout is 1 + its index), and every cut-out texture's
// alpha, four texels a word. Used by the BVH's buffers (raytrace/cutout_buffers.h) and the raster
// passes' cut-out draws (raster/scene_geometry.h).
#pragma once
#include <cstdint>
#include <vector>

#include "core/scene.h"
#include "shared/alpha.h"

namespace penumbra {

static_assert(sizeof(shared::CutoutTriangle) == 48, "CutoutTriangle must match std430");

struct CutoutData {
  std::vector<shared::CutoutTriangle> triangles;
  // Each cut-out texture's alpha, four texels a word (the lowest byte first), then its alpha
  // ranges (shared/alpha.h), two cells a word, from a word's start.
  std::vector<std::uint32_t> texels;
  std::vector<std::uint32_t> firstTexel;  // per Scene texture, its first texel in `texels`
  std::vector<std::uint32_t> firstRange;  // per Scene texture, the half word of its level-1 ranges
};
CutoutData cutoutData(const Scene& scene);

// The bytes cutoutData(scene) will hold (at most 8 bytes over), counted without building it: the
// memory estimate's term for each copy the GPU keeps.
std::uint64_t cutoutDataBytes(const Scene& scene);

bool hasCutouts(const Scene& scene);

// Per mesh, 1 + the CutoutTriangle index of its first triangle, or 0 for an opaque mesh.
std::vector<std::uint32_t> cutoutIndices(const Scene& scene);

}  // namespace penumbra
