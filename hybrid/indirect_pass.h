// Indirect rays on the GPU (shaders/indirect_trace.glsl): for every covered pixel of the G-buffer,
// K cosine-weighted rays, giving ambient occlusion or one-bounce diffuse light per pixel in the
// output buffer (vec4: rgb light, a occlusion). One kernel per tracer structure, each with one
// pipeline per way of reading the light's map (a specialization constant, light_texels.glsl). The
// scene's triangles (SceneTriangle) are uploaded here for the hits' shading, read by address.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/options.h"
#include "core/scene.h"
#include "gpu/pipeline.h"
#include "raster/gbuffer_pass.h"
#include "raster/shadow_map_pass.h"
#include "raytrace/bvh_tracer.h"
#include "raytrace/candidate_tracer.h"
#include "raytrace/linespace_tracer.h"
#include "raytrace/ntree_candidate_tracer.h"
#include "raytrace/ray_query_tracer.h"
#include "raytrace/shadow_tracer.h"
#include "shared/indirect.h"

namespace penumbra {

// Methods ao and indirect (hybrid/indirect_method.cpp).
struct IndirectSettings {
  std::uint32_t rays = 16;   // per pixel
  float aoRadius = 0.1f;     // ao: fraction of the scene radius
  std::string tracer = "bvh";  // the tracer of `ao` and `indirect` without a -<tracer> suffix
  // bvh-ls: candidate line spaces (N from RenderSettings::lineSpace) at the BVH's inner nodes at
  // this depth, and the normal test of their plane hits.
  std::uint32_t bvhDepth = 9;
  // ntree-ls: candidate line spaces at the N-tree's (N, d from RenderSettings::lineSpace) nodes at
  // this level (-1: d - 1) and at shallower nodes with fewer than this many triangles.
  int ntreeDepth = -1;
  std::uint32_t ntreeMinTriangles = 8;
  float maxDeviationDeg = 30.0f;
  bool hitShadowMap = false;  // indirect: the bounces' hits see the light through the shadow map, not a shadow ray
};

// The command line's options of methods ao and indirect (--indirect-rays, --ao-radius, ...; the
// tracer list is parsed with the run).
const Options<IndirectSettings>& indirectOptions();

// What the kernels read and write: the camera's G-buffer, the light's map (for hits that look the
// light up in it), the frame data and the output (vec4 per pixel).
struct IndirectTargets {
  const raster::GBufferPass& gbuffer;
  const raster::ShadowMapPass& shadowMap;
  const gpu::Buffer& frame;
  const gpu::Buffer& output;
};

// The tracers of methods ao and indirect (embree: the reference), and whether `name` is one.
const std::vector<std::string>& indirectTracers();
bool isIndirectTracer(const std::string& name);
std::string indirectTracerList();  // "bvh, embree, ..."

class IndirectPass {
 public:
  IndirectPass(const gpu::Context& context, const Scene& scene);
  // The scene's dynamic meshes moved: rewrites their triangles (call between frames).
  void update(const Scene& scene);

  // Records the kernel on the BVH tracer's trees over the G-buffer, writing the output, after
  // zeroing the counters.
  void record(const vk::raii::CommandBuffer& cmd, const IndirectTargets& targets, const shared::IndirectParams& params,
              const BvhTracer& bvh);
  // The same with ray queries on the driver's acceleration structures (rq).
  void record(const vk::raii::CommandBuffer& cmd, const IndirectTargets& targets, const shared::IndirectParams& params,
              const RayQueryTracer& rq);
  // The same on the BVH with candidate line spaces (bvh-ls): ao and bounce rays approximate.
  void record(const vk::raii::CommandBuffer& cmd, const IndirectTargets& targets, const shared::IndirectParams& params,
              const CandidateTracer& candidates);
  // The same on the N-tree's line space in exact mode (ntree): exact, the moving meshes on its BVH.
  void record(const vk::raii::CommandBuffer& cmd, const IndirectTargets& targets, const shared::IndirectParams& params,
              const LineSpaceTracer& ntree);
  // The same on the N-tree with candidate line spaces (ntree-ls): ao and bounce rays approximate,
  // shadow rays of the hits on the binary line space.
  void record(const vk::raii::CommandBuffer& cmd, const IndirectTargets& targets, const shared::IndirectParams& params,
              const NTreeCandidateTracer& ntreeLs);
  // After the submission: indirect rays (rays), node visits and triangle tests; shadowRays apart.
  TraceReport report(std::uint64_t* shadowRays = nullptr) const;
  std::uint64_t bytes() const { return triangles_.size(); }

 private:
  // Zeroes the counters; returns params with this pass's scene triangles (read through their address).
  shared::IndirectParams recordStart(const vk::raii::CommandBuffer& cmd, shared::IndirectParams params);
  gpu::Descriptors descriptors(const IndirectTargets& targets) const;
  void dispatch(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer) const;

  const gpu::Context& context_;
  gpu::Buffer triangles_;
  gpu::Buffer counters_;
  gpu::SpecializedComputePipeline bvh_, bvhLs_, ntree_, ntreeLs_;
  std::optional<gpu::SpecializedComputePipeline> rq_;  // made on first use: only devices with ray queries
};

}  // namespace penumbra
