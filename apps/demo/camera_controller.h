// Camera and light motion for the demo as pure math (no window, no GPU), so the mouse, the
// scripted runs and the tests all drive the same code. The camera keeps world +Y as its up
// vector, which is what view files store, so --save-view reproduces what is on screen.
#pragma once
#include <glm/glm.hpp>

#include "core/scene.h"

namespace penumbra::demo {

class CameraController {
 public:
  CameraController(const Camera& home, const Bounds& bounds);

  const Camera& camera() const { return camera_; }
  void setCamera(const Camera& camera);
  void reset() { setCamera(home_); }

  // Turns the eye about the target: yaw about world +Y, pitch up/down (held within +-85 degrees so
  // the view never flips over the pole and view files keep +Y as up). The distance to the target is kept.
  void orbit(float yawDeg, float pitchDeg);
  // Moves the eye toward the target (steps > 0) or away, 10% of the distance per step, kept
  // between 1% and 20 times the scene radius.
  void zoom(float steps);
  // Moves eye and target together, in the view's frame: move.x right, move.y up, move.z forward,
  // at half the scene radius per second.
  void fly(const glm::vec3& move, float seconds);

 private:
  Camera home_, camera_;
  float radius_;
};

// Turns the light about the bounds centre (azimuth about world +Y, elevation toward +Y) keeping its
// distance; a directional light turns its direction instead. Lights with a direction (spot, rect,
// disk) turn it with them, so a light aimed at the centre stays aimed at it. Elevation is held
// within +-89 degrees.
void moveLight(Light& light, const Bounds& bounds, float azimuthDeg, float elevationDeg);

// The light as another type at the same place: positional types keep the position (a directional
// light's stands 2 radii up its direction from the centre) and aim at the centre; a directional
// light shines from the old position toward the centre. `sizeFraction` (of the radius) applies to
// rect and disk lights; other types get size 0.
Light convertLight(const Light& light, LightType type, const Bounds& bounds, float sizeFraction);

// Mouse drag to degrees: a 1000-pixel drag turns 300 degrees.
inline constexpr float kDegreesPerPixel = 0.3f;

}  // namespace penumbra::demo
