// The glTF document before tinygltf sees it (files are untrusted): the GLB container's header and
// chunk lengths checked, the JSON parsed, and its required extensions and external references
// checked, so that no lying length, unread extension or path outside the model's folder reaches
// tinygltf. Every failure is an InputError naming the file and the fix.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace penumbra::gltf {

// The JSON chunk's text and where the BIN chunk lies (0 bytes without one).
struct GlbChunks {
  std::string json;
  std::size_t binOffset = 0, binSize = 0;
};

// GLB container (spec section "Binary glTF Layout"): checked here so no lying length reaches tinygltf.
// Returns its JSON chunk and where its BIN chunk lies.
GlbChunks validateGlb(const std::vector<unsigned char>& b, const std::string& path);

// The compression extensions the document uses, in decoding order: meshopt first, since a Draco
// stream could lie in a meshopt-compressed view.
std::vector<std::string> compressionUsed(const nlohmann::json& doc);

nlohmann::json parseDocument(const std::string& jsonText, const std::string& path);

// Before tinygltf opens anything: refuses external references outside the model's folder (naming
// their kind) and required extensions nothing here reads (naming them: a compressed buffer would
// otherwise fail as a truncated one). Returns notes on the optional extensions it ignores.
std::vector<std::string> checkDocument(const nlohmann::json& doc, const std::string& path, const std::string& folder);

}  // namespace penumbra::gltf
