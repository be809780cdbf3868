// The candidate line space (Keul et al. 2018, 3): shaft numbering, the sparse layout against the
// dense one, the builder's candidates against a brute-force search, placement on N-trees and BVHs,
// and the budget.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "core/mesh_builder.h"
#include "core/scene_loader.h"
#include "core/units.h"
#include "raytrace/bvh_tracer.h"
#include "raytrace/candidate_line_space.h"
#include "raytrace/candidate_tracer.h"
#include "raytrace/scene_triangles.h"
#include "bounds.h"
#include "render_fixture.h"
#include "shared/linespace.h"

namespace penumbra {
namespace {

using test::expectValidationSilent;
using test::messageOf;
using test::validatedContext;

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


// ---- GPU lookup and traversal ------------------------------------------------------------------

// Largest fraction of rays whose BVH+LS hit differs from the exact one by more than 1% of the
// scene radius (or hits where the other misses), from the measurement printed by the test.
// Measured on courtyard:2, N = 4, 20000 rays: D = 6 0.0285, D = 10 0.0018 (the bounds leave about
// twice that).
constexpr double kShallowBound = 0.06;
constexpr double kDeepBound = 0.005;

// Whether a point of the box surface lies within a small margin of a patch border (where the
// GPU's float entry point may fall in the neighbouring patch).
bool nearPatchBorder(const glm::dvec3& p, const glm::vec3& lo, const glm::vec3& hi, std::uint32_t n) {
  for (int k = 0; k < 3; ++k) {
    const double x = (p[k] - lo[k]) / (hi[k] - lo[k]) * n;
    if (std::abs(x - std::round(x)) < 1e-3 && x > 1e-3 && x < n - 1e-3) return true;
  }
  return false;
}

// The face of the unit-less box [lo, hi] that point p (on its surface) lies on, and its patch.
void facePatch(const glm::dvec3& p, const glm::vec3& lo, const glm::vec3& hi, std::uint32_t n, std::uint32_t& face,
               std::uint32_t& patch) {
  double best = 1e300;
  for (std::uint32_t f = 0; f < 6; ++f) {
    const double plane = (f % 2) ? hi[f / 2] : lo[f / 2];
    const double d = std::abs(p[f / 2] - plane);
    if (d < best) best = d, face = f;
  }
  const glm::vec3 local = glm::vec3((p - glm::dvec3(lo)) / glm::dvec3(hi - lo));
  patch = shared::lsPatch(local, face, n);
}

// The corners of patch `patch` of face `face`.
std::array<glm::dvec3, 4> patchCorners(const glm::vec3& lo, const glm::vec3& hi, std::uint32_t face, std::uint32_t patch,
                                       std::uint32_t n) {
  const std::uint32_t a = face / 2, u = (a + 1) % 3, v = (a + 2) % 3;
  std::array<glm::dvec3, 4> out;
  for (int k = 0; k < 4; ++k) {
    glm::dvec3 p;
    p[a] = (face % 2) ? hi[a] : lo[a];
    p[u] = lo[u] + (double(patch % n) + (k & 1)) / n * (hi[u] - lo[u]);
    p[v] = lo[v] + (double(patch / n) + (k >> 1)) / n * (hi[v] - lo[v]);
    out[k] = p;
  }
  return out;
}

TEST(CandidateGpu, PlaneThroughABoxIsAnsweredExactly) {
  // A tilted quad far larger than the box [-1, 1]^3 through its centre, and a far-away box so the
  // scene has more than one mesh.
  Scene scene;
  scene.name = "plane through a box";
  const glm::dvec3 normal = glm::normalize(glm::dvec3(0.3, 1.0, 0.2));
  const glm::dvec3 centre(0.05, 0.1, -0.08);
  const glm::dvec3 t1 = glm::normalize(glm::cross(normal, glm::dvec3(0, 0, 1)));
  const glm::dvec3 t2 = glm::cross(normal, t1);
  Mesh quad;
  quad.name = "quad";
  const auto at = [&](double a, double b) { return glm::vec3(centre + 10.0 * (a * t1 + b * t2)); };
  mesh::addQuad(quad, at(-1, -1), at(1, -1), at(1, 1), at(-1, 1), glm::vec3(normal));
  Mesh other;
  other.name = "other";
  mesh::addBox(other, glm::vec3(20, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1), false);
  scene.meshes = {quad, other};
  cleanScene(scene, scene.name);
  const std::uint32_t quadTriangles = std::uint32_t(scene.meshes[0].triangleCount());

  const std::uint32_t n = 5;
  const glm::vec3 lo(-1.0f), hi(1.0f);
  const CandidateBox box{lo, hi, 0};
  CandidateTracerSettings settings;
  settings.n = n;
  CandidateTracer tracer(validatedContext(), scene, std::span<const CandidateBox>(&box, 1), settings);

  // Rays between random points on two different faces, half starting outside, half inside.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto surfacePoint = [&](std::uint32_t face) {
    glm::dvec3 p(unit(rng) * 2 - 1, unit(rng) * 2 - 1, unit(rng) * 2 - 1);
    p[face / 2] = (face % 2) ? 1.0 : -1.0;
    return p;
  };
  std::vector<shared::RayQuery> rays;
  std::vector<glm::dvec3> entries, exits;
  for (int i = 0; i < 20000; ++i) {
    const std::uint32_t fa = rng() % 6, fb = (fa + 1 + rng() % 5) % 6;
    const glm::dvec3 a = surfacePoint(fa), b = surfacePoint(fb);
    const glm::dvec3 d = b - a;
    const double start = (i % 2) ? -0.5 : 0.8 * unit(rng);  // inside the box: the line's entry still counts
    rays.push_back({glm::vec3(a + start * d), 0.0f, glm::vec3(d), 1e30f});
    entries.push_back(a);
    exits.push_back(b);
  }
  const auto hits = tracer.traceBox(rays, 0);
  expectValidationSilent();
  ASSERT_EQ(hits.size(), rays.size());

