#include "core/animation.h"

#include <cmath>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

namespace penumbra {
namespace {

double period(const MeshAnimation& animation) {
  return animation.keys.empty() ? 0.0 : double(animation.keys.back().time);
}

void check(const Scene& scene, const MeshAnimation& animation) {
  const std::string where = "scene '" + scene.name + "': animation of mesh " + std::to_string(animation.mesh);
  if (animation.mesh >= scene.meshes.size()) throw InputError(where + " names a mesh the scene does not have");
  const Mesh& mesh = scene.meshes[animation.mesh];
  if (animation.restPositions.size() != mesh.positions.size() || animation.restNormals.size() != mesh.normals.size()) {
    throw InputError(where + " ('" + mesh.name + "') does not match the mesh's vertices");
  }
  if (animation.keys.empty()) throw InputError(where + " ('" + mesh.name + "') has no keys");
  for (std::size_t k = 0; k < animation.keys.size(); ++k) {
    const float t = animation.keys[k].time;
    if (!std::isfinite(t) || t < 0.0f || (k > 0 && !(t > animation.keys[k - 1].time))) {
      throw InputError(where + " ('" + mesh.name + "'): key times must be finite, >= 0 and increasing (key " +
                       std::to_string(k) + " is " + std::to_string(t) + ")");
    }
  }
}

}  // namespace

bool isAnimated(const Scene& scene) { return !scene.animations.empty(); }

double animationPeriod(const Scene& scene) {
  double longest = 0.0;
  for (const MeshAnimation& animation : scene.animations) longest = std::max(longest, period(animation));
  return longest;
}

glm::mat4 poseAt(const MeshAnimation& animation, double seconds) {
  const std::vector<RigidKey>& keys = animation.keys;
  if (keys.empty()) return glm::mat4(1.0f);
  const double p = period(animation);
  const float t = float(p > 0.0 ? seconds - p * std::floor(seconds / p) : 0.0);
  std::size_t k = 0;
  while (k + 1 < keys.size() && keys[k + 1].time <= t) ++k;
  glm::vec3 translation = keys[k].translation;
  glm::quat rotation = keys[k].rotation;
  if (k + 1 < keys.size()) {
    const float f = (t - keys[k].time) / (keys[k + 1].time - keys[k].time);
    translation = glm::mix(keys[k].translation, keys[k + 1].translation, f);
    rotation = glm::slerp(keys[k].rotation, keys[k + 1].rotation, f);
  }
  return glm::translate(glm::mat4(1.0f), translation) * glm::mat4_cast(glm::normalize(rotation));
}

void poseScene(Scene& scene, double seconds) {
  if (!std::isfinite(seconds)) throw InputError("animation time must be finite (got " + std::to_string(seconds) + ")");
  for (const MeshAnimation& animation : scene.animations) {
    check(scene, animation);
    const glm::mat4 pose = poseAt(animation, seconds);
    const glm::mat3 rotation(pose);  // rigid: normals turn with the same rotation
    Mesh& mesh = scene.meshes[animation.mesh];
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      mesh.positions[i] = glm::vec3(pose * glm::vec4(animation.restPositions[i], 1.0f));
      mesh.normals[i] = rotation * animation.restNormals[i];
    }
  }
}

void animateMesh(Scene& scene, std::size_t mesh, std::vector<RigidKey> keys) {
  MeshAnimation animation;
  animation.mesh = mesh;
  animation.restPositions = scene.meshes.at(mesh).positions;
  animation.restNormals = scene.meshes.at(mesh).normals;
  animation.keys = std::move(keys);
  check(scene, animation);
  scene.meshes[mesh].dynamic = true;
  scene.animations.push_back(std::move(animation));
}

}  // namespace penumbra
