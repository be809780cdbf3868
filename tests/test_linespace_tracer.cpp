// The line-space tracer (Keul et al. 2017) on the GPU: method `ls` against the reference, with its
// known failures (blocky single-sample silhouettes, missing contact shadows from the start-node
// skip) measured, and exact mode (--ls-shadows exact) against the reference and the BVH.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/animation.h"
#include "core/camera.h"
#include "core/mesh_builder.h"
#include "core/metrics.h"
#include "bounds.h"
#include "raytrace/embree_tracer.h"
#include "raytrace/linespace_tracer.h"
#include "render_fixture.h"

namespace penumbra {
namespace {

using test::expectValidationSilent;
using test::validatedContext;

// ---- GPU method ls -------------------------------------------------------------------------

RenderSettings lsSettings(std::uint32_t size, std::uint32_t spp, LineSpaceSettings lineSpace = {5, 3, 0}) {
  RenderSettings s = test::smallSettings(size, 2048);
  s.spp = spp;
  s.lineSpace = lineSpace;
  return s;
}

// Fraction of covered pixels where `test` is brighter than `reference` by more than `margin`.
double brighterFraction(const Frame& test, const Frame& reference, float margin) {
  std::size_t covered = 0, brighter = 0;
  for (std::size_t i = 0; i < reference.visibility.size(); ++i) {
    if (!reference.covered[i]) continue;
    ++covered;
    brighter += test.visibility[i] > reference.visibility[i] + margin;
  }
  return double(brighter) / double(std::max<std::size_t>(covered, 1));
}

// Root-mean-square difference over the pixels in `mask`.
double rmseOver(const Frame& test, const Frame& reference, const std::vector<std::uint8_t>& mask) {
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) continue;
    const double d = double(test.visibility[i]) - double(reference.visibility[i]);
    sum += d * d;
    ++count;
  }
  return std::sqrt(sum / double(std::max<std::size_t>(count, 1)));
}

// Per sample, the line space answers "occluded" whenever the reference does (it is conservative),
// except for blockers inside the finest node around the shading point (start-node skip) or within
// the start offset of its surface: only those pixels may come out brighter. Everything else is
// over-darkening, of two kinds:
//  - silhouettes: a shaft that meets a caster's cell blocks rays that pass beside the caster,
//    blocky with one sample, averaged out by many (the paper's Figure 7);
//  - bands along node faces: a ray that leaves its (skipped) start node through a side face
//    within one leaf cell of the receiver's own surface enters the neighbour node through the
//    receiver's cell row, so its shaft meets the receiver and the ray counts as occluded. All
//    samples of such a point see the same, so this does not average out; it grows as the light
//    gets lower. The start offset (LineSpaceSettings::startOffsetCells, default one leaf cell)
//    removes most of them: the line space only answers once the ray is a cell above the surface.
// On the courtyard what remains is mostly the first kind: wires and fence bars thinner than a
// cell shadow as solid blocks.
TEST(LineSpaceTracer, SoftShadowsOnlyDarken) {
  test::SceneRun run("builtin:courtyard", lsSettings(160, 25));
  run.light.size = 0.1f * run.scene.bounds().radius();
  const Frame r = run.render("ref");
  const Frame l = run.render("ls");
  const ErrorMetrics e = compareVisibility(l.visibility, r.visibility, r.covered, kWrongThresholdSoft);
  const double brighter = brighterFraction(l, r, 0.0f);
  double darkening = 0.0;
  for (std::size_t p = 0; p < r.visibility.size(); ++p) {
    if (r.covered[p]) darkening += r.visibility[p] - l.visibility[p];
  }
  std::printf("courtyard, light 0.1, ls (5,3) 25 spp vs ref: rmse %.4f, mae %.4f, wrong %.4f, brighter %.4f of "
              "pixels, %.2f node visits/ray\n",
              e.rmse, e.mae, e.wrongPixelFraction, brighter, double(*l.stats.nodeVisits) / double(*l.stats.raysTraced));
  ASSERT_EQ(l.stats.tracer, "ls");
  EXPECT_EQ(*l.stats.raysTraced, *r.stats.raysTraced) << "the same samples as the reference";
  EXPECT_GT(l.stats.memoryBytes.at("linespace"), 0u);
  EXPECT_TRUE(l.stats.setupMs.count("linespace_build"));
  EXPECT_GT(*l.stats.nodeVisits, *l.stats.raysTraced);
  // Brighter pixels come only from the start-node skip (measured 0.20% of the covered pixels).
  EXPECT_LE(brighter, test::bound::kLineSpaceBrighter);
  // Everything else darkens: the mean darkening is nearly all of the mean error (measured 0.1396 of 0.1425).
  const double covered = double(std::count(r.covered.begin(), r.covered.end(), std::uint8_t(1)));
  EXPECT_GE(darkening / covered, 0.95 * e.mae) << "the line space over-darkens";
  expectValidationSilent();
}

