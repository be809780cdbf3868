// What counts as one surface (issue 17, item 0), and where shadow rays leave it.
// - The camera pass draws with reversed depth (core/camera.h), so it orders a decal a hair above
//   its surface instead of z-fighting between them: the G-buffer sees the decal, and no method or
//   reference shadows the surface under it in stripes.
// - Shadow rays leave a surface by the scene's tolerance or by the position's own float error,
//   whichever is larger (shared::shadowRayOrigin), so a scene far from the origin does not shadow
//   itself in the reference, and the GPU tracers agree with it.
// - A model read from a file far from the world origin is stored relative to Scene::origin
//   (issue 20), so it renders as it would at the origin.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <unistd.h>

#include "core/view.h"

#include "core/mesh_builder.h"
#include "mesh_checks.h"
#include "render_fixture.h"

namespace penumbra::test {
namespace {

// A 20x20 floor with a 4x4 decal `gap` above it, seen from inside the scene's bounds (a 30-unit
// mast behind the camera widens them), so the camera's near plane is 1e-4 of its far plane - where
// a conventional 32-bit depth cannot tell the two layers apart at this distance.
TEST(RayOrigins, CameraSeesTheDecalAHairAboveItsSurface) {
  const float gap = 1e-4f;
  Mesh floor = namedMesh("floor"), decal = namedMesh("decal"), mast = namedMesh("mast");
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
  const std::vector<glm::vec4> positions = renderer.frameContext().gbuffer().positions();
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
    EXPECT_EQ(differingPixels(renderer.render(method, camera, light), ref), 0.0) << method;
  }
  expectValidationSilent();
}

// A ball on a floor at the origin and the same scene 1e5 units away (camera and light moved along):
// the reference sees the same shadows in both but along their edges, which move with the vertices
// (at 1e5 one float step is 0.008 units); a fixed origin offset of 1e-4 of the scene radius left
// the far ball shadowing itself in speckles (8% of the pixels differed). The GPU tracer agrees.
TEST(RayOrigins, FarFromTheOriginNothingShadowsItself) {
  auto scene = [](glm::vec3 o) {
    Mesh floor = namedMesh("floor"), ball = namedMesh("ball");
    mesh::addQuad(floor, o + glm::vec3(-4, 0, -4), o + glm::vec3(4, 0, -4), o + glm::vec3(4, 0, 4),
                  o + glm::vec3(-4, 0, 4), {0, 1, 0});
    mesh::addSphere(ball, o + glm::vec3(0, 1, 0), 1.0f, 48, 24);
    return sceneOf({floor, ball});
  };
  auto render = [&](glm::vec3 o, const char* method) {
    const Scene s = scene(o);  // the renderer keeps a reference
    Renderer renderer(validatedContext(), s, smallSettings(128, 1024));
    const Camera camera{.eye = o + glm::vec3(3, 3, 4), .target = o + glm::vec3(0, 0.7f, 0)};
    const Light light{.type = LightType::Disk, .position = o + glm::vec3(-3, 6, 1.5f), .direction = {0.45f, -0.89f, -0.1f}};
    return renderer.render(method, camera, light);
  };
  const Frame near = render({0, 0, 0}, "ref");
  const Frame far = render({1e5f, 0, 1e5f}, "ref");
  // Measured 0.009%: the ball's points carry float rounding of 1e5-unit coordinates.
  EXPECT_LE(differingPixels(near, far, true), 0.00027) << "the reference far from the origin shadows itself";
  EXPECT_EQ(differingPixels(render({1e5f, 0, 1e5f}, "frt"), far), 0.0);
  expectValidationSilent();
}

// A 20-unit scene (ground, box, a pole 0.06 wide) written as an OBJ whose coordinates are
// `offset` + its own, with 6 decimals, as georeferenced tiles come.
std::string writeObjAt(double offset) {
  Mesh m;
  mesh::addQuad(m, {-10, 0, -10}, {10, 0, -10}, {10, 0, 10}, {-10, 0, 10}, {0, 1, 0});
  mesh::addBox(m, {0, 1.5f, 0}, {2, 0, 0}, {0, 1.5f, 0}, {0, 0, 2});
  mesh::addBox(m, {4, 3, 3}, {0.03f, 0, 0}, {0, 3, 0}, {0, 0, 0.03f});
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("penumbra_far_" + std::to_string(::getpid()) + "_" + std::to_string(offset) + ".obj")).string();
  writeObj({m}, path, {offset, 0.0, offset});
  return path;
}

// Before Scene::origin, this scene placed 1e6 units away was 2.4% wrong with sm and 1.8% with srt
// (at the origin: 0.06% and 0): acne over the ground and lost pole shadows. Now every method sees
// what it sees at the origin, and the view options given in world coordinates land where they did.
TEST(RayOrigins, GeoreferencedModelRendersAsAtTheOrigin) {
  static constexpr const char* kMethods[] = {"ref", "sm", "srt", "frt"};
  auto renderAt = [](double offset) {
    const std::string path = writeObjAt(offset);
    const Scene scene = loadScene(path);
    std::filesystem::remove(path);
    char camera[160], light[160];
    std::snprintf(camera, sizeof camera, "%.6f,12,%.6f:%.6f,0,%.6f", offset + 14, offset + 16, offset, offset);
    std::snprintf(light, sizeof light, "point:%.6f,18,%.6f", offset - 6, offset + 4);
    Renderer renderer(validatedContext(), scene, smallSettings(128, 1024));
    std::vector<Frame> frames;
    for (const char* method : kMethods) {
      frames.push_back(renderer.render(method, parseCamera(camera, scene.origin), parseLight(light, scene.origin)));
    }
    return std::pair(scene.origin, frames);
  };
  const auto [nearOrigin, near] = renderAt(0.0);
  EXPECT_EQ(nearOrigin, glm::dvec3(0.0));
  for (const double offset : {1e5, 1e6}) {
    const auto [origin, far] = renderAt(offset);
    EXPECT_GT(glm::length(origin), 0.9 * offset) << "the model is stored relative to a far origin";
    for (std::size_t m = 0; m < far.size(); ++m) {
      // Stored relative to its own origin, the model is the same floats as at the origin: identical.
      EXPECT_EQ(differingPixels(near[m], far[m]), 0.0) << kMethods[m] << " at " << offset;
    }
    EXPECT_EQ(differingPixels(far[0], far[2]), 0.0) << "srt against the reference at " << offset;
  }
  expectValidationSilent();
}

}  // namespace
}  // namespace penumbra::test
