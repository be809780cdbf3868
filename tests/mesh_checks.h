// Shared by the scene tests: find a scene's mesh by name, and the axis-aligned boxes a mesh built
// of mesh::addBox calls (24 vertices each) is made of.
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "core/scene.h"

namespace penumbra::test {

inline const Mesh& meshNamed(const Scene& scene, const std::string& name) {
  for (const Mesh& m : scene.meshes) {
    if (m.name == name) return m;
  }
  ADD_FAILURE() << scene.name << " has no mesh '" << name << "'";
  static const Mesh none;
  return none;
}

struct Box {
  glm::vec3 lo{1e30f}, hi{-1e30f};
  glm::vec3 centre() const { return 0.5f * (lo + hi); }
};

inline std::vector<Box> boxesOf(const Mesh& m) {
  EXPECT_EQ(m.positions.size() % 24, 0u) << m.name;
  std::vector<Box> boxes(m.positions.size() / 24);
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    boxes[i / 24].lo = glm::min(boxes[i / 24].lo, m.positions[i]);
    boxes[i / 24].hi = glm::max(boxes[i / 24].hi, m.positions[i]);
  }
  return boxes;
}

}  // namespace penumbra::test
