// Thin-triangle pass: a sliver 0.2 texel wide and 50 long mostly falls between texel centres of
// an ordinary shadow map; the thin mask must cover every texel its square touches (exact
// triangle-square overlap on the CPU), never farther than the triangle, and nothing else.
// Triangles are placed in texel space and unprojected, so their light-space size is known exactly.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "core/gpu_light.h"
#include "core/scene.h"
#include "gpu/pipeline.h"
#include "raster/scene_geometry.h"
#include "raster/shadow_map_pass.h"
#include "raster/thin_triangle_pass.h"
#include "render_fixture.h"
#include "shared/raster.h"
#include "shared/thin.h"

namespace penumbra {
namespace {

using raster::ThinTriangleSettings;
constexpr std::uint32_t kRes = 256;
using Tri = std::array<glm::dvec2, 3>;  // texel space


struct Maps {
  std::vector<float> ordinary;  // faceCount layers of kRes * kRes, row-major, framebuffer y
  std::vector<float> thin;
  float at(const std::vector<float>& m, std::uint32_t face, int x, int y) const {
    return m[(std::size_t(face) * kRes + std::size_t(y)) * kRes + std::size_t(x)];
  }
};

raster::ShadowMapSettings mapSettings() {
  raster::ShadowMapSettings s;
  s.resolution = kRes;
  return s;
}

// Runs the light pass, the thin pass and the ordinary coverage in one submission and reads back.
Maps render(const Scene& scene, const shared::ShadowMapInfo& info, ThinTriangleSettings thin = {}) {
  gpu::Context& context = test::validatedContext();
  const raster::SceneGeometry geometry(context, scene);
  const raster::ShadowMapPass shadowMap(context, mapSettings(), info.faceCount);
  raster::ThinTrianglePass pass(context, mapSettings(), info.faceCount, thin);
  const gpu::Buffer ordinaryBuffer(context, shadowMap.depth().bytes(), vk::BufferUsageFlagBits::eTransferDst, "test ordinary readback");
  const gpu::Buffer thinBuffer(context, pass.depth().bytes(), vk::BufferUsageFlagBits::eTransferDst, "test thin readback");
  context.submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
    using Stage = vk::PipelineStageFlagBits2;
    using Access = vk::AccessFlagBits2;
    shadowMap.record(cmd, geometry, info);  // the pair a frame records: both must be validation-clean
    pass.record(cmd, geometry, info);
    // Both maps are left for compute reads; the copy wants GENERAL, then they go back.
    for (const auto& [image, buffer] : {std::pair{&shadowMap.depth(), &ordinaryBuffer}, std::pair{&pass.depth(), &thinBuffer}}) {
      gpu::transition(cmd, *image, {vk::ImageLayout::eShaderReadOnlyOptimal, vk::ImageLayout::eGeneral,
                                    Stage::eComputeShader, Access::eNone, Stage::eCopy, Access::eTransferRead});
      gpu::copyImageToBuffer(cmd, *image, *buffer);
      gpu::transition(cmd, *image, {vk::ImageLayout::eGeneral, vk::ImageLayout::eShaderReadOnlyOptimal,
                                    Stage::eAllCommands, Access::eNone, Stage::eComputeShader,
                                    Access::eShaderSampledRead});
    }
  });
  const std::size_t count = std::size_t(info.faceCount) * kRes * kRes;
  return {ordinaryBuffer.download<float>(count), thinBuffer.download<float>(count)};
}

// World point at texel-space `texel` of `face`, a fraction t of the way from the near to the far plane.
glm::vec3 unproject(const shared::ShadowMapInfo& info, std::uint32_t face, glm::dvec2 texel, float t) {
  const glm::mat4 inv = glm::inverse(info.viewProj[face]);
  const glm::vec2 ndc = glm::vec2(texel / double(kRes) * 2.0 - 1.0);
  const glm::vec4 nearPoint = inv * glm::vec4(ndc, 0.0f, 1.0f);
  const glm::vec4 farPoint = inv * glm::vec4(ndc, 1.0f, 1.0f);
  return glm::mix(glm::vec3(nearPoint) / nearPoint.w, glm::vec3(farPoint) / farPoint.w, t);
}

