// Shared by the scene tests: find a scene's mesh by name, the axis-aligned boxes a mesh built of
// mesh::addBox calls (24 vertices each) is made of, and scenes made in a test from such meshes.
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "core/scene.h"

namespace penumbra::test {

// An empty mesh called `name`, for the mesh:: primitives to fill.
inline Mesh namedMesh(const std::string& name) {
  Mesh m;
  m.name = name;
  return m;
}

// A scene of `meshes`, cleaned as the loaders clean theirs.
inline Scene sceneOf(std::vector<Mesh> meshes, const std::string& name = "test") {
  Scene s;
  s.name = name;
  s.meshes = std::move(meshes);
  cleanScene(s, name);
  return s;
}

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
