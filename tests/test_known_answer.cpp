// builtin:square has an analytic shadow: ground [-5,5]^2 at y=0, a square occluder [-1,1]^2 at
// y=1 and a directional light travelling along normalize(0.3,-1,0.2). A ground point p is in
// shadow iff p moved towards the light up to y=1 lands inside the square. `ref` must agree up to
// numerical noise; `sm` up to the footprint of a shadow-map texel around the shadow's edge.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "core/builtin_scenes.h"
#include "core/gpu_light.h"
#include "raster/light_fit_pass.h"
#include "render_fixture.h"

namespace penumbra::test {
namespace {

const glm::vec3 kLightDir = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));

struct Disagreement {
  int pixels = 0;              // covered pixels whose answer differs from the analytic one
  double maxEdgeDistance = 0;  // of those, the farthest from the shadow's edge (occluder plane)
  int shadowed = 0;            // pixels the analytic answer puts in shadow
  int occluderWrong = 0;       // lit occluder-top pixels reported as shadowed
  int litUnderOccluder = 0;    // pixels under the occluder the analytic answer leaves lit (its holes)
};

// Distance in the occluder plane from (x, z) to the boundary of [-1,1]^2.
double distanceToSquareEdge(double x, double z) {
  const double dx = std::abs(x) - 1.0, dz = std::abs(z) - 1.0;
  if (dx < 0.0 && dz < 0.0) return -std::max(dx, dz);
  return std::hypot(std::max(dx, 0.0), std::max(dz, 0.0));
}

// builtin:checker cuts the occluder into cells x cells squares, solid where the cell's row and column
// sum to an even number (core/builtin_scenes.h: kCheckerCells a side).
bool inSolidCell(double x, double z, int cells) {
  if (std::abs(x) >= 1.0 || std::abs(z) >= 1.0) return false;
  const double cell = 2.0 / cells;
  return (int(std::floor((x + 1.0) / cell)) + int(std::floor((z + 1.0) / cell))) % 2 == 0;
}
double distanceToCheckerEdge(double x, double z, int cells) {
  const double square = distanceToSquareEdge(x, z);
  if (std::abs(x) >= 1.0 || std::abs(z) >= 1.0) return square;
  const double cell = 2.0 / cells;
  const auto line = [&](double c) {
    const double f = (c + 1.0) / cell;
    return std::abs(f - std::round(f)) * cell;
  };
  return std::min({square, line(x), line(z)});
}

// builtin:checker with a finer checker texture: `cells` a side.
Scene finerChecker(std::uint32_t cells) {
  Scene scene = loadScene("builtin:checker");
  Texture& t = scene.textures.at(0);
  t.width = t.height = cells;
  t.rgba.clear();
  for (std::uint32_t y = 0; y < cells; ++y) {
    for (std::uint32_t x = 0; x < cells; ++x) t.rgba.insert(t.rgba.end(), {200, 200, 200, std::uint8_t((x + y) % 2 == 0 ? 255 : 0)});
  }
  return scene;
}

// Against the square's analytic shadow, or with `cells` > 0 the checker's of that many cells a side.
Disagreement againstAnalytic(const Frame& frame, const std::vector<glm::vec4>& positions, int cells = 0) {
  Disagreement d;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (!frame.covered[i]) continue;
    const glm::vec3 p(positions[i]);
    const bool lit = frame.visibility[i] > 0.5f;
    if (p.y > 0.5f) {  // top of the occluder: nothing above it
      d.occluderWrong += !lit;
      continue;
    }
    const glm::vec3 q = p - kLightDir * ((1.0f - p.y) / -kLightDir.y);
    const bool inside = cells > 0 ? inSolidCell(q.x, q.z, cells) : std::abs(q.x) < 1.0f && std::abs(q.z) < 1.0f;
    d.shadowed += inside;
    d.litUnderOccluder += !inside && std::abs(q.x) < 1.0f && std::abs(q.z) < 1.0f;
    if (lit == inside) {  // lit inside the shadow, or shadowed outside it
      ++d.pixels;
      d.maxEdgeDistance =
          std::max(d.maxEdgeDistance, cells > 0 ? distanceToCheckerEdge(q.x, q.z, cells) : distanceToSquareEdge(q.x, q.z));
    }
  }
  return d;
}

TEST(KnownAnswer, SquareSceneMatchesTheStatedGeometry) {
  const Scene scene = loadScene("builtin:square");
  ASSERT_FALSE(scene.lights.empty());
  EXPECT_EQ(scene.lights[0].type, LightType::Directional);
  EXPECT_NEAR(glm::dot(glm::normalize(scene.lights[0].direction), kLightDir), 1.0f, 1e-6f);
  const Bounds b = scene.bounds();
  EXPECT_NEAR(b.lo.x, -5.0f, 1e-5f);
  EXPECT_NEAR(b.hi.y, 1.0f, 1e-5f);
}

TEST(KnownAnswer, ReferenceMatchesAnalyticShadow) {
  SceneRun run("builtin:square", smallSettings(256, 2048));
  const Frame frame = run.render("ref");
  const Disagreement d = againstAnalytic(frame, run.renderer->frameContext().gbuffer().positions());
  EXPECT_GT(d.shadowed, 500) << "the shadow must be in view";
  EXPECT_EQ(d.occluderWrong, 0);
  // Only pixels whose shading point is within float noise of the edge may differ.
  EXPECT_LE(d.maxEdgeDistance, 1e-3) << d.pixels << " pixels differ";
  expectValidationSilent();
}

// The occluder cut out by a checker texture (alpha-tested): the shadow has the holes, cell for
// cell, in the reference (Embree's filters), in frt on the GPU BVH (its candidate-hit test) and in
// srt (the light pass cuts the map, whose hole edges the classification traces); sm within a map
// texel's footprint of the cells' edges. The camera pass cuts the occluder too, so the ground seen
// through a hole is ground (a solid occluder there would show its lit top).
TEST(KnownAnswer, ShadowHasTheCheckersHoles) {
  RenderSettings settings = smallSettings(256, 2048);
  settings.tracer = "bvh";
  SceneRun run("builtin:checker", settings);
  const Bounds bounds = run.scene.bounds();
  const float texel = raster::makeShadowMapInfo(toGpuLight(run.light, bounds), bounds, settings.shadowMap).texelWorld;
  std::size_t groundSeen = 0;
  for (const char* method : {"ref", "frt", "srt", "sm"}) {
    const Frame frame = run.render(method);
    const std::vector<glm::vec4> positions = run.renderer->frameContext().gbuffer().positions();
    const Disagreement d = againstAnalytic(frame, positions, kCheckerCells);
    std::printf("checker, %s: %d ground pixels in the cells' shadows, %d in their holes, %d differ\n", method,
                d.shadowed, d.litUnderOccluder, d.pixels);
    EXPECT_GT(d.shadowed, 250) << "the shadow must be in view";
    EXPECT_GT(d.litUnderOccluder, 250) << "and its holes";
    EXPECT_EQ(d.occluderWrong, 0) << method;
    const double bound = std::string(method) == "sm" ? 2.0 * texel / -kLightDir.y : 1e-3;
    EXPECT_LE(d.maxEdgeDistance, bound) << method << ": " << d.pixels << " pixels differ";
    groundSeen = 0;
    for (const glm::vec4& p : positions) groundSeen += p.w > 0.0f && p.y < 0.5f;
  }
  // The camera sees the ground through the holes, half of the solid occluder's pixels.
  SceneRun solid("builtin:square", settings);
  solid.render("sm");
  std::size_t groundAroundSolid = 0, solidOccluder = 0;
  for (const glm::vec4& p : solid.renderer->frameContext().gbuffer().positions()) {
    groundAroundSolid += p.w > 0.0f && p.y < 0.5f;
    solidOccluder += p.w > 0.0f && p.y >= 0.5f;
  }
  std::printf("ground pixels seen: %zu through the checker, %zu around the solid square (its occluder: %zu)\n",
              groundSeen, groundAroundSolid, solidOccluder);
  EXPECT_GT(double(groundSeen), double(groundAroundSolid) + 0.4 * double(solidOccluder)) << "the camera pass must cut the occluder";
  EXPECT_LT(double(groundSeen), double(groundAroundSolid) + 0.6 * double(solidOccluder));
  expectValidationSilent();
}

// The camera pass colours a mesh with its colour texture: builtin:square's ground textured with 8 x 1
// texels, the left four red and the right four blue, over u = (x + 5) / 10. Away from the texels'
// boundaries (and the repeat's seam at x = -5) the lit ground shows red at x in (-4, -1.5), blue at
// x in (1.5, 4); the untextured ground is grey. The occluder, a cut-out, takes its checker texture
// (RGB 200: a linear 0.58) as its colour and darkens. The shadows are the same as without colour.
TEST(KnownAnswer, CameraPassColoursWithTheTexture) {
  RenderSettings settings = smallSettings(128, 256);
  Scene scene = loadScene("builtin:checker");
  Texture paint{"red | blue", 8, 1, {}};
  for (int x = 0; x < 8; ++x)
    paint.rgba.insert(paint.rgba.end(), {std::uint8_t(x < 4 ? 255 : 0), 0, std::uint8_t(x < 4 ? 0 : 255), 255});
  scene.textures.push_back(paint);
  Mesh& ground = scene.meshes.at(0);
  ground.baseColor = glm::vec3(1.0f);
  for (const glm::vec3& p : ground.positions) ground.uvs.push_back({(p.x + 5.0f) / 10.0f, (p.z + 5.0f) / 10.0f});
  SceneRun plain(scene, settings);
  const Frame grey = plain.render("sm");
  ground.colorTexture = 1;
  scene.meshes.at(1).colorTexture = 0;
  SceneRun run(scene, settings);
  const Frame coloured = run.render("sm");
  const std::vector<glm::vec4> positions = run.renderer->frameContext().gbuffer().positions();
  int red = 0, blue = 0, greyGround = 0, occluder = 0, wrong = 0;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (!coloured.covered[i] || coloured.visibility[i] < 0.5f) continue;
    const glm::vec3 p(positions[i]);
    const std::uint8_t* c = &coloured.rgba[4 * i];
    const std::uint8_t* g = &grey.rgba[4 * i];
    if (p.y > 0.5f) {  // the occluder's top
      ++occluder;
      wrong += !(c[0] < g[0] && c[0] > g[0] / 2);
      continue;
    }
    greyGround += std::abs(int(g[0]) - int(g[2])) <= 8;
    if (p.x > -4.0f && p.x < -1.5f) {
      ++red;
      wrong += !(c[0] > 40 && c[2] == 0);
    } else if (p.x > 1.5f && p.x < 4.0f) {
      ++blue;
      wrong += !(c[2] > 40 && c[0] == 0);
    }
  }
  std::printf("textured ground: %d red, %d blue pixels, %d wrong; occluder %d; %d grey without the texture\n", red,
              blue, wrong, occluder, greyGround);
  EXPECT_GT(red, 300);
  EXPECT_GT(blue, 300);
  EXPECT_GT(occluder, 100);
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(greyGround, red + blue) << "the ground without its texture is grey";
  EXPECT_EQ(coloured.visibility, grey.visibility) << "colour does not change the shadows";
  expectValidationSilent();
}

// A 64 x 64 checker under a 256^2 map: a texel (0.055) spans about two cells (0.031), so the map
// cannot show the holes and sm shadows many of them whole. Every cut-out triangle is in the thin
// mask, so srt traces the receivers behind it and stays exact (the known failure of a map:
// cut-outs finer than a texel; without the mask srt kept sm's answer there).
TEST(KnownAnswer, SrtTracesCutoutHolesFinerThanATexel) {
  constexpr int kCells = 64;
  RenderSettings settings = smallSettings(256, 256);
  settings.tracer = "bvh";
  SceneRun run(finerChecker(kCells), settings);
  const Bounds bounds = run.scene.bounds();
  const float texel = raster::makeShadowMapInfo(toGpuLight(run.light, bounds), bounds, settings.shadowMap).texelWorld;
  EXPECT_GT(texel, 1.5 * 2.0 / kCells) << "the cells must be finer than a texel";
  const Frame sm = run.render("sm");
  const Frame srt = run.render("srt");
  const std::vector<glm::vec4> positions = run.renderer->frameContext().gbuffer().positions();
  const Disagreement wrongSm = againstAnalytic(sm, positions, kCells), wrongSrt = againstAnalytic(srt, positions, kCells);
  std::printf("checker %dx%d, 256^2 map (texel %.3f, cell %.3f): sm %d pixels differ, srt %d (PIP %.1f%%)\n", kCells,
              kCells, texel, 2.0 / kCells, wrongSm.pixels, wrongSrt.pixels, 100.0 * srt.stats.pipFraction.value_or(0.0));
  EXPECT_GT(wrongSm.pixels, 100) << "sm must miss holes";
  EXPECT_LE(wrongSrt.maxEdgeDistance, 1e-3) << wrongSrt.pixels << " pixels differ";
  EXPECT_LT(*srt.stats.pipFraction, 0.5) << "srt must not trace everything";
  expectValidationSilent();
}

// The other side of the thin mask's cut-outs: where a cut-out triangle's alpha is the same over a
// texel's block (the inside of a checker cell many texels wide), the map's answer holds and srt
// leaves it alone (thin_cutout.glsl); it traces near the cells' edges only.
TEST(KnownAnswer, SrtLeavesCutoutCellsWiderThanTexelsToTheMap) {
  RenderSettings settings = smallSettings(256, 2048);
  settings.tracer = "bvh";
  SceneRun run("builtin:checker", settings);
  const Bounds bounds = run.scene.bounds();
  const float texel = raster::makeShadowMapInfo(toGpuLight(run.light, bounds), bounds, settings.shadowMap).texelWorld;
  const double cell = 2.0 / kCheckerCells;
  EXPECT_GT(cell, 20.0 * texel) << "the cells must be many texels wide";
  const Frame srt = run.render("srt");
  const std::vector<glm::vec4> positions = run.renderer->frameContext().gbuffer().positions();
  EXPECT_LE(againstAnalytic(srt, positions, kCheckerCells).maxEdgeDistance, 1e-3);
  // Ground pixels under the occluder farther from every cell's edge than the mask's reach (the
  // 3x3 block, the normal offset and a texel's footprint on the ground, with room to spare).
  const double reach = 4.0 * texel / -kLightDir.y;
  int inside = 0, traced = 0;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const glm::vec3 p(positions[i]);
    if (!srt.covered[i] || p.y > 0.5f) continue;
    const glm::vec3 q = p - kLightDir * ((1.0f - p.y) / -kLightDir.y);
    if (std::abs(q.x) >= 1.0f || std::abs(q.z) >= 1.0f || distanceToCheckerEdge(q.x, q.z, kCheckerCells) < reach) continue;
    ++inside;
    traced += srt.pip[i] != 0;
  }
  std::printf("checker %ux%u, 2048^2 map (texel %.4f, cell %.3f): %d of %d pixels inside the cells traced\n", kCheckerCells,
              kCheckerCells, texel, cell, traced, inside);
  EXPECT_GT(inside, 300);
  EXPECT_LE(traced, inside / 100) << "srt traces the cells' insides";
  expectValidationSilent();
}

TEST(KnownAnswer, ShadowMapWithinATexelOfAnalyticShadow) {
  for (std::uint32_t res : {512u, 2048u}) {
    RenderSettings settings = smallSettings(256, res);
    SceneRun run("builtin:square", settings);
    const Frame frame = run.render("sm");
    const Disagreement d = againstAnalytic(frame, run.renderer->frameContext().gbuffer().positions());
    const Bounds bounds = run.scene.bounds();
    const float texel = raster::makeShadowMapInfo(toGpuLight(run.light, bounds), bounds, settings.shadowMap).texelWorld;
    // A texel seen on the horizontal occluder plane is texel / cos(angle to vertical) wide; allow
    // the texel footprint plus the normal offset (0.75 texel) on each side.
    const double footprint = texel / -kLightDir.y;
    EXPECT_GT(d.shadowed, 500);
    EXPECT_EQ(d.occluderWrong, 0) << "shadow acne on the occluder at " << res;
    EXPECT_LE(d.maxEdgeDistance, 2.0 * footprint) << res << "^2 map: " << d.pixels << " pixels differ";
    expectValidationSilent();
  }
}

// pcf's fractional values from the map's placement alone: a tap's texel holds the occluder when the
// light's line through the texel centre (the map's inverse projection) crosses the square, so a
// ground pixel's 3x3 kernel around its texel (taken after the normal offset, as sm takes it) is lit
// on the taps whose lines miss it. No texture is read: the rasterized map, the kernel's offsets, the
// receiver-plane compare and the average are all checked against this count.
TEST(KnownAnswer, PcfTapsMatchTheSquaresAnalyticShadow) {
  RenderSettings settings = smallSettings(256, 128);  // texels wider than pixels: a band to measure
  settings.pcfFilter = FILTER_PCF3;
  SceneRun run("builtin:square", settings);
  const Frame pcf = run.render("pcf");
  const shared::ShadowMapInfo& map = run.renderer->frameContext().frameData().shadow;
  ASSERT_EQ(map.kind, SHADOW_ORTHO);
  const glm::mat4 toWorld = glm::inverse(map.viewProj[0]);
  const auto positions = run.renderer->frameContext().gbuffer().positions();
  const int res = int(map.resolution);
  auto occluderOnTexel = [&](glm::ivec2 t) {
    const glm::vec2 ndc = (glm::vec2(t) + 0.5f) / float(res) * 2.0f - 1.0f;
    const glm::vec4 a = toWorld * glm::vec4(ndc, 0.0f, 1.0f), b = toWorld * glm::vec4(ndc, 1.0f, 1.0f);
    const glm::vec3 from = glm::vec3(a) / a.w, to = glm::vec3(b) / b.w;
    const glm::vec3 q = from + (to - from) * ((1.0f - from.y) / (to.y - from.y));  // the line at y = 1
    return std::abs(q.x) < 1.0f && std::abs(q.z) < 1.0f;
  };
  std::size_t ground = 0, fractional = 0, differ = 0;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (!pcf.covered[i] || positions[i].y > 0.5f) continue;  // the ground only
    ++ground;
    const glm::vec3 offsetP = glm::vec3(positions[i]) + glm::vec3(0, 1, 0) * (map.normalOffset * map.texelWorld);
    const glm::vec4 clip = map.viewProj[0] * glm::vec4(offsetP, 1.0f);
    const glm::ivec2 t(glm::floor((glm::vec2(clip) / clip.w * 0.5f + 0.5f) * float(res)));
    int lit = 0;
    for (int y = -1; y <= 1; ++y) {
      for (int x = -1; x <= 1; ++x) lit += !occluderOnTexel(t + glm::ivec2(x, y));
    }
    fractional += lit > 0 && lit < 9;
    differ += std::abs(pcf.visibility[i] - float(lit) / 9.0f) > 1e-3f;
  }
  std::printf("pcf 3x3 on the square: %zu ground pixels, %zu with fractional values, %zu differ from the taps' count\n",
              ground, fractional, differ);
  ASSERT_GT(fractional, 300u) << "an edge band to measure in";
  EXPECT_EQ(differ, 0u);  // measured: none (a texel centre on the square's very edge could tie)
  expectValidationSilent();
}

// pcss and msm under a square light over the square occluder, both axis-aligned and centred: from a
// ground point (x, 0, z) the occluder (side 2 at height 1) projects onto the light's plane (height
// H) as a rectangle whose overlap with the light (side L) is a product of two intervals, so the
// exact visible fraction is 1 - f(x) f(z), f the share of the light's side each axis hides. pcss (a Poisson disc of 32 taps sized by
// the blocker search) and msm (64 maps from the light's samples) approximate it; the test states
// how closely, over the penumbra and everywhere.
double hiddenShare(double x, double lightHeight, double lightSide) {
  // The occluder's side [-1, 1] at height 1 seen from (x, 0) on the light's plane: [x - (1 + x) H, x + (1 - x) H].
  const double lo = x - (1.0 + x) * lightHeight, hi = x + (1.0 - x) * lightHeight;
  const double overlap = std::min(hi, 0.5 * lightSide) - std::max(lo, -0.5 * lightSide);
  return std::clamp(overlap / lightSide, 0.0, 1.0);
}

TEST(KnownAnswer, SoftBaselinesApproachTheSquaresExactPenumbra) {
  // Measured, 1024^2 map: pcss mean 0.030 over the penumbra, worst 0.149 (a disc kernel for a square
  // light, 32 taps); msm mean 0.0152, worst 0.069 (64 maps, each a hard edge).
  constexpr double kPcssMean = 0.04, kPcssWorst = 0.2, kMsmMean = 0.02, kMsmWorst = 0.09;
  const float lightHeight = 5.0f, lightSide = 2.0f;
  RenderSettings settings = smallSettings(256, 1024);
  settings.msmMaps = 64;
  SceneRun run("builtin:square", settings);
  run.light = Light{.type = LightType::Rect, .position = {0, lightHeight, 0}, .direction = {0, -1, 0}, .size = lightSide};
  const auto positions = [&] {
    run.render("sm");
    return run.renderer->frameContext().gbuffer().positions();
  }();
  for (const char* method : {"pcss", "msm"}) {
    const Frame f = run.render(method);
    double penumbraError = 0.0, worst = 0.0;
    std::size_t penumbra = 0, ground = 0;
    for (std::size_t i = 0; i < positions.size(); ++i) {
      if (!f.covered[i] || positions[i].y > 0.5f) continue;
      ++ground;
      const double exact = 1.0 - hiddenShare(positions[i].x, lightHeight, lightSide) * hiddenShare(positions[i].z, lightHeight, lightSide);
      const double error = std::abs(f.visibility[i] - exact);
      worst = std::max(worst, error);
      if (exact > 0.0 && exact < 1.0) {
        penumbraError += error;
        ++penumbra;
      }
    }
    std::printf("%s on the square under a %gx%g light at %g: %zu penumbra pixels, mean |error| there %.4f, worst %.4f\n",
                method, lightSide, lightSide, lightHeight, penumbra, penumbraError / double(penumbra), worst);
    ASSERT_GT(penumbra, 1000u);
    EXPECT_LE(penumbraError / double(penumbra), std::string(method) == "pcss" ? kPcssMean : kMsmMean) << method;
    EXPECT_LE(worst, std::string(method) == "pcss" ? kPcssWorst : kMsmWorst) << method;
  }
  expectValidationSilent();
}

