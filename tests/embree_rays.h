// Embree as the oracle the GPU BVH tests compare with, ray by ray: one geometry holding the
// scene's triangles in scene order (so primID is BvhTriangle.id), robust mode, high quality, and
// the ISA whose rounding the GPU traversal mirrors on this device.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include "core/scene.h"
#include "gpu/context.h"
#include "shared/bvh.h"

namespace penumbra::test {

// lavapipe lowers fma() to a multiply and an add, which is how Embree's SSE4.2 kernels round; its
// AVX2 kernels (the default on current CPUs) fuse, as GPUs do. With the same rounding the two
// robust triangle tests agree bit for bit, so even rays placed exactly on ties must agree.
inline const char* embreeConfigFor(const gpu::Context& context) {
  return context.deviceName().find("llvmpipe") != std::string::npos ? "isa=sse4.2" : nullptr;
}

class EmbreeRays {
 public:
  // The scene's triangles as they are now.
  EmbreeRays(const Scene& scene, const gpu::Context& context)
      : device_(rtcNewDevice(embreeConfigFor(context))), scene_(rtcNewScene(device_.get())) {
    rtcSetSceneFlags(scene_.get(), RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_.get(), RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geom = rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
    const std::size_t count = scene.triangleCount();
    auto* v = static_cast<glm::vec3*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(glm::vec3), 3 * count));
    auto* idx = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), count));
    unsigned corner = 0;
    for (const Mesh& mesh : scene.meshes) {
      for (std::uint32_t index : mesh.indices) {
        v[corner] = mesh.positions[index];
        idx[corner] = corner;
        ++corner;
      }
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_.get(), geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene_.get());
  }
  RTCRayHit closest(const shared::RayQuery& q) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh{.ray = ray(q)};
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_.get(), &context, &rh);
    return rh;
  }
  bool occluded(const shared::RayQuery& q) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r = ray(q);
    rtcOccluded1(scene_.get(), &context, &r);
    return r.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
  }

 private:
  struct Release {
    void operator()(RTCDevice d) const { rtcReleaseDevice(d); }
    void operator()(RTCScene s) const { rtcReleaseScene(s); }
  };
  static RTCRay ray(const shared::RayQuery& q) {
    return {q.origin.x, q.origin.y, q.origin.z, q.tMin, q.direction.x, q.direction.y, q.direction.z, 0.0f, q.tMax, ~0u};
  }
  std::unique_ptr<RTCDeviceTy, Release> device_;
  std::unique_ptr<RTCSceneTy, Release> scene_;
};

}  // namespace penumbra::test
