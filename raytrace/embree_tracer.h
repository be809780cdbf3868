// The reference tracer: an Embree scene of the same world-space triangles, traced on all cores.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/scene.h"
#include "raytrace/shadow_tracer.h"
#include "shared/indirect.h"
#include "shared/light.h"
#include "shared/shading_point.h"

namespace penumbra {

struct PrimaryHit {
  bool hit = false;
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f};  // geometric, unit, turned towards the camera
  std::uint32_t mesh = 0;
};

// Also a ShadowTracer: it reads the same host-visible point list the GPU tracers read.
class EmbreeTracer final : public ShadowTracer {
 public:
  explicit EmbreeTracer(const Scene& scene);  // builds a high-quality BVH; throws on device errors
  ~EmbreeTracer() override;
  EmbreeTracer(const EmbreeTracer&) = delete;
  EmbreeTracer& operator=(const EmbreeTracer&) = delete;

  // Wall-clock time of the BVH build (scene creation to commit), in milliseconds.
  double buildMs() const;

  // Closest hit through every pixel centre (pixelRay), row-major, width*height entries.
  std::vector<PrimaryHit> tracePrimary(const ViewMatrices& view, int width, int height) const;

  // visibility[i] = fraction of points[i].spp light samples (lightSamplePoint with
  // pixel = points[i].pixel) that reach the point: lightReaches() and no occluder between.
  // Shadow rays start at shared::shadowRayOrigin (the point lifted off its surface along the normal). Returns the number of rays traced.
  std::uint64_t traceShadows(std::span<const shared::ShadingPoint> points, const shared::GpuLight& light,
                             std::span<float> visibility) const;

  // The indirect rays of `points` (their pixel, position and normal) as indirect_trace.glsl traces
  // them: out[i] = (rgb one-bounce light, occlusion) from params.rays rays each, with `triangles`
  // (sceneTriangles) shading the hits. Returns the indirect rays traced; shadowRays gets the
  // shadow rays from their hits.
  std::uint64_t traceIndirect(std::span<const shared::ShadingPoint> points, const shared::GpuLight& light,
                              std::span<const shared::SceneTriangle> triangles, const shared::IndirectParams& params,
                              std::span<glm::vec4> out, std::uint64_t* shadowRays = nullptr) const;

  std::string name() const override { return "embree"; }
  void record(const vk::raii::CommandBuffer&, const TraceJob&) override {}
  TraceReport finish(const TraceJob& job) override;  // traces job.points on all cores
  std::optional<BvhRefitReport> sceneMoved(const Scene&) override { return std::nullopt; }  // built anew on next use

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra
