#include "raytrace/line_space.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <thread>

#include "core/cutouts.h"
#include "core/units.h"
#include "raytrace/shaft_table.h"

namespace penumbra {

const Options<LineSpaceSettings>& lineSpaceOptions() {
  static const Options<LineSpaceSettings> options = [] {
    using S = LineSpaceSettings;
    Options<S> o("Line space");
    o.number("--linespace-n", "line_space/n", &S::n, "Line space: N-tree branching factor N", LS_MIN_N, LS_MAX_N)
        .sweep("N", {"srt", "frt", "ls"}, false, true);
    o.number("--linespace-depth", "line_space/depth", &S::depth, "Line space: N-tree depth d", LS_MIN_DEPTH,
             LS_MAX_DEPTH)
        .sweep("d", {"srt", "frt", "ls"}, false, true);
    o.megabytes("--linespace-budget", "line_space/budget_mb", &S::budgetBytes,
                "Line space: memory budget of its pools in MB (0 = a quarter of the available memory)");
    o.choice("--ls-shadows,--linespace-shadows", "line_space/shadows", &S::shadows,
             "Line space: shadow rays answered by the shaft bits alone (binary: fast, conservative, thin casters "
             "shadow as whole cells, no contact shadows) or by the leaf cells' triangles the set bits lead to "
             "(exact: the BVH's answer; more memory)",
             {{"binary", S::Shadows::Binary}, {"exact", S::Shadows::Exact}});
    o.number("--linespace-offset", "line_space/offset_cells", &LineSpaceSettings::startOffsetCells,
             "Line space: ignore occluders within this many leaf cells of the receiver's surface (0 = the paper's "
             "start-node rule alone)",
             0.0f, 16.0f);
    return o;
  }();
  return options;
}
const char* shadowsName(LineSpaceSettings::Shadows shadows) {
  return shadows == LineSpaceSettings::Shadows::Exact ? "exact" : "binary";
}

LineSpaceSizes lineSpaceSizes(std::uint32_t n, std::uint64_t nodes, std::uint64_t groups, std::uint64_t leaves,
                              std::uint64_t leafTriangleRefs, std::uint64_t triangles) {
  LineSpaceSizes s;
  s.treeBytes = std::max<std::uint64_t>(groups, 1) * n * n * n * sizeof(std::uint32_t);
  s.nodeBytes = nodes * sizeof(shared::LsNode);
  s.lineSpaceBytes = nodes * shared::lsWordsPerNode(n) * sizeof(std::uint32_t);
  s.leafBytes = leaves * sizeof(shared::LsLeaf);
  s.leafTriangleBytes = leafTriangleRefs * sizeof(std::uint32_t);
  s.triangleBytes = triangles * sizeof(shared::BvhTriangle);
  return s;
}

std::vector<shared::BvhTriangle> lineSpaceTriangles(const Scene& scene, MeshSet set) {
  std::vector<shared::BvhTriangle> out;
  out.reserve(triangleCount(scene, set));
  std::uint32_t id = 0;  // scene index of the triangle
  const std::vector<std::uint32_t> firstCutout = cutoutIndices(scene);
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    const bool in = inMeshSet(mesh, set);
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t, ++id) {
      if (!in) continue;
      const glm::vec3 a = mesh.positions[mesh.indices[3 * t]], b = mesh.positions[mesh.indices[3 * t + 1]];
      const glm::vec3 c = mesh.positions[mesh.indices[3 * t + 2]];
      out.push_back({a, id, b, firstCutout[m] == 0 ? 0u : firstCutout[m] + std::uint32_t(t), c, 0u});
    }
  }
  return out;
}

std::uint64_t defaultLineSpaceBudget() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  std::uint64_t kib = 0;
  std::string unit;
  while (meminfo >> key >> kib >> unit) {
    if (key == "MemAvailable:") return kib * 1024 / 4;
  }
  return std::uint64_t(1) << 30;  // no /proc: 1 GiB
}

