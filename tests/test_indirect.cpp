// Methods ao and indirect (shared/indirect.h): the GPU BVH kernel against the Embree reference on
// the same rays, the sampling against a closed form, and colour bleeding where it must appear.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "core/animation.h"
#include "core/mesh_builder.h"
#include "core/scene_loader.h"
#include "core/metrics.h"
#include "hybrid/method.h"
#include "bounds.h"
#include "render_fixture.h"
#include "shared/scene_triangles.h"

namespace penumbra {
namespace {

using test::SceneRun;
using test::expectValidationSilent;

RenderSettings indirectSettings(std::uint32_t size, std::uint32_t rays) {
  RenderSettings s = test::smallSettings(size);
  s.indirect.rays = rays;
  return s;
}

// Same rays, same hit shading: the GPU BVH's answers equal Embree's except where a ray grazes an
// edge and float rounding of the sampled direction differs (cos/sin on CPU and GPU): the bounds
// (tests/bounds.h) allow a few such rays. Ray queries (rq) likewise: the driver's watertight
// traversal; skipped, and said so, on a device without them.
class IndirectTracers : public ::testing::TestWithParam<const char*> {};

TEST_P(IndirectTracers, MatchTheEmbreeReference) {
  const std::string tracer = GetParam();
  if (tracer == "rq" && !test::validatedContext().rayQuery())
    GTEST_SKIP() << test::validatedContext().driverInfo() << " has no ray queries: rq not tested";
  SceneRun run("builtin:courtyard", indirectSettings(128, 16));
  for (const char* term : {"ao", "indirect"}) {
    const Frame ref = run.render(std::string(term) + "-embree");
    const Frame traced = run.render(std::string(term) + "-" + tracer);
    const ErrorMetrics e = compareVisibility(traced.visibility, ref.visibility, ref.covered, kWrongThresholdSoft);
    std::printf("%s: %s vs embree rmse %.6f, wrong %.4f%%, %llu rays, %.1f node visits/ray\n", term, tracer.c_str(),
                e.rmse, 100.0 * e.wrongPixelFraction, (unsigned long long)*traced.stats.raysTraced,
                double(traced.stats.nodeVisits.value_or(0)) /
                    double(*traced.stats.raysTraced + traced.stats.counts.at("shadow_rays")));
    EXPECT_EQ(*traced.stats.raysTraced, *ref.stats.raysTraced) << term;
    EXPECT_LE(e.wrongPixelFraction, test::bound::kIndirectWrong) << term;
    EXPECT_LE(e.rmse, test::bound::kIndirectRmse) << term;
    double sum = 0.0;
    for (std::size_t i = 0; i < ref.visibility.size(); ++i) sum += ref.covered[i] ? ref.visibility[i] : 0.0f;
    EXPECT_GT(sum, 0.0) << term << ": a term to compare";
  }
  expectValidationSilent();
}

INSTANTIATE_TEST_SUITE_P(Tracers, IndirectTracers, ::testing::Values("bvh", "rq"));

// Closest and any hits of the exact tracers (the GPU BVH, ray queries, the N-tree's exact line
// space) pass through a cut-out's holes as Embree's filters do: ao and one bounce under
// builtin:checker's occluder match the reference's (solid cells would darken the holes' share).
TEST(Indirect, ExactTracersPassThroughCutouts) {
  SceneRun run("builtin:checker", indirectSettings(128, 16));
  for (const char* term : {"ao", "indirect"}) {
    const Frame ref = run.render(std::string(term) + "-embree");
    for (const char* tracer : {"bvh", "rq", "ntree"}) {
      if (std::string(tracer) == "rq" && !test::validatedContext().rayQuery()) continue;
      const Frame traced = run.render(std::string(term) + "-" + tracer);
      const ErrorMetrics e = compareVisibility(traced.visibility, ref.visibility, ref.covered, kWrongThresholdSoft);
      std::printf("checker %s: %s vs embree rmse %.6f, wrong %.4f%%\n", term, tracer, e.rmse, 100.0 * e.wrongPixelFraction);
      EXPECT_LE(e.wrongPixelFraction, test::bound::kIndirectWrong) << term << " " << tracer;
      EXPECT_LE(e.rmse, test::bound::kIndirectRmse) << term << " " << tracer;
    }
  }
  expectValidationSilent();
}

// Between two parallel planes h apart, a cosine-weighted ray from one reaches the other within
// radius R exactly when cos(theta) >= h / R; cos^2(theta) of cosine-weighted directions is uniform,
// so the unoccluded fraction (ao) is (h / R)^2, with h less the rays' origin offset.
TEST(Indirect, AmbientOcclusionBetweenTwoPlanesIsTheClosedForm) {
  Scene scene;
  scene.name = "two planes";
  Mesh floor{.name = "floor"}, ceiling{.name = "ceiling"};
  const float half = 60.0f, h = 1.0f;
  mesh::addQuad(floor, {-half, 0, -half}, {half, 0, -half}, {half, 0, half}, {-half, 0, half}, {0, 1, 0});
  mesh::addQuad(ceiling, {-half, h, -half}, {half, h, -half}, {half, h, half}, {-half, h, half}, {0, -1, 0});
  scene.meshes = {floor, ceiling};
  scene.camera = Camera{.eye = {0, 0.6f, 3}, .target = {0, 0.2f, 0}};
  scene.lights.push_back(Light{.type = LightType::Point, .position = {0, 0.8f, 0}});
  const float radius = 2.0f * h;  // world units: ao = 0.25
  RenderSettings settings = indirectSettings(96, 64);
  settings.indirect.aoRadius = radius / scene.bounds().radius();
  const float offset = settings.rayEpsilon * scene.bounds().radius();  // shadowRayOrigin's lift off the surface
  SceneRun run(std::move(scene), settings);
  for (const char* method : {"ao-bvh", "ao-embree"}) {
    const Frame f = run.render(method);
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < f.visibility.size(); ++i) {
      if (!f.covered[i]) continue;
      sum += f.visibility[i];
      ++n;
    }
    ASSERT_GT(n, f.visibility.size() / 2) << method;
    const double expected = ((h - offset) / radius) * ((h - offset) / radius);
    std::printf("%s between planes: mean ao %.4f over %zu pixels (closed form %.4f)\n", method, sum / double(n), n, expected);
    // The mean of 9K pixels x 64 stratified rays: its standard error is below 0.001.
    EXPECT_NEAR(sum / double(n), expected, 0.003) << method;
  }
  expectValidationSilent();
}

// A white floor beside a red wall under a light: the floor's one-bounce light near the wall is red,
// and no hit sends back more than its base colour times the light.
TEST(Indirect, ColourBleedsFromARedWall) {
  Scene scene;
  scene.name = "red wall";
  Mesh floor{.name = "floor"}, wall{.name = "wall"};
  mesh::addQuad(floor, {-3, 0, -3}, {3, 0, -3}, {3, 0, 3}, {-3, 0, 3}, {0, 1, 0});
  mesh::addQuad(wall, {0, 0, -3}, {0, 2, -3}, {0, 2, 3}, {0, 0, 3}, {1, 0, 0});
  floor.baseColor = glm::vec3(0.8f);
  wall.baseColor = glm::vec3(0.9f, 0.1f, 0.1f);
  scene.meshes = {floor, wall};
  scene.camera = Camera{.eye = {4, 3, 0}, .target = {0.5f, 0, 0}};
  scene.lights.push_back(Light{.type = LightType::Point, .position = {2, 3, 0}});
  SceneRun run(std::move(scene), indirectSettings(64, 32));
  const Frame f = run.render("indirect-bvh");
  const Frame ao = run.render("ao-bvh");  // the same renderer, another term: the shading changes with it
  ASSERT_GT(*f.stats.raysTraced, 0u);
  EXPECT_GT(f.stats.counts.at("shadow_rays"), 0u);
  // Red over green in the image where the indirect term is largest (the floor at the wall's foot).
  std::size_t best = 0;
  for (std::size_t i = 0; i < f.visibility.size(); ++i) {
    if (f.covered[i] && f.visibility[i] > f.visibility[best]) best = i;
    EXPECT_LE(f.visibility[i], 0.9f) << "more light than the brightest albedo reflects";
  }
  ASSERT_GT(f.visibility[best], 0.0f);
  EXPECT_GT(int(f.rgba[4 * best]), int(f.rgba[4 * best + 1]) + 10) << "the floor by the wall is tinted red";
  EXPECT_NE(f.rgba, ao.rgba);
  expectValidationSilent();
}

// One bounce against a closed form, not computed with shared/indirect.h: a grey wall (x = 0, facing
// +x, albedo a) lit by a directional light, beside a floor. Every ray from a floor point p that
// meets the wall returns a (n_wall . l), the others nothing, so the expected term is
// a (n_wall . l) F(p), with F the form factor from p (normal n = +y) to the wall polygon, by the
// contour integral F = 1/(2 pi) |sum over edges of gamma_i n . (R_i x R_i+1) / |R_i x R_i+1||,
// R_i the vectors from p to the corners and gamma_i the angle between consecutive ones (checked
// against a direct quadrature of x y / (pi r^4) over the wall to 1e-4). 256 cosine-weighted rays
// per pixel on the GPU BVH and on the Embree reference come within a stated bound of it per pixel,
// and unbiased over the floor.
double formFactor(glm::dvec3 p, glm::dvec3 n, const std::vector<glm::dvec3>& polygon) {
  double sum = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const glm::dvec3 a = polygon[i] - p, b = polygon[(i + 1) % polygon.size()] - p, c = glm::cross(a, b);
    if (glm::length(c) == 0.0) continue;
    sum += std::acos(std::clamp(glm::dot(a, b) / (glm::length(a) * glm::length(b)), -1.0, 1.0)) * glm::dot(n, c) /
           glm::length(c);
  }
  return std::abs(sum) / (2.0 * 3.14159265358979);
}

