// The line space (Keul et al. 2017) on the CPU: N-tree, shaft table and bits against exact geometry
// and Embree, and the budget. The GPU tracer and method `ls` are in test_linespace_tracer.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "core/scene_loader.h"
#include "raytrace/embree_tracer.h"
#include "raytrace/line_space.h"
#include "raytrace/ntree_builder.h"
#include "raytrace/shaft_table.h"
#include "render_fixture.h"

namespace penumbra {
namespace {

using test::expectValidationSilent;
using test::messageOf;
using test::validatedContext;

// ---- Settings and budget -------------------------------------------------------------------

TEST(LineSpace, RefusesBadBranchingAndDepth) {
  for (auto [n, d] : {std::pair{3u, 3u}, std::pair{11u, 3u}, std::pair{6u, 1u}, std::pair{6u, 5u}, std::pair{0u, 0u}}) {
    const std::string message = messageOf([&] { NTreeBuilder(n, d); });
    EXPECT_NE(message.find("N=" + std::to_string(n) + ", d=" + std::to_string(d)), std::string::npos) << message;
    EXPECT_NE(message.find("--linespace-n"), std::string::npos) << message;
  }
  EXPECT_THROW(ShaftTable::get(11), InputError);
  const Scene scene = loadScene("builtin:square");
  EXPECT_THROW(buildLineSpace(scene, {12, 3, 0}, 0), InputError);
  EXPECT_NO_THROW(NTreeBuilder(4, 2));
  EXPECT_NO_THROW(NTreeBuilder(10, 4));
}

TEST(LineSpace, RefusesParameterSetsOverTheBudgetOrTheBindingLimit) {
  const Scene scene = loadScene("builtin:courtyard:2");
  // The estimate is exact: the pools of an accepted build have exactly the refused size's parts.
  const LineSpace fits = buildLineSpace(scene, {8, 3, 0}, 0);
  const std::uint64_t bytes = fits.stats.bytes;
  const std::uint64_t groups = fits.stats.nodes - std::count_if(fits.nodes.begin(), fits.nodes.end(), [](const auto& n) {
                                 return n.children == LS_SKIP;
                               });
  EXPECT_EQ(lineSpaceSizes(8, fits.stats.nodes, groups).total(), bytes);

  EXPECT_THROW(buildLineSpace(scene, {8, 3, bytes - 1}, 0), InputError);
  const std::string budget = messageOf([&] { buildLineSpace(scene, {8, 3, bytes / 2}, 0); });
  std::printf("%s\n", budget.c_str());
  EXPECT_NE(budget.find("(N=8, d=3)"), std::string::npos) << budget;
  EXPECT_NE(budget.find(" MB"), std::string::npos) << budget;
  EXPECT_NE(budget.find("--linespace-budget"), std::string::npos) << budget;
  EXPECT_NO_THROW(buildLineSpace(scene, {8, 3, bytes}, 0));

  const std::string binding = messageOf([&] { buildLineSpace(scene, {8, 3, 0}, fits.stats.lineSpaceBytes - 1); });
  EXPECT_NE(binding.find("maxStorageBufferRange"), std::string::npos) << binding;
  EXPECT_NE(binding.find("(N=8, d=3)"), std::string::npos) << binding;
  EXPECT_GT(defaultLineSpaceBudget(), 0u);
}

// Exact mode adds leaf-cell children groups, leaf records, triangle lists and triangles, counted
// in the estimate and the budget; binary mode's pools stay as they were.
TEST(LineSpace, ExactModeAddsTheLeafPoolsToTheEstimateAndTheBudget) {
  const Scene scene = loadScene("builtin:courtyard:2");
  LineSpaceSettings settings{6, 3, 0};
  const LineSpace binary = buildLineSpace(scene, settings, 0);
  settings.shadows = LineSpaceSettings::Shadows::Exact;
  const LineSpace exact = buildLineSpace(scene, settings, 0);
  EXPECT_EQ(binary.stats.exactBytes(), 0u);
  EXPECT_TRUE(binary.leaves.empty() && binary.leafTriangles.empty() && binary.triangles.empty());
  EXPECT_EQ(binary.bits, exact.bits) << "the same bits";
  const std::uint64_t lastLevel = std::count_if(exact.nodes.begin(), exact.nodes.end(),
                                                [](const auto& n) { return n.level + 1 == 3; });
  ASSERT_GT(lastLevel, 0u);
  EXPECT_EQ(exact.tree.size(), binary.tree.size() + lastLevel * 216) << "one more group per second-to-last node";
  EXPECT_EQ(exact.stats.leafGroupBytes, lastLevel * 216 * sizeof(std::uint32_t));
  EXPECT_EQ(exact.triangles.size(), scene.triangleCount());
  EXPECT_EQ(exact.stats.bytes, binary.stats.bytes + exact.stats.exactBytes());
  EXPECT_EQ(lineSpaceSizes(6, exact.stats.nodes, exact.stats.nodes, exact.leaves.size(), exact.leafTriangles.size(),
                           exact.triangles.size())
                .total(),
            exact.stats.bytes);
  // Every leaf cell's entry names a leaf record whose triangles overlap the cell.
  std::uint64_t checked = 0;
  for (const shared::LsNode& node : exact.nodes) {
    ASSERT_NE(node.children, LS_SKIP);
    if (node.level + 1 != 3) continue;
    for (std::uint32_t c = 0; c < 216; ++c) {
      const std::uint32_t leaf = exact.tree[node.children + c];
      if (leaf == LS_SKIP) continue;
      ASSERT_LT(leaf, exact.leaves.size());
      const double cell = double(node.size) / 6.0;
      const glm::dvec3 lo = glm::dvec3(node.position) + glm::dvec3(c % 6, (c / 6) % 6, c / 36) * cell;
      const shared::LsLeaf record = exact.leaves[leaf];
      ASSERT_GT(record.count, 0u);
      for (std::uint32_t i = record.first; i < record.first + record.count; ++i) {
        const shared::BvhTriangle& t = exact.triangles[exact.leafTriangles[i]];
        EXPECT_EQ(t.id, exact.leafTriangles[i]) << "all meshes static: ids are the list's indices";
        const glm::dvec3 slack(1e-4 * cell);
        EXPECT_TRUE(triangleOverlapsBox(glm::dvec3(t.v0), glm::dvec3(t.v1), glm::dvec3(t.v2), lo - slack,
                                        lo + glm::dvec3(cell) + slack));
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, exact.leafTriangles.size()) << "every list entry is reached from a leaf cell";
  // The budget counts the exact pools: one byte short is refused, naming the way back to binary.
  settings.budgetBytes = exact.stats.bytes - 1;
  const std::string message = messageOf([&] { buildLineSpace(scene, settings, 0); });
  EXPECT_NE(message.find("exact shadows"), std::string::npos) << message;
  EXPECT_NE(message.find("--ls-shadows binary"), std::string::npos) << message;
  settings.budgetBytes = exact.stats.bytes;
  EXPECT_NO_THROW(buildLineSpace(scene, settings, 0));
}

// Triangle ids are scene-order indices even when the line space holds only the static meshes.
TEST(LineSpace, ExactModeTrianglesKeepSceneOrderIds) {
  const Scene scene = loadScene("builtin:courtyard-moving:1");
  const auto all = lineSpaceTriangles(scene, MeshSet::All);
  const auto statics = lineSpaceTriangles(scene, MeshSet::Static);
  ASSERT_LT(statics.size(), all.size()) << "the drone moves";
  for (const shared::BvhTriangle& t : statics) {
    ASSERT_LT(t.id, all.size());
    EXPECT_EQ(glm::vec3(all[t.id].v0), glm::vec3(t.v0));
    EXPECT_EQ(glm::vec3(all[t.id].v2), glm::vec3(t.v2));
  }
}

// ---- N-tree --------------------------------------------------------------------------------

// The leaf cell (or empty cell) holding point p: descends by coordinates. Returns the leaf index
// or -1 when a cell on the way is empty.
long leafAt(const NTree& tree, const glm::dvec3& p) {
  std::uint32_t node = 0;
  for (;;) {
    const NTree::Node& nd = tree.nodes[node];
    const double cell = double(nd.size) / tree.n;
    std::uint32_t ijk[3];
    for (int k = 0; k < 3; ++k) {
      ijk[k] = std::uint32_t(std::clamp(int(std::floor((p[k] - nd.lo[k]) / cell)), 0, int(tree.n) - 1));
    }
    const std::uint32_t entry = tree.child(node, shared::lsCellIndex(ijk[0], ijk[1], ijk[2], tree.n));
    if (entry == NTree::kEmpty) return -1;
    if (entry & NTree::kLeafBit) return long(entry & ~NTree::kLeafBit);
    node = entry;
  }
}

TEST(NTree, EveryPointOfEveryTriangleLiesInALeafThatListsIt) {
  const Scene scene = loadScene("builtin:courtyard:2");
  std::vector<std::array<glm::dvec3, 3>> tris;
  for (const Mesh& m : scene.meshes) {
    for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3) {
      tris.push_back({glm::dvec3(m.positions[m.indices[i]]), glm::dvec3(m.positions[m.indices[i + 1]]),
                      glm::dvec3(m.positions[m.indices[i + 2]])});
    }
  }
  for (auto [n, d] : {std::pair{4u, 3u}, std::pair{7u, 2u}}) {
    const NTree tree = NTreeBuilder(n, d).build(scene);
    // Structure: children are the parent's cells, one level down; counts match the stats.
    for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
      const NTree::Node& node = tree.nodes[i];
      for (std::uint32_t c = 0; c < n * n * n; ++c) {
        const std::uint32_t entry = tree.child(std::uint32_t(i), c);
        if (entry == NTree::kEmpty) continue;
        if (entry & NTree::kLeafBit) {
          ASSERT_EQ(node.level + 1, d) << "leaves only at level d";
          continue;
        }
        ASSERT_GT(entry, i) << "parents come before children";
        EXPECT_EQ(tree.nodes[entry].level, node.level + 1);
        EXPECT_FLOAT_EQ(tree.nodes[entry].size, node.size / float(n));
      }
    }
    EXPECT_EQ(tree.stats.nodes, tree.nodes.size());
    EXPECT_EQ(tree.stats.nodesPerLevel.front(), 1u);
    // Conservative: points sampled on every triangle fall in a leaf that lists the triangle, and
    // every listed triangle overlaps its leaf (up to the builder's slack).
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (std::uint32_t t = 0; t < tris.size(); ++t) {
      for (int s = 0; s < 8; ++s) {
        double a = unit(rng), b = unit(rng);
        if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
        const glm::dvec3 p = tris[t][0] + a * (tris[t][1] - tris[t][0]) + b * (tris[t][2] - tris[t][0]);
        const long leaf = leafAt(tree, p);
        ASSERT_GE(leaf, 0) << "triangle " << t << " point in an empty cell";
        const NTree::Leaf& l = tree.leaves[std::size_t(leaf)];
        const auto begin = tree.leafTriangles.begin() + l.first;
        ASSERT_TRUE(std::find(begin, begin + l.count, t) != begin + l.count) << "triangle " << t;
      }
    }
    std::printf("N-tree (%u,%u) on courtyard:2 (%zu triangles): %zu nodes, %zu leaves, %zu refs, %.1f ms\n", n, d,
                tris.size(), tree.nodes.size(), tree.leaves.size(), tree.leafTriangles.size(), tree.stats.buildMs);
  }
}

TEST(NTree, TriangleBoxOverlapIsExact) {
  const glm::dvec3 lo(0.0), hi(1.0);
  EXPECT_TRUE(triangleOverlapsBox({0.5, 0.5, 0.5}, {3, 0.5, 0.5}, {0.5, 3, 0.5}, lo, hi));  // a vertex inside
  EXPECT_TRUE(triangleOverlapsBox({-1, -1, 0.5}, {3, -1, 0.5}, {-1, 3, 0.5}, lo, hi));     // slices through
  EXPECT_TRUE(triangleOverlapsBox({1, 0, 0}, {2, 0, 0}, {1, 1, 0}, lo, hi));                // touches a face
  // The triangle's box overlaps the cube but the triangle passes beside a corner (edge-cross axis).
  EXPECT_FALSE(triangleOverlapsBox({1.2, -0.5, 0.5}, {1.2, 1.5, 0.5}, {2.5, 0.5, 0.5}, lo, hi));
  // The plane x + y = c passes the corner (1, 1, z) beside it for c = 2.1, cuts it for c = 1.9.
  EXPECT_FALSE(triangleOverlapsBox({2.1, 0.0, -1.0}, {-1.0, 3.1, -1.0}, {-1.0, 3.1, 3.0}, lo, hi));
  EXPECT_TRUE(triangleOverlapsBox({1.9, 0.0, -1.0}, {-1.0, 2.9, -1.0}, {-1.0, 2.9, 3.0}, lo, hi));
}

// ---- Shaft table ---------------------------------------------------------------------------

TEST(ShaftTable, NumberingIsABijectionAndSymmetric) {
  for (std::uint32_t n : {4u, 7u}) {
    std::vector<int> seen(shared::lsShaftCount(n), 0);
    for (std::uint32_t fa = 0; fa < 6; ++fa) {
      for (std::uint32_t fb = 0; fb < 6; ++fb) {
        for (std::uint32_t pa = 0; pa < n * n; ++pa) {
          for (std::uint32_t pb = 0; pb < n * n; ++pb) {
            const std::uint32_t s = shared::lsShaft(fa, pa, fb, pb, n);
            if (fa == fb) {
              ASSERT_EQ(s, LS_NO_SHAFT);
              continue;
            }
            ASSERT_EQ(s, shared::lsShaft(fb, pb, fa, pa, n));
            ASSERT_LT(s, shared::lsShaftCount(n));
            if (fa < fb) {
              ++seen[s];
              ShaftTable::Patch a, b;
              ShaftTable::decode(s, n, a, b);
              ASSERT_TRUE(a.face == fa && b.face == fb);
              ASSERT_EQ(shared::lsPatch(glm::vec3(0.5 * (a.lo + a.hi)), fa, n), pa);
              ASSERT_EQ(shared::lsPatch(glm::vec3(0.5 * (b.lo + b.hi)), fb, n), pb);
            }
          }
        }
      }
    }
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int c) { return c == 1; })) << "N=" << n;
  }
}