// A triangle as the GPU sees it on one face: clipped to the near plane (z >= 0), in texel space.
struct Projected {
  std::vector<glm::dvec2> texel;  // convex, 0 (behind the light) or 3..4 corners
  std::vector<double> depth;
  double minDepth() const { return *std::min_element(depth.begin(), depth.end()); }
  double maxDepth() const { return *std::max_element(depth.begin(), depth.end()); }
};

// The first triangle of `mesh` projected with the float matrix, as the shaders do.
Projected project(const shared::ShadowMapInfo& info, std::uint32_t face, const Mesh& mesh) {
  std::array<glm::dvec4, 3> clip;
  for (int i = 0; i < 3; ++i) clip[i] = glm::dvec4(info.viewProj[face] * glm::vec4(mesh.positions[mesh.indices[i]], 1.0f));
  Projected out;
  auto add = [&](const glm::dvec4& c) {
    out.texel.push_back((glm::dvec2(c) / c.w * 0.5 + 0.5) * double(kRes));
    out.depth.push_back(c.z / c.w);
  };
  for (int i = 0; i < 3; ++i) {
    const glm::dvec4& a = clip[i];
    const glm::dvec4& b = clip[(i + 1) % 3];
    if (a.z >= 0.0) add(a);
    if ((a.z >= 0.0) != (b.z >= 0.0)) add(glm::mix(a, b, a.z / (a.z - b.z)));
  }
  if (out.texel.size() < 3) out = {};
  return out;
}

double cross(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

// Separating axes (the square's two, the polygon's edge normals): the closed square [lo, hi] and
// the convex polygon overlap iff no axis separates them.
bool overlaps(const std::vector<glm::dvec2>& poly, glm::dvec2 lo, glm::dvec2 hi) {
  const std::array<glm::dvec2, 4> corners{lo, glm::dvec2(hi.x, lo.y), hi, glm::dvec2(lo.x, hi.y)};
  std::vector<glm::dvec2> axes{{1, 0}, {0, 1}};
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const glm::dvec2 e = poly[(i + 1) % poly.size()] - poly[i];
    axes.emplace_back(e.y, -e.x);
  }
  for (const glm::dvec2& n : axes) {
    double pa = 1e300, pb = -1e300, sa = 1e300, sb = -1e300;
    for (const glm::dvec2& p : poly) pa = std::min(pa, glm::dot(n, p)), pb = std::max(pb, glm::dot(n, p));
    for (const glm::dvec2& p : corners) sa = std::min(sa, glm::dot(n, p)), sb = std::max(sb, glm::dot(n, p));
    if (pb < sa || sb < pa) return false;
  }
  return true;
}

// Distance from p to the closed convex polygon in texel space.
double distance(const std::vector<glm::dvec2>& poly, glm::dvec2 p) {
  bool anyPositive = false, anyNegative = false;
  double best = 1e300;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const glm::dvec2 a = poly[i], e = poly[(i + 1) % poly.size()] - a;
    const double side = cross(e, p - a);
    anyPositive |= side > 0.0;
    anyNegative |= side < 0.0;
    const double u = std::clamp(glm::dot(p - a, e) / std::max(glm::dot(e, e), 1e-300), 0.0, 1.0);
    best = std::min(best, glm::length(p - (a + u * e)));
  }
  return anyPositive && anyNegative ? best : 0.0;
}