TEST(Indirect, BounceOffALitWallIsItsFormFactor) {
  // Measured worst 0.0143 (256 strata: a few cut by the wall's silhouette) and mean error 5e-5 on
  // both tracers; unbiased rays leave the mean within ~6e-5 (a standard deviation over 7296
  // pixels), a wrong weighting of the rays (uniform instead of cosine) moves it by ~1e-2.
  constexpr double kWorst = 0.02, kBias = 3e-4;
  Scene scene;
  scene.name = "grey wall";
  Mesh floor{.name = "floor"}, wall{.name = "wall"};
  const float height = 2.0f, halfWidth = 3.0f;
  mesh::addQuad(floor, {-3, 0, -4}, {4, 0, -4}, {4, 0, 4}, {-3, 0, 4}, {0, 1, 0});
  mesh::addQuad(wall, {0, 0, -halfWidth}, {0, height, -halfWidth}, {0, height, halfWidth}, {0, 0, halfWidth}, {1, 0, 0});
  wall.baseColor = glm::vec3(0.8f);  // 204/255 in the scene's 8-bit colours: 0.8 exactly
  scene.meshes = {floor, wall};
  scene.camera = Camera{.eye = {2.2f, 4.0f, 0.0f}, .target = {1.2f, 0.0f, 0.0f}};
  const glm::vec3 travel = glm::normalize(glm::vec3(-0.6f, -1.0f, 0.2f));
  scene.lights.push_back(Light{.type = LightType::Directional, .direction = travel});
  SceneRun run(std::move(scene), indirectSettings(96, 256));
  const double reflected = 0.8 * double(glm::dot(glm::vec3(1, 0, 0), -travel));
  const std::vector<glm::dvec3> wallCorners{{0, 0, -halfWidth}, {0, height, -halfWidth}, {0, height, halfWidth}, {0, 0, halfWidth}};
  for (const char* method : {"indirect-bvh", "indirect-embree"}) {
    const Frame f = run.render(method);
    const auto positions = run.renderer->frameContext().gbuffer().positions();
    double worst = 0.0, bias = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < positions.size(); ++i) {
      const glm::vec4 p = positions[i];
      if (!f.covered[i] || std::abs(p.y) > 1e-3f || p.x < 0.1f || std::abs(p.z) > 2.0f) continue;  // the floor by the wall
      const double expected = reflected * formFactor(glm::dvec3(p), {0, 1, 0}, wallCorners);
      worst = std::max(worst, std::abs(f.visibility[i] - expected));
      bias += f.visibility[i] - expected;
      ++n;
    }
    ASSERT_GT(n, 2000u) << method;
    bias /= double(n);
    std::printf("%s: %zu floor pixels, worst |error| %.4f, mean error %.5f (wall reflects %.4f)\n", method, n, worst,
                bias, reflected);
    EXPECT_LE(worst, kWorst) << method;
    EXPECT_LE(std::abs(bias), kBias) << method;
  }
  expectValidationSilent();
}

