// Scene loader tests. Every model is written by the test into a fresh temporary folder.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "core/animation.h"
#include "core/scene_loader.h"

namespace fs = std::filesystem;
using nlohmann::json;
using penumbra::InputError;
using penumbra::LightType;
using penumbra::Scene;
using Bytes = std::vector<unsigned char>;

namespace {

struct TempDir {
  fs::path path;
  TempDir() {
    static int counter = 0;
    path = fs::temp_directory_path() /
           ("penumbra_loader_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string file(const std::string& name) const { return (path / name).string(); }
};

void writeFile(const std::string& path, const void* data, std::size_t size) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path, std::ios::binary).write(static_cast<const char*>(data), std::streamsize(size));
}
void writeFile(const std::string& path, const std::string& text) { writeFile(path, text.data(), text.size()); }
void writeFile(const std::string& path, const Bytes& bytes) { writeFile(path, bytes.data(), bytes.size()); }

std::string base64(const Bytes& in) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < in.size(); i += 3) {
    const std::uint32_t n = std::uint32_t(in[i]) << 16 | (i + 1 < in.size() ? std::uint32_t(in[i + 1]) << 8 : 0) |
                            (i + 2 < in.size() ? in[i + 2] : 0);
    for (std::size_t k = 0; k < 4; ++k) out += i + k <= in.size() ? table[(n >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

void putU32(Bytes& b, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<unsigned char>(v >> (8 * i)));
}

// GLB container from JSON text and BIN payload, each padded to 4 bytes as the spec requires.
Bytes makeGlb(std::string jsonText, Bytes bin) {
  while (jsonText.size() % 4) jsonText += ' ';
  while (bin.size() % 4) bin.push_back(0);
  Bytes out;
  putU32(out, 0x46546C67u);  // "glTF"
  putU32(out, 2);
  putU32(out, std::uint32_t(12 + 8 + jsonText.size() + (bin.empty() ? 0 : 8 + bin.size())));
  putU32(out, std::uint32_t(jsonText.size()));
  putU32(out, 0x4E4F534Au);  // "JSON"
  out.insert(out.end(), jsonText.begin(), jsonText.end());
  if (!bin.empty()) {
    putU32(out, std::uint32_t(bin.size()));
    putU32(out, 0x004E4942u);  // "BIN\0"
    out.insert(out.end(), bin.begin(), bin.end());
  }
  return out;
}

// One mesh of `positions` (+ uint16 `indices` when given) in buffer 0; one node, one scene.
// The buffer has no uri yet: the caller picks external file, data URI or GLB.
json meshDoc(const std::vector<glm::vec3>& positions, const std::vector<std::uint16_t>& indices, Bytes& bin,
             int mode = 4) {
  bin.resize(positions.size() * 12);
  std::memcpy(bin.data(), positions.data(), bin.size());
  json prim = {{"attributes", {{"POSITION", 0}}}, {"material", 0}, {"mode", mode}};
  json doc = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}, {"name", "n"}}}},
      {"materials", {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.25, 0.5, 0.75, 1.0}}}}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", bin.size()}}}},
      {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", positions.size()}, {"type", "VEC3"}}}}};
  if (!indices.empty()) {
    const std::size_t offset = bin.size();
    bin.resize(offset + indices.size() * 2);
    std::memcpy(bin.data() + offset, indices.data(), indices.size() * 2);
    while (bin.size() % 4) bin.push_back(0);
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", indices.size() * 2}});
    doc["accessors"].push_back({{"bufferView", 1}, {"componentType", 5123}, {"count", indices.size()}, {"type", "SCALAR"}});
    prim["indices"] = 1;
  }
  doc["meshes"] = {{{"name", "tri"}, {"primitives", {prim}}}};
  doc["buffers"] = {{{"byteLength", bin.size()}}};
  return doc;
}

const std::vector<glm::vec3> kTriangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

// Writes doc (+ bin as name.bin) into dir; returns the .gltf path.
std::string writeGltf(const TempDir& dir, json doc, const Bytes& bin, const std::string& name = "model") {
  if (!doc["buffers"][0].contains("uri")) {
    doc["buffers"][0]["uri"] = name + ".bin";
    writeFile(dir.file(name + ".bin"), bin);
  }
  writeFile(dir.file(name + ".gltf"), doc.dump());
  return dir.file(name + ".gltf");
}

