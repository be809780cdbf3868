// Method bitmask (Eisemann & Décoret 2007): the Hough table against direct left-of-line tests, the
// receiver's visibility against the Embree reference with the same samples (--shared-samples), the
// paper's worst case (a large light close to the casters), casters crossing the receiver or lying
// level with the light, and bad input.
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "bounds.h"
#include "core/gpu_light.h"
#include "core/planar_receivers.h"
#include "core/mesh_builder.h"
#include "core/metrics.h"
#include "hybrid/patch_visibility.h"
#include "raster/bitmask_pass.h"
#include "tests/embree_rays.h"
#include "tests/mesh_checks.h"
#include "tests/render_fixture.h"

namespace penumbra::test {
namespace {

// Every bin's mask is the set of samples left of the bin's centre line (a sample within float
// rounding of it may go either way: the second half of the directions holds the complement of the
// first, houghOpposite); and a line binned by
// houghBin keeps every sample farther from it than the bin's quantization on its own side.
TEST(Bitmask, HoughTableMatchesLeftOfLineTests) {
  gpu::Context& context = validatedContext();
  raster::BitmaskTable hough(context);
  for (const Light& l : {Light{.type = LightType::Rect, .position = {0, 3, 0}, .size = 1.0f},
                         Light{.type = LightType::Disk, .position = {0, 3, 0}, .size = 1.0f}}) {
    for (std::uint32_t samples : {32u, 100u, 1024u}) {
      SCOPED_TRACE(std::to_string(samples) + " samples, light type " + std::to_string(int(l.type)));
      shared::GpuLight light = toGpuLight(l, Bounds{{-1, -1, -1}, {1, 1, 1}}, 1e-4f);
      light.sharedPattern = 1;
      context.submitAndWait([&](const vk::raii::CommandBuffer& cmd) { hough.record(cmd, light, samples); });
      const std::uint32_t words = hough.words();
      const auto table = hough.buffer().download<std::uint32_t>(std::size_t(BITMASK_THETA_BINS) * BITMASK_R_BINS * words);
      std::vector<glm::vec2> q(samples);
      for (std::uint32_t s = 0; s < samples; ++s) q[s] = shared::lightSampleOnLight(light, 0, s, samples);
      std::size_t wrongBits = 0;
      for (std::uint32_t bin = 0; bin < BITMASK_THETA_BINS * BITMASK_R_BINS; bin += 97) {  // every 97th bin
        const glm::vec3 line = shared::houghBinLine(bin / BITMASK_R_BINS, bin % BITMASK_R_BINS);
        for (std::uint32_t s = 0; s < words * 32; ++s) {
          const bool set = (table[std::size_t(bin) * words + s / 32] >> (s % 32)) & 1u;
          if (s < samples && std::abs(glm::dot(q[s], glm::vec2(line)) - line.z) < 1e-5f) continue;  // on the line (float)
          wrongBits += set != (s < samples && glm::dot(q[s], glm::vec2(line)) > line.z);
        }
      }
      EXPECT_EQ(wrongBits, 0u);
      // Random lines: a sample more than one bin's reach from the line is on the side its bin says.
      const float reach = BITMASK_R_MAX / float(BITMASK_R_BINS) + BITMASK_R_MAX * 3.14159265f / float(BITMASK_THETA_BINS);
      std::mt19937 rng(7);
      std::uniform_real_distribution<float> u(-0.8f, 0.8f);
      std::size_t far = 0, misplaced = 0;
      for (int k = 0; k < 2000; ++k) {
        const glm::vec2 a(u(rng), u(rng)), b(u(rng), u(rng));
        if (glm::length(b - a) < 1e-3f) continue;
        const glm::vec2 line = shared::houghLine(a, b);
        if (std::abs(line.y) >= BITMASK_R_MAX) continue;
        const std::uint32_t bin = shared::houghBin(line);
        const glm::vec2 left = glm::vec2(-(b - a).y, (b - a).x) / glm::length(b - a);
        for (std::uint32_t s = 0; s < samples; ++s) {
          const float side = glm::dot(q[s], left) - line.y;
          if (std::abs(side) <= reach) continue;
          ++far;
          misplaced += (((table[std::size_t(bin) * words + s / 32] >> (s % 32)) & 1u) != 0) != (side > 0.0f);
        }
      }
      EXPECT_GT(far, 1000u);
      EXPECT_EQ(misplaced, 0u);
    }
  }
  expectValidationSilent();
}

// A ground under casters of several kinds: a floating square, a thin bar, a triangle piercing the
// ground (its part below must be clipped off), a long beam slanting across the scene, and a quad
// above the light (level with it: it cannot shadow the ground).
Scene bitmaskScene() {
  Mesh ground = namedMesh("ground"), casters = namedMesh("casters");
  mesh::addQuad(ground, {-3, 0, -3}, {3, 0, -3}, {3, 0, 3}, {-3, 0, 3}, {0, 1, 0});
  mesh::addQuad(casters, {-1.2f, 1.0f, -1.2f}, {-0.2f, 1.0f, -1.2f}, {-0.2f, 1.0f, -0.2f}, {-1.2f, 1.0f, -0.2f}, {0, 1, 0});
  mesh::addBox(casters, {0.8f, 0.6f, 0.3f}, {0.02f, 0, 0}, {0, 0.02f, 0}, {0, 0, 1.0f});
  casters.positions.insert(casters.positions.end(), {{0.2f, -0.5f, 1.0f}, {1.2f, -0.5f, 1.4f}, {0.6f, 1.2f, 1.2f}});
  casters.normals.insert(casters.normals.end(), 3, glm::normalize(glm::vec3(-0.4f, 0.0f, 1.0f)));
  const std::uint32_t first = std::uint32_t(casters.positions.size()) - 3;
  casters.indices.insert(casters.indices.end(), {first, first + 1, first + 2});
  mesh::addBox(casters, {0.0f, 1.4f, -1.6f}, {2.0f, 1.0f, 0.0f}, {0.0f, 0.03f, 0.0f}, {0.0f, 0.0f, 0.05f});
  mesh::addQuad(casters, {-0.3f, 3.5f, -0.3f}, {0.3f, 3.5f, -0.3f}, {0.3f, 3.5f, 0.3f}, {-0.3f, 3.5f, 0.3f}, {0, -1, 0});
  Scene scene = sceneOf({ground, casters}, "bitmask");
  scene.camera = Camera{.eye = {0, 5, 5}, .target = {0, 0, 0}};
  scene.lights.push_back(Light{.type = LightType::Disk, .position = {0, 3, 0}, .size = 0.5f});
  return scene;
}

struct Compared {
  double wrongOnReceiver = 0.0, rmseOnReceiver = 0.0;
  std::size_t receiverPixels = 0, otherWrong = 0;
  double traced = 0.0;  // of covered pixels, the fallback's
};

Compared compareWithReference(const Light& light, std::uint32_t spp, const std::string& fallback = "srt") {
  RenderSettings settings = smallSettings(128);
  settings.bitmask.fallback = fallback;
  settings.spp = spp;
  settings.sharedSamples = true;  // the reference traces bitmask's samples
  settings.bitmask.resolution = 1024;  // texels far smaller than pixels: the footprint error is small
  SceneRun run(bitmaskScene(), settings);
  const Frame reference = run.renderer->render("ref", run.camera, light);
  const Frame bitmask = run.renderer->render("bitmask", run.camera, light);
  const auto positions = run.renderer->frameContext().gbuffer().positions();
  Compared c;
  double squares = 0.0;
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (!reference.covered[i]) continue;
    const float d = bitmask.visibility[i] - reference.visibility[i];
    if (std::abs(positions[i].y) < 1e-3f) {  // the ground
      ++c.receiverPixels;
      squares += double(d) * d;
      wrong += std::abs(d) > 0.05f;
    } else {
      c.otherWrong += std::abs(d) > 0.05f;
    }
  }
  c.wrongOnReceiver = double(wrong) / double(c.receiverPixels);
  c.rmseOnReceiver = std::sqrt(squares / double(c.receiverPixels));
  c.traced = *bitmask.stats.pipFraction;
  return c;
}

// On the ground bitmask gives the reference's visibility up to the texel footprint (the map is
// evaluated at texel centres: 1024^2 texels over the ground's visible part, about 4 per pixel
// along each axis at 128^2) and the Hough table's binning (samples within ~0.003 light sizes of
// an edge's line); the other pixels are answered by srt or frt with the same samples and equal the
// reference (srt tracing fewer of them).
// Bounds: tests/bounds.h (kBitmaskWrong, kBitmaskRmse).
TEST(Bitmask, ReceiverMatchesTheReferenceWithTheSameSamples) {
  const Light light{.type = LightType::Disk, .position = {0.4f, 3.0f, 0.3f}, .direction = glm::normalize(glm::vec3(-0.1f, -1, -0.1f)), .size = 0.8f};
  for (std::uint32_t spp : {32u, 128u}) {
    double traced[2] = {0.0, 0.0};
    for (int k = 0; k < 2; ++k) {
      const std::string fallback = k == 0 ? "frt" : "srt";
      SCOPED_TRACE(std::to_string(spp) + " samples, fallback " + fallback);
      const Compared c = compareWithReference(light, spp, fallback);
      std::cout << spp << " spp, " << fallback << ": ground " << c.receiverPixels << " px, wrong " << c.wrongOnReceiver
                << ", rmse " << c.rmseOnReceiver << "; traced " << c.traced << "\n";
      ASSERT_GT(c.receiverPixels, 5000u);
      EXPECT_LE(c.wrongOnReceiver, bound::kBitmaskWrong);
      EXPECT_LE(c.rmseOnReceiver, bound::kBitmaskRmse);
      EXPECT_EQ(c.otherWrong, 0u);
      // Only the casters' pixels are traced: measured 5.6% of the covered pixels with frt, 0.22% with srt.
      EXPECT_LT(c.traced, k == 0 ? 0.17 : 0.0067);
      traced[k] = c.traced;
    }
    EXPECT_LT(traced[1], traced[0]) << "srt traces only the casters' doubtful pixels";
  }
  expectValidationSilent();
}

// The paper's worst case: a light three times the casters' size just above them. Influence
// regions cover most of the map, and the answer stays the reference's.
TEST(Bitmask, LargeLightCloseToTheCastersStaysCorrect) {
  const Light light{.type = LightType::Rect, .position = {0.0f, 1.8f, 0.0f}, .direction = {0, -1, 0}, .size = 3.0f};
  const Compared c = compareWithReference(light, 64);
  std::cout << "large light: ground wrong " << c.wrongOnReceiver << ", rmse " << c.rmseOnReceiver << "\n";
  EXPECT_LE(c.wrongOnReceiver, bound::kBitmaskWrong);
  EXPECT_LE(c.rmseOnReceiver, bound::kBitmaskRmse);
  EXPECT_EQ(c.otherWrong, 0u);
  expectValidationSilent();
}

TEST(Bitmask, BadInputIsRefused) {
  RenderSettings settings = smallSettings(64);
  SceneRun run(bitmaskScene(), settings);
  const Light point{.type = LightType::Point, .position = {0, 3, 0}};
  EXPECT_THROW(run.renderer->render("bitmask", run.camera, point), InputError);  // no area
  const Light below{.type = LightType::Disk, .position = {0, 0.1f, 0}, .direction = {1, 0, 0}, .size = 0.5f};
  EXPECT_THROW(run.renderer->render("bitmask", run.camera, below), InputError);  // the light on the receiver
  settings.spp = 2048;
  SceneRun many(bitmaskScene(), settings);
  const Light disk{.type = LightType::Disk, .position = {0, 3, 0}, .size = 0.5f};
  EXPECT_THROW(many.renderer->render("bitmask", many.camera, disk), InputError);  // more samples than a map holds
  settings.spp = 16;
  settings.bitmask.receivers = {"no such mesh"};
  SceneRun named(bitmaskScene(), settings);
  EXPECT_THROW(named.renderer->render("bitmask", named.camera, disk), InputError);
  Mesh box = namedMesh("box");
  mesh::addBox(box, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
  Scene boxOnly = sceneOf({box}, "box");
  boxOnly.camera = Camera{.eye = {0, 4, 4}, .target = {0, 0, 0}};
  boxOnly.lights.push_back(Light{.type = LightType::Disk, .position = {0, 5, 0}, .size = 0.5f});
  settings.bitmask.receivers.clear();
  SceneRun noPlane(std::move(boxOnly), settings);
  EXPECT_THROW(noPlane.renderer->render("bitmask", noPlane.camera, Light{.type = LightType::Disk, .position = {0, 5, 0}, .size = 0.5f}), InputError);
  expectValidationSilent();
}

}  // namespace
}  // namespace penumbra::test

