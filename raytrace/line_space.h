// The binary line space (Keul et al. 2017, 3 and 3.1): per subdivided node of the N-tree one bit
// per shaft, set when any child cell the shaft meets is non-empty, in the paper's three GPU pools:
// tree pool (children groups of N^3 entries: a node-pool index or LS_SKIP), node pool (LsNode)
// and line-space pool (shared::lsWordsPerNode(N) 32-bit words per node, node i <-> line space i).
// The size is known exactly once the tree is built (node counts times fixed per-node sizes), so
// a parameter set that does not fit the budget is refused before any bit is computed.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/options.h"
#include "raytrace/ntree_builder.h"
#include "shared/bvh.h"
#include "shared/linespace.h"

namespace penumbra {

static_assert(sizeof(shared::LsNode) == 32, "LsNode must match std430");
static_assert(sizeof(shared::LsPush) == 48, "LsPush must match std430");
static_assert(sizeof(shared::LsLeaf) == 8, "LsLeaf must match std430");

struct LineSpaceSettings {
  std::uint32_t n = 6;             // branching factor N, LS_MIN_N..LS_MAX_N
  std::uint32_t depth = 3;         // maximum depth d, LS_MIN_DEPTH..LS_MAX_DEPTH
  std::uint64_t budgetBytes = 0;   // the three pools together; 0 = defaultLineSpaceBudget()
  // The line space answers for a shadow ray only from where it is this many leaf cells above the
  // receiver's surface plane on. A shaft leaving the skipped start node near the receiver's own
  // surface contains the receiver's cells and so reads as occluded (dark bands along node
  // boundaries); skipping the ray's part within one cell of the surface avoids that, at the price
  // of occluders that close (contact shadows). The ray itself is unchanged, so shadow edges stay
  // where they are. 0 = the paper's start-node rule alone.
  float startOffsetCells = 1.0f;
  // How the moving meshes (not in the line space) are traced: on their own compute BVH, with ray
  // queries on the driver's acceleration structures, or Auto: as defaultTracer says.
  enum class Moving { Auto, Bvh, RayQuery } movingTracer = Moving::Auto;
  // What a set shaft bit at the second-to-last level means. Binary: occluded (the paper's
  // approximation: conservative, thin casters shadow as whole cells; the start node is skipped).
  // Exact: walk that node's leaf cells along the ray and test their triangles with the BVH's
  // robust test, the start node included and without the start offset, so the answer is the
  // BVH's. Exact adds the leaf records, triangle lists and triangles to the pools.
  enum class Shadows { Binary, Exact } shadows = Shadows::Binary;
};

// The command line's options of the line space (--linespace-n, --linespace-depth, --ls-shadows, ...).
const Options<LineSpaceSettings>& lineSpaceOptions();

const char* shadowsName(LineSpaceSettings::Shadows shadows);  // "binary" / "exact"

struct LineSpaceStats {
  std::uint32_t n = 0, depth = 0;
  std::uint64_t nodes = 0;        // subdivided nodes = line spaces
  std::uint64_t leaves = 0;       // non-empty cells at level d (not stored in the pools)
  std::uint64_t treeBytes = 0, nodeBytes = 0, lineSpaceBytes = 0;
  // Exact mode only (0 in binary mode): the leaf-cell children groups in the tree pool, the leaf
  // records, the leaf triangle lists and the triangles.
  std::uint64_t leafGroupBytes = 0, leafBytes = 0, leafTriangleBytes = 0, triangleBytes = 0;
  std::uint64_t leafTriangleRefs = 0;  // entries of the leaf triangle lists (N-tree)
  std::uint64_t dynamicBvhBytes = 0;  // the moving meshes' BVH traced beside it (LineSpaceTracer), as allocated
  std::uint64_t bytes = 0;        // the pools as uploaded (treeBytes includes leafGroupBytes), plus dynamicBvhBytes
  std::uint64_t exactBytes() const { return leafGroupBytes + leafBytes + leafTriangleBytes + triangleBytes; }
  double treeMs = 0.0;            // N-tree build
  double tableMs = 0.0;           // shaft table (0 when it was cached)
  double lineSpaceMs = 0.0;       // bits
  double buildMs = 0.0;           // all three
  double filledFraction = 0.0;    // set bits over all bits
};

struct LineSpaceSizes {
  std::uint64_t treeBytes = 0, nodeBytes = 0, lineSpaceBytes = 0;
  std::uint64_t leafBytes = 0, leafTriangleBytes = 0, triangleBytes = 0;  // exact mode only
  std::uint64_t total() const { return treeBytes + nodeBytes + lineSpaceBytes + leafBytes + leafTriangleBytes + triangleBytes; }
};

struct LineSpace {
  std::uint32_t n = 0, depth = 0;
  std::vector<std::uint32_t> tree;    // tree pool
  std::vector<shared::LsNode> nodes;  // node pool, node 0 the root
  std::vector<std::uint32_t> bits;    // line-space pool
  // Exact mode only (empty in binary mode): leaf records (the tree pool entries of
  // second-to-last-level nodes index them), their packed triangle lists, and the triangles of the
  // meshes the tree was built on, in scene order with scene-order ids.
  std::vector<shared::LsLeaf> leaves;
  std::vector<std::uint32_t> leafTriangles;
  std::vector<shared::BvhTriangle> triangles;
  LineSpaceStats stats;

  bool bit(std::uint32_t node, std::uint32_t shaft) const {
    return (bits[std::size_t(node) * shared::lsWordsPerNode(n) + shaft / 32] >> (shaft % 32)) & 1u;
  }
};

// Pool sizes for `nodes` subdivided nodes of which `groups` have a children group (those above
// the second-to-last level; in exact mode all of them), and in exact mode `leaves` leaf records
// with `leafTriangleRefs` list entries over `triangles` triangles.
LineSpaceSizes lineSpaceSizes(std::uint32_t n, std::uint64_t nodes, std::uint64_t groups, std::uint64_t leaves = 0,
                              std::uint64_t leafTriangleRefs = 0, std::uint64_t triangles = 0);
// A quarter of the memory the system reports available (lavapipe's buffers are host memory).
std::uint64_t defaultLineSpaceBudget();

// The triangles of the meshes in `set` in BvhTriangle format, in scene order with their
// scene-order index as id (the order of NTree::leafTriangles' indices).
std::vector<shared::BvhTriangle> lineSpaceTriangles(const Scene& scene, MeshSet set);

// Builds the pools on top of `tree`. Throws InputError naming (N, d), the size in MB and how to
// change it when the pools and dynamicBvhBytes (the moving meshes' BVH that the tracer keeps
// beside the line space, counted against the same budget) exceed the budget, or one pool exceeds
// maxPoolBytes (the device's maxStorageBufferRange; 0 = no limit). Exact mode needs the tree's
// `triangles` (lineSpaceTriangles over the same meshes; std::invalid_argument when their count
// does not cover the tree's lists); binary mode ignores them.
LineSpace buildLineSpace(const NTree& tree, const LineSpaceSettings& settings, std::uint64_t maxPoolBytes,
                         const std::string& sceneName, std::uint64_t dynamicBvhBytes = 0,
                         std::vector<shared::BvhTriangle> triangles = {});
// The N-tree over the meshes in `set` and then the pools; the stats include the tree's build time.
LineSpace buildLineSpace(const Scene& scene, const LineSpaceSettings& settings, std::uint64_t maxPoolBytes,
                         MeshSet set = MeshSet::All, std::uint64_t dynamicBvhBytes = 0);

}  // namespace penumbra