// The paper's Figure 7 on builtin:square under a rect light above it (0.5 radii wide): in the
// penumbra the error is the silhouettes', blocky with 1 sample and averaged by 25.
TEST(LineSpaceTracer, ManySamplesHideBlockySilhouettes) {
  Frame reference[2], ls[2];
  for (int i = 0; i < 2; ++i) {
    const std::uint32_t spp = i == 0 ? 1u : 25u;
    test::SceneRun run("builtin:square", lsSettings(160, spp));
    run.light.type = LightType::Rect;
    run.light.position = {0.0f, 8.0f, 0.0f};
    run.light.direction = {0.0f, -1.0f, 0.0f};
    run.light.size = 0.5f * run.scene.bounds().radius();
    reference[i] = run.render("ref");
    ls[i] = run.render("ls");
    // No blocker lies within the ground's start node or offset here: never brighter (measured so).
    EXPECT_EQ(brighterFraction(ls[i], reference[i], 0.0f), 0.0) << spp << " spp";
  }
  std::vector<std::uint8_t> penumbra(reference[1].visibility.size());
  std::size_t penumbraPixels = 0;
  for (std::size_t p = 0; p < penumbra.size(); ++p) {
    const float v = reference[1].visibility[p];
    penumbra[p] = reference[1].covered[p] && v > 0.0f && v < 1.0f;
    penumbraPixels += penumbra[p];
  }
  const double one = rmseOver(ls[0], reference[0], penumbra), many = rmseOver(ls[1], reference[1], penumbra);
  const ErrorMetrics all[2] = {
      compareVisibility(ls[0].visibility, reference[0].visibility, reference[0].covered, kWrongThresholdSoft),
      compareVisibility(ls[1].visibility, reference[1].visibility, reference[1].covered, kWrongThresholdSoft)};
  std::printf("square, overhead light 0.5: penumbra (%zu px) rmse 1 spp %.4f, 25 spp %.4f; all pixels rmse %.4f / "
              "%.4f, mae %.4f / %.4f\n",
              penumbraPixels, one, many, all[0].rmse, all[1].rmse, all[0].mae, all[1].mae);
  ASSERT_GT(penumbraPixels, 300u);  // a penumbra to measure in
  // Blocky silhouettes with one sample; 25 samples at most half that error.
  EXPECT_LT(many, 0.5 * one);
  expectValidationSilent();
}

TEST(LineSpaceTracer, RunsAreBitIdenticalAndSrtCanUseIt) {
  RenderSettings settings = lsSettings(128, 9);
  settings.tracer = "ls";
  test::SceneRun run("builtin:courtyard", settings);
  run.light.size = 0.1f * run.scene.bounds().radius();
  const Frame a = run.render("ls");
  const Frame b = run.render("ls");
  EXPECT_EQ(a.visibility, b.visibility);
  EXPECT_EQ(*a.stats.nodeVisits, *b.stats.nodeVisits);
  // srt on --tracer ls traces only its PIP rays with the same tracer.
  const Frame srt = run.render("srt");
  ASSERT_EQ(srt.stats.tracer, "ls");
  EXPECT_LT(*srt.stats.raysTraced, *a.stats.raysTraced);
  expectValidationSilent();
}

