#include "core/gltf_meshopt.h"

#include <meshoptimizer.h>

#include "core/gltf_accessor.h"

namespace penumbra::gltf {
namespace {

constexpr const char* kName = "EXT_meshopt_compression";

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

DecodeStats decodeMeshopt(GlbRewrite& rewrite) {
  DecodeStats result;
  const std::string& path = rewrite.path();
  nlohmann::json& views = rewrite.doc()["bufferViews"];
  for (std::size_t v = 0; v < views.size(); ++v) {
    nlohmann::json& view = views[v];
    if (!view.is_object()) fail(path, "bufferView " + std::to_string(v) + " is not an object", kCorrupt);
    if (!view.contains("extensions") || !view["extensions"].contains(kName)) continue;
    const std::string where = "bufferView " + std::to_string(v) + " (" + kName + ")";
    const nlohmann::json ext = view["extensions"][kName];
    if (!ext.is_object()) fail(path, where + " is not an object", kCorrupt);
    const std::size_t count = sizeField(ext, "count", 0, where, path),
                      stride = sizeField(ext, "byteStride", 0, where, path);
    const std::size_t offset = sizeField(ext, "byteOffset", 0, where, path),
                      length = sizeField(ext, "byteLength", 0, where, path);
    if (count == 0 || stride == 0 || count > (std::size_t(1) << 31) / stride) {
      fail(path, where + " decodes to " + std::to_string(count) + " elements of " + std::to_string(stride) + " bytes",
           kCorrupt);
    }
    const std::size_t at = rewrite.append(count * stride);  // before the source: appending moves buffer 0
    const std::span<const unsigned char> src = rewrite.buffer(sizeField(ext, "buffer", 0, where, path), where);
    if (offset > src.size() || length > src.size() - offset)
      fail(path, where + "'s compressed bytes lie outside its buffer", kCorrupt);
    decodeView(ext, src.data() + offset, length, count, stride, rewrite.at(at), where, path);
    view["buffer"] = 0;
    view["byteOffset"] = at;
    view["byteLength"] = count * stride;
    view["extensions"].erase(kName);
    ++result.items;
    result.decodedBytes += count * stride;
  }
  for (nlohmann::json& buffer : rewrite.doc()["buffers"]) {  // fallbacks hold no data; nothing points at them any more
    if (buffer.is_object() && buffer.contains("extensions") && buffer["extensions"].contains(kName)) {
      buffer = {{"byteLength", 1}, {"uri", "data:application/octet-stream;base64,AA=="}};
    }
  }
  return result;
}

}  // namespace penumbra::gltf