  int crossing = 0, apart = 0, mixed = 0, wrong = 0;
  double worst = 0.0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (nearPatchBorder(entries[i], lo, hi, n) || nearPatchBorder(exits[i], lo, hi, n)) {
      ++mixed;
      continue;
    }
    std::uint32_t fa, pa, fb, pb;
    facePatch(entries[i], lo, hi, n, fa, pa);
    facePatch(exits[i], lo, hi, n, fb, pb);
    // Signed side of the plane of every corner of both patches.
    int above = 0, below = 0, aboveIn = 0;
    for (const auto& c : patchCorners(lo, hi, fa, pa, n)) {
      const double s = glm::dot(c - centre, normal);
      (s > 0 ? above : below)++;
      if (s > 0) ++aboveIn;
    }
    for (const auto& c : patchCorners(lo, hi, fb, pb, n)) (glm::dot(c - centre, normal) > 0 ? above : below)++;
    const glm::dvec3 o(rays[i].origin), d(rays[i].direction);
    const double tPlane = glm::dot(centre - o, normal) / glm::dot(d, normal);
    const bool inFront = tPlane >= 0.0;
    const bool fullyCrossed = (aboveIn == 4 && above == 4) || (aboveIn == 0 && below == 4);
    if (fullyCrossed) {
      // Every segment of the shaft crosses the plane: the answer is the plane's hit (when ahead).
      ++crossing;
      if (!inFront) {
        if (hits[i].triangle != BVH_NO_HIT) ++wrong;
        continue;
      }
      if (hits[i].triangle == BVH_NO_HIT || hits[i].triangle >= quadTriangles) {
        ++wrong;
        continue;
      }
      EXPECT_EQ(hits[i].pad1, CS_HIT_FROM_LINE_SPACE);
      // Distance along the ray between the two hit points, relative to the box's edge length.
      const double rel = std::abs(double(hits[i].t) - tPlane) * glm::length(d) / double(hi.x - lo.x);
      worst = std::max(worst, rel);
      // The shading normal (flat quad) faces the origin.
      const glm::vec3 shading = unpackNormal(hits[i].pad0);
      EXPECT_LT(glm::dot(glm::dvec3(shading), d), 0.0);
      EXPECT_GT(std::abs(glm::dot(glm::dvec3(shading), normal)), 0.999);
    } else if (above == 8 || below == 8) {
      ++apart;  // the shaft does not meet the plane: a miss
      if (hits[i].triangle != BVH_NO_HIT) ++wrong;
    } else {
      ++mixed;
    }
  }
  std::printf("plane box N=%u: %d rays in fully crossed shafts, %d in shafts beside the plane, %d in shafts it cuts; "
              "wrong %d; worst hit distance %.2e box edges; filled %.3f\n",
              n, crossing, apart, mixed, wrong, worst, tracer.lineSpace().stats.filledFraction);
  EXPECT_EQ(wrong, 0);
  EXPECT_LT(worst, test::bound::kCandidatePlaneHit);
  EXPECT_GT(crossing, 1000);
  EXPECT_GT(apart, 1000);
  EXPECT_EQ(tracer.lastRaysReport().trace.rays, rays.size());
  EXPECT_GT(tracer.lastRaysReport().candidateTests, 0u);
}

