// Owns what every method shares for one scene on one device: the uploaded geometry, the
// G-buffer, the shadow map, the lookup and shading passes, the Embree reference (built on first
// use), and the frame's buffers. render() runs one method and the shared shading pass.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/scene.h"
#include "gpu/timer.h"
#include "hybrid/compact_pass.h"
#include "hybrid/denoise_pass.h"
#include "hybrid/frame_stats.h"
#include "hybrid/indirect_pass.h"
#include "hybrid/shade_pass.h"
#include "raster/bitmask_pass.h"
#include "raster/corner_maps_pass.h"
#include "raster/gbuffer_pass.h"
#include "raster/light_fit_pass.h"
#include "raster/pip_classify_pass.h"
#include "raster/shadow_lookup_pass.h"
#include "raster/shadow_map_pass.h"
#include "raster/thin_triangle_pass.h"
#include "raytrace/bvh_tracer.h"
#include "raytrace/embree_tracer.h"
#include "raytrace/linespace_tracer.h"
#include "raytrace/ray_query_tracer.h"
#include "shared/frame.h"

namespace penumbra {

class Method;

struct RenderSettings {
  std::uint32_t width = 256;
  std::uint32_t height = 256;
  std::uint32_t spp = 16;            // light samples per pixel for area lights
  std::uint32_t referenceSpp = 0;    // samples for `ref`; 0 = spp
  raster::ShadowMapSettings shadowMap;
  std::uint32_t pcfFilter = FILTER_PCF3;  // kernel of `pcf`: FILTER_PCF3, FILTER_PCF5, FILTER_POISSON
  std::uint32_t msmMaps = 4;         // `msm`: shadow maps from this many light samples, averaged
  float rayEpsilon = 1e-4f;          // shadow-ray origin offset, fraction of the scene radius
  // Ray tracer of srt and frt: "bvh" (GPU compute), "rq" (GPU ray queries), "embree" (CPU), "ls"
  // (line space), or "auto" (resolveTracer).
  std::string tracer = "auto";
  LineSpaceSettings lineSpace;       // tracer "ls" and method ls: N, depth, memory budget
  raster::PipSettings pip;
  raster::ThinTriangleSettings thin;
  // Directional and spot lights with point-like extent: fit the centre map to the receivers the
  // camera sees (raster/light_fit_pass.h) instead of the whole scene (false, the default: the
  // finer texels halve PIP but let srt miss more along grazing edges, bench/results/passes.md).
  bool fitLightToView = false;
  bool simulateBandwidth = false;    // srt/frt on the bvh tracer: replay the trace for its memory traffic (raytrace/bandwidth_model.h)
  // A frame whose light map would be the last one's (same map placement, geometry unmoved) keeps
  // the last shadow map and edge pyramid instead of rendering them again, as an engine keeps a
  // still light's map (--reuse-light-passes; the demo's default). Off: every frame renders them.
  bool reuseLightPasses = false;
  // srt takes, per frame, whichever of its paths (classify, or trace every covered pixel) its own
  // measurements say is cheaper (--srt-choice auto; hybrid/traced_method.cpp). Off: always classify.
  bool srtChoice = false;
  DenoiseSettings denoise;           // srt/frt with an area light: the shadow denoiser (hybrid/denoise_pass.h)
  // Every pixel uses the same light samples, the pattern method bitmask looks up (--shared-samples):
  // the reference and the tracers then see bitmask's samples.
  bool sharedSamples = false;
  raster::BitmaskSettings bitmask;   // method bitmask: map resolution, receiver
  IndirectSettings indirect;         // methods ao and indirect: rays per pixel, ao radius, tracer
};

// One rendered frame, read back to the host.
struct Frame {
  std::uint32_t width = 0, height = 0;
  std::vector<float> visibility;      // width*height, row 0 at the top
  std::vector<std::uint8_t> covered;  // 1 where geometry covers the pixel
  std::vector<std::uint8_t> rgba;     // shaded sRGB image, width*height*4
  std::vector<std::uint8_t> pip;      // methods that classify: PIP_* flags per pixel (0 = not traced)
  std::vector<float> shadowMapVisibility;  // methods that classify: the sm answer before tracing
  std::vector<std::uint8_t> pipWhy;        // with settings.pip.explain, hard shadows: PIP_WHY_* per pixel
  FrameStats stats;
};

class Renderer {
 public:
  Renderer(const gpu::Context& context, const Scene& scene, const RenderSettings& settings);
  ~Renderer();  // out of line: Method is incomplete here
  Frame render(const std::string& method, const Camera& camera, const Light& light);
  // The scene's dynamic meshes were posed anew (core/animation.h, between frames): re-uploads their
  // vertices, refits the built tracers' dynamic BVHs (rebuilding when the SAH grew too much) and
  // drops the Embree reference (rebuilt on next use). Frames report the refit in stats.refit.
  void sceneMoved();
  // The frame of a sequence the next renders belong to (0 until set): rotates every pixel's light
  // samples (shared::lightSampleOffset), the same for every method and the reference, so that
  // frames of a sequence see new samples and a temporal denoiser gathers them.
  void setFrame(std::uint32_t frame) { frame_ = frame; }
  std::uint64_t sceneVersion() const { return sceneVersion_; }  // counts sceneMoved() calls

