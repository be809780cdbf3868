#include "core/builtin_scenes.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <utility>

#include "core/animation.h"
#include "core/mesh_builder.h"
#include "core/stress_scenes.h"

namespace penumbra {

namespace {

constexpr int kDefaultCourtyardLevel = 8;
constexpr int kMaxCourtyardLevel = 512;
constexpr int kDefaultStreetLamps = 16, kMaxStreetLamps = 256;

Mesh& addMesh(Scene& scene, std::string name, const glm::vec3& color) {
  Mesh& m = scene.meshes.emplace_back();
  m.name = std::move(name);
  m.baseColor = color;
  return m;
}

// Disk light with no extent (users widen it with --light-size) aimed at `aim`.
Light pointLikeDisk(const glm::vec3& position, const glm::vec3& aim) {
  Light light;
  light.type = LightType::Disk;
  light.position = position;
  light.direction = glm::normalize(aim - position);
  light.size = 0.0f;
  return light;
}

Scene courtyard(int level) {
  Scene scene;
  scene.name = "builtin:courtyard";
  const int L = level;

  // Ground: 24 x 24 at y = 0, 8*LEVEL cells a side; wide enough to catch every shadow.
  mesh::addGrid(addMesh(scene, "ground", {0.62f, 0.60f, 0.55f}), {-12.0f, 0.0f, 12.0f}, {24.0f, 0.0f, 0.0f},
                {0.0f, 0.0f, -24.0f}, 8 * L, 8 * L, {0.0f, 1.0f, 0.0f});

  mesh::addYawedBox(addMesh(scene, "box_red", {0.75f, 0.28f, 0.22f}), {-5.5f, 1.0f, -2.5f}, {1.0f, 1.0f, 1.0f}, 20.0f);
  mesh::addBox(addMesh(scene, "box_slab", {0.25f, 0.45f, 0.75f}), {0.5f, 0.4f, -3.5f}, {1.5f, 0.0f, 0.0f},
               {0.0f, 0.4f, 0.0f}, {0.0f, 0.0f, 0.8f});
  mesh::addYawedBox(addMesh(scene, "box_tower", {0.85f, 0.72f, 0.28f}), {4.8f, 1.5f, -2.0f}, {0.5f, 1.5f, 0.5f}, 45.0f);

  // Colonnade along the back.
  const glm::vec3 columnColors[5] = {{0.85f, 0.85f, 0.80f}, {0.80f, 0.78f, 0.70f}, {0.75f, 0.80f, 0.85f},
                                     {0.82f, 0.75f, 0.78f}, {0.78f, 0.84f, 0.74f}};
  for (int i = 0; i < 5; ++i) {
    const float x = -5.6f + 2.8f * float(i);
    mesh::addCylinder(addMesh(scene, "column_" + std::to_string(i + 1), columnColors[i]), {x, 0.0f, -6.0f},
                      {x, 4.0f, -6.0f}, 0.35f, 8 * L);
  }

  // Sphere resolution stops growing at LEVEL 128 so its pole triangles keep a clearly non-zero
  // area in float (cleanScene would drop them); the ground and torus carry the larger levels.
  const int sphereLevel = std::min(L, 128);
  mesh::addSphere(addMesh(scene, "sphere", {0.30f, 0.70f, 0.35f}), {2.0f, 1.2f, 1.5f}, 1.2f, 12 * sphereLevel,
                  6 * sphereLevel);
  // Upright torus, so its shadow is a ring with a hole.
  mesh::addTorus(addMesh(scene, "torus", {0.70f, 0.35f, 0.75f}), {-3.5f, 1.6f, 1.5f}, {1.0f, 0.0f, 0.35f}, 1.2f,
                 0.35f, 12 * L, 6 * L);

  // Fence of 20 bars 0.24 wide (0.014 of the scene radius, 17.09) with a top rail.
  Mesh& fence = addMesh(scene, "fence", {0.45f, 0.30f, 0.20f});
  for (int i = 0; i < 20; ++i) {
    mesh::addBox(fence, {7.5f, 1.0f, -3.8f + 0.4f * float(i)}, {0.12f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f},
                 {0.0f, 0.0f, 0.12f});
  }
  mesh::addBox(fence, {7.5f, 2.06f, 0.0f}, {0.08f, 0.0f, 0.0f}, {0.0f, 0.06f, 0.0f}, {0.0f, 0.0f, 4.0f});

  // Two posts with cross-arms carrying six horizontal wires 0.05 thick (0.0029 of the radius).
  Mesh& posts = addMesh(scene, "wire_posts", {0.35f, 0.35f, 0.38f});
  for (const float x : {-6.0f, 6.0f}) {
    mesh::addBox(posts, {x, 1.6f, 6.0f}, {0.12f, 0.0f, 0.0f}, {0.0f, 1.6f, 0.0f}, {0.0f, 0.0f, 0.12f});
    mesh::addBox(posts, {x, 3.1f, 6.0f}, {0.08f, 0.0f, 0.0f}, {0.0f, 0.08f, 0.0f}, {0.0f, 0.0f, 1.15f});
  }
  Mesh& wires = addMesh(scene, "wires", {0.10f, 0.10f, 0.12f});
  for (int i = 0; i < 6; ++i) {
    mesh::addBox(wires, {0.0f, 3.0f, 6.0f - 1.0f + 0.4f * float(i)}, {6.0f, 0.0f, 0.0f}, {0.0f, 0.025f, 0.0f},
                 {0.0f, 0.0f, 0.025f});
  }

  // High on the camera's left: every shadow falls on the ground, beside its caster and in view.
  const glm::vec3 centre = scene.bounds().center();
  scene.lights.push_back(pointLikeDisk({-16.0f, 22.0f, -1.0f}, centre));
  Camera camera;
  camera.eye = {7.0f, 17.0f, 22.0f};
  camera.target = {0.8f, 0.0f, 0.6f};
  camera.fovYDeg = 45.0f;
  scene.camera = camera;
  return scene;
}

// The courtyard with a drone (a flat body and two crossed rotor bars, 0.06 thick) flying a circle
// 3.6 above the ground and spinning as it goes: a rigid animation, looped every 8 s.
Scene courtyardMoving(int level) {
  Scene scene = courtyard(level);
  scene.name = "builtin:courtyard-moving";
  Mesh& drone = addMesh(scene, "drone", {0.90f, 0.45f, 0.10f});
  mesh::addBox(drone, {0.0f, 0.0f, 0.0f}, {0.5f, 0.0f, 0.0f}, {0.0f, 0.12f, 0.0f}, {0.0f, 0.0f, 0.5f});
  mesh::addBox(drone, {0.0f, 0.18f, 0.0f}, {1.6f, 0.0f, 0.0f}, {0.0f, 0.02f, 0.0f}, {0.0f, 0.0f, 0.03f});
  mesh::addBox(drone, {0.0f, 0.18f, 0.0f}, {0.0f, 0.0f, 0.03f}, {0.0f, 0.02f, 0.0f}, {-1.6f, 0.0f, 0.0f});
  // 16 segments a lap; per segment the heading turns 22.5 and the spin 67.5 degrees (< 180, so
  // slerp turns the intended way).
  std::vector<RigidKey> keys;
  for (int k = 0; k <= 16; ++k) {
    const float a = glm::radians(22.5f * float(k));
    RigidKey key;
    key.time = 0.5f * float(k);
    key.translation = {0.5f + 3.5f * std::cos(a), 3.6f, 0.5f - 3.5f * std::sin(a)};
    key.rotation = glm::angleAxis(glm::radians(90.0f * float(k)), glm::vec3(0.0f, 1.0f, 0.0f));
    keys.push_back(key);
  }
  animateMesh(scene, scene.meshes.size() - 1, std::move(keys));
  poseScene(scene, 0.0);
  return scene;
}

// Direction on the ground rotated by `deg` about +y from +x.
glm::vec3 yawed(float deg, const glm::vec3& v) {
  const float a = glm::radians(deg);
  return {std::cos(a) * v.x + std::sin(a) * v.z, v.y, -std::sin(a) * v.x + std::cos(a) * v.z};
}

Scene wires() {
  Scene scene;
  scene.name = "builtin:wires";
  mesh::addQuad(addMesh(scene, "ground", {0.70f, 0.70f, 0.68f}), {-20.0f, 0.0f, -20.0f}, {20.0f, 0.0f, -20.0f},
                {20.0f, 0.0f, 20.0f}, {-20.0f, 0.0f, 20.0f}, {0.0f, 1.0f, 0.0f});
  // 10 + 10 wires 0.012 thick, 0.3 apart, 3 long, turned 7 degrees so they cross texel rows at an
  // angle; the second layer sits 0.02 higher so the boxes do not interpenetrate.
  Mesh& m = addMesh(scene, "wires", {0.15f, 0.15f, 0.18f});
  const glm::vec3 along = yawed(7.0f, {1.0f, 0.0f, 0.0f});
  const glm::vec3 across = yawed(7.0f, {0.0f, 0.0f, 1.0f});
  const glm::vec3 up{0.0f, 1.0f, 0.0f};
  const float half = 0.006f;
  for (int layer = 0; layer < 2; ++layer) {
    const glm::vec3 dirA = layer == 0 ? along : across;
    const glm::vec3 dirB = layer == 0 ? across : along;
    const float y = layer == 0 ? 1.0f : 1.02f;
    for (int i = 0; i < 10; ++i) {
      const float offset = 0.3f * (float(i) - 4.5f);
      mesh::addBox(m, glm::vec3(0.0f, y, 0.0f) + offset * dirB, 1.5f * dirA, half * up, half * dirB);
    }
  }
  Light light;
  light.type = LightType::Directional;
  light.direction = glm::normalize(glm::vec3(0.15f, -1.0f, 0.1f));
  scene.lights.push_back(light);
  // Looks down ~50 degrees from the -z side with a narrow fov, so one pixel covers < 0.008 of
  // ground and a wire's shadow (>= 0.012 wide) spans >= 1.5 pixels at 256 x 256.
  Camera camera;
  camera.target = {0.1f, 0.0f, 0.1f};
  const glm::vec3 back = glm::normalize(glm::vec3(-0.25f, 0.0f, -1.0f));
  const float distance = 3.4f, down = glm::radians(50.0f);
  camera.eye = camera.target + distance * (std::cos(down) * back + std::sin(down) * up);
  camera.fovYDeg = 25.0f;
  scene.camera = camera;
  return scene;
}

Scene square() {
  Scene scene;
  scene.name = "builtin:square";
  const glm::vec3 up{0.0f, 1.0f, 0.0f};
  mesh::addQuad(addMesh(scene, "ground", {0.75f, 0.75f, 0.75f}), {-5.0f, 0.0f, -5.0f}, {5.0f, 0.0f, -5.0f},
                {5.0f, 0.0f, 5.0f}, {-5.0f, 0.0f, 5.0f}, up);
  mesh::addQuad(addMesh(scene, "occluder", {0.80f, 0.30f, 0.25f}), {-1.0f, 1.0f, -1.0f}, {1.0f, 1.0f, -1.0f},
                {1.0f, 1.0f, 1.0f}, {-1.0f, 1.0f, 1.0f}, up);
  Light light;
  light.type = LightType::Directional;
  light.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
  scene.lights.push_back(light);
  Camera camera;
  camera.eye = {0.0f, 9.0f, 9.0f};
  camera.target = {0.3f, 0.0f, 0.2f};  // the shadow's centre
  camera.fovYDeg = 45.0f;
  scene.camera = camera;
  return scene;
}

// The square with its occluder cut out by an 8 x 8 checker of alpha 1 and 0 (builtin_scenes.h).
Scene checker() {
  Scene scene = square();
  scene.name = "builtin:checker";
  Mesh& occluder = scene.meshes[1];
  occluder.name = "checker";
  for (const glm::vec3& p : occluder.positions) occluder.uvs.push_back({(p.x + 1.0f) / 2.0f, (p.z + 1.0f) / 2.0f});
  occluder.cutout = Cutout{.texture = 0, .factor = 1.0f, .cutoff = 0.5f};
  Texture& texture = scene.textures.emplace_back();
  texture.name = "checker";
  texture.width = texture.height = kCheckerCells;
  for (std::uint32_t y = 0; y < kCheckerCells; ++y) {
    for (std::uint32_t x = 0; x < kCheckerCells; ++x) {
      const std::uint8_t solid = (x + y) % 2 == 0 ? 255 : 0;
      texture.rgba.insert(texture.rgba.end(), {200, 200, 200, solid});
    }
  }
  return scene;
}

Scene room() {
  Scene scene;
  scene.name = "builtin:room";
  // Walls, floor and ceiling as one inward-facing box: x, z in [-5, 5], y in [0, 4].
  mesh::addBox(addMesh(scene, "room", {0.80f, 0.78f, 0.72f}), {0.0f, 2.0f, 0.0f}, {5.0f, 0.0f, 0.0f},
               {0.0f, 2.0f, 0.0f}, {0.0f, 0.0f, 5.0f}, /*inward=*/true);
  // The light sits off the camera's line of sight so shadows are not hidden behind their casters.
  mesh::addYawedBox(addMesh(scene, "crate", {0.70f, 0.45f, 0.25f}), {-1.5f, 0.75f, 2.2f}, {0.75f, 0.75f, 0.75f},
                    25.0f);
  // Floor-to-ceiling pillar: its shadow climbs the -x wall.
  mesh::addCylinder(addMesh(scene, "pillar", {0.55f, 0.60f, 0.70f}), {-2.2f, 0.0f, -2.5f}, {-2.2f, 4.0f, -2.5f},
                    0.35f, 48);
  // A ball hanging above the light's height throws its shadow onto the ceiling.
  mesh::addSphere(addMesh(scene, "ball", {0.30f, 0.65f, 0.40f}), {-1.0f, 3.1f, -0.5f}, 0.5f, 48, 24);
  mesh::addCylinder(addMesh(scene, "cord", {0.20f, 0.20f, 0.20f}), {-1.0f, 3.6f, -0.5f}, {-1.0f, 4.0f, -0.5f},
                    0.02f, 8);
  Light light;
  light.type = LightType::Point;
  light.position = {1.2f, 2.0f, -1.0f};
  scene.lights.push_back(light);
  Camera camera;
  camera.eye = {4.4f, 3.2f, 4.4f};
  camera.target = {-2.0f, 1.2f, -2.0f};
  camera.fovYDeg = 60.0f;
  scene.camera = camera;
  return scene;
}

// A street of `lamps` lamps (builtin_scenes.h).
Scene street(int lamps) {
  Scene scene;
  scene.name = "builtin:street";
  const int perSide = (lamps + 1) / 2;
  constexpr float kSpacing = 6.0f, kRange = 7.0f, kHeight = 3.6f;
  const float length = kSpacing * float(perSide) + 6.0f;  // from x = -3, the first lamp at x = 0
  mesh::addGrid(addMesh(scene, "road", {0.35f, 0.35f, 0.37f}), {-3.0f, 0.0f, 7.0f}, {length, 0.0f, 0.0f},
                {0.0f, 0.0f, -14.0f}, 4 * perSide, 8, {0.0f, 1.0f, 0.0f});
  addMesh(scene, "lamp_posts", {0.20f, 0.22f, 0.25f});
  addMesh(scene, "railings", {0.55f, 0.50f, 0.45f});
  addMesh(scene, "benches", {0.55f, 0.35f, 0.20f});
  Mesh& poles = scene.meshes[1];  // taken once all are added: adding moves them
  Mesh& fence = scene.meshes[2];
  Mesh& benches = scene.meshes[3];
  for (int i = 0; i < lamps; ++i) {
    const float side = i % 2 == 0 ? 1.0f : -1.0f;  // alternate sides, so that every count fills both
    const float x = kSpacing * (float(i / 2) + (side > 0.0f ? 0.0f : 0.5f));
    const float z = 4.5f * side;
    mesh::addCylinder(poles, {x, 0.0f, z}, {x, kHeight + 0.3f, z}, 0.06f, 8);  // a thin post
    mesh::addBox(poles, {x, kHeight + 0.3f, z - 0.45f * side}, {0.04f, 0.0f, 0.0f}, {0.0f, 0.04f, 0.0f},
                 {0.0f, 0.0f, 0.45f});  // its arm over the road
    mesh::addBox(benches, {x + 1.6f, 0.45f, z + 0.4f * side}, {0.8f, 0.0f, 0.0f}, {0.0f, 0.05f, 0.0f},
                 {0.0f, 0.0f, 0.25f});  // a bench seat
    for (int b = 0; b < 12; ++b) {      // railing bars 0.03 wide behind the pavement
      const float bx = x - 2.75f + 0.5f * float(b);
      mesh::addBox(fence, {bx, 0.6f, 6.2f * side}, {0.015f, 0.0f, 0.0f}, {0.0f, 0.6f, 0.0f}, {0.0f, 0.0f, 0.015f});
    }
    Light lamp;
    lamp.type = LightType::Point;
    lamp.position = {x, kHeight, z - 0.8f * side};
    lamp.inverseSquare = true;
    lamp.intensity = kHeight * kHeight;  // irradiance 1 on the road below it
    lamp.range = kRange;
    lamp.color = i % 3 == 0 ? glm::vec3(1.0f, 0.85f, 0.65f) : glm::vec3(1.0f, 0.95f, 0.85f);
    scene.lights.push_back(lamp);
  }
  scene.camera = Camera{.eye = {-4.0f, 6.0f, 0.0f}, .target = {12.0f, 0.0f, 0.0f}, .fovYDeg = 60.0f};  // whatever LAMPS
  return scene;
}

std::string usage() {
  std::string names;
  for (const std::string& name : builtinSceneNames()) names += (names.empty() ? "" : ", ") + name;
  return "use builtin:NAME with NAME one of " + names +
         ", builtin:courtyard[-moving]:LEVEL with LEVEL an integer in 1.." + std::to_string(kMaxCourtyardLevel) +
         " (default " + std::to_string(kDefaultCourtyardLevel) + "), or builtin:street:LAMPS with LAMPS in 1.." +
         std::to_string(kMaxStreetLamps) + " (default " + std::to_string(kDefaultStreetLamps) + ")";
}

}  // namespace

std::vector<std::string> builtinSceneNames() {
  return {"courtyard", "courtyard-moving", "street", "wires", "square", "checker", "room", "foliage", "level", "knot"};
}

namespace {
// A courtyard spec's name and level (InputError for a bad level); nullopt for other scenes.
std::optional<std::pair<std::string, int>> courtyardSpec(const std::string& nameAndLevel) {
  std::string spec = nameAndLevel;
  if (spec.rfind("builtin:", 0) == 0) spec.erase(0, 8);
  const std::size_t colon = spec.find(':');
  const std::string name = spec.substr(0, colon);
  if (name != "courtyard" && name != "courtyard-moving" && name != "street") return std::nullopt;
  int level = name == "street" ? kDefaultStreetLamps : kDefaultCourtyardLevel;
  const int maxLevel = name == "street" ? kMaxStreetLamps : kMaxCourtyardLevel;
  if (colon != std::string::npos) {
    const std::string levelText = spec.substr(colon + 1);
    const char* begin = levelText.data();
    const char* end = begin + levelText.size();
    const auto [ptr, ec] = std::from_chars(begin, end, level);
    if (levelText.empty() || ec != std::errc() || ptr != end || level < 1 || level > maxLevel) {
      throw InputError("built-in scene 'builtin:" + spec + "' has the bad level '" + levelText + "'; " + usage());
    }
  }
  return std::make_pair(name, level);
}
}  // namespace

std::optional<std::uint64_t> builtinTriangleCount(const std::string& nameAndLevel) {
  const auto courtyardLevel = courtyardSpec(nameAndLevel);
  if (!courtyardLevel || courtyardLevel->first == "street") return std::nullopt;
  const std::uint64_t l = std::uint64_t(courtyardLevel->second), s = std::min<std::uint64_t>(l, 128);
  const std::uint64_t count = 272 * l * l + 144 * s * s + 160 * l - 24 * s + 408;  // see builtin_scenes.h
  return courtyardLevel->first == "courtyard" ? count : count + 36;  // the drone
}

Scene makeBuiltinScene(const std::string& nameAndLevel) {
  if (const auto courtyardLevel = courtyardSpec(nameAndLevel)) {
    if (courtyardLevel->first == "street") return street(courtyardLevel->second);
    return courtyardLevel->first == "courtyard" ? courtyard(courtyardLevel->second) : courtyardMoving(courtyardLevel->second);
  }
  std::string spec = nameAndLevel;
  if (spec.rfind("builtin:", 0) == 0) spec.erase(0, 8);
  const std::size_t colon = spec.find(':');
  const std::string name = spec.substr(0, colon);
  const bool hasLevel = colon != std::string::npos;
  Scene (*make)() = name == "wires"     ? wires
                    : name == "square"  ? square
                    : name == "checker" ? checker
                    : name == "room"    ? room
                    : name == "foliage" ? foliageScene
                    : name == "level"   ? levelScene
                    : name == "knot"    ? knotScene
                                        : nullptr;
  if (make == nullptr) {
    throw InputError("unknown built-in scene '" + name + "' (from 'builtin:" + spec + "'); " + usage());
  }
  if (hasLevel) {
    throw InputError("built-in scene '" + name + "' takes no level (got 'builtin:" + spec + "'); " + usage());
  }
  return make();
}

}  // namespace penumbra
