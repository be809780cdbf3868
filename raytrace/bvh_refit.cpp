#include "raytrace/bvh_refit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/units.h"

namespace penumbra {
namespace {

struct Box {
  glm::vec3 lo{std::numeric_limits<float>::max()};
  glm::vec3 hi{-std::numeric_limits<float>::max()};
  void extend(const glm::vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void extend(const Box& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
};

}  // namespace

void refitBvh(Bvh& bvh, const Scene& scene) {
  if (bvh.empty()) return;  // the empty tree's degenerate triangle is no scene triangle
  // Scene-wide id -> mesh: the first id of every mesh.
  std::vector<std::uint64_t> firstIds;
  firstIds.reserve(scene.meshes.size() + 1);
  std::uint64_t total = 0;
  for (const Mesh& mesh : scene.meshes) {
    firstIds.push_back(total);
    total += mesh.triangleCount();
  }
  firstIds.push_back(total);

  float extent = 0.0f;  // as the builder measures it, over the tree's triangles
  for (shared::BvhTriangle& tri : bvh.triangles) {
    if (tri.id >= total) {
      throw InputError("BVH refit: triangle id " + std::to_string(tri.id) + " is outside scene '" + scene.name +
                       "' (" + std::to_string(total) + " triangles); moving meshes must keep their triangles");
    }
    const auto m = std::size_t(std::upper_bound(firstIds.begin(), firstIds.end(), tri.id) - firstIds.begin() - 1);
    const Mesh& mesh = scene.meshes[m];
    const std::size_t t = tri.id - firstIds[m];
    glm::vec3 v[3];
    triangleVertices(scene, mesh, t, v, extent);
    tri.v0 = v[0];
    tri.v1 = v[1];
    tri.v2 = v[2];
  }

  // Children follow their parent in the depth-first order, so a reverse sweep sees every child
  // before its parent. Boxes are unioned unpadded, as Embree's builder hands them over, and each
  // child slot is padded once, as the builder's flattening does.
  const float pad = bvhBoxPadding(extent);
  std::vector<Box> nodeBox(bvh.nodes.size());
  for (std::size_t i = bvh.nodes.size(); i-- > 0;) {
    shared::BvhNode& node = bvh.nodes[i];
    Box slotBox[2];
    for (int c = 0; c < 2; ++c) {
      const shared::BvhChild& child = node.child[c];
      if (child.count > 0) {
        for (std::uint32_t k = child.index; k < child.index + child.count; ++k) {
          const shared::BvhTriangle& tri = bvh.triangles[k];
          slotBox[c].extend(tri.v0);
          slotBox[c].extend(tri.v1);
          slotBox[c].extend(tri.v2);
        }
      } else if (child.index != 0) {
        if (child.index <= i || child.index >= bvh.nodes.size()) {
          throw std::logic_error("BVH refit: node " + std::to_string(i) + " has child " + std::to_string(child.index) +
                                 ", not after it in depth-first order");
        }
        slotBox[c] = nodeBox[child.index];
      }
    }
    nodeBox[i] = slotBox[0];
    const bool emptySlot = node.child[1].count == 0 && node.child[1].index == 0;
    if (!emptySlot) nodeBox[i].extend(slotBox[1]);
    node.child[0].lo = slotBox[0].lo - pad;
    node.child[0].hi = slotBox[0].hi + pad;
    // An empty slot repeats slot 0's box, as the builder writes it.
    node.child[1].lo = emptySlot ? node.child[0].lo : slotBox[1].lo - pad;
    node.child[1].hi = emptySlot ? node.child[0].hi : slotBox[1].hi + pad;
  }
  bvh.stats.sahCost = sahCost(bvh);
}

DynamicBvh::DynamicBvh(const Scene& scene, const BvhBuildSettings& settings)
    : settings_(settings), builder_(settings), triangles_(penumbra::triangleCount(scene, MeshSet::Dynamic)) {
  if (triangles_ == 0) return;
  bvh_ = builder_.build(scene, MeshSet::Dynamic);
  builtSah_ = bvh_.stats.sahCost;
}

BvhRefitReport DynamicBvh::update(const Scene& scene) {
  BvhRefitReport report;
  if (empty()) return report;
  const auto start = std::chrono::steady_clock::now();
  const std::uint64_t now = penumbra::triangleCount(scene, MeshSet::Dynamic);
  if (now != triangles_) {
    throw InputError("BVH update: the dynamic meshes of scene '" + scene.name + "' had " +
                     std::to_string(triangles_) + " triangles and now have " + std::to_string(now) +
                     "; moving meshes may only change positions and normals");
  }
  refitBvh(bvh_, scene);
  report.refitSah = bvh_.stats.sahCost;
  report.growth = report.refitSah / builtSah_;
  if (report.growth > double(settings_.rebuildGrowth)) {
    bvh_ = builder_.build(scene, MeshSet::Dynamic);
    if (bvh_.nodes.size() > nodeCapacity()) {
      throw std::runtime_error("BVH update: the rebuilt dynamic tree has " + std::to_string(bvh_.nodes.size()) +
                               " nodes, more than the " + std::to_string(nodeCapacity()) + " its buffers hold");
    }
    builtSah_ = bvh_.stats.sahCost;
    ++rebuilds_;
    report.rebuilt = true;
  }
  report.sah = bvh_.stats.sahCost;
  report.builtSah = builtSah_;
  report.triangles = triangles_;
  report.rebuilds = rebuilds_;
  write();
  report.ms = msSince(start);
  return report;
}

void DynamicBvh::attach(const gpu::Buffer& nodes, const gpu::Buffer& triangles, std::uint32_t nodeOffset,
                        std::uint32_t triangleOffset) {
  if (empty()) return;
  if (nodeOffset == 0) throw std::logic_error("DynamicBvh::attach: node offset 0 would read as an empty slot");
  if (nodes.size() < (nodeOffset + nodeCapacity()) * sizeof(shared::BvhNode) ||
      triangles.size() < (triangleOffset + triangles_) * sizeof(shared::BvhTriangle)) {
    throw std::logic_error("DynamicBvh::attach: the buffers are too small for the tree at its offsets");
  }
  nodes_ = &nodes;
  triangleBuffer_ = &triangles;
  nodeOffset_ = nodeOffset;
  triangleOffset_ = triangleOffset;
  write();
}

void DynamicBvh::write() const {
  if (!nodes_) return;
  auto* nodes = static_cast<shared::BvhNode*>(nodes_->data()) + nodeOffset_;
  for (std::size_t i = 0; i < bvh_.nodes.size(); ++i) {
    shared::BvhNode node = bvh_.nodes[i];
    for (shared::BvhChild& child : node.child) {
      if (child.count > 0) child.index += triangleOffset_;
      else if (child.index != 0) child.index += nodeOffset_;  // index 0, count 0: the empty slot stays
    }
    nodes[i] = node;
  }
  std::copy(bvh_.triangles.begin(), bvh_.triangles.end(),
            static_cast<shared::BvhTriangle*>(triangleBuffer_->data()) + triangleOffset_);
}

}  // namespace penumbra
