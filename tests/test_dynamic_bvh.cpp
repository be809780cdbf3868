// Moving geometry in the ray tracers (issue 8): the dynamic BVH beside the static one, refit and
// rebuilt, against Embree on the moved scene; the renderer's srt/frt and the two-level line space.
// The meshes are moved here by rewriting their positions (rigid: rotate + translate, or per-piece
// for the rebuild case), as an animation would between frames.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <numeric>
#include <random>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "core/mesh_builder.h"
#include "core/metrics.h"
#include "raytrace/bandwidth_model.h"
#include "raytrace/bvh_refit.h"
#include "raytrace/bvh_tracer.h"
#include "raytrace/linespace_tracer.h"
#include "raytrace/ray_query_tracer.h"
#include "bounds.h"
#include "embree_rays.h"
#include "render_fixture.h"
#include "shared/trace.h"

namespace penumbra {
namespace {

using shared::RayHit;
using shared::RayQuery;
using test::expectValidationSilent;
using test::validatedContext;

std::size_t meshIndex(const Scene& scene, const std::string& name) {
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
    if (scene.meshes[i].name == name) return i;
  }
  ADD_FAILURE() << "no mesh '" << name << "' in " << scene.name;
  return 0;
}

// A mesh's rest pose, so that every move is absolute (as an animation poses from its rest pose).
struct Rest {
  std::size_t mesh = 0;
  std::vector<glm::vec3> positions, normals;
  Rest(Scene& scene, std::size_t m) : mesh(m), positions(scene.meshes[m].positions), normals(scene.meshes[m].normals) {
    scene.meshes[m].dynamic = true;
  }
  glm::vec3 centre() const {
    Bounds b;
    for (const glm::vec3& p : positions) b.extend(p);
    return b.center();
  }
  // Rotates by `degrees` about `axis` through the rest centre, then translates.
  void pose(Scene& scene, const glm::vec3& translation, float degrees, const glm::vec3& axis) const {
    const glm::vec3 c = centre();
    const glm::mat4 m = glm::translate(glm::mat4(1.0f), c + translation) *
                        glm::rotate(glm::mat4(1.0f), glm::radians(degrees), glm::normalize(axis)) *
                        glm::translate(glm::mat4(1.0f), -c);
    Mesh& mesh = scene.meshes[this->mesh];
    for (std::size_t i = 0; i < positions.size(); ++i) {
      mesh.positions[i] = glm::vec3(m * glm::vec4(positions[i], 1.0f));
      mesh.normals[i] = glm::normalize(glm::mat3(m) * normals[i]);
    }
  }
  Bounds bounds(const Scene& scene) const {
    Bounds b;
    for (const glm::vec3& p : scene.meshes[mesh].positions) b.extend(p);
    return b;
  }
};

// Rays from a sphere around `target` (2.5 of its radii) through random points of the box widened
// by a fifth, and on through the far side: most pass through the object, some beside it.
void addRaysThrough(const Bounds& target, std::size_t count, std::mt19937& rng, std::vector<RayQuery>& rays) {
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  std::normal_distribution<float> normal;
  const float r = 2.5f * target.radius();
  const glm::vec3 size = 1.2f * (target.hi - target.lo);
  for (std::size_t i = 0; i < count; ++i) {
    const glm::vec3 dir(normal(rng), normal(rng), normal(rng));
    const glm::vec3 origin = target.center() + r * glm::normalize(dir);
    const glm::vec3 aim = target.center() + (glm::vec3(uni(rng), uni(rng), uni(rng)) - 0.5f) * size;
    rays.push_back({origin, 0.0f, glm::normalize(aim - origin), 2.0f * r});
  }
}

struct Comparison {
  std::size_t rays = 0, hits = 0;
  std::size_t anyDisagree = 0;      // occluded or not differs from Embree
  std::size_t closestDisagree = 0;  // hit/miss differs, or another triangle at another t
  std::size_t tOff = 0;             // same triangle, t off by more than kRelativeT
  double maxRelativeT = 0.0;
};

// Both tracers evaluate the same robust edge test on the same float vertices operation for
// operation (bvh_traverse.glsl), so the hit triangle and its t agree to the last few bits; t is
// compared relative to itself at 1e-6 (8 ulps), the float rounding of the t division alone.
constexpr double kRelativeT = 1e-6;

template <class Tracer>  // BvhTracer or RayQueryTracer
Comparison compareWithEmbree(Tracer& tracer, const Scene& scene, const std::vector<RayQuery>& rays) {
  const test::EmbreeRays embree(scene, validatedContext());
  const std::vector<RayHit> any = tracer.traceRays(rays, true);
  const std::vector<RayHit> closest = tracer.traceRays(rays, false);
  Comparison c;
  c.rays = rays.size();
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const RTCRayHit ref = embree.closest(rays[i]);
    const bool refHit = ref.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    c.hits += refHit;
    c.anyDisagree += (any[i].triangle != BVH_NO_HIT) != embree.occluded(rays[i]);
    const bool gpuHit = closest[i].triangle != BVH_NO_HIT;
    if (gpuHit != refHit) {
      ++c.closestDisagree;
    } else if (gpuHit) {
      const double rel = std::abs(double(closest[i].t) - double(ref.ray.tfar)) / double(ref.ray.tfar);
      c.maxRelativeT = std::max(c.maxRelativeT, rel);
      // A ray through an edge or vertex hits the triangles that share it at the same t; which of
      // them a closest-hit query names is its traversal order's choice, so a different triangle
      // counts as a disagreement only at a different t.
      if (closest[i].triangle == ref.hit.primID) c.tOff += rel > kRelativeT;
      else c.closestDisagree += rel > kRelativeT;
    }
  }
  return c;
}

