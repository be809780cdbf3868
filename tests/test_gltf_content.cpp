// glTF content tests: what a file holds arrives in the Scene - node transforms, animations,
// lights and cameras, models far from the world origin, every accessor form and the extensions
// optimizers write, GLB and data URIs, deep hierarchies. Bad input: test_loaders.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "core/animation.h"
#include "gltf_writer.h"

using namespace loader_test;
using penumbra::LightType;

namespace {

// The triangle under a parent node that turns about y (rotation channel) while the child slides
// along x (translation channel, keys at other times): one rigid animation with the union of keys.
json animatedDoc(Bytes& bin, const char* childPath = "translation") {
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["nodes"] = {{{"name", "parent"}, {"translation", {0.0, 1.0, 0.0}}, {"children", {1}}},
                  {{"name", "child"}, {"mesh", 0}, {"translation", {1.0, 0.0, 0.0}}}};
  doc["scenes"] = {{{"nodes", {0}}}};
  const float s = std::sqrt(0.5f);
  const int rotT = addFloats(doc, bin, {0.0f, 2.0f}, "SCALAR", 2);
  const int rotV = addFloats(doc, bin, {0, 0, 0, 1, 0, s, 0, s}, "VEC4", 2);  // 0 -> 90 degrees about y
  const int moveT = addFloats(doc, bin, {0.0f, 1.0f, 3.0f}, "SCALAR", 3);
  const bool scale = std::string(childPath) == "scale";
  const int moveV = addFloats(
      doc, bin, scale ? std::vector<float>{1, 1, 1, 2, 2, 2, 1, 1, 1} : std::vector<float>{1, 0, 0, 3, 0, 0, 3, 0, 0},
      "VEC3", 3);
  doc["animations"] = {{{"name", "fly"},
                        {"samplers",
                         {{{"input", rotT}, {"output", rotV}, {"interpolation", "LINEAR"}},
                          {{"input", moveT}, {"output", moveV}, {"interpolation", "LINEAR"}}}},
                        {"channels",
                         {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "rotation"}}}},
                          {{"sampler", 1}, {"target", {{"node", 1}, {"path", childPath}}}}}}}};
  return doc;
}

}  // namespace

TEST(GltfLoader, ExternalBinWithNodeTransform) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["nodes"][0]["translation"] = {1.0, 2.0, 3.0};
  doc["nodes"][0]["scale"] = {2.0, 2.0, 2.0};
  const Scene s = penumbra::loadScene(writeGltf(dir, doc, bin));
  EXPECT_EQ(s.name, "model");
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.triangleCount(), 1u);
  EXPECT_EQ(s.meshes[0].name, "tri/0");
  EXPECT_TRUE(near(s.meshes[0].positions[0], {1, 2, 3}));
  EXPECT_TRUE(near(s.meshes[0].positions[1], {3, 2, 3}));
  EXPECT_TRUE(near(s.meshes[0].positions[2], {1, 4, 3}));
  EXPECT_TRUE(near(s.meshes[0].baseColor, {0.25f, 0.5f, 0.75f}));
  EXPECT_TRUE(near(s.meshes[0].normals[0], {0, 0, 1}));  // computed by cleanScene
  EXPECT_FALSE(s.camera.has_value());
}

TEST(GltfLoader, NodeAnimationBecomesARigidMeshAnimation) {
  TempDir dir;
  Bytes bin;
  Scene s = penumbra::loadScene(writeGltf(dir, animatedDoc(bin), bin));
  ASSERT_EQ(s.animations.size(), 1u);
  EXPECT_TRUE(s.meshes[0].dynamic);
  const penumbra::MeshAnimation& a = s.animations[0];
  ASSERT_EQ(a.keys.size(), 4u);  // union of {0, 2} and {0, 1, 3}
  EXPECT_EQ(a.keys[1].time, 1.0f);
  EXPECT_EQ(a.restPositions.size(), 3u);
  EXPECT_TRUE(near(a.restPositions[0], {1, 1, 0}));  // the rest pose: the nodes' own TRS
  // At t = 2 the parent has turned 90 degrees about y and the child sits at x = 3 (its key at 1 and 3).
  penumbra::poseScene(s, 2.0);
  const glm::mat4 parent =
      glm::translate(glm::mat4(1.0f), {0, 1, 0}) * glm::rotate(glm::mat4(1.0f), glm::half_pi<float>(), {0, 1, 0});
  for (int i = 0; i < 3; ++i) {
    const glm::vec3 want(parent * glm::vec4(kTriangle[std::size_t(i)] + glm::vec3(3, 0, 0), 1.0f));
    EXPECT_TRUE(near(s.meshes[0].positions[std::size_t(i)], want, 1e-4f)) << i;
  }
  EXPECT_TRUE(near(s.meshes[0].normals[0], {1, 0, 0}, 1e-4f));  // +z turned 90 degrees about y
}

// A mesh placed by its node far from the world origin (a georeferenced tile) keeps its detail:
// the node transform is composed in double and the mesh stored relative to Scene::origin. In float
// world coordinates this millimetre triangle at 3e6 (one float step: 0.25) collapsed to a point.
TEST(GltfLoader, FarNodeKeepsItsMeshDetail) {
  TempDir dir;
  Bytes bin;
  const std::vector<glm::vec3> small = {{0, 0, 0}, {0.001f, 0, 0}, {0, 0.001f, 0}};
  json doc = meshDoc(small, {0, 1, 2}, bin);
  doc["nodes"][0]["translation"] = {3e6 + 0.3, 10.0, -2e6};
  const Scene s = penumbra::loadScene(writeGltf(dir, doc, bin));
  ASSERT_EQ(s.triangleCount(), 1u);
  EXPECT_GT(glm::length(s.origin), 3e6);
  for (std::size_t i = 0; i < 3; ++i) {
    const glm::dvec3 world = s.origin + glm::dvec3(s.meshes[0].positions[i]);
    const glm::dvec3 want = glm::dvec3(3e6 + 0.3, 10.0, -2e6) + glm::dvec3(small[i]);
    EXPECT_LT(glm::length(world - want), 1e-7) << i;
  }
  Bytes nearBin;
  json nearDoc = meshDoc(small, {0, 1, 2}, nearBin);
  nearDoc["nodes"][0]["translation"] = {0.001, 0.0, 0.0};  // within 16 radii: world coordinates kept
  EXPECT_EQ(penumbra::loadScene(writeGltf(dir, nearDoc, nearBin, "near")).origin, glm::dvec3(0.0));
}

// The same animation placed 1e5 units away poses the mesh at its keys exactly as at the origin: the
// keys turn it about its own parent, not about the scene's origin. (Between keys the rigid model
// interpolates the motion of the scene's origin point, which for a far model now lies in the scene
// instead of 1e5 units away.)
TEST(GltfLoader, FarAnimationTurnsInPlace) {
  TempDir dir;
  Bytes nearBin, farBin;
  Scene nearScene = penumbra::loadScene(writeGltf(dir, animatedDoc(nearBin), nearBin, "near"));
  json farDoc = animatedDoc(farBin);
  farDoc["nodes"][0]["translation"] = {1e5, 1.0, -1e5};
  Scene farScene = penumbra::loadScene(writeGltf(dir, farDoc, farBin, "far"));
  ASSERT_EQ(farScene.animations.size(), 1u);
  ASSERT_GT(glm::length(farScene.origin), 1e5);
  for (const double t : {1.0, 2.0, 3.0}) {
    penumbra::poseScene(nearScene, t);
    penumbra::poseScene(farScene, t);
    for (std::size_t i = 0; i < 3; ++i) {
      const glm::dvec3 world = farScene.origin + glm::dvec3(farScene.meshes[0].positions[i]);
      const glm::dvec3 want = glm::dvec3(nearScene.meshes[0].positions[i]) + glm::dvec3(1e5, 0.0, -1e5);
      EXPECT_LT(glm::length(world - want), 1e-5) << "t " << t << " vertex " << i;
    }
  }
}

TEST(GltfLoader, NonRigidOrBrokenAnimationsAreRefusedOrKeptStatic) {
  TempDir dir;
  Bytes bin;
  const Scene scaled = penumbra::loadScene(writeGltf(dir, animatedDoc(bin, "scale"), bin, "scaled"));
  EXPECT_TRUE(scaled.animations.empty());
  EXPECT_FALSE(scaled.meshes[0].dynamic);
  EXPECT_TRUE(anyWarningContains(scaled, "scales or shears"));
  Bytes bin2;
  json doc = animatedDoc(bin2);
  doc["accessors"][std::size_t(doc["animations"][0]["samplers"][1]["input"])]["count"] = 2;  // 2 times, 3 values
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin2, "short")); }, {"short.gltf", "animation"});
  Bytes bin3;
  json matrix = animatedDoc(bin3);
  matrix["nodes"][0].erase("translation");
  matrix["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 1};
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, matrix, bin3, "matrix")); }, {"matrix.gltf", "matrix"});
}

// KHR_mesh_quantization as gltfpack writes it: 16-bit integer positions, interleaved with padding
// (byteStride 8) and scaled back by the node; normalized 8-bit normals; 8-bit indices. The mesh
// comes out where the float file puts it.
TEST(GltfLoader, QuantizedAndNormalizedAccessors) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  const std::int16_t positions[] = {0, 0, 0, 0, 1000, 0, 0, 0, 0, 1000, 0, 0};  // x, y, z, pad per vertex
  const std::int8_t normals[] = {0, 0, 127, 0, 0, 0, 127, 0, 0, 0, -128, 0};    // +z, +z, -z (4-byte aligned)
  const std::uint8_t indices[] = {0, 1, 2};
  auto& prim = doc["meshes"][0]["primitives"][0];
  prim["attributes"]["POSITION"] = addAccessor(doc, bin, positions, sizeof positions, 5122, "VEC3", 3, false, 8);
  prim["attributes"]["NORMAL"] = addAccessor(doc, bin, normals, sizeof normals, 5120, "VEC3", 3, true, 4);
  prim["indices"] = addAccessor(doc, bin, indices, sizeof indices, 5121, "SCALAR", 3);
  doc["nodes"][0]["scale"] = {0.001, 0.001, 0.001};
  doc["nodes"][0]["translation"] = {1.0, 2.0, 3.0};
  doc["extensionsUsed"] = {"KHR_mesh_quantization"};
  doc["extensionsRequired"] = {"KHR_mesh_quantization"};
  const Scene s = penumbra::loadScene(writeGltf(dir, doc, bin));
  ASSERT_EQ(s.triangleCount(), 1u);
  EXPECT_TRUE(near(s.meshes[0].positions[0], {1, 2, 3}));
  EXPECT_TRUE(near(s.meshes[0].positions[1], {2, 2, 3}));
  EXPECT_TRUE(near(s.meshes[0].positions[2], {1, 3, 3}));
  EXPECT_TRUE(near(s.meshes[0].normals[0], {0, 0, 1}));
  EXPECT_TRUE(near(s.meshes[0].normals[2], {0, 0, -1}));  // -128 clamps to -1
}

// An accessor without a bufferView is zeros; a sparse part then replaces some elements.
TEST(GltfLoader, SparseAndZeroFilledAccessors) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  const std::uint16_t which[] = {1, 2};
  const float values[] = {4, 0, 0, 0, 4, 0};
  (void)addAccessor(doc, bin, which, sizeof which, 5123, "SCALAR", 2);  // views for the sparse part
  (void)addAccessor(doc, bin, values, sizeof values, 5126, "VEC3", 2);
  const std::size_t views = doc["bufferViews"].size();
  doc["accessors"][0] = {{"componentType", 5126},
                         {"count", 3},
                         {"type", "VEC3"},
                         {"sparse",
                          {{"count", 2},
                           {"indices", {{"bufferView", views - 2}, {"componentType", 5123}}},
                           {"values", {{"bufferView", views - 1}}}}}};
  const Scene s = penumbra::loadScene(writeGltf(dir, doc, bin));
  ASSERT_EQ(s.triangleCount(), 1u);
  EXPECT_TRUE(near(s.meshes[0].positions[0], {0, 0, 0}));
  EXPECT_TRUE(near(s.meshes[0].positions[1], {4, 0, 0}));
  EXPECT_TRUE(near(s.meshes[0].positions[2], {0, 4, 0}));

  json past = doc;  // a sparse index beyond the accessor, and more sparse elements than it has
  const std::uint16_t far[] = {1, 7};
  past["accessors"][0]["sparse"]["indices"]["bufferView"] = doc["bufferViews"].size();
  Bytes bin2 = bin;
  (void)addAccessor(past, bin2, far, sizeof far, 5123, "SCALAR", 2);
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, past, bin2, "past")); }, {"past.gltf", "sparse index 7"});
  json many = doc;
  many["accessors"][0]["sparse"]["count"] = 4;
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, many, bin, "many")); }, {"many.gltf", "sparse part of 4"});
}

// Required extensions nothing here reads are named before tinygltf meets their buffers (a
// compressed file's it reported as an invalid byteLength); appearance-only ones load, optional
// ones are noted.
TEST(GltfLoader, RequiredExtensionsNamedOptionalOnesNoted) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  doc["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "instanced")); },
                   {"instanced.gltf", "requires the extension EXT_mesh_gpu_instancing", "without that extension"});
  doc["extensionsUsed"] = doc["extensionsRequired"] = {"KHR_mesh_quantization", "EXT_mesh_gpu_instancing"};
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "both")); },
                   {"both.gltf", "EXT_mesh_gpu_instancing"});
  doc["extensionsUsed"] = {"KHR_materials_unlit", "KHR_texture_transform"};
  doc["extensionsRequired"] = {"KHR_texture_transform"};
  const Scene s = penumbra::loadScene(writeGltf(dir, doc, bin, "appearance"));
  EXPECT_EQ(s.triangleCount(), 1u);
  EXPECT_TRUE(anyWarningContains(s, "KHR_materials_unlit"));
}

TEST(GltfLoader, Base64DataUriAndDefaultColour) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {}, bin);  // non-indexed: sequential indices
  doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin);
  doc["meshes"][0]["primitives"][0].erase("material");
  const Scene s = penumbra::loadScene(writeGltf(dir, doc, bin));
  ASSERT_EQ(s.triangleCount(), 1u);
  EXPECT_EQ(s.meshes[0].indices, (std::vector<std::uint32_t>{0, 1, 2}));
  EXPECT_TRUE(near(s.meshes[0].positions[1], {1, 0, 0}));
  EXPECT_TRUE(near(s.meshes[0].baseColor, glm::vec3(0.8f)));
}

TEST(GltfLoader, AssembledGlbLoads) {
  TempDir dir;
  Bytes bin;
  const json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  writeFile(dir.file("m.GLB"), makeGlb(doc.dump(), bin));
  const Scene s = penumbra::loadScene(dir.file("m.GLB"));  // extension is case-insensitive
  EXPECT_EQ(s.name, "m");
  EXPECT_EQ(s.triangleCount(), 1u);
  EXPECT_TRUE(near(s.meshes[0].positions[2], {0, 1, 0}));
}

TEST(GltfLoader, StripFanAndPointsPrimitives) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}, {}, bin, 5);
  doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin);
  json fan = doc["meshes"][0]["primitives"][0], points = fan;
  fan["mode"] = 6;
  points["mode"] = 0;
  doc["meshes"][0]["primitives"].push_back(fan);
  doc["meshes"][0]["primitives"].push_back(points);
  const Scene s = penumbra::loadScene(writeGltf(dir, doc, bin));
  ASSERT_EQ(s.meshes.size(), 2u);
  EXPECT_EQ(s.meshes[0].indices, (std::vector<std::uint32_t>{0, 1, 2, 2, 1, 3}));
  EXPECT_EQ(s.meshes[1].indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_TRUE(anyWarningContains(s, "tri/2")) << "points primitive must be reported";
}

