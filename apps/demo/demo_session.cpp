#include "apps/demo/demo_session.h"

#include <algorithm>
#include <cstring>

#include "core/animation.h"
#include "core/lights_file.h"
#include "core/metrics.h"
#include "hybrid/method.h"

namespace penumbra::demo {
namespace {

bool sameCamera(const Camera& a, const Camera& b) {
  return a.eye == b.eye && a.target == b.target && a.up == b.up && a.fovYDeg == b.fovYDeg;
}
bool sameLight(const Light& a, const Light& b) {
  return a.type == b.type && a.position == b.position && a.direction == b.direction && a.spotAngleDeg == b.spotAngleDeg &&
         a.size == b.size && a.color == b.color;
}

// Mean |Δ| of two frames' visibility, when they can be compared (same size).
std::optional<double> changeBetween(const Frame& previous, const Frame& current) {
  if (previous.visibility.empty() || previous.width != current.width || previous.height != current.height) return {};
  return temporalChange(previous.visibility, current.visibility, previous.covered, current.covered);
}

}  // namespace

bool DemoSession::Key::operator==(const Key& o) const {
  return sameCamera(camera, o.camera) &&
         std::equal(lights.begin(), lights.end(), o.lights.begin(), o.lights.end(), sameLight) && time == o.time &&
         settingsVersion == o.settingsVersion;
}

DemoSession::DemoSession(const gpu::Context& context, RunSetup setup, std::string method, bool canonicalViews)
    : context_(context),
      setup_(std::move(setup)),
      bounds_(setup_.scene.bounds()),
      method_(std::move(method)),
      canonicalViews_(canonicalViews),
      camera_(setup_.camera, bounds_),
      lights_(setup_.lights),
      shown_(lights_.size(), 1),
      animated_(isAnimated(setup_.scene)) {
  // One light: sized by the run's fraction; several: each by its own size (a lights file's).
  for (const Light& light : lights_) {
    sizeFractions_.push_back(lights_.size() == 1 ? setup_.lightSizeFraction : light.size / bounds_.radius());
  }
  term_ = methodTerm(method_);  // unknown names fail before the GPU work
  renderer_ = std::make_unique<Renderer>(context_, setup_.scene, setup_.settings);
}

void DemoSession::selectLight(std::size_t index) {
  if (index >= lights_.size()) {
    throw InputError("light " + std::to_string(index) + ": the run has " + std::to_string(lights_.size()) + " lights");
  }
  selected_ = index;
}

void DemoSession::showLight(std::size_t index, bool shown) {
  if (!shown && std::count(shown_.begin(), shown_.end(), std::uint8_t(1)) == 1 && shown_.at(index)) {
    throw InputError("a frame needs a light: show another before hiding this one");
  }
  shown_.at(index) = shown ? 1 : 0;
}

void DemoSession::setSettings(const RenderSettings& settings) {
  const RenderSettings previous = setup_.settings;
  renderer_.reset();  // the old one's GPU objects go before the new one's are made
  try {
    setup_.settings = settings;
    renderer_ = std::make_unique<Renderer>(context_, setup_.scene, setup_.settings);
  } catch (...) {  // refused: back to the previous settings
    setup_.settings = previous;
    renderer_ = std::make_unique<Renderer>(context_, setup_.scene, setup_.settings);
    throw;
  }
  ++settingsVersion_;
}

void DemoSession::setMethod(const std::string& method) {
  term_ = methodTerm(method);  // InputError for unknown names, before anything changes
  method_ = method;
}

void DemoSession::setLightSize(float fraction) {
  Light light = lights_[selected_];
  applyLightSize(light, fraction, bounds_);
  lights_[selected_] = light;
  sizeFractions_[selected_] = fraction;
}

void DemoSession::setLightType(LightType type) {
  const bool area = type == LightType::Rect || type == LightType::Disk;
  float& fraction = sizeFractions_[selected_];
  lights_[selected_] = convertLight(lights_[selected_], type, bounds_, area ? fraction : 0.0f);
  if (!area) fraction = 0.0f;
}

void DemoSession::setTime(double seconds) {
  if (!animated_ || seconds == time_) return;
  time_ = seconds;
  poseScene(setup_.scene, seconds);
  renderer_->sceneMoved();
}

Camera DemoSession::renderCamera() const {
  return canonicalViews_ ? parseCamera(formatCamera(camera_.camera())) : camera_.camera();
}

// The shown lights (the selected one alone for methods of one light), exactly as a view file
// stores them where views are canonical: one light by its text and fraction, several as "lights".
std::vector<Light> DemoSession::renderLights() const {
  std::vector<Light> lights;
  for (std::size_t i = 0; i < lights_.size(); ++i) {
    if (term_ == Term::Shadow ? !shown_[i] : i != selected_) continue;
    Light light = lights_[i];
    if (canonicalViews_ && lights_.size() == 1) {
      light = parseLight(formatLight(light));
      applyLightSize(light, sizeFractions_[i], bounds_);
    } else if (canonicalViews_) {
      light = lightFromJson(lightToJson(light));
    }
    lights.push_back(light);
  }
  return lights;
}

DemoSession::Key DemoSession::currentKey() const { return {renderCamera(), renderLights(), time_, settingsVersion_}; }

std::optional<std::size_t> DemoSession::selectedPlace() const {
  if (!shown_[selected_]) return std::nullopt;
  std::size_t k = 0;
  for (std::size_t i = 0; i < selected_; ++i) k += shown_[i];
  return k;
}

const std::vector<float>& DemoSession::selectedVisibility(const Frame& frame, const Key& key) const {
  if (frame.lights.empty()) return frame.visibility;
  const std::optional<std::size_t> k = selectedPlace();
  return k && *k < frame.lights.size() && key.lights.size() == frame.lights.size() ? frame.lights[*k].visibility
                                                                                   : frame.visibility;
}

const Frame& DemoSession::render() {
  const Key key = currentKey();
  renderer_->setFrame(setup_.settings.denoise.mode == DenoiseMode::Temporal ? sequenceFrame_++ : 0u);
  renderer_->keepLightBuffers(selectedPlace().value_or(0));  // the selected light's, for its error
  Frame frame = renderer_->render(method_, key.camera, key.lights);
  temporalChange_ = frame_.stats.method == method_ ? changeBetween(frame_, frame) : std::nullopt;
  frame_ = std::move(frame);  // replaces the previous frame's buffers (same sizes: no growth)
  lastKey_ = key;
  return frame_;
}

const Frame& DemoSession::renderReference() {
  const Key key = currentKey();
  renderer_->setFrame(0);
  renderer_->keepLightBuffers(selectedPlace().value_or(0));
  Frame reference = renderer_->render("ref", key.camera, key.lights);
  referenceTemporalChange_ = changeBetween(reference_, reference);
  reference_ = std::move(reference);
  referenceKey_ = key;
  return reference_;
}

const Frame* DemoSession::reference() const {
  return referenceKey_ && *referenceKey_ == currentKey() ? &reference_ : nullptr;
}

const Frame& DemoSession::selectedLightFrame() const {
  const std::optional<std::size_t> k = selectedPlace();
  const bool ofKey = k && *k < frame_.lights.size() && lastKey_.lights.size() == frame_.lights.size();
  return ofKey && !frame_.lights[*k].pip.empty() ? frame_.lights[*k] : frame_;
}

const std::vector<std::uint8_t>& DemoSession::selectedPip() const { return selectedLightFrame().pip; }

const std::vector<std::uint8_t>& DemoSession::selectedMaskTiles() const { return selectedLightFrame().maskTiles; }

std::vector<std::uint8_t> DemoSession::errorHeatmap() const {
  const Frame* reference = this->reference();
  if (!reference || reference->width != frame_.width || reference->height != frame_.height) {
    throw std::logic_error("errorHeatmap() needs the reference of the current view");
  }
  // the selected light's error (a frame of several: its own visibility in each)
  const float fullScale = light().size > 0.0f ? 0.25f : 1.0f;
  return penumbra::errorHeatmap(selectedVisibility(frame_, lastKey_), selectedVisibility(*reference, *referenceKey_),
                                reference->covered, fullScale);
}

View DemoSession::view() const {
  const Key key = lastKey_.lights.empty() ? currentKey() : lastKey_;  // before the first render: the current
  const bool several = lights_.size() > 1;                            // rendered by their own sizes (renderLights)
  return {key.camera,
          key.lights.front(),
          several ? 0.0f : sizeFractions_.front(),
          several ? key.lights : std::vector<Light>{},
          int(setup_.settings.width),
          int(setup_.settings.height)};
}

}  // namespace penumbra::demo