LineSpace buildLineSpace(const NTree& tree, const LineSpaceSettings& settings, std::uint64_t maxPoolBytes,
                         const std::string& sceneName, std::uint64_t dynamicBvhBytes,
                         std::vector<shared::BvhTriangle> triangles) {
  const auto start = std::chrono::steady_clock::now();
  const std::uint32_t n = tree.n, depth = tree.depth;
  const bool exact = settings.shadows == LineSpaceSettings::Shadows::Exact;
  if (exact) {
    const auto covered = [&](std::uint32_t t) { return t < triangles.size(); };
    if (!std::all_of(tree.leafTriangles.begin(), tree.leafTriangles.end(), covered)) {
      throw std::invalid_argument("buildLineSpace: exact mode needs the tree's triangles (lineSpaceTriangles)");
    }
  } else {
    triangles.clear();
  }
  // Exact mode: every subdivided node has a children group (leaf records at the last level).
  const std::uint64_t groups = exact ? tree.nodes.size() : tree.nodes.size() - tree.stats.nodesPerLevel[depth - 1];
  const LineSpaceSizes sizes = exact ? lineSpaceSizes(n, tree.nodes.size(), groups, tree.leaves.size(),
                                                      tree.leafTriangles.size(), triangles.size())
                                     : lineSpaceSizes(n, tree.nodes.size(), groups);
  const std::uint64_t budget = settings.budgetBytes ? settings.budgetBytes : defaultLineSpaceBudget();
  const std::string set = "line space (N=" + std::to_string(n) + ", d=" + std::to_string(depth) + ") of scene '" +
                          sceneName + "'";
  if (sizes.total() + dynamicBvhBytes > budget) {
    throw InputError(set + " needs " + megabytes(sizes.total() + dynamicBvhBytes) + " (" +
                     std::to_string(tree.nodes.size()) + " subdivided nodes" +
                     (exact ? ", exact shadows: " + std::to_string(tree.leaves.size()) + " leaf cells, " +
                                  std::to_string(tree.leafTriangles.size()) + " triangle references, " +
                                  std::to_string(triangles.size()) + " triangles"
                            : "") +
                     (dynamicBvhBytes ? ", and " + megabytes(dynamicBvhBytes) + " for the moving meshes' BVH" : "") +
                     ") but the budget is " + megabytes(budget) +
                     "; lower N (--linespace-n) or d (--linespace-depth), or raise --linespace-budget (MB)" +
                     (exact ? ", or use --ls-shadows binary" : ""));
  }
  const std::uint64_t largest = std::max({sizes.treeBytes, sizes.nodeBytes, sizes.lineSpaceBytes, sizes.leafBytes,
                                          sizes.leafTriangleBytes, sizes.triangleBytes});
  if (maxPoolBytes && largest > maxPoolBytes) {
    throw InputError(set + " needs " + megabytes(largest) + " in one pool but the device binds at most " +
                     megabytes(maxPoolBytes) +
                     " per storage buffer (maxStorageBufferRange); lower N (--linespace-n) or d (--linespace-depth)");
  }

  const auto tableStart = std::chrono::steady_clock::now();
  const ShaftTable& table = ShaftTable::get(n);
  const double tableMs = msSince(tableStart);

  LineSpace ls;
  ls.n = n;
  ls.depth = depth;
  const std::uint32_t cells = n * n * n, words = shared::lsWordsPerNode(n);
  ls.nodes.resize(tree.nodes.size());
  ls.tree.reserve(sizes.treeBytes / sizeof(std::uint32_t));
  for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
    const NTree::Node& node = tree.nodes[i];
    shared::LsNode& out = ls.nodes[i];
    out = {node.lo, node.size, LS_SKIP, node.level, 0u, 0u};
    // Binary mode: the children of second-to-last-level nodes are leaves, never entered.
    if (node.level + 1 >= depth && !exact) continue;
    out.children = std::uint32_t(ls.tree.size());
    for (std::uint32_t c = 0; c < cells; ++c) {
      // Above level d-1 children are nodes; at level d-1 (exact mode) kLeafBit | leaf record.
      const std::uint32_t entry = tree.child(std::uint32_t(i), c);
      ls.tree.push_back(entry == NTree::kEmpty ? LS_SKIP : entry & ~NTree::kLeafBit);
    }
  }
  if (ls.tree.empty()) ls.tree.assign(cells, LS_SKIP);  // d = 2 keeps its root group; never empty on the GPU
  if (exact) {
    ls.leaves.reserve(tree.leaves.size());
    for (const NTree::Leaf& leaf : tree.leaves) ls.leaves.push_back({leaf.first, leaf.count});
    ls.leafTriangles = tree.leafTriangles;
    ls.triangles = std::move(triangles);
  }

  // Bits: the OR of the shaft sets of the node's non-empty cells, 64 bits at a time.
  ls.bits.assign(tree.nodes.size() * words, 0u);
  std::atomic<std::uint32_t> next{0};
  std::atomic<std::uint64_t> setBits{0};
  auto work = [&] {
    std::vector<std::uint64_t> row(table.shaftWords());
    std::uint64_t set = 0;
    for (std::uint32_t i = next++; i < tree.nodes.size(); i = next++) {
      std::fill(row.begin(), row.end(), 0);
      for (std::uint32_t c = 0; c < cells; ++c) {
        if (tree.child(i, c) == NTree::kEmpty) continue;
        const auto shafts = table.cellShafts(c);
        for (std::size_t w = 0; w < row.size(); ++w) row[w] |= shafts[w];
      }
      for (std::uint64_t w : row) set += std::uint64_t(std::popcount(w));
      // Little-endian: 64-bit word w is 32-bit words 2w (bits 0..31) and 2w+1, as lsWordsPerNode counts.
      std::memcpy(ls.bits.data() + std::size_t(i) * words, row.data(), row.size() * sizeof(std::uint64_t));
    }
    setBits += set;
  };
  std::vector<std::thread> threads;
  for (unsigned w = 1; w < std::max(1u, std::thread::hardware_concurrency()); ++w) threads.emplace_back(work);
  work();
  for (std::thread& thread : threads) thread.join();

  LineSpaceStats& s = ls.stats;
  s.n = n;
  s.depth = depth;
  s.nodes = tree.nodes.size();
  s.leaves = tree.leaves.size();
  s.treeBytes = ls.tree.size() * sizeof(std::uint32_t);
  s.nodeBytes = ls.nodes.size() * sizeof(shared::LsNode);
  s.lineSpaceBytes = ls.bits.size() * sizeof(std::uint32_t);
  s.leafTriangleRefs = tree.leafTriangles.size();
  if (exact) {
    s.leafGroupBytes = tree.stats.nodesPerLevel[depth - 1] * cells * sizeof(std::uint32_t);
    s.leafBytes = ls.leaves.size() * sizeof(shared::LsLeaf);
    s.leafTriangleBytes = ls.leafTriangles.size() * sizeof(std::uint32_t);
    s.triangleBytes = ls.triangles.size() * sizeof(shared::BvhTriangle);
  }
  s.dynamicBvhBytes = dynamicBvhBytes;
  s.bytes = s.treeBytes + s.nodeBytes + s.lineSpaceBytes + s.leafBytes + s.leafTriangleBytes + s.triangleBytes +
            dynamicBvhBytes;
  s.treeMs = tree.stats.buildMs;
  s.tableMs = tableMs;
  s.lineSpaceMs = msSince(start);
  s.buildMs = s.treeMs + s.lineSpaceMs;
  s.filledFraction = double(setBits.load()) / (double(s.nodes) * shared::lsShaftCount(n));
  return ls;
}

LineSpace buildLineSpace(const Scene& scene, const LineSpaceSettings& settings, std::uint64_t maxPoolBytes,
                         MeshSet set, std::uint64_t dynamicBvhBytes) {
  NTreeBuilder::validate(settings.n, settings.depth);
  const NTree tree = NTreeBuilder(settings.n, settings.depth).build(scene, set);
  std::vector<shared::BvhTriangle> triangles;
  if (settings.shadows == LineSpaceSettings::Shadows::Exact) triangles = lineSpaceTriangles(scene, set);
  return buildLineSpace(tree, settings, maxPoolBytes, scene.name, dynamicBvhBytes, std::move(triangles));
}

}  // namespace penumbra