TEST(CandidateGpu, NormalDeviationThresholdDropsEdgeShafts) {
  // A coarse smooth sphere in a box: shafts that graze its silhouette get candidates whose plane,
  // extrapolated far outside the triangle, carries normals that lean far from the face's.
  Scene scene;
  scene.name = "coarse sphere";
  Mesh sphere;
  sphere.name = "sphere";
  mesh::addSphere(sphere, glm::vec3(0.0f), 1.0f, 10, 5);
  scene.meshes = {sphere};
  cleanScene(scene, scene.name);
  const CandidateBox box{glm::vec3(-1.2f), glm::vec3(1.2f), 0};
  CandidateTracerSettings settings;
  settings.n = 6;
  CandidateTracer tracer(validatedContext(), scene, std::span<const CandidateBox>(&box, 1), settings);
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> unit(-1.2f, 1.2f);
  std::vector<shared::RayQuery> rays;
  for (int i = 0; i < 20000; ++i) {
    const glm::vec3 a(unit(rng), unit(rng), unit(rng)), b(unit(rng), unit(rng), unit(rng));
    rays.push_back({a - 3.0f * (b - a), 0.0f, b - a, 1e30f});
  }
  const std::vector<shared::SceneTriangle> tris = sceneTriangles(scene);
  std::vector<std::size_t> counts;
  for (float degrees : {30.0f, 180.0f}) {
    tracer.setMaxNormalDeviation(degrees);
    const auto hits = tracer.traceBox(rays, 0);
    std::size_t count = 0;
    double worst = 0.0;
    for (const shared::RayHit& h : hits) {
      if (h.triangle == BVH_NO_HIT) continue;
      ++count;
      const shared::SceneTriangle& t = tris[h.triangle];
      const glm::vec3 face = glm::normalize(glm::cross(t.v1 - t.v0, t.v2 - t.v0));
      const float c = std::abs(glm::dot(face, unpackNormal(h.pad0)));  // the hit's normal faces the ray
      worst = std::max(worst, std::acos(double(std::min(c, 1.0f))) * 180.0 / 3.14159265358979);
    }
    std::printf("coarse sphere N=6, at most %.0f degrees: %zu hits, largest normal deviation %.1f degrees\n", degrees,
                count, worst);
    if (degrees < 180.0f) {
      EXPECT_LE(worst, degrees + 0.5);
    }
    counts.push_back(count);
  }
  expectValidationSilent();
  EXPECT_LT(counts[0], counts[1]);
  EXPECT_GT(counts[0], 1000u);
}