// The candidate line space (Keul et al. 2018) answers ao and bounce rays from one representative
// triangle per shaft at the BVH's depth D: approximate, closer to the exact BVH the deeper D is.
// Bounds measured on this scene at 128^2 with 16 rays (ao rmse 0.065 at D = 6, 0.050 at D = 9;
// indirect 0.010 and 0.008), with margin; the error shows at line-space transitions and where a
// candidate's plane stands in for a curved or partly covered surface (compare writes its heatmap).
TEST(Indirect, CandidateLineSpaceErrorIsBoundedAndShrinksWithDepth) {
  const Frame exactAo = SceneRun("builtin:courtyard", indirectSettings(128, 16)).render("ao-bvh");
  const Frame exactIndirect = SceneRun("builtin:courtyard", indirectSettings(128, 16)).render("indirect-bvh");
  double rmse[2][2] = {};
  const std::uint32_t depths[2] = {6, 9};
  for (int d = 0; d < 2; ++d) {
    RenderSettings settings = indirectSettings(128, 16);
    settings.indirect.bvhDepth = depths[d];
    SceneRun run("builtin:courtyard", settings);
    const Frame ao = run.render("ao-bvh-ls"), indirect = run.render("indirect-bvh-ls");
    rmse[d][0] = compareVisibility(ao.visibility, exactAo.visibility, exactAo.covered, kWrongThresholdSoft).rmse;
    rmse[d][1] = compareVisibility(indirect.visibility, exactIndirect.visibility, exactIndirect.covered, kWrongThresholdSoft).rmse;
    std::printf("bvh-ls D=%u: ao rmse %.4f, indirect rmse %.4f vs the exact BVH; %.2f MB\n", depths[d], rmse[d][0],
                rmse[d][1], double(ao.stats.memoryBytes.at("bvh_ls")) / 1e6);
    EXPECT_GT(rmse[d][0], 0.0) << "an approximation: some rays answer differently";
    EXPECT_EQ(*ao.stats.raysTraced, *exactAo.stats.raysTraced);
  }
  EXPECT_LE(rmse[0][0], 0.09);
  EXPECT_LE(rmse[0][1], 0.015);
  EXPECT_LE(rmse[1][0], 0.07);
  EXPECT_LE(rmse[1][1], 0.012);
  EXPECT_LE(rmse[1][0], rmse[0][0] + 0.005) << "deeper line spaces are no worse";
  EXPECT_LE(rmse[1][1], rmse[0][1] + 0.002);
  expectValidationSilent();
}

