// The raster G-buffer and Embree's primary rays see the same surfaces through the same pixel
// centres (core/camera.h is the one mapping both use).
#include <gtest/gtest.h>

#include "raytrace/embree_tracer.h"
#include "render_fixture.h"

namespace penumbra::test {
namespace {

double agreement(const std::string& spec, std::uint32_t size) {
  SceneRun run(spec, smallSettings(size, 256));
  run.render("sm");
  const std::vector<glm::vec4> raster = run.renderer->frameContext().gbuffer().positions();
  EmbreeTracer embree(run.scene);
  const Bounds bounds = run.scene.bounds();
  const auto hits = embree.tracePrimary(cameraMatrices(run.camera, bounds, int(size), int(size)), int(size), int(size));
  const float tolerance = 1e-3f * bounds.radius();
  std::size_t agree = 0, covered = 0;
  for (std::size_t i = 0; i < hits.size(); ++i) {
    const bool rasterHit = raster[i].w != 0.0f;
    covered += rasterHit || hits[i].hit;
    if (rasterHit && hits[i].hit) agree += glm::length(glm::vec3(raster[i]) - hits[i].position) <= tolerance;
  }
  EXPECT_GT(covered, hits.size() / 4) << spec << ": most of the image should show geometry";
  expectValidationSilent();
  return double(agree) / double(covered);
}

TEST(PrimaryVisibility, RasterAgreesWithEmbreeOnCourtyard) { EXPECT_GE(agreement("builtin:courtyard", 256), 0.99); }
TEST(PrimaryVisibility, RasterAgreesWithEmbreeInRoom) { EXPECT_GE(agreement("builtin:room", 128), 0.99); }

}  // namespace
}  // namespace penumbra::test