// A box standing on a ground plane (contact) and a plate floating above it, under a slanted
// point-like light: the floating plate's shadow is kept (conservative), the box's shadow next to
// its base goes missing, because the finest node around those ground points also holds the box's
// base and is skipped (the paper's start-node rule).
Scene contactScene() {
  Scene scene;
  scene.name = "test:contact";
  Mesh ground, box, plate;
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  mesh::addQuad(ground, {-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5}, up);
  mesh::addBox(box, {-2.0f, 0.6f, 0.0f}, {0.6f, 0, 0}, {0, 0.6f, 0}, {0, 0, 0.6f});
  mesh::addQuad(plate, {1.5f, 2.5f, -0.6f}, {2.7f, 2.5f, -0.6f}, {2.7f, 2.5f, 0.6f}, {1.5f, 2.5f, 0.6f}, up);
  for (Mesh* m : {&ground, &box, &plate}) scene.meshes.push_back(*m);
  cleanScene(scene, scene.name);
  Light light;
  light.type = LightType::Directional;
  light.direction = glm::normalize(glm::vec3(0.8f, -1.0f, 0.3f));
  scene.lights.push_back(light);
  Camera camera;
  camera.eye = {0.0f, 10.0f, 6.0f};
  camera.target = {0.0f, 0.0f, 0.0f};
  scene.camera = camera;
  return scene;
}

TEST(LineSpaceTracer, StartNodeSkipLosesContactShadowsOnly) {
  const Scene scene = contactScene();
  const std::uint32_t size = 192;
  Renderer renderer(validatedContext(), scene, lsSettings(size, 1, {4, 3, 0}));
  const Frame reference = renderer.render("ref", *scene.camera, scene.lights.front());
  const Frame ls = renderer.render("ls", *scene.camera, scene.lights.front());
  // The paper's rule alone (no start offset): the bands along node faces.
  Renderer paperRule(validatedContext(), scene, lsSettings(size, 1, {4, 3, 0, 0.0f}));
  const Frame banded = paperRule.render("ls", *scene.camera, scene.lights.front());
  // Where does the floating plate's shadow fall, and where the box's? Split the ground by x:
  // the box's shadow lies at x < 0, the plate's at x > 0 (the light travels towards +x).
  const EmbreeTracer embree(scene);
  const Bounds bounds = scene.bounds();
  const auto hits = embree.tracePrimary(cameraMatrices(*scene.camera, bounds, int(size), int(size)), int(size), int(size));
  std::size_t boxShadow = 0, boxMissing = 0, plateShadow = 0, plateMissing = 0, missingFar = 0, lit = 0, falselyDark = 0,
              falselyDarkBanded = 0;
  const double finest = double(bounds.hi.x - bounds.lo.x) * 1.0001 / 16.0;  // level-2 node edge of (4,3)
  for (std::size_t i = 0; i < hits.size(); ++i) {
    if (!reference.covered[i] || !hits[i].hit || hits[i].position.y > 1e-3f) continue;  // ground only
    const bool shadowed = reference.visibility[i] < 0.5f, missing = shadowed && ls.visibility[i] > 0.5f;
    lit += !shadowed;
    falselyDark += !shadowed && ls.visibility[i] < 0.5f;
    falselyDarkBanded += !shadowed && banded.visibility[i] < 0.5f;
    const bool boxSide = hits[i].position.x < 0.0f;
    (boxSide ? boxShadow : plateShadow) += shadowed;
    (boxSide ? boxMissing : plateMissing) += missing;
    // A missing shadow lies within two finest nodes of the box's base (the node holding the
    // point and the box, measured between their far corners).
    const glm::vec3 p = hits[i].position;
    const double dx = std::max(0.0, std::abs(double(p.x) + 2.0) - 0.6), dz = std::max(0.0, std::abs(double(p.z)) - 0.6);
    if (missing && std::sqrt(dx * dx + dz * dz) > 2.0 * std::sqrt(2.0) * finest) ++missingFar;
  }
  std::printf("contact scene, ls (4,3), 1 spp: box shadow %zu px, %zu missing (%.1f%%); plate shadow %zu px, %zu "
              "missing; brighter anywhere %.4f; lit ground falsely dark %.1f%% (without the start offset %.1f%%: bands)\n",
              boxShadow, boxMissing, 100.0 * double(boxMissing) / double(std::max<std::size_t>(boxShadow, 1)),
              plateShadow, plateMissing, brighterFraction(ls, reference, 0.0f),
              100.0 * double(falselyDark) / double(std::max<std::size_t>(lit, 1)),
              100.0 * double(falselyDarkBanded) / double(std::max<std::size_t>(lit, 1)));
  ASSERT_GT(boxShadow, 200u);
  ASSERT_GT(plateShadow, 200u);
  EXPECT_GT(boxMissing, 0u) << "the start-node skip must show at the contact";
  EXPECT_EQ(plateMissing, 0u) << "a floating caster's shadow is never lost";
  EXPECT_EQ(missingFar, 0u) << "shadows go missing only next to the contact";
  EXPECT_LT(falselyDark * 4, falselyDarkBanded) << "the start offset removes most of the bands";
  expectValidationSilent();
}