// The least depth of the projected triangle over the square [lo, hi] (+infinity where they do not
// meet): NDC depth is affine over the triangle in texel space, so its minimum over the triangle
// clipped to the square lies at a corner of that polygon (Sutherland-Hodgman, one side at a time).
double minDepthOver(const Projected& tri, glm::dvec2 lo, glm::dvec2 hi) {
  std::vector<glm::dvec3> poly;  // texel x, y and depth
  for (std::size_t i = 0; i < tri.texel.size(); ++i) poly.emplace_back(tri.texel[i], tri.depth[i]);
  for (int side = 0; side < 4 && !poly.empty(); ++side) {
    const int axis = side % 2;
    const double bound = side < 2 ? lo[axis] : hi[axis];
    const auto inside = [&](const glm::dvec3& p) { return side < 2 ? p[axis] >= bound : p[axis] <= bound; };
    std::vector<glm::dvec3> kept;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const glm::dvec3 a = poly[i], b = poly[(i + 1) % poly.size()];
      if (inside(a)) kept.push_back(a);
      if (inside(a) != inside(b)) kept.push_back(glm::mix(a, b, (bound - a[axis]) / (b[axis] - a[axis])));
    }
    poly = std::move(kept);
  }
  double least = std::numeric_limits<double>::infinity();
  for (const glm::dvec3& p : poly) least = std::min(least, p.z);
  return least;
}

// A mesh holding one triangle (normals left to cleanScene).
void addTriangle(Scene& scene, const char* name, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  Mesh& m = scene.meshes.emplace_back();
  m.name = name;
  m.positions = {a, b, c};
  m.indices = {0, 1, 2};
}

// Texel-space corners of a sliver: `length` long from `start` at `angleDeg`, its apex `width` off
// the base 60% along, so its smallest altitude is exactly `width`.
Tri sliver(glm::dvec2 start, double angleDeg, double length, double width) {
  const double a = glm::radians(angleDeg);
  const glm::dvec2 dir(std::cos(a), std::sin(a));
  const glm::dvec2 perp(-dir.y, dir.x);
  return {start, start + length * dir, start + 0.6 * length * dir + width * perp};
}

Scene sceneWith(const shared::ShadowMapInfo& info, std::uint32_t face, const Tri& thin, float t) {
  Scene scene;
  scene.name = "thin test";
  // Each corner at a slightly different distance, so the triangle is not parallel to the face.
  addTriangle(scene, "thin", unproject(info, face, thin[0], t), unproject(info, face, thin[1], t + 0.04f),
              unproject(info, face, thin[2], t + 0.02f));
  return scene;
}

struct Coverage {
  int touched = 0;       // texels whose square the thin triangle overlaps
  int ordinaryHits = 0;  // of those, how many the ordinary shadow map recorded the triangle in
  int reached = 0;       // texels with a touched texel in their 3x3 block: the dilated mask's share
  int maskMissing = 0;   // reached texels the mask left at 1.0
  int maskTooFar = 0;    // reached texels where the mask is farther than the triangle
  int strayFar = 0;      // texels more than 3 texels from the thin triangle that the mask covers
  double maskFarthest = 0.0;  // the mask's deepest value over the reached texels
};

Coverage measure(const Maps& maps, std::uint32_t face, const Projected& tri) {
  constexpr double kMargin = 1e-3;  // overlap by more than float noise: ties are not "touched"
  Coverage c;
  for (int y = 0; y < int(kRes); ++y) {
    for (int x = 0; x < int(kRes); ++x) {
      const float mask = maps.at(maps.thin, face, x, y);
      const glm::dvec2 lo(x + kMargin, y + kMargin), hi(x + 1 - kMargin, y + 1 - kMargin);
      if (!tri.texel.empty() && overlaps(tri.texel, lo, hi)) {
        ++c.touched;
        if (maps.at(maps.ordinary, face, x, y) <= tri.maxDepth() + 1e-5) ++c.ordinaryHits;
      }
      // The mask is dilated (THIN_DILATE_TEXELS = 1): texel (x, y) stands for its 3x3 block.
      const glm::dvec2 blockLo(x - 1 + kMargin, y - 1 + kMargin), blockHi(x + 2 - kMargin, y + 2 - kMargin);
      if (!tri.texel.empty() && overlaps(tri.texel, blockLo, blockHi)) {
        ++c.reached;
        if (mask >= 1.0f) ++c.maskMissing;
        // Never farther than the triangle within the block; and where the triangle slopes away
        // from the light, deeper than its nearest corner.
        const double least = minDepthOver(tri, blockLo, blockHi);
        if (double(mask) > least + 1e-5) ++c.maskTooFar;
        c.maskFarthest = std::max(c.maskFarthest, double(mask));
      } else if (mask < 1.0f && (tri.texel.empty() || distance(tri.texel, glm::dvec2(x + 0.5, y + 0.5)) > 3.0)) {
        ++c.strayFar;
      }
    }
  }
  return c;
}

void expectThinCovered(const Coverage& c) {
  EXPECT_GT(c.touched, 50);
  EXPECT_LT(c.ordinaryHits * 4, c.touched) << "the ordinary map was expected to miss most of the sliver";
  EXPECT_GT(c.reached, c.touched);
  EXPECT_EQ(c.maskMissing, 0) << "of " << c.reached << " texels whose 3x3 block the sliver touches";
  EXPECT_EQ(c.maskTooFar, 0);
  EXPECT_EQ(c.strayFar, 0);
}

int coveredTexels(const Maps& maps, std::uint32_t face) {
  int n = 0;
  for (int y = 0; y < int(kRes); ++y)
    for (int x = 0; x < int(kRes); ++x) n += maps.at(maps.thin, face, x, y) < 1.0f ? 1 : 0;
  return n;
}

Bounds box(glm::vec3 lo, glm::vec3 hi) {
  Bounds b;
  b.extend(lo);
  b.extend(hi);
  return b;
}

shared::ShadowMapInfo infoFor(const Light& light, const Bounds& bounds) {
  return raster::makeShadowMapInfo(toGpuLight(light, bounds), bounds, mapSettings());
}

// One face: the sliver plus a large regular triangle elsewhere that the ordinary map shows and
// the mask must not.
void checkSingleFace(const Light& light, std::uint32_t expectedKind) {
  const Bounds bounds = box({-4, 0, -4}, {4, 2, 4});
  const shared::ShadowMapInfo info = infoFor(light, bounds);
  ASSERT_EQ(info.kind, expectedKind);
  const Tri thin = sliver({140.3, 150.7}, 23.0, 50.0, 0.2);
  Scene scene = sceneWith(info, 0, thin, 0.4f);
  addTriangle(scene, "large", unproject(info, 0, {20, 20}, 0.6f), unproject(info, 0, {110, 25}, 0.6f),
              unproject(info, 0, {30, 115}, 0.65f));
  cleanScene(scene, "thin test");
  ASSERT_EQ(scene.triangleCount(), 2u);
  const Projected tri = project(info, 0, scene.meshes[0]);
  ASSERT_EQ(tri.texel.size(), 3u);
  ASSERT_TRUE(shared::thinTriangle(glm::vec2(tri.texel[0]), glm::vec2(tri.texel[1]), glm::vec2(tri.texel[2]), 1.0f, 4.0f));

  const Maps maps = render(scene, info);
  const Coverage coverage = measure(maps, 0, tri);
  expectThinCovered(coverage);
  // The mask follows the sliver's depth: its far end is not stamped with the nearest corner's.
  EXPECT_GT(coverage.maskFarthest, tri.minDepth() + 0.5 * (tri.maxDepth() - tri.minDepth()));
  // The large triangle: ordinary map yes, mask no (its texels are far from the sliver).
  int largeOrdinary = 0, largeMask = 0;
  for (int y = 25; y < 60; ++y) {
    for (int x = 25; x < 60; ++x) {
      largeOrdinary += maps.at(maps.ordinary, 0, x, y) < 1.0f ? 1 : 0;
      largeMask += maps.at(maps.thin, 0, x, y) < 1.0f ? 1 : 0;
    }
  }
  EXPECT_GT(largeOrdinary, 1000);
  EXPECT_EQ(largeMask, 0);
  test::expectValidationSilent();
}

