// Shared by the penumbra mask's tests (test_penumbra_mask.cpp, test_mask_tiles.cpp): their
// settings and the groove, a smooth surface that rises over its receivers without a depth edge.
#pragma once
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/scene_loader.h"
#include "render_fixture.h"

namespace penumbra::test {

// Soft srt at pixels^2 on the bvh tracer, 16 samples, a 2048^2 map.
inline RenderSettings maskSettings(std::uint32_t pixels) {
  RenderSettings settings = smallSettings(pixels, 2048);
  settings.tracer = "bvh";
  settings.spp = 16;
  return settings;
}

// A ground 4 x 4 wide with a groove along z: a circular arc (radius 1, 1.9 wide, walls rising to
// 72 degrees at the rim) with smooth normals, meeting the ground without a depth edge in the map.
inline Scene grooveScene(const glm::vec3& lightAt) {
  Mesh m;
  const float radius = 1.0f, halfWidth = 0.95f, centreY = std::sqrt(radius * radius - halfWidth * halfWidth);
  std::vector<float> xs{-2.0f};
  for (int i = 0; i <= 64; ++i) xs.push_back(-halfWidth + 2.0f * halfWidth * float(i) / 64.0f);
  xs.push_back(2.0f);
  const int zs = 32;
  for (float x : xs) {
    const bool inGroove = std::abs(x) < halfWidth;
    const float y = inGroove ? centreY - std::sqrt(radius * radius - x * x) : 0.0f;
    const glm::vec3 n = inGroove ? glm::normalize(glm::vec3(-x, centreY - y, 0.0f)) : glm::vec3(0.0f, 1.0f, 0.0f);
    for (int j = 0; j <= zs; ++j) {
      m.positions.push_back({x, y, -2.0f + 4.0f * float(j) / float(zs)});
      m.normals.push_back(n);
    }
  }
  for (std::uint32_t i = 0; i + 1 < xs.size(); ++i) {
    for (std::uint32_t j = 0; j < std::uint32_t(zs); ++j) {
      const std::uint32_t a = i * (zs + 1) + j, b = a + zs + 1;
      m.indices.insert(m.indices.end(), {a, a + 1, b + 1, a, b + 1, b});
    }
  }
  Scene scene;
  scene.name = "groove";
  scene.meshes.push_back(std::move(m));
  scene.camera = Camera{.eye = {0.0f, 3.0f, 3.0f}, .target = {0.0f, 0.0f, 0.0f}};
  scene.lights.push_back(Light{.type = LightType::Disk, .position = lightAt, .direction = glm::normalize(-lightAt)});
  cleanScene(scene, "groove");
  return scene;
}

}  // namespace penumbra::test
