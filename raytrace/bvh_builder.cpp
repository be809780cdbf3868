#include "raytrace/bvh_builder.h"

#include "core/cutouts.h"
#include "raytrace/embree_handles.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

namespace penumbra {
namespace {

using embree::DevicePtr;
using EmbreeBvhPtr = embree::BvhPtr;

// The builder's own tree, allocated by Embree's thread-local allocator and freed with the RTCBVH.
struct BuildNode {
  bool leaf = false;
};
struct InnerNode : BuildNode {
  unsigned childCount = 0;
  RTCBounds bounds[2] = {};
  const BuildNode* children[2] = {nullptr, nullptr};
};
struct LeafNode : BuildNode {
  RTCBounds bounds = {};
  std::uint32_t count = 0;
  std::uint32_t ids[BvhBuildSettings::kMaxLeafSize] = {};
};

// Shared with the callbacks, which run on Embree's worker threads and must not throw.
struct BuildContext {
  std::atomic<bool> failed{false};           // a callback met something it cannot store
  std::atomic<std::uint64_t> innerNodes{0};  // to size the flattened node array up front
};

void* createNode(RTCThreadLocalAllocator alloc, unsigned childCount, void* user) {
  void* memory = rtcThreadLocalAlloc(alloc, sizeof(InnerNode), alignof(InnerNode));
  if (!memory) return nullptr;
  InnerNode* node = std::construct_at(static_cast<InnerNode*>(memory));
  auto* context = static_cast<BuildContext*>(user);
  if (childCount > 2) context->failed = true;
  context->innerNodes.fetch_add(1, std::memory_order_relaxed);
  node->childCount = std::min(childCount, 2u);
  return node;
}

void setNodeChildren(void* nodePtr, void** children, unsigned childCount, void*) {
  auto* node = static_cast<InnerNode*>(nodePtr);
  for (unsigned i = 0; i < std::min(childCount, 2u); ++i)
    node->children[i] = static_cast<const BuildNode*>(children[i]);
}

void setNodeBounds(void* nodePtr, const RTCBounds** bounds, unsigned childCount, void*) {
  auto* node = static_cast<InnerNode*>(nodePtr);
  for (unsigned i = 0; i < std::min(childCount, 2u); ++i) node->bounds[i] = *bounds[i];
}

void* createLeaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t count, void* user) {
  void* memory = rtcThreadLocalAlloc(alloc, sizeof(LeafNode), alignof(LeafNode));
  if (!memory) return nullptr;
  LeafNode* leaf = std::construct_at(static_cast<LeafNode*>(memory));
  leaf->leaf = true;
  if (count > BvhBuildSettings::kMaxLeafSize) static_cast<BuildContext*>(user)->failed = true;
  leaf->count = std::uint32_t(std::min<size_t>(count, BvhBuildSettings::kMaxLeafSize));
  RTCBounds& b = leaf->bounds;
  b.lower_x = b.lower_y = b.lower_z = std::numeric_limits<float>::max();
  b.upper_x = b.upper_y = b.upper_z = -std::numeric_limits<float>::max();
  for (std::uint32_t i = 0; i < leaf->count; ++i) {
    const RTCBuildPrimitive& p = prims[i];
    leaf->ids[i] = p.primID;
    b.lower_x = std::min(b.lower_x, p.lower_x);
    b.lower_y = std::min(b.lower_y, p.lower_y);
    b.lower_z = std::min(b.lower_z, p.lower_z);
    b.upper_x = std::max(b.upper_x, p.upper_x);
    b.upper_y = std::max(b.upper_y, p.upper_y);
    b.upper_z = std::max(b.upper_z, p.upper_z);
  }
  return leaf;
}

double surfaceArea(const glm::vec3& lo, const glm::vec3& hi) {
  const glm::dvec3 d = glm::max(glm::dvec3(hi) - glm::dvec3(lo), glm::dvec3(0.0));
  return 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
}

// Depth-first flattening: an inner node's first child follows it directly in memory.
class Flattener {
 public:
  Flattener(const std::vector<shared::BvhTriangle>& source, float pad, Bvh& out)
      : source_(source), pad_(pad), out_(out) {}

