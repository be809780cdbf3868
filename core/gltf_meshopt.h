// EXT_meshopt_compression (what `gltfpack -c` / `-cc` writes): decodes a glTF document's
// compressed bufferViews with meshoptimizer and returns a GLB that tinygltf reads as a plain one:
// the decoded bytes appended to the BIN chunk (a new first buffer for a .gltf), the views pointed
// at them, the fallback buffers (which hold no data) emptied. Source buffers are the GLB's BIN
// chunk or files in the model's folder. Every failure is an InputError naming the view.
#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

namespace penumbra::gltf {

struct MeshoptResult {
  std::vector<unsigned char> glb;
  std::size_t views = 0;         // bufferViews decoded
  std::size_t decodedBytes = 0;  // their bytes
};

// doc: the parsed JSON; bin: the GLB's BIN chunk (empty for a .gltf); folder: the model's folder.
MeshoptResult decodeMeshopt(nlohmann::json doc, std::span<const unsigned char> bin, const std::string& folder,
                            const std::string& path);

}  // namespace penumbra::gltf
