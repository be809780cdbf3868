// What a method works with during one frame (Method::run): the scene's uploaded geometry, the
// frame's data and buffers, the shared passes as stages (camera pass, light pass, classification,
// the trace list), the tracers by name, the GPU timer. The Renderer owns one and runs a frame as
// begin, the method's stages, shade and readBack.
#pragma once
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "core/camera.h"
#include "core/scene.h"
#include "gpu/timer.h"
#include "hybrid/cheaper_of.h"
#include "hybrid/compact_pass.h"
#include "hybrid/denoise_pass.h"
#include "hybrid/frame_stats.h"
#include "hybrid/indirect_pass.h"
#include "hybrid/render_settings.h"
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

// Which pixels a frame traces (FrameContext::recordTraceList).
enum class TraceList {
  Doubtful,      // classify, then list the pixels it flagged (in the classification itself where it can)
  Flagged,       // list the pixels already flagged (after a method's own passes changed the flags)
  EveryCovered,  // no classification: visibility 1, every covered pixel
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
  // Classified with the penumbra mask's tile test: PIP_TILE_* per PIP_MASK_TILE_SIZE^2 tile of
  // pixels, rows of ceil(width / PIP_MASK_TILE_SIZE) tiles (else empty)
  std::vector<std::uint8_t> maskTiles;
  // --light-error, methods that honour it: the light's shared::shadowWeight per pixel (judgeFrame:
  // the error its approximate answers caused)
  std::vector<float> shadowWeight;
  FrameStats stats;
  // A frame of several lights: each light's visibility, PIP flags, sm answer and stats (no image);
  // visibility, pip and shadowMapVisibility above are the first light's.
  std::vector<Frame> lights;
};

// Which of a frame's lights FrameContext::begin starts: its index among the frame's lights (methods
// keep state per light by it), and its place among the ones the view reaches, which run and shade in
// turn: the first renders the G-buffer the others keep, the last writes the image.
struct LightSlot {
  std::uint32_t index = 0, order = 0, count = 1;
  bool buffers = true;  // readBack keeps its visibility, PIP flags and sm answer (Renderer::keepLightBuffers)
};

class FrameContext {
 public:
  FrameContext(const gpu::Context& context, const Scene& scene, const RenderSettings& settings);
  ~FrameContext();

  // The stages around a method's own (Renderer::render): the frame's data for this camera, light
  // and method (frame: of a sequence, rotating the light samples), the light's map fitted to the
  // view, shading, and reading the frame back.
  void begin(const Camera& camera, const Light& light, const Method& method, std::uint32_t frame, FrameStats& stats,
             LightSlot slot = {});
  std::uint32_t lightIndex() const { return slot_.index; }
  // False where the light's range lies wholly outside the camera's view: every pixel is beyond it
  // (lightReaches' range rule), so its visibility is 0 there without any pass.
  bool lightReachesView(const Camera& camera, const Light& light) const;
  // Renders the G-buffer in a submission of its own and narrows frameData().shadow to what it sees,
  // where settings().fitLightToView applies to this light (for methods that read its map).
  void fitLightToView(FrameStats& stats);
  // The pixels [xy, zw) the light's range projects to (the whole image for lights without one):
  // beyond it the light reaches nothing, so no pass of it need run there (FrameData::lightRectMin/Max).
  glm::uvec4 lightRect() const;
  // After Method::run: this light's shading (ShadePass) in a submission of its own, unless the
  // method recorded it in its last one (recordShade); a frame of several lights shades a batch of
  // them where it is full and after its last light, tracing the batch's traced lights first
  // (traceWithLights; the trace's counters join stats).
  void shade(FrameStats& stats);
  // With the shaded image where this is the frame's last light (the others have none of their own).
  Frame readBack(const Method& method, FrameStats stats);
  // After readBack: the visibility and rays of the lights that traceWithLights traced since the last
  // call (their batches were shaded), into frames (by light index).
  void settleTracedLights(std::vector<Frame>& frames);
  // Renderer::sceneMoved: re-uploads the moving meshes and refits the built tracers.
  void sceneMoved();
  std::uint64_t sceneVersion() const { return sceneVersion_; }  // counts sceneMoved() calls