void print(const char* what, const Comparison& c) {
  std::printf("%s: %zu rays (%zu hit), any-hit disagree %zu, closest disagree %zu, t off %zu (max rel %.2g)\n", what,
              c.rays, c.hits, c.anyDisagree, c.closestDisagree, c.tOff, c.maxRelativeT);
}

// The static part of both buffers, to check that updates never touch it.
struct StaticPart {
  std::vector<std::uint8_t> nodes, triangles;
  explicit StaticPart(const BvhTracer& tracer) {
    const auto* n = static_cast<const std::uint8_t*>(tracer.nodeBuffer().data());
    const auto* t = static_cast<const std::uint8_t*>(tracer.triangleBuffer().data());
    nodes.assign(n, n + std::size_t(tracer.dynamicRoot()) * sizeof(shared::BvhNode));
    triangles.assign(t, t + std::size_t(tracer.staticTriangles()) * sizeof(shared::BvhTriangle));
  }
  bool operator==(const StaticPart&) const = default;
};

// ---- Builder and refit on the CPU -------------------------------------------------------------

TEST(DynamicBvh, SplitBuildsKeepSceneIdsAndRefitOfAnUnmovedTreeIsTheBuild) {
  Scene scene = loadScene("builtin:courtyard:2");
  const std::size_t sphere = meshIndex(scene, "sphere");
  scene.meshes[sphere].dynamic = true;
  const BvhBuilder builder;
  const Bvh all = builder.build(scene), fixed = builder.build(scene, MeshSet::Static),
            moving = builder.build(scene, MeshSet::Dynamic);
  EXPECT_EQ(fixed.stats.triangles + moving.stats.triangles, all.stats.triangles);
  EXPECT_EQ(moving.stats.triangles, scene.meshes[sphere].triangleCount());
  // Ids are scene-wide: each names a triangle of the right set with exactly these vertices.
  std::vector<std::pair<std::size_t, std::size_t>> owner;  // id -> (mesh, triangle)
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    for (std::size_t t = 0; t < scene.meshes[m].triangleCount(); ++t) owner.push_back({m, t});
  }
  for (const Bvh* bvh : {&fixed, &moving}) {
    for (const shared::BvhTriangle& tri : bvh->triangles) {
      ASSERT_LT(tri.id, owner.size());
      const auto [m, t] = owner[tri.id];
      EXPECT_EQ(scene.meshes[m].dynamic, bvh == &moving);
      EXPECT_EQ(tri.v1, scene.meshes[m].positions[scene.meshes[m].indices[3 * t + 1]]);
    }
  }
  // Refitting an unmoved tree reproduces the builder's boxes bit for bit (same padding, same
  // unions), and so its SAH cost.
  Bvh refit = moving;
  refitBvh(refit, scene);
  ASSERT_EQ(refit.nodes.size(), moving.nodes.size());
  EXPECT_EQ(std::memcmp(refit.nodes.data(), moving.nodes.data(), moving.nodes.size() * sizeof(shared::BvhNode)), 0);
  EXPECT_EQ(refit.stats.sahCost, moving.stats.sahCost);
  EXPECT_EQ(sahCost(all), all.stats.sahCost);

  // An empty selection is a tree, not an error; a scene without triangles still is one.
  Scene still = loadScene("builtin:courtyard:1");
  const Bvh none = builder.build(still, MeshSet::Dynamic);
  EXPECT_TRUE(none.empty());
  EXPECT_EQ(none.nodes.size(), 1u);
  Scene nothing;
  nothing.name = "test:nothing";
  EXPECT_THROW(builder.build(nothing, MeshSet::Dynamic), InputError);
  // The growth threshold must be a growth.
  BvhBuildSettings bad;
  bad.rebuildGrowth = 1.0f;
  EXPECT_THROW(BvhBuilder{bad}, std::invalid_argument);
}