namespace penumbra::test {
namespace {

// Patch-to-patch visibility between two 4x4 rectangles 2 apart, 32x32 samples each: open (the
// blocker lies beside them), half blocked (a quad over half of the target), fully blocked (one
// over all of it). The fraction of unblocked pairs is within 1/1024 (one source sample's share)
// of Embree's, tracing every pair of the same sample points.
TEST(Bitmask, PatchToPatchVisibilityMatchesEmbree) {
  const Patch from{{-2, 2, -2}, {4, 0, 0}, {0, 0, 4}}, to{{-2, 0, -2}, {4, 0, 0}, {0, 0, 4}};
  struct Case {
    const char* name;
    glm::vec3 lo, hi;  // the blocking quad's corners at y = 1
    double expected;   // roughly
  };
  for (const Case& c : {Case{"open", {5, 1, -1}, {7, 1, 1}, 1.0}, Case{"half", {-3, 1, -3}, {0, 1, 3}, 0.5},
                        Case{"full", {-5, 1, -5}, {5, 1, 5}, 0.0}}) {
    SCOPED_TRACE(c.name);
    Mesh blocker = namedMesh("blocker");
    mesh::addQuad(blocker, {c.lo.x, 1, c.lo.z}, {c.hi.x, 1, c.lo.z}, {c.hi.x, 1, c.hi.z}, {c.lo.x, 1, c.hi.z}, {0, 1, 0});
    const Scene scene = sceneOf({blocker}, c.name);
    const std::uint32_t n = 32;
    const PatchVisibility v = patchVisibility(validatedContext(), scene, from, to, n);
    const EmbreeRays rays(scene, validatedContext());
    std::uint64_t unblocked = 0, disagree = 0;
    for (std::uint32_t i = 0; i < n * n; ++i) {
      const glm::vec3 target = targetSample(to, n, i);
      for (std::uint32_t s = 0; s < n * n; ++s) {
        const glm::vec3 source = sourceSample(from, to, n, s);
        const bool blocked = rays.occluded({target, 1e-4f, source - target, 1.0f - 1e-4f});
        unblocked += !blocked;
        disagree += blocked != v.blocked(i, s);
      }
    }
    const double embree = double(unblocked) / double(v.pairs);
    std::cout << c.name << ": bitmask " << v.fraction() << ", embree " << embree << ", pairs that differ " << disagree << "\n";
    EXPECT_NEAR(v.fraction(), c.expected, 0.05);
    // Measured 0 / 6.1e-5 / 0 (960 of 1M pairs differ where the blocker's edge cuts the rectangles).
    EXPECT_NEAR(v.fraction(), embree, bound::kPatchVisibility);
  }
  // Patches that cross each other's plane, or too many samples, are refused.
  Mesh aside = namedMesh("aside");
  mesh::addQuad(aside, {5, 1, -1}, {7, 1, -1}, {7, 1, 1}, {5, 1, 1}, {0, 1, 0});
  const Scene scene = sceneOf({aside}, "aside");
  EXPECT_THROW(patchVisibility(validatedContext(), scene, from, Patch{{-2, 3, -2}, {4, 0, 0}, {0, -2, 0}}, 8), InputError);
  EXPECT_THROW(patchVisibility(validatedContext(), scene, from, to, 33), InputError);
  EXPECT_THROW(parsePatch("0,0,0:1,0,0:1,1,0"), InputError);  // edges not perpendicular
  expectValidationSilent();
}

}  // namespace
}  // namespace penumbra::test

