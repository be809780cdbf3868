// The ray-query tracer (--tracer rq, issue 15): inline ray queries on driver-built acceleration
// structures must give the GPU BVH's answers, ray for ray and pixel for pixel, on the scenes where
// shadow maps fail, with hard and soft shadows, static and moving; where the device has no ray
// queries (Mesa 22.3's lavapipe) these tests say so and skip, and asking for rq is a clear error.
#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "core/animation.h"
#include "core/metrics.h"
#include "core/scene_loader.h"
#include "embree_rays.h"
#include "raytrace/bvh_tracer.h"
#include "raytrace/ray_query_tracer.h"
#include "hybrid/registry.h"
#include "render_fixture.h"

namespace penumbra {
namespace {

using shared::RayHit;
using shared::RayQuery;
using test::expectValidationSilent;
using test::SceneRun;
using test::validatedContext;

#define REQUIRE_RAY_QUERIES()                                                                      \
  if (!validatedContext().rayQuery())                                                              \
  GTEST_SKIP() << validatedContext().deviceName() << " (" << validatedContext().driverInfo()       \
               << ") has no ray queries: rq not tested here (lavapipe has them from Mesa 25)"

Scene oneTriangle() {
  Scene s{.name = "one triangle"};
  s.meshes.push_back({.name = "tri", .positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, .indices = {0, 1, 2}});
  return s;
}

TEST(RayQueryTracer, OneTriangleHitsAndMisses) {
  REQUIRE_RAY_QUERIES();
  RayQueryTracer tracer(validatedContext(), oneTriangle());
  const std::vector<RayQuery> rays = {{{0.25f, 0.25f, 2.0f}, 0.0f, {0, 0, -1}, 10.0f},   // hit at t = 2
                                      {{0.75f, 0.75f, 2.0f}, 0.0f, {0, 0, -1}, 10.0f},   // beside it
                                      {{0.25f, 0.25f, 2.0f}, 0.0f, {0, 0, -1}, 1.5f},    // stops short
                                      {{0.25f, 0.25f, 2.0f}, 2.5f, {0, 0, -1}, 10.0f},   // starts beyond
                                      {{0.25f, 0.25f, -2.0f}, 0.0f, {0, 0, 2}, 10.0f}};  // from behind, t in units of |dir|
  for (bool anyHit : {true, false}) {
    const std::vector<RayHit> hits = tracer.traceRays(rays, anyHit);
    EXPECT_FLOAT_EQ(hits[0].t, 2.0f);
    EXPECT_EQ(hits[0].triangle, 0u);
    for (int i = 1; i < 4; ++i) EXPECT_TRUE(hits[i].triangle == BVH_NO_HIT && hits[i].t < 0.0f) << i;
    EXPECT_FLOAT_EQ(hits[4].t, 1.0f) << "no culling: the back face is hit too";
  }
  EXPECT_EQ(tracer.stats().bottomLevels, 1u);
  EXPECT_THROW(RayQueryTracer(validatedContext(), Scene{.name = "empty"}), InputError);
  expectValidationSilent();
}

// Random rays through a scene, from a sphere around it: the nearest hit names the same triangle
// (scene-order ids across meshes and instances) at the same t as the GPU BVH and Embree.
TEST(RayQueryTracer, RaysHitWhatTheBvhAndEmbreeHit) {
  REQUIRE_RAY_QUERIES();
  for (const char* spec : {"builtin:courtyard:2", "builtin:wires", "builtin:room"}) {
    SCOPED_TRACE(spec);
    const Scene scene = loadScene(spec);
    const Bounds b = scene.bounds();
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> uni(-1.0f, 1.0f);
    std::vector<RayQuery> rays;
    for (int i = 0; i < 20000; ++i) {
      const glm::vec3 dir = glm::normalize(glm::vec3(uni(rng), uni(rng), uni(rng)) + glm::vec3(0, 0, 1e-3f));
      const glm::vec3 aim = b.center() + 0.5f * glm::vec3(uni(rng), uni(rng), uni(rng)) * (b.hi - b.lo);
      rays.push_back({aim - 2.0f * b.radius() * dir, 0.0f, dir, 4.0f * b.radius()});
    }
    RayQueryTracer rq(validatedContext(), scene);
    BvhTracer bvh(validatedContext(), scene);
    const test::EmbreeRays embree(scene, validatedContext());
    std::size_t hits = 0, anyDisagree = 0, closestDisagree = 0;
    const auto rqAny = rq.traceRays(rays, true), rqClosest = rq.traceRays(rays, false);
    const auto bvhClosest = bvh.traceRays(rays, false);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const bool hit = bvhClosest[i].triangle != BVH_NO_HIT;
      hits += hit;
      anyDisagree += (rqAny[i].triangle != BVH_NO_HIT) != embree.occluded(rays[i]);
      // A ray through a shared edge hits both triangles at one t: either may be named.
      const bool same = rqClosest[i].triangle == bvhClosest[i].triangle ||
                        (hit && std::abs(rqClosest[i].t - bvhClosest[i].t) <= 1e-6f * bvhClosest[i].t);
      closestDisagree += !same;
      if (same && hit) {
        EXPECT_NEAR(rqClosest[i].t, bvhClosest[i].t, 1e-5f * bvhClosest[i].t) << i;
      }
    }
    std::printf("%s: %zu rays, %zu hit; rq any-hit vs Embree differ %zu, closest vs bvh differ %zu\n", spec,
                rays.size(), hits, anyDisagree, closestDisagree);
    EXPECT_GT(hits, rays.size() / 5);
    EXPECT_EQ(anyDisagree, 0u);
    EXPECT_EQ(closestDisagree, 0u);
  }
  expectValidationSilent();
}

// Cut-out meshes are non-opaque geometry whose candidates the proceed loop tests (rq_common.glsl):
// rays through the checker's holes pass, rays on its cells stop, as on the BVH, any and closest.
TEST(RayQueryTracer, CutoutsLetRaysThroughWhereTheBvhDoes) {
  REQUIRE_RAY_QUERIES();
  const Scene scene = loadScene("builtin:checker"), solid = loadScene("builtin:square");
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> uni(-1.2f, 1.2f);
  std::vector<RayQuery> rays;
  for (int i = 0; i < 20000; ++i) {  // down through the occluder's plane (y = 1) onto the ground
    const glm::vec3 at(uni(rng), 1.0f, uni(rng));
    const glm::vec3 dir = glm::normalize(glm::vec3(0.3f * uni(rng), -1.0f, 0.3f * uni(rng)));
    rays.push_back({at - 2.0f * dir, 0.0f, dir, 10.0f});
  }
  RayQueryTracer rq(validatedContext(), scene), rqSolid(validatedContext(), solid);
  BvhTracer bvh(validatedContext(), scene);
  const auto rqAny = rq.traceRays(rays, true), rqClosest = rq.traceRays(rays, false);
  const auto bvhClosest = bvh.traceRays(rays, false), solidClosest = rqSolid.traceRays(rays, false);
  std::size_t throughHoles = 0, differ = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    // the occluder is mesh 1: triangles after the ground's
    const std::uint32_t groundTriangles = std::uint32_t(scene.meshes[0].triangleCount());
    const bool solidOccluder = solidClosest[i].triangle != BVH_NO_HIT && solidClosest[i].triangle >= groundTriangles;
    throughHoles += solidOccluder && !(rqClosest[i].triangle != BVH_NO_HIT && rqClosest[i].triangle >= groundTriangles);
    differ += rqClosest[i].triangle != bvhClosest[i].triangle || (rqAny[i].triangle != BVH_NO_HIT) != (bvhClosest[i].triangle != BVH_NO_HIT);
  }
  std::printf("checker: %zu rays, %zu through its holes; rq vs bvh differ %zu\n", rays.size(), throughHoles, differ);
  EXPECT_GT(throughHoles, rays.size() / 5);
  EXPECT_EQ(differ, 0u);
  expectValidationSilent();
}

