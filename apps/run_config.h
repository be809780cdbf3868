// The options `render` and `compare` share, and turning them into a checked run: scene, camera,
// light and settings, all resolved (and refused with a clear message) before the GPU starts.
#pragma once
#include <cstdint>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "core/miss_explainer.h"
#include "core/scene.h"
#include "gpu/context.h"
#include "hybrid/renderer.h"

namespace penumbra {

// Light samples per pixel of the reference a denoised run is compared with when --reference-spp
// is not given: the converged image, not one with the method's few samples.
constexpr std::uint32_t kConvergedSpp = 256;

struct RunConfig {
  std::string scene = "builtin:courtyard";
  std::string camera, viewFile, saveView;
  std::vector<std::string> lights;  // --light, repeatable
  std::string lightsFile;           // --lights
  float lightSize = 0.0f;
  bool lightSizeGiven = false;
  double time = 0.0;  // animated scenes: pose at this many seconds
  bool timeGiven = false;
  std::uint32_t referenceSpp = 0;
  std::string resolution = "256x256";
  std::uint32_t warmup = 1;  // frames rendered and discarded before the measured ones
  std::uint32_t repeat = 1;  // measured frames; the median one is reported, with the spread
  std::string csv;           // compare: append one row per method to this CSV file
  bool noReport = false;     // compare: skip report.html (report.py and matplotlib)
  std::string tracer = "auto";  // one tracer, or for methods ao and indirect a comma-separated list
  bool explainMisses = false;  // compare: why srt left out each pixel sm gets wrong (hard shadows)
  bool validate = false;
  std::uint32_t denoiseFrames = 8;  // temporal: the frame of the sequence (after a cut) that is measured
  std::string outDir = "out";
  // What the declared options set (renderOptions(): every pass's, method's and tracer's settings), with
  // the command line's defaults: srt chooses its path per frame (--srt-choice auto) and, for area
  // lights, per tile (--tile-choice on).
  RenderSettings settings = [] {
    RenderSettings s;
    s.srtChoice = true;
    s.pip.tileChoice = true;
    return s;
  }();
};

struct RunSetup {
  Scene scene;
  Camera camera;
  // Every light of the frame: --light's (repeatable), else the view file's, else the scene's, else a
  // default one.
  std::vector<Light> lights;
  float lightSizeFraction = 0.0f;
  double time = 0.0;  // the scene is posed at this time
  RenderSettings settings;
};

// The frames one method renders in a run (`render`, `compare`, `bench`). With --denoise temporal
// (and a method other than `ref`) each is the next frame of a sequence from a cut, with new light
// samples, and the warm-up frames are its first ones, so that the first measured frame is
// --denoise-frames (or the one after --warmup's, when those are more); otherwise every frame is frame 0.
class FrameSequence {
 public:
  FrameSequence(const RunConfig& config, const RenderSettings& settings, std::string method);
  std::uint32_t warmup() const { return warmup_; }
  Frame next(Renderer& renderer, const Camera& camera, std::span<const Light> lights);

 private:
  std::string method_;
  bool sequence_;
  std::uint32_t warmup_;
  std::uint32_t frame_ = 0;
};

// The median of repeated frames by total time, with their spread (min, max, runs) in its stats.
Frame medianFrame(std::vector<Frame> runs);

void addRunOptions(CLI::App& app, RunConfig& config);
// Loads the scene (or copies `loaded`, config.scene's), resolves camera/light (printing defaults so
// they can be reused), checks every number and the memory the run needs; writes --save-view.
// Throws InputError.
RunSetup prepareRun(const RunConfig& config, const std::vector<std::string>& methods, const Scene* loaded = nullptr);
// The reference a method's frame is compared with: ref for shadows, the Embree tracer's own run
// for ao and indirect.
std::string referenceFor(const std::string& method);
// Judges `frame` against its reference as compare does, into its stats: visibility and image
// errors (the FLIP map into `flip`), and for methods that classify the PIP misses, the penumbra
// misses (`soft`: an area light) and, with --explain-misses, why (returned).
std::optional<MissReport> judgeFrame(Frame& frame, const Frame& reference, bool soft, std::vector<float>* flip);
nlohmann::json describeRun(const RunConfig& config, const RunSetup& setup, const gpu::Context& context);
void printSummary(const std::vector<Frame>& frames, std::ostream& out);
std::vector<std::string> splitList(const std::string& list);
// The methods a run renders: ao and indirect once per tracer of --tracer (ao-bvh, indirect-embree,
// ...; auto is bvh). InputError for a tracer list (or an indirect-only tracer) with shadow methods,
// and for tracers a method does not have.
std::vector<std::string> expandMethods(const RunConfig& config, const std::vector<std::string>& methods);
// One row per frame: scene, method, tracer, times (median, min, max), PIP, rays, steps, error, machine.
void appendCsv(const std::string& path, const std::vector<Frame>& frames, const nlohmann::json& context);

}  // namespace penumbra