// Asserts that `load` throws InputError whose message contains every one of `needles`.
void expectInputError(const std::function<void()>& load, const std::vector<std::string>& needles) {
  try {
    load();
    FAIL() << "expected InputError mentioning '" << needles.front() << "'";
  } catch (const InputError& e) {
    for (const std::string& n : needles) EXPECT_NE(std::string(e.what()).find(n), std::string::npos) << e.what();
  }
}

bool near(const glm::vec3& a, const glm::vec3& b, float eps = 1e-5f) { return glm::length(a - b) < eps; }

bool anyWarningContains(const Scene& s, const std::string& needle) {
  for (const std::string& w : s.warnings) {
    if (w.find(needle) != std::string::npos) return true;
  }
  return false;
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

// Appends float data to bin as a new accessor (4-byte aligned); returns its index.
int addFloatAccessor(json& doc, Bytes& bin, const std::vector<float>& values, const char* type, std::size_t count) {
  while (bin.size() % 4) bin.push_back(0);
  const std::size_t offset = bin.size();
  bin.resize(offset + values.size() * 4);
  std::memcpy(bin.data() + offset, values.data(), values.size() * 4);
  doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", values.size() * 4}});
  doc["accessors"].push_back({{"bufferView", doc["bufferViews"].size() - 1}, {"componentType", 5126}, {"count", count}, {"type", type}});
  doc["buffers"][0]["byteLength"] = bin.size();
  return int(doc["accessors"].size()) - 1;
}

// The triangle under a parent node that turns about y (rotation channel) while the child slides
// along x (translation channel, keys at other times): one rigid animation with the union of keys.
json animatedDoc(Bytes& bin, const char* childPath = "translation") {
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["nodes"] = {{{"name", "parent"}, {"translation", {0.0, 1.0, 0.0}}, {"children", {1}}},
                  {{"name", "child"}, {"mesh", 0}, {"translation", {1.0, 0.0, 0.0}}}};
  doc["scenes"] = {{{"nodes", {0}}}};
  const float s = std::sqrt(0.5f);
  const int rotT = addFloatAccessor(doc, bin, {0.0f, 2.0f}, "SCALAR", 2);
  const int rotV = addFloatAccessor(doc, bin, {0, 0, 0, 1, 0, s, 0, s}, "VEC4", 2);  // 0 -> 90 degrees about y
  const int moveT = addFloatAccessor(doc, bin, {0.0f, 1.0f, 3.0f}, "SCALAR", 3);
  const bool scale = std::string(childPath) == "scale";
  const int moveV = addFloatAccessor(doc, bin, scale ? std::vector<float>{1, 1, 1, 2, 2, 2, 1, 1, 1}
                                                     : std::vector<float>{1, 0, 0, 3, 0, 0, 3, 0, 0}, "VEC3", 3);
  doc["animations"] = {{{"name", "fly"},
                        {"samplers", {{{"input", rotT}, {"output", rotV}, {"interpolation", "LINEAR"}},
                                      {{"input", moveT}, {"output", moveV}, {"interpolation", "LINEAR"}}}},
                        {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "rotation"}}}},
                                      {{"sampler", 1}, {"target", {{"node", 1}, {"path", childPath}}}}}}}};
  return doc;
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
  const glm::mat4 parent = glm::translate(glm::mat4(1.0f), {0, 1, 0}) * glm::rotate(glm::mat4(1.0f), glm::half_pi<float>(), {0, 1, 0});
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

// Appends raw bytes as a bufferView (4-byte aligned, optional byteStride) and an accessor on it.
int addAccessor(json& doc, Bytes& bin, const void* data, std::size_t bytes, int componentType, const char* type,
                std::size_t count, bool normalized = false, std::size_t stride = 0) {
  while (bin.size() % 4) bin.push_back(0);
  const std::size_t offset = bin.size();
  bin.resize(offset + bytes);
  std::memcpy(bin.data() + offset, data, bytes);
  json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
  if (stride) view["byteStride"] = stride;
  doc["bufferViews"].push_back(view);
  json accessor = {{"bufferView", doc["bufferViews"].size() - 1}, {"componentType", componentType}, {"count", count}, {"type", type}};
  if (normalized) accessor["normalized"] = true;
  doc["accessors"].push_back(accessor);
  doc["buffers"][0]["byteLength"] = bin.size();
  return int(doc["accessors"].size()) - 1;
}

