// Builds the GPU BVH: a binary SAH tree from Embree's builder API (rtcBuildBVH), flattened
// depth-first into nodes that hold both children's boxes and triangles reordered by leaf
// (shared/bvh.h). The layout favours GPUs: one 64-byte fetch per visit, contiguous leaves.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "core/scene.h"
#include "shared/bvh.h"

namespace penumbra {

static_assert(sizeof(shared::BvhChild) == 32, "BvhChild must match std430");
static_assert(sizeof(shared::BvhNode) == 64, "BvhNode must match std430");
static_assert(sizeof(shared::BvhTriangle) == 48, "BvhTriangle must match std430");
static_assert(sizeof(shared::RayQuery) == 32, "RayQuery must match std430");
static_assert(sizeof(shared::RayHit) == 16, "RayHit must match std430");
static_assert(sizeof(shared::BvhRaysPush) == 48, "BvhRaysPush must match std430");
static_assert(sizeof(shared::BvhTracePush) == 48, "BvhTracePush must match std430");

struct BvhBuildSettings {
  std::uint32_t maxLeafSize = 4;  // triangles per leaf, 1..kMaxLeafSize
  float traversalCost = 1.0f;     // SAH weights of Embree's builder
  float intersectionCost = 1.0f;
  // Dynamic trees (raytrace/bvh_refit.h): an update rebuilds instead of refitting once the refit
  // tree's SAH cost exceeds this multiple of the cost it had when last built (> 1).
  float rebuildGrowth = 1.5f;
  static constexpr std::uint32_t kMaxLeafSize = 8;
};

// Which meshes a BVH covers: all, the static ones (Mesh::dynamic false) or the moving ones.
enum class MeshSet { All, Static, Dynamic };
inline bool inMeshSet(const Mesh& mesh, MeshSet set) {
  return set == MeshSet::All || mesh.dynamic == (set == MeshSet::Dynamic);
}
// Triangles of the scene's meshes in `set`.
std::uint64_t triangleCount(const Scene& scene, MeshSet set);

struct BvhStats {
  double buildMs = 0.0;     // Embree build + flattening, wall clock
  std::uint64_t nodes = 0;  // BvhNodes (inner nodes; a one-leaf tree still has its root)
  std::uint64_t leaves = 0;
  std::uint64_t triangles = 0;
  std::uint64_t bytes = 0;     // nodes and triangles as uploaded
  double sahCost = 0.0;        // Ct = Ci = 1, areas relative to the root's box (>= 1)
  std::uint32_t maxDepth = 0;  // nodes on the longest root-to-leaf path (root = 1)
};

// An empty selection (no triangles in the MeshSet) is one root whose only leaf holds one
// degenerate triangle (all three vertices one point, id BVH_NO_HIT) that no ray can hit: the
// traversal then needs no special case, whatever the ray's extent. Its stats count 0 triangles.
// The vertices of triangle t of `mesh`, for building and refitting alike; InputError naming the
// mesh and scene for an out-of-range index or a non-finite vertex. `extent` grows to the largest
// coordinate magnitude (the scale of rounding errors, which sets the boxes' padding).
void triangleVertices(const Scene& scene, const Mesh& mesh, std::size_t t, glm::vec3 (&v)[3], float& extent);

struct Bvh {
  std::vector<shared::BvhNode> nodes;  // nodes[0] is the root
  std::vector<shared::BvhTriangle> triangles;
  BvhStats stats;
  bool empty() const { return stats.triangles == 0; }
};

// The builder's conservative padding of every child box for triangles whose largest coordinate
// magnitude is `extent`; refitting pads with the same function so its boxes equal a build's.
float bvhBoxPadding(float extent);
// SAH cost of a flattened tree as BvhStats::sahCost reports it (Ct = Ci = 1, areas relative to
// the root's box).
double sahCost(const Bvh& bvh);

class BvhBuilder {
 public:
  explicit BvhBuilder(const BvhBuildSettings& settings = {});  // throws std::invalid_argument on bad settings
  ~BvhBuilder();
  BvhBuilder(const BvhBuilder&) = delete;
  BvhBuilder& operator=(const BvhBuilder&) = delete;

  // Builds over the meshes in `set`; BvhTriangle.id stays the triangle's index in the whole scene.
  // Throws InputError for a scene without triangles (an empty selection of a non-empty scene gives
  // the empty Bvh above) or with bad indices or non-finite vertices, std::runtime_error when
  // Embree fails.
  Bvh build(const Scene& scene, MeshSet set = MeshSet::All) const;

  // Bytes of the triangle buffer of a scene with `triangles` triangles, known before building
  // (each is stored once); the node buffer is smaller for any leaf size above 1.
  static std::uint64_t triangleBytes(std::uint64_t triangles) { return triangles * sizeof(shared::BvhTriangle); }

 private:
  struct Impl;
  BvhBuildSettings settings_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra
