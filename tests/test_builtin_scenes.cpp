#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "mesh_checks.h"

#include "core/builtin_scenes.h"
#include "core/camera.h"
#include "core/mesh_builder.h"
#include "core/scene.h"

using namespace penumbra;
using penumbra::test::Box;
using penumbra::test::boxesOf;
using penumbra::test::meshNamed;

namespace {


bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

struct Projector {
  ViewMatrices m;
  Projector(const Scene& scene, int w, int h) : m(cameraMatrices(*scene.camera, scene.bounds(), w, h)) {}
  glm::vec3 ndc(const glm::vec3& p) const {
    const glm::vec4 clip = m.viewProj * glm::vec4(p, 1.0f);
    if (clip.w <= 0.0f) return glm::vec3(1e9f);
    return glm::vec3(clip) / clip.w;
  }
  bool inView(const glm::vec3& p) const {
    const glm::vec3 n = ndc(p);
    return std::abs(n.x) <= 1.0f && std::abs(n.y) <= 1.0f && n.z >= 0.0f && n.z <= 1.0f;
  }
};

// Ray/triangle hit distance (Moller-Trumbore) with edges counted as hits; negative when missed.
float hitDistance(const glm::vec3& o, const glm::vec3& d, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::vec3 e1 = b - a, e2 = c - a, p = glm::cross(d, e2);
  const float det = glm::dot(e1, p);
  if (std::abs(det) < 1e-12f) return -1.0f;
  const glm::vec3 s = o - a;
  const float u = glm::dot(s, p) / det;
  const glm::vec3 q = glm::cross(s, e1);
  const float v = glm::dot(d, q) / det;
  if (u < -1e-5f || v < -1e-5f || u + v > 1.0f + 1e-5f) return -1.0f;
  return glm::dot(e2, q) / det;
}

// Evenly spread unit directions (Fibonacci sphere).
std::vector<glm::vec3> sphereDirections(int n) {
  std::vector<glm::vec3> dirs;
  const float golden = 3.14159265f * (3.0f - std::sqrt(5.0f));
  for (int i = 0; i < n; ++i) {
    const float y = 1.0f - 2.0f * (float(i) + 0.5f) / float(n);
    const float r = std::sqrt(1.0f - y * y);
    dirs.push_back({r * std::cos(golden * float(i)), y, r * std::sin(golden * float(i))});
  }
  return dirs;
}

// Centres and vertical thickness of the boxes of a mesh built from 24-vertex boxes.

void expectWellFormed(const Scene& scene) {
  ASSERT_FALSE(scene.meshes.empty());
  for (const Mesh& m : scene.meshes) {
    SCOPED_TRACE(scene.name + "/" + m.name);
    ASSERT_FALSE(m.indices.empty());
    ASSERT_EQ(m.indices.size() % 3, 0u);
    ASSERT_EQ(m.normals.size(), m.positions.size());
    for (const glm::vec3& p : m.positions) ASSERT_TRUE(finite(p));
    for (const glm::vec3& n : m.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-4f);
    for (const std::uint32_t i : m.indices) ASSERT_LT(i, m.positions.size());
    // Winding agrees with the vertex normals: counter-clockwise seen from the side they face.
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
      const std::uint32_t a = m.indices[t], b = m.indices[t + 1], c = m.indices[t + 2];
      const glm::vec3 face = glm::cross(m.positions[b] - m.positions[a], m.positions[c] - m.positions[a]);
      ASSERT_GT(glm::dot(face, m.normals[a] + m.normals[b] + m.normals[c]), 0.0f) << "triangle " << t / 3;
    }
  }
  // Every object has its own colour.
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
    for (std::size_t j = i + 1; j < scene.meshes.size(); ++j) {
      EXPECT_GT(glm::length(scene.meshes[i].baseColor - scene.meshes[j].baseColor), 0.02f)
          << scene.meshes[i].name << " vs " << scene.meshes[j].name;
    }
  }
  ASSERT_TRUE(scene.camera.has_value());
  EXPECT_GT(glm::length(scene.camera->target - scene.camera->eye), 0.0f);
  EXPECT_GT(scene.camera->fovYDeg, 0.0f);
  EXPECT_LT(scene.camera->fovYDeg, 180.0f);
  ASSERT_EQ(scene.lights.size(), scene.name == "builtin:street" ? scene.lights.size() : 1u);  // the street: many
  ASSERT_FALSE(scene.lights.empty());
  for (const Light& light : scene.lights) {
    EXPECT_NEAR(glm::length(light.direction), 1.0f, 1e-5f);
    EXPECT_TRUE(finite(light.position));
  }
}

}  // namespace

TEST(BuiltinScenes, ListsTheTenScenes) {
  EXPECT_EQ(builtinSceneNames(), (std::vector<std::string>{"courtyard", "courtyard-moving", "street", "wires", "square",
                                                           "checker", "room", "foliage", "level", "knot"}));
}

TEST(BuiltinScenes, EachIsWellFormedAndSurvivesCleaning) {
  for (const std::string& name : builtinSceneNames()) {
    Scene scene = makeBuiltinScene(name);
    EXPECT_EQ(scene.name, "builtin:" + name);
    expectWellFormed(scene);
    const std::size_t before = scene.triangleCount();
    const std::size_t meshes = scene.meshes.size();
    cleanScene(scene, "builtin:" + name);
    EXPECT_EQ(scene.triangleCount(), before) << name;
    EXPECT_EQ(scene.meshes.size(), meshes) << name;
    EXPECT_TRUE(scene.warnings.empty()) << name << ": " << scene.warnings.front();
  }
  // The "builtin:" prefix is accepted too.
  EXPECT_EQ(makeBuiltinScene("builtin:square").name, "builtin:square");
}

TEST(BuiltinScenes, CourtyardTriangleCountGrowsWithLevelAsDocumented) {
  // The counts documented in core/builtin_scenes.h.
  const std::vector<std::pair<int, std::size_t>> documented = {{1, 960}, {8, 28120}, {32, 430744}};
  std::size_t previous = 0;
  for (const auto& [level, count] : documented) {
    const Scene s = makeBuiltinScene("courtyard:" + std::to_string(level));
    EXPECT_EQ(s.triangleCount(), count) << "level " << level;
    EXPECT_GT(s.triangleCount(), previous);
    previous = s.triangleCount();
  }
  // Counted without building (the memory estimate refuses huge levels before they are built).
  for (const char* spec : {"courtyard:1", "courtyard:8", "courtyard:32", "courtyard:130", "builtin:courtyard-moving:3", "courtyard"}) {
    EXPECT_EQ(builtinTriangleCount(spec), makeBuiltinScene(spec).triangleCount()) << spec;
  }
  EXPECT_EQ(builtinTriangleCount("courtyard:512"), 73741720u);  // as documented
  EXPECT_FALSE(builtinTriangleCount("square").has_value());
  EXPECT_THROW(builtinTriangleCount("courtyard:0"), InputError);
  const std::size_t defaultCount = makeBuiltinScene("courtyard").triangleCount();
  EXPECT_EQ(defaultCount, makeBuiltinScene("courtyard:8").triangleCount());
  EXPECT_GE(defaultCount, 10000u);
  EXPECT_LT(defaultCount, 100000u);
  expectWellFormed(makeBuiltinScene("courtyard:1"));
}

// The street: one point lamp per post, of range 7, lighting the road below at irradiance 1; the
// camera the same for every count; counts outside 1..256 refused with the syntax.
TEST(BuiltinScenes, StreetHasALampPerPost) {
  for (int lamps : {1, 4, 16, 64}) {
    Scene s = makeBuiltinScene("street:" + std::to_string(lamps));
    ASSERT_EQ(s.lights.size(), std::size_t(lamps));
    for (const Light& l : s.lights) {
      EXPECT_EQ(l.type, LightType::Point);
      EXPECT_TRUE(l.inverseSquare);
      EXPECT_FLOAT_EQ(l.range, 7.0f);
      EXPECT_NEAR(l.intensity / (l.position.y * l.position.y), 1.0f, 1e-6f);
    }
    EXPECT_EQ(s.camera->eye, makeBuiltinScene("street:1").camera->eye);
    expectWellFormed(s);
    const std::size_t count = s.triangleCount();
    cleanScene(s, "builtin:street");
    EXPECT_EQ(s.triangleCount(), count);
  }
  EXPECT_EQ(makeBuiltinScene("street").lights.size(), 16u);
  for (const char* bad : {"street:0", "street:257", "street:x"}) {
    try {
      makeBuiltinScene(bad);
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("builtin:street:LAMPS"), std::string::npos) << e.what();
    }
  }
}

TEST(BuiltinScenes, CourtyardLevel64HasOverAMillionCleanTriangles) {
  Scene s = makeBuiltinScene("courtyard:64");
  const std::size_t count = s.triangleCount();
  EXPECT_EQ(count, 1713048u);  // documented
  EXPECT_GE(count, 1000000u);
  cleanScene(s, "builtin:courtyard:64");
  EXPECT_EQ(s.triangleCount(), count);
}

TEST(BuiltinScenes, CourtyardSphereAtItsResolutionCapKeepsItsPoleTriangles) {
  // The courtyard's sphere stops refining at LEVEL 128 (1536 x 768); its pole triangles must still
  // pass cleanScene's area test at the courtyard's extent, for every higher LEVEL up to 512.
  Scene s;
  s.meshes.resize(2);
  mesh::addSphere(s.meshes[0], {2.0f, 1.2f, 1.5f}, 1.2f, 12 * 128, 6 * 128);
  mesh::addQuad(s.meshes[1], {-12.0f, 0.0f, -12.0f}, {12.0f, 0.0f, -12.0f}, {12.0f, 0.0f, 12.0f},
                {-12.0f, 0.0f, 12.0f}, {0.0f, 1.0f, 0.0f});
  const std::size_t before = s.triangleCount();
  EXPECT_EQ(s.meshes[0].triangleCount(), mesh::sphereTriangles(12 * 128, 6 * 128));
  cleanScene(s, "sphere");
  EXPECT_EQ(s.triangleCount(), before);
}

TEST(BuiltinScenes, CourtyardHasTheListedObjectsAtTheirScales) {
  const Scene s = makeBuiltinScene("courtyard");
  const float radius = s.bounds().radius();
  for (const char* name : {"ground", "sphere", "torus", "fence", "wire_posts", "wires"}) meshNamed(s, name);
  const auto columns = std::count_if(s.meshes.begin(), s.meshes.end(),
                                     [](const Mesh& m) { return m.name.rfind("column_", 0) == 0; });
  EXPECT_GE(columns, 4);
  EXPECT_LE(columns, 6);
  const auto boxes =
      std::count_if(s.meshes.begin(), s.meshes.end(), [](const Mesh& m) { return m.name.rfind("box_", 0) == 0; });
  EXPECT_GE(boxes, 2);

  // Fence: ~20 bars 0.01..0.02 of the radius wide (plus one rail).
  const std::vector<Box> fence = boxesOf(meshNamed(s, "fence"));
  EXPECT_GE(fence.size(), 19u);
  for (std::size_t i = 0; i + 1 < fence.size(); ++i) {
    const float width = std::min(fence[i].hi.x - fence[i].lo.x, fence[i].hi.z - fence[i].lo.z);
    EXPECT_GE(width, 0.01f * radius);
    EXPECT_LE(width, 0.02f * radius);
  }
  // Wires: 5..8 horizontal, 0.002..0.004 of the radius thick, above the ground.
  const std::vector<Box> wires = boxesOf(meshNamed(s, "wires"));
  EXPECT_GE(wires.size(), 5u);
  EXPECT_LE(wires.size(), 8u);
  for (const Box& w : wires) {
    const float thickness = w.hi.y - w.lo.y;
    EXPECT_GE(thickness, 0.002f * radius);
    EXPECT_LE(thickness, 0.004f * radius);
    EXPECT_GT(w.lo.y, 1.0f);
    EXPECT_GT(std::max(w.hi.x - w.lo.x, w.hi.z - w.lo.z), 0.5f * radius);  // long
  }
}

TEST(BuiltinScenes, CourtyardShadowsFallOnTheGroundInView) {
  const Scene s = makeBuiltinScene("courtyard");
  const Light& light = s.lights[0];
  EXPECT_EQ(light.type, LightType::Disk);
  EXPECT_EQ(light.size, 0.0f);
  const Bounds bounds = s.bounds();
  EXPECT_GT(light.position.y, 2.0f * bounds.hi.y);
  const glm::vec3 expected = glm::normalize(bounds.center() - light.position);
  EXPECT_NEAR(glm::dot(light.direction, expected), 1.0f, 1e-6f);

  const Projector view(s, 256, 256);
  const Mesh& ground = meshNamed(s, "ground");
  Bounds groundBounds;
  for (const glm::vec3& p : ground.positions) {
    groundBounds.extend(p);
    EXPECT_GT(glm::dot(p - light.position, light.direction), 0.0f);  // in front of the disk
  }
  for (const Mesh& m : s.meshes) {
    if (&m == &ground) continue;
    SCOPED_TRACE(m.name);
    for (const glm::vec3& p : m.positions) {
      ASSERT_TRUE(view.inView(p)) << p.x << "," << p.y << "," << p.z;
      if (p.y < 1e-4f) continue;
      // Where the light ray through p meets the ground.
      const glm::vec3 shadow = light.position + (p - light.position) * (light.position.y / (light.position.y - p.y));
      ASSERT_GT(shadow.x, groundBounds.lo.x);
      ASSERT_LT(shadow.x, groundBounds.hi.x);
      ASSERT_GT(shadow.z, groundBounds.lo.z);
      ASSERT_LT(shadow.z, groundBounds.hi.z);
      ASSERT_TRUE(view.inView(shadow)) << shadow.x << "," << shadow.z;
    }
  }
}

TEST(BuiltinScenes, WiresAreThinnerThanHalfAShadowMapTexel) {
  const Scene s = makeBuiltinScene("wires");
  const float texel = 2.0f * s.bounds().radius() / 2048.0f;
  EXPECT_LE(meshNamed(s, "ground").triangleCount(), 8u);
  const std::vector<Box> wires = boxesOf(meshNamed(s, "wires"));
  EXPECT_GE(wires.size(), 16u);
  for (const Box& w : wires) {
    EXPECT_LT(w.hi.y - w.lo.y, 0.5f * texel);
    EXPECT_NEAR(w.centre().y, 1.0f, 0.1f);
    // Not aligned with the axes: a long box turned by ~7 degrees spans both x and z.
    const glm::vec3 extent = w.hi - w.lo;
    EXPECT_GT(std::min(extent.x, extent.z), 0.2f);
  }
  const Light& light = s.lights[0];
  EXPECT_EQ(light.type, LightType::Directional);
  EXPECT_NEAR(glm::dot(light.direction, glm::normalize(glm::vec3(0.15f, -1.0f, 0.1f))), 1.0f, 1e-6f);
}

TEST(BuiltinScenes, WiresAndTheirShadowsAreInViewAndWideEnough) {
  const Scene s = makeBuiltinScene("wires");
  const Light& light = s.lights[0];
  const Projector view(s, 256, 256);
  const std::vector<Box> wires = boxesOf(meshNamed(s, "wires"));
  int wiresInView = 0, shadowsInView = 0;
  for (const Box& w : wires) {
    const glm::vec3 mid = w.centre();
    const glm::vec3 shadow = mid + light.direction * (mid.y / -light.direction.y);
    wiresInView += view.inView(mid);
    shadowsInView += view.inView(shadow);
  }
  EXPECT_GE(wiresInView, 2);
  EXPECT_GE(shadowsInView, 2);

  // A wire's shadow (>= 0.012 across on the ground) covers >= 1.5 pixels at the view centre,
  // for wires of either direction.
  const glm::vec3 centre = s.camera->target;
  const auto pixel = [&](const glm::vec3& p) { return 128.0f * glm::vec2(view.ndc(p)); };
  // The wires run within 7 degrees of x and z, so their shadows are about 0.012 across x or z.
  for (const glm::vec3 across : {glm::vec3(1.0f, 0.0f, 0.0f), glm::vec3(0.0f, 0.0f, 1.0f)}) {
    EXPECT_GE(glm::length(pixel(centre + 0.012f * across) - pixel(centre)), 1.5f) << across.x;
  }
  EXPECT_LT(std::abs(centre.y), 1.0f);
}

TEST(BuiltinScenes, SquareIsExactlyAsDocumented) {
  const Scene s = makeBuiltinScene("square");
  ASSERT_EQ(s.meshes.size(), 2u);
  const Mesh& ground = meshNamed(s, "ground");
  const Mesh& occluder = meshNamed(s, "occluder");
  ASSERT_EQ(ground.triangleCount(), 2u);
  ASSERT_EQ(occluder.triangleCount(), 2u);
  const auto corners = [](const Mesh& m) {
    std::set<std::array<float, 3>> c;
    for (const glm::vec3& p : m.positions) c.insert({p.x, p.y, p.z});
    return c;
  };
  EXPECT_EQ(corners(ground), (std::set<std::array<float, 3>>{{-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5}}));
  EXPECT_EQ(corners(occluder), (std::set<std::array<float, 3>>{{-1, 1, -1}, {1, 1, -1}, {1, 1, 1}, {-1, 1, 1}}));
  for (const Mesh* m : {&ground, &occluder}) {
    for (const glm::vec3& n : m->normals) EXPECT_EQ(n, glm::vec3(0.0f, 1.0f, 0.0f));
  }
  const Light& light = s.lights[0];
  EXPECT_EQ(light.type, LightType::Directional);
  const glm::vec3 dir = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
  EXPECT_NEAR(glm::length(light.direction - dir), 0.0f, 1e-7f);

  // The analytic shadow is the occluder moved by (0.3, 0.2): ground points inside it have a ray
  // towards the light that hits an occluder triangle; the whole shadow and occluder are in view.
  const Projector view(s, 256, 256);
  for (float x = -0.65f; x < 1.3f; x += 0.1f) {
    for (float z = -0.75f; z < 1.2f; z += 0.1f) {
      const glm::vec3 p{x, 0.0f, z};
      const auto& q = occluder.positions;
      const auto& idx = occluder.indices;
      const bool hit = hitDistance(p, -dir, q[idx[0]], q[idx[1]], q[idx[2]]) > 0.0f ||
                       hitDistance(p, -dir, q[idx[3]], q[idx[4]], q[idx[5]]) > 0.0f;
      EXPECT_TRUE(hit) << x << "," << z;
    }
  }
  EXPECT_LT(hitDistance({1.4f, 0.0f, 0.2f}, -dir, occluder.positions[occluder.indices[0]],
                        occluder.positions[occluder.indices[1]], occluder.positions[occluder.indices[2]]) +
                hitDistance({1.4f, 0.0f, 0.2f}, -dir, occluder.positions[occluder.indices[3]],
                            occluder.positions[occluder.indices[4]], occluder.positions[occluder.indices[5]]),
            0.0f);
  for (const glm::vec3& c : occluder.positions) {
    EXPECT_TRUE(view.inView(c));
    EXPECT_TRUE(view.inView(c + glm::vec3(0.3f, -1.0f, 0.2f)));  // shadow corner
  }
  EXPECT_EQ(s.camera->eye, glm::vec3(0.0f, 9.0f, 9.0f));
  EXPECT_EQ(s.camera->target, glm::vec3(0.3f, 0.0f, 0.2f));
  EXPECT_EQ(s.camera->fovYDeg, 45.0f);
}

