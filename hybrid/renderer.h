// Renders methods of one scene on one device: Renderer::render runs a frame as its stages (the
// frame's data, the light's map fitted to the view, the method's own passes, shading, read-back)
// on a FrameContext it owns, with one method object per name (they may own GPU objects).
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "core/camera.h"
#include "core/scene.h"
#include "hybrid/frame_context.h"
#include "hybrid/render_settings.h"

namespace penumbra {

class Renderer {
 public:
  Renderer(const gpu::Context& context, const Scene& scene, const RenderSettings& settings);
  ~Renderer();  // out of line: Method is incomplete here
  Frame render(const std::string& method, const Camera& camera, const Light& light);
  // Every light of the frame, one after the other through the same stages on the one G-buffer,
  // their direct light summed in shading: Frame::lights holds each light's visibility and stats.
  // Methods ao and indirect take one light (InputError).
  Frame render(const std::string& method, const Camera& camera, std::span<const Light> lights);
  // The scene's dynamic meshes were posed anew (core/animation.h, between frames): re-uploads their
  // vertices, refits the built tracers' dynamic BVHs (rebuilding when the SAH grew too much) and
  // drops the Embree reference (rebuilt on next use). Frames report the refit in stats.refit.
  void sceneMoved() { frameContext_->sceneMoved(); }
  // The frame of a sequence the next renders belong to (0 until set): rotates every pixel's light
  // samples (shared::lightSampleOffset), the same for every method and the reference, so that
  // frames of a sequence see new samples and a temporal denoiser gathers them.
  void setFrame(std::uint32_t frame) { frame_ = frame; }
  // A frame of several lights: the lights whose own buffers (visibility, PIP flags, the sm answer)
  // Frame::lights keeps beside every light's stats: all (the default: metrics per light), or only
  // the first the view reaches and light `light` (a view that shows one light's: reading back every
  // light's whole-image buffers costs more than the frame on a CPU device).
  void keepLightBuffers(std::optional<std::size_t> light) { lightBuffersOf_ = light; }
  std::uint64_t sceneVersion() const { return frameContext_->sceneVersion(); }  // counts sceneMoved() calls
  // What methods work with: the shared passes, buffers and tracers (tests inspect them here).
  FrameContext& frameContext() { return *frameContext_; }

 private:
  std::unique_ptr<FrameContext> frameContext_;
  std::map<std::string, std::unique_ptr<Method>> methods_;  // one per name, kept: they may own GPU objects
  std::uint32_t frame_ = 0;
  std::optional<std::size_t> lightBuffersOf_;  // keepLightBuffers
};

}  // namespace penumbra