  // For methods, during Method::run:
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
  const raster::ShadowMapPass& shadowMap() const { return *maps_->shadowMap; }
  const raster::ShadowLookupPass& shadowLookup() const { return lookup_; }
  const ViewMatrices& view() const { return view_; }
  const glm::vec3& cameraPosition() const { return cameraPosition_; }
  const EmbreeTracer& embree(FrameStats& stats);  // builds on first use, reports the build
  // settings().tracer (or `name` when given), built on first use
  ShadowTracer& tracer(FrameStats& stats, const std::string& name = {});
  // Before the submission: what `tracer` traces for `list` and where results go: the list's points,
  // or for TraceList::EveryCovered on a tracer that can take them from the G-buffer (frt's best
  // self, no compaction: a GPU tracer and no bandwidth replay) the G-buffer itself (sets
  // FrameData::traceInPlace for this frame).
  TraceJob traceJob(const ShadowTracer& tracer, TraceList list);
  // After the submission that traced `job`: refuses a list that overflowed, collects the tracer's
  // report into stats (pixels listed, rays, traversal counts, host time).
  void finishTrace(ShadowTracer& tracer, const TraceJob& job, FrameStats& stats);
  // A frame of several lights on a GPU tracer (--lights-trace one): this light's trace of every
  // covered pixel can join the one trace of its batch of lights (traceWithLights).
  bool tracesWithLights(const ShadowTracer& tracer) const;
  // What joining its batch's trace last cost the light: that trace's time, shared by rays among the
  // lights it traced (srt's --srt-choice auto); nullopt before the light joined one.
  std::optional<double> joinedTraceMs(std::uint32_t light) const;
  // Instead of a trace of its own (TraceList::EveryCovered): the light joins its batch's trace, one
  // dispatch over the batch's traced lights, each pixel to each light its tile lists (trace_points.glsl),
  // recorded when the batch is shaded (shade()); settleTracedLights gives its visibility and rays.
  void traceWithLights(ShadowTracer& tracer, FrameStats& stats);

  // Records the camera pass with its timer scope (every method starts with it).
  void recordGBuffer(const vk::raii::CommandBuffer& cmd);
  // Records the light pass with its timer scope (making the map for this light if needed).
  void recordShadowMap(const vk::raii::CommandBuffer& cmd, FrameStats& stats);
  // The trace list, the one stage that makes it, after the camera pass (and the light pass for
  // TraceList::Doubtful), with timer scopes.
  void recordTraceList(const vk::raii::CommandBuffer& cmd, TraceList list, FrameStats& stats);
  // Thin-triangle mask (when settings().pip.thinPass), then PIP classification (and the corner
  // maps' additions to the penumbra mask with --penumbra-maps 5): flags and the sm answer, for a
  // method whose own passes change flags before TraceList::Flagged lists them (bitmask).
  void recordClassify(const vk::raii::CommandBuffer& cmd, FrameStats& stats) { classify(cmd, stats, false); }
  // For methods that trace without classifying: visibility 1 everywhere, no ray intervals.
  void recordUnclassified(const vk::raii::CommandBuffer& cmd);
  // This light's shading, at the end of a method's last submission, once its visibility is final
  // on the device (a CPU tracer's is not before finish): it saves shade() a submission per light.
  // A frame of several lights shades them a batch at a time (ShadePass::recordLight).
  void recordShade(const vk::raii::CommandBuffer& cmd);