// ---- Exact shadows -------------------------------------------------------------------------

LineSpaceSettings exactLineSpace(LineSpaceSettings s = {5, 3, 0}) {
  s.shadows = LineSpaceSettings::Shadows::Exact;
  return s;
}

// Pixels along a line across the fence's shadow on the ground, in order: the ground points the
// light's centre throws the fence's mid-height onto, for z from before its first bar to past its
// last (the fence of core/builtin_scenes.cpp: bars side by side along z), projected with the
// camera; only pixels whose primary hit is that ground point (not hidden by anything).
std::vector<std::size_t> fenceShadowLine(const Scene& scene, const Camera& camera, const Light& light, int size) {
  const auto fence = std::find_if(scene.meshes.begin(), scene.meshes.end(), [](const Mesh& m) { return m.name == "fence"; });
  if (fence == scene.meshes.end()) return {};
  Bounds bars;
  for (const glm::vec3& p : fence->positions) bars.extend(p);
  const glm::vec3 l = light.position;
  const float height = 0.5f * (bars.lo.y + bars.hi.y), x = 0.5f * (bars.lo.x + bars.hi.x);
  const ViewMatrices m = cameraMatrices(camera, scene.bounds(), size, size);
  const EmbreeTracer embree(scene);
  const auto hits = embree.tracePrimary(m, size, size);
  std::vector<std::size_t> line;
  const int steps = 4 * size;
  const float margin = 0.1f * (bars.hi.z - bars.lo.z);
  for (int i = 0; i <= steps; ++i) {
    const glm::vec3 p(x, height, bars.lo.z - margin + (bars.hi.z - bars.lo.z + 2.0f * margin) * float(i) / float(steps));
    const glm::vec3 ground = l + (p - l) * (l.y / (l.y - p.y));  // on y = 0
    const glm::vec4 clip = m.viewProj * glm::vec4(ground, 1.0f);
    const int px = int(std::floor((clip.x / clip.w * 0.5f + 0.5f) * float(size)));
    const int py = int(std::floor((clip.y / clip.w * 0.5f + 0.5f) * float(size)));
    if (px < 0 || py < 0 || px >= size || py >= size) continue;
    const std::size_t pixel = std::size_t(py) * std::size_t(size) + std::size_t(px);
    if (!hits[pixel].hit || glm::distance(hits[pixel].position, ground) > 0.2f) continue;
    if (line.empty() || line.back() != pixel) line.push_back(pixel);
  }
  return line;
}

