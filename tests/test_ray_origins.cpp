// What counts as one surface (issue 17, item 0), and where shadow rays leave it.
// - The camera pass draws with reversed depth (core/camera.h), so it orders a decal a hair above
//   its surface instead of z-fighting between them: the G-buffer sees the decal, and no method or
//   reference shadows the surface under it in stripes.
#include <gtest/gtest.h>

#include "core/mesh_builder.h"
#include "render_fixture.h"

namespace penumbra::test {
namespace {

Mesh meshNamed(const std::string& name) {
  Mesh m;
  m.name = name;
  return m;
}

Scene sceneOf(std::vector<Mesh> meshes) {
  Scene s;
  s.name = "test";
  s.meshes = std::move(meshes);
  cleanScene(s, "test");
  return s;
}

// Fraction of covered pixels where two visibility buffers differ by more than 0.5; with
// `awayFromEdges`, only pixels whose 3x3 neighbourhood in `a` is all covered and all lit or all dark.
double differing(const Frame& a, const Frame& b, bool awayFromEdges = false) {
  const int w = int(a.width), h = int(a.height);
  auto uniform = [&](int x, int y) {
    if (x < 1 || y < 1 || x >= w - 1 || y >= h - 1) return false;
    const bool dark = a.visibility[std::size_t(y * w + x)] < 0.5f;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const std::size_t j = std::size_t((y + dy) * w + x + dx);
        if (!a.covered[j] || (a.visibility[j] < 0.5f) != dark) return false;
      }
    }
    return true;
  };
  std::size_t covered = 0, differ = 0;
  for (std::size_t i = 0; i < a.visibility.size(); ++i) {
    if (!a.covered[i]) continue;
    ++covered;
    if (awayFromEdges && !uniform(int(i % std::size_t(w)), int(i / std::size_t(w)))) continue;
    differ += std::abs(a.visibility[i] - b.visibility[i]) > 0.5f;
  }
  return covered ? double(differ) / double(covered) : 1.0;
}

// A 20x20 floor with a 4x4 decal `gap` above it, seen from inside the scene's bounds (a 30-unit
// mast behind the camera widens them), so the camera's near plane is 1e-4 of its far plane - where
// a conventional 32-bit depth cannot tell the two layers apart at this distance.
TEST(RayOrigins, CameraSeesTheDecalAHairAboveItsSurface) {
  const float gap = 1e-4f;
  Mesh floor = meshNamed("floor"), decal = meshNamed("decal"), mast = meshNamed("mast");
  mesh::addGrid(floor, {-10, 0, -10}, {20, 0, 0}, {0, 0, 20}, 10, 10, {0, 1, 0});
  mesh::addQuad(decal, {-2, gap, -2}, {2, gap, -2}, {2, gap, 2}, {-2, gap, 2}, {0, 1, 0});
  mesh::addBox(mast, {0, 15, 9.5f}, {0.2f, 0, 0}, {0, 15, 0}, {0, 0, 0.2f});
  const Scene scene = sceneOf({floor, decal, mast});
  RenderSettings settings = smallSettings(128, 1024);
  settings.rayEpsilon = 1e-6f;  // 2e-5 world units: the decal is more than that above the floor
  Renderer renderer(validatedContext(), scene, settings);
  const Camera camera{.eye = {0, 3, 7}, .target = {0, 0, 0}};
  const Light light{.type = LightType::Disk, .position = {-3, 12, 4}, .direction = glm::normalize(glm::vec3(3, -12, -4))};

  const Frame ref = renderer.render("ref", camera, light);
  const std::vector<glm::vec4> positions = renderer.gbuffer().positions();
  std::size_t inside = 0, decalSeen = 0, lit = 0;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const glm::vec4 p = positions[i];
    if (p.w == 0.0f || std::abs(p.x) > 1.9f || std::abs(p.z) > 1.9f) continue;  // the decal's footprint, off its rim
    ++inside;
    decalSeen += p.y > 0.5f * gap;
    lit += ref.visibility[i] == 1.0f;
  }
  ASSERT_GT(inside, 500u);
  EXPECT_EQ(decalSeen, inside) << "the floor shows through the decal";
  EXPECT_EQ(lit, inside) << "the decal's footprint is shadowed (the decal shadows the floor seen through it)";
  for (const char* method : {"sm", "srt", "frt"}) {
    EXPECT_EQ(differing(renderer.render(method, camera, light), ref), 0.0) << method;
  }
  expectValidationSilent();
}

}  // namespace
}  // namespace penumbra::test