 private:
  // recordClassify; with appendList the classification also lists the flagged pixels where it can
  // (returns whether it did: else the compaction must).
  bool classify(const vk::raii::CommandBuffer& cmd, FrameStats& stats, bool appendList);
  void recordCompact(const vk::raii::CommandBuffer& cmd, std::uint32_t mode);
  // hybrid/frame_classify.cpp, with classify: whether this frame runs the penumbra mask's tile test;
  // and in readBack, with the frame's passes, --tile-test auto's time of its take and the test's counts.
  bool takesTileTest();
  void reportTileTest(const std::vector<std::pair<std::string, double>>& passes, bool classified, FrameStats& stats);
  // In readBack, where the frame classified with the tile choice: its counts (how many tiles took
  // which path; into frame.maskTiles, with buffers), the cost model's threshold for the light's
  // next frame from this one's timings, and the counts' buffers swapped.
  void reportTileChoice(const std::vector<std::pair<std::string, double>>& passes, FrameStats& stats, Frame& frame);
  // Before an in-place trace: its dispatch size (every pixel, in tiles) in the count buffer.
  void recordInPlaceCount(const vk::raii::CommandBuffer& cmd);
  shared::TraceCount inPlaceCount(const glm::uvec4& rect) const;  // every tile's pixels of rect
  // Shades the batch of lights (ShadePass) in a submission of its own, its traced lights' trace first.
  void shadeBatch(bool last, FrameStats& stats);
  // Writes the trace list's count and dispatch size, ordered after earlier uses and before the next.
  void recordTraceCount(const vk::raii::CommandBuffer& cmd, const shared::TraceCount& count);

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
  struct Clearance {  // a light's distance to the nearest triangle, for its cube map's near plane
    glm::vec3 at;
    std::uint64_t sceneVersion;
    float distance;
  };
  std::vector<Clearance> clearances_;  // one per light position of the frame, while the scene stays
  LightSlot slot_;
  Term term_ = Term::Shadow;       // the method's (begin)
  bool shadeRecorded_ = false;     // this light's shading, by recordShade (several lights: it joined the batch, and the
                                   // last one's is shaded)
  bool joinedBatch_ = false;       // several lights: this light joined the shading batch
  bool tracedWithLights_ = false;  // this light's visibility is the batch trace's (traceWithLights)
  ShadowTracer* lightsTracer_ = nullptr;  // the tracer of the frame's traceWithLights
  // Since settleTracedLights: the lights traceWithLights traced, each with its visibility over its
  // rectangle, kept (keepTracedLights) where the batch buffer was to be written before the settling.
  struct TracedLight {
    ShadePass::TracedLight light;
    std::optional<std::vector<float>> kept;
  };
  std::vector<TracedLight> tracedLights_;
  std::vector<std::uint32_t> withoutBuffers_;  // the frame's lights readBack keeps no buffers of
  void keepTracedLights();
  gpu::Buffer lightsFrame_, lightsCount_;          // the batch trace's FrameData and TraceCount
  std::map<std::uint32_t, double> joinedTraceMs_;  // by light index (joinedTraceMs)
  std::uint32_t methodSpp_ = 1;                    // the method's light samples per pixel (area lights take them)
  bool gbufferRecorded_ = false;  // this frame's G-buffer is already rendered (by fitLightToView)
  std::vector<std::uint8_t> covered_;           // the G-buffer's coverage, read back once per G-buffer
  std::vector<glm::vec4> positions_, normals_;  // ... and, with --light-error, its points
  bool coveredRead_ = false;
  // What the shadow map and the edge pyramid were last rendered from (settings_.reuseLightPasses):
  // the map's placement and the last geometry version whose move reached what the map sees.
  struct LightPassesKey {
    shared::ShadowMapInfo shadow;
    std::uint64_t geometryVersion;
    bool operator==(const LightPassesKey& other) const;
  };
  LightPassesKey lightPassesKey() const;
  // A light's passes at one map resolution and face count, each made on first use.
  struct LightMaps {
    std::unique_ptr<raster::ShadowMapPass> shadowMap;
    std::unique_ptr<raster::ThinTrianglePass> thin;
    std::unique_ptr<raster::DepthPyramidPass> pyramid;
    std::optional<LightPassesKey> shadowMapKey, pyramidKey;
  };
  // By (owner, resolution, faces): a light's own while settings().lightMapsMiB holds them, owner its
  // index (several lights, reuseLightPasses: chooseMaps), else kSharedMaps', which every light of
  // that resolution and face count renders again.
  static constexpr std::uint32_t kSharedMaps = ~0u;
  std::map<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>, LightMaps> lightMaps_;
  LightMaps* maps_ = nullptr;     // this light's, chosen on first use in its frame (maps())
  bool maskTilesTested_ = false;  // the last classification ran the penumbra mask's tile test (PipPush::tileTest)
  // --tile-test auto, by light index: with or without the tile test, by the classification's time
  // with each; the take of this light's frame (classify), timed in readBack.
  std::map<std::uint32_t, CheaperOf> tileTestChoices_;
  std::optional<bool> tileTestTake_;
  // The tile choice (PipSettings::tileChoice), by light index: the counts of its last frame and of
  // this one (PipBuffers::tileDoubtLast, tileDoubt; swapped after each frame that classified), the
  // frames it classified (PipPush::tilePhase) and its cost model's threshold (PipPush::tileTraceBelow:
  // 1 until timed, so that only tiles found wholly doubtful are traced whole).
  struct TileChoice {
    TileChoice(const gpu::Context& context, vk::DeviceSize bytes);
    gpu::Buffer last, next;
    std::uint32_t frames = 0, traceBelow = 1;
  };
  std::map<std::uint32_t, TileChoice> tileChoices_;
  TileChoice* tileChoice_ = nullptr;  // this light's, where its frame classified with it
  double lastTraceHostMs_ = 0.0;      // the frame's last trace's CPU time (Embree's; finishTrace), for its cost model
  bool mapsPastBudget_ = false;       // its own would not fit settings().lightMapsMiB
  LightMaps& maps();
  LightMaps& chooseMaps();
  // The moving meshes' boxes as of the last sceneMoved, and what the last moves swept (each mesh's
  // box before and after), by the geometry version each made.
  std::vector<Bounds> movingBounds_;
  struct Move {
    std::uint64_t version;
    std::vector<Bounds> swept;
  };
  std::deque<Move> moves_;
  // The resolution of this light's map: settings().shadowMap's, or less by the footprint rule
  // (RenderSettings::footprintMaps).
  std::uint32_t mapResolution() const;
  raster::ShadowMapSettings mapSettings_;               // settings().shadowMap at this light's resolution
  std::unique_ptr<raster::CornerMapsPass> cornerMaps_;  // --penumbra-maps 5
  std::map<std::string, std::unique_ptr<ShadowTracer>> tracers_;  // by name (hybrid/registry.h), built on first use
  std::unique_ptr<IndirectPass> indirectPass_;
  std::unique_ptr<CandidateTracer> candidates_;
  std::unique_ptr<LineSpaceTracer> ntree_;
  std::unique_ptr<NTreeCandidateTracer> ntreeLs_;
  gpu::Buffer frameBuffer_, visibility_, indirect_, color_;
  gpu::Buffer smVisibility_, traceFlags_, rayMax_, why_, maskTiles_, blockers_;
  gpu::GpuTimer timer_;
  shared::FrameData frameData_{};
  ViewMatrices view_;
  glm::vec3 cameraPosition_{0.0f};
  std::uint64_t sceneVersion_ = 0;
  std::optional<FrameStats::Refit> refit_;  // the last sceneMoved()'s, for the frames after it
};

}  // namespace penumbra