// --hit-light shadow-map: the bounces' hits take sm's answer instead of a shadow ray. Close to the
// reference (which traces the ray), not equal: the map's texels and bias show at the hits' shadow
// edges. No shadow rays are traced.
TEST(Indirect, HitsSeeTheLightThroughTheShadowMapWhenAsked) {
  RenderSettings settings = indirectSettings(128, 16);
  SceneRun rays("builtin:courtyard", settings);
  const Frame ref = rays.render("indirect-embree");
  settings.indirect.hitShadowMap = true;
  SceneRun map("builtin:courtyard", settings);
  const Frame f = map.render("indirect-bvh");
  const ErrorMetrics e = compareVisibility(f.visibility, ref.visibility, ref.covered, kWrongThresholdSoft);
  std::printf("indirect, hits through the shadow map vs shadow rays: rmse %.5f, wrong %.3f%%\n", e.rmse,
              100.0 * e.wrongPixelFraction);
  EXPECT_EQ(f.stats.counts.at("shadow_rays"), 0u);
  EXPECT_GT(e.rmse, 0.0);
  EXPECT_LE(e.rmse, 0.0058);  // measured 0.0019
  expectValidationSilent();
}

// The N-tree's line space in exact mode (ntree): the set bits lead to the leaf cells, whose
// triangles are tested as the BVH tests them, front to back: the Embree reference's answers, as
// bvh gives them (the same bounds as IndirectTracers.MatchTheEmbreeReference).
TEST(Indirect, NTreeMatchesTheEmbreeReference) {
  SceneRun run("builtin:courtyard", indirectSettings(128, 16));
  for (const char* term : {"ao", "indirect"}) {
    const Frame ref = run.render(std::string(term) + "-embree");
    const Frame ntree = run.render(std::string(term) + "-ntree");
    const ErrorMetrics e = compareVisibility(ntree.visibility, ref.visibility, ref.covered, kWrongThresholdSoft);
    std::printf("%s: ntree vs embree rmse %.6f, wrong %.4f%%, %.1f node visits and %.1f triangle tests per ray, %.2f MB\n",
                term, e.rmse, 100.0 * e.wrongPixelFraction,
                double(*ntree.stats.nodeVisits) / double(*ntree.stats.raysTraced + ntree.stats.counts.at("shadow_rays")),
                double(*ntree.stats.triangleTests) / double(*ntree.stats.raysTraced + ntree.stats.counts.at("shadow_rays")),
                double(ntree.stats.memoryBytes.at("ntree")) / 1e6);
    EXPECT_EQ(*ntree.stats.raysTraced, *ref.stats.raysTraced) << term;
    EXPECT_LE(e.wrongPixelFraction, test::bound::kIndirectWrong) << term;
    EXPECT_LE(e.rmse, test::bound::kIndirectRmse) << term;
  }
  expectValidationSilent();
}

