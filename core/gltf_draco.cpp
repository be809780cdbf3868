#include "core/gltf_draco.h"

#include <draco/compression/decode.h>

#include <cstdint>
#include <cstring>
#include <memory>

#include "core/gltf_accessor.h"

namespace penumbra::gltf {
namespace {

constexpr const char* kName = "KHR_draco_mesh_compression";

std::size_t componentCount(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4") return 4;
  return 0;
}

template <typename T>
bool convert(const draco::PointAttribute& attribute, std::size_t points, std::size_t components, std::size_t stride,
             unsigned char* out) {
  T value[4];
  for (std::size_t i = 0; i < points; ++i) {
    const draco::AttributeValueIndex v = attribute.mapped_index(draco::PointIndex(std::uint32_t(i)));
    if (v.value() >= attribute.size() ||
        !attribute.ConvertValue<T>(v, static_cast<std::int8_t>(components), value))
      return false;
    std::memcpy(out + i * stride, value, components * sizeof(T));
  }
  return true;
}

// Whether glTF may store a vertex attribute in `componentType` (double is not glTF).
bool attributeComponent(int componentType) {
  return componentType != TINYGLTF_COMPONENT_TYPE_DOUBLE && tinygltf::GetComponentSizeInBytes(componentType) > 0;
}

bool convertAttribute(const draco::PointAttribute& attribute, int componentType, std::size_t points,
                      std::size_t components, std::size_t stride, unsigned char* out) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return convert<std::int8_t>(attribute, points, components, stride, out);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return convert<std::uint8_t>(attribute, points, components, stride, out);
    case TINYGLTF_COMPONENT_TYPE_SHORT: return convert<std::int16_t>(attribute, points, components, stride, out);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return convert<std::uint16_t>(attribute, points, components, stride, out);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return convert<std::uint32_t>(attribute, points, components, stride, out);
    default: return convert<float>(attribute, points, components, stride, out);  // FLOAT (attributeComponent)
  }
}

// Points accessor `a` at a new view over [offset, offset + bytes) of buffer 0.
void pointAccessor(GlbRewrite& rewrite, nlohmann::json& a, std::size_t offset, std::size_t bytes, std::size_t stride) {
  const std::size_t view = rewrite.addView(offset, bytes);
  if (stride) rewrite.doc()["bufferViews"][view]["byteStride"] = stride;
  a["bufferView"] = view;
  a.erase("byteOffset");
  a.erase("sparse");
}

class PrimitiveDecoder {
 public:
  PrimitiveDecoder(GlbRewrite& rewrite, std::string where) : rewrite_(rewrite), where_(std::move(where)) {}