// KHR_mesh_quantization as gltfpack writes it: 16-bit integer positions, interleaved with padding
// (byteStride 8) and scaled back by the node; normalized 8-bit normals; 8-bit indices. The mesh
// comes out where the float file puts it.
TEST(GltfLoader, QuantizedAndNormalizedAccessors) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  const std::int16_t positions[] = {0, 0, 0, 0, 1000, 0, 0, 0, 0, 1000, 0, 0};  // x, y, z, pad per vertex
  const std::int8_t normals[] = {0, 0, 127, 0, 0, 0, 127, 0, 0, 0, -128, 0};   // +z, +z, -z (4-byte aligned)
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
  doc["accessors"][0] = {{"componentType", 5126}, {"count", 3}, {"type", "VEC3"},
                         {"sparse", {{"count", 2},
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

// Required extensions nothing here reads are named before tinygltf meets their buffers (a Draco
// file's it reported as an invalid byteLength); appearance-only ones load, optional ones are noted.
TEST(GltfLoader, RequiredExtensionsNamedOptionalOnesNoted) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  doc["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "instanced")); },
                   {"instanced.gltf", "requires the extension EXT_mesh_gpu_instancing", "without that extension"});
  doc["extensionsUsed"] = doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "draco")); }, {"KHR_draco_mesh_compression", "Draco"});
  doc["extensionsUsed"] = {"KHR_materials_unlit", "KHR_texture_transform"};
  doc["extensionsRequired"] = {"KHR_texture_transform"};
  const Scene s = penumbra::loadScene(writeGltf(dir, doc, bin, "appearance"));
  EXPECT_EQ(s.triangleCount(), 1u);
  EXPECT_TRUE(anyWarningContains(s, "KHR_materials_unlit"));
}

TEST(GltfLoader, EmptyUriSaysSo) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["buffers"][0]["uri"] = "";
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "empty")); }, {"empty.gltf", "uri is empty"});
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

TEST(GltfLoader, MalformedOrTruncatedJsonNamesFile) {
  TempDir dir;
  writeFile(dir.file("bad.gltf"), std::string("{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [,]}"));
  expectInputError([&] { penumbra::loadScene(dir.file("bad.gltf")); }, {"bad.gltf", "JSON"});
  Bytes bin;
  const std::string text = meshDoc(kTriangle, {0, 1, 2}, bin).dump();
  writeFile(dir.file("cut.gltf"), text.substr(0, text.size() / 2));
  expectInputError([&] { penumbra::loadGltf(dir.file("cut.gltf")); }, {"cut.gltf"});
}

TEST(GltfLoader, BufferFileShortOrMissing) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["buffers"][0]["uri"] = "short.bin";
  writeFile(dir.file("short.bin"), Bytes(bin.begin(), bin.end() - 8));
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin)); }, {"model.gltf", "short.bin"});
  doc["buffers"][0]["uri"] = "absent.bin";
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin)); }, {"model.gltf", "absent.bin"});
}

TEST(GltfLoader, GlbTotalLengthLies) {
  TempDir dir;
  Bytes bin;
  const std::string text = meshDoc(kTriangle, {0, 1, 2}, bin).dump();  // fills bin first
  const Bytes good = makeGlb(text, bin);
  for (const std::int64_t delta : {64, -4}) {
    Bytes glb = good;
    const std::uint32_t lie = std::uint32_t(std::int64_t(glb.size()) + delta);
    std::memcpy(glb.data() + 8, &lie, 4);
    writeFile(dir.file("lie.glb"), glb);
    expectInputError([&] { penumbra::loadScene(dir.file("lie.glb")); }, {"lie.glb", "header length"});
  }
}