namespace penumbra::test {
namespace {

// Watertight casters (a box and a sphere, closed and wound outward): dropping the triangles that
// face the whole light leaves the shadows as they were (their back faces cast them) and cuts the
// fill; on an open surface (a lone quad facing the light) it drops the shadow, which is why it is
// an option.
TEST(Bitmask, WatertightCullingKeepsClosedCastersShadows) {
  auto run = [](bool closed, bool watertight) {
    Mesh ground = namedMesh("ground"), casters = namedMesh("casters");
    mesh::addQuad(ground, {-3, 0, -3}, {3, 0, -3}, {3, 0, 3}, {-3, 0, 3}, {0, 1, 0});
    if (closed) {
      mesh::addBox(casters, {-0.8f, 0.8f, 0.0f}, {0.4f, 0, 0}, {0, 0.3f, 0}, {0, 0, 0.5f});
      mesh::addSphere(casters, {0.9f, 1.0f, 0.3f}, 0.5f, 24, 12);
    } else {
      mesh::addQuad(casters, {-0.5f, 1, -0.5f}, {0.5f, 1, -0.5f}, {0.5f, 1, 0.5f}, {-0.5f, 1, 0.5f}, {0, 1, 0});
    }
    Scene scene = sceneOf({ground, casters}, "watertight");
    scene.camera = Camera{.eye = {0, 5, 5}, .target = {0, 0, 0}};
    scene.lights.push_back(Light{.type = LightType::Rect, .position = {0.3f, 3, 0.2f}, .direction = {0, -1, 0}, .size = 1.0f});
    RenderSettings settings = smallSettings(128);
    settings.spp = 64;
    settings.bitmask.watertight = watertight;
    SceneRun r(std::move(scene), settings);
    return r.render("bitmask");
  };
  const Frame all = run(true, false), culled = run(true, true);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < all.visibility.size(); ++i) differ += std::abs(all.visibility[i] - culled.visibility[i]) > 0.05f;
  const auto fill = [](const Frame& f) { return f.stats.counts.at("bitmask_fill_texels"); };
  std::cout << "closed casters: " << differ << " pixels differ by > 0.05, fill " << fill(all) << " -> " << fill(culled) << "\n";
  EXPECT_EQ(differ, 0u);  // measured: none (the closed casters' back faces cover what the front faces do)
  EXPECT_LT(fill(culled), fill(all) * 3 / 4);
  const Frame open = run(false, false), openCulled = run(false, true);
  double darkOpen = 0.0, darkCulled = 0.0;
  for (std::size_t i = 0; i < open.visibility.size(); ++i) {
    darkOpen += 1.0 - open.visibility[i];
    darkCulled += 1.0 - openCulled.visibility[i];
  }
  EXPECT_GT(darkOpen, 100.0);
  EXPECT_LT(darkCulled, 0.01 * darkOpen) << "a lone quad facing the light is dropped: the option is for closed casters";
  expectValidationSilent();
}

}  // namespace
}  // namespace penumbra::test

