// The candidate line space (Keul et al. 2018, 3): shaft numbering, the sparse layout against the
// dense one, the builder's candidates against a brute-force search, placement on N-trees and BVHs,
// and the budget. Its lookup and traversal on the GPU: test_candidate_tracer.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "core/scene_loader.h"
#include "core/units.h"
#include "raytrace/candidate_line_space.h"
#include "render_fixture.h"
#include "shared/linespace.h"

namespace penumbra {
namespace {

using test::messageOf;

// Scene-order triangles of a scene, in double.
std::vector<std::array<glm::dvec3, 3>> triangles(const Scene& scene) {
  std::vector<std::array<glm::dvec3, 3>> out;
  for (const Mesh& m : scene.meshes)
    for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3)
      out.push_back({glm::dvec3(m.positions[m.indices[i]]), glm::dvec3(m.positions[m.indices[i + 1]]),
                     glm::dvec3(m.positions[m.indices[i + 2]])});
  return out;
}

// Segment parameter in [0, 1] where p + s * d meets the triangle (Moeller-Trumbore, double), or -1.
double segmentHit(const glm::dvec3& p, const glm::dvec3& d, const std::array<glm::dvec3, 3>& t) {
  const glm::dvec3 e1 = t[1] - t[0], e2 = t[2] - t[0];
  const glm::dvec3 q = glm::cross(d, e2);
  const double det = glm::dot(e1, q);
  if (std::abs(det) < 1e-300) return -1.0;
  const glm::dvec3 s = p - t[0];
  const double u = glm::dot(s, q) / det;
  const glm::dvec3 r = glm::cross(s, e1);
  const double v = glm::dot(d, r) / det;
  const double w = glm::dot(e2, r) / det;
  const double eps = 1e-7;
  if (u < -eps || v < -eps || u + v > 1.0 + eps || w < -eps || w > 1.0 + eps) return -1.0;
  return w;
}

TEST(CandidateShafts, NumberingIsABijectionOverDirectedPairs) {
  for (std::uint32_t n : {4u, 5u}) {
    std::vector<int> seen(shared::csShaftCount(n), 0);
    for (std::uint32_t fi = 0; fi < 6; ++fi)
      for (std::uint32_t fo = 0; fo < 6; ++fo) {
        if (fi == fo) continue;
        for (std::uint32_t pi = 0; pi < n * n; ++pi)
          for (std::uint32_t po = 0; po < n * n; ++po) {
            const std::uint32_t s = shared::csShaft(fi, pi, fo, po, n);
            ASSERT_LT(s, shared::csShaftCount(n));
            ++seen[s];
          }
      }
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int c) { return c == 1; })) << "N=" << n;
    EXPECT_EQ(shared::csWordsPerBox(n) * 32u >= shared::csShaftCount(n), true);
  }
}

TEST(CandidateSparseLayout, RandomTablesRoundTrip) {
  std::mt19937 rng(2018);
  for (std::uint32_t n : {4u, 5u}) {  // 5: the words do not end on a box boundary
    const std::size_t shafts = shared::csShaftCount(n), boxes = 7;
    std::vector<std::uint32_t> dense(boxes * shafts);
    for (std::size_t b = 0; b < boxes; ++b) {
      // Fill rates from empty to full, so words of all popcounts occur.
      const double fill = double(b) / double(boxes - 1);
      std::bernoulli_distribution filled(fill);
      for (std::size_t s = 0; s < shafts; ++s) dense[b * shafts + s] = filled(rng) ? std::uint32_t(rng() % 1000000) : CS_NONE;
    }
    CandidateLineSpace ls;
    packCandidates(n, dense, ls);
    const std::size_t filledCount = std::count_if(dense.begin(), dense.end(), [](std::uint32_t c) { return c != CS_NONE; });
    EXPECT_EQ(ls.candidates.size(), filledCount);
    EXPECT_EQ(ls.stats.filled, filledCount);
    EXPECT_EQ(ls.bits.size(), boxes * shared::csWordsPerBox(n));
    for (std::uint32_t b = 0; b < boxes; ++b)
      for (std::uint32_t s = 0; s < shafts; ++s)
        ASSERT_EQ(ls.lookup(b, s), dense[b * shafts + s]) << "N=" << n << " box " << b << " shaft " << s;
    EXPECT_LT(ls.stats.sparseBytes, ls.stats.denseBytes);  // mean fill 50%
  }
}