TEST(GltfLoader, GlbChunkLengthsExceedFile) {
  TempDir dir;
  Bytes bin;
  const std::string text = meshDoc(kTriangle, {0, 1, 2}, bin).dump();  // fills bin first
  const Bytes good = makeGlb(text, bin);
  Bytes glb = good;
  const std::uint32_t jsonLie = std::uint32_t(glb.size());
  std::memcpy(glb.data() + 12, &jsonLie, 4);
  writeFile(dir.file("json.glb"), glb);
  expectInputError([&] { penumbra::loadGltf(dir.file("json.glb")); }, {"json.glb", "chunk 0 (JSON) length"});

  glb = good;
  std::uint32_t jsonLength;
  std::memcpy(&jsonLength, glb.data() + 12, 4);
  const std::uint32_t binLie = 1u << 30;
  std::memcpy(glb.data() + 20 + jsonLength, &binLie, 4);
  writeFile(dir.file("bin.glb"), glb);
  expectInputError([&] { penumbra::loadGltf(dir.file("bin.glb")); }, {"bin.glb", "chunk 1 (BIN) length"});

  glb = good;
  glb[4] = 1;  // version 1
  writeFile(dir.file("v1.glb"), glb);
  expectInputError([&] { penumbra::loadGltf(dir.file("v1.glb")); }, {"v1.glb", "version 1"});
  writeFile(dir.file("text.glb"), std::string("{\"asset\": {\"version\": \"2.0\"}}"));
  expectInputError([&] { penumbra::loadGltf(dir.file("text.glb")); }, {"text.glb", "magic"});

  writeFile(dir.file("tiny.glb"), Bytes(good.begin(), good.begin() + 7));
  expectInputError([&] { penumbra::loadGltf(dir.file("tiny.glb")); }, {"tiny.glb", "12-byte"});
}

TEST(GltfLoader, AccessorOutOfBounds) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["accessors"][0]["count"] = 1000;
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "a")); }, {"a.gltf", "POSITION accessor 0"});

  doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["bufferViews"][1]["byteLength"] = 4096;  // view larger than the buffer
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "b")); }, {"b.gltf", "bufferView 1"});

  doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["accessors"][0]["componentType"] = 5125;  // POSITION: float or 8/16-bit integers, never 32-bit ones
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "c")); }, {"c.gltf", "float or 8/16-bit integers"});

  doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["meshes"][0]["primitives"][0]["indices"] = 7;
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "d")); }, {"d.gltf", "accessor"});
}

TEST(GltfLoader, NanAndDegenerateTrianglesAreCleanedOrRefused) {
  TempDir dir;
  Bytes bin;
  const float nan = std::nanf("");
  const json doc = meshDoc({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {nan, 0, 0}, {2, 0, 0}}, {0, 1, 2, 0, 3, 1, 0, 1, 4}, bin);
  const Scene s = penumbra::loadScene(writeGltf(dir, doc, bin));
  EXPECT_EQ(s.triangleCount(), 1u);
  EXPECT_TRUE(anyWarningContains(s, "non-finite"));
  EXPECT_TRUE(anyWarningContains(s, "degenerate"));
  const json flat = meshDoc({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {0, 1, 2}, bin);  // nothing drawable left
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, flat, bin, "flat")); }, {"flat.gltf", "no drawable"});
  const std::vector<std::uint16_t> many(3000, 0);  // 1,000 triangles, every vertex in one point
  const json point = meshDoc({{5, 5, 5}}, many, bin);
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, point, bin, "point")); }, {"point.gltf", "no drawable"});
}

TEST(GltfLoader, BufferUriOutsideFolderRefused) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  writeFile(dir.file("secret.bin"), bin);  // a real file: only the confinement rule can stop it
  doc["buffers"][0]["uri"] = "../secret.bin";
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "sub/m")); },
                   {"m.gltf", "buffer URI '../secret.bin'", "outside the model's folder"});
  doc["buffers"][0]["uri"] = dir.file("secret.bin");
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "sub/m")); },
                   {"m.gltf", dir.file("secret.bin"), "absolute"});
  // Percent-encoding hides the climb from a raw check; the file-system callbacks still refuse it.
  doc["buffers"][0]["uri"] = "%2E%2E/secret.bin";
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "sub/m")); },
                   {"m.gltf", "'../secret.bin'", "outside the model's folder"});
  // A link inside the folder that leads out is refused too.
  fs::create_symlink(dir.path / "secret.bin", dir.path / "sub" / "link.bin");
  doc["buffers"][0]["uri"] = "link.bin";
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "sub/m")); },
                   {"m.gltf", "buffer URI 'link.bin'", "through a link"});
  fs::copy_file(dir.path / "secret.bin", dir.path / "sub" / "copy.bin");
  doc["buffers"][0]["uri"] = "./copy.bin";  // inside: fine
  EXPECT_EQ(penumbra::loadScene(writeGltf(dir, doc, bin, "sub/m")).triangleCount(), 1u);
}