// Rays from random points in the courtyard's lower part in uniform random directions.
std::vector<shared::RayQuery> courtyardRays(const Scene& scene, int count) {
  const Bounds b = scene.bounds();
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::normal_distribution<float> gauss;
  std::vector<shared::RayQuery> rays;
  for (int i = 0; i < count; ++i) {
    const glm::vec3 o(b.lo.x + unit(rng) * (b.hi.x - b.lo.x), 0.02f + unit(rng) * 4.0f, b.lo.z + unit(rng) * (b.hi.z - b.lo.z));
    glm::vec3 d(gauss(rng), gauss(rng), gauss(rng));
    rays.push_back({o, 1e-4f, glm::normalize(d), 1e30f});
  }
  return rays;
}

TEST(CandidateGpu, BvhWithLineSpacesAgainstExactClosestHit) {
  const Scene scene = loadScene("builtin:courtyard:2");
  const float radius = scene.bounds().radius();
  const auto rays = courtyardRays(scene, 20000);

  // The exact mode equals the BVH tracer's closest hit.
  BvhTracer bvhTracer(validatedContext(), scene);
  const auto reference = bvhTracer.traceRays(rays, false);
  std::vector<double> errors;
  std::vector<std::uint32_t> depths{6, 10};
  for (std::uint32_t d : depths) {
    CandidateTracerSettings settings;
    settings.n = 4;
    settings.depth = d;
    CandidateTracer tracer(validatedContext(), scene, settings);
    const auto exact = tracer.traceRays(rays, false);
    const CandidateRaysReport exactReport = tracer.lastRaysReport();
    for (std::size_t i = 0; i < rays.size(); ++i) {
      ASSERT_EQ(exact[i].triangle, reference[i].triangle) << "ray " << i;
      ASSERT_EQ(exact[i].t, reference[i].t) << "ray " << i;
    }
    const auto approx = tracer.traceRays(rays, true);
    const CandidateRaysReport lsReport = tracer.lastRaysReport();
    expectValidationSilent();
    std::size_t differ = 0, fromLs = 0, missed = 0, extra = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const bool a = approx[i].triangle != BVH_NO_HIT, e = exact[i].triangle != BVH_NO_HIT;
      fromLs += (approx[i].pad1 & CS_HIT_FROM_LINE_SPACE) ? 1 : 0;
      if (a != e) {
        ++differ;
        (e ? missed : extra)++;
      } else if (a && std::abs(approx[i].t - exact[i].t) > 0.01f * radius) {
        ++differ;
      }
    }
    const CandidateStats& s = tracer.lineSpace().stats;
    const double error = double(differ) / double(rays.size());
    errors.push_back(error);
    std::printf("courtyard:2 BVH+LS N=4 D=%u: %llu line spaces, filled %.3f, sparse %.2f MB vs dense %.2f MB, build "
                "%.0f ms; hits from line spaces %.3f; differ by > 1%% of the radius %.4f (missed %zu, extra %zu); "
                "node visits %.1f vs %.1f exact, triangle tests %.1f vs %.1f, candidate tests %.2f per ray\n",
                d, (unsigned long long)s.boxes, s.filledFraction, s.sparseBytes / 1e6, s.denseBytes / 1e6, s.buildMs,
                double(fromLs) / rays.size(), error, missed, extra,
                double(*lsReport.trace.nodeVisits) / rays.size(), double(*exactReport.trace.nodeVisits) / rays.size(),
                double(*lsReport.trace.triangleTests) / rays.size(), double(*exactReport.trace.triangleTests) / rays.size(),
                double(lsReport.candidateTests) / rays.size());
    EXPECT_GT(fromLs, 0u);
    EXPECT_LT(*lsReport.trace.nodeVisits, *exactReport.trace.nodeVisits);
  }
  EXPECT_LE(errors[1], errors[0] + 0.02) << "deeper line spaces should not be much worse";
  EXPECT_LT(errors[0], kShallowBound);
  EXPECT_LT(errors[1], kDeepBound);
}

}  // namespace
}  // namespace penumbra
