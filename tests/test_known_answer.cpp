// builtin:square has an analytic shadow: ground [-5,5]^2 at y=0, a square occluder [-1,1]^2 at
// y=1 and a directional light travelling along normalize(0.3,-1,0.2). A ground point p is in
// shadow iff p moved towards the light up to y=1 lands inside the square. `ref` must agree up to
// numerical noise; `sm` up to the footprint of a shadow-map texel around the shadow's edge.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "core/gpu_light.h"
#include "render_fixture.h"

namespace penumbra::test {
namespace {

const glm::vec3 kLightDir = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));

struct Disagreement {
  int pixels = 0;              // covered pixels whose answer differs from the analytic one
  double maxEdgeDistance = 0;  // of those, the farthest from the shadow's edge (occluder plane)
  int shadowed = 0;            // pixels the analytic answer puts in shadow
  int occluderWrong = 0;       // lit occluder-top pixels reported as shadowed
};

// Distance in the occluder plane from (x, z) to the boundary of [-1,1]^2.
double distanceToSquareEdge(double x, double z) {
  const double dx = std::abs(x) - 1.0, dz = std::abs(z) - 1.0;
  if (dx < 0.0 && dz < 0.0) return -std::max(dx, dz);
  return std::hypot(std::max(dx, 0.0), std::max(dz, 0.0));
}

Disagreement againstAnalytic(const Frame& frame, const std::vector<glm::vec4>& positions) {
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
    const bool inside = std::abs(q.x) < 1.0f && std::abs(q.z) < 1.0f;
    d.shadowed += inside;
    if (lit == inside) {  // lit inside the shadow, or shadowed outside it
      ++d.pixels;
      d.maxEdgeDistance = std::max(d.maxEdgeDistance, distanceToSquareEdge(q.x, q.z));
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
  const Disagreement d = againstAnalytic(frame, run.renderer->gbuffer().positions());
  EXPECT_GT(d.shadowed, 500) << "the shadow must be in view";
  EXPECT_EQ(d.occluderWrong, 0);
  // Only pixels whose shading point is within float noise of the edge may differ.
  EXPECT_LE(d.maxEdgeDistance, 1e-3) << d.pixels << " pixels differ";
  expectValidationSilent();
}

TEST(KnownAnswer, ShadowMapWithinATexelOfAnalyticShadow) {
  for (std::uint32_t res : {512u, 2048u}) {
    RenderSettings settings = smallSettings(256, res);
    SceneRun run("builtin:square", settings);
    const Frame frame = run.render("sm");
    const Disagreement d = againstAnalytic(frame, run.renderer->gbuffer().positions());
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

}  // namespace
}  // namespace penumbra::test
