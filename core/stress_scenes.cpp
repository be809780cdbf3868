#include "core/stress_scenes.h"

#include <array>
#include <cmath>
#include <numbers>
#include <random>

#include "core/mesh_builder.h"

namespace penumbra {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

Mesh& addMesh(Scene& scene, std::string name, const glm::vec3& color) {
  Mesh& m = scene.meshes.emplace_back();
  m.name = std::move(name);
  m.baseColor = color;
  return m;
}

// Disk light with no extent aimed at the bounds centre.
void addPointLikeDisk(Scene& scene, const glm::vec3& position) {
  Light light;
  light.type = LightType::Disk;
  light.position = position;
  light.direction = glm::normalize(scene.bounds().center() - position);
  light.size = 0.0f;
  scene.lights.push_back(light);
}

void setCamera(Scene& scene, const glm::vec3& eye, const glm::vec3& target, float fovYDeg) {
  Camera camera;
  camera.eye = eye;
  camera.target = target;
  camera.fovYDeg = fovYDeg;
  scene.camera = camera;
}

// Uniform floats in [0, 1) from mt19937's standard-defined sequence (24 high bits), so every
// platform builds the same scene.
class Random {
 public:
  explicit Random(std::uint32_t seed) : engine_(seed) {}
  float uniform() { return float(engine_() >> 8) * (1.0f / 16777216.0f); }
  float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
  glm::vec3 unitVector() {
    const float y = uniform(-1.0f, 1.0f), phi = uniform(0.0f, 2.0f * kPi);
    const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
    return {r * std::cos(phi), y, r * std::sin(phi)};
  }
  glm::vec3 inBall(float radius) {
    for (;;) {
      const glm::vec3 p{uniform(-1.0f, 1.0f), uniform(-1.0f, 1.0f), uniform(-1.0f, 1.0f)};
      if (glm::dot(p, p) <= 1.0f) return radius * p;
    }
  }

 private:
  std::mt19937 engine_;
};

// Axis-aligned box between two corners whose faces lie exactly on the corners' coordinates (a
// centre and half sizes would round them), so touching and coplanar faces are exact. 24 vertices,
// faces in mesh::addBox's order.
void addBoxBetween(Mesh& m, const glm::vec3& lo, const glm::vec3& hi) {
  for (int axis = 0; axis < 3; ++axis) {
    const int s = (axis + 1) % 3, t = (axis + 2) % 3;
    for (const bool high : {true, false}) {
      const auto corner = [&](bool sHigh, bool tHigh) {
        glm::vec3 p;
        p[axis] = high ? hi[axis] : lo[axis];
        p[s] = sHigh ? hi[s] : lo[s];
        p[t] = tHigh ? hi[t] : lo[t];
        return p;
      };
      glm::vec3 facing(0.0f);
      facing[axis] = high ? 1.0f : -1.0f;
      mesh::addQuad(m, corner(false, false), corner(true, false), corner(true, true), corner(false, true), facing);
    }
  }
}

}  // namespace

Scene foliageScene() {
  Scene scene;
  scene.name = "builtin:foliage";
  mesh::addCylinder(addMesh(scene, "trunk", {0.40f, 0.27f, 0.16f}), {0.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f}, 0.11f, 16);

  // Six side branches spiralling up the trunk (golden-angle azimuths) and a leader on top.
  struct Branch {
    glm::vec3 start, end;
  };
  std::vector<Branch> branches;
  for (int k = 0; k < 6; ++k) {
    const float azimuth = glm::radians(137.5f * float(k));
    const glm::vec3 start{0.0f, 1.05f + 0.17f * float(k), 0.0f};
    const glm::vec3 dir = glm::normalize(glm::vec3(std::cos(azimuth), 0.55f + 0.08f * float(k), std::sin(azimuth)));
    branches.push_back({start, start + (1.15f - 0.07f * float(k)) * dir});
  }
  branches.push_back({{0.0f, 1.9f, 0.0f}, {0.08f, 2.9f, -0.05f}});
  Mesh& wood = addMesh(scene, "branches", {0.47f, 0.33f, 0.20f});
  for (const Branch& b : branches) mesh::addCylinder(wood, b.start, b.end, 0.035f, 8);

  // Leaves around the outer 70 % of each branch, within 0.32 of its axis, turned at random.
  Mesh& leaves = addMesh(scene, "leaves", {0.24f, 0.55f, 0.18f});
  Random random(17);
  for (int i = 0; i < 7000; ++i) {
    const Branch& b = branches[std::size_t(i) % branches.size()];
    const glm::vec3 centre = b.start + random.uniform(0.3f, 1.0f) * (b.end - b.start) + random.inBall(0.32f);
    const glm::vec3 n = random.unitVector();
    const glm::vec3 helper = std::abs(n.y) < 0.9f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
    const glm::vec3 e1 = glm::normalize(glm::cross(helper, n)), e2 = glm::cross(n, e1);
    const float spin = random.uniform(0.0f, 2.0f * kPi);
    const float halfLength = random.uniform(0.03f, 0.05f), halfWidth = 0.55f * halfLength;
    const glm::vec3 along = halfLength * (std::cos(spin) * e1 + std::sin(spin) * e2);
    const glm::vec3 across = halfWidth * (-std::sin(spin) * e1 + std::cos(spin) * e2);
    mesh::addQuad(leaves, centre - along - across, centre + along - across, centre + along + across,
                  centre - along + across, n);
  }

  addPointLikeDisk(scene, {3.0f, 6.5f, 2.0f});
  setCamera(scene, {1.0f, 2.5f, 4.0f}, {0.15f, 2.15f, -0.05f}, 45.0f);
  return scene;
}

Scene levelScene() {
  Scene scene;
  scene.name = "builtin:level";
  // The long floor slab and a patch slab whose top lies in the same plane, overlapping it.
  addBoxBetween(addMesh(scene, "floor", {0.62f, 0.60f, 0.56f}), {-6.0f, -0.3f, -10.0f}, {6.0f, 0.0f, 10.0f});
  addBoxBetween(addMesh(scene, "floor_patch", {0.55f, 0.50f, 0.62f}), {0.1f, -0.1f, 3.0f}, {1.6f, 0.0f, 7.0f});
  // A decal lying exactly on the floor top.
  mesh::addQuad(addMesh(scene, "decal", {0.80f, 0.70f, 0.25f}), {-1.1f, 0.0f, 1.0f}, {-0.1f, 0.0f, 1.0f},
                {-0.1f, 0.0f, 2.0f}, {-1.1f, 0.0f, 2.0f}, {0.0f, 1.0f, 0.0f});

  // Slatted wall at z = 0: five boards with four vertical cracks narrower than a shadow-map texel,
  // close to the light's plane x = 0 so light passes through them at this board thickness.
  const std::array<float, 4> crackX = {-0.75f, -0.25f, 0.25f, 0.75f};
  const std::array<float, 4> crackWidth = {0.004f, 0.003f, 0.005f, 0.0035f};
  Mesh& boards = addMesh(scene, "wall_boards", {0.58f, 0.42f, 0.28f});
  float left = -3.0f;
  for (std::size_t i = 0; i <= crackX.size(); ++i) {
    const float right = i < crackX.size() ? crackX[i] - 0.5f * crackWidth[i] : 3.0f;
    addBoxBetween(boards, {left, 0.0f, -0.025f}, {right, 2.5f, 0.025f});
    if (i < crackX.size()) left = crackX[i] + 0.5f * crackWidth[i];
  }
  // Posts at both ends and a lintel on top: the boards and lintel end on the posts' faces.
  Mesh& frame = addMesh(scene, "wall_frame", {0.36f, 0.30f, 0.26f});
  addBoxBetween(frame, {-3.3f, 0.0f, -0.15f}, {-3.0f, 2.9f, 0.15f});
  addBoxBetween(frame, {3.0f, 0.0f, -0.15f}, {3.3f, 2.9f, 0.15f});
  addBoxBetween(frame, {-3.0f, 2.5f, -0.1f}, {3.0f, 2.9f, 0.1f});
  // A partition ending on the back face of the rightmost board.
  addBoxBetween(addMesh(scene, "partition", {0.70f, 0.68f, 0.60f}), {2.0f, 0.0f, 0.025f}, {2.2f, 2.5f, 6.0f});
  // A wall thinner than a texel, turned 35 degrees, in front of the slats.
  mesh::addYawedBox(addMesh(scene, "thin_wall", {0.30f, 0.50f, 0.60f}), {-3.5f, 0.9f, -4.5f}, {1.0f, 0.9f, 0.002f},
                    35.0f);
  // Colonnade: three pillars ending under the middle of a beam.
  Mesh& colonnade = addMesh(scene, "colonnade", {0.78f, 0.76f, 0.70f});
  for (const float z : {-8.0f, -5.0f, -2.0f}) addBoxBetween(colonnade, {4.35f, 0.0f, z - 0.15f}, {4.65f, 3.0f, z + 0.15f});
  addBoxBetween(colonnade, {4.2f, 3.0f, -8.6f}, {4.8f, 3.3f, -1.4f});
  // Back wall of the room behind the slats, facing the light: most light lines run up it.
  addBoxBetween(addMesh(scene, "back_wall", {0.66f, 0.56f, 0.50f}), {-4.0f, 0.0f, 6.0f}, {4.0f, 3.0f, 6.2f});

  // Low and far along -z: grazing on the floor, in line with the cracks.
  addPointLikeDisk(scene, {0.0f, 3.0f, -24.0f});
  setCamera(scene, {-3.2f, 4.2f, -1.2f}, {0.6f, 0.6f, 5.5f}, 55.0f);
  return scene;
}

