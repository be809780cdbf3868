#include "raytrace/embree_tracer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include <embree3/rtcore.h>

#include "core/cutouts.h"
#include "raytrace/embree_handles.h"
#include "shared/alpha.h"
#include "shared/frame.h"
#include "shared/indirect.h"
#include "shared/trace.h"

namespace penumbra {
namespace {

using embree::DevicePtr;
using embree::errorName;
using embree::GeometryPtr;
using embree::ScenePtr;

constexpr std::size_t kBlock = 256;  // points (or pixels) handed to a worker at a time

// Runs body(begin, end) over [0, count) in blocks on all cores. Each item's result depends only on
// the item, so the output is the same for any thread count or scheduling.
template <typename Body>
void parallelBlocks(std::size_t count, Body&& body) {
  const std::size_t blocks = (count + kBlock - 1) / kBlock;
  const std::size_t workers =
      std::min<std::size_t>(std::max(1u, std::thread::hardware_concurrency()), blocks);
  std::atomic<std::size_t> next{0};
  auto run = [&] {
    for (std::size_t b = next.fetch_add(1); b < blocks; b = next.fetch_add(1)) {
      body(b * kBlock, std::min(count, (b + 1) * kBlock));
    }
  };
  if (workers <= 1) {
    run();
    return;
  }
  std::vector<std::thread> pool;
  pool.reserve(workers - 1);
  for (std::size_t i = 1; i < workers; ++i) pool.emplace_back(run);
  run();  // the calling thread works too
  for (std::thread& t : pool) t.join();
}

RTCRay embreeRay(const glm::vec3& origin, const glm::vec3& dir, float tMax) {
  RTCRay ray{};
  ray.org_x = origin.x;
  ray.org_y = origin.y;
  ray.org_z = origin.z;
  ray.dir_x = dir.x;
  ray.dir_y = dir.y;
  ray.dir_z = dir.z;
  ray.tnear = 0.0f;
  ray.tfar = tMax;
  ray.mask = ~0u;
  return ray;
}

bool occluded(RTCScene scene, RTCIntersectContext& context, const glm::vec3& origin, const glm::vec3& dir, float tMax) {
  RTCRay ray = embreeRay(origin, dir, tMax);
  rtcOccluded1(scene, &context, &ray);
  return ray.tfar < 0.0f;  // Embree marks an occluded ray by setting tfar to -inf
}


// A cut-out mesh's filter data: the scene's cut-outs (core/cutouts.h, as the GPU tracers read them)
// and the index of the mesh's first CutoutTriangle there.
struct CutoutGeometry {
  const CutoutData* data;
  std::uint32_t first;
};

// Intersection and occlusion filter of a cut-out mesh: a candidate hit where the texture is cut
// away is rejected, and the ray goes on (shared/alpha.h's rule, as every GPU tracer applies it).
void cutoutFilter(const RTCFilterFunctionNArguments* args) {
  const auto* g = static_cast<const CutoutGeometry*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const shared::CutoutTriangle& c = g->data->triangles[g->first + RTCHitN_primID(args->hit, args->N, i)];
    const glm::vec2 uv =
        shared::cutoutUv(c.uv0, c.uv1, c.uv2, RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i));
    const std::uint32_t texel = c.texels + shared::cutoutTexel(uv, c.width, c.height);
    if (!shared::cutoutSolid(shared::cutoutAlpha(g->data->texels[texel / 4], texel), c.factor, c.cutoff)) {
      args->valid[i] = 0;
    }
  }
}

}  // namespace

struct EmbreeTracer::Impl {
  // Declared before the handles: the error callback writes here for their whole lifetime.
  std::mutex errorMutex;
  std::string firstError;
  // Member order matters: the scene must be released before the device that owns it.
  DevicePtr device;
  ScenePtr scene;
  std::vector<std::uint32_t> geomToMesh;  // Embree geomID -> Scene mesh index (empty meshes skipped)
  std::vector<std::uint32_t> geomFirstTriangle;  // Embree geomID -> scene-order index of its first triangle
  CutoutData cutouts;                          // the scene's cut-outs, which the filters read
  std::vector<CutoutGeometry> cutoutGeometries;  // each cut-out mesh's filter data (reserved: stable)

