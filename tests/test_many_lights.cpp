// Frames of several lights: every light shadowed by the method as if it were alone, the shaded image
// their sum, each light judged against the reference's same light, glTF's falloff, and the refusals.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_fixture.h"
#include "core/camera.h"
#include "core/gpu_light.h"
#include "core/image_io.h"
#include "core/metrics.h"
#include "core/view.h"
#include "gltf_writer.h"
#include "png_check.h"
#include "render_fixture.h"
#include "shared/light.h"

namespace penumbra::test {
using namespace loader_test;
namespace {

// The courtyard's own light, a directional one from another side and a spot with a soft edge.
std::vector<Light> threeLights(const Scene& scene) {
  Light spot = parseLight("spot:4,14,3:0,0,0:70");
  spot.innerAngleDeg = 40.0f;
  spot.intensity = 0.6f;
  Light sun = parseLight("dir:0.5,-1,0.3");
  sun.intensity = 0.4f;
  return {scene.lights.front(), sun, spot};
}

TEST(ManyLights, EachLightIsShadowedAsIfAlone) {
  SceneRun run("builtin:courtyard", smallSettings(128));
  const std::vector<Light> lights = threeLights(run.scene);
  for (const char* method : {"ref", "frt", "srt"}) {
    const Frame frame = run.renderer->render(method, run.camera, lights);
    ASSERT_EQ(frame.lights.size(), lights.size()) << method;
    ASSERT_EQ(frame.stats.lights.size(), lights.size()) << method;
    std::uint64_t rays = 0;
    for (std::size_t i = 0; i < lights.size(); ++i) {
      const Frame alone = run.renderer->render(method, run.camera, lights[i]);
      EXPECT_EQ(frame.lights[i].visibility, alone.visibility) << method << " light " << i;
      rays += frame.lights[i].stats.raysTraced.value_or(0);
    }
    EXPECT_EQ(frame.visibility, frame.lights.front().visibility) << method;
    EXPECT_EQ(frame.stats.raysTraced.value_or(0), rays) << method;
    EXPECT_GT(rays, 0u) << method;
  }
  expectValidationSilent();
}

// The image adds the lights: two copies of a light at half its intensity shade exactly as the light.
TEST(ManyLights, ShadingAddsTheLights) {
  SceneRun run("builtin:courtyard", smallSettings(96));
  Light half = run.light;
  half.intensity = 0.5f;
  const Frame one = run.renderer->render("frt", run.camera, run.light);
  const Frame two = run.renderer->render("frt", run.camera, std::vector<Light>{half, half});
  std::size_t differ = 0;
  for (std::size_t i = 0; i < one.rgba.size(); ++i) differ += one.rgba[i] != two.rgba[i];
  EXPECT_EQ(differ, 0u) << "of " << one.rgba.size() << " bytes";
  // A second light changes the image (where it reaches), not the first light's shadow.
  const std::vector<Light> lights = threeLights(run.scene);
  const Frame three = run.renderer->render("frt", run.camera, lights);
  differ = 0;
  for (std::size_t i = 0; i < one.rgba.size(); ++i) differ += one.rgba[i] != three.rgba[i];
  EXPECT_GT(differ, one.rgba.size() / 10);
  EXPECT_EQ(three.lights.front().visibility, one.visibility);
  expectValidationSilent();
}

// The image sums the lights a batch at a time, each light's visibility kept over its range's
// rectangle: two copies of a street lamp at half its intensity shade exactly as the lamp where its
// rectangle is part of the view, and 32 copies of the courtyard's light at 1/32 of it, more than one
// batch holds, shade as the light to within a level of rounding.
TEST(ManyLights, BatchesAddEveryLightOnce) {
  SceneRun street("builtin:street:16", smallSettings(96));
  const Light lamp = street.scene.lights[10];
  const glm::uvec4 rect =
      screenRect(cameraMatrices(street.camera, street.scene.bounds(), 96, 96), lamp.position, lamp.range, 96, 96);
  ASSERT_LT(rect.z - rect.x, 96u) << "the lamp's rectangle is part of every row it meets";
  ASSERT_LT(rect.w - rect.y, 96u);
  Light half = lamp;
  half.intensity *= 0.5f;
  const Frame one = street.renderer->render("frt", street.camera, lamp);
  const Frame two = street.renderer->render("frt", street.camera, std::vector<Light>{half, half});
  EXPECT_EQ(two.rgba, one.rgba);

  SceneRun run("builtin:courtyard", smallSettings(96));
  const Frame light = run.renderer->render("frt", run.camera, run.light);
  Light part = run.light;
  part.intensity /= 32.0f;
  const std::vector<Light> parts(32, part);
  const Frame sum = run.renderer->render("frt", run.camera, parts);
  EXPECT_EQ(sum.stats.counts.at("shade_batches"), 2u) << "batches of " << ShadePass::kBatchImages << " images";
  int worst = 0;
  std::size_t differ = 0;
  for (std::size_t i = 0; i < light.rgba.size(); ++i) {
    worst = std::max(worst, std::abs(int(light.rgba[i]) - int(sum.rgba[i])));
    differ += light.rgba[i] != sum.rgba[i];
  }
  EXPECT_LE(worst, 1);
  EXPECT_LT(differ, light.rgba.size() / 100);
  expectValidationSilent();
}

// srt and sm per light against the reference's same light: srt within the hard-shadow bound on
// every light; sm, the map alone, wrong on more pixels.
TEST(ManyLights, SrtMatchesTheReferenceOnEveryLight) {
  SceneRun run("builtin:courtyard", smallSettings(128));
  const std::vector<Light> lights = threeLights(run.scene);
  const Frame ref = run.renderer->render("ref", run.camera, lights);
  const Frame srt = run.renderer->render("srt", run.camera, lights);
  const Frame sm = run.renderer->render("sm", run.camera, lights);
  double smWrong = 0.0, srtWrong = 0.0;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const double s =
        compareVisibility(srt.lights[i].visibility, ref.lights[i].visibility, ref.covered, kWrongThresholdHard)
            .wrongPixelFraction;
    const double m =
        compareVisibility(sm.lights[i].visibility, ref.lights[i].visibility, ref.covered, kWrongThresholdHard)
            .wrongPixelFraction;
    EXPECT_LE(s, 0.0005) << "light " << i;  // 0.05%
    srtWrong += s;
    smWrong += m;
  }
  EXPECT_GT(smWrong, srtWrong);
  expectValidationSilent();
}

// The street of 16 lamps, its middle seen from above: lamps whose range the view cannot reach are culled
// (nothing runs for them), and culling is exact: the reference lit alone by such a lamp is 0 on
// every covered pixel (its range rule), and srt and frt match it on every lamp the view reaches.
TEST(ManyLights, LampsBeyondTheViewAreCulledExactly) {
  SceneRun run("builtin:street:16", smallSettings(96, 1024));
  run.camera =
      Camera{.eye = {22.0f, 10.0f, 1.0f}, .target = {22.0f, 0.0f, 0.0f}, .fovYDeg = 45.0f};  // the middle lamps
  const Frame ref = run.renderer->render("ref", run.camera, run.scene.lights);
  const Frame srt = run.renderer->render("srt", run.camera, run.scene.lights);
  const Frame frt = run.renderer->render("frt", run.camera, run.scene.lights);
  ASSERT_EQ(ref.lights.size(), 16u);
  std::size_t culled = 0;
  for (std::size_t i = 0; i < ref.lights.size(); ++i) {
    const bool isCulled = !run.renderer->frameContext().lightReachesView(run.camera, run.scene.lights[i]);
    culled += isCulled;
    if (!isCulled) {
      EXPECT_EQ(compareVisibility(srt.lights[i].visibility, ref.lights[i].visibility, ref.covered, kWrongThresholdHard)
                    .wrongPixelFraction,
                0.0)
          << "lamp " << i;
      EXPECT_EQ(compareVisibility(frt.lights[i].visibility, ref.lights[i].visibility, ref.covered, kWrongThresholdHard)
                    .wrongPixelFraction,
                0.0)
          << "frt, lamp " << i;
      continue;
    }
    EXPECT_FALSE(ref.stats.lights[i].notes.empty()) << "lamp " << i;
    const Frame alone = run.renderer->render("ref", run.camera, run.scene.lights[i]);
    for (std::size_t p = 0; p < alone.visibility.size(); ++p) {
      if (alone.covered[p]) ASSERT_EQ(alone.visibility[p], 0.0f) << "lamp " << i << " pixel " << p;
    }
  }
  EXPECT_GT(culled, 4u);
  EXPECT_LT(culled, 14u);
  // A lamp before the last shades only the rectangle its range projects to: every pixel within its
  // range lies inside it (else the image would lose that lamp's light there).
  const ViewMatrices view = cameraMatrices(run.camera, run.scene.bounds(), 96, 96);
  const auto positions = run.renderer->frameContext().gbuffer().positions();
  std::size_t inRange = 0;
  for (const Light& lamp : run.scene.lights) {
    const glm::uvec4 rect = screenRect(view, lamp.position, lamp.range, 96, 96);
    for (std::size_t p = 0; p < positions.size(); ++p) {
      if (positions[p].w == 0.0f || glm::distance(glm::vec3(positions[p]), lamp.position) >= lamp.range) continue;
      ++inRange;
      const glm::uvec2 pixel(p % 96, p / 96);
      EXPECT_TRUE(pixel.x >= rect.x && pixel.y >= rect.y && pixel.x < rect.z && pixel.y < rect.w) << "pixel " << p;
    }
  }
  EXPECT_GT(inRange, 1000u);
  expectValidationSilent();
}

TEST(ManyLights, FalloffFollowsKhrLightsPunctual) {
  Bounds bounds;
  bounds.extend(glm::vec3(-1.0f));
  bounds.extend(glm::vec3(1.0f));
  Light point;
  point.type = LightType::Point;
  point.position = glm::vec3(0.0f, 4.0f, 0.0f);
  point.inverseSquare = true;
  point.range = 8.0f;
  const shared::GpuLight p = toGpuLight(point, bounds);
  const glm::vec3 down(0.0f, 1.0f, 0.0f);  // towards the light from below it
  const float d2 = 16.0f, x = d2 / 64.0f;
  EXPECT_FLOAT_EQ(shared::lightFalloff(p, glm::vec3(0.0f), down), (1.0f - x * x) / d2);
  EXPECT_EQ(shared::lightFalloff(p, glm::vec3(0.0f, -4.0f, 0.0f), down), 0.0f);  // at its range
  Light spot = point;
  spot.type = LightType::Spot;
  spot.direction = glm::vec3(0.0f, -1.0f, 0.0f);
  spot.spotAngleDeg = 90.0f;
  spot.innerAngleDeg = 30.0f;
  spot.range = 0.0f;
  const shared::GpuLight s = toGpuLight(spot, bounds);
  const auto at = [&](float degrees) {  // a point 4 below the spot, `degrees` off its axis
    const glm::vec3 q =
        spot.position + 4.0f * glm::vec3(std::sin(glm::radians(degrees)), -std::cos(glm::radians(degrees)), 0.0f);
    return shared::lightFalloff(s, q, glm::normalize(spot.position - q)) * 16.0f;
  };
  EXPECT_NEAR(at(0.0f), 1.0f, 1e-5f);
  EXPECT_NEAR(at(14.0f), 1.0f, 1e-5f);  // inside the inner cone
  EXPECT_GT(at(30.0f), 0.0f);
  EXPECT_LT(at(30.0f), 1.0f);
  EXPECT_NEAR(at(44.9f), 0.0f, 1e-3f);
  Light plain;  // a light of the command line: no falloff, so its frames are unchanged
  plain.position = point.position;
  EXPECT_EQ(shared::lightFalloff(toGpuLight(plain, bounds), glm::vec3(0.0f), down), 1.0f);
}

TEST(ManyLights, RefusedWhereAMethodTakesOneLight) {
  SceneRun run("builtin:courtyard", smallSettings(32));
  const std::vector<Light> lights = threeLights(run.scene);
  EXPECT_NE(messageOf([&] { run.renderer->render("ao", run.camera, lights); }).find("takes one light"),
            std::string::npos);
  EXPECT_NE(messageOf([&] { run.renderer->render("sm", run.camera, std::span<const Light>()); }).find("needs a light"),
            std::string::npos);
}

// A glTF file with a point, a spot and a directional light renders all three in `compare`, each
// judged against the reference's same light.
class ManyLightsCli : public CliTest {};

TEST_F(ManyLightsCli, GltfLightsAllRenderAndAreJudgedEach) {
  TempDir dir;
  Bytes bin;
  // a ground square and a table top above it
  json doc = meshDoc({{-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5}, {-1, 1, -1}, {1, 1, -1}, {1, 1, 1}, {-1, 1, 1}},
                     {0, 2, 1, 0, 3, 2, 4, 6, 5, 4, 7, 6}, bin);
  const double h = std::sqrt(0.5);
  const json down = {-h, 0.0, 0.0, h};  // local -Z to world -Y
  doc["extensionsUsed"] = {"KHR_lights_punctual"};
  doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "point"}, {"intensity", 40.0}, {"range", 30.0}},
      {{"type", "spot"}, {"intensity", 60.0}, {"spot", {{"innerConeAngle", 0.3}, {"outerConeAngle", 0.7}}}},
      {{"type", "directional"}, {"intensity", 0.5}, {"color", {1.0, 0.9, 0.8}}}};
  auto lightRef = [](int i) { return json{{"KHR_lights_punctual", {{"light", i}}}}; };
  doc["nodes"].push_back({{"translation", {0.5, 4.0, 2.0}}, {"extensions", lightRef(0)}});
  doc["nodes"].push_back({{"translation", {-2.0, 5.0, 0.5}}, {"rotation", down}, {"extensions", lightRef(1)}});
  doc["nodes"].push_back({{"rotation", {-0.50110364, 0.20044146, 0.0, 0.84185412}}, {"extensions", lightRef(2)}});
  doc["scenes"][0]["nodes"] = {0, 1, 2, 3};
  const std::string file = writeGltf(dir, doc, bin, "lights");
  const Scene scene = loadScene(file);
  ASSERT_EQ(scene.lights.size(), 3u);
  float brightest = 0.0f;  // the exposure: the brightest gives irradiance 1 at the scene's centre
  for (const Light& l : scene.lights) {
    const glm::vec3 v = l.position - scene.bounds().center();
    brightest = std::max(brightest, l.inverseSquare ? l.intensity / glm::dot(v, v) : l.intensity);
  }
  EXPECT_NEAR(brightest, 1.0f, 1e-5f);
  EXPECT_NEAR(scene.lights[1].innerAngleDeg, glm::degrees(0.6f), 1e-3f);
  EXPECT_FLOAT_EQ(scene.lights[0].range, 30.0f);

  const auto r = run("compare --scene " + file + " --methods sm,srt,frt --res 96x96 --out " + (dir_ / "out").string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto metrics = nlohmann::json::parse(slurp(dir_ / "out" / "metrics.json"));
  ASSERT_EQ(metrics["reference"]["lights"].size(), 3u);
  for (const auto& m : metrics["methods"]) {
    const std::string name = m["method"];
    ASSERT_EQ(m["lights"].size(), 3u) << name;
    for (const auto& light : m["lights"]) {
      const double wrong = light["error"]["wrong_pixel_fraction"].get<double>();
      if (name != "sm") {
        EXPECT_LE(wrong, 0.0005) << name;
      }
    }
    EXPECT_TRUE(m["image_error"]["rmse"].is_number()) << name;
  }
  // Each light's own images: its visibility (the reference's and each method's, the lights' differing)
  // and its heatmap against the reference's same light (a light without error: one colour where
  // covered, the visibility the reference's); the report lists the lights of each method.
  const std::string report = slurp(dir_ / "out" / "report.html");
  std::vector<Image> reference;
  std::size_t exact = 0;
  for (const std::string name : {"ref", "sm", "srt", "frt"}) {
    std::vector<Image> visibility;
    const auto stats = nlohmann::json::parse(slurp(dir_ / "out" / (name + ".stats.json")));
    for (int i = 0; i < 3; ++i) {
      const std::string base = (dir_ / "out" / "lights" / (name + "." + std::to_string(i))).string();
      visibility.push_back(readPng(base + ".visibility.png"));
      EXPECT_EQ(visibility.back().width, 96) << base;
      if (name == "ref") continue;
      const Image heatmap = readPng(base + ".heatmap.png");
      EXPECT_EQ(heatmap.width, 96) << base;
      EXPECT_NE(report.find("lights/" + name + "." + std::to_string(i) + ".heatmap.png"), std::string::npos) << base;
      if (stats["lights"][i]["error"]["rmse"].get<double>() == 0.0) {
        ++exact;
        EXPECT_EQ(visibility.back().rgba, reference[i].rgba) << base;
        EXPECT_LE(colourSpread(heatmap).first, 2u) << base;  // covered, uncovered
      }
    }
    EXPECT_NE(visibility[0].rgba, visibility[1].rgba) << name;
    EXPECT_NE(visibility[1].rgba, visibility[2].rgba) << name;
    if (name != "ref") EXPECT_NE(report.find(name + ": per light"), std::string::npos) << name;
    if (name == "ref") reference = visibility;
  }
  EXPECT_GE(exact, 3u) << "frt's lights, at least, match the reference";
}

// A lights file gives each light its own size, colour and range; --save-view keeps them all and
// --view restores them: the same frames bit for bit.
TEST_F(ManyLightsCli, LightsFileAndViewKeepEveryLight) {
  std::ofstream(dir_ / "lights.json") << R"([
    {"light": "disk:6,12,4:0,0,0", "size": 1.5, "color": [1, 0.8, 0.6]},
    {"light": "point:-3,2,1", "range": 6, "inverse_square": true, "intensity": 4}])";
  const std::string common = " --scene builtin:courtyard --res 64x64 --method frt --spp 4";
  const auto a = run("render" + common + " --lights " + (dir_ / "lights.json").string() + " --save-view " +
                     (dir_ / "view.json").string() + " --out " + (dir_ / "a").string());
  ASSERT_EQ(a.exitCode, 0) << a.err;
  const auto view = nlohmann::json::parse(slurp(dir_ / "view.json"));
  ASSERT_EQ(view["lights"].size(), 2u);
  EXPECT_EQ(view["lights"][0]["size"].get<double>(), 1.5) << "the file's own size, not --light-size's 0";
  EXPECT_EQ(view["lights"][1]["range"].get<double>(), 6.0);
  const auto b =
      run("render" + common + " --view " + (dir_ / "view.json").string() + " --out " + (dir_ / "b").string());
  ASSERT_EQ(b.exitCode, 0) << b.err;
  int w = 0, h = 0;
  const auto va = readExrGray((dir_ / "a" / "frt.visibility.exr").string(), w, h);
  EXPECT_EQ(va, readExrGray((dir_ / "b" / "frt.visibility.exr").string(), w, h));
  EXPECT_EQ(slurp(dir_ / "a" / "frt.png"), slurp(dir_ / "b" / "frt.png"));
  const auto soft = std::count_if(va.begin(), va.end(), [](float v) { return v > 0.0f && v < 1.0f; });
  EXPECT_GT(soft, 0) << "the disk's own size gives a penumbra";
  const auto bad = run("render" + common + " --lights " + (dir_ / "missing.json").string());
  EXPECT_NE(bad.exitCode, 0);
  EXPECT_NE(bad.err.find("missing.json"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace penumbra::test