// fitShadowMap zooms the map onto the receivers' NDC rectangle with square texels and a margin of
// whole texels, never past maxZoom, and leaves cube maps and empty views alone.
TEST(LightFit, ZoomsOntoReceiversWithMarginAndLimit) {
  Bounds bounds;
  bounds.extend({-5, 0, -5});
  bounds.extend({5, 3, 5});
  Light light;
  light.type = LightType::Directional;
  light.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
  raster::ShadowMapSettings settings;
  settings.resolution = 1024;
  const shared::ShadowMapInfo whole = raster::makeShadowMapInfo(toGpuLight(light, bounds), bounds, settings);
  raster::ReceiverBounds seen{{-0.2f, -0.1f}, {0.3f, 0.2f}, 100};
  const shared::ShadowMapInfo fitted = raster::fitShadowMap(whole, seen, 4.0f, 16.0f);
  const float zoom = whole.texelWorld / fitted.texelWorld;
  EXPECT_NEAR(zoom, (1.0f - 8.0f / 1024.0f) / 0.25f, 1e-4f);  // the wider side (0.5) fills the map less its margin
  // A world point whose old NDC is a corner of the rectangle lands 4 texels inside the new map on
  // the wider axis, and inside it on the other.
  const glm::mat4 inverse = glm::inverse(whole.viewProj[0]);
  for (glm::vec2 corner : {seen.lo, seen.hi, glm::vec2(seen.lo.x, seen.hi.y)}) {
    const glm::vec4 world = inverse * glm::vec4(corner, 0.5f, 1.0f);
    const glm::vec4 clip = fitted.viewProj[0] * world;
    const glm::vec2 texel = (glm::vec2(clip) / clip.w * 0.5f + 0.5f) * 1024.0f;
    EXPECT_GE(std::min(texel.x, texel.y), 4.0f - 1e-2f);
    EXPECT_LE(std::max(texel.x, texel.y), 1020.0f + 1e-2f);
  }
  EXPECT_EQ(fitted.nearPlane, whole.nearPlane);
  EXPECT_EQ(fitted.farPlane, whole.farPlane);
  // A single receiver point: the zoom stops at the limit.
  const raster::ReceiverBounds dot{{0.1f, 0.1f}, {0.1f, 0.1f}, 1};
  EXPECT_NEAR(whole.texelWorld / raster::fitShadowMap(whole, dot, 4.0f, 16.0f).texelWorld, 16.0f, 1e-3f);
  // Nothing seen, or the whole map seen: unchanged.
  EXPECT_EQ(raster::fitShadowMap(whole, {}, 4.0f, 16.0f).texelWorld, whole.texelWorld);
  EXPECT_EQ(raster::fitShadowMap(whole, {{-1.0f, -1.0f}, {1.0f, 1.0f}, 5}, 4.0f, 16.0f).texelWorld, whole.texelWorld);
  // A light inside the scene: a cube, never fitted.
  Light point;
  point.type = LightType::Point;
  point.position = {0.0f, 1.0f, 0.0f};
  const shared::ShadowMapInfo cube = raster::makeShadowMapInfo(toGpuLight(point, bounds), bounds, settings);
  ASSERT_EQ(cube.faceCount, 6u);
  EXPECT_EQ(raster::fitShadowMap(cube, seen, 4.0f, 16.0f).texelWorld, cube.texelWorld);
}

}  // namespace
}  // namespace penumbra::test