// Whether segment p..q crosses the interior of cell (i, j, k) of the unit cube's N^3 grid over a
// length above `eps` (exact slab test in double precision).
bool crossesCell(const glm::dvec3& p, const glm::dvec3& q, std::uint32_t n, const std::uint32_t ijk[3], double eps) {
  double t0 = 0.0, t1 = 1.0;
  const glm::dvec3 d = q - p;
  for (int k = 0; k < 3; ++k) {
    const double lo = double(ijk[k]) / n, hi = double(ijk[k] + 1) / n;
    if (d[k] == 0.0) {
      if (p[k] <= lo || p[k] >= hi) return false;
      continue;
    }
    double a = (lo - p[k]) / d[k], b = (hi - p[k]) / d[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  return (t1 - t0) * glm::length(d) > eps;
}

TEST(ShaftTable, EveryCellARayInTheShaftCrossesIsInItsSet) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (std::uint32_t n = LS_MIN_N; n <= LS_MAX_N; ++n) {
    const ShaftTable& table = ShaftTable::get(n);
    ASSERT_EQ(table.shaftCount(), shared::lsShaftCount(n));
    std::uniform_int_distribution<std::uint32_t> pick(0, table.shaftCount() - 1);
    std::uint64_t crossings = 0, cellsInSets = 0;
    const int shafts = 1500, raysPerShaft = 12;
    for (int s = 0; s < shafts; ++s) {
      const std::uint32_t shaft = pick(rng);
      ShaftTable::Patch a, b;
      ShaftTable::decode(shaft, n, a, b);
      cellsInSets += table.cellsOf(shaft);
      for (int r = 0; r < raysPerShaft; ++r) {
        glm::dvec3 p, q;
        for (int k = 0; k < 3; ++k) {
          p[k] = a.lo[k] + unit(rng) * (a.hi[k] - a.lo[k]);
          q[k] = b.lo[k] + unit(rng) * (b.hi[k] - b.lo[k]);
        }
        for (std::uint32_t c = 0; c < table.cellCount(); ++c) {
          const std::uint32_t ijk[3] = {c % n, (c / n) % n, c / (n * n)};
          if (!crossesCell(p, q, n, ijk, 1e-9)) continue;
          ++crossings;
          ASSERT_TRUE(table.contains(shaft, c)) << "N=" << n << " shaft " << shaft << " misses cell " << c;
        }
      }
    }
    // Not trivially conservative: a shaft holds a small part of the grid.
    const double fill = double(cellsInSets) / (double(shafts) * table.cellCount());
    std::printf("N=%u: %llu crossings checked, shafts hold %.1f%% of the cells on average, table %.1f ms, %.1f MB\n", n,
                (unsigned long long)crossings, 100.0 * fill, table.buildMs(), double(table.bytes()) / 1e6);
    EXPECT_LT(fill, 0.5) << "N=" << n;
    EXPECT_GT(crossings, std::uint64_t(shafts) * raysPerShaft * n);
  }
  // A straight shaft between facing patches holds exactly its row of cells: neighbours it only
  // touches stay out.
  const std::uint32_t n = 6, row = shared::lsPatch(glm::vec3(0.0f, 0.3f, 0.6f), 0, n);
  const std::uint32_t straight = shared::lsShaft(0, row, 1, row, n);
  EXPECT_EQ(ShaftTable::get(n).cellsOf(straight), n);
}

// ---- Line space vs Embree ------------------------------------------------------------------

TEST(LineSpace, EverySegmentEmbreeFindsBlockedHasItsShaftBitSet) {
  const Scene scene = loadScene("builtin:courtyard:2");
  const EmbreeTracer embree(scene);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (auto [n, d] : {std::pair{5u, 3u}, std::pair{8u, 2u}}) {
    const NTree tree = NTreeBuilder(n, d).build(scene);
    const LineSpace ls = buildLineSpace(tree, {n, d, 0}, 0, scene.name);
    std::uint64_t blocked = 0, clear = 0, setBits = 0;
    std::uniform_int_distribution<std::uint32_t> pickNode(0, std::uint32_t(ls.nodes.size()) - 1);
    std::uniform_int_distribution<std::uint32_t> pickShaft(0, shared::lsShaftCount(n) - 1);
    for (int trial = 0; trial < 1500; ++trial) {
      const std::uint32_t node = trial < 30 ? 0u : pickNode(rng);
      const std::uint32_t shaft = pickShaft(rng);
      const shared::LsNode& nd = ls.nodes[node];
      ShaftTable::Patch a, b;
      ShaftTable::decode(shaft, n, a, b);
      auto world = [&](const ShaftTable::Patch& patch) {
        glm::dvec3 u;
        for (int k = 0; k < 3; ++k) u[k] = patch.lo[k] + unit(rng) * (patch.hi[k] - patch.lo[k]);
        return glm::vec3(glm::dvec3(nd.position) + u * double(nd.size));
      };
      // Segments from 16 points of patch A to one point of patch B (a point light there).
      const glm::vec3 q = world(b);
      std::vector<shared::ShadingPoint> points;
      for (int r = 0; r < 16; ++r) {
        const glm::vec3 p = world(a);
        points.push_back({p, 0u, glm::normalize(q - p), 1u, 0.0f});
      }
      shared::GpuLight light{};
      light.position = glm::vec4(q, 1.0f);
      light.type = LIGHT_POINT;
      light.cosHalfAngle = -1.0f;
      std::vector<float> visibility(points.size());
      embree.traceShadows(points, light, visibility);
      const bool bit = ls.bit(node, shaft);
      setBits += bit;
      for (float v : visibility) {
        if (v == 0.0f) {
          ++blocked;
          ASSERT_TRUE(bit) << "(" << n << "," << d << ") node " << node << " shaft " << shaft
                           << ": Embree finds a blocker, the line space says empty";
        } else {
          ++clear;
        }
      }
    }
    std::printf("(%u,%u): %zu nodes, %.1f%% bits set; %llu blocked segments (all with the bit set), %llu clear\n", n, d,
                ls.nodes.size(), 100.0 * ls.stats.filledFraction, (unsigned long long)blocked,
                (unsigned long long)clear);
    EXPECT_GT(blocked, 500u) << "the check needs blocked segments to mean something";
    EXPECT_GT(clear, 500u);
    EXPECT_LT(setBits, 1500u) << "not every bit is set";
    EXPECT_GT(ls.stats.filledFraction, 0.0);
    EXPECT_LT(ls.stats.filledFraction, 1.0);
  }
}

}  // namespace
}  // namespace penumbra
