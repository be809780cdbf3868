// A glTF document being rewritten into a GLB that tinygltf reads as a plain one, for the
// compression extensions tinygltf does not read (EXT_meshopt_compression, KHR_draco_mesh_compression):
// their decoders append decoded bytes to buffer 0 and point views and accessors at them. Buffer 0
// is the GLB's BIN chunk, grown, or, for a .gltf (or a GLB without one), a new first buffer, every
// reference to the others (bufferViews' and their extensions' `buffer`) moved up by one. Source buffers are buffer 0 or files in the model's
// folder (same confinement as the loader). Every failure is an InputError naming what failed.
#pragma once
#include <cstddef>
#include <map>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

namespace penumbra::gltf {

class GlbRewrite {
 public:
  // doc: the parsed JSON; bin: the GLB's BIN chunk (empty for a .gltf); folder: the model's folder.
  GlbRewrite(nlohmann::json doc, std::span<const unsigned char> bin, std::string folder, std::string path);

  nlohmann::json& doc() { return doc_; }
  const std::string& path() const { return path_; }

  // The file's own bytes of buffer `index` (in the rewritten numbering: for buffer 0 the BIN chunk
  // without what was appended); `where` names the reader in errors. A span into buffer 0 is
  // invalidated by append().
  std::span<const unsigned char> buffer(std::size_t index, const std::string& where);
  // The bytes of bufferView `index`, bounds-checked against its buffer (decoded bytes included).
  std::span<const unsigned char> view(std::size_t index, const std::string& where);

  // Appends `bytes` zeroed bytes to buffer 0 (16-byte aligned); returns their offset.
  std::size_t append(std::size_t bytes);
  unsigned char* at(std::size_t offset) { return out_.data() + offset; }
  // Appends a new bufferView on buffer 0 over [offset, offset + bytes); returns its index.
  std::size_t addView(std::size_t offset, std::size_t bytes);

  // The GLB, the `decoded` extensions gone from extensionsUsed and extensionsRequired.
  std::vector<unsigned char> finish(const std::vector<std::string>& decoded);

 private:
  nlohmann::json doc_;
  std::string folder_, path_;
  std::vector<unsigned char> out_;  // buffer 0: the BIN chunk's bytes (original_ of them), then decoded ones
  std::size_t original_ = 0;
  std::map<std::size_t, std::vector<unsigned char>> files_;
};

// Reads an unsigned size field `key` of a JSON object (fallback when absent); InputError otherwise.
std::size_t sizeField(const nlohmann::json& object, const char* key, std::size_t fallback, const std::string& where,
                      const std::string& path);

extern const std::string kCorrupt;  // the fix for a corrupt file

}  // namespace penumbra::gltf