  void addCutout(RTCGeometry geom, std::uint32_t first) {
    CutoutGeometry& g = cutoutGeometries.emplace_back(CutoutGeometry{&cutouts, first - 1});
    rtcSetGeometryUserData(geom, &g);
    rtcSetGeometryIntersectFilterFunction(geom, &cutoutFilter);
    rtcSetGeometryOccludedFilterFunction(geom, &cutoutFilter);
  }
  double buildMs = 0.0;

  static void onError(void* user, RTCError code, const char* message) {
    auto* self = static_cast<Impl*>(user);
    std::lock_guard lock(self->errorMutex);
    if (self->firstError.empty()) {
      self->firstError = std::string(errorName(code)) + (message ? std::string(": ") + message : "");
    }
  }

  // Throws the first error Embree reported (by callback or error code) since the last check.
  void check(const char* stage) {
    const RTCError code = rtcGetDeviceError(device.get());
    std::string message;
    {
      std::lock_guard lock(errorMutex);
      message.swap(firstError);
    }
    if (message.empty() && code != RTC_ERROR_NONE) message = errorName(code);
    if (!message.empty()) throw std::runtime_error(std::string("Embree ") + stage + ": " + message);
  }
};

EmbreeTracer::EmbreeTracer(const Scene& scene) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.device.reset(rtcNewDevice(nullptr));
  if (!m.device) {
    // Without a device there is no callback yet; the thread-local error code is all we have.
    throw std::runtime_error(std::string("Embree device creation failed: ") +
                             errorName(rtcGetDeviceError(nullptr)));
  }
  rtcSetDeviceErrorFunction(m.device.get(), &Impl::onError, &m);

  const auto start = std::chrono::steady_clock::now();
  m.scene.reset(rtcNewScene(m.device.get()));
  m.check("scene creation");
  rtcSetSceneBuildQuality(m.scene.get(), RTC_BUILD_QUALITY_HIGH);
  // Robust mode avoids cracks between adjacent triangles that would leak light through meshes.
  rtcSetSceneFlags(m.scene.get(), RTC_SCENE_FLAG_ROBUST);

  m.cutouts = cutoutData(scene);
  const std::vector<std::uint32_t> firstCutout = cutoutIndices(scene);
  m.cutoutGeometries.reserve(scene.meshes.size());
  std::uint32_t firstTriangle = 0;
  for (std::size_t mi = 0; mi < scene.meshes.size(); ++mi) {
    const Mesh& mesh = scene.meshes[mi];
    const std::size_t triangles = mesh.triangleCount();
    firstTriangle += std::uint32_t(triangles);
    if (triangles == 0 || mesh.positions.empty()) continue;
    for (std::size_t i = 0; i < triangles * 3; ++i) {
      // Embree would read out of bounds, so bad input must stop here rather than crash later.
      if (mesh.indices[i] >= mesh.positions.size()) {
        throw std::invalid_argument("EmbreeTracer: mesh '" + mesh.name + "' has an index out of range");
      }
    }
    GeometryPtr geom(rtcNewGeometry(m.device.get(), RTC_GEOMETRY_TYPE_TRIANGLE));
    m.check("geometry creation");
    rtcSetGeometryBuildQuality(geom.get(), RTC_BUILD_QUALITY_HIGH);
    // Copies: the tracer must stay valid after the Scene is gone. Embree pads these buffers itself.
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom.get(), RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size()));
    auto* indices = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
        geom.get(), RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), triangles));
    m.check("buffer allocation");
    if (!vertices || !indices) throw std::runtime_error("Embree buffer allocation failed");
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      vertices[3 * v + 0] = mesh.positions[v].x;
      vertices[3 * v + 1] = mesh.positions[v].y;
      vertices[3 * v + 2] = mesh.positions[v].z;
    }
    std::copy_n(mesh.indices.begin(), triangles * 3, indices);
    if (firstCutout[mi] != 0) m.addCutout(geom.get(), firstCutout[mi]);
    rtcCommitGeometry(geom.get());
    const unsigned id = rtcAttachGeometry(m.scene.get(), geom.get());
    m.check("geometry commit");
    if (id >= m.geomToMesh.size()) m.geomToMesh.resize(id + 1, 0);
    if (id >= m.geomFirstTriangle.size()) m.geomFirstTriangle.resize(id + 1, 0);
    m.geomToMesh[id] = static_cast<std::uint32_t>(mi);
    m.geomFirstTriangle[id] = firstTriangle - std::uint32_t(triangles);
  }
  rtcCommitScene(m.scene.get());
  m.check("scene build");
  m.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