// Changes between lit (visibility >= 0.5) and shadowed along `line`.
int transitions(const Frame& frame, const std::vector<std::size_t>& line) {
  int count = 0;
  for (std::size_t i = 1; i < line.size(); ++i) {
    count += (frame.visibility[line[i]] >= 0.5f) != (frame.visibility[line[i - 1]] >= 0.5f);
  }
  return count;
}

// The courtyard of SoftShadowsOnlyDarken: binary mode shadows the fence bars and wires, thinner
// than a leaf cell, as solid blocks; exact mode tests their triangles, so it matches the reference
// up to the 25 samples' noise (none: the same samples) and the bars' shadows stay bars.
TEST(LineSpaceTracer, ExactShadowsMatchTheReferenceAndKeepTheFenceBars) {
  const std::uint32_t size = 256;
  test::SceneRun run("builtin:courtyard", lsSettings(size, 25));
  run.light.size = 0.1f * run.scene.bounds().radius();
  test::SceneRun exactRun("builtin:courtyard", lsSettings(size, 25, exactLineSpace()));
  exactRun.light = run.light;
  const Frame r = run.render("ref");
  const Frame binary = run.render("ls");
  const Frame exact = exactRun.render("ls");
  const ErrorMetrics eb = compareVisibility(binary.visibility, r.visibility, r.covered, kWrongThresholdSoft);
  const ErrorMetrics ee = compareVisibility(exact.visibility, r.visibility, r.covered, kWrongThresholdSoft);
  const double rays = double(*exact.stats.raysTraced);
  std::printf("courtyard, light 0.1, ls (5,3) 25 spp vs ref at %u^2: binary rmse %.4f wrong %.4f (%.2f visits/ray); "
              "exact rmse %.4f wrong %.4f (%.2f visits/ray, %.2f triangle tests/ray)\n",
              size, eb.rmse, eb.wrongPixelFraction, double(*binary.stats.nodeVisits) / double(*binary.stats.raysTraced),
              ee.rmse, ee.wrongPixelFraction, double(*exact.stats.nodeVisits) / rays,
              double(*exact.stats.triangleTests) / rays);
  ASSERT_EQ(exact.stats.tracer, "ls");
  EXPECT_EQ(*exact.stats.raysTraced, *r.stats.raysTraced) << "the same samples as the reference";
  EXPECT_EQ(ee.wrongPixelFraction, 0.0) << "the BVH's triangle test on the reference's samples";
  EXPECT_LE(ee.rmse, test::bound::kExactLineSpaceRmse);
  EXPECT_LT(ee.rmse, 0.25 * eb.rmse) << "exact mode removes most of binary mode's error";
  EXPECT_GT(*exact.stats.triangleTests, 0u);
  EXPECT_EQ(*binary.stats.triangleTests, 0u) << "binary mode tests no triangles";
  EXPECT_GT(exact.stats.memoryBytes.at("linespace"), binary.stats.memoryBytes.at("linespace"));

  const std::vector<std::size_t> line = fenceShadowLine(run.scene, run.camera, run.light, int(size));
  const int tr = transitions(r, line), tb = transitions(binary, line), te = transitions(exact, line);
  std::size_t agree = 0;
  for (std::size_t p : line) agree += (exact.visibility[p] >= 0.5f) == (r.visibility[p] >= 0.5f);
  std::printf("fence shadow line: %zu pixels; lit/shadow transitions: ref %d, binary %d, exact %d; exact agrees on "
              "%zu pixels\n",
              line.size(), tr, tb, te, agree);
  ASSERT_GT(line.size(), 40u) << "the line crosses the fence's shadow in view";
  EXPECT_GE(tr, 20) << "the reference shows the bars (20 bars: two transitions each)";
  EXPECT_LT(tb, tr / 4) << "binary mode: a solid block";
  EXPECT_NEAR(te, tr, 2) << "exact mode keeps the bars";
  EXPECT_GE(double(agree), 0.98 * double(line.size()));
  expectValidationSilent();
}

// Cut-outs: exact mode tests a cut-out triangle's alpha at the hit as the BVH does, so the
// checker's holes let light through and the frame is the reference's; binary mode's shafts hold
// the triangle whole (a documented approximation) and shadow the holes.
TEST(LineSpaceTracer, ExactShadowsPassThroughCutouts) {
  test::SceneRun binaryRun("builtin:checker", lsSettings(192, 1));
  test::SceneRun exactRun("builtin:checker", lsSettings(192, 1, exactLineSpace()));
  const Frame r = exactRun.render("ref");
  const ErrorMetrics exact = compareVisibility(exactRun.render("ls").visibility, r.visibility, r.covered, kWrongThresholdHard);
  const Frame binaryFrame = binaryRun.render("ls");
  const ErrorMetrics binary = compareVisibility(binaryFrame.visibility, r.visibility, r.covered, kWrongThresholdHard);
  EXPECT_TRUE(test::hasNote(binaryFrame, "cut-outs solid")) << "the frame says so";
  std::printf("checker, ls (5,3) hard vs ref: exact wrong %.4f%%, binary wrong %.4f%%\n", 100.0 * exact.wrongPixelFraction,
              100.0 * binary.wrongPixelFraction);
  EXPECT_EQ(exact.wrongPixelFraction, 0.0);
  EXPECT_GT(binary.wrongPixelFraction, 0.005) << "binary mode shadows the holes";
  expectValidationSilent();
}

// The contact scene of StartNodeSkipLosesContactShadowsOnly: exact mode does not skip the start
// node, so the box's contact shadow is back and the answer is the BVH's (frt, the same rays).
TEST(LineSpaceTracer, ExactShadowsAgreeWithTheBvhAndKeepContactShadows) {
  const Scene scene = contactScene();
  const std::uint32_t size = 192;
  RenderSettings settings = lsSettings(size, 1, exactLineSpace({4, 3, 0}));
  settings.tracer = "bvh";
  Renderer renderer(validatedContext(), scene, settings);
  const Frame frt = renderer.render("frt", *scene.camera, scene.lights.front());
  const Frame exact = renderer.render("ls", *scene.camera, scene.lights.front());
  Renderer binaryRenderer(validatedContext(), scene, lsSettings(size, 1, {4, 3, 0}));
  const Frame binary = binaryRenderer.render("ls", *scene.camera, scene.lights.front());
  std::size_t dark = 0, binaryLost = 0, exactLost = 0;
  for (std::size_t i = 0; i < frt.visibility.size(); ++i) {
    if (!frt.covered[i] || frt.visibility[i] >= 0.5f) continue;
    ++dark;
    binaryLost += binary.visibility[i] >= 0.5f;
    exactLost += exact.visibility[i] >= 0.5f;
  }
  const double wrongExact = test::differingPixels(exact, frt), wrongBinary = test::differingPixels(binary, frt);
  const double rays = double(*exact.stats.raysTraced);
  std::printf("contact scene (4,3), 1 spp vs frt (bvh): %zu shadow px; binary loses %zu, wrong %.5f; exact loses %zu, "
              "wrong %.5f; exact %.2f visits/ray, %.2f triangle tests/ray\n",
              dark, binaryLost, wrongBinary, exactLost, wrongExact, double(*exact.stats.nodeVisits) / rays,
              double(*exact.stats.triangleTests) / rays);
  ASSERT_EQ(frt.stats.tracer, "bvh");
  EXPECT_EQ(*exact.stats.raysTraced, *frt.stats.raysTraced);
  ASSERT_GT(dark, 400u);
  EXPECT_GT(binaryLost, 0u) << "binary mode loses the contact shadow";
  // The same rays as frt and the BVH's triangle test on the same device: the same answers.
  EXPECT_EQ(exactLost, 0u) << "exact mode keeps it";
  EXPECT_EQ(wrongExact, 0.0);
  expectValidationSilent();
}