namespace penumbra::test {
namespace {

// Decorrelation: each texel sees the pattern under one of the light square's symmetries, so the
// pattern's aliasing between texels becomes noise that the bilinear resolve averages. Against the
// converged reference (512 samples per pixel, each pixel its own pattern) 32 decorrelated samples
// are closer on the ground than 32 shared ones.
TEST(Bitmask, DecorrelationBringsFewSamplesCloserToTheConvergedAnswer) {
  const Light light{.type = LightType::Disk, .position = {0.4f, 3.0f, 0.3f}, .direction = glm::normalize(glm::vec3(-0.1f, -1, -0.1f)), .size = 0.8f};
  auto groundRmse = [&](bool decorrelate) {
    RenderSettings settings = smallSettings(128);
    settings.spp = 32;
    settings.referenceSpp = 512;
    settings.bitmask.decorrelate = decorrelate;
    SceneRun run(bitmaskScene(), settings);
    const Frame reference = run.renderer->render("ref", run.camera, light);
    const Frame bitmask = run.renderer->render("bitmask", run.camera, light);
    const auto positions = run.renderer->frameContext().gbuffer().positions();
    double squares = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < positions.size(); ++i) {
      if (!reference.covered[i] || std::abs(positions[i].y) >= 1e-3f) continue;
      const double d = bitmask.visibility[i] - reference.visibility[i];
      squares += d * d;
      ++n;
    }
    return std::sqrt(squares / double(n));
  };
  const double shared = groundRmse(false), decorrelated = groundRmse(true);
  std::cout << "ground rmse vs 512 spp: shared pattern " << shared << ", decorrelated " << decorrelated << "\n";
  EXPECT_LT(decorrelated, shared);
  expectValidationSilent();
}

}  // namespace
}  // namespace penumbra::test

