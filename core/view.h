// Camera and light as text and as a JSON view file, and default framing for models without them.
//
// Camera spec: "ex,ey,ez:tx,ty,tz[:fovy]"                          (eye, target, vertical fov in degrees)
// Light spec:  "dir:dx,dy,dz"                                       directional, travel direction
//              "point:x,y,z"
//              "spot:x,y,z:tx,ty,tz[:angle]"                        full cone angle in degrees
//              "rect:x,y,z:tx,ty,tz"  "disk:x,y,z:tx,ty,tz"         area light at x,y,z facing t;
//                                                                   size from --light-size
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "core/scene.h"

namespace penumbra {

// Specs and view files speak world coordinates; Camera and Light hold them relative to the
// scene's origin (Scene::origin), which these subtract on reading and add on writing, in double.
Camera parseCamera(const std::string& spec, const glm::dvec3& origin = glm::dvec3(0.0));  // InputError on malformed text
// parseCamera(formatCamera(c, o), o) == c (to 6 digits)
std::string formatCamera(const Camera& camera, const glm::dvec3& origin = glm::dvec3(0.0));
Light parseLight(const std::string& spec, const glm::dvec3& origin = glm::dvec3(0.0));
std::string formatLight(const Light& light, const glm::dvec3& origin = glm::dvec3(0.0));

// A rectangle (patch) for patch-to-patch visibility: corner + s u + t v, s and t in [0, 1].
// Spec: "x,y,z:ux,uy,uz:vx,vy,vz" (the corner in world coordinates, u and v its perpendicular edges).
struct Patch {
  glm::vec3 corner{0.0f}, u{0.0f}, v{0.0f};
};
Patch parsePatch(const std::string& spec, const glm::dvec3& origin = glm::dvec3(0.0));  // InputError on malformed text

// Three-quarter view that frames the whole bounds.
Camera defaultCamera(const Bounds& bounds);
// A disk light (size 0 = point-like) above and to the side of the bounds, facing their centre.
Light defaultLight(const Bounds& bounds);

// The light turned by `degrees` about the vertical (+y) axis through the bounds' centre: position
// and direction alike, so a light keeps aiming at the same part of the scene as it circles. The
// slowly moving light of the demo's --light-path circle and of bench's temporal-stability frames.
Light orbitLight(const Light& light, const Bounds& bounds, float degrees);

// Sets light.size from a fraction of the scene radius. Refuses (InputError) a size > 0 for light
// types that have no extent (directional, spot, point) and negative or non-finite fractions.
void applyLightSize(Light& light, float fractionOfRadius, const Bounds& bounds);

// A view pins camera, light and resolution for reproducible runs (JSON).
struct View {
  Camera camera;
  Light light;
  float lightSizeFraction = 0.0f;  // --light-size
  // "lights" (core/lights_file.h): every light of a view of several, each with its own size, colour
  // and range; empty: the view's one light is `light`, sized by lightSizeFraction.
  std::vector<Light> lights;
  int width = 256;
  int height = 256;
  double time = 0.0;  // animated scenes: seconds into the animation (optional field "time")
};
// The double whose shortest text reads back as `v`: a JSON file then shows 0.85, not
// 0.8500000238418579 (view files, lights files).
double shortestDouble(float v);
// The JSON in a file; InputError naming it (`file`, e.g. "view file 'x'") when it is missing,
// unreadable or not JSON (then saying what was `expected`).
nlohmann::json readJsonFile(const std::string& path, const std::string& file, const std::string& expected);
// InputError naming the file and the bad field.
View readViewFile(const std::string& path, const glm::dvec3& origin = glm::dvec3(0.0));
void writeViewFile(const std::string& path, const View& view, const glm::dvec3& origin = glm::dvec3(0.0));

}  // namespace penumbra