// ---- GPU BVH: refit ----------------------------------------------------------------------------

TEST(DynamicBvh, RefitTracesTheMovedSphereAsEmbreeDoes) {
  Scene scene = loadScene("builtin:courtyard:2");
  const Rest sphere(scene, meshIndex(scene, "sphere"));
  BvhTracer tracer(validatedContext(), scene);
  ASSERT_NE(tracer.dynamicRoot(), BVH_NO_TREE);
  EXPECT_EQ(tracer.dynamicBvh().triangleCount(), scene.meshes[sphere.mesh].triangleCount());
  const StaticPart before(tracer);

  // Unmoved: both trees together answer as Embree does.
  std::mt19937 rng(8);
  std::vector<RayQuery> rays;
  addRaysThrough(sphere.bounds(scene), 3000, rng, rays);
  const Comparison still = compareWithEmbree(tracer, scene, rays);
  print("unmoved", still);
  EXPECT_EQ(still.anyDisagree, 0u);

  // Moved (rotated 35 degrees, shifted by about its radius), rays through the new place and the old.
  const Bounds old = sphere.bounds(scene);
  sphere.pose(scene, {-1.0f, 0.4f, 1.2f}, 35.0f, {1.0f, 1.0f, 0.0f});
  rays.clear();
  addRaysThrough(sphere.bounds(scene), 3000, rng, rays);
  addRaysThrough(old, 2000, rng, rays);
  const Comparison stale = compareWithEmbree(tracer, scene, rays);
  print("moved, before update", stale);
  EXPECT_GT(stale.anyDisagree, rays.size() / 20) << "the test must see a tree that did not follow";

  const BvhRefitReport report = tracer.update(scene);
  std::printf("refit: %.3f ms, SAH %.3f (built %.3f, growth %.3f)\n", report.ms, report.sah, report.builtSah,
              report.growth);
  EXPECT_FALSE(report.rebuilt);
  EXPECT_EQ(report.rebuilds, 0u);
  EXPECT_EQ(report.triangles, scene.meshes[sphere.mesh].triangleCount());
  EXPECT_EQ(report.sah, report.refitSah);
  const Comparison moved = compareWithEmbree(tracer, scene, rays);
  print("moved, refit", moved);
  EXPECT_EQ(moved.anyDisagree, 0u);
  EXPECT_EQ(moved.closestDisagree, 0u);
  EXPECT_EQ(moved.tOff, 0u);
  EXPECT_GT(moved.hits, rays.size() / 4);
  EXPECT_TRUE(StaticPart(tracer) == before) << "an update wrote into the static tree";

  // A scene without dynamic meshes has one tree and nothing to update.
  const Scene still2 = loadScene("builtin:courtyard:1");
  BvhTracer plain(validatedContext(), still2);
  EXPECT_EQ(plain.dynamicRoot(), BVH_NO_TREE);
  const BvhRefitReport none = plain.update(still2);
  EXPECT_EQ(none.triangles, 0u);
  EXPECT_FALSE(none.rebuilt);
  expectValidationSilent();
}

// ---- GPU BVH: rebuild --------------------------------------------------------------------------

