// Animated scenes: rigid keyframe posing (core/animation), bounds that hold every pose, bad
// animation input, and frames of the moving built-in scene that follow the pose on the GPU
// (raster geometry re-uploaded by Renderer::sceneMoved, tracers refit) and agree with Embree.
#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "core/animation.h"
#include "core/builtin_scenes.h"
#include "core/metrics.h"
#include "core/view.h"
#include "bounds.h"
#include "render_fixture.h"

namespace penumbra {
namespace {

using test::SceneRun;

const MeshAnimation& droneAnimation(const Scene& scene) {
  EXPECT_EQ(scene.animations.size(), 1u);
  return scene.animations.front();
}

bool inside(const Bounds& b, const glm::vec3& p) {
  return glm::all(glm::greaterThanEqual(p, b.lo)) && glm::all(glm::lessThanEqual(p, b.hi));
}

TEST(Animation, KeysPoseTheRestMeshRigidlyAndLoop) {
  Scene scene = makeBuiltinScene("courtyard-moving:1");
  const MeshAnimation& anim = droneAnimation(scene);
  const Mesh& drone = scene.meshes[anim.mesh];
  EXPECT_TRUE(drone.dynamic);
  EXPECT_EQ(animationPeriod(scene), 8.0);
  for (const RigidKey& key : anim.keys) {
    poseScene(scene, key.time);
    const glm::mat4 expected = glm::translate(glm::mat4(1.0f), key.translation) * glm::mat4_cast(key.rotation);
    for (std::size_t i = 0; i < drone.positions.size(); ++i) {
      const glm::vec3 want(expected * glm::vec4(anim.restPositions[i], 1.0f));
      ASSERT_LT(glm::length(drone.positions[i] - want), 1e-4f) << "key at " << key.time << " s, vertex " << i;
      ASSERT_NEAR(glm::length(drone.normals[i]), 1.0f, 1e-5f);
    }
  }
  // Rigid: distances between vertices survive any pose; the loop repeats with the period.
  poseScene(scene, 1.3);
  const std::vector<glm::vec3> at13 = drone.positions;
  for (std::size_t i = 1; i < at13.size(); ++i) {
    EXPECT_NEAR(glm::distance(at13[i], at13[0]), glm::distance(anim.restPositions[i], anim.restPositions[0]), 1e-4f);
  }
  poseScene(scene, 1.3 + 2.0 * animationPeriod(scene));
  for (std::size_t i = 0; i < at13.size(); ++i) EXPECT_LT(glm::length(drone.positions[i] - at13[i]), 1e-4f);
  // Between keys the drone is somewhere else than at either key.
  poseScene(scene, 0.25);
  const glm::vec3 mid = drone.positions[0];
  poseScene(scene, 0.0);
  EXPECT_GT(glm::distance(mid, drone.positions[0]), 0.1f);
}

TEST(Animation, BoundsHoldEveryPoseAndDoNotDependOnTime) {
  Scene scene = makeBuiltinScene("courtyard-moving:1");
  const Bounds bounds = scene.bounds();
  const Mesh& drone = scene.meshes[droneAnimation(scene).mesh];
  for (int step = 0; step <= 400; ++step) {
    poseScene(scene, 0.02 * step);
    for (const glm::vec3& p : drone.positions) ASSERT_TRUE(inside(bounds, p)) << "t = " << 0.02 * step;
    const Bounds now = scene.bounds();
    ASSERT_EQ(now.lo, bounds.lo);
    ASSERT_EQ(now.hi, bounds.hi);
  }
  // The static courtyard is inside too, and the drone's sweep adds little to it.
  const Bounds still = makeBuiltinScene("courtyard:1").bounds();
  EXPECT_TRUE(inside(bounds, still.lo) && inside(bounds, still.hi));
  EXPECT_LT(bounds.radius(), 1.2f * still.radius());
}

TEST(Animation, BadInputIsRefusedWithAMessage) {
  Scene scene = makeBuiltinScene("courtyard-moving:1");
  EXPECT_THROW(poseScene(scene, std::nan("")), InputError);
  EXPECT_THROW(poseScene(scene, INFINITY), InputError);
  Scene other = makeBuiltinScene("square");
  EXPECT_THROW(animateMesh(other, 0, {}), InputError);  // no keys
  RigidKey a, b;
  a.time = 1.0f;
  b.time = 0.5f;  // decreasing
  EXPECT_THROW(animateMesh(other, 0, {a, b}), InputError);
  EXPECT_THROW(animateMesh(other, 7, {a}), std::out_of_range);
  Scene broken = makeBuiltinScene("courtyard-moving:1");
  broken.animations.front().restPositions.pop_back();  // no longer matches the mesh
  try {
    poseScene(broken, 1.0);
    FAIL() << "a rest pose that does not match its mesh was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("drone"), std::string::npos) << e.what();
  }
}

// The frame follows the pose: after poseScene + sceneMoved the drone's shadow is elsewhere, and
// every tracer's srt still agrees with the Embree reference of the moved scene.
class MovingFrames : public ::testing::TestWithParam<const char*> {};

TEST_P(MovingFrames, SrtFollowsTheMovingDroneAndMatchesTheReference) {
  if (std::string(GetParam()) == "rq" && !test::validatedContext().rayQuery())
    GTEST_SKIP() << test::validatedContext().driverInfo() << " has no ray queries: rq not tested";
  RenderSettings settings = test::smallSettings(128, 1024);
  settings.tracer = GetParam();
  SceneRun run("builtin:courtyard-moving:1", settings);
  const Frame before = run.render("srt");
  EXPECT_TRUE(before.stats.refit.has_value() == false);
  poseScene(run.scene, 2.3);
  run.renderer->sceneMoved();
  const Frame srt = run.render("srt");
  const Frame ref = run.render("ref");
  // The GPU BVH and the driver's acceleration structures refit their moving part; Embree (the
  // reference, or --tracer embree) is rebuilt instead.
  const bool gpu = std::string(GetParam()) != "embree";
  ASSERT_EQ(srt.stats.refit.has_value(), gpu);
  const ErrorMetrics error = compareVisibility(srt.visibility, ref.visibility, ref.covered, kWrongThresholdHard);
  const double moved = temporalChange(before.visibility, srt.visibility, before.covered, srt.covered);
  std::cout << GetParam() << ": srt wrong " << error.wrongPixelFraction << ", mean change after the move " << moved
            << (gpu ? ", refit " + std::to_string(srt.stats.refit->ms) + " ms" : std::string()) << "\n";
  // The bound of the static hard-shadow tests: exact (measured 0 on every tracer).
  EXPECT_LE(error.wrongPixelFraction, test::bound::kSrtWrong);
  EXPECT_GT(moved, 0.0005);  // the drone's shadow (and the drone) moved on screen
  test::expectValidationSilent();
}

INSTANTIATE_TEST_SUITE_P(Tracers, MovingFrames, ::testing::Values("embree", "bvh", "rq"));

// RenderSettings::reuseLightPasses: while the light and the geometry stay still, a frame keeps the
// last shadow map and edge pyramid and is the frame a renderer that renders them again makes; a
// frame after the light or the geometry moved renders them again (and still agrees).
TEST(Animation, StillLightPassesAreKeptUntilTheLightOrTheGeometryMoves) {
  RenderSettings settings = test::smallSettings(128, 1024);
  settings.spp = 4;
  settings.tracer = "bvh";
  SceneRun again("builtin:courtyard-moving:1", settings);
  settings.reuseLightPasses = true;
  SceneRun keep("builtin:courtyard-moving:1", settings);
  for (SceneRun* run : {&again, &keep}) applyLightSize(run->light, 0.1f, run->scene.bounds());
  const std::vector<std::string> kept{"shadow_map", "depth_pyramid"};
  auto expectSame = [&](const std::vector<std::string>& reused, const char* when) {
    const Frame a = again.render("srt"), k = keep.render("srt");
    EXPECT_TRUE(a.stats.reusedPasses.empty()) << when;
    EXPECT_EQ(k.stats.reusedPasses, reused) << when;
    EXPECT_EQ(k.visibility, a.visibility) << when;
    EXPECT_EQ(k.pip, a.pip) << when;
  };
  expectSame({}, "first frame");
  expectSame(kept, "still light");
  for (SceneRun* run : {&again, &keep}) run->light.position += glm::vec3(0.5f, 0.0f, 0.0f);
  expectSame({}, "after the light moved");
  expectSame(kept, "still again");
  for (SceneRun* run : {&again, &keep}) {
    poseScene(run->scene, 2.3);
    run->renderer->sceneMoved();
  }
  expectSame({}, "after the geometry moved");
  test::expectValidationSilent();
}

// A frame of several still lights keeps each light's own maps (RenderSettings::reuseLightPasses):
// a move renders again only the maps that see what moved (the drone passes under one lamp; the other
// lamp's map, at the courtyard's far side, ends before the drone's swept box), and every frame is the
// one a renderer that renders every map makes.
TEST(Animation, AMoveRendersAgainOnlyTheMapsThatSeeIt) {
  RenderSettings settings = test::smallSettings(96, 256);
  settings.tracer = "bvh";
  SceneRun again("builtin:courtyard-moving:1", settings);
  settings.reuseLightPasses = true;
  SceneRun keep("builtin:courtyard-moving:1", settings);
  Light under = parseLight("point:3.5,5,0"), far = parseLight("point:-5.5,3,1");  // far: by the torus and red box
  under.range = 7.0f;
  far.range = 4.0f;
  const std::vector<Light> lamps{under, far};
  const std::vector<std::string> kept{"shadow_map"};
  auto expectSame = [&](const std::vector<std::vector<std::string>>& reused, const char* when) {
    const Frame a = again.renderer->render("srt", again.camera, lamps);
    const Frame k = keep.renderer->render("srt", keep.camera, lamps);
    for (std::size_t i = 0; i < lamps.size(); ++i) {
      EXPECT_TRUE(a.lights[i].stats.reusedPasses.empty()) << when << ", lamp " << i;
      EXPECT_EQ(k.lights[i].stats.reusedPasses, reused[i]) << when << ", lamp " << i;
      EXPECT_EQ(k.lights[i].visibility, a.lights[i].visibility) << when << ", lamp " << i;
      EXPECT_EQ(k.lights[i].pip, a.lights[i].pip) << when << ", lamp " << i;
      const auto& v = k.lights[i].visibility;
      EXPECT_GT(std::count(v.begin(), v.end(), 1.0f), 0) << when << ", lamp " << i << " lights some pixels";
    }
    EXPECT_EQ(k.lights.back().stats.counts.at("lights_with_own_maps"), lamps.size()) << when;
    return a;
  };
  expectSame({{}, {}}, "first frame");
  const Frame before = expectSame({kept, kept}, "still lamps");
  for (SceneRun* run : {&again, &keep}) {
    poseScene(run->scene, 0.5);
    run->renderer->sceneMoved();
  }
  const Frame after = expectSame({{}, kept}, "after the drone moved");
  EXPECT_NE(after.lights[0].visibility, before.lights[0].visibility) << "the drone's shadow under the lamp moved";
  expectSame({kept, kept}, "still again");
  test::expectValidationSilent();
}

}  // namespace
}  // namespace penumbra
