#include "core/gltf_meshopt.h"

#include <meshoptimizer.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "core/gltf_accessor.h"
#include "core/scene_loader.h"

namespace penumbra::gltf {
namespace {

constexpr const char* kName = "EXT_meshopt_compression";
const std::string kCorrupt = "the file is corrupt; re-export it";

std::size_t sizeField(const nlohmann::json& object, const char* key, std::size_t fallback, const std::string& where,
                      const std::string& path) {
  if (!object.contains(key)) return fallback;
  const nlohmann::json& v = object.at(key);
  if (!v.is_number_unsigned()) fail(path, where + " has a " + key + " that is not an unsigned integer", kCorrupt);
  return v.get<std::size_t>();
}

void putU32(std::vector<unsigned char>& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
}

// The bytes of buffer `index`: the GLB's BIN chunk, or a file in the model's folder.
std::span<const unsigned char> sourceBuffer(const nlohmann::json& doc, std::size_t index,
                                            std::span<const unsigned char> bin, const std::string& folder,
                                            const std::string& path,
                                            std::map<std::size_t, std::vector<unsigned char>>& files) {
  const std::string where = std::string(kName) + " source buffer " + std::to_string(index);
  if (!doc.contains("buffers") || !doc["buffers"].is_array() || index >= doc["buffers"].size()) {
    fail(path, where + " does not exist", kCorrupt);
  }
  const nlohmann::json& buffer = doc["buffers"][index];
  if (!buffer.contains("uri")) {
    if (index != 0 || bin.empty()) fail(path, where + " has no uri and is not the GLB's BIN chunk", kCorrupt);
    return bin;
  }
  if (auto it = files.find(index); it != files.end()) return it->second;
  const std::string uri = buffer["uri"].is_string() ? buffer["uri"].get<std::string>() : std::string();
  if (uri.rfind("data:", 0) == 0)
    fail(path, where + " is a data: URI", "write the compressed model as a .glb or with a .bin");
  const std::string why = confinedPathProblem(folder, uri);
  if (!why.empty())
    fail(path, where + " '" + uri + "' is outside the model's folder (" + why + ")", "copy it beside the model");
  std::ifstream in(std::filesystem::path(folder) / uri, std::ios::binary);
  if (!in) fail(path, where + " '" + uri + "' cannot be opened", "check that the file beside the model is complete");
  return files[index] =
             std::vector<unsigned char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Decodes one compressed view (its extension object `ext`) into `out` (count * byteStride bytes).
void decodeView(const nlohmann::json& ext, const unsigned char* src, std::size_t srcSize, std::size_t count,
                std::size_t stride, unsigned char* out, const std::string& where, const std::string& path) {
  const std::string mode = ext.value("mode", std::string());
  const std::string filter = ext.value("filter", std::string("NONE"));
  int rc = -1;
  if (mode == "ATTRIBUTES") {
    if (stride == 0 || stride % 4 != 0 || stride > 256)
      fail(path, where + " has byteStride " + std::to_string(stride), kCorrupt);
    rc = meshopt_decodeVertexBuffer(out, count, stride, src, srcSize);
    if (rc == 0 && filter == "OCTAHEDRAL" && (stride == 4 || stride == 8))
      meshopt_decodeFilterOct(out, count, stride);
    else if (rc == 0 && filter == "QUATERNION" && stride == 8)
      meshopt_decodeFilterQuat(out, count, stride);
    else if (rc == 0 && filter == "EXPONENTIAL")
      meshopt_decodeFilterExp(out, count, stride);
    else if (rc == 0 && filter != "NONE")
      fail(path, where + " has filter " + filter + " with byteStride " + std::to_string(stride), kCorrupt);
  } else if (mode == "TRIANGLES" || mode == "INDICES") {
    if (stride != 2 && stride != 4) fail(path, where + " has index size " + std::to_string(stride), kCorrupt);
    if (mode == "TRIANGLES" && count % 3 != 0)
      fail(path, where + " has " + std::to_string(count) + " indices, not triangles", kCorrupt);
    rc = mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(out, count, stride, src, srcSize)
                             : meshopt_decodeIndexSequence(out, count, stride, src, srcSize);
  } else {
    fail(path, where + " has mode '" + mode + "'", "expected ATTRIBUTES, TRIANGLES or INDICES; " + kCorrupt);
  }
  if (rc != 0)
    fail(path, where + "'s compressed stream does not decode (meshoptimizer error " + std::to_string(rc) + ")",
         kCorrupt);
}

}  // namespace

MeshoptResult decodeMeshopt(nlohmann::json doc, std::span<const unsigned char> bin, const std::string& folder,
                            const std::string& path) {
  MeshoptResult result;
  std::map<std::size_t, std::vector<unsigned char>> files;
  // A GLB whose buffer 0 is its BIN chunk keeps it and grows it; otherwise a new first buffer holds
  // the decoded bytes and every buffer reference moves up by one.
  const bool append = !bin.empty() && doc.contains("buffers") && doc["buffers"].is_array() && !doc["buffers"].empty() &&
                      doc["buffers"][0].is_object() && !doc["buffers"][0].contains("uri");
  std::vector<unsigned char> out =
      append ? std::vector<unsigned char>(bin.begin(), bin.end()) : std::vector<unsigned char>();
  nlohmann::json& views = doc["bufferViews"];
  if (!views.is_array()) fail(path, "bufferViews is not an array", kCorrupt);
  for (std::size_t v = 0; v < views.size(); ++v) {
    nlohmann::json& view = views[v];
    if (!view.is_object()) fail(path, "bufferView " + std::to_string(v) + " is not an object", kCorrupt);
    if (!append && view.contains("buffer") && view["buffer"].is_number_unsigned())
      view["buffer"] = view["buffer"].get<std::size_t>() + 1;
    if (!view.contains("extensions") || !view["extensions"].contains(kName)) continue;
    const std::string where = "bufferView " + std::to_string(v) + " (" + kName + ")";
    const nlohmann::json ext = view["extensions"][kName];
    if (!ext.is_object()) fail(path, where + " is not an object", kCorrupt);
    const std::size_t count = sizeField(ext, "count", 0, where, path),
                      stride = sizeField(ext, "byteStride", 0, where, path);
    const std::size_t offset = sizeField(ext, "byteOffset", 0, where, path),
                      length = sizeField(ext, "byteLength", 0, where, path);
    const std::span<const unsigned char> src =
        sourceBuffer(doc, sizeField(ext, "buffer", 0, where, path), bin, folder, path, files);
    if (offset > src.size() || length > src.size() - offset)
      fail(path, where + "'s compressed bytes lie outside its buffer", kCorrupt);
    if (count == 0 || stride == 0 || count > (std::size_t(1) << 31) / stride) {
      fail(path, where + " decodes to " + std::to_string(count) + " elements of " + std::to_string(stride) + " bytes",
           kCorrupt);
    }
    while (out.size() % 16) out.push_back(0);
    const std::size_t at = out.size();
    out.resize(at + count * stride);
    decodeView(ext, src.data() + offset, length, count, stride, out.data() + at, where, path);
    view["buffer"] = 0;
    view["byteOffset"] = at;
    view["byteLength"] = count * stride;
    view["extensions"].erase(kName);
    ++result.views;
    result.decodedBytes += count * stride;
  }
  nlohmann::json& buffers = doc["buffers"];
  for (nlohmann::json& buffer : buffers) {  // fallbacks hold no data; nothing points at them any more
    if (buffer.is_object() && buffer.contains("extensions") && buffer["extensions"].contains(kName)) {
      buffer = {{"byteLength", 1}, {"uri", "data:application/octet-stream;base64,AA=="}};
    }
  }
  while (out.size() % 4) out.push_back(0);
  if (append)
    buffers[0]["byteLength"] = out.size();
  else
    buffers.insert(buffers.begin(), nlohmann::json{{"byteLength", std::max<std::size_t>(out.size(), 4)}});
  if (out.empty()) out.resize(4);
  for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
    if (!doc.contains(key) || !doc[key].is_array()) continue;
    nlohmann::json kept = nlohmann::json::array();
    for (const auto& e : doc[key]) {
      if (e != kName) kept.push_back(e);
    }
    doc[key] = kept;
  }

  std::string json = doc.dump();
  while (json.size() % 4) json += ' ';
  std::vector<unsigned char>& glb = result.glb;
  putU32(glb, 0x46546C67u);  // "glTF"
  putU32(glb, 2);
  putU32(glb, std::uint32_t(12 + 8 + json.size() + 8 + out.size()));
  putU32(glb, std::uint32_t(json.size()));
  putU32(glb, 0x4E4F534Au);  // "JSON"
  glb.insert(glb.end(), json.begin(), json.end());
  putU32(glb, std::uint32_t(out.size()));
  putU32(glb, 0x004E4942u);  // "BIN\0"
  glb.insert(glb.end(), out.begin(), out.end());
  return result;
}

}  // namespace penumbra::gltf
