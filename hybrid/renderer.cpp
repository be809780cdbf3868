#include "hybrid/renderer.h"

#include <algorithm>
#include <chrono>
#include <map>

#include "core/units.h"
#include "hybrid/method.h"
#include "hybrid/registry.h"

namespace penumbra {

Renderer::Renderer(const gpu::Context& context, const Scene& scene, const RenderSettings& settings)
    : frameContext_(std::make_unique<FrameContext>(context, scene, settings)) {}

Renderer::~Renderer() = default;

namespace {

// The frame of several lights: the image their shading summed (with its coverage, from the last
// light shaded), the first light's buffers, every light's own frame, and stats that add theirs up.
Frame combine(std::vector<Frame> lights, std::vector<std::uint8_t> covered, std::vector<std::uint8_t> rgba) {
  Frame frame;
  frame.width = lights.front().width;
  frame.height = lights.front().height;
  frame.covered = std::move(covered);
  frame.rgba = std::move(rgba);
  frame.visibility = lights.front().visibility;
  frame.pip = lights.front().pip;
  frame.maskTiles = lights.front().maskTiles;
  frame.shadowMapVisibility = lights.front().shadowMapVisibility;
  FrameStats& s = frame.stats;
  const FrameStats& first = lights.front().stats;
  s.method = first.method;
  s.tracer = first.tracer;
  s.samplesPerPixel = first.samplesPerPixel;
  s.setupMs = first.setupMs;
  std::map<std::string, std::size_t> noteLights;  // how many lights gave each note
  for (Frame& light : lights) {
    light.covered.clear();
    light.rgba.clear();
    const FrameStats& l = light.stats;
    s.totalMs += l.totalMs;
    for (const auto& [pass, ms] : l.passMs) s.addPass(pass, ms);
    if (l.raysTraced) s.raysTraced = s.raysTraced.value_or(0) + *l.raysTraced;
    if (l.nodeVisits) s.nodeVisits = s.nodeVisits.value_or(0) + *l.nodeVisits;
    if (l.triangleTests) s.triangleTests = s.triangleTests.value_or(0) + *l.triangleTests;
    if (l.pipPixels) s.pipPixels = s.pipPixels.value_or(0) + *l.pipPixels;
    for (const auto& [what, bytes] : l.memoryBytes) s.memoryBytes[what] = std::max(s.memoryBytes[what], bytes);
    for (const auto& [what, count] : l.counts) s.counts[what] += count;
    for (const std::string& note : l.notes) ++noteLights[note];
    s.lights.push_back(l);
  }
  // every light's share of the same covered pixels
  const std::uint64_t coveredLights =
      std::uint64_t(std::count(frame.covered.begin(), frame.covered.end(), std::uint8_t(1))) * s.lights.size();
  if (s.pipPixels) s.pipFraction = coveredLights ? double(*s.pipPixels) / double(coveredLights) : 0.0;
  // The frame's notes are those every light gave; a light's own (culled, srt's path and timings)
  // stay in its stats, which a note counts.
  std::size_t own = 0;
  for (const FrameStats& l : s.lights) {
    bool ownNote = false;
    for (const std::string& note : l.notes) {
      const bool everyLight = noteLights[note] == s.lights.size();
      ownNote = ownNote || !everyLight;
      if (everyLight && std::find(s.notes.begin(), s.notes.end(), note) == s.notes.end()) s.notes.push_back(note);
    }
    own += ownNote;
  }
  if (own) {
    s.notes.push_back(std::to_string(own) + " of " + std::to_string(s.lights.size()) +
                      " lights have notes of their own (each light's stats: lights[i].notes)");
  }
  frame.lights = std::move(lights);
  return frame;
}

}  // namespace

Frame Renderer::render(const std::string& methodName, const Camera& camera, const Light& light) {
  return render(methodName, camera, std::span<const Light>(&light, 1));
}

Frame Renderer::render(const std::string& methodName, const Camera& camera, std::span<const Light> lights) {
  if (lights.empty()) throw InputError("a frame needs a light");
  std::unique_ptr<Method>& method = methods_[methodName];
  if (!method) method = makeMethod(methodName);
  if (lights.size() > 1 && method->term() != Term::Shadow) {
    throw InputError("method " + methodName + " takes one light, but the frame has " + std::to_string(lights.size()) +
                     "; give one --light");
  }
  // A light whose range the view does not reach is 0 wherever the view sees: nothing runs for it.
  std::vector<std::size_t> reaching;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    if (lights.size() == 1 || frameContext_->lightReachesView(camera, lights[i])) reaching.push_back(i);
  }
  if (reaching.empty()) reaching.push_back(0);  // one light shades the image
  std::vector<Frame> frames(lights.size());
  std::vector<bool> reached(lights.size(), false);
  for (std::size_t k = 0; k < reaching.size(); ++k) {
    FrameStats stats;
    stats.method = methodName;
    const bool buffers = !lightBuffersOf_ || k == 0 || reaching[k] == *lightBuffersOf_;
    frameContext_->begin(camera, lights[reaching[k]], *method, frame_, stats,
                         {std::uint32_t(reaching[k]), std::uint32_t(k), std::uint32_t(reaching.size()), buffers});
    reached[reaching[k]] = true;
    const auto start = std::chrono::steady_clock::now();
    if (method->readsShadowMap()) frameContext_->fitLightToView(stats);
    method->run(*frameContext_, stats);
    frameContext_->shade(stats);
    stats.totalMs = msSince(start);
    frames[reaching[k]] = frameContext_->readBack(*method, std::move(stats));
    frameContext_->settleTracedLights(frames);
  }
  if (lights.size() == 1) return std::move(frames.front());
  Frame& shaded = frames[reaching.back()];
  std::vector<std::uint8_t> covered = std::move(shaded.covered), rgba = std::move(shaded.rgba);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (reached[i]) continue;
    Frame& f = frames[i];
    f.width = shaded.width;
    f.height = shaded.height;
    if (!lightBuffersOf_ || i == *lightBuffersOf_) f.visibility.assign(covered.size(), 0.0f);
    f.stats.method = methodName;
    f.stats.notes.push_back("culled: the light's range does not reach the view");
  }
  return combine(std::move(frames), std::move(covered), std::move(rgba));
}

}  // namespace penumbra