// The selection pass lists exactly the thin triangles, is kept while the light and the geometry
// stay, and a face whose list overflows draws the whole scene: the mask is the same either way.
TEST(ThinTrianglePass, SelectionListsThinTrianglesIsReusedAndOverflowsSafely) {
  Light light;
  light.type = LightType::Directional;
  light.direction = glm::normalize(glm::vec3(0.2f, -1.0f, 0.1f));
  const shared::ShadowMapInfo info = infoFor(light, box({-4, 0, -4}, {4, 2, 4}));
  Scene scene = sceneWith(info, 0, sliver({140.3, 150.7}, 23.0, 50.0, 0.2), 0.4f);
  const Scene second = sceneWith(info, 0, sliver({40.6, 200.2}, -8.0, 60.0, 0.3), 0.5f);
  scene.meshes.push_back(second.meshes[0]);
  addTriangle(scene, "large", unproject(info, 0, {20, 20}, 0.6f), unproject(info, 0, {110, 25}, 0.6f),
              unproject(info, 0, {30, 115}, 0.65f));
  cleanScene(scene, "selection test");
  ASSERT_EQ(scene.triangleCount(), 3u);

  gpu::Context& context = test::validatedContext();
  raster::SceneGeometry geometry(context, scene);
  const gpu::Buffer readback(context, vk::DeviceSize(kRes) * kRes * 4, vk::BufferUsageFlagBits::eTransferDst, "test readback");
  auto mask = [&](raster::ThinTrianglePass& pass) {
    context.submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
      using Stage = vk::PipelineStageFlagBits2;
      using Access = vk::AccessFlagBits2;
      pass.record(cmd, geometry, info);
      gpu::transition(cmd, pass.depth(), {vk::ImageLayout::eShaderReadOnlyOptimal, vk::ImageLayout::eGeneral,
                                          Stage::eComputeShader, Access::eNone, Stage::eCopy, Access::eTransferRead});
      gpu::copyImageToBuffer(cmd, pass.depth(), readback);
      gpu::transition(cmd, pass.depth(), {vk::ImageLayout::eGeneral, vk::ImageLayout::eShaderReadOnlyOptimal,
                                          Stage::eCopy, Access::eNone, Stage::eComputeShader, Access::eShaderSampledRead});
    });
    return readback.download<float>(std::size_t(kRes) * kRes);
  };

  raster::ThinTrianglePass pass(context, mapSettings(), 1);
  const std::vector<float> first = mask(pass);
  EXPECT_FALSE(pass.selectionReused());
  EXPECT_EQ(pass.thinTriangles(), 2u);
  EXPECT_EQ(mask(pass), first);
  EXPECT_TRUE(pass.selectionReused());
  geometry.update(scene);  // posed anew (here: the same pose): selected again
  EXPECT_EQ(mask(pass), first);
  EXPECT_FALSE(pass.selectionReused());

  raster::ThinTrianglePass small(context, mapSettings(), 1, {.listCapacity = 1});
  EXPECT_EQ(mask(small), first);  // one listed, both drawn through the whole-scene draw
  EXPECT_EQ(small.thinTriangles(), 2u);
  const int covered = int(std::count_if(first.begin(), first.end(), [](float v) { return v < 1.0f; }));
  EXPECT_GT(covered, 2 * 150);  // both slivers (about 3 texels across 50-60 texels each)
  test::expectValidationSilent();
}

