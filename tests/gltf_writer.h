// Shared by the scene-loader tests: models written by the test into a fresh temporary folder
// (glTF documents with their buffers, GLB containers), and checks of the errors they cause.
#pragma once
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/scene_loader.h"

namespace loader_test {

namespace fs = std::filesystem;
using nlohmann::json;
using penumbra::InputError;
using penumbra::Scene;
using Bytes = std::vector<unsigned char>;

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

inline void writeFile(const std::string& path, const void* data, std::size_t size) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path, std::ios::binary).write(static_cast<const char*>(data), std::streamsize(size));
}
inline void writeFile(const std::string& path, const std::string& text) { writeFile(path, text.data(), text.size()); }
inline void writeFile(const std::string& path, const Bytes& bytes) { writeFile(path, bytes.data(), bytes.size()); }

inline std::string base64(const Bytes& in) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < in.size(); i += 3) {
    const std::uint32_t n = std::uint32_t(in[i]) << 16 | (i + 1 < in.size() ? std::uint32_t(in[i + 1]) << 8 : 0) |
                            (i + 2 < in.size() ? in[i + 2] : 0);
    for (std::size_t k = 0; k < 4; ++k) out += i + k <= in.size() ? table[(n >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

inline void putU32(Bytes& b, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<unsigned char>(v >> (8 * i)));
}

// GLB container from JSON text and BIN payload, each padded to 4 bytes as the spec requires.
inline Bytes makeGlb(std::string jsonText, Bytes bin) {
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
inline json meshDoc(const std::vector<glm::vec3>& positions, const std::vector<std::uint16_t>& indices, Bytes& bin,
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
    doc["accessors"].push_back(
        {{"bufferView", 1}, {"componentType", 5123}, {"count", indices.size()}, {"type", "SCALAR"}});
    prim["indices"] = 1;
  }
  doc["meshes"] = {{{"name", "tri"}, {"primitives", {prim}}}};
  doc["buffers"] = {{{"byteLength", bin.size()}}};
  return doc;
}

inline const std::vector<glm::vec3> kTriangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

// Writes doc (+ bin as name.bin) into dir; returns the .gltf path.
inline std::string writeGltf(const TempDir& dir, json doc, const Bytes& bin, const std::string& name = "model") {
  if (!doc["buffers"][0].contains("uri")) {
    doc["buffers"][0]["uri"] = name + ".bin";
    writeFile(dir.file(name + ".bin"), bin);
  }
  writeFile(dir.file(name + ".gltf"), doc.dump());
  return dir.file(name + ".gltf");
}

// Asserts that `load` throws InputError whose message contains every one of `needles`.
inline void expectInputError(const std::function<void()>& load, const std::vector<std::string>& needles) {
  try {
    load();
    FAIL() << "expected InputError mentioning '" << needles.front() << "'";
  } catch (const InputError& e) {
    for (const std::string& n : needles) EXPECT_NE(std::string(e.what()).find(n), std::string::npos) << e.what();
  }
}

inline bool near(const glm::vec3& a, const glm::vec3& b, float eps = 1e-5f) { return glm::length(a - b) < eps; }

inline bool anyWarningContains(const Scene& s, const std::string& needle) {
  for (const std::string& w : s.warnings) {
    if (w.find(needle) != std::string::npos) return true;
  }
  return false;
}

// Appends raw bytes as a bufferView (4-byte aligned, optional byteStride) and an accessor on it;
// returns the accessor's index.
inline int addAccessor(json& doc, Bytes& bin, const void* data, std::size_t bytes, int componentType, const char* type,
                       std::size_t count, bool normalized = false, std::size_t stride = 0) {
  while (bin.size() % 4) bin.push_back(0);
  const std::size_t offset = bin.size();
  bin.resize(offset + bytes);
  std::memcpy(bin.data() + offset, data, bytes);
  json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
  if (stride) view["byteStride"] = stride;
  doc["bufferViews"].push_back(view);
  json accessor = {{"bufferView", doc["bufferViews"].size() - 1},
                   {"componentType", componentType},
                   {"count", count},
                   {"type", type}};
  if (normalized) accessor["normalized"] = true;
  doc["accessors"].push_back(accessor);
  doc["buffers"][0]["byteLength"] = bin.size();
  return int(doc["accessors"].size()) - 1;
}

// Float data as a new accessor of `count` elements of `type`.
inline int addFloats(json& doc, Bytes& bin, const std::vector<float>& values, const char* type, std::size_t count) {
  return addAccessor(doc, bin, values.data(), values.size() * sizeof(float), 5126, type, count);
}

}  // namespace loader_test
