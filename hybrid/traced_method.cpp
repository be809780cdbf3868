// Methods srt and frt on the chosen tracer (--tracer bvh|embree|ls), and ls: frt on the line-space tracer.
//   srt: camera pass, light pass, thin-triangle mask, PIP classification (which also gives the sm
//        answer and appends the PIP pixels to the trace list; a compaction pass makes the list
//        instead when corner maps add flags after it), trace only those (Lauterbach et al. 2009, 3.1).
//   frt: camera pass, then the trace of every covered pixel: GPU tracers take them straight from the
//        G-buffer (no compaction: frt at its best); Embree, and --simulate-bandwidth, compact them.
// Tracers write visibility[pixel] directly, so the write-back is part of the trace pass.
#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "core/cutouts.h"
#include "hybrid/frame_context.h"
#include "hybrid/method.h"
#include "hybrid/registry.h"
#include "raytrace/bandwidth_model.h"
#include "shared/trace.h"

namespace penumbra {
namespace {

// --simulate-bandwidth: the trace kernel's memory traffic, replayed on the CPU, and the estimate
// for the passes before it (raytrace/bandwidth_model.h). Only the bvh tracer's kernel is modelled.
void simulateBandwidth(FrameContext& r, const ShadowTracer& tracer, const TraceJob& job, bool selective, FrameStats& stats) {
  const auto* bvh = dynamic_cast<const BvhTracer*>(&tracer);
  if (!bvh) {
    stats.notes.push_back("--simulate-bandwidth models the bvh tracer's kernel only; " + tracer.name() + " was not simulated");
    return;
  }
  const auto start = std::chrono::steady_clock::now();
  const BandwidthReport trace =
      simulateTraceBandwidth(*bvh, job, r.frameData().light, bandwidthSettingsFor(r.context().deviceName()));
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  // CPU work inside the frame: say so, so that nobody reads this frame's total as the method's time.
  stats.setupMs["bandwidth_simulation"] = ms;
  stats.notes.push_back("the frame's total time includes " + std::to_string(int(ms)) +
                        " ms of bandwidth simulation (--simulate-bandwidth); time without it");
  const RasterEstimate raster = estimateRasterBytes({.pixels = std::uint64_t(r.settings().width) * r.settings().height,
                                                     .triangles = r.scene().triangleCount(),
                                                     .shadowMapRes = r.settings().shadowMap.resolution,
                                                     .faces = r.frameData().shadow.faceCount,
                                                     .selective = selective,
                                                     .thinPass = r.settings().pip.thinPass,
                                                     .tracedPoints = trace.invocations});
  stats.traceBytesSimulated = trace.bytes();
  stats.traceLinesSimulated = trace.lines();
  stats.rasterBytesEstimated = raster.total();
  stats.bandwidth = toJson(trace, raster);
}

class TracedMethod final : public Method {
 public:
  TracedMethod(bool selective, std::string tracerName) : selective_(selective), tracerName_(std::move(tracerName)) {}
  bool classifies() const override { return classified_; }
  bool readsShadowMap() const override { return selective_; }

  void run(FrameContext& r, FrameStats& stats) override {
    ShadowTracer& tracer = r.tracer(stats, tracerName_);
    // The frame's last submission shades: the denoiser's, else the last trace's where the
    // visibility is final at its end (a GPU tracer).
    const bool denoised = r.frameData().blockers != glm::uvec2(0u);
    const bool shade = tracer.onDevice() && !denoised;
    if (!selective_ && r.tracesWithLights(tracer)) {
      traceWithLights(r, tracer, stats);
    } else if (!selective_) {
      trace(r, tracer, false, shade, stats);
    } else if (!r.settings().srtChoice) {
      trace(r, tracer, true, shade, stats);
    } else {
      choose(r, tracer, shade, stats);
    }
    if (r.settings().simulateBandwidth) simulateBandwidth(r, tracer, *lastJob_, classified_, stats);
    if (r.settings().lightError > 0.0f && !classified_ && r.frameData().traceInPlace == 0u) {
      stats.notes.push_back(
          "--light-error applies to srt's classification and to traces in place (a GPU tracer "
          "without --simulate-bandwidth): this frame traced every covered pixel");
    }
    const bool binaryLineSpace = r.settings().lineSpace.shadows == LineSpaceSettings::Shadows::Binary;
    if (tracer.name() == "ls" && binaryLineSpace && hasCutouts(r.scene())) {
      stats.notes.push_back("ls in binary mode shadows cut-outs solid: its shafts hold whole triangles "
                            "(--ls-shadows exact tests their alpha)");
    }
    if (denoised) denoise(r, stats);
  }