  void flattenRoot(const BuildNode* root) {
    if (!root->leaf) {
      emitInner(static_cast<const InnerNode*>(root), 1);
      return;
    }
    // A one-leaf tree still starts at a node: the leaf in slot 0, slot 1 empty (index 0, count 0).
    const auto* leaf = static_cast<const LeafNode*>(root);
    out_.nodes.emplace_back();
    maxDepth_ = 1;
    const shared::BvhChild slot = child(leaf, leaf->bounds, 1);
    out_.nodes[0].child[0] = slot;
    out_.nodes[0].child[1] = {slot.lo, 0u, slot.hi, 0u};
  }
  std::uint32_t maxDepth() const { return maxDepth_; }
  std::uint64_t leaves() const { return leaves_; }

 private:
  std::uint32_t emitInner(const InnerNode* node, std::uint32_t depth) {
    const auto index = std::uint32_t(out_.nodes.size());
    out_.nodes.emplace_back();
    maxDepth_ = std::max(maxDepth_, depth);
    shared::BvhChild slots[2];
    for (unsigned c = 0; c < 2; ++c) {
      slots[c] = c < node->childCount ? child(node->children[c], node->bounds[c], depth) : shared::BvhChild{};
    }
    if (node->childCount < 2) slots[1] = {slots[0].lo, 0u, slots[0].hi, 0u};  // empty slot
    out_.nodes[index].child[0] = slots[0];  // after the recursion: emplace_back may have moved nodes
    out_.nodes[index].child[1] = slots[1];
    return index;
  }

  shared::BvhChild child(const BuildNode* node, const RTCBounds& b, std::uint32_t depth) {
    // Padding keeps the box test conservative against rounding in the slab and triangle tests.
    const glm::vec3 lo = glm::vec3(b.lower_x, b.lower_y, b.lower_z) - pad_;
    const glm::vec3 hi = glm::vec3(b.upper_x, b.upper_y, b.upper_z) + pad_;
    if (!node->leaf) return {lo, emitInner(static_cast<const InnerNode*>(node), depth + 1), hi, 0u};
    const auto* leaf = static_cast<const LeafNode*>(node);
    const auto first = std::uint32_t(out_.triangles.size());
    for (std::uint32_t i = 0; i < leaf->count; ++i) out_.triangles.push_back(source_[leaf->ids[i]]);
    ++leaves_;
    return {lo, first, hi, leaf->count};
  }

  const std::vector<shared::BvhTriangle>& source_;
  float pad_;
  Bvh& out_;
  std::uint32_t maxDepth_ = 0;
  std::uint64_t leaves_ = 0;
};

// The empty selection's tree (see Bvh in the header): a degenerate triangle fails the edge or
// the plane test for every ray, so the root's one leaf never reports a hit.
Bvh emptyBvh() {
  Bvh bvh;
  const glm::vec3 p(0.0f);
  bvh.triangles.push_back({p, BVH_NO_HIT, p, 0u, p, 0u});
  bvh.nodes.emplace_back();
  bvh.nodes[0].child[0] = {p, 0u, p, 1u};
  bvh.nodes[0].child[1] = {p, 0u, p, 0u};  // empty slot
  BvhStats& s = bvh.stats;
  s.nodes = 1;
  s.bytes = sizeof(shared::BvhNode) + sizeof(shared::BvhTriangle);
  s.sahCost = 1.0;
  s.maxDepth = 1;
  return bvh;
}

}  // namespace

std::uint64_t triangleCount(const Scene& scene, MeshSet set) {
  std::uint64_t count = 0;
  for (const Mesh& mesh : scene.meshes) {
    if (inMeshSet(mesh, set)) count += mesh.triangleCount();
  }
  return count;
}

// About 8 ulps of the largest coordinate: above the rounding of the slab and edge tests for
// origins inside the scene, far below any feature size (1e-6 of the scene's extent).
float bvhBoxPadding(float extent) { return std::max(extent * 1.0e-6f, std::numeric_limits<float>::min()); }

