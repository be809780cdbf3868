#include "core/gltf_document.h"

#include <algorithm>
#include <cstdint>
#include <cstring>

#include "core/gltf_accessor.h"
#include "core/scene_loader.h"

namespace penumbra::gltf {
namespace {

std::uint32_t readU32(const std::vector<unsigned char>& b, std::size_t at) {
  return std::uint32_t(b[at]) | std::uint32_t(b[at + 1]) << 8 | std::uint32_t(b[at + 2]) << 16 |
         std::uint32_t(b[at + 3]) << 24;
}

// Extensions that change geometry or lights and are read here; extensions of materials and
// textures only change appearance, which Penumbra does not render, so they may be ignored even
// where a file requires them.
bool readsExtension(const std::string& name) {
  return name == "KHR_mesh_quantization" || name == "KHR_lights_punctual" || name == "EXT_meshopt_compression" ||
         name == "KHR_draco_mesh_compression";
}
bool appearanceOnly(const std::string& name) {
  return name.rfind("KHR_materials_", 0) == 0 || name.rfind("KHR_texture_", 0) == 0 || name.rfind("EXT_texture_", 0) == 0;
}

}  // namespace

GlbChunks validateGlb(const std::vector<unsigned char>& b, const std::string& path) {
  const std::string fix = "the .glb is truncated or corrupt; re-export it";
  const std::size_t size = b.size();
  if (size < 12) fail(path, "only " + std::to_string(size) + " bytes, shorter than the 12-byte GLB header", fix);
  if (std::memcmp(b.data(), "glTF", 4) != 0) fail(path, "GLB magic is not 'glTF'", "give a binary glTF (.glb) file");
  if (readU32(b, 4) != 2) fail(path, "GLB version " + std::to_string(readU32(b, 4)) + " is not 2", "give a glTF 2.0 file");
  if (readU32(b, 8) != size) {
    fail(path, "GLB header length " + std::to_string(readU32(b, 8)) + " differs from the file size " +
         std::to_string(size), fix);
  }
  std::size_t offset = 12;
  GlbChunks out;
  std::string& json = out.json;
  for (int chunk = 0; offset < size; ++chunk) {
    const std::string field = "chunk " + std::to_string(chunk) + (chunk == 0 ? " (JSON)" : chunk == 1 ? " (BIN)" : "");
    if (size - offset < 8) fail(path, field + " header needs 8 bytes but only " + std::to_string(size - offset) + " remain", fix);
    const std::uint64_t length = readU32(b, offset);
    if (length > size - offset - 8) {
      fail(path, field + " length " + std::to_string(length) + " exceeds the " + std::to_string(size - offset - 8) +
           " bytes left in the file", fix);
    }
    if (chunk == 0) {
      if (readU32(b, offset + 4) != 0x4E4F534Au) fail(path, "first GLB chunk is not JSON", fix);
      json.assign(reinterpret_cast<const char*>(b.data()) + offset + 8, length);
    } else if (chunk == 1 && readU32(b, offset + 4) == 0x004E4942u) {  // "BIN\0"
      out.binOffset = offset + 8;
      out.binSize = length;
    }
    offset += 8 + length;
  }
  if (json.empty()) fail(path, "GLB has no JSON chunk", fix);
  return out;
}

std::vector<std::string> compressionUsed(const nlohmann::json& doc) {
  std::vector<std::string> out;
  const auto used = doc.find("extensionsUsed");
  for (const char* name : {"EXT_meshopt_compression", "KHR_draco_mesh_compression"}) {
    if (used != doc.end() && used->is_array() && std::find(used->begin(), used->end(), name) != used->end())
      out.push_back(name);
  }
  return out;
}

nlohmann::json parseDocument(const std::string& jsonText, const std::string& path) {
  nlohmann::json doc;
  const std::size_t end = jsonText.find_last_not_of(std::string(" \t\r\n\0", 5));  // GLB padding
  try {
    doc = nlohmann::json::parse(jsonText.substr(0, end == std::string::npos ? 0 : end + 1));
  } catch (const nlohmann::json::exception& e) {
    fail(path, std::string("is not valid JSON (") + e.what() + ")", "the file is truncated or malformed; re-export it");
  }
  if (!doc.is_object()) fail(path, "top-level JSON value is not an object", "give a glTF 2.0 file");
  return doc;
}

std::vector<std::string> checkDocument(const nlohmann::json& doc, const std::string& path, const std::string& folder) {
  const auto names = [&](const char* key) {
    std::vector<std::string> out;
    const auto list = doc.find(key);
    if (list == doc.end() || !list->is_array()) return out;
    for (const auto& item : *list) {
      if (item.is_string()) out.push_back(item.get<std::string>());
    }
    return out;
  };
  const std::vector<std::string> required = names("extensionsRequired");
  for (const std::string& name : required) {
    if (!readsExtension(name) && !appearanceOnly(name)) {
      fail(path, "requires the extension " + name + ", which Penumbra does not read", "export it without that extension");
    }
  }
  std::vector<std::string> notes;
  for (const std::string& name : names("extensionsUsed")) {
    if (!readsExtension(name)) notes.push_back("glTF extension " + name + " ignored (it changes appearance only, or is optional)");
  }
  for (const char* kind : {"buffers", "images"}) {
    const auto list = doc.find(kind);
    if (list == doc.end() || !list->is_array()) continue;
    for (const auto& item : *list) {
      if (!item.is_object() || !item.contains("uri") || !item["uri"].is_string()) continue;
      const std::string uri = item["uri"].get<std::string>();
      if (uri.rfind("data:", 0) == 0) continue;
      if (uri.empty()) {
        fail(path, std::string("has a ") + (kind[0] == 'b' ? "buffer" : "image") + " whose uri is empty",
             "name the file it refers to, or leave uri out in a .glb whose BIN chunk holds the data");
      }
      const std::string why = confinedPathProblem(folder, uri);
      if (!why.empty()) {
        fail(path, std::string("refuses ") + (kind[0] == 'b' ? "buffer" : "image") + " URI '" + uri +
             "': outside the model's folder (" + why + ")",
             "copy the file into '" + folder + "' and refer to it relatively, or embed it as a data: URI");
      }
    }
  }
  return notes;
}

}  // namespace penumbra::gltf