Scene knotScene() {
  Scene scene;
  scene.name = "builtin:knot";
  constexpr int kAlong = 512, kAround = 32;
  constexpr float kTube = 0.4f;
  // (2, 3) torus knot in the xz plane, lifted and tilted a little so strands overhang each other.
  const auto curve = [](float t) {
    const float r = 1.6f + 0.7f * std::cos(3.0f * t);
    return glm::vec3(r * std::cos(2.0f * t), 0.7f * std::sin(3.0f * t), r * std::sin(2.0f * t));
  };
  const auto tangent = [&](float t) { return glm::normalize(curve(t + 1e-3f) - curve(t - 1e-3f)); };

  // A frame transported along the curve (projection of the previous normal), then twisted back by
  // the angle it is off after one lap, spread evenly, so the tube closes without a seam.
  std::vector<glm::vec3> centre(kAlong), along(kAlong), normal(kAlong);
  for (int i = 0; i < kAlong; ++i) {
    const float t = 2.0f * kPi * float(i) / float(kAlong);
    centre[i] = curve(t);
    along[i] = tangent(t);
    const glm::vec3 previous = i == 0 ? glm::vec3(0.0f, 1.0f, 0.0f) : normal[i - 1];
    normal[i] = glm::normalize(previous - glm::dot(previous, along[i]) * along[i]);
  }
  const glm::vec3 back = glm::normalize(normal[kAlong - 1] - glm::dot(normal[kAlong - 1], along[0]) * along[0]);
  const float offBy = std::atan2(glm::dot(glm::cross(back, normal[0]), along[0]), glm::dot(back, normal[0]));

  Mesh& m = addMesh(scene, "knot", {0.80f, 0.52f, 0.20f});
  for (int i = 0; i < kAlong; ++i) {
    const float twist = offBy * float(i) / float(kAlong);
    const glm::vec3 u = std::cos(twist) * normal[i] + std::sin(twist) * glm::cross(along[i], normal[i]);
    const glm::vec3 v = glm::cross(along[i], u);
    for (int j = 0; j < kAround; ++j) {
      const float a = 2.0f * kPi * float(j) / float(kAround);
      const glm::vec3 n = glm::normalize(std::cos(a) * u + std::sin(a) * v);
      m.positions.push_back(centre[i] + kTube * n);
      m.normals.push_back(n);
    }
  }
  const auto at = [](int i, int j) { return std::uint32_t((i % kAlong) * kAround + j % kAround); };
  for (int i = 0; i < kAlong; ++i) {
    for (int j = 0; j < kAround; ++j) {
      // d/di x d/dj points inward for (u, v, along), so the quad runs j first.
      m.indices.insert(m.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  }

  // From the side, so upper strands throw their shadows across lower ones.
  addPointLikeDisk(scene, {4.5f, 3.5f, 2.0f});
  setCamera(scene, {0.5f, 3.2f, 6.4f}, {0.0f, 0.0f, 0.0f}, 45.0f);
  return scene;
}

}  // namespace penumbra
