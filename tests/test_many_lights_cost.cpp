// What a frame of several lights costs, and that its answer does not change for it: one trace for the
// lights (each light's own, bit for bit), buffers kept for the lights asked for, each still light's own
// maps within the memory budget, srt's choice of path per light, --light-error's bounded
// approximation, and the traces and maps each lamp's range and footprint need.
#include <gtest/gtest.h>

#include "apps/run_config.h"
#include "core/camera.h"
#include "core/metrics.h"
#include "core/view.h"
#include "render_fixture.h"

namespace penumbra::test {
namespace {

// --lights-trace one: frt's lights traced in one dispatch per batch give each light's own trace bit
// for bit (visibility and rays, so the image too), on every GPU tracer, over two batches (20
// whole-image lights, one of them an area light: 16 in the first) and over the street's lamps, whose
// rectangles are parts of the image.
TEST(ManyLights, OneTraceForTheLightsIsEachLightsOwn) {
  std::vector<std::string> tracers = {"bvh", "ls"};
  if (validatedContext().rayQuery()) tracers.push_back("rq");
  for (const std::string& tracer : tracers) {
    for (const char* scene : {"builtin:courtyard", "builtin:street:16"}) {
      RenderSettings settings = smallSettings(96);
      settings.tracer = tracer;
      settings.spp = 4;
      SceneRun one(scene, settings);
      settings.oneLightsTrace = false;
      SceneRun each(scene, settings);
      std::vector<Light> lights = one.scene.lights;
      if (lights.size() == 1) {
        Light part = lights.front();
        part.intensity /= 20.0f;
        lights.assign(20, part);
        lights[7] = parseLight("disk:6,12,4:0,0,0");  // not every light alike: an area light's samples
        lights[7].size = 1.5f;
        lights[7].intensity = part.intensity;
      }
      const Frame a = one.renderer->render("frt", one.camera, lights);
      const Frame b = each.renderer->render("frt", each.camera, lights);
      const std::string what = tracer + " " + scene;
      ASSERT_EQ(a.lights.size(), lights.size()) << what;
      std::uint64_t rays = 0;
      for (std::size_t i = 0; i < lights.size(); ++i) {
        EXPECT_EQ(a.lights[i].visibility, b.lights[i].visibility) << what << " light " << i;
        EXPECT_EQ(a.lights[i].stats.raysTraced, b.lights[i].stats.raysTraced) << what << " light " << i;
        rays += a.lights[i].stats.raysTraced.value_or(0);
      }
      EXPECT_GT(rays, 0u) << what;
      EXPECT_EQ(a.rgba, b.rgba) << what;
      if (lights.size() == 20) EXPECT_EQ(a.stats.counts.at("shade_batches"), 2u) << what;
    }
  }
  expectValidationSilent();
}

// Renderer::keepLightBuffers: only the first lamp's and the kept lamp's buffers come back, every
// lamp's stats still do, and the frame is the same.
TEST(ManyLights, KeepsTheBuffersOfTheLightsAskedFor) {
  SceneRun run("builtin:street:16", smallSettings(96));
  const std::vector<Light>& lamps = run.scene.lights;
  for (const char* method : {"frt", "srt"}) {
    const Frame all = run.renderer->render(method, run.camera, lamps);
    run.renderer->keepLightBuffers(5);
    const Frame some = run.renderer->render(method, run.camera, lamps);
    run.renderer->keepLightBuffers(std::nullopt);
    ASSERT_EQ(some.lights.size(), lamps.size()) << method;
    EXPECT_EQ(some.rgba, all.rgba) << method;
    EXPECT_EQ(some.covered, all.covered) << method;
    EXPECT_EQ(some.visibility, all.visibility) << method;
    EXPECT_EQ(some.lights[5].visibility, all.lights[5].visibility) << method;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < lamps.size(); ++i) {
      kept += !some.lights[i].visibility.empty();
      EXPECT_EQ(some.lights[i].stats.raysTraced, all.lights[i].stats.raysTraced) << method << " lamp " << i;
    }
    EXPECT_LE(kept, 2u) << method;
    EXPECT_EQ(some.stats.raysTraced, all.stats.raysTraced) << method;
  }
  expectValidationSilent();
}

// Keeping still lights' maps (RenderSettings::reuseLightPasses), every lamp of a frame keeps maps
// of its own within --light-maps-memory: the second frame renders no lamp's map again; with a budget
// that holds only some lamps' maps, the others share maps rendered again every frame and say so.
// Every frame is the one a renderer that renders every map makes.
TEST(ManyLights, StillLampsKeepTheirOwnMapsWithinTheBudget) {
  RenderSettings settings = smallSettings(96, 128);  // every lamp's cube map at 128^2
  SceneRun again("builtin:street:16", settings);
  settings.reuseLightPasses = true;
  SceneRun keep("builtin:street:16", settings);
  settings.lightMapsMiB = 4;  // a 128^2 cube's passes are estimated at 1.1 or 1.9 MiB
  SceneRun tight("builtin:street:16", settings);
  const std::vector<Light>& lamps = again.scene.lights;
  for (int frame = 0; frame < 2; ++frame) {
    const Frame a = again.renderer->render("srt", again.camera, lamps);
    const Frame k = keep.renderer->render("srt", keep.camera, lamps);
    const Frame t = tight.renderer->render("srt", tight.camera, lamps);
    std::size_t reached = 0, shared = 0;
    for (std::size_t i = 0; i < lamps.size(); ++i) {
      EXPECT_EQ(k.lights[i].visibility, a.lights[i].visibility) << "frame " << frame << ", lamp " << i;
      EXPECT_EQ(t.lights[i].visibility, a.lights[i].visibility) << "frame " << frame << ", lamp " << i;
      EXPECT_EQ(t.lights[i].pip, a.lights[i].pip) << "frame " << frame << ", lamp " << i;
      if (!k.lights[i].stats.counts.contains("shadow_map_texels")) continue;  // culled
      ++reached;
      const auto reused = [](const Frame& f) {
        const auto& passes = f.stats.reusedPasses;
        return std::find(passes.begin(), passes.end(), "shadow_map") != passes.end();
      };
      EXPECT_EQ(reused(k.lights[i]), frame == 1) << "lamp " << i;
      const auto& notes = t.lights[i].stats.notes;
      const bool past = std::any_of(notes.begin(), notes.end(), [](const std::string& n) {
        return n.find("--light-maps-memory") != std::string::npos;
      });
      shared += past;
      EXPECT_EQ(reused(t.lights[i]), frame == 1 && !past) << "lamp " << i;
    }
    EXPECT_GT(reached, 2u);
    EXPECT_EQ(k.lights.back().stats.counts.at("lights_with_own_maps"), reached);
    const std::uint64_t own = t.lights.back().stats.counts.at("lights_with_own_maps");
    EXPECT_GT(own, 0u);
    EXPECT_LT(own, reached) << "the budget holds some lamps' maps, not all";
    EXPECT_EQ(own + shared, reached);
    EXPECT_LE(t.lights.back().stats.memoryBytes.at("light_maps"), k.lights.back().stats.memoryBytes.at("light_maps"));
  }
  expectValidationSilent();
}

// --srt-choice auto in a frame of several lights on a GPU tracer: after its first frame (the paper's,
// both paths timed on their own) a lamp joins the frame's one trace of its lights once, learns its
// share of that trace, and then weighs its classify path against that share; a joined lamp's frame is
// frt's same lamp's, bit for bit.
TEST(ManyLights, SrtChoiceWeighsItsShareOfTheLightsTrace) {
  RenderSettings settings = smallSettings(96, 256);
  settings.srtChoice = true;
  SceneRun run("builtin:street:16", settings);
  const std::vector<Light>& lamps = run.scene.lights;
  const Frame full = run.renderer->render("frt", run.camera, lamps);
  const auto noted = [](const Frame& f, const std::string& text) {
    return std::any_of(f.stats.notes.begin(), f.stats.notes.end(),
                       [&](const std::string& n) { return n.find(text) != std::string::npos; });
  };
  std::size_t shares = 0;
  for (int frame = 0; frame < 4; ++frame) {
    const Frame f = run.renderer->render("srt", run.camera, lamps);
    for (std::size_t i = 0; i < lamps.size(); ++i) {
      const Frame& lamp = f.lights[i];
      if (!lamp.stats.srtPath) continue;  // culled
      if (frame == 0) EXPECT_EQ(*lamp.stats.srtPath, "classify") << "lamp " << i;
      if (frame == 1) EXPECT_TRUE(noted(lamp, "this one on its own")) << "lamp " << i << " joins to learn its share";
      if (*lamp.stats.srtPath == "trace_all") {
        EXPECT_GE(frame, 1) << "lamp " << i;
        EXPECT_TRUE(noted(lamp, "in the trace of the frame's lights")) << "frame " << frame << ", lamp " << i;
        EXPECT_EQ(lamp.visibility, full.lights[i].visibility) << "frame " << frame << ", lamp " << i;
        EXPECT_EQ(lamp.stats.raysTraced, full.lights[i].stats.raysTraced) << "frame " << frame << ", lamp " << i;
        if (frame >= 2) shares += noted(lamp, "its share of that trace");
      }
    }
  }
  EXPECT_GT(shares, 0u) << "lamps that joined weighed their share";
  expectValidationSilent();
}

// --light-error ε: where a lamp's shadow weighs less than ε (shared::shadowWeight), srt keeps its map's
// answer and frt takes the lamp unshadowed, tracing no ray there. Against the reference: each lamp's
// visibility errors change no pixel's shade by ε or more; the image itself (shaded by shade.comp, so
// independent of the weight's formula) differs from the reference's by no more than the weighted
// errors summed over the lamps, up to 8-bit rounding (a white street: the weight's albedo of 1 is
// the surface's, so a weight too small shows); fewer rays are traced; and the reference ignores the
// option. The street's lamps are exact without it.
TEST(ManyLights, LightErrorBoundsWhatEachLightChanges) {
  constexpr float kEpsilon = 0.03f;
  Scene street = loadScene("builtin:street:16");
  for (Mesh& mesh : street.meshes) mesh.baseColor = glm::vec3(1.0f);
  RenderSettings settings = smallSettings(128, 512);
  SceneRun exact(street, settings);
  settings.lightError = kEpsilon;
  SceneRun slight(street, settings);
  const std::vector<Light>& lamps = exact.scene.lights;
  const Frame ref = exact.renderer->render("ref", exact.camera, lamps);
  const Frame refSlight = slight.renderer->render("ref", slight.camera, lamps);
  for (std::size_t i = 0; i < lamps.size(); ++i) {
    EXPECT_EQ(refSlight.lights[i].visibility, ref.lights[i].visibility) << "lamp " << i;
    EXPECT_TRUE(refSlight.lights[i].shadowWeight.empty()) << "the reference approximates nothing";
  }
  // an sRGB byte's linear interval
  const auto lo = [](int b) { return std::pow(std::max(b - 0.5, 0.0) / 255.0, 2.2); };
  const auto hi = [](int b) { return std::pow(std::min(b + 0.5, 255.0) / 255.0, 2.2); };
  const std::size_t pixels = ref.covered.size();
  for (const char* method : {"frt", "srt"}) {
    Frame before = exact.renderer->render(method, exact.camera, lamps);
    Frame frame = slight.renderer->render(method, slight.camera, lamps);
    judgeFrame(before, ref, false, nullptr);
    judgeFrame(frame, ref, false, nullptr);
    std::vector<double> bound(pixels, 0.0);
    std::uint64_t raysBefore = 0, rays = 0, slightPixels = 0, wrong = 0;
    for (std::size_t i = 0; i < lamps.size(); ++i) {
      const Frame& lamp = frame.lights[i];
      raysBefore += before.lights[i].stats.raysTraced.value_or(0);
      rays += lamp.stats.raysTraced.value_or(0);
      EXPECT_EQ(before.lights[i].stats.error->wrongPixelFraction, 0.0) << method << ", lamp " << i;
      EXPECT_TRUE(before.lights[i].shadowWeight.empty());
      if (lamp.shadowWeight.empty()) continue;  // culled
      ASSERT_TRUE(lamp.stats.lightErrorMax) << method << ", lamp " << i;
      EXPECT_LT(*lamp.stats.lightErrorMax, kEpsilon * (1.0 + 1e-5)) << method << ", lamp " << i;
      slightPixels += lamp.stats.counts.at("light_error_pixels");
      for (std::size_t p = 0; p < pixels; ++p) {
        if (!ref.covered[p]) continue;
        const double e = std::abs(double(lamp.visibility[p]) - ref.lights[i].visibility[p]);
        bound[p] += lamp.shadowWeight[p] * e;
        wrong += e > 0.5;
      }
    }
    std::size_t over = 0;
    for (std::size_t p = 0; p < pixels; ++p) {
      if (!ref.covered[p]) continue;
      for (int c = 0; c < 3; ++c) {
        const int a = frame.rgba[4 * p + c], b = ref.rgba[4 * p + c];
        const double gap = a > b ? lo(a) - hi(b) : b > a ? lo(b) - hi(a) : 0.0;
        over += gap > bound[p] + 1e-6;
      }
    }
    std::cout << method << ": " << raysBefore << " -> " << rays << " rays, " << slightPixels
              << " lamp pixels below epsilon, " << wrong << " of them wrong, largest shade change "
              << *frame.stats.lightErrorMax << "\n";
    EXPECT_EQ(over, 0u) << method << ": pixels whose image changed by more than the lamps' weighted errors";
    EXPECT_GT(wrong, 0u) << method << ": the approximation changed some answers";
    EXPECT_GT(slightPixels, wrong);
    EXPECT_LT(rays, raysBefore) << method;
    EXPECT_GT(*frame.stats.lightErrorMax, 0.0);
  }
  expectValidationSilent();
}

// Down the street, the far lamps' ranges cover a few pixels: frt's in-place trace covers only the
// rectangle each lamp's range projects to, and every lamp's shadow still equals the reference's.
TEST(ManyLights, FrtTracesOnlyTheRectangleALampReaches) {
  SceneRun run("builtin:street:16", smallSettings(96, 1024));
  const Frame ref = run.renderer->render("ref", run.camera, run.scene.lights);
  const Frame frt = run.renderer->render("frt", run.camera, run.scene.lights);
  const auto covered = std::uint64_t(std::count(ref.covered.begin(), ref.covered.end(), std::uint8_t(1)));
  std::size_t narrowed = 0;
  for (std::size_t i = 0; i < ref.lights.size(); ++i) {
    EXPECT_EQ(compareVisibility(frt.lights[i].visibility, ref.lights[i].visibility, ref.covered, kWrongThresholdHard)
                  .wrongPixelFraction,
              0.0)
        << "lamp " << i;
    narrowed += frt.stats.lights[i].pipPixels.value_or(covered) < covered / 4;
  }
  EXPECT_GT(narrowed, 4u) << "far lamps' ranges cover under a quarter of the view";
  expectValidationSilent();
}

// A lamp's map is as fine as its range's nearest approach to the camera needs (--light-map-res
// footprint): down the street the far lamps' maps are far smaller, sm stays about as right as with
// every map at full resolution, and srt still equals the reference on every lamp.
TEST(ManyLights, FootprintMapsCostLessAndKeepTheAnswer) {
  RenderSettings fixed = smallSettings(128, 1024);
  fixed.footprintMaps = false;
  SceneRun run("builtin:street:16", smallSettings(128, 1024));
  SceneRun full("builtin:street:16", fixed);
  const Frame ref = run.renderer->render("ref", run.camera, run.scene.lights);
  const Frame sm = run.renderer->render("sm", run.camera, run.scene.lights);
  const Frame smFull = full.renderer->render("sm", run.camera, run.scene.lights);
  const Frame srt = run.renderer->render("srt", run.camera, run.scene.lights);
  const auto wrong = [&](const Frame& f, std::size_t i) {
    const ErrorMetrics e =
        compareVisibility(f.lights[i].visibility, ref.lights[i].visibility, ref.covered, kWrongThresholdHard);
    return std::uint64_t(std::llround(e.wrongPixelFraction * double(e.pixels)));
  };
  std::uint64_t smWrong = 0, smFullWrong = 0;
  for (std::size_t i = 0; i < ref.lights.size(); ++i) {
    EXPECT_EQ(wrong(srt, i), 0u) << "lamp " << i;
    smWrong += wrong(sm, i);
    smFullWrong += wrong(smFull, i);
  }
  EXPECT_LE(smWrong, 2 * smFullWrong + 16) << "sm's wrong pixels over the lamps, at full resolution " << smFullWrong;
  const std::uint64_t texels = sm.stats.counts.at("shadow_map_texels"),
                      fullTexels = smFull.stats.counts.at("shadow_map_texels");
  EXPECT_EQ(fullTexels, 16u * 6u * 1024u * 1024u);
  EXPECT_LT(texels * 4, fullTexels) << "the far lamps' maps are coarser";
  for (const char* filtered : {"pcf", "pcss", "msm"}) {  // the other map baselines take the same maps
    const Frame f = run.renderer->render(filtered, run.camera, run.scene.lights);
    EXPECT_EQ(f.lights.size(), ref.lights.size()) << filtered;
  }
  expectValidationSilent();
}

}  // namespace
}  // namespace penumbra::test