TEST(BuiltinScenes, RoomIsClosedAroundItsPointLight) {
  const Scene s = makeBuiltinScene("room");
  const Light& light = s.lights[0];
  EXPECT_EQ(light.type, LightType::Point);
  const Bounds b = s.bounds();
  EXPECT_EQ(b.lo, glm::vec3(-5.0f, 0.0f, -5.0f));
  EXPECT_EQ(b.hi, glm::vec3(5.0f, 4.0f, 5.0f));
  for (int k = 0; k < 3; ++k) {
    EXPECT_GT(light.position[k], b.lo[k] + 1.0f);
    EXPECT_LT(light.position[k], b.hi[k] - 1.0f);
  }
  const Mesh& room = meshNamed(s, "room");
  for (std::size_t i = 0; i < room.positions.size(); ++i) {
    EXPECT_GT(glm::dot(room.normals[i], light.position - room.positions[i]), 0.0f);  // inward
  }
  // Every ray from the light hits the room's walls.
  for (const glm::vec3& d : sphereDirections(4000)) {
    bool hit = false;
    for (std::size_t t = 0; t < room.indices.size() && !hit; t += 3) {
      hit = hitDistance(light.position, d, room.positions[room.indices[t]], room.positions[room.indices[t + 1]],
                        room.positions[room.indices[t + 2]]) > 0.0f;
    }
    ASSERT_TRUE(hit) << d.x << "," << d.y << "," << d.z;
  }
  // Casters' shadows land on several faces of the room (so several cube-map faces matter): the
  // face where the ray from the light through a caster's triangle centre leaves the room.
  std::set<int> shadowed;
  for (const Mesh& m : s.meshes) {
    if (&m == &room) continue;
    for (const glm::vec3& p : m.positions) {
      for (int k = 0; k < 3; ++k) EXPECT_TRUE(p[k] >= b.lo[k] && p[k] <= b.hi[k]) << m.name;
    }
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
      const glm::vec3 p =
          (m.positions[m.indices[t]] + m.positions[m.indices[t + 1]] + m.positions[m.indices[t + 2]]) / 3.0f;
      if (p.y <= 1e-4f || p.y >= 4.0f - 1e-4f) continue;  // touching floor or ceiling
      const glm::vec3 d = p - light.position;
      float exit = 1e30f;
      int face = -1;
      for (int k = 0; k < 3; ++k) {
        if (d[k] == 0.0f) continue;
        const float t = ((d[k] > 0.0f ? b.hi[k] : b.lo[k]) - light.position[k]) / d[k];
        if (t < exit) {
          exit = t;
          face = 2 * k + (d[k] > 0.0f);
        }
      }
      if (exit > 1.0f) shadowed.insert(face);
    }
  }
  EXPECT_GE(shadowed.size(), 4u);
  // The camera stands inside, looking across at the casters.
  ASSERT_TRUE(s.camera.has_value());
  for (int k = 0; k < 3; ++k) {
    EXPECT_GT(s.camera->eye[k], b.lo[k]);
    EXPECT_LT(s.camera->eye[k], b.hi[k]);
  }
  const Projector view(s, 256, 256);
  for (const char* caster : {"pillar", "ball"}) {
    const Mesh& m = meshNamed(s, caster);
    Bounds cb;
    for (const glm::vec3& p : m.positions) cb.extend(p);
    EXPECT_TRUE(view.inView(cb.center())) << caster;
  }
}

TEST(BuiltinScenes, RejectsUnknownNamesAndBadLevels) {
  for (const std::string bad : {"nope", "", "Courtyard", "courtyard:0", "courtyard:513", "courtyard:abc",
                                "courtyard:", "courtyard:8x", "courtyard:-1", "courtyard:8:9", "courtyard: 8",
                                "square:3", "wires:8", "room:", "builtin:nope", "knot:2", "foliage:"}) {
    try {
      makeBuiltinScene(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      const std::string message = e.what();
      for (const char* needed : {"courtyard", "wires", "square", "room", "foliage", "level", "knot", "LEVEL", "1..512"}) {
        EXPECT_NE(message.find(needed), std::string::npos) << bad << ": " << message;
      }
    }
  }
}
