// The rendering side of the demo, with no window: the scene (posed in place for animations), its
// Renderer (made anew when a setting that is fixed per Renderer changes), method, camera, light and
// animation time; the reference for the error overlay, kept while the view stays the same; and the
// frame-to-frame change of the visibility buffer. The scripted runs and the UI both drive this.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "apps/demo/camera_controller.h"
#include "apps/run_config.h"
#include "core/view.h"
#include "gpu/context.h"
#include "hybrid/method.h"
#include "hybrid/renderer.h"

namespace penumbra::demo {

class DemoSession {
 public:
  // `canonicalViews`: render the camera and light exactly as a view file stores them (text round
  // trip: up = +Y, the light's direction re-derived from its target), so that --save-view
  // reproduces the frame bit for bit with `penumbra render --view`.
  DemoSession(const gpu::Context& context, RunSetup setup, std::string method, bool canonicalViews);

  const Scene& scene() const { return setup_.scene; }
  const Bounds& bounds() const { return bounds_; }
  const RenderSettings& settings() const { return setup_.settings; }
  // A new Renderer (its structures are rebuilt on use); when refused, the previous one and rethrows.
  void setSettings(const RenderSettings& settings);
  const std::string& method() const { return method_; }
  Term term() const { return term_; }  // the method's (methodTerm), kept with it
  void setMethod(const std::string& method);  // InputError for unknown names

  CameraController& cameraController() { return camera_; }
  // The run's lights (--light, --lights, the view's or the scene's): every shown one lights the
  // frame (methods ao and indirect: the selected one); the light controls act on the selected one.
  std::size_t lightCount() const { return lights_.size(); }
  std::size_t selectedLight() const { return selected_; }
  void selectLight(std::size_t index);  // InputError past the last
  bool lightShown(std::size_t index) const { return shown_.at(index) != 0; }
  void showLight(std::size_t index, bool shown);  // InputError when it would hide every light
  const Light& lightAt(std::size_t index) const { return lights_.at(index); }
  const Light& light() const { return lights_[selected_]; }  // the selected one
  void setLight(const Light& light) { lights_[selected_] = light; }
  float lightSizeFraction() const { return sizeFractions_[selected_]; }
  void setLightSize(float fraction);  // rect and disk lights; InputError for other types
  void setLightType(LightType type);

  bool animated() const { return animated_; }
  double time() const { return time_; }
  void setTime(double seconds);  // poses the animated meshes and tells the renderer

  // Renders the method for the current view; the change against the previous frame of the same
  // method and resolution is then in temporalChange(). With --denoise temporal every frame is the
  // next of a sequence (new light samples, accumulated by the denoiser).
  const Frame& render();
  const Frame& frame() const { return frame_; }
  std::optional<double> temporalChange() const { return temporalChange_; }

  // Renders `ref` for the current view and keeps it (and its change against the previous one).
  const Frame& renderReference();
  // The reference when it was rendered for exactly the current view, time and settings; else null.
  const Frame* reference() const;
  std::optional<double> referenceTemporalChange() const { return referenceTemporalChange_; }
  // |frame - reference| of the visibility as RGBA8 (core/metrics.h errorHeatmap; full scale 1 for
  // hard shadows, 0.25 for soft ones, as in `penumbra compare`). Needs reference().
  std::vector<std::uint8_t> errorHeatmap() const;
  // The selected light's PIP flags in the last frame (what the pip, mask and thin overlays mark), or
  // the frame's own (its first light's) where that light is hidden or the method classified nothing.
  const std::vector<std::uint8_t>& selectedPip() const;
  // The selected light's tile test verdicts in the last frame (Frame::maskTiles; the tiles overlay).
  const std::vector<std::uint8_t>& selectedMaskTiles() const;

  View view() const;  // what --save-view writes: the camera and lights of the last render

 private:
  struct Key {  // what a rendered frame depends on besides the method
    Camera camera;
    std::vector<Light> lights;  // the shown ones, as rendered
    double time = 0.0;
    std::uint64_t settingsVersion = 0;
    bool operator==(const Key& other) const;
  };
  Key currentKey() const;
  Camera renderCamera() const;
  std::vector<Light> renderLights() const;
  // The selected light's place among the lights a frame shows (none where it is hidden).
  std::optional<std::size_t> selectedPlace() const;
  const Frame& selectedLightFrame() const;  // the selected light's own frame where it has one, else the frame
  // The selected light's visibility in `frame` (a frame of the key's lights), or the frame's own.
  const std::vector<float>& selectedVisibility(const Frame& frame, const Key& key) const;

  const gpu::Context& context_;
  RunSetup setup_;
  Bounds bounds_;
  std::string method_;
  Term term_ = Term::Shadow;
  bool canonicalViews_;
  CameraController camera_;
  std::vector<Light> lights_;
  std::vector<float> sizeFractions_;  // each light's --light-size (a fraction of the scene's radius)
  std::vector<std::uint8_t> shown_;
  std::size_t selected_ = 0;
  bool animated_;
  double time_ = 0.0;
  std::uint64_t settingsVersion_ = 0;
  std::uint32_t sequenceFrame_ = 0;  // --denoise temporal: frames rendered so far (each gets new light samples)
  std::unique_ptr<Renderer> renderer_;

  Frame frame_;
  std::optional<double> temporalChange_;
  Frame reference_;
  std::optional<Key> referenceKey_;
  std::optional<double> referenceTemporalChange_;
  Key lastKey_;
};

}  // namespace penumbra::demo
