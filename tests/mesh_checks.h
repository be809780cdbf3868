// Shared by the scene tests: find a scene's mesh by name, the axis-aligned boxes a mesh built of
// mesh::addBox calls (24 vertices each) is made of, and scenes made in a test from such meshes.
#pragma once
#include <cstdio>
#include <fstream>
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

// Writes `meshes` as one Wavefront OBJ (an object per mesh, positions and normals) with `offset`
// added in double and 6 decimals, as georeferenced tiles and exporters write them.
inline void writeObj(const std::vector<Mesh>& meshes, const std::string& path, const glm::dvec3& offset = glm::dvec3(0.0)) {
  std::ofstream out(path);
  std::size_t first = 1;
  char line[160];
  for (const Mesh& m : meshes) {
    out << "o " << (m.name.empty() ? "mesh" : m.name) << "\n";
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
      const glm::dvec3 w = offset + glm::dvec3(m.positions[i]);
      const glm::vec3 n = i < m.normals.size() ? m.normals[i] : glm::vec3(0.0f, 1.0f, 0.0f);
      std::snprintf(line, sizeof line, "v %.6f %.6f %.6f\nvn %.6f %.6f %.6f\n", w.x, w.y, w.z, n.x, n.y, n.z);
      out << line;
    }
    for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3) {
      out << "f";
      for (std::size_t k = 0; k < 3; ++k) out << " " << first + m.indices[i + k] << "//" << first + m.indices[i + k];
      out << "\n";
    }
    first += m.positions.size();
  }
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