TEST(CandidateSparseLayout, RealBuildMatchesDenseAndBruteForce) {
  const Scene scene = loadScene("builtin:courtyard:2");
  const NTree tree = NTreeBuilder(4, 3).build(scene);
  const std::vector<CandidateBox> boxes = boxesAtDepth(tree, 1, 8);
  ASSERT_FALSE(boxes.empty());
  CandidateSettings settings;
  settings.n = 4;
  settings.keepDense = true;
  const CandidateLineSpace ls = buildCandidateLineSpace(scene, boxes, settings, 0);
  const CandidateStats& s = ls.stats;
  std::printf("courtyard:2 N-tree(4,3) D=1 T=8, N=4: %llu boxes, %llu shafts, filled %.3f, sparse %.2f MB vs dense "
              "%.2f MB, %llu rays, build %.1f ms (Embree scene %.1f ms)\n",
              (unsigned long long)s.boxes, (unsigned long long)s.shafts, s.filledFraction, s.sparseBytes / 1e6,
              s.denseBytes / 1e6, (unsigned long long)s.raysCast, s.buildMs, s.embreeMs);
  EXPECT_GT(s.filledFraction, 0.0);
  EXPECT_LT(s.filledFraction, 1.0);
  const std::uint32_t shafts = shared::csShaftCount(4);
  for (std::uint32_t b = 0; b < boxes.size(); ++b)
    for (std::uint32_t sh = 0; sh < shafts; ++sh) ASSERT_EQ(ls.lookup(b, sh), ls.lookupDense(b, sh)) << b << " " << sh;

  // Sampled shafts against a brute-force nearest hit of the centroid segment.
  const auto tris = triangles(scene);
  std::mt19937 rng(5);
  int checked = 0, filled = 0;
  for (int k = 0; k < 300; ++k) {
    const std::uint32_t b = rng() % boxes.size();
    const std::uint32_t fi = rng() % 6, fo = (fi + 1 + rng() % 5) % 6, pi = rng() % 16, po = rng() % 16;
    const glm::dvec3 a(candidatePatchCentroid(boxes[b].lo, boxes[b].hi, fi, pi, 4));
    const glm::dvec3 d = glm::dvec3(candidatePatchCentroid(boxes[b].lo, boxes[b].hi, fo, po, 4)) - a;
    double best = 2.0;
    for (const auto& t : tris) {
      const double w = segmentHit(a, d, t);
      if (w >= 0.0) best = std::min(best, w);
    }
    const std::uint32_t c = ls.lookup(b, shared::csShaft(fi, pi, fo, po, 4));
    ++checked;
    if (best > 1.0) {
      EXPECT_EQ(c, CS_NONE) << "box " << b << ": Embree found triangle " << c << " where none is";
      continue;
    }
    ++filled;
    ASSERT_NE(c, CS_NONE) << "box " << b << ": missed a hit at " << best;
    ASSERT_LT(c, tris.size());
    const double w = segmentHit(a, d, tris[c]);
    EXPECT_GE(w, 0.0) << "candidate " << c << " is not on the segment";
    EXPECT_NEAR(w, best, 1e-4) << "candidate " << c << " is not the nearest";
  }
  std::printf("brute force: %d shafts checked, %d filled\n", checked, filled);
  EXPECT_GT(filled, 10);
}