TEST(GltfLoader, LightsAndCamerasInWorldSpace) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  const double h = std::sqrt(0.5);
  const json down = {-h, 0.0, 0.0, h};  // -90 deg about X: local -Z points to world -Y
  doc["extensionsUsed"] = {"KHR_lights_punctual"};
  doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "directional"}, {"color", {1.0, 0.5, 0.25}}},
                                                        {{"type", "spot"}, {"spot", {{"outerConeAngle", 0.5}}}},
                                                        {{"type", "point"}}};
  auto lightRef = [](int i) { return json{{"KHR_lights_punctual", {{"light", i}}}}; };
  doc["nodes"] = {{{"mesh", 0}, {"camera", 1}, {"children", {1, 2, 3}}, {"translation", {10.0, 0.0, 0.0}}},
                  {{"rotation", down}, {"extensions", lightRef(0)}},
                  {{"translation", {0.0, 5.0, 0.0}}, {"rotation", down}, {"extensions", lightRef(1)}},
                  {{"translation", {1.0, 2.0, 3.0}}, {"extensions", lightRef(2)}},
                  {{"camera", 0}, {"translation", {0.0, 0.0, 10.0}}, {"rotation", {0.0, h, 0.0, h}}}};
  doc["scenes"][0]["nodes"] = {0, 4};
  doc["cameras"] = {
      {{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}},
      {{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0}, {"zfar", 9}}}}};
  const Scene s = penumbra::loadScene(writeGltf(dir, doc, bin));
  ASSERT_EQ(s.lights.size(), 3u);
  EXPECT_EQ(s.lights[0].type, LightType::Directional);
  EXPECT_TRUE(near(s.lights[0].direction, {0, -1, 0}));
  EXPECT_TRUE(near(s.lights[0].color, {1, 0.5f, 0.25f}));
  EXPECT_EQ(s.lights[1].type, LightType::Spot);
  EXPECT_TRUE(near(s.lights[1].position, {10, 5, 0}));
  EXPECT_TRUE(near(s.lights[1].direction, {0, -1, 0}));
  EXPECT_NEAR(s.lights[1].spotAngleDeg, 2.0 * 0.5 * 180.0 / glm::pi<double>(), 1e-3);
  EXPECT_EQ(s.lights[2].type, LightType::Point);
  EXPECT_TRUE(near(s.lights[2].position, {11, 2, 3}));
  ASSERT_TRUE(s.camera.has_value());
  EXPECT_TRUE(near(s.camera->eye, {0, 0, 10}));
  EXPECT_TRUE(near(glm::normalize(s.camera->target - s.camera->eye), {-1, 0, 0}));  // +90 deg about Y
  EXPECT_TRUE(near(s.camera->up, {0, 1, 0}));
  EXPECT_NEAR(s.camera->fovYDeg, 0.8 * 180.0 / glm::pi<double>(), 1e-3);
  EXPECT_TRUE(anyWarningContains(s, "orthographic"));  // visited first, warned about, ignored
}

// A hierarchy deeper than the call stack goes (issue 20: 20,000 levels crashed a recursive walk):
// 100,000 nested nodes, each moved by 0.001 in x, the mesh at the bottom.
TEST(GltfLoader, DeepHierarchyLoads) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  constexpr int kDepth = 100000;
  json nodes = json::array();
  for (int i = 0; i < kDepth; ++i) {
    json node = {{"translation", {0.001, 0.0, 0.0}}};
    if (i + 1 < kDepth)
      node["children"] = {i + 1};
    else
      node["mesh"] = 0;
    nodes.push_back(node);
  }
  doc["nodes"] = nodes;
  const Scene s = penumbra::loadScene(writeGltf(dir, doc, bin, "deep"));
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_NEAR(s.origin.x + s.meshes[0].positions[0].x, 100.0, 1e-6);  // double sums of 100,000 steps
  EXPECT_NEAR(s.origin.x + s.meshes[0].positions[1].x, 101.0, 1e-6);
}