TEST(GltfLoader, ImageUriOutsideFolderRefusedInsideAccepted) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin);
  writeFile(dir.file("secret.png"), std::string("not really a png"));
  writeFile(dir.file("sub/tex.png"), std::string("not really a png either"));
  doc["images"] = {{{"uri", "tex.png"}}};  // inside: loads, and is never decoded
  EXPECT_EQ(penumbra::loadScene(writeGltf(dir, doc, bin, "sub/m")).triangleCount(), 1u);
  doc["images"] = {{{"uri", "../secret.png"}}};
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "sub/m")); },
                   {"m.gltf", "image URI '../secret.png'", "outside the model's folder"});
  doc["images"] = {{{"uri", "%2e%2e/secret.png"}}};
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "sub/m")); },
                   {"m.gltf", "'../secret.png'", "outside the model's folder"});
}

TEST(GltfLoader, LightsAndCamerasInWorldSpace) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  const double h = std::sqrt(0.5);
  const json down = {-h, 0.0, 0.0, h};  // -90 deg about X: local -Z points to world -Y
  doc["extensionsUsed"] = {"KHR_lights_punctual"};
  doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "directional"}, {"color", {1.0, 0.5, 0.25}}},
      {{"type", "spot"}, {"spot", {{"outerConeAngle", 0.5}}}},
      {{"type", "point"}}};
  auto lightRef = [](int i) { return json{{"KHR_lights_punctual", {{"light", i}}}}; };
  doc["nodes"] = {{{"mesh", 0}, {"camera", 1}, {"children", {1, 2, 3}}, {"translation", {10.0, 0.0, 0.0}}},
                  {{"rotation", down}, {"extensions", lightRef(0)}},
                  {{"translation", {0.0, 5.0, 0.0}}, {"rotation", down}, {"extensions", lightRef(1)}},
                  {{"translation", {1.0, 2.0, 3.0}}, {"extensions", lightRef(2)}},
                  {{"camera", 0}, {"translation", {0.0, 0.0, 10.0}}, {"rotation", {0.0, h, 0.0, h}}}};
  doc["scenes"][0]["nodes"] = {0, 4};
  doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}},
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

TEST(GltfLoader, NodeCycleRefused) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["nodes"] = {{{"mesh", 0}, {"children", {1}}}, {{"children", {0}}}};
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "loop")); }, {"loop.gltf", "ancestor"});
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
    if (i + 1 < kDepth) node["children"] = {i + 1};
    else node["mesh"] = 0;
    nodes.push_back(node);
  }
  doc["nodes"] = nodes;
  const Scene s = penumbra::loadScene(writeGltf(dir, doc, bin, "deep"));
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_NEAR(s.origin.x + s.meshes[0].positions[0].x, 100.0, 1e-6);  // double sums of 100,000 steps
  EXPECT_NEAR(s.origin.x + s.meshes[0].positions[1].x, 101.0, 1e-6);
}

namespace {
const char* kCubeObj =
    "mtllib cube.mtl\no cube\n"
    "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
    "usemtl red\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nf 1 5 8 4\n";
}  // namespace

TEST(ObjLoader, CubeWithMaterial) {
  TempDir dir;
  writeFile(dir.file("cube.obj"), std::string(kCubeObj));
  writeFile(dir.file("cube.mtl"), std::string("newmtl red\nKd 0.9 0.1 0.2\n"));
  const Scene s = penumbra::loadScene(dir.file("cube.obj"));
  EXPECT_EQ(s.name, "cube");
  EXPECT_EQ(s.triangleCount(), 12u);
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.meshes[0].positions.size(), 8u);
  EXPECT_TRUE(near(s.meshes[0].baseColor, {0.9f, 0.1f, 0.2f}));
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
}

TEST(ObjLoader, MissingMtlIsAWarning) {
  TempDir dir;
  writeFile(dir.file("cube.obj"), std::string(kCubeObj));
  const Scene s = penumbra::loadScene(dir.file("cube.obj"));
  EXPECT_EQ(s.triangleCount(), 12u);
  EXPECT_TRUE(anyWarningContains(s, "cube.mtl"));
  EXPECT_TRUE(near(s.meshes[0].baseColor, glm::vec3(0.8f)));
}