TEST(ThinCriterion, SliversAndEdgeOnAreThinRegularAndPointsAreNot) {
  using glm::vec2;
  auto thin = [](vec2 a, vec2 b, vec2 c, float maxWidth = 1.0f, float minAspect = 4.0f) {
    return shared::thinTriangle(a, b, c, maxWidth, minAspect);
  };
  EXPECT_TRUE(thin({0, 0}, {50, 0}, {30, 0.2f}));                   // sliver: altitude 0.2, aspect 250
  EXPECT_TRUE(thin({0, 0}, {50, 0}, {30, 0}));                      // edge-on: a segment
  EXPECT_FALSE(thin({0, 0}, {0.6f, 0}, {0.3f, 0.52f}));             // sub-texel but regular (aspect ~1.15)
  EXPECT_TRUE(thin({0, 0}, {0.6f, 0}, {0.3f, 0.52f}, 1.0f, 0.0f));  // ... unless the aspect test is off
  EXPECT_FALSE(thin({0, 0}, {50, 0}, {30, 0.2f}, 0.1f));            // wider than maxWidth
  EXPECT_FALSE(thin({0, 0}, {10, 0}, {5, 3}));                      // plainly large
  EXPECT_FALSE(thin({3, 3}, {3, 3}, {3, 3}));                       // a point: nothing to miss
  EXPECT_TRUE(shared::thinMeasure(40.0f, 40.0f * 0.5f, 1.0f, 4.0f));  // altitude 0.5, aspect 80
}

TEST(ThinTrianglePass, DirectionalSliverIsCoveredConservatively) {
  Light light;
  light.type = LightType::Directional;
  light.direction = glm::normalize(glm::vec3(0.2f, -1.0f, 0.1f));
  checkSingleFace(light, SHADOW_ORTHO);
}

TEST(ThinTrianglePass, PerspectiveSliverIsCoveredConservatively) {
  Light light;
  light.type = LightType::Point;
  light.position = {1.0f, 14.0f, 0.5f};  // outside the bounding sphere: one perspective face
  checkSingleFace(light, SHADOW_PERSPECTIVE);
}

// A closed room around a point light: a cube map whose walls cross every face's near plane.
struct Room {
  Bounds bounds = box({-2, 0, -2}, {2, 3, 2});
  Light light;
  shared::ShadowMapInfo info;
  Room() {
    light.type = LightType::Point;
    light.position = {0.3f, 1.2f, -0.2f};
    info = infoFor(light, bounds);
  }
  void addWalls(Scene& scene) const {
    Mesh& room = scene.meshes.emplace_back();
    room.name = "room";
    for (int i = 0; i < 8; ++i) room.positions.push_back(glm::mix(bounds.lo, bounds.hi, glm::vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1)));
    room.indices = {0, 1, 3, 0, 3, 2, 4, 7, 5, 4, 6, 7, 0, 5, 1, 0, 4, 5, 2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3};
  }
  bool inside(const Mesh& mesh) const {
    for (const glm::vec3& p : mesh.positions) {
      if (!glm::all(glm::lessThan(p, bounds.hi)) || !glm::all(glm::greaterThan(p, bounds.lo))) return false;
    }
    return true;
  }
};

TEST(ThinTrianglePass, CubeSliverIsCoveredOnItsFaceOnly) {
  const Room room;
  ASSERT_EQ(room.info.kind, SHADOW_CUBE);
  const std::uint32_t face = 0;  // +X
  Scene scene = sceneWith(room.info, face, sliver({70.6, 100.2}, -31.0, 50.0, 0.2), 0.25f);
  room.addWalls(scene);
  cleanScene(scene, "thin cube test");
  ASSERT_EQ(scene.triangleCount(), 13u);
  ASSERT_TRUE(room.inside(scene.meshes[0]));

  const Maps maps = render(scene, room.info);
  expectThinCovered(measure(maps, face, project(room.info, face, scene.meshes[0])));
  for (std::uint32_t other = 1; other < 6; ++other) EXPECT_EQ(coveredTexels(maps, other), 0) << "face " << other;
  test::expectValidationSilent();
}