 private:
  // One path of the frame: the paper's (light pass, classification, trace of the doubtful pixels)
  // or every covered pixel traced; then the shading, where `shade`.
  void trace(FrameContext& r, ShadowTracer& tracer, bool classify, bool shade, FrameStats& stats) {
    const TraceList list = classify ? TraceList::Doubtful : TraceList::EveryCovered;
    const TraceJob& job = lastJob_.emplace(r.traceJob(tracer, list));
    r.context().submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
      r.recordGBuffer(cmd);
      if (classify) r.recordShadowMap(cmd, stats);
      r.recordTraceList(cmd, list, stats);
      r.timer().begin(cmd, "trace");
      tracer.record(cmd, job);
      r.timer().end(cmd);
      if (shade) r.recordShade(cmd);
    });
    r.finishTrace(tracer, job, stats);
    classified_ = classify;
  }

  // The trace of every covered pixel, joining the frame's one trace of its lights that take it
  // (FrameContext::traceWithLights; a frame of several lights on a GPU tracer).
  void traceWithLights(FrameContext& r, ShadowTracer& tracer, FrameStats& stats) {
    r.traceWithLights(tracer, stats);
    classified_ = false;
  }

  // trace(), timed: its wall time (the device's passes and a CPU tracer's trace, which no GPU
  // timestamp sees: Embree) less the camera pass and the shading, which both paths share - except
  // where the light could join the frame's one trace of its lights: there this path's shading pass,
  // the copy of its visibility into the lights' batch, is its own (a joined light pays none).
  double timedTrace(FrameContext& r, ShadowTracer& tracer, bool classify, bool shade, FrameStats& stats) {
    const bool ownShade = r.tracesWithLights(tracer);
    const std::size_t passesBefore = r.timer().passCount();
    const auto start = std::chrono::steady_clock::now();
    trace(r, tracer, classify, shade, stats);
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const auto passes = r.timer().read();
    for (std::size_t i = passesBefore; i < passes.size(); ++i) {
      if (passes[i].first == "gbuffer" || (passes[i].first == "shade" && !ownShade)) ms -= passes[i].second;
    }
    return ms;
  }