// Moving meshes are not in the line space: ntree asks their own BVH for a nearer hit, refit by
// sceneMoved(); after a move it answers as bvh does.
TEST(Indirect, NTreeFollowsTheMovingMeshes) {
  SceneRun run("builtin:courtyard-moving:1", indirectSettings(96, 8));
  for (const char* term : {"ao", "indirect"}) run.render(std::string(term) + "-ntree");  // built before the move
  const Frame before = run.render("indirect-bvh");
  poseScene(run.scene, 2.7);
  run.renderer->sceneMoved();
  for (const char* term : {"ao", "indirect"}) {
    const Frame bvh = run.render(std::string(term) + "-bvh");
    const Frame ntree = run.render(std::string(term) + "-ntree");
    const ErrorMetrics e = compareVisibility(ntree.visibility, bvh.visibility, bvh.covered, kWrongThresholdSoft);
    std::printf("%s after the move: ntree vs bvh rmse %.6f, wrong %.4f%%\n", term, e.rmse, 100.0 * e.wrongPixelFraction);
    // The same sampled rays on the same device, triangles tested alike: identical (measured so).
    EXPECT_EQ(ntree.visibility, bvh.visibility) << term;
    if (std::string(term) == "indirect") {
      EXPECT_NE(bvh.visibility, before.visibility) << "the move changes the frame";
    }
  }
  expectValidationSilent();
}

