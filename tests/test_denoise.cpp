// The shadow denoiser (issue 23) on few-sample soft shadows, judged against the converged Embree
// reference (256 samples): a sequence of one-sample frames, denoised over time, comes closer to it
// than undenoised frames with four times the samples; contact shadows stay sharp (the filter's
// radius is bounded by the penumbra's width); a light that moves and stops leaves no trail; a
// camera cut does not carry one surface's shadow onto another; a frame is deterministic.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "core/mesh_builder.h"
#include "core/metrics.h"
#include "core/view.h"
#include "mesh_checks.h"
#include "render_fixture.h"
#include "shared/denoise.h"

namespace penumbra::test {
namespace {

constexpr std::uint32_t kSize = 192;
constexpr std::uint32_t kReferenceSpp = 256;

RenderSettings denoiseSettings(std::uint32_t spp, DenoiseMode mode, std::uint32_t referenceSpp = kReferenceSpp) {
  RenderSettings s = smallSettings(kSize, 2048);
  s.spp = spp;
  s.referenceSpp = referenceSpp;
  s.denoise.mode = mode;
  return s;
}

// Frames `first` .. `first + count - 1` of a sequence of `method`; the last one.
Frame renderFrames(Renderer& renderer, const std::string& method, const Camera& camera, const Light& light,
                   std::uint32_t first, std::uint32_t count) {
  Frame last;
  for (std::uint32_t i = first; i < first + count; ++i) {
    renderer.setFrame(i);
    last = renderer.render(method, camera, light);
  }
  return last;
}

// The courtyard with a disk light a tenth of the scene radius wide.
struct SoftCourtyard : SceneRun {
  explicit SoftCourtyard(const RenderSettings& settings) : SceneRun("builtin:courtyard", settings) {
    applyLightSize(light, 0.1f, scene.bounds());
  }
  Frame sequence(const std::string& method, std::uint32_t first, std::uint32_t count, const Light& at) {
    return renderFrames(*renderer, method, camera, at, first, count);
  }
};

// Frames 0 .. frames - 1 of `method` on a scene built in the test; the last one.
Frame sequenceOf(const Scene& scene, const Camera& camera, const Light& light, const RenderSettings& settings,
                 const std::string& method, std::uint32_t frames) {
  Renderer renderer(validatedContext(), scene, settings);
  return renderFrames(renderer, method, camera, light, 0, frames);
}

// A disk light `size` radii wide up and to the left of the ground.
Light diskLight(const Scene& scene, float size = 0.15f) {
  Light light;
  light.type = LightType::Disk;
  light.position = {-6.0f, 8.0f, -3.0f};
  light.direction = glm::normalize(-light.position);
  applyLightSize(light, size, scene.bounds());
  return light;
}

Mesh groundMesh() {
  Mesh ground = namedMesh("ground");
  mesh::addGrid(ground, {-6.0f, 0.0f, 6.0f}, {12.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -12.0f}, 8, 8, {0.0f, 1.0f, 0.0f});
  return ground;
}

const Camera kGroundCamera{{5.0f, 6.0f, 7.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 45.0f};

ErrorMetrics against(const Frame& frame, const Frame& reference) {
  return compareVisibility(frame.visibility, reference.visibility, reference.covered, kWrongThresholdSoft);
}

TEST(Denoise, OneSampleSequenceBeatsFourUndenoisedSamples) {
  SoftCourtyard converged(denoiseSettings(1, DenoiseMode::Off));
  const Frame reference = converged.render("ref");
  const double oneRaw = against(converged.render("srt"), reference).rmse;
  SoftCourtyard four(denoiseSettings(4, DenoiseMode::Off));
  const double fourRaw = against(four.render("srt"), reference).rmse;
  SoftCourtyard temporal(denoiseSettings(1, DenoiseMode::Temporal));
  const Frame srt = temporal.sequence("srt", 0, 8, temporal.light);
  const Frame frt = temporal.sequence("frt", 0, 8, temporal.light);
  SoftCourtyard spatial(denoiseSettings(1, DenoiseMode::Spatial));
  const double oneSpatial = against(spatial.render("srt"), reference).rmse;
  std::cout << "rmse vs 256 spp: srt 1 spp " << oneRaw << ", 4 spp " << fourRaw << ", 1 spp spatial " << oneSpatial
            << ", 1 spp temporal (8th frame) srt " << against(srt, reference).rmse << " frt " << against(frt, reference).rmse
            << "\n";
  EXPECT_EQ(srt.stats.denoise, "temporal");
  EXPECT_LT(oneSpatial, oneRaw);
  EXPECT_LT(against(srt, reference).rmse, fourRaw);
  EXPECT_LT(against(frt, reference).rmse, fourRaw);
  expectValidationSilent();
}

// Where every pixel is noisy (frt), most of the courtyard is wholly lit or in umbra around each
// pixel: the spatial filter leaves those pixels as they are, reading only its tiles' value ranges.
// Filtering them all the same gives the same frames, up to DENOISE_UNIFORM (and float rounding).
TEST(Denoise, SkippingAgreeingPixelsChangesNothing) {
  std::vector<float> frames[2];
  for (const bool skip : {false, true}) {
    RenderSettings settings = denoiseSettings(1, DenoiseMode::Temporal);
    settings.denoise.skipAgreeing = skip;
    SoftCourtyard run(settings);
    frames[skip] = run.sequence("frt", 0, 4, run.light).visibility;
  }
  ASSERT_EQ(frames[0].size(), frames[1].size());
  float largest = 0.0f;
  std::size_t soft = 0;
  for (std::size_t i = 0; i < frames[0].size(); ++i) {
    largest = std::max(largest, std::abs(frames[0][i] - frames[1][i]));
    soft += frames[0][i] > 0.01f && frames[0][i] < 0.99f;
  }
  std::cout << "largest difference " << largest << " over " << frames[0].size() << " pixels, " << soft
            << " in penumbrae\n";
  EXPECT_GT(soft, 1000u);  // the filter has penumbrae to filter
  EXPECT_LE(largest, float(DENOISE_UNIFORM) + 1e-6f);
  expectValidationSilent();
}

// A still view keeps gathering samples: on the foliage stress scene (thousands of small leaves
// shadowing each other) one sample a frame, 32 frames on, is closer to the converged reference than
// undenoised 16 samples. The history of a still scene is not clipped to its few-sample neighbourhood
// (clipped, the penumbrae's tails drift: 0.026 at 32 frames against 0.017 for 16 samples).
TEST(Denoise, StillViewConvergesPastSixteenSamples) {
  const auto run = [](std::uint32_t spp, DenoiseMode mode, std::uint32_t frames) {
    SceneRun foliage("builtin:foliage", denoiseSettings(spp, mode));
    applyLightSize(foliage.light, 0.1f, foliage.scene.bounds());
    const Frame last = renderFrames(*foliage.renderer, "frt", foliage.camera, foliage.light, 0, frames);
    return std::pair{last, foliage.render("ref")};
  };
  const auto [sixteen, reference] = run(16, DenoiseMode::Off, 1);
  const Frame one = run(1, DenoiseMode::Temporal, 32).first;
  const double sixteenError = against(sixteen, reference).rmse, oneError = against(one, reference).rmse;
  std::cout << "foliage: rmse of 16 spp " << sixteenError << ", 1 spp after 32 frames " << oneError << "\n";
  EXPECT_LT(oneError, sixteenError);
  expectValidationSilent();
}

// The light circles 3 degrees a frame for four frames, then stops. At once, no pixel that the
// reference now lights fully, and that lay in full shadow where the light was, stays dark (the
// history is clipped where the neighbourhood agrees); 16 frames later the result is as close to
// the reference as a sequence that started at the light's new place and ran as long (within 25%).
TEST(Denoise, LightThatStopsLeavesNoTrail) {
  SoftCourtyard run(denoiseSettings(1, DenoiseMode::Temporal));
  const Bounds bounds = run.scene.bounds();
  const Light start = run.light, stop = orbitLight(run.light, bounds, 12.0f);
  run.sequence("srt", 0, 8, start);
  for (std::uint32_t i = 1; i <= 3; ++i) run.sequence("srt", 7 + i, 1, orbitLight(start, bounds, 3.0f * float(i)));
  const Frame stopped = run.sequence("srt", 11, 1, stop);
  const Frame settled = run.sequence("srt", 12, 16, stop);

  SoftCourtyard still(denoiseSettings(1, DenoiseMode::Temporal));
  const Frame fresh = still.sequence("srt", 0, 17, stop);
  const Frame before = still.renderer->render("ref", still.camera, start);
  const Frame after = still.renderer->render("ref", still.camera, stop);

  std::size_t trail = 0, revealed = 0;
  for (std::size_t i = 0; i < after.visibility.size(); ++i) {
    if (!after.covered[i] || after.visibility[i] < 0.99f || before.visibility[i] > 0.01f) continue;
    ++revealed;
    trail += stopped.visibility[i] < 0.5f;
  }
  const double settledError = against(settled, after).rmse, freshError = against(fresh, after).rmse;
  std::cout << revealed << " pixels lit now and dark before: " << trail << " still dark at the stop; rmse 16 frames after "
            << settledError << ", of a sequence that never moved " << freshError << "\n";
  ASSERT_GT(revealed, 50u);
  EXPECT_EQ(trail, 0u);
  EXPECT_LT(settledError, 1.25 * freshError);
  expectValidationSilent();
}

// A light circling half a degree a frame: each pixel's history is fetched where the shadow now on
// it fell (from its blocker distance), so over the moving frames the sequence stays closer to the
// reference of each frame than the same history kept at its surface point, which drags the shadows.
TEST(Denoise, HistoryFollowsTheShadowsOfAMovingLight) {
  double moving[2] = {0.0, 0.0};
  SoftCourtyard reference(denoiseSettings(1, DenoiseMode::Off));
  const Bounds bounds = reference.scene.bounds();
  std::vector<Frame> references;
  for (std::uint32_t i = 1; i <= 8; ++i) references.push_back(reference.renderer->render("ref", reference.camera, orbitLight(reference.light, bounds, 0.5f * float(i))));
  for (const bool follow : {false, true}) {
    RenderSettings settings = denoiseSettings(1, DenoiseMode::Temporal);
    settings.denoise.followShadows = follow;
    SoftCourtyard run(settings);
    run.sequence("srt", 0, 8, run.light);
    for (std::uint32_t i = 1; i <= 8; ++i) {
      const Frame frame = run.sequence("srt", 7 + i, 1, orbitLight(run.light, bounds, 0.5f * float(i)));
      moving[follow] += against(frame, references[i - 1]).rmse / 8.0;
    }
  }
  std::cout << "mean rmse of 8 moving frames: history following the shadows " << moving[1] << ", kept at its point "
            << moving[0] << "\n";
  EXPECT_LT(moving[1], 0.9 * moving[0]);
  expectValidationSilent();
}

// A camera cut: the history of the old view is reused only where the same surface point was seen
// (reprojected, on the same plane, within a few pixels); elsewhere the frame starts afresh. So the
// first frame after the cut is no further from the reference than a first frame without history,
// and has no more pixels off by more than half (what another surface's shadow carried over makes).
TEST(Denoise, CameraCutCarriesNoHistoryAcrossSurfaces) {
  SoftCourtyard run(denoiseSettings(1, DenoiseMode::Temporal));
  run.sequence("srt", 0, 8, run.light);
  Camera cut = run.camera;
  cut.eye = cut.target + glm::vec3(-1.0f, 0.8f, -1.0f) * glm::length(run.camera.eye - run.camera.target);
  run.camera = cut;
  const Frame afterCut = run.sequence("srt", 8, 1, run.light);

  SoftCourtyard fresh(denoiseSettings(1, DenoiseMode::Temporal));
  fresh.camera = cut;
  fresh.renderer->setFrame(8);
  const Frame first = fresh.render("srt");
  const Frame reference = fresh.render("ref");
  const auto grossly = [&](const Frame& f) {
    return compareVisibility(f.visibility, reference.visibility, reference.covered, kWrongThresholdHard);
  };
  const ErrorMetrics cutError = grossly(afterCut), firstError = grossly(first);
  std::cout << "after the cut: rmse " << cutError.rmse << ", wrong " << cutError.wrongPixelFraction
            << "; a first frame: rmse " << firstError.rmse << ", wrong " << firstError.wrongPixelFraction
            << " (wrong: off by more than 0.5)\n";
  EXPECT_LE(cutError.rmse, firstError.rmse * 1.01);
  EXPECT_LE(cutError.wrongPixelFraction, firstError.wrongPixelFraction + 1e-4);
  expectValidationSilent();
}

// Same scene, settings and frame numbers: the same images, bit for bit.
TEST(Denoise, SequenceIsDeterministic) {
  std::vector<float> images[2];
  for (std::vector<float>& image : images) {
    SoftCourtyard run(denoiseSettings(1, DenoiseMode::Temporal));
    image = run.sequence("srt", 0, 3, run.light).visibility;
  }
  EXPECT_EQ(images[0], images[1]);
}

// A box resting on the ground under a disk light: its shadow starts sharp at the contact and
// widens away from it. Where the reference's shadow edge is hard (its 5x5 neighbourhood spans dark
// and lit), the denoised sequence keeps it; the same filter with its radius freed from the
// penumbra's width (the bound this test guards) blurs it.
TEST(Denoise, ContactShadowsStayHard) {
  Mesh box = namedMesh("box");
  mesh::addBox(box, {0.0f, 1.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f});
  const Scene scene = sceneOf({groundMesh(), box});
  const Light light = diskLight(scene);
  const Frame reference = sequenceOf(scene, kGroundCamera, light, denoiseSettings(1, DenoiseMode::Off), "ref", 1);
  const Frame bounded = sequenceOf(scene, kGroundCamera, light, denoiseSettings(1, DenoiseMode::Temporal), "srt", 8);
  RenderSettings freed = denoiseSettings(1, DenoiseMode::Temporal);
  freed.denoise.widthFraction = 1e6f;
  freed.denoise.targetSamples = 256.0f;
  const Frame blurred = sequenceOf(scene, kGroundCamera, light, freed, "srt", 8);

  const int w = int(kSize);
  double boundedError = 0.0, blurredError = 0.0;
  std::size_t hard = 0;
  for (int y = 2; y < w - 2; ++y) {
    for (int x = 2; x < w - 2; ++x) {
      float lo = 1.0f, hi = 0.0f;
      bool covered = true;
      for (int dy = -2; dy <= 2; ++dy) {
        for (int dx = -2; dx <= 2; ++dx) {
          const std::size_t j = std::size_t((y + dy) * w + x + dx);
          covered = covered && reference.covered[j];
          lo = std::min(lo, reference.visibility[j]);
          hi = std::max(hi, reference.visibility[j]);
        }
      }
      if (!covered || lo > 0.1f || hi < 0.9f) continue;
      const std::size_t i = std::size_t(y * w + x);
      boundedError += std::abs(bounded.visibility[i] - reference.visibility[i]);
      blurredError += std::abs(blurred.visibility[i] - reference.visibility[i]);
      ++hard;
    }
  }
  ASSERT_GT(hard, 100u);
  boundedError /= double(hard);
  blurredError /= double(hard);
  std::cout << hard << " pixels at hard shadow edges: mean |error| " << boundedError << " (radius bounded by the penumbra), "
            << blurredError << " (not bounded)\n";
  EXPECT_LT(boundedError, 0.016);  // measured 0.0056
  EXPECT_LT(boundedError, 0.7 * blurredError);
  expectValidationSilent();
}

// A sphere on the ground under a small disk light: its side turned away from the light is dark for
// certain (no ray is traced there), its lit side next to it is lit, the terminator between them
// sharp. The filter does not average across it, where no blocker distance bounds its radius: lit
// pixels within 3 pixels of dark ones keep their light.
TEST(Denoise, TerminatorOfCurvedSurfacesStaysSharp) {
  Mesh sphere = namedMesh("sphere");
  mesh::addSphere(sphere, {0.0f, 1.0f, 0.0f}, 1.0f, 64, 32);
  const Scene scene = sceneOf({groundMesh(), sphere});
  const Light light = diskLight(scene, 0.01f);
  const Frame reference = sequenceOf(scene, kGroundCamera, light, denoiseSettings(1, DenoiseMode::Off), "ref", 1);
  const Frame denoised = sequenceOf(scene, kGroundCamera, light, denoiseSettings(1, DenoiseMode::Temporal), "srt", 8);
  const int w = int(kSize);
  double error = 0.0;
  std::size_t lit = 0;
  for (int y = 3; y < w - 3; ++y) {
    for (int x = 3; x < w - 3; ++x) {
      const std::size_t i = std::size_t(y * w + x);
      if (!reference.covered[i] || reference.visibility[i] < 0.99f) continue;
      bool nearDark = false;
      for (int dy = -3; dy <= 3 && !nearDark; ++dy) {
        for (int dx = -3; dx <= 3 && !nearDark; ++dx) {
          const std::size_t j = std::size_t((y + dy) * w + x + dx);
          nearDark = reference.covered[j] && reference.visibility[j] < 0.01f;
        }
      }
      if (!nearDark) continue;
      error += std::abs(denoised.visibility[i] - reference.visibility[i]);
      ++lit;
    }
  }
  ASSERT_GT(lit, 100u);
  std::cout << lit << " lit pixels within 3 of dark ones: mean |error| " << error / double(lit) << "\n";
  EXPECT_LT(error / double(lit), 0.0048);  // measured 0.0016; 0.015 when taps cross the terminator
  expectValidationSilent();
}

}  // namespace
}  // namespace penumbra::test