  // --srt-choice auto: srt takes whichever path its own last timings of both say is cheaper
  // on this device, scene, view and light (where the light's map and the classification cost more
  // than the rays they save, it traces every covered pixel, as frt does, and says so; each light of
  // a frame keeps its own timings, so a lamp that lights a few pixels traces them and skips its map). Its first frame
  // runs each path twice and keeps the second, warm, times (on lavapipe a path's first run also
  // pays the first touch of its buffers: +35% at 1024^2), the classify path last, so that the
  // frame's result is the paper's; every kRemeasureFrames frames the other path runs once more,
  // as views and content change.
  void choose(FrameContext& r, ShadowTracer& tracer, bool shade, FrameStats& stats) {
    constexpr std::uint64_t kRemeasureFrames = 32;
    Choice& c = choices_[r.lightIndex()];
    if (!c.classifyMs || !c.traceAllMs) {
      for (int run = 0; run < 2; ++run) {
        c.traceAllMs = timedTrace(r, tracer, false, false, stats);
        c.classifyMs = timedTrace(r, tracer, true, shade && run == 1, stats);
      }
      stats.notes.push_back("srt measured both of its paths in this frame (--srt-choice auto): classify " +
                            std::to_string(*c.classifyMs) + " ms, trace every pixel " + std::to_string(*c.traceAllMs) +
                            " ms; the frame is the classify path's, its time both's");
    } else {
      // Joining the frame's one trace of its lights (a frame of several lights on a GPU tracer) costs
      // the light its share of that trace, which it learns by joining once: its trace-all time is then
      // the share of its last join.
      const bool canJoin = r.tracesWithLights(tracer);
      if (c.joined) {
        if (const std::optional<double> share = r.joinedTraceMs(r.lightIndex())) {
          c.traceAllMs = share;
          c.shareKnown = true;
        }
      }
      bool classify = *c.classifyMs <= *c.traceAllMs;
      const bool remeasure = ++c.frames % kRemeasureFrames == 0;
      if (remeasure) classify = !classify;
      if (canJoin && !c.shareKnown) classify = false;
      c.joined = !classify && canJoin;
      if (c.joined) {
        traceWithLights(r, tracer, stats);
        stats.notes.push_back(
            "srt traced every covered pixel in the trace of the frame's lights (--srt-choice auto): "
            "its classify path last took " +
            std::to_string(*c.classifyMs) + " ms, " +
            (c.shareKnown ? "its share of that trace " : "this one on its own ") + std::to_string(*c.traceAllMs) +
            " ms");
      } else {
        (classify ? c.classifyMs : c.traceAllMs) = timedTrace(r, tracer, classify, shade, stats);
        if (!classify) {
          stats.notes.push_back("srt traced every covered pixel (--srt-choice auto): its classify path last took " +
                                std::to_string(*c.classifyMs) + " ms, this one " + std::to_string(*c.traceAllMs) +
                                " ms");
        }
      }
    }
    stats.srtPath = classified_ ? "classify" : "trace_all";
  }

  // The denoiser over this method's visibility (its own history: one pass per method object).
  void denoise(FrameContext& r, FrameStats& stats) {
    const RenderSettings& s = r.settings();
    if (!denoiser_) denoiser_ = std::make_unique<DenoisePass>(r.context(), s.width, s.height);
    r.context().submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
      r.timer().begin(cmd, "denoise");
      denoiser_->record(cmd,
                        {r.gbuffer(), r.frameBuffer(), r.visibility(), r.traceFlags(), r.blockers(), classified_,
                         r.view(), r.frameData().light, r.sceneVersion()},
                        s.denoise);
      r.timer().end(cmd);
      r.recordShade(cmd);
    });
    stats.memoryBytes["denoiser"] = denoiser_->bytes() + r.blockers().size();
    stats.denoise = denoiseModeName(s.denoise.mode);
  }

  bool selective_;
  bool classified_ = false;  // this frame took the classify path (its flags and sm answer are the frame's)
  std::optional<TraceJob> lastJob_;  // this frame's last trace
  struct Choice {                    // --srt-choice auto, per light of the frame: each path's last time
    std::optional<double> classifyMs, traceAllMs;
    std::uint64_t frames = 0;
    bool joined = false;      // its last frame joined the frame's one trace of its lights
    bool shareKnown = false;  // traceAllMs is its share of that trace (FrameContext::joinedTraceMs)
  };
  std::map<std::uint32_t, Choice> choices_;
  std::unique_ptr<DenoisePass> denoiser_;
  std::string tracerName_;  // empty: the settings' tracer
};

}  // namespace

void register_traced_method(Registry& r) {
  r.method("srt", [] { return std::make_unique<TracedMethod>(true, ""); });
  r.method("frt", [] { return std::make_unique<TracedMethod>(false, ""); });
  r.method("ls", [] { return std::make_unique<TracedMethod>(false, "ls"); });  // frt on the line-space tracer
}

}  // namespace penumbra