TEST(ObjLoader, MtllibOutsideFolderIgnored) {
  TempDir dir;
  std::string obj = kCubeObj;
  obj.replace(0, obj.find('\n'), "mtllib ../evil.mtl");
  writeFile(dir.file("sub/cube.obj"), obj);
  writeFile(dir.file("evil.mtl"), std::string("newmtl red\nKd 0 1 0\n"));
  const Scene s = penumbra::loadScene(dir.file("sub/cube.obj"));
  EXPECT_EQ(s.triangleCount(), 12u);
  EXPECT_TRUE(anyWarningContains(s, "'../evil.mtl' outside"));
  EXPECT_TRUE(near(s.meshes[0].baseColor, glm::vec3(0.8f)));
}

TEST(ObjLoader, NormalsKept) {
  TempDir dir;
  writeFile(dir.file("tri.obj"), std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n"));
  const Scene s = penumbra::loadScene(dir.file("tri.obj"));
  ASSERT_EQ(s.triangleCount(), 1u);
  ASSERT_EQ(s.meshes[0].normals.size(), 3u);
  EXPECT_TRUE(near(s.meshes[0].normals[2], {0, 0, 1}));
}

// Georeferenced OBJ coordinates are read in double and stored relative to Scene::origin: a
// millimetre triangle 5e6 units out keeps its shape (float steps there are half a unit).
TEST(ObjLoader, GeoreferencedCoordinatesKeepTheirDetail) {
  TempDir dir;
  writeFile(dir.file("far.obj"), std::string("v 5000000.123 20.5 -4000000.456\nv 5000000.124 20.5 -4000000.456\n"
                                             "v 5000000.123 20.501 -4000000.456\nf 1 2 3\n"));
  const Scene s = penumbra::loadScene(dir.file("far.obj"));
  ASSERT_EQ(s.triangleCount(), 1u);
  const glm::dvec3 want[3] = {{5000000.123, 20.5, -4000000.456}, {5000000.124, 20.5, -4000000.456},
                              {5000000.123, 20.501, -4000000.456}};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_LT(glm::length(s.origin + glm::dvec3(s.meshes[0].positions[i]) - want[i]), 1e-7) << i;
  }
}

TEST(ObjLoader, BadIndicesRefused) {
  TempDir dir;
  writeFile(dir.file("range.obj"), std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"));
  expectInputError([&] { penumbra::loadScene(dir.file("range.obj")); }, {"range.obj", "out of"});
  writeFile(dir.file("quad.obj"), std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 -9\n"));
  expectInputError([&] { penumbra::loadScene(dir.file("quad.obj")); }, {"quad.obj"});
  writeFile(dir.file("zero.obj"), std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"));
  expectInputError([&] { penumbra::loadScene(dir.file("zero.obj")); }, {"zero.obj", "zero value"});
  writeFile(dir.file("vn.obj"), std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//5\n"));
  expectInputError([&] { penumbra::loadScene(dir.file("vn.obj")); }, {"vn.obj"});
}

TEST(SceneLoader, MissingFileAndUnknownExtension) {
  TempDir dir;
  expectInputError([&] { penumbra::loadScene(dir.file("nope.gltf")); }, {"scene file '" + dir.file("nope.gltf") + "' not found"});
  expectInputError([&] { penumbra::loadScene(dir.file("nope.obj")); }, {"nope.obj", "not found"});
  writeFile(dir.file("model.xyzzy"), std::string("x"));
  expectInputError([&] { penumbra::loadScene(dir.file("model.xyzzy")); }, {"model.xyzzy", ".xyzzy", "builtin:", ".gltf", ".obj", "assimp"});
  writeFile(dir.file("model.fbx"), std::string("x"));  // a format assimp reads, but not this file
  expectInputError([&] { penumbra::loadScene(dir.file("model.fbx")); }, {"model.fbx", "could not be read by assimp"});
  expectInputError([&] { penumbra::loadScene("courtyard"); }, {"'courtyard'", "builtin:"});
}

TEST(SceneLoader, BuiltinDispatch) {
  const Scene s = penumbra::loadScene("builtin:square");
  EXPECT_GT(s.triangleCount(), 0u);
  EXPECT_FALSE(s.name.empty());
}