  // For methods, valid during render():
  const gpu::Context& context() const { return context_; }
  const Scene& scene() const { return scene_; }
  const Bounds& bounds() const { return bounds_; }
  const RenderSettings& settings() const { return settings_; }
  const shared::FrameData& frameData() const { return frameData_; }
  const gpu::Buffer& frameBuffer() const { return frameBuffer_; }
  const gpu::Buffer& visibility() const { return visibility_; }
  gpu::Buffer& visibility() { return visibility_; }
  // Methods ao and indirect: vec4 per pixel (rgb one-bounce light, a occlusion), which shading adds
  // to the direct light for their frames.
  gpu::Buffer& indirect() { return indirect_; }
  IndirectPass& indirectPass(FrameStats& stats);  // made on first use
  // Tracer bvh-ls of ao and indirect: the BVH with candidate line spaces, built on first use (and
  // again after sceneMoved), its build and memory in stats.
  const CandidateTracer& candidateTracer(FrameStats& stats);
  // Tracer ntree: the N-tree's line space in exact mode (apart from the shadow tracer ls, whose
  // mode may be binary), the moving meshes on its BVH; built on first use, refit by sceneMoved.
  const LineSpaceTracer& ntreeTracer(FrameStats& stats);
  // Tracer ntree-ls: the N-tree with candidate line spaces at level settings().indirect.ntreeDepth
  // (and the T rule), built on first use (static meshes only: sceneMoved refits the moving BVH).
  const NTreeCandidateTracer& ntreeCandidateTracer(FrameStats& stats);
  const gpu::Buffer& traceFlags() const { return traceFlags_; }  // srt: nonzero where the pixel was traced
  // Mean blocker distance per traced pixel, written by the GPU tracers when settings().denoise is on.
  const gpu::Buffer& blockers() const { return blockers_; }
  gpu::GpuTimer& timer() { return timer_; }
  const raster::SceneGeometry& geometry() const { return geometry_; }
  const raster::GBufferPass& gbuffer() const { return gbuffer_; }
  const raster::ShadowMapPass& shadowMap() const { return *shadowMap_; }
  const raster::ShadowLookupPass& shadowLookup() const { return lookup_; }
  const ViewMatrices& view() const { return view_; }
  const glm::vec3& cameraPosition() const { return cameraPosition_; }
  const EmbreeTracer& embree(FrameStats& stats);  // builds on first use, reports the build
  // The tracer "auto" stands for on this device (defaultTracer: rq on a GPU with ray queries, else
  // bvh); other names stay.
  static std::string resolveTracer(const gpu::Context& context, const std::string& name);
  // settings().tracer (or `name` when given), built on first use
  ShadowTracer& tracer(FrameStats& stats, const std::string& name = {});
  // Whether `tracer` can trace every covered pixel straight from the G-buffer (frt's best self: no
  // compaction): a GPU tracer, and no bandwidth replay (which reads the list).
  bool canTraceInPlace(const ShadowTracer& tracer) const;
  // The compacted points and where results go; inPlace: the G-buffer instead (sets
  // FrameData::traceInPlace for this frame).
  TraceJob traceJob(bool inPlace = false);
  // After the submission that traced `job`: refuses a list that overflowed, collects the tracer's
  // report into stats (pixels listed, rays, traversal counts, host time).
  void finishTrace(ShadowTracer& tracer, const TraceJob& job, FrameStats& stats);
  // Before an in-place trace: its dispatch size (every pixel, in tiles) in the count buffer.
  void recordInPlaceCount(const vk::raii::CommandBuffer& cmd);

