// glTF node animations as rigid mesh animations (Scene::animations). The file's first animation is
// used: a mesh under animated nodes gets one key at every time any channel of its node chain has a
// key, holding the pose world(t) * world(rest)^-1 as translation + rotation (exact at the keys,
// interpolated between them by core/animation). Motions that scale or shear are not rigid: such a
// mesh stays static, with a warning.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <tiny_gltf.h>

#include "core/scene.h"

namespace penumbra::gltf {

// A node's own transform: its matrix, else translation * rotation * scale (the rest pose).
glm::dmat4 localTransform(const tinygltf::Node& node);

class NodeAnimations {
 public:
  // Reads and checks the channels of the first animation (InputError for broken accessors, times
  // that are not finite, non-negative and increasing, or outputs that do not match the times).
  NodeAnimations(const tinygltf::Model& model, const std::string& path, std::vector<std::string>& warnings);
  bool animates(int node) const;
  // The node's transform at `seconds`: its TRS with the animated parts sampled.
  glm::dmat4 localAt(const tinygltf::Node& node, int index, double seconds) const;
  // Sorted distinct key times of the channels driving any of `nodes`.
  std::vector<double> keyTimes(const std::vector<int>& nodes) const;

 private:
  struct Channel {
    int node = -1;
    int path = 0;  // 0 translation, 1 rotation, 2 scale
    bool step = false;
    std::vector<float> times, values;  // values: 3 or 4 per key
  };
  glm::dvec4 sample(const Channel& channel, double seconds) const;
  std::vector<Channel> channels_;
};

// The rigid keys of a mesh whose node chain (root first) is `chain`; nullopt and a warning naming
// `meshName` when no node of the chain is animated or the motion is not rigid. The keys move the
// mesh in scene coordinates (world minus `origin`, Scene::origin).
std::optional<std::vector<RigidKey>> rigidKeys(const tinygltf::Model& model, const NodeAnimations& animations,
                                               const std::vector<int>& chain, const glm::dvec3& origin,
                                               const std::string& meshName,
                                               std::vector<std::string>& warnings);

}  // namespace penumbra::gltf
