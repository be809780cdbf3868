#include "apps/demo/demo_session.h"

#include <cstring>

#include "core/animation.h"
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
  return sameCamera(camera, o.camera) && sameLight(light, o.light) && time == o.time && settingsVersion == o.settingsVersion;
}

DemoSession::DemoSession(const gpu::Context& context, RunSetup setup, std::string method, bool canonicalViews)
    : context_(context),
      setup_(std::move(setup)),
      bounds_(setup_.scene.bounds()),
      method_(std::move(method)),
      canonicalViews_(canonicalViews),
      camera_(setup_.camera, bounds_),
      light_(setup_.lights.front()),
      lightSizeFraction_(setup_.lightSizeFraction),
      animated_(isAnimated(setup_.scene)) {
  term_ = methodTerm(method_);  // unknown names fail before the GPU work
  renderer_ = std::make_unique<Renderer>(context_, setup_.scene, setup_.settings);
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
  Light light = light_;
  applyLightSize(light, fraction, bounds_);
  light_ = light;
  lightSizeFraction_ = fraction;
}

void DemoSession::setLightType(LightType type) {
  const bool area = type == LightType::Rect || type == LightType::Disk;
  light_ = convertLight(light_, type, bounds_, area ? lightSizeFraction_ : 0.0f);
  if (!area) lightSizeFraction_ = 0.0f;
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

Light DemoSession::renderLight() const {
  if (!canonicalViews_) return light_;
  Light light = parseLight(formatLight(light_));
  applyLightSize(light, lightSizeFraction_, bounds_);
  return light;
}

DemoSession::Key DemoSession::currentKey() const { return {renderCamera(), renderLight(), time_, settingsVersion_}; }

const Frame& DemoSession::render() {
  const Key key = currentKey();
  renderer_->setFrame(setup_.settings.denoise.mode == DenoiseMode::Temporal ? sequenceFrame_++ : 0u);
  Frame frame = renderer_->render(method_, key.camera, key.light);
  temporalChange_ = frame_.stats.method == method_ ? changeBetween(frame_, frame) : std::nullopt;
  frame_ = std::move(frame);  // replaces the previous frame's buffers (same sizes: no growth)
  lastKey_ = key;
  return frame_;
}

const Frame& DemoSession::renderReference() {
  const Key key = currentKey();
  renderer_->setFrame(0);
  Frame reference = renderer_->render("ref", key.camera, key.light);
  referenceTemporalChange_ = changeBetween(reference_, reference);
  reference_ = std::move(reference);
  referenceKey_ = key;
  return reference_;
}

const Frame* DemoSession::reference() const {
  return referenceKey_ && *referenceKey_ == currentKey() ? &reference_ : nullptr;
}

std::vector<std::uint8_t> DemoSession::errorHeatmap() const {
  const Frame* reference = this->reference();
  if (!reference || reference->width != frame_.width || reference->height != frame_.height) {
    throw std::logic_error("errorHeatmap() needs the reference of the current view");
  }
  const float fullScale = renderLight().size > 0.0f ? 0.25f : 1.0f;
  return penumbra::errorHeatmap(frame_.visibility, reference->visibility, reference->covered, fullScale);
}

View DemoSession::view() const {
  return {
      lastKey_.camera, lastKey_.light, lightSizeFraction_, {}, int(setup_.settings.width), int(setup_.settings.height)};
}

}  // namespace penumbra::demo
