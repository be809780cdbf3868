// Methods srt and frt on the chosen tracer (--tracer bvh|embree).
//   srt: camera pass, light pass, thin-triangle mask, PIP classification (which also gives the sm
//        answer), compaction of the PIP pixels, trace only those (Lauterbach et al. 2009, 3.1).
//   frt: camera pass, compaction of every covered pixel, trace all of them.
// Tracers write visibility[pixel] directly, so the write-back is part of the trace pass.
#include "hybrid/method.h"
#include "hybrid/renderer.h"
#include "shared/compact.h"
#include "shared/trace.h"

namespace penumbra {
namespace {

class TracedMethod final : public Method {
 public:
  explicit TracedMethod(bool selective) : selective_(selective) {}
  bool classifies() const override { return selective_; }

  void run(Renderer& r, FrameStats& stats) override {
    ShadowTracer& tracer = r.tracer(stats);
    const TraceJob job = r.traceJob();
    r.context().submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
      r.recordGBuffer(cmd);
      if (selective_) {
        r.recordShadowMap(cmd, stats);
        r.recordClassify(cmd, stats);
        r.recordCompact(cmd, COMPACT_FLAGGED);
      } else {
        r.recordUnclassified(cmd);
        r.recordCompact(cmd, COMPACT_ALL_COVERED);
      }
      r.timer().begin(cmd, "trace");
      tracer.record(cmd, job);
      r.timer().end(cmd);
    });
    const TraceReport report = tracer.finish(job);
    if (report.hostMs > 0.0) stats.addPass("trace", report.hostMs);
    stats.tracer = tracer.name();
    stats.raysTraced = report.rays;
    stats.pipPixels = job.count.download<shared::TraceCount>(1).front().count;
    stats.nodeVisits = report.nodeVisits;
    stats.triangleTests = report.triangleTests;
  }

 private:
  bool selective_;
};

}  // namespace

std::unique_ptr<Method> makeTracedMethod(bool selective) { return std::make_unique<TracedMethod>(selective); }

}  // namespace penumbra
