// Methods ao and indirect (Keul et al. 2018's indirect rays): the direct light as sm gives it
// (camera pass, light pass, shadow-map lookup), then K cosine-weighted rays per covered pixel
// (shared/indirect.h) on the chosen tracer for ambient occlusion (`ao`) or one-bounce diffuse
// light (`indirect`), into FrameContext::indirect(), which the shading pass adds. On tracer embree
// the same rays are traced on the CPU: the reference the others are compared with. Tracers: bvh
// and rq (exact), bvh-ls (BVH + candidate line spaces), ntree (the N-tree's line space in exact
// mode: exact), ntree-ls (N-tree + candidate line spaces; its hits' shadow rays on the binary line space).
// Names: ao, indirect (settings.indirect.tracer), or ao-<tracer>, indirect-<tracer>.
#include <chrono>
#include <string>
#include <utility>

#include "core/units.h"
#include "hybrid/frame_context.h"
#include "hybrid/method.h"
#include "hybrid/registry.h"
#include "raytrace/scene_triangles.h"

namespace penumbra {
namespace {

class IndirectMethod final : public Method {
 public:
  IndirectMethod(Term term, std::string tracer) : term_(term), tracer_(std::move(tracer)) {}
  Term term() const override { return term_; }
  bool readsShadowMap() const override { return true; }
  std::uint32_t samplesPerPixel(const RenderSettings& settings) const override { return settings.indirect.rays; }

  void run(FrameContext& r, FrameStats& stats) override {
    const RenderSettings& s = r.settings();
    const std::string tracer = tracer_.empty() ? s.indirect.tracer : tracer_;
    const float radius = r.bounds().radius();
    shared::IndirectParams params{};
    params.mode = term_ == Term::Ao ? INDIRECT_AO : INDIRECT_BOUNCE;
    params.rays = s.indirect.rays;
    params.frame = r.frameData().light.sampleFrame;
    params.aoRadius = s.indirect.aoRadius * radius;
    params.rayMax = 4.0f * radius;
    params.hitLight = s.indirect.hitShadowMap ? INDIRECT_HIT_SHADOW_MAP : INDIRECT_HIT_SHADOW_RAY;
    stats.tracer = tracer;
    if (term_ == Term::Indirect && s.indirect.hitShadowMap && tracer != "embree") {
      stats.notes.push_back("the bounces' hits see the light through the shadow map (--hit-light shadow-map)");
    }
    stats.term = termName(term_);
    if (tracer == "embree") return runReference(r, stats, params);

    IndirectPass& pass = r.indirectPass(stats);
    if (!isIndirectTracer(tracer)) {
      throw InputError("unknown tracer '" + tracer + "' for " + termName(term_) + "; use " + indirectTracerList());
    }
    BvhTracer* bvh = tracer == "bvh" ? &dynamic_cast<BvhTracer&>(r.tracer(stats, "bvh")) : nullptr;
    RayQueryTracer* rq = tracer == "rq" ? &dynamic_cast<RayQueryTracer&>(r.tracer(stats, "rq")) : nullptr;
    const CandidateTracer* candidates = tracer == "bvh-ls" ? &r.candidateTracer(stats) : nullptr;
    const LineSpaceTracer* ntree = tracer == "ntree" ? &r.ntreeTracer(stats) : nullptr;
    const NTreeCandidateTracer* ntreeLs = tracer == "ntree-ls" ? &r.ntreeCandidateTracer(stats) : nullptr;
    r.context().submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
      recordDirect(r, cmd, stats);
      r.timer().begin(cmd, "indirect");
      const IndirectTargets targets{r.gbuffer(), r.shadowMap(), r.frameBuffer(), r.indirect()};
      if (bvh) pass.record(cmd, targets, params, *bvh);
      else if (rq) pass.record(cmd, targets, params, *rq);
      else if (candidates) pass.record(cmd, targets, params, *candidates);
      else if (ntree) pass.record(cmd, targets, params, *ntree);
      else pass.record(cmd, targets, params, *ntreeLs);
      r.timer().end(cmd);
    });
    report(pass, stats, !rq);  // the driver's traversal counts no steps
  }