  // Records the camera pass with its timer scope (every method starts with it).
  void recordGBuffer(const vk::raii::CommandBuffer& cmd);
  // Records the light pass with its timer scope (making the map for this light if needed).
  void recordShadowMap(const vk::raii::CommandBuffer& cmd, FrameStats& stats);
  // Thin-triangle mask (when settings().pip.thinPass), then PIP classification (and the corner
  // maps' additions to the penumbra mask with --penumbra-maps 5), with timer scopes.
  // Returns true when the classification also made the trace list (else recordCompact must);
  // never with makeList false (a later pass changes the flags: bitmask's fallback).
  bool recordClassify(const vk::raii::CommandBuffer& cmd, FrameStats& stats, bool makeList = true);
  // Dense list of the pixels to trace: flagged ones (COMPACT_FLAGGED) or all covered ones.
  void recordCompact(const vk::raii::CommandBuffer& cmd, std::uint32_t mode);
  // For methods that trace without classifying: visibility 1 everywhere, no ray intervals.
  void recordUnclassified(const vk::raii::CommandBuffer& cmd);

 private:
  // Writes the trace list's count and dispatch size, ordered after earlier uses and before the next.
  void recordTraceCount(const vk::raii::CommandBuffer& cmd, const shared::TraceCount& count);
  void prepareFrame(const Camera& camera, const Light& light, const Method& method);
  // Renders the G-buffer in a submission of its own and narrows frameData_.shadow to what it sees
  // (when settings_.fitLightToView applies to this light).
  void fitLightToView(FrameStats& stats);

  const gpu::Context& context_;
  const Scene& scene_;
  RenderSettings settings_;
  Bounds bounds_;
  raster::SceneGeometry geometry_;
  raster::GBufferPass gbuffer_;
  raster::ShadowLookupPass lookup_;
  ShadePass shade_;
  raster::PipClassifyPass classify_;
  CompactPass compact_;
  raster::LightFitPass lightFit_;
  struct Clearance {  // the light's distance to the nearest triangle, for its cube map's near plane
    glm::vec3 at;
    std::uint64_t sceneVersion;
    float distance;
  };
  std::optional<Clearance> clearance_;
  bool gbufferRecorded_ = false;  // this frame's G-buffer is already rendered (by fitLightToView)
  std::map<std::string, std::unique_ptr<Method>> methods_;  // one per name, kept: they may own GPU objects
  std::unique_ptr<raster::ShadowMapPass> shadowMap_;
  // What the shadow map and the edge pyramid were last rendered from (settings_.reuseLightPasses).
  struct LightPassesKey {
    shared::ShadowMapInfo shadow;
    std::uint64_t geometryVersion;
    bool operator==(const LightPassesKey& other) const;
  };
  LightPassesKey lightPassesKey() const;
  std::optional<LightPassesKey> shadowMapKey_, pyramidKey_;
  std::unique_ptr<raster::ThinTrianglePass> thin_;
  std::unique_ptr<raster::DepthPyramidPass> pyramid_;
  std::unique_ptr<raster::CornerMapsPass> cornerMaps_;  // --penumbra-maps 5
  std::map<std::string, std::unique_ptr<ShadowTracer>> tracers_;  // by name (hybrid/registry.h), built on first use
  std::unique_ptr<IndirectPass> indirectPass_;
  std::unique_ptr<CandidateTracer> candidates_;
  std::unique_ptr<LineSpaceTracer> ntree_;
  std::unique_ptr<NTreeCandidateTracer> ntreeLs_;
  gpu::Buffer frameBuffer_, visibility_, indirect_, color_;
  gpu::Buffer smVisibility_, traceFlags_, rayMax_, why_, blockers_;
  gpu::GpuTimer timer_;
  shared::FrameData frameData_{};
  ViewMatrices view_;
  glm::vec3 cameraPosition_{0.0f};
  std::uint32_t frame_ = 0;
  std::uint64_t sceneVersion_ = 0;
  std::optional<FrameStats::Refit> refit_;  // the last sceneMoved()'s, for the frames after it
};

}  // namespace penumbra