RenderSettings settingsFor(const std::string& tracer, float lightSize = 0.0f) {
  RenderSettings s = test::smallSettings(192, 2048);
  s.tracer = tracer;
  s.spp = lightSize > 0.0f ? 16 : 1;
  return s;
}

std::size_t differingPixels(const Frame& a, const Frame& b) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.visibility.size(); ++i) n += a.visibility[i] != b.visibility[i];
  return n;
}

// Same rays, same answers: srt and frt on rq are the BVH's frames bit for bit, on the scenes of
// the stability suite (sub-texel wires, cube-map seams, the courtyard), hard and soft; and the
// BVH's frames are within the reference bounds there (test_selective.cpp), so these are too.
TEST(RayQueryTracer, FramesAreTheBvhFramesPixelForPixel) {
  REQUIRE_RAY_QUERIES();
  for (const char* spec : {"builtin:courtyard", "builtin:wires", "builtin:room", "builtin:checker"}) {
    for (float lightSize : {0.0f, 0.05f}) {
      if (lightSize > 0.0f && std::string(spec) == "builtin:room") continue;  // a point light inside a room
      SCOPED_TRACE(std::string(spec) + " light size " + std::to_string(lightSize));
      SceneRun bvh(spec, settingsFor("bvh"));
      SceneRun rq(spec, settingsFor("rq"));
      for (SceneRun* run : {&bvh, &rq}) run->light.size = lightSize * run->scene.bounds().radius();
      for (const char* method : {"srt", "frt"}) {
        const Frame a = bvh.render(method), b = rq.render(method);
        EXPECT_EQ(b.stats.tracer, "rq");
        EXPECT_EQ(a.stats.raysTraced, b.stats.raysTraced) << method;
        EXPECT_EQ(a.stats.pipPixels, b.stats.pipPixels) << method;
        EXPECT_EQ(differingPixels(a, b), 0u) << method;
        EXPECT_FALSE(b.stats.nodeVisits.has_value()) << "the driver's traversal is not counted";
        EXPECT_GT(b.stats.memoryBytes.at("acceleration_structures"), 0u);
      }
      const Frame ref = rq.render("ref");
      const Frame frt = rq.render("frt");
      const double threshold = lightSize > 0.0f ? kWrongThresholdSoft : kWrongThresholdHard;
      EXPECT_EQ(compareVisibility(frt.visibility, ref.visibility, ref.covered, threshold).wrongPixelFraction, 0.0)
          << "frt traces the reference's rays";
    }
  }
  expectValidationSilent();
}

// The line space's exact part, the moving meshes, on ray queries: the same frames as on their own
// BVH, before and after the drone moved (both are exact; the line space itself is unchanged).
TEST(RayQueryTracer, LineSpaceTracesItsMovingMeshesWithRayQueries) {
  REQUIRE_RAY_QUERIES();
  std::vector<Frame> frames[2];
  for (int rq = 0; rq < 2; ++rq) {
    RenderSettings settings = test::smallSettings(128, 1024);
    settings.tracer = "ls";
    settings.lineSpace.n = 4;
    settings.lineSpace.depth = 2;
    settings.lineSpace.movingTracer = rq ? LineSpaceSettings::Moving::RayQuery : LineSpaceSettings::Moving::Bvh;
    SceneRun run("builtin:courtyard-moving:1", settings);
    frames[rq].push_back(run.render("ls"));
    poseScene(run.scene, 2.3);
    run.renderer->sceneMoved();
    frames[rq].push_back(run.render("ls"));
    EXPECT_EQ(frames[rq].back().stats.memoryBytes.count("acceleration_structures"), std::size_t(rq));
    ASSERT_TRUE(frames[rq].back().stats.refit.has_value());
  }
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(frames[0][i].stats.raysTraced, frames[1][i].stats.raysTraced) << "frame " << i;
    EXPECT_EQ(differingPixels(frames[0][i], frames[1][i]), 0u) << "frame " << i;
  }
  EXPECT_GT(differingPixels(frames[1][0], frames[1][1]), 0u) << "the drone's shadow moved";
  expectValidationSilent();
}

// Without ray queries (a device that lacks them, or PENUMBRA_NO_RAY_QUERY=1): rq is refused with a
// message that says why and what to use, and "auto" means the compute BVH. Runs on every driver.
TEST(RayQueryTracer, WithoutRayQueriesRqIsRefusedAndAutoIsBvh) {
  ::setenv("PENUMBRA_NO_RAY_QUERY", "1", 1);
  gpu::Context context({.validate = true, .printMessages = true});
  ::unsetenv("PENUMBRA_NO_RAY_QUERY");
  EXPECT_FALSE(context.rayQuery());
  EXPECT_EQ(resolveTracer(context, "auto"), "bvh");
  EXPECT_EQ(resolveTracer(context, "ls"), "ls");
  try {
    RayQueryTracer tracer(context, oneTriangle());
    ADD_FAILURE() << "rq was built without ray queries";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("--tracer bvh"), std::string::npos) << what;
    EXPECT_NE(what.find("PENUMBRA_NO_RAY_QUERY"), std::string::npos) << what;
  }
  // On lavapipe, where rq has them, "auto" still picks the faster compute BVH (bench/results/tracers.md).
  const bool cpu = validatedContext().physicalDevice().getProperties().deviceType == vk::PhysicalDeviceType::eCpu;
  EXPECT_EQ(resolveTracer(validatedContext(), "auto"), validatedContext().rayQuery() && !cpu ? "rq" : "bvh");
  EXPECT_TRUE(context.validationMessages().empty());
}

}  // namespace
}  // namespace penumbra