// A ground quad under a swarm of 64 small cubes in one dynamic mesh, 8 x 8 in a grid: moving the
// cubes to each other's places keeps every cube rigid but scatters what the tree's nodes grouped.
struct Swarm {
  static constexpr int kSide = 8;
  Scene scene;
  std::vector<glm::vec3> rest;
  std::size_t perCube = 0;
  Swarm() {
    scene.name = "test:swarm";
    Mesh ground, cubes;
    mesh::addQuad(ground, {-6, 0, -6}, {6, 0, -6}, {6, 0, 6}, {-6, 0, 6}, {0, 1, 0});
    for (int k = 0; k < kSide * kSide; ++k) {
      mesh::addBox(cubes, slot(k), {0.2f, 0, 0}, {0, 0.2f, 0}, {0, 0, 0.2f});
      if (k == 0) perCube = cubes.positions.size();
    }
    cubes.name = "swarm";
    scene.meshes.push_back(ground);
    scene.meshes.push_back(cubes);
    cleanScene(scene, scene.name);
    scene.meshes[1].dynamic = true;
    rest = scene.meshes[1].positions;
  }
  static glm::vec3 slot(int k) { return {float(k % kSide) - 3.5f, 1.0f + 0.1f * float(k % 3), float(k / kSide) - 3.5f}; }
  // Cube k to slot place[k], shifted by `shift`.
  void move(const std::vector<int>& place, const glm::vec3& shift) {
    Mesh& m = scene.meshes[1];
    for (std::size_t i = 0; i < rest.size(); ++i) {
      const int k = int(i / perCube);
      m.positions[i] = rest[i] - slot(k) + slot(place[k]) + shift;
    }
  }
  Bounds bounds() const {
    Bounds b;
    for (const glm::vec3& p : scene.meshes[1].positions) b.extend(p);
    return b;
  }
};

TEST(DynamicBvh, RebuildsWhenRefittingGrewTheSah) {
  Swarm swarm;
  ASSERT_EQ(swarm.rest.size(), swarm.perCube * Swarm::kSide * Swarm::kSide) << "addBox adds a fixed vertex count";
  BvhTracer tracer(validatedContext(), swarm.scene);
  const StaticPart before(tracer);
  std::vector<int> place(Swarm::kSide * Swarm::kSide);
  std::iota(place.begin(), place.end(), 0);

  // A small move refits.
  swarm.move(place, {0.05f, 0.02f, -0.03f});
  const BvhRefitReport small = tracer.update(swarm.scene);
  std::printf("small move: growth %.3f, rebuilt %d, %.3f ms\n", small.growth, int(small.rebuilt), small.ms);
  EXPECT_FALSE(small.rebuilt);
  EXPECT_LE(small.growth, 1.5);

  // Every cube to another cube's place: the refit tree's nodes span the swarm.
  std::mt19937 rng(3);
  std::shuffle(place.begin(), place.end(), rng);
  swarm.move(place, {0.05f, 0.02f, -0.03f});
  const BvhRefitReport big = tracer.update(swarm.scene);
  std::printf("shuffled: refit SAH %.3f = %.2f x built, rebuilt %d -> SAH %.3f, %.3f ms\n", big.refitSah, big.growth,
              int(big.rebuilt), big.sah, big.ms);
  EXPECT_TRUE(big.rebuilt);
  EXPECT_GT(big.growth, 1.5);
  EXPECT_EQ(big.rebuilds, 1u);
  EXPECT_EQ(big.sah, big.builtSah);
  EXPECT_LT(big.sah, big.refitSah);
  EXPECT_TRUE(StaticPart(tracer) == before) << "a rebuild wrote into the static tree";

  std::vector<RayQuery> rays;
  addRaysThrough(swarm.bounds(), 4000, rng, rays);
  const Comparison c = compareWithEmbree(tracer, swarm.scene, rays);
  print("swarm, rebuilt", c);
  EXPECT_EQ(c.anyDisagree, 0u);
  EXPECT_EQ(c.closestDisagree, 0u);
  EXPECT_EQ(c.tOff, 0u);
  EXPECT_GT(c.hits, rays.size() / 10);

  // The bandwidth model replays one tree only and says so.
  const auto& context = validatedContext();
  gpu::Buffer buffer(context, 256, vk::BufferUsageFlagBits::eStorageBuffer, "test buffer");
  const TraceJob job{buffer, buffer, buffer, buffer};
  EXPECT_THROW(simulateTraceBandwidth(tracer, job, shared::GpuLight{}), InputError);
  expectValidationSilent();
}