// A wire passing over the light from +x to -x: the +X and -X faces each see a piece whose other
// end is behind their near plane (clipped there), the +Y and +Z faces pieces that leave the face.
TEST(ThinTrianglePass, CubeWirePastTheLightIsCoveredOnEveryFaceItCrosses) {
  const Room room;
  const glm::vec3 l = room.light.position;
  const glm::vec3 a = l + glm::vec3(0.8f, 0.5f, 0.3f), b = l + glm::vec3(-0.8f, 0.5f, 0.6f);
  const glm::vec3 apexBase = glm::mix(a, b, 0.6f);
  // 1 mm off the base, across the line of sight: about 0.2-0.5 texel at 0.5-0.9 from the light.
  const glm::vec3 across = glm::normalize(glm::cross(b - a, apexBase - l));
  Scene scene;
  scene.name = "thin wire test";
  addTriangle(scene, "wire", a, b, apexBase + 0.001f * across);
  room.addWalls(scene);
  cleanScene(scene, "thin wire test");
  ASSERT_EQ(scene.triangleCount(), 13u);
  ASSERT_TRUE(room.inside(scene.meshes[0]));

  const Maps maps = render(scene, room.info);
  int facesCrossed = 0;
  for (std::uint32_t face = 0; face < 6; ++face) {
    const Coverage c = measure(maps, face, project(room.info, face, scene.meshes[0]));
    facesCrossed += c.touched > 0 ? 1 : 0;
    EXPECT_EQ(c.maskMissing, 0) << "face " << face << ": of " << c.touched << " touched texels";
    EXPECT_EQ(c.maskTooFar, 0) << "face " << face;
    EXPECT_EQ(c.strayFar, 0) << "face " << face;
  }
  EXPECT_GE(facesCrossed, 3);  // +X, +Y, -X at least
  test::expectValidationSilent();
}

TEST(ThinTrianglePass, ThresholdsKeepRegularAndWideTrianglesOut) {
  Light light;
  light.type = LightType::Directional;
  light.direction = glm::normalize(glm::vec3(0.2f, -1.0f, 0.1f));
  const shared::ShadowMapInfo info = infoFor(light, box({-4, 0, -4}, {4, 2, 4}));
  // Sub-texel equilateral triangle (side 0.6 texel, aspect ~1.15) straddling texel borders.
  const Scene small = [&] {
    Scene s = sceneWith(info, 0, {glm::dvec2(99.8, 99.9), glm::dvec2(100.4, 99.9), glm::dvec2(100.1, 100.42)}, 0.5f);
    cleanScene(s, "small");
    return s;
  }();
  EXPECT_EQ(coveredTexels(render(small, info), 0), 0);
  // The same triangle is drawn once the aspect test is off: maxWidth alone would enlarge it.
  EXPECT_GE(coveredTexels(render(small, info, {.maxWidthTexels = 1.0f, .minAspect = 0.0f}), 0), 1);
  // A 0.2-texel sliver is not thin for maxWidth 0.1.
  Scene slim = sceneWith(info, 0, sliver({60.5, 140.5}, 10.0, 50.0, 0.2), 0.5f);
  cleanScene(slim, "slim");
  EXPECT_EQ(coveredTexels(render(slim, info, {.maxWidthTexels = 0.1f, .minAspect = 4.0f}), 0), 0);
  test::expectValidationSilent();
}

TEST(ThinTrianglePass, RejectsBadSettings) {
  gpu::Context& context = test::validatedContext();
  EXPECT_THROW(raster::ThinTrianglePass(context, mapSettings(), 1, {.maxWidthTexels = 0.0f}), InputError);
  EXPECT_THROW(raster::ThinTrianglePass(context, mapSettings(), 1, {.maxWidthTexels = NAN}), InputError);
  EXPECT_THROW(raster::ThinTrianglePass(context, mapSettings(), 1, {.minAspect = -1.0f}), InputError);
  test::expectValidationSilent();
}

}  // namespace
}  // namespace penumbra