EmbreeTracer::~EmbreeTracer() = default;

double EmbreeTracer::buildMs() const { return impl_->buildMs; }

std::vector<PrimaryHit> EmbreeTracer::tracePrimary(const ViewMatrices& view, int width, int height) const {
  if (width <= 0 || height <= 0) throw std::invalid_argument("EmbreeTracer::tracePrimary: empty image");
  const std::size_t count = std::size_t(width) * std::size_t(height);
  std::vector<PrimaryHit> hits(count);
  RTCScene scene = impl_->scene.get();
  const std::vector<std::uint32_t>& geomToMesh = impl_->geomToMesh;

  parallelBlocks(count, [&](std::size_t begin, std::size_t end) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (std::size_t i = begin; i < end; ++i) {
      const int x = int(i % std::size_t(width));
      const int y = int(i / std::size_t(width));
      const Ray ray = pixelRay(view, x, y, width, height);
      RTCRayHit rh{};
      rh.ray.org_x = ray.origin.x;
      rh.ray.org_y = ray.origin.y;
      rh.ray.org_z = ray.origin.z;
      rh.ray.dir_x = ray.direction.x;
      rh.ray.dir_y = ray.direction.y;
      rh.ray.dir_z = ray.direction.z;
      rh.ray.tnear = 0.0f;
      rh.ray.tfar = std::numeric_limits<float>::infinity();
      rh.ray.mask = ~0u;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &context, &rh);
      if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
      PrimaryHit& h = hits[i];
      h.hit = true;
      h.position = ray.origin + rh.ray.tfar * ray.direction;
      glm::vec3 n{rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z};
      const float len = glm::length(n);
      n = len > 0.0f ? n / len : -ray.direction;
      h.normal = glm::dot(n, ray.direction) > 0.0f ? -n : n;  // face the camera
      h.mesh = rh.hit.geomID < geomToMesh.size() ? geomToMesh[rh.hit.geomID] : 0u;
    }
  });
  impl_->check("primary tracing");
  return hits;
}

std::uint64_t EmbreeTracer::traceShadows(std::span<const shared::ShadingPoint> points,
                                         const shared::GpuLight& light, std::span<float> visibility) const {
  if (visibility.size() != points.size()) {
    throw std::invalid_argument("EmbreeTracer::traceShadows: visibility size " +
                                std::to_string(visibility.size()) + " != points size " +
                                std::to_string(points.size()));
  }
  RTCScene scene = impl_->scene.get();
  const bool directional = light.type == LIGHT_DIRECTIONAL;
  std::atomic<std::uint64_t> totalRays{0};

  parallelBlocks(points.size(), [&](std::size_t begin, std::size_t end) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    std::uint64_t rays = 0;
    for (std::size_t i = begin; i < end; ++i) {
      const shared::ShadingPoint& sp = points[i];
      // spp 0 would divide by zero; like lightSampleCount, it means one sample.
      const std::uint32_t n = std::max(sp.spp, 1u);
      const glm::vec3 p = sp.position;
      const glm::vec3 normal = sp.normal;
      const glm::vec3 origin = shared::shadowRayOrigin(light, p, normal);
      std::uint32_t visible = 0;
      for (std::uint32_t s = 0; s < n; ++s) {
        const glm::vec3 q = shared::lightSamplePoint(light, sp.pixel, s, n);
        if (!shared::lightReaches(light, p, normal, q)) continue;
        const glm::vec3 d = shared::directionToLight(light, p, q);
        ++rays;
        // Stop just short of the light point so geometry at the light itself does not count.
        if (!occluded(scene, context, origin, d, shared::shadowRayEnd(glm::distance(origin, q), directional, sp.rayMax))) {
          ++visible;
        }
      }
      visibility[i] = float(visible) / float(n);
    }
    totalRays.fetch_add(rays, std::memory_order_relaxed);
  });
  impl_->check("shadow tracing");
  return totalRays.load();
}