TEST(CandidatePlacement, NTreeDepthAndTriangleRule) {
  const Scene scene = loadScene("builtin:courtyard:2");
  const NTree tree = NTreeBuilder(4, 3).build(scene);
  const auto tris = triangles(scene);
  // Distinct triangles under a node, brute force.
  std::function<void(std::uint32_t, std::set<std::uint32_t>&)> under = [&](std::uint32_t node, std::set<std::uint32_t>& out) {
    for (std::uint32_t c = 0; c < 64; ++c) {
      const std::uint32_t e = tree.child(node, c);
      if (e == NTree::kEmpty) continue;
      if (e & NTree::kLeafBit) {
        const NTree::Leaf& l = tree.leaves[e & ~NTree::kLeafBit];
        out.insert(tree.leafTriangles.begin() + l.first, tree.leafTriangles.begin() + l.first + l.count);
      } else {
        under(e, out);
      }
    }
  };
  for (std::uint32_t t : {0u, 8u, 64u}) {
    const std::vector<CandidateBox> boxes = boxesAtDepth(tree, 2, t);
    std::set<std::uint32_t> chosen;
    for (const CandidateBox& b : boxes) {
      chosen.insert(b.node);
      const NTree::Node& nd = tree.nodes[b.node];
      EXPECT_EQ(b.lo, nd.lo);
      EXPECT_EQ(b.hi, nd.lo + glm::vec3(nd.size));
      if (nd.level != 2) {
        std::set<std::uint32_t> ts;
        under(b.node, ts);
        EXPECT_LT(ts.size(), t) << "node " << b.node << " at level " << nd.level;
      }
    }
    // Walk the tree: every path from the root to a level-2 node meets exactly one chosen node, and
    // no unchosen node above level 2 has fewer than T triangles.
    std::size_t shallow = 0;
    std::function<void(std::uint32_t, bool)> walk = [&](std::uint32_t node, bool covered) {
      const bool here = chosen.count(node) > 0;
      EXPECT_FALSE(covered && here) << "node " << node << " chosen below a chosen node";
      if (here && tree.nodes[node].level < 2) ++shallow;
      if (!here && !covered && tree.nodes[node].level < 2 && t > 0) {
        std::set<std::uint32_t> ts;
        under(node, ts);
        EXPECT_GE(ts.size(), t) << "node " << node << " should have been chosen";
      }
      if (tree.nodes[node].level == 2) {
        EXPECT_TRUE(covered || here) << "level-2 node " << node << " not covered";
        return;
      }
      for (std::uint32_t c = 0; c < 64; ++c) {
        const std::uint32_t e = tree.child(node, c);
        if (e != NTree::kEmpty && !(e & NTree::kLeafBit)) walk(e, covered || here);
      }
    };
    walk(0, false);
    std::printf("N-tree(4,3) D=2 T=%u: %zu boxes, %zu of them above level 2\n", t, boxes.size(), shallow);
    if (t == 0) {
      EXPECT_EQ(shallow, 0u);
    }
  }
  EXPECT_THROW(boxesAtDepth(tree, 3, 8), InputError);
}

TEST(CandidatePlacement, BvhNodesAtDepth) {
  const Scene scene = loadScene("builtin:courtyard:2");
  const Bvh bvh = BvhBuilder().build(scene);
  for (std::uint32_t d : {0u, 3u, 6u}) {
    const BvhLineSpaceNodes placed = bvhNodesAtDepth(bvh, d);
    ASSERT_EQ(placed.nodeMap.size(), bvh.nodes.size());
    // Reference: inner nodes at depth d by recursion, with the slot boxes that lead to them.
    std::size_t expected = 0;
    std::function<void(std::uint32_t, std::uint32_t, glm::vec3, glm::vec3)> walk = [&](std::uint32_t node, std::uint32_t depth,
                                                                                       glm::vec3 lo, glm::vec3 hi) {
      if (depth == d) {
        ++expected;
        const std::uint32_t ls = placed.nodeMap[node];
        ASSERT_NE(ls, CS_NONE) << "node " << node;
        EXPECT_EQ(placed.boxes[ls].node, node);
        if (depth > 0) {
          EXPECT_EQ(placed.boxes[ls].lo, lo);
          EXPECT_EQ(placed.boxes[ls].hi, hi);
        }
        return;
      }
      EXPECT_EQ(placed.nodeMap[node], CS_NONE);
      for (const shared::BvhChild& c : bvh.nodes[node].child)
        if (c.count == 0 && c.index != 0) walk(c.index, depth + 1, c.lo, c.hi);
    };
    walk(0, 0, {}, {});
    EXPECT_EQ(placed.boxes.size(), expected) << "depth " << d;
    EXPECT_GT(expected, 0u);
    std::printf("BVH depth %u: %zu line-space nodes of %zu\n", d, expected, bvh.nodes.size());
  }
  // The root's box holds both children's.
  const BvhLineSpaceNodes root = bvhNodesAtDepth(bvh, 0);
  for (const shared::BvhChild& c : bvh.nodes[0].child) {
    EXPECT_TRUE(glm::all(glm::lessThanEqual(root.boxes[0].lo, c.lo)));
    EXPECT_TRUE(glm::all(glm::greaterThanEqual(root.boxes[0].hi, c.hi)));
  }
}

// Refused from the worst-case estimate alone, before anything is built: the same refusal for a
// scene with no triangles at all (building would need them), naming the estimate's size.
TEST(CandidateBudget, RefusedBeforeAnyWork) {
  const Scene scene = loadScene("builtin:courtyard:2");
  Scene empty;
  empty.name = "empty";
  std::vector<CandidateBox> many(200000, CandidateBox{glm::vec3(0.0f), glm::vec3(1.0f), 0});
  CandidateSettings settings;
  settings.n = 10;
  settings.budgetBytes = std::uint64_t(1) << 30;
  const std::string budget = messageOf([&] { buildCandidateLineSpace(empty, many, settings, 0); });
  std::printf("%s\n", budget.c_str());
  EXPECT_NE(budget.find("N=10"), std::string::npos) << budget;
  EXPECT_NE(budget.find("200000 boxes"), std::string::npos) << budget;
  EXPECT_NE(budget.find("may need " + megabytes(candidateWorstCaseSizes(10, many.size()).total())), std::string::npos) << budget;
  EXPECT_NE(budget.find("budget"), std::string::npos) << budget;
  EXPECT_NE(budget.find("lower N"), std::string::npos) << budget;
  EXPECT_EQ(messageOf([&] { buildCandidateLineSpace(scene, many, settings, 0); }),
            std::string(budget).replace(budget.find("'empty'"), 7, "'" + scene.name + "'"))
      << "the scene's triangles play no part in the refusal";

  // The estimate's boundary: exactly the worst case fits, a byte less does not.
  const std::vector<CandidateBox> two(2, CandidateBox{glm::vec3(-1.0f), glm::vec3(1.0f), 0});
  settings.n = 4;
  settings.budgetBytes = candidateWorstCaseSizes(4, 2).total();
  EXPECT_NO_THROW(buildCandidateLineSpace(scene, two, settings, 0));
  settings.budgetBytes -= 1;
  EXPECT_THROW(buildCandidateLineSpace(scene, two, settings, 0), InputError);

  settings.budgetBytes = 0;
  // Bits, offsets and boxes are bound (one binding's range); the candidates are read through an
  // address (one buffer's size): each limit is checked against its own.
  const CandidateSizes worst = candidateWorstCaseSizes(4, 2);
  const std::string binding = messageOf([&] { buildCandidateLineSpace(scene, two, settings, worst.bitBytes - 1); });
  EXPECT_NE(binding.find("maxStorageBufferRange"), std::string::npos) << binding;
  EXPECT_NE(binding.find("N=4"), std::string::npos) << binding;
  EXPECT_NO_THROW(buildCandidateLineSpace(scene, two, settings, worst.bitBytes)) << "the candidates are not bound";
  settings.maxCandidateBytes = worst.candidateBytes - 1;
  const std::string buffer = messageOf([&] { buildCandidateLineSpace(scene, two, settings, 0); });
  EXPECT_NE(buffer.find("maxBufferSize"), std::string::npos) << buffer;
  settings.maxCandidateBytes = 0;
  settings.n = 11;
  EXPECT_NE(messageOf([&] { buildCandidateLineSpace(scene, two, settings, 0); }).find("N=11"), std::string::npos);
}

}  // namespace
}  // namespace penumbra