// ---- Through the renderer ----------------------------------------------------------------------

double wrong(const Frame& frame, const Frame& reference) {
  return compareVisibility(frame.visibility, reference.visibility, reference.covered, kWrongThresholdHard)
      .wrongPixelFraction;
}

// Pixels lit before the move and in shadow after it, by the reference: the moved sphere's new shadow.
std::vector<std::size_t> newShadow(const Frame& before, const Frame& after) {
  std::vector<std::size_t> pixels;
  for (std::size_t p = 0; p < after.visibility.size(); ++p) {
    if (after.covered[p] && before.covered[p] && before.visibility[p] > 0.5f && after.visibility[p] < 0.5f)
      pixels.push_back(p);
  }
  return pixels;
}

TEST(DynamicBvh, SrtAndFrtFollowTheMovedSphere) {
  Scene scene = loadScene("builtin:courtyard:1");
  const Rest sphere(scene, meshIndex(scene, "sphere"));
  Renderer renderer(validatedContext(), scene, test::smallSettings(160));
  const Camera camera = *scene.camera;
  const Light light = scene.lights.front();
  const Frame refBefore = renderer.render("ref", camera, light);
  const Frame frtBefore = renderer.render("frt", camera, light);  // builds the GPU BVH
  EXPECT_EQ(wrong(frtBefore, refBefore), 0.0);

  sphere.pose(scene, {-1.2f, 0.3f, 1.0f}, 40.0f, {0.0f, 1.0f, 1.0f});
  renderer.sceneMoved();
  const Frame ref = renderer.render("ref", camera, light);
  const Frame frt = renderer.render("frt", camera, light);
  const Frame srt = renderer.render("srt", camera, light);
  const std::size_t moved = newShadow(refBefore, ref).size();
  std::printf("moved sphere: %zu pixels newly in shadow; frt wrong %.5f, srt wrong %.5f\n", moved, wrong(frt, ref),
              wrong(srt, ref));
  ASSERT_GT(moved, 100u) << "the move must move a shadow";
  EXPECT_EQ(wrong(frt, ref), 0.0);
  EXPECT_LE(wrong(srt, ref), test::bound::kSrtWrong);  // the bound test_selective holds srt to (measured 0)
  ASSERT_TRUE(frt.stats.refit.has_value());
  EXPECT_FALSE(frt.stats.refit->rebuilt);
  EXPECT_GT(frt.stats.refit->sah, 0.0);
  expectValidationSilent();
}

TEST(DynamicBvh, LineSpaceTracesTheMovedSphereWithoutRebuilding) {
  Scene scene = loadScene("builtin:courtyard:1");
  const Rest sphere(scene, meshIndex(scene, "sphere"));
  RenderSettings settings = test::smallSettings(160);
  settings.spp = 1;
  settings.lineSpace = {5, 3, 0};
  Renderer renderer(validatedContext(), scene, settings);
  const Camera camera = *scene.camera;
  const Light light = scene.lights.front();
  const Frame refBefore = renderer.render("ref", camera, light);
  const Frame lsBefore = renderer.render("ls", camera, light);
  FrameStats scratch;
  const auto* tracer = &dynamic_cast<LineSpaceTracer&>(renderer.frameContext().tracer(scratch, "ls"));
  const LineSpaceStats statsBefore = tracer->stats();
  EXPECT_GT(statsBefore.dynamicBvhBytes, 0u);
  EXPECT_EQ(statsBefore.bytes,
            statsBefore.treeBytes + statsBefore.nodeBytes + statsBefore.lineSpaceBytes + statsBefore.dynamicBvhBytes);

  sphere.pose(scene, {-1.2f, 0.3f, 1.0f}, 40.0f, {0.0f, 1.0f, 1.0f});
  renderer.sceneMoved();
  const Frame ref = renderer.render("ref", camera, light);
  const Frame ls = renderer.render("ls", camera, light);
  const std::vector<std::size_t> shadow = newShadow(refBefore, ref);
  std::size_t lsDark = 0, staleLit = 0;
  for (std::size_t p : shadow) {
    lsDark += ls.visibility[p] < 0.5f;
    staleLit += lsBefore.visibility[p] > 0.5f;
  }
  std::size_t covered = 0, brighter = 0;
  for (std::size_t p = 0; p < ref.visibility.size(); ++p) {
    covered += ref.covered[p];
    brighter += ref.covered[p] && ls.visibility[p] > ref.visibility[p];
  }
  std::printf("ls after the move: %zu of %zu new shadow pixels dark (before the move %zu lit); brighter than ref on "
              "%.4f of covered pixels\n",
              lsDark, shadow.size(), staleLit, double(brighter) / double(covered));
  ASSERT_GT(shadow.size(), 100u);
  EXPECT_GT(staleLit, shadow.size() / 2) << "the new shadow must be new to the line space";
  // The moved sphere is traced exactly by its BVH: its new shadow is all there.
  EXPECT_EQ(lsDark, shadow.size());
  // Everywhere else the bound the line-space tests hold ls to: brighter only through the
  // start-node skip, on at most 1% of the covered pixels.
  EXPECT_LE(double(brighter), 0.01 * double(covered));
  // The same line space: not rebuilt, same pools.
  EXPECT_EQ(&dynamic_cast<LineSpaceTracer&>(renderer.frameContext().tracer(scratch, "ls")), tracer);
  EXPECT_EQ(tracer->stats().bytes, statsBefore.bytes);
  EXPECT_EQ(tracer->stats().buildMs, statsBefore.buildMs);
  ASSERT_TRUE(ls.stats.refit.has_value());
  EXPECT_EQ(ls.stats.refit->rebuilds, 0u);
  expectValidationSilent();
}