std::uint64_t EmbreeTracer::traceIndirect(std::span<const shared::ShadingPoint> points, const shared::GpuLight& light,
                                          std::span<const shared::SceneTriangle> triangles,
                                          const shared::IndirectParams& params, std::span<glm::vec4> out,
                                          std::uint64_t* shadowRays) const {
  if (out.size() != points.size()) throw std::invalid_argument("EmbreeTracer::traceIndirect: output size != points size");
  RTCScene scene = impl_->scene.get();
  const std::vector<std::uint32_t>& firstTriangle = impl_->geomFirstTriangle;
  std::atomic<std::uint64_t> totalShadow{0};
  parallelBlocks(points.size(), [&](std::size_t begin, std::size_t end) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    std::uint64_t shadow = 0;
    for (std::size_t i = begin; i < end; ++i) {
      const shared::ShadingPoint& sp = points[i];
      const glm::vec3 origin = shared::shadowRayOrigin(light, sp.position, sp.normal);
      glm::vec3 reflected(0.0f);
      std::uint32_t blocked = 0;
      for (std::uint32_t k = 0; k < params.rays; ++k) {
        const glm::vec3 dir = shared::indirectDirection(sp.pixel, k, params.rays, params.frame, sp.normal);
        if (params.mode == INDIRECT_AO) {
          blocked += occluded(scene, context, origin, dir, params.aoRadius);
          continue;
        }
        RTCRayHit rh{};
        rh.ray = embreeRay(origin, dir, params.rayMax);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &context, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
        const shared::SceneTriangle& tri = triangles[firstTriangle[rh.hit.geomID] + rh.hit.primID];
        const shared::IndirectHit hit = shared::indirectHit(tri, origin, dir, rh.ray.tfar, light);
        if (!hit.lit) continue;
        ++shadow;
        if (!occluded(scene, context, hit.shadowOrigin, hit.toLight, hit.shadowEnd)) reflected += hit.reflected;
      }
      out[i] = glm::vec4(reflected / float(params.rays), float(blocked) / float(params.rays));
    }
    totalShadow.fetch_add(shadow, std::memory_order_relaxed);
  });
  impl_->check("indirect tracing");
  if (shadowRays) *shadowRays = totalShadow.load();
  return std::uint64_t(points.size()) * params.rays;
}

}  // namespace penumbra

namespace penumbra {

TraceReport EmbreeTracer::finish(const TraceJob& job) {
  const auto start = std::chrono::steady_clock::now();
  const auto count = job.count.download<shared::TraceCount>(1).front();
  const std::span<const shared::ShadingPoint> points(static_cast<const shared::ShadingPoint*>(job.points.data()), count.count);
  const auto& frame = *static_cast<const shared::FrameData*>(job.frame.data());
  std::vector<float> traced(points.size());
  TraceReport report;
  report.rays = traceShadows(points, frame.light, traced);
  auto* visibility = static_cast<float*>(job.visibility.data());
  for (std::size_t i = 0; i < points.size(); ++i) visibility[points[i].pixel] = traced[i];
  report.hostMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace penumbra
