#include "core/gltf_rewrite.h"

#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/gltf_accessor.h"
#include "core/scene_loader.h"

namespace penumbra::gltf {

const std::string kCorrupt = "the file is corrupt; re-export it";

std::size_t sizeField(const nlohmann::json& object, const char* key, std::size_t fallback, const std::string& where,
                      const std::string& path) {
  if (!object.contains(key)) return fallback;
  const nlohmann::json& v = object.at(key);
  if (!v.is_number_unsigned()) fail(path, where + " has a " + key + " that is not an unsigned integer", kCorrupt);
  return v.get<std::size_t>();
}

namespace {

void putU32(std::vector<unsigned char>& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
}

void moveUp(nlohmann::json& object) {
  if (object.is_object() && object.contains("buffer") && object["buffer"].is_number_unsigned())
    object["buffer"] = object["buffer"].get<std::size_t>() + 1;
}

}  // namespace

GlbRewrite::GlbRewrite(nlohmann::json doc, std::span<const unsigned char> bin, std::string folder, std::string path)
    : doc_(std::move(doc)), folder_(std::move(folder)), path_(std::move(path)) {
  if (!doc_.contains("buffers") || !doc_["buffers"].is_array()) doc_["buffers"] = nlohmann::json::array();
  if (!doc_.contains("bufferViews")) doc_["bufferViews"] = nlohmann::json::array();
  if (!doc_["bufferViews"].is_array()) fail(path_, "bufferViews is not an array", kCorrupt);
  nlohmann::json& buffers = doc_["buffers"];
  if (bin.empty() || buffers.empty() || !buffers[0].is_object() || buffers[0].contains("uri")) {
    buffers.insert(buffers.begin(), nlohmann::json{{"byteLength", 0}});
    for (nlohmann::json& view : doc_["bufferViews"]) {
      moveUp(view);
      if (view.is_object() && view.contains("extensions") && view["extensions"].is_object()) {
        for (auto& ext : view["extensions"].items()) moveUp(ext.value());
      }
    }
  } else {
    out_.assign(bin.begin(), bin.end());
    original_ = out_.size();
  }
}

std::span<const unsigned char> GlbRewrite::buffer(std::size_t index, const std::string& where) {
  const nlohmann::json& buffers = doc_["buffers"];
  if (index >= buffers.size() || !buffers[index].is_object())
    fail(path_, where + " names buffer " + std::to_string(index) + ", which does not exist", kCorrupt);
  if (index == 0) return std::span<const unsigned char>(out_).first(original_);
  const nlohmann::json& buffer = buffers[index];
  if (!buffer.contains("uri")) fail(path_, where + " reads a buffer without uri that is not the GLB's BIN chunk", kCorrupt);
  if (auto it = files_.find(index); it != files_.end()) return it->second;
  const std::string uri = buffer["uri"].is_string() ? buffer["uri"].get<std::string>() : std::string();
  if (uri.rfind("data:", 0) == 0)
    fail(path_, where + " reads a data: URI buffer", "write the compressed model as a .glb or with a .bin");
  const std::string why = confinedPathProblem(folder_, uri);
  if (!why.empty())
    fail(path_, where + " reads '" + uri + "', outside the model's folder (" + why + ")", "copy it beside the model");
  std::ifstream in(std::filesystem::path(folder_) / uri, std::ios::binary);
  if (!in) fail(path_, where + " reads '" + uri + "', which cannot be opened", "check that the file beside the model is complete");
  return files_[index] =
             std::vector<unsigned char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::span<const unsigned char> GlbRewrite::view(std::size_t index, const std::string& where) {
  const nlohmann::json& views = doc_["bufferViews"];
  if (index >= views.size() || !views[index].is_object())
    fail(path_, where + " names bufferView " + std::to_string(index) + ", which does not exist", kCorrupt);
  const nlohmann::json& v = views[index];
  const std::string name = where + "'s bufferView " + std::to_string(index);
  const std::size_t b = sizeField(v, "buffer", 0, name, path_);
  const std::span<const unsigned char> bytes = b == 0 ? std::span<const unsigned char>(out_) : buffer(b, name);
  const std::size_t offset = sizeField(v, "byteOffset", 0, name, path_), length = sizeField(v, "byteLength", 0, name, path_);
  if (offset > bytes.size() || length > bytes.size() - offset) fail(path_, name + " lies outside its buffer", kCorrupt);
  return bytes.subspan(offset, length);
}

std::size_t GlbRewrite::append(std::size_t bytes) {
  while (out_.size() % 16) out_.push_back(0);
  const std::size_t offset = out_.size();
  out_.resize(offset + bytes);
  return offset;
}

std::size_t GlbRewrite::addView(std::size_t offset, std::size_t bytes) {
  doc_["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
  return doc_["bufferViews"].size() - 1;
}

std::vector<unsigned char> GlbRewrite::finish(const std::vector<std::string>& decoded) {
  while (out_.size() % 4) out_.push_back(0);
  if (out_.empty()) out_.resize(4);
  doc_["buffers"][0] = nlohmann::json{{"byteLength", out_.size()}};
  for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
    if (!doc_.contains(key) || !doc_[key].is_array()) continue;
    nlohmann::json kept = nlohmann::json::array();
    for (const auto& e : doc_[key]) {
      if (std::find(decoded.begin(), decoded.end(), e) == decoded.end()) kept.push_back(e);
    }
    doc_[key] = kept;
  }
  std::string json = doc_.dump();
  while (json.size() % 4) json += ' ';
  std::vector<unsigned char> glb;
  glb.reserve(28 + json.size() + out_.size());
  putU32(glb, 0x46546C67u);  // "glTF"
  putU32(glb, 2);
  putU32(glb, std::uint32_t(12 + 8 + json.size() + 8 + out_.size()));
  putU32(glb, std::uint32_t(json.size()));
  putU32(glb, 0x4E4F534Au);  // "JSON"
  glb.insert(glb.end(), json.begin(), json.end());
  putU32(glb, std::uint32_t(out_.size()));
  putU32(glb, 0x004E4942u);  // "BIN\0"
  glb.insert(glb.end(), out_.begin(), out_.end());
  return glb;
}

}  // namespace penumbra::gltf