// SAH cost of the flattened tree with Ct = Ci = 1: every node is visited with the probability
// area(node box) / area(root box), every leaf's triangles are tested with its own area ratio.
double sahCost(const Bvh& bvh) {
  auto nodeBox = [&](const shared::BvhNode& n, glm::vec3& lo, glm::vec3& hi) {
    lo = n.child[0].lo;
    hi = n.child[0].hi;
    const shared::BvhChild& c = n.child[1];
    if (c.count > 0 || c.index != 0) {
      lo = glm::min(lo, c.lo);
      hi = glm::max(hi, c.hi);
    }
  };
  glm::vec3 lo, hi;
  nodeBox(bvh.nodes[0], lo, hi);
  double rootArea = surfaceArea(lo, hi);
  if (!(rootArea > 0.0)) rootArea = 1.0;  // a flat, line-like scene: plain counts instead
  double cost = 0.0;
  for (const shared::BvhNode& n : bvh.nodes) {
    nodeBox(n, lo, hi);
    cost += surfaceArea(lo, hi) / rootArea;
    for (const shared::BvhChild& c : n.child) {
      if (c.count > 0) cost += double(c.count) * surfaceArea(c.lo, c.hi) / rootArea;
    }
  }
  return std::max(cost, 1.0);  // the root is always visited; flat scenes can round below
}

struct BvhBuilder::Impl {
  DevicePtr device;
};

BvhBuilder::BvhBuilder(const BvhBuildSettings& settings) : settings_(settings), impl_(std::make_unique<Impl>()) {
  if (!(settings.rebuildGrowth > 1.0f)) {
    throw std::invalid_argument("BvhBuilder: rebuildGrowth " + std::to_string(settings.rebuildGrowth) +
                                " must exceed 1 (a refit tree is rebuilt when its SAH cost grows past it)");
  }
  if (settings.maxLeafSize < 1 || settings.maxLeafSize > BvhBuildSettings::kMaxLeafSize) {
    throw std::invalid_argument("BvhBuilder: maxLeafSize " + std::to_string(settings.maxLeafSize) + " is outside 1.." +
                                std::to_string(BvhBuildSettings::kMaxLeafSize));
  }
  if (!(settings.traversalCost > 0.0f) || !(settings.intersectionCost > 0.0f)) {
    throw std::invalid_argument("BvhBuilder: SAH costs must be positive");
  }
  impl_->device.reset(rtcNewDevice(nullptr));
  if (!impl_->device) throw std::runtime_error("BvhBuilder: Embree device creation failed");
}

BvhBuilder::~BvhBuilder() = default;

void triangleVertices(const Scene& scene, const Mesh& mesh, std::size_t t, glm::vec3 (&v)[3], float& extent) {
  for (int k = 0; k < 3; ++k) {
    const std::uint32_t index = mesh.indices[3 * t + k];
    if (index >= mesh.positions.size()) {
      throw InputError("BVH: mesh '" + mesh.name + "' of scene '" + scene.name + "' has vertex index " +
                       std::to_string(index) + " out of range (" + std::to_string(mesh.positions.size()) +
                       " vertices); load scenes through loadScene, which cleans them");
    }
    v[k] = mesh.positions[index];
    if (!std::isfinite(v[k].x) || !std::isfinite(v[k].y) || !std::isfinite(v[k].z)) {
      throw InputError("BVH: mesh '" + mesh.name + "' of scene '" + scene.name + "' has a non-finite vertex");
    }
    extent = std::max({extent, std::abs(v[k].x), std::abs(v[k].y), std::abs(v[k].z)});
  }
}