namespace penumbra::test {
namespace {

// Several receivers: a ground and a wall, each with its own map; the shadows on both match the
// reference with the same samples, and fewer pixels fall back to tracing than with the ground alone.
TEST(Bitmask, GroundAndWallEachGetAMap) {
  Mesh ground = namedMesh("ground"), wall = namedMesh("wall"), casters = namedMesh("casters");
  mesh::addQuad(ground, {-3, 0, -2}, {3, 0, -2}, {3, 0, 3}, {-3, 0, 3}, {0, 1, 0});
  mesh::addQuad(wall, {-3, 0, -2}, {3, 0, -2}, {3, 3, -2}, {-3, 3, -2}, {0, 0, 1});
  mesh::addBox(casters, {-0.5f, 1.2f, -1.2f}, {0.4f, 0, 0}, {0, 0.4f, 0}, {0, 0, 0.3f});
  mesh::addBox(casters, {1.0f, 0.6f, 0.5f}, {0.2f, 0, 0}, {0, 0.6f, 0}, {0, 0, 0.2f});
  Scene scene = sceneOf({ground, wall, casters}, "ground and wall");
  scene.camera = Camera{.eye = {1.5f, 2.5f, 5.0f}, .target = {0, 0.8f, -1}};
  scene.lights.push_back(Light{.type = LightType::Disk, .position = {0.5f, 3.5f, 2.5f},
                               .direction = glm::normalize(glm::vec3(-0.3f, -1.0f, -1.0f)), .size = 0.8f});
  auto run = [&](std::vector<std::string> receivers) {
    RenderSettings settings = smallSettings(128);
    settings.spp = 64;
    settings.sharedSamples = true;
    settings.bitmask.resolution = 1024;
    settings.bitmask.fallback = "frt";  // every pixel off the receivers traced: their count shows
    settings.bitmask.receivers = std::move(receivers);
    SceneRun r(Scene(scene), settings);
    return std::pair{r.render("ref"), r.render("bitmask")};
  };
  const auto [reference, both] = run({});  // detected: the ground and the wall
  const auto [reference1, groundOnly] = run({"ground"});
  const double wrong = compareVisibility(both.visibility, reference.visibility, reference.covered, 0.05f).wrongPixelFraction;
  std::cout << "ground and wall: wrong " << wrong << ", traced " << *both.stats.pipFraction << " (ground only: "
            << *groundOnly.stats.pipFraction << "); " << both.stats.notes.front() << "\n";
  EXPECT_NE(both.stats.notes.front().find("'wall'"), std::string::npos);
  EXPECT_LE(wrong, bound::kBitmaskTwoReceiversWrong);
  // Measured 7.2% of the pixels traced, 55% with the ground's map alone.
  EXPECT_LT(*both.stats.pipFraction, 0.3 * *groundOnly.stats.pipFraction) << "the wall's pixels use its map";
  expectValidationSilent();
}

}  // namespace
}  // namespace penumbra::test