// The paper's NTree + LS(D): candidate line spaces at the N-tree's level D (and the T rule) answer
// ao and bounce rays approximately; the bounces' shadow rays use the binary line space. Measured on
// this scene at 128^2 with 16 rays, N = 4, d = 3 against the exact ntree: D = 1 (30 line spaces)
// ao rmse 0.107, indirect 0.033; D = 2 (396) ao 0.124, indirect 0.031 (the ao error does not
// shrink: most ao rays end in the node they start in, where a shaft's candidate lies behind the
// origin). Bounds with margin.
TEST(Indirect, NTreeCandidateLineSpaceErrorIsBounded) {
  RenderSettings base = indirectSettings(128, 16);
  base.lineSpace.n = 4;
  base.lineSpace.depth = 3;
  SceneRun exact("builtin:courtyard", base);
  const Frame exactAo = exact.render("ao-ntree"), exactIndirect = exact.render("indirect-ntree");
  const double aoBound[2] = {0.14, 0.16}, indirectBound[2] = {0.045, 0.045};
  std::uint64_t bytes[2] = {};
  for (std::uint32_t d = 0; d < 2; ++d) {
    RenderSettings settings = base;
    settings.indirect.ntreeDepth = d + 1;
    SceneRun run("builtin:courtyard", settings);
    const Frame ao = run.render("ao-ntree-ls"), indirect = run.render("indirect-ntree-ls");
    const double aoRmse = compareVisibility(ao.visibility, exactAo.visibility, exactAo.covered, kWrongThresholdSoft).rmse;
    const double indirectRmse =
        compareVisibility(indirect.visibility, exactIndirect.visibility, exactIndirect.covered, kWrongThresholdSoft).rmse;
    bytes[d] = ao.stats.memoryBytes.at("ntree_ls");
    std::printf("ntree-ls D=%u: ao rmse %.4f, indirect rmse %.4f vs ntree; %.2f MB, build %.0f ms\n", d + 1, aoRmse,
                indirectRmse, double(bytes[d]) / 1e6, ao.stats.setupMs.at("ntree_ls_build"));
    EXPECT_GT(aoRmse, 0.0) << "an approximation";
    EXPECT_LE(aoRmse, aoBound[d]);
    EXPECT_LE(indirectRmse, indirectBound[d]);
    EXPECT_EQ(*ao.stats.raysTraced, *exactAo.stats.raysTraced);
  }
  EXPECT_GT(bytes[1], bytes[0]) << "deeper: more line spaces";
  expectValidationSilent();
}

// Both N-tree tracers check their memory before building: a tiny budget is a clear InputError.
TEST(Indirect, NTreeTracersRefuseToExceedTheBudget) {
  RenderSettings settings = indirectSettings(32, 4);
  settings.lineSpace.budgetBytes = 10'000;
  SceneRun run("builtin:courtyard:2", settings);
  for (const char* method : {"ao-ntree", "ao-ntree-ls"}) {
    try {
      run.render(method);
      ADD_FAILURE() << method << " built over the budget";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--linespace-budget"), std::string::npos) << e.what();
    }
  }
  expectValidationSilent();
}

// The scene's triangles and the packed candidates are read through device addresses, so a device
// whose storage bindings span only 1 MiB (ContextOptions' test limit) renders the same frames:
// the courtyard's 1.8 MB of SceneTriangles and its candidates do not fit one binding there.
TEST(Indirect, TrianglesAndCandidatesLargerThanOneBindingTrace) {
  gpu::Context limited({.validate = true, .printMessages = true, .storageBufferRangeLimit = 1u << 20});
  const Scene scene = loadScene("builtin:courtyard");
  ASSERT_GT(scene.triangleCount() * sizeof(shared::SceneTriangle), limited.storageBufferRange());
  RenderSettings settings = indirectSettings(96, 4);
  settings.lineSpace.n = 4;
  settings.indirect.bvhDepth = 6;
  Renderer full(test::validatedContext(), scene, settings), small(limited, scene, settings);
  const Camera camera = *scene.camera;
  const Light light = scene.lights.front();
  for (const char* method : {"indirect-bvh", "ao-bvh-ls", "indirect-bvh-ls"}) {
    const Frame f = full.render(method, camera, light);
    EXPECT_EQ(small.render(method, camera, light).visibility, f.visibility) << method;
    for (const std::string& note : f.stats.notes) {
      if (note.find("candidate line space") != std::string::npos) std::printf("%s\n", note.c_str());
    }
  }
  const auto messages = limited.validationMessages();
  EXPECT_TRUE(messages.empty()) << messages.front();
  expectValidationSilent();
}

TEST(Indirect, FramesAreDeterministicAndUnknownTracersAreRefused) {
  SceneRun run("builtin:courtyard:2", indirectSettings(64, 8));
  const Frame a = run.render("indirect-bvh");
  const Frame b = run.render("indirect-bvh");
  EXPECT_EQ(a.visibility, b.visibility);
  EXPECT_EQ(a.rgba, b.rgba);
  EXPECT_EQ(*a.stats.term, "indirect");
  EXPECT_THROW(run.render("ao-nosuch"), InputError);
  expectValidationSilent();
}

}  // namespace
}  // namespace penumbra
