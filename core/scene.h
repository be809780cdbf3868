// Scene model: world-space triangle meshes (node transforms flattened at load), lights, camera.
// Units are the model's own; sizes that depend on scale are fractions of bounds().radius().
// Positions, cameras and lights are stored relative to Scene::origin (see WorldBounds), so that a
// model far from the world origin keeps the float precision of its own size.
#pragma once
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace penumbra {

// Thrown for every problem with user input (files, options, scenes); the message names the input and the fix.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// An image of a model, decoded to 8-bit RGBA; row 0 is the top, where texture coordinate v = 0 is
// (glTF's and OBJ's convention once the OBJ loader flips v).
struct Texture {
  std::string name;  // the file or the image's name in the model, for messages
  std::uint32_t width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  // width * height * 4
};

// A mesh whose texture cuts it out (glTF alphaMode MASK, and BLEND by the same rule with cutoff 0.5;
// OBJ map_d): a point of a triangle is solid where `factor` times the alpha of the texture's nearest
// texel at the point's texture coordinate is >= `cutoff` (shared/alpha.h, one rule for every method
// and the reference). Without a texture, factor alone decides for the whole mesh.
struct Cutout {
  std::int32_t texture = -1;  // index into Scene::textures; -1: none
  float factor = 1.0f;        // baseColorFactor's alpha
  float cutoff = 0.5f;
};

struct Mesh {
  std::string name;
  std::vector<glm::vec3> positions;  // world space
  std::vector<glm::vec3> normals;    // world space, unit, one per position
  std::vector<std::uint32_t> indices;  // three per triangle
  std::vector<glm::vec2> uvs;        // texture coordinates, one per position (or none)
  std::optional<Cutout> cutout;      // alpha-tested; a cut-out with a texture has uvs
  glm::vec3 baseColor{0.8f};         // linear RGB, times the colour texture's where there is one
  std::int32_t colorTexture = -1;    // index into Scene::textures: the base colour (sRGB) at uvs; -1: none
  bool dynamic = false;  // moves during the run (posed by an animation, core/animation.h); static otherwise
  std::size_t triangleCount() const { return indices.size() / 3; }
};

enum class LightType { Directional, Spot, Point, Rect, Disk };

struct Light {
  LightType type = LightType::Point;
  glm::vec3 position{0.0f};              // unused for Directional
  glm::vec3 direction{0.0f, -1.0f, 0.0f};  // unit: where the light points (travel direction for Directional)
  float spotAngleDeg = 60.0f;            // full cone angle, Spot only
  float size = 0.0f;                     // world units: Rect side / Disk diameter; 0 = a point
  glm::vec3 color{1.0f};
  // How bright, relative to a light of irradiance 1: the scale of its colour in shading. glTF lights
  // (KHR_lights_punctual) fall off by the inverse square of the distance (then intensity is the
  // irradiance at distance 1) within their range; other lights do not fall off. The shadow does
  // not depend on any of these: only the shaded image does.
  float intensity = 1.0f;
  bool inverseSquare = false;
  float range = 0.0f;           // distance at which the light's contribution ends (glTF's window); 0 = none
  float innerAngleDeg = -1.0f;  // Spot: full cone angle inside which it is at full strength (glTF's
                                // innerConeAngle, fading to spotAngleDeg); < 0: full strength to the edge
};

struct Camera {
  glm::vec3 eye{0.0f, 0.0f, 5.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fovYDeg = 45.0f;
};

struct Bounds {
  glm::vec3 lo{std::numeric_limits<float>::max()};
  glm::vec3 hi{-std::numeric_limits<float>::max()};
  bool empty() const { return lo.x > hi.x; }
  void extend(const glm::vec3& p) { lo = glm::min(lo, p); hi = glm::max(hi, p); }
  glm::vec3 center() const { return 0.5f * (lo + hi); }
  float radius() const { return 0.5f * glm::length(hi - lo); }  // bounding sphere of the box
};

// Rigid keyframe animation of one dynamic mesh (core/animation.h poses it). Positions and normals
// at time t are the rest ones under translate(translation) * rotate(rotation), both interpolated
// between the keys around t (linear, slerp); the keys repeat with the period of the last key time.
struct RigidKey {
  float time = 0.0f;  // seconds, increasing from 0
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
};
struct MeshAnimation {
  std::size_t mesh = 0;  // index into Scene::meshes (a mesh with dynamic = true)
  std::vector<glm::vec3> restPositions, restNormals;
  std::vector<RigidKey> keys;
};

// World-space bounds of a model as a loader reads it, in double (non-finite points are skipped).
// origin() is where the loader puts Scene::origin: the world origin itself unless the box's centre
// lies more than 16 of its radii from it (georeferenced tiles, terrain, ships in world
// coordinates), else the centre snapped to a power-of-two step no larger than the radius.
struct WorldBounds {
  glm::dvec3 lo{std::numeric_limits<double>::infinity()};
  glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
  void extend(const glm::dvec3& p);
  glm::dvec3 origin() const;
};

struct Scene;
// Moves each mesh of `scene` from its local coordinates by its world transform (meshWorld[i] for
// scene.meshes[i]) into the scene's, composed in double, after choosing Scene::origin from the
// world bounds (WorldBounds): a node placed far from the world origin keeps its mesh's detail.
// Returns the world-to-scene transform, for the loader's cameras and lights.
glm::dmat4 placeMeshes(Scene& scene, const std::vector<glm::dmat4>& meshWorld);

struct Scene {
  std::string name;
  // World position of (0,0,0) in every coordinate below. Options and view files give cameras and
  // lights in world coordinates; core/view.h converts them with this origin.
  glm::dvec3 origin{0.0};
  std::vector<Mesh> meshes;
  std::vector<Texture> textures;  // those the meshes use (Cutout::texture, Mesh::colorTexture)
  std::optional<Camera> camera;  // from the file or the built-in scene; else a default framing
  std::vector<Light> lights;     // every one is rendered (RunSetup::lights); --light replaces them
  std::vector<std::string> warnings;  // what loading cleaned or ignored, reported in stats
  double loadMs = 0.0;                 // reading, decoding and cleaning the model (loadScene), reported in stats
  std::vector<MeshAnimation> animations;  // dynamic meshes and how they move

  // Every pose the scene takes: static meshes, and each animated mesh swept over its keys (so
  // shadow-map fitting and ray offsets stay fixed while objects move).
  Bounds bounds() const;
  std::size_t triangleCount() const;
};

// Drops triangles with non-finite vertices, out-of-range indices or zero area; fills missing or
// non-finite normals from faces; records what it removed in scene.warnings. Throws InputError
// naming `source` when nothing drawable is left.
void cleanScene(Scene& scene, const std::string& source);

const char* lightTypeName(LightType type);

// The distance from p to the nearest point of any of the scene's triangles (infinity without any):
// how far a point light's cube map can set its near plane.
float distanceToNearestTriangle(const Scene& scene, const glm::vec3& p);

}  // namespace penumbra