namespace penumbra::test {
namespace {

// A height-field receiver (the paper's extension): a rolling terrain under a floating box and a
// pole, named with --bitmask-receivers. Each map texel's receiver point lies on the terrain, so
// its shadows match the reference with the same samples (hills shadow themselves too; a texel's
// surface is its centre's height, a facet's plane between the centres); the other pixels are srt's.
TEST(Bitmask, HeightFieldReceiverMatchesTheReference) {
  const auto height = [](float x, float z) { return 0.25f * std::sin(1.3f * x) * std::cos(1.1f * z) + 0.25f; };
  Mesh terrain = namedMesh("terrain"), casters = namedMesh("casters");
  const int cells = 48;
  for (int j = 0; j <= cells; ++j) {
    for (int i = 0; i <= cells; ++i) {
      const float x = -3.0f + 6.0f * float(i) / cells, z = -3.0f + 6.0f * float(j) / cells;
      terrain.positions.push_back({x, height(x, z), z});
      terrain.normals.push_back({0, 1, 0});
    }
  }
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      const std::uint32_t a = j * (cells + 1) + i, b = a + 1, c = a + cells + 1, d = c + 1;
      terrain.indices.insert(terrain.indices.end(), {a, c, b, b, c, d});  // counter-clockwise seen from above
    }
  }
  mesh::addBox(casters, {-0.6f, 1.6f, 0.2f}, {0.5f, 0, 0}, {0, 0.2f, 0}, {0, 0, 0.4f});
  mesh::addCylinder(casters, {1.0f, 0.3f, -0.5f}, {1.0f, 1.8f, -0.5f}, 0.08f, 12);
  Scene scene = sceneOf({terrain, casters}, "terrain");
  scene.camera = Camera{.eye = {0, 4.5f, 4.5f}, .target = {0, 0.3f, 0}};
  scene.lights.push_back(Light{.type = LightType::Disk, .position = {0.8f, 3.5f, 0.6f},
                               .direction = glm::normalize(glm::vec3(-0.2f, -1, -0.2f)), .size = 0.6f});
  RenderSettings settings = smallSettings(128);
  settings.spp = 64;
  settings.sharedSamples = true;
  settings.bitmask.resolution = 1024;
  settings.bitmask.receivers = {"terrain"};
  SceneRun run(std::move(scene), settings);
  const Frame reference = run.render("ref");
  const Frame bitmask = run.render("bitmask");
  const auto positions = run.renderer->frameContext().gbuffer().positions();
  std::size_t onTerrain = 0, wrong = 0;
  double squares = 0.0;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (!reference.covered[i]) continue;
    const float d = bitmask.visibility[i] - reference.visibility[i];
    if (std::abs(positions[i].y - height(positions[i].x, positions[i].z)) < 0.02f) {
      ++onTerrain;
      squares += double(d) * d;
    }
    wrong += std::abs(d) > 0.05f;
  }
  const double covered = double(std::count(reference.covered.begin(), reference.covered.end(), std::uint8_t(1)));
  std::cout << "terrain: " << onTerrain << " px, rmse " << std::sqrt(squares / double(onTerrain)) << "; wrong "
            << double(wrong) / covered << ", traced " << *bitmask.stats.pipFraction << "; " << bitmask.stats.notes.front() << "\n";
  ASSERT_GT(onTerrain, 8000u);
  EXPECT_NE(bitmask.stats.notes.front().find("height field"), std::string::npos);
  EXPECT_LE(double(wrong) / covered, bound::kBitmaskTerrainWrong);
  EXPECT_LE(std::sqrt(squares / double(onTerrain)), bound::kBitmaskTerrainRmse);
  EXPECT_LT(*bitmask.stats.pipFraction, 0.13) << "the terrain's pixels use the map (measured 4.4% traced)";
  // A mesh that folds over itself is no height field.
  Mesh box = namedMesh("box");
  mesh::addBox(box, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
  EXPECT_FALSE(findHeightField(sceneOf({box}, "box"), "box"));
  expectValidationSilent();
}

}  // namespace
}  // namespace penumbra::test
