// The N-tree of the line space (Keul et al. 2017, 3): a cubic root around the scene, every
// subdivided node split into N x N x N equal cubes, only non-empty cells subdivided, down to the
// maximum depth d (root level 0, leaf cells at level d). A cell is non-empty when a triangle
// overlaps it (exact triangle/box separating-axis test on a slightly enlarged cell, so it is
// conservative). Leaves keep their triangle lists; the binary shadow tracer never reads them.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/scene.h"
#include "raytrace/bvh_builder.h"

namespace penumbra {

struct NTreeStats {
  double buildMs = 0.0;
  std::uint64_t nodes = 0;   // subdivided nodes (each holds a line space)
  std::uint64_t leaves = 0;  // non-empty cells at level d
  std::uint64_t leafTriangleRefs = 0;
  std::vector<std::uint64_t> nodesPerLevel;  // subdivided nodes at levels 0 .. d-1
};

struct NTree {
  static constexpr std::uint32_t kEmpty = 0xffffffffu;  // a child cell without geometry
  static constexpr std::uint32_t kLeafBit = 0x80000000u;  // child entry: kLeafBit | leaf index

  struct Node {
    glm::vec3 lo{0.0f};  // low corner
    float size = 0.0f;   // edge length
    std::uint32_t level = 0;
    std::uint32_t childBase = 0;  // its N^3 entries in `children`, numbered by lsCellIndex
  };
  struct Leaf {
    std::uint32_t first = 0;  // into leafTriangles
    std::uint32_t count = 0;
  };

  std::uint32_t n = 0, depth = 0;
  std::vector<Node> nodes;  // subdivided nodes; nodes[0] is the root, parents before children
  // Per node N^3 entries: kEmpty, a subdivided node's index, or kLeafBit | leaf index.
  std::vector<std::uint32_t> children;
  std::vector<Leaf> leaves;
  // Triangle indices in scene order (meshes, then triangles) over the meshes the tree was built on.
  std::vector<std::uint32_t> leafTriangles;
  NTreeStats stats;

  std::uint32_t child(std::uint32_t node, std::uint32_t cell) const { return children[nodes[node].childBase + cell]; }
};

// Whether triangle (a, b, c) overlaps the box [lo, hi] (separating axis test in double precision;
// touching counts as overlapping).
bool triangleOverlapsBox(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& lo,
                         const glm::dvec3& hi);

class NTreeBuilder {
 public:
  // Throws InputError unless N is in [LS_MIN_N, LS_MAX_N] and d in [LS_MIN_DEPTH, LS_MAX_DEPTH].
  NTreeBuilder(std::uint32_t n, std::uint32_t depth);
  static void validate(std::uint32_t n, std::uint32_t depth);

  // Over the meshes in `set` (the line-space tracer: the static ones; moving ones are traced by
  // their own BVH). Throws InputError when they have no triangles. Builds the root's children on
  // all cores.
  NTree build(const Scene& scene, MeshSet set = MeshSet::All) const;

 private:
  std::uint32_t n_, depth_;
};

}  // namespace penumbra