  // Decodes primitive `p` (its extension object `ext`); returns the bytes written.
  std::size_t run(nlohmann::json& p, const nlohmann::json& ext) {
    if (!ext.is_object() || !ext.contains("attributes") || !ext["attributes"].is_object())
      fail(path(), where_ + " has no attributes object", kCorrupt);
    const std::span<const unsigned char> stream =
        rewrite_.view(sizeField(ext, "bufferView", std::size_t(-1), where_, path()), where_);
    draco::DecoderBuffer input;
    input.Init(reinterpret_cast<const char*>(stream.data()), stream.size());
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&input);
    if (!decoded.ok())
      fail(path(), where_ + "'s Draco stream does not decode (" + decoded.status().error_msg_string() + ")", kCorrupt);
    const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
    std::size_t written = indices(p, *mesh);
    if (!p.contains("attributes") || !p["attributes"].is_object()) fail(path(), where_ + " has no attributes", kCorrupt);
    for (const auto& [semantic, id] : ext["attributes"].items()) {
      if (!p["attributes"].contains(semantic))
        fail(path(), where_ + " compresses " + semantic + ", which the primitive does not have", kCorrupt);
      const draco::PointAttribute* attribute =
          id.is_number_unsigned() ? mesh->GetAttributeByUniqueId(id.get<std::uint32_t>()) : nullptr;
      if (!attribute) fail(path(), where_ + "'s Draco stream has no attribute " + id.dump() + " for " + semantic, kCorrupt);
      written += attributeData(accessor(p["attributes"][semantic], semantic), *attribute, mesh->num_points(), semantic);
    }
    p["mode"] = 4;  // decoded as a triangle list, whatever the strips it was
    p["extensions"].erase(kName);
    return written;
  }

 private:
  const std::string& path() const { return rewrite_.path(); }

  nlohmann::json& accessor(const nlohmann::json& index, const std::string& what) {
    nlohmann::json& accessors = rewrite_.doc()["accessors"];
    if (!index.is_number_unsigned() || !accessors.is_array() || index.get<std::size_t>() >= accessors.size() ||
        !accessors[index.get<std::size_t>()].is_object())
      fail(path(), where_ + "'s " + what + " accessor " + index.dump() + " does not exist", kCorrupt);
    return accessors[index.get<std::size_t>()];
  }

  std::size_t indices(nlohmann::json& p, const draco::Mesh& mesh) {
    const std::size_t count = std::size_t(mesh.num_faces()) * 3;
    if (!p.contains("indices")) {
      rewrite_.doc()["accessors"].push_back({{"componentType", TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT}, {"type", "SCALAR"}, {"count", count}});
      p["indices"] = rewrite_.doc()["accessors"].size() - 1;
    }
    nlohmann::json& a = accessor(p["indices"], "indices");
    if (sizeField(a, "count", 0, where_ + "'s indices accessor", path()) != count)
      fail(path(), where_ + "'s indices accessor claims " + a["count"].dump() + " indices; its Draco stream holds " +
                       std::to_string(count), kCorrupt);
    const std::size_t offset = rewrite_.append(count * 4);
    auto* out = reinterpret_cast<std::uint32_t*>(rewrite_.at(offset));
    for (draco::FaceIndex f(0); f < mesh.num_faces(); ++f) {
      for (int k = 0; k < 3; ++k) out[3 * f.value() + k] = mesh.face(f)[k].value();
    }
    a["componentType"] = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    pointAccessor(rewrite_, a, offset, count * 4, 0);
    return count * 4;
  }

  std::size_t attributeData(nlohmann::json& a, const draco::PointAttribute& attribute, std::size_t points,
                            const std::string& semantic) {
    const std::string what = where_ + "'s " + semantic + " accessor";
    const int componentType = a.contains("componentType") && a["componentType"].is_number_integer()
                                  ? a["componentType"].get<int>() : 0;
    const std::string type = a.contains("type") && a["type"].is_string() ? a["type"].get<std::string>() : "?";
    const std::size_t components = componentCount(type);
    if (!components || !attributeComponent(componentType))
      fail(path(), what + " has type " + type + " / componentType " + std::to_string(componentType), kCorrupt);
    if (sizeField(a, "count", 0, what, path()) != points)
      fail(path(), what + " claims " + a["count"].dump() + " elements; its Draco stream holds " + std::to_string(points),
           kCorrupt);
    const std::size_t stride = (components * std::size_t(tinygltf::GetComponentSizeInBytes(componentType)) + 3) / 4 * 4;
    if (points > (std::size_t(1) << 31) / stride) fail(path(), what + " decodes to more than 2 GiB", "split the model");
    const std::size_t offset = rewrite_.append(points * stride);
    if (!convertAttribute(attribute, componentType, points, components, stride, rewrite_.at(offset)))
      fail(path(), what + "'s Draco values do not convert to its component type", kCorrupt);
    pointAccessor(rewrite_, a, offset, points * stride, stride);
    return points * stride;
  }

  GlbRewrite& rewrite_;
  std::string where_;
};

}  // namespace

DecodeStats decodeDraco(GlbRewrite& rewrite) {
  DecodeStats stats;
  nlohmann::json& meshes = rewrite.doc()["meshes"];
  if (!meshes.is_array()) return stats;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    if (!meshes[m].is_object() || !meshes[m].contains("primitives") || !meshes[m]["primitives"].is_array()) continue;
    nlohmann::json& primitives = meshes[m]["primitives"];
    for (std::size_t i = 0; i < primitives.size(); ++i) {
      nlohmann::json& p = primitives[i];
      if (!p.is_object() || !p.contains("extensions") || !p["extensions"].is_object() || !p["extensions"].contains(kName))
        continue;
      const int mode = p.contains("mode") && p["mode"].is_number_integer() ? p["mode"].get<int>() : 4;
      if (mode < 4) {  // points and lines: Penumbra drops them anyway
        p["extensions"].erase(kName);
        continue;
      }
      const nlohmann::json ext = p["extensions"][kName];
      stats.decodedBytes += PrimitiveDecoder(rewrite, "mesh " + std::to_string(m) + " primitive " + std::to_string(i) +
                                                          " (" + kName + ")")
                                .run(p, ext);
      ++stats.items;
    }
  }
  return stats;
}

}  // namespace penumbra::gltf