// ---- Ray queries: the moving meshes' acceleration structures ------------------------------------

// The driver's structures follow the same moves: refit in place for a small move, rebuilt when the
// refit would have grown the SAH past the limit (the DynamicBvh's decision), answering as Embree
// does after each update, and not before it.
TEST(DynamicBvh, RayQueryStructuresRefitAndRebuildAsTheBvhDoes) {
  if (!validatedContext().rayQuery()) GTEST_SKIP() << validatedContext().driverInfo() << " has no ray queries";
  Swarm swarm;
  RayQueryTracer tracer(validatedContext(), swarm.scene);
  EXPECT_EQ(tracer.stats().bottomLevels, 2u);
  std::vector<int> place(Swarm::kSide * Swarm::kSide);
  std::iota(place.begin(), place.end(), 0);
  std::mt19937 rng(3);

  swarm.move(place, {0.3f, 0.02f, -0.2f});
  std::vector<RayQuery> rays;
  addRaysThrough(swarm.bounds(), 4000, rng, rays);
  const Comparison stale = compareWithEmbree(tracer, swarm.scene, rays);
  EXPECT_GT(stale.anyDisagree, rays.size() / 50) << "the test must see structures that did not follow";
  const BvhRefitReport small = tracer.update(swarm.scene);
  std::printf("rq small move: growth %.3f, rebuilt %d, %.3f ms\n", small.growth, int(small.rebuilt), small.ms);
  EXPECT_FALSE(small.rebuilt);
  const Comparison refit = compareWithEmbree(tracer, swarm.scene, rays);
  print("rq swarm, refit", refit);
  EXPECT_EQ(refit.anyDisagree, 0u);
  EXPECT_EQ(refit.closestDisagree, 0u);

  std::shuffle(place.begin(), place.end(), rng);
  swarm.move(place, {0.05f, 0.02f, -0.03f});
  const BvhRefitReport big = tracer.update(swarm.scene);
  std::printf("rq shuffled: growth %.2f, rebuilt %d, %.3f ms\n", big.growth, int(big.rebuilt), big.ms);
  EXPECT_TRUE(big.rebuilt);
  EXPECT_EQ(big.rebuilds, 1u);
  rays.clear();
  addRaysThrough(swarm.bounds(), 4000, rng, rays);
  const Comparison rebuilt = compareWithEmbree(tracer, swarm.scene, rays);
  print("rq swarm, rebuilt", rebuilt);
  EXPECT_EQ(rebuilt.anyDisagree, 0u);
  EXPECT_EQ(rebuilt.closestDisagree, 0u);
  EXPECT_GT(rebuilt.hits, rays.size() / 10);
  expectValidationSilent();
}

}  // namespace
}  // namespace penumbra