Bvh BvhBuilder::build(const Scene& scene, MeshSet set) const {
  const auto start = std::chrono::steady_clock::now();
  const std::size_t sceneTotal = scene.triangleCount();
  if (sceneTotal == 0) throw InputError("BVH: scene '" + scene.name + "' has no triangles to build a BVH over");
  if (sceneTotal >= std::size_t(BVH_NO_HIT)) {
    throw InputError("BVH: scene '" + scene.name + "' has " + std::to_string(sceneTotal) +
                     " triangles, more than 32-bit ids allow");
  }
  const std::size_t total = triangleCount(scene, set);
  if (total == 0) {
    Bvh bvh = emptyBvh();
    bvh.stats.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return bvh;
  }

  // Triangles in scene order (their id) and their boxes, the builder's input.
  std::vector<shared::BvhTriangle> source;
  std::vector<RTCBuildPrimitive> prims;
  source.reserve(total);
  prims.reserve(total);
  float extent = 0.0f;  // largest coordinate magnitude, the scale of rounding errors
  std::uint32_t firstId = 0;  // scene index of the mesh's first triangle
  const std::vector<std::uint32_t> firstCutout = cutoutIndices(scene);
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    const std::uint32_t meshFirst = firstId;
    firstId += std::uint32_t(mesh.triangleCount());
    if (!inMeshSet(mesh, set)) continue;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      glm::vec3 v[3];
      triangleVertices(scene, mesh, t, v, extent);
      // The builder sees positions in `source` (primID); the triangle keeps its scene-wide id.
      const auto primId = std::uint32_t(source.size());
      const std::uint32_t cutout = firstCutout[m] == 0 ? 0u : firstCutout[m] + std::uint32_t(t);
      source.push_back({v[0], meshFirst + std::uint32_t(t), v[1], cutout, v[2], 0u});
      const glm::vec3 lo = glm::min(v[0], glm::min(v[1], v[2]));
      const glm::vec3 hi = glm::max(v[0], glm::max(v[1], v[2]));
      prims.push_back({lo.x, lo.y, lo.z, 0u, hi.x, hi.y, hi.z, primId});
    }
  }

  BuildContext context;
  EmbreeBvhPtr embreeBvh(rtcNewBVH(impl_->device.get()));
  if (!embreeBvh) throw std::runtime_error("BvhBuilder: rtcNewBVH failed");
  RTCBuildArguments args = rtcDefaultBuildArguments();
  // HIGH without a split callback is Embree's binned SAH builder: no spatial splits, so every
  // triangle lands in exactly one leaf.
  args.buildQuality = RTC_BUILD_QUALITY_HIGH;
  args.maxBranchingFactor = 2;
  // Embree counts the root as depth 1 and keeps leaves at depth <= maxDepth, so the nodes on a
  // path number at most BVH_STACK_SIZE and the traversal pushes fewer than that.
  args.maxDepth = BVH_STACK_SIZE;
  args.minLeafSize = 1;
  args.maxLeafSize = settings_.maxLeafSize;
  args.traversalCost = settings_.traversalCost;
  args.intersectionCost = settings_.intersectionCost;
  args.bvh = embreeBvh.get();
  args.primitives = prims.data();
  args.primitiveCount = prims.size();
  args.primitiveArrayCapacity = prims.size();
  args.createNode = createNode;
  args.setNodeChildren = setNodeChildren;
  args.setNodeBounds = setNodeBounds;
  args.createLeaf = createLeaf;
  args.userPtr = &context;
  const auto* root = static_cast<const BuildNode*>(rtcBuildBVH(&args));
  if (!root || context.failed) {
    const RTCError code = rtcGetDeviceError(impl_->device.get());
    throw std::runtime_error("BvhBuilder: Embree could not build a BVH over scene '" + scene.name + "' (" +
                             std::to_string(total) + " triangles, error code " + std::to_string(int(code)) +
                             (context.failed ? ", a node or leaf exceeded the requested size" : "") + ")");
  }

  Bvh bvh;
  bvh.nodes.reserve(std::max<std::uint64_t>(context.innerNodes, 1));
  bvh.triangles.reserve(total);
  const float pad = bvhBoxPadding(extent);
  Flattener flattener(source, pad, bvh);
  flattener.flattenRoot(root);
  if (bvh.triangles.size() != total) {
    throw std::runtime_error("BvhBuilder: the leaves hold " + std::to_string(bvh.triangles.size()) +
                             " triangles, the selected meshes " + std::to_string(total));
  }
  if (flattener.maxDepth() > BVH_STACK_SIZE) {
    throw std::runtime_error("BvhBuilder: depth " + std::to_string(flattener.maxDepth()) + " exceeds BVH_STACK_SIZE " +
                             std::to_string(BVH_STACK_SIZE));
  }

  BvhStats& s = bvh.stats;
  s.nodes = bvh.nodes.size();
  s.leaves = flattener.leaves();
  s.triangles = bvh.triangles.size();
  s.bytes = s.nodes * sizeof(shared::BvhNode) + s.triangles * sizeof(shared::BvhTriangle);
  s.sahCost = sahCost(bvh);
  s.maxDepth = flattener.maxDepth();
  s.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return bvh;
}

}  // namespace penumbra