// srt on --tracer ls in exact mode traces its PIP rays as exactly as on the BVH: the same image.
TEST(LineSpaceTracer, SrtOnTheExactLineSpaceMatchesSrtOnTheBvh) {
  Frame frames[3];
  for (int i = 0; i < 3; ++i) {
    RenderSettings settings = lsSettings(128, 9, i == 2 ? LineSpaceSettings{5, 3, 0} : exactLineSpace());
    settings.tracer = i == 0 ? "bvh" : "ls";
    test::SceneRun run("builtin:courtyard", settings);
    run.light.size = 0.1f * run.scene.bounds().radius();
    frames[i] = run.render("srt");
    if (i == 1) {
      EXPECT_EQ(run.render("srt").visibility, frames[i].visibility) << "bit-identical runs";
    }
  }
  const double exactWrong = test::differingPixels(frames[1], frames[0]);
  const double binaryWrong = test::differingPixels(frames[2], frames[0]);
  std::printf("srt, courtyard 9 spp: tracer ls exact vs bvh differ on %.5f of pixels, binary on %.5f; exact %.2f "
              "triangle tests/ray\n",
              exactWrong, binaryWrong, double(*frames[1].stats.triangleTests) / double(*frames[1].stats.raysTraced));
  ASSERT_EQ(frames[1].stats.tracer, "ls");
  EXPECT_EQ(*frames[1].stats.raysTraced, *frames[0].stats.raysTraced) << "the same PIP rays";
  EXPECT_EQ(exactWrong, 0.0) << "the BVH's triangle test on the same PIP rays";
  EXPECT_LT(exactWrong, binaryWrong);
  expectValidationSilent();
}

// The two-level path: the drone (moving, on its own BVH or ray queries) beside the exact line
// space over the static meshes; before and after it moves, the same shadows as frt on the BVH
// (the same rays and triangle test: identical). Ray queries are skipped, and said so, on a device
// without them.
class ExactLineSpaceMovers : public ::testing::TestWithParam<LineSpaceSettings::Moving> {};

TEST_P(ExactLineSpaceMovers, MatchTheBvhBeforeAndAfterTheMove) {
  const LineSpaceSettings::Moving moving = GetParam();
  if (moving == LineSpaceSettings::Moving::RayQuery && !validatedContext().rayQuery())
    GTEST_SKIP() << validatedContext().driverInfo() << " has no ray queries: the movers on rq not tested";
  RenderSettings settings = lsSettings(128, 1, exactLineSpace({4, 2, 0}));
  settings.lineSpace.movingTracer = moving;
  settings.tracer = "bvh";
  test::SceneRun run("builtin:courtyard-moving:1", settings);
  for (int pose = 0; pose < 2; ++pose) {
    if (pose == 1) {
      poseScene(run.scene, 2.3);
      run.renderer->sceneMoved();
    }
    const Frame frt = run.render("frt");
    const Frame ls = run.render("ls");
    const double wrong = test::differingPixels(ls, frt);
    std::printf("courtyard-moving, exact ls (moving on %s), pose %d: differs from frt on %.5f of pixels\n",
                moving == LineSpaceSettings::Moving::Bvh ? "bvh" : "ray queries", pose, wrong);
    EXPECT_EQ(wrong, 0.0) << "pose " << pose;
  }
  expectValidationSilent();
}

INSTANTIATE_TEST_SUITE_P(Movers, ExactLineSpaceMovers,
                         ::testing::Values(LineSpaceSettings::Moving::Bvh, LineSpaceSettings::Moving::RayQuery),
                         [](const auto& info) { return info.param == LineSpaceSettings::Moving::Bvh ? "bvh" : "rq"; });

}  // namespace
}  // namespace penumbra
