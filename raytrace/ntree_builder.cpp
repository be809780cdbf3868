#include "raytrace/ntree_builder.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <string>
#include <thread>

#include "shared/linespace.h"

namespace penumbra {
namespace {

// Cells are enlarged by this fraction of their edge before the overlap test: triangles lying on a
// cell face (a ground plane on a grid line) land on both sides rather than on neither after
// rounding. Costs a few extra non-empty cells, never a missing one.
constexpr double kCellSlack = 1e-5;

struct Triangles {
  std::vector<glm::vec3> v;  // three per triangle, scene order
  glm::dvec3 vertex(std::uint32_t t, int k) const { return glm::dvec3(v[std::size_t(t) * 3 + std::size_t(k)]); }
  std::uint32_t count() const { return std::uint32_t(v.size() / 3); }
};

// A subtree built by one worker, indices local to it; merged in cell order afterwards.
struct Fragment {
  std::vector<NTree::Node> nodes;
  std::vector<std::uint32_t> children;
  std::vector<NTree::Leaf> leaves;
  std::vector<std::uint32_t> leafTriangles;
};

unsigned workerCount() { return std::max(1u, std::thread::hardware_concurrency()); }

// Appends to cells[c] every triangle of `tris` (which overlap the node) that overlaps child cell c.
void distribute(const Triangles& t, const std::uint32_t* tris, std::size_t count, const glm::vec3& lo, float size,
                std::uint32_t n, std::vector<std::vector<std::uint32_t>>& cells) {
  const double cell = double(size) / n;
  const glm::dvec3 origin(lo);
  const double slack = cell * kCellSlack;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t tri = tris[i];
    const glm::dvec3 a = t.vertex(tri, 0), b = t.vertex(tri, 1), c = t.vertex(tri, 2);
    const glm::dvec3 bmin = glm::min(a, glm::min(b, c)), bmax = glm::max(a, glm::max(b, c));
    int first[3], last[3];
    for (int k = 0; k < 3; ++k) {
      first[k] = std::clamp(int(std::floor((bmin[k] - slack - origin[k]) / cell)), 0, int(n) - 1);
      last[k] = std::clamp(int(std::floor((bmax[k] + slack - origin[k]) / cell)), 0, int(n) - 1);
    }
    // The triangle overlaps the node, so when its box spans one cell it overlaps that cell.
    const bool single = first[0] == last[0] && first[1] == last[1] && first[2] == last[2];
    for (int z = first[2]; z <= last[2]; ++z) {
      for (int y = first[1]; y <= last[1]; ++y) {
        for (int x = first[0]; x <= last[0]; ++x) {
          const glm::dvec3 clo = origin + glm::dvec3(x, y, z) * cell - slack;
          const glm::dvec3 chi = origin + glm::dvec3(x + 1, y + 1, z + 1) * cell + slack;
          if (single || triangleOverlapsBox(a, b, c, clo, chi)) {
            cells[shared::lsCellIndex(std::uint32_t(x), std::uint32_t(y), std::uint32_t(z), n)].push_back(tri);
          }
        }
      }
    }
  }
}

glm::vec3 cellLow(const NTree::Node& node, std::uint32_t cell, std::uint32_t n) {
  const std::uint32_t i = cell % n, j = (cell / n) % n, k = cell / (n * n);
  return node.lo + glm::vec3(float(i), float(j), float(k)) * (node.size / float(n));
}

// Splits fragment node `index` (which the triangles `tris` overlap) into its N^3 cells, depth first.
void subdivide(const Triangles& t, std::uint32_t n, std::uint32_t depth, Fragment& f, std::uint32_t index,
               const std::vector<std::uint32_t>& tris) {
  const NTree::Node node = f.nodes[index];
  const std::uint32_t cellCount = n * n * n;
  std::vector<std::vector<std::uint32_t>> cells(cellCount);
  distribute(t, tris.data(), tris.size(), node.lo, node.size, n, cells);
  const auto base = std::uint32_t(f.children.size());
  f.children.resize(f.children.size() + cellCount, NTree::kEmpty);
  f.nodes[index].childBase = base;
  for (std::uint32_t c = 0; c < cellCount; ++c) {
    if (cells[c].empty()) continue;
    if (node.level + 1 < depth) {
      const auto child = std::uint32_t(f.nodes.size());
      f.nodes.push_back({cellLow(node, c, n), node.size / float(n), node.level + 1, 0});
      f.children[base + c] = child;
      subdivide(t, n, depth, f, child, cells[c]);
    } else {
      f.children[base + c] = NTree::kLeafBit | std::uint32_t(f.leaves.size());
      f.leaves.push_back({std::uint32_t(f.leafTriangles.size()), std::uint32_t(cells[c].size())});
      f.leafTriangles.insert(f.leafTriangles.end(), cells[c].begin(), cells[c].end());
    }
    std::vector<std::uint32_t>().swap(cells[c]);  // the subtree is built: free its list early
  }
}

// Runs job(i) for i in [0, count) on all cores, each index once.
template <class Job>
void parallelFor(std::uint32_t count, const Job& job) {
  std::atomic<std::uint32_t> next{0};
  auto work = [&] {
    for (std::uint32_t i = next++; i < count; i = next++) job(i);
  };
  std::vector<std::thread> threads;
  for (unsigned w = 1; w < std::min<unsigned>(workerCount(), count); ++w) threads.emplace_back(work);
  work();
  for (std::thread& thread : threads) thread.join();
}

}  // namespace

bool triangleOverlapsBox(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& lo,
                         const glm::dvec3& hi) {
  const glm::dvec3 centre = 0.5 * (lo + hi), h = 0.5 * (hi - lo);
  const glm::dvec3 v[3] = {a - centre, b - centre, c - centre};
  auto separated = [&](const glm::dvec3& axis) {
    const double p0 = glm::dot(v[0], axis), p1 = glm::dot(v[1], axis), p2 = glm::dot(v[2], axis);
    const double r = h.x * std::abs(axis.x) + h.y * std::abs(axis.y) + h.z * std::abs(axis.z);
    return std::min(p0, std::min(p1, p2)) > r || std::max(p0, std::max(p1, p2)) < -r;
  };
  for (int k = 0; k < 3; ++k) {
    glm::dvec3 axis(0.0);
    axis[k] = 1.0;
    if (separated(axis)) return false;
  }
  const glm::dvec3 e[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  if (separated(glm::cross(e[0], e[1]))) return false;
  for (const glm::dvec3& edge : e) {
    for (int k = 0; k < 3; ++k) {
      glm::dvec3 axis(0.0);
      axis[k] = 1.0;
      if (separated(glm::cross(axis, edge))) return false;
    }
  }
  return true;
}

void NTreeBuilder::validate(std::uint32_t n, std::uint32_t depth) {
  if (n < LS_MIN_N || n > LS_MAX_N || depth < LS_MIN_DEPTH || depth > LS_MAX_DEPTH) {
    throw InputError("line space: N=" + std::to_string(n) + ", d=" + std::to_string(depth) +
                     " is not supported; use N (--linespace-n) from " + std::to_string(LS_MIN_N) + " to " +
                     std::to_string(LS_MAX_N) + " and d (--linespace-depth) from " + std::to_string(LS_MIN_DEPTH) +
                     " to " + std::to_string(LS_MAX_DEPTH));
  }
}

NTreeBuilder::NTreeBuilder(std::uint32_t n, std::uint32_t depth) : n_(n), depth_(depth) { validate(n, depth); }

NTree NTreeBuilder::build(const Scene& scene, MeshSet set) const {
  const auto start = std::chrono::steady_clock::now();
  Triangles t;
  t.v.reserve(triangleCount(scene, set) * 3);
  for (const Mesh& mesh : scene.meshes) {
    if (!inMeshSet(mesh, set)) continue;
    for (std::uint32_t index : mesh.indices) t.v.push_back(mesh.positions[index]);
  }
  if (t.count() == 0) {
    throw InputError("line space: scene '" + scene.name + "' has no " +
                     (set == MeshSet::Static ? "static triangles (the line space covers static meshes; use --tracer bvh)"
                                             : "triangles"));
  }
  Bounds bounds;
  for (const glm::vec3& p : t.v) bounds.extend(p);
  const glm::vec3 extent = bounds.hi - bounds.lo;
  // A cube a little larger than the largest extent, so that no triangle touches the root's faces.
  const float largest = std::max(extent.x, std::max(extent.y, extent.z));
  const float size = largest * 1.0001f + 1e-6f * std::max(1.0f, glm::length(bounds.center()));

  NTree tree;
  tree.n = n_;
  tree.depth = depth_;
  tree.nodes.push_back({bounds.center() - glm::vec3(0.5f * size), size, 0, 0});
  const std::uint32_t cellCount = n_ * n_ * n_;

  // The root's cells: triangles distributed in chunks on all cores, lists joined in chunk order.
  const std::uint32_t chunks = std::min(t.count(), workerCount() * 4);
  std::vector<std::vector<std::vector<std::uint32_t>>> parts(chunks);
  parallelFor(chunks, [&](std::uint32_t chunk) {
    const std::uint32_t begin = std::uint32_t(std::uint64_t(t.count()) * chunk / chunks);
    const std::uint32_t end = std::uint32_t(std::uint64_t(t.count()) * (chunk + 1) / chunks);
    std::vector<std::uint32_t> ids(end - begin);
    for (std::uint32_t i = begin; i < end; ++i) ids[i - begin] = i;
    parts[chunk].resize(cellCount);
    distribute(t, ids.data(), ids.size(), tree.nodes[0].lo, size, n_, parts[chunk]);
  });
  std::vector<std::uint32_t> occupied;  // non-empty root cells, in cell order
  std::vector<std::vector<std::uint32_t>> rootCells(cellCount);
  for (std::uint32_t c = 0; c < cellCount; ++c) {
    for (auto& part : parts) rootCells[c].insert(rootCells[c].end(), part[c].begin(), part[c].end());
    if (!rootCells[c].empty()) occupied.push_back(c);
  }
  parts.clear();

  // Each non-empty root cell is one subtree (d >= 2, so root cells are always subdivided).
  std::vector<Fragment> fragments(occupied.size());
  parallelFor(std::uint32_t(occupied.size()), [&](std::uint32_t i) {
    Fragment& f = fragments[i];
    f.nodes.push_back({cellLow(tree.nodes[0], occupied[i], n_), size / float(n_), 1, 0});
    subdivide(t, n_, depth_, f, 0, rootCells[occupied[i]]);
    std::vector<std::uint32_t>().swap(rootCells[occupied[i]]);
  });

  tree.children.assign(cellCount, NTree::kEmpty);
  for (std::size_t i = 0; i < fragments.size(); ++i) {
    const Fragment& f = fragments[i];
    const auto nodeOffset = std::uint32_t(tree.nodes.size());
    const auto childOffset = std::uint32_t(tree.children.size());
    const auto leafOffset = std::uint32_t(tree.leaves.size());
    const auto triOffset = std::uint32_t(tree.leafTriangles.size());
    tree.children[occupied[i]] = nodeOffset;
    for (NTree::Node node : f.nodes) {
      node.childBase += childOffset;
      tree.nodes.push_back(node);
    }
    for (std::uint32_t entry : f.children) {
      if (entry == NTree::kEmpty) tree.children.push_back(entry);
      else if (entry & NTree::kLeafBit) tree.children.push_back(NTree::kLeafBit | ((entry & ~NTree::kLeafBit) + leafOffset));
      else tree.children.push_back(entry + nodeOffset);
    }
    for (NTree::Leaf leaf : f.leaves) tree.leaves.push_back({leaf.first + triOffset, leaf.count});
    tree.leafTriangles.insert(tree.leafTriangles.end(), f.leafTriangles.begin(), f.leafTriangles.end());
  }

  tree.stats.nodes = tree.nodes.size();
  tree.stats.leaves = tree.leaves.size();
  tree.stats.leafTriangleRefs = tree.leafTriangles.size();
  tree.stats.nodesPerLevel.assign(depth_, 0);
  for (const NTree::Node& node : tree.nodes) ++tree.stats.nodesPerLevel[node.level];
  tree.stats.buildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return tree;
}

}  // namespace penumbra