 private:
  // The camera pass, the light pass and sm's lookup: the direct light's visibility.
  static void recordDirect(FrameContext& r, const vk::raii::CommandBuffer& cmd, FrameStats& stats) {
    r.recordGBuffer(cmd);
    r.recordShadowMap(cmd, stats);
    r.timer().begin(cmd, "lookup");
    r.shadowLookup().record(cmd, r.gbuffer(), r.shadowMap(), r.frameBuffer(), r.visibility(), r.lightRect());
    r.timer().end(cmd);
  }

  static void report(const IndirectPass& pass, FrameStats& stats, bool traversalCounted) {
    std::uint64_t shadowRays = 0;
    const TraceReport traced = pass.report(&shadowRays);
    stats.raysTraced = traced.rays;
    if (traversalCounted) {
      stats.nodeVisits = traced.nodeVisits;
      stats.triangleTests = traced.triangleTests;
    }
    stats.counts["shadow_rays"] = shadowRays;
  }

  void runReference(FrameContext& r, FrameStats& stats, const shared::IndirectParams& params) {
    const EmbreeTracer& embree = r.embree(stats);
    r.context().submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
      recordDirect(r, cmd, stats);
      r.gbuffer().recordReadback(cmd);
    });
    const auto start = std::chrono::steady_clock::now();
    const std::vector<glm::vec4> positions = r.gbuffer().positions();
    const std::vector<glm::vec4> normals = r.gbuffer().normals();
    std::vector<shared::ShadingPoint> points;
    for (std::uint32_t i = 0; i < positions.size(); ++i) {
      if (positions[i].w != 0.0f) points.push_back({glm::vec3(positions[i]), i, glm::vec3(normals[i]), 1u});
    }
    if (triangles_.empty() || trianglesVersion_ != r.sceneVersion()) {
      triangles_ = sceneTriangles(r.scene());  // again after the dynamic meshes moved
      trianglesVersion_ = r.sceneVersion();
    }
    std::vector<glm::vec4> traced(points.size());
    std::uint64_t shadowRays = 0;
    stats.raysTraced = embree.traceIndirect(points, r.frameData().light, triangles_, params, traced, &shadowRays);
    stats.counts["shadow_rays"] = shadowRays;
    std::vector<glm::vec4> out(positions.size(), glm::vec4(0.0f));
    for (std::size_t k = 0; k < points.size(); ++k) out[points[k].pixel] = traced[k];
    r.indirect().upload(std::span<const glm::vec4>(out));
    stats.addPass("indirect", msSince(start));
  }

  Term term_;
  std::string tracer_;
  std::vector<shared::SceneTriangle> triangles_;  // the reference's copy, of the scene at trianglesVersion_
  std::uint64_t trianglesVersion_ = 0;
};

}  // namespace

const char* termName(Term term) {
  switch (term) {
    case Term::Ao: return "ao";
    case Term::Indirect: return "indirect";
    case Term::Shadow: break;
  }
  return "shadow";
}

// ao and indirect on settings.indirect.tracer; ao-<tracer> and indirect-<tracer> on that tracer
// (embree: the reference).
void register_indirect_method(Registry& r) {
  r.method("ao", [] { return std::make_unique<IndirectMethod>(Term::Ao, ""); });
  r.method("indirect", [] { return std::make_unique<IndirectMethod>(Term::Indirect, ""); });
  r.methodFamily("ao-", [](const std::string& tracer) { return std::make_unique<IndirectMethod>(Term::Ao, tracer); });
  r.methodFamily("indirect-", [](const std::string& tracer) { return std::make_unique<IndirectMethod>(Term::Indirect, tracer); });
}

}  // namespace penumbra
