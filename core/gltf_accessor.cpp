#include "core/gltf_accessor.h"

#include <cstring>

namespace penumbra::gltf {

[[noreturn]] void fail(const std::string& path, const std::string& problem, const std::string& fix) {
  throw InputError("glTF '" + path + "': " + problem + "; " + fix);
}

ElementView viewAccessor(const tinygltf::Model& model, int index, const std::string& what, const std::string& path,
                         Kind kind) {
  const std::string name = what + " accessor " + std::to_string(index);
  const std::string fix = "the file is corrupt; re-export it";
  if (index < 0 || std::size_t(index) >= model.accessors.size()) {
    fail(path, name + " does not exist (the file has " + std::to_string(model.accessors.size()) + " accessors)", fix);
  }
  const tinygltf::Accessor& acc = model.accessors[std::size_t(index)];
  if (acc.sparse.isSparse) fail(path, name + " is sparse, which is not supported", "re-export without sparse accessors");
  const bool indices = kind == Kind::Indices;
  const int type = kind == Kind::Vec3 ? TINYGLTF_TYPE_VEC3 : kind == Kind::Vec4 ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_SCALAR;
  const bool typeOk = acc.type == type && (indices ? (acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                                      acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
                                                      acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
                                                   : acc.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT);
  if (!typeOk) {
    static const char* const expected[] = {"FLOAT VEC3", "FLOAT VEC4", "FLOAT SCALAR", "an unsigned SCALAR"};
    fail(path, name + " has type " + std::to_string(acc.type) + " / componentType " + std::to_string(acc.componentType) +
         ", expected " + expected[int(kind)], "re-export with standard formats");
  }
  if (acc.bufferView < 0 || std::size_t(acc.bufferView) >= model.bufferViews.size()) {
    fail(path, name + " refers to bufferView " + std::to_string(acc.bufferView) + ", which does not exist", fix);
  }
  const tinygltf::BufferView& view = model.bufferViews[std::size_t(acc.bufferView)];
  if (view.buffer < 0 || std::size_t(view.buffer) >= model.buffers.size()) {
    fail(path, "bufferView " + std::to_string(acc.bufferView) + " refers to missing buffer " + std::to_string(view.buffer), fix);
  }
  const std::size_t bufferSize = model.buffers[std::size_t(view.buffer)].data.size();
  if (view.byteOffset > bufferSize || view.byteLength > bufferSize - view.byteOffset) {
    fail(path, "bufferView " + std::to_string(acc.bufferView) + " (offset " + std::to_string(view.byteOffset) +
         ", length " + std::to_string(view.byteLength) + ") lies outside its " + std::to_string(bufferSize) + "-byte buffer", fix);
  }
  const std::size_t elementSize = std::size_t(tinygltf::GetComponentSizeInBytes(std::uint32_t(acc.componentType))) *
                                  std::size_t(tinygltf::GetNumComponentsInType(std::uint32_t(acc.type)));
  ElementView out;
  out.count = acc.count;
  out.stride = view.byteStride != 0 ? view.byteStride : elementSize;
  out.componentType = acc.componentType;
  out.base = model.buffers[std::size_t(view.buffer)].data.data() + view.byteOffset + acc.byteOffset;
  if (acc.count == 0) return out;
  // offset + stride * (count - 1) + elementSize <= byteLength, written so nothing can overflow.
  const bool fits = acc.byteOffset <= view.byteLength && elementSize <= view.byteLength - acc.byteOffset &&
                    acc.count - 1 <= (view.byteLength - acc.byteOffset - elementSize) / out.stride;
  if (!fits) {
    fail(path, name + " (offset " + std::to_string(acc.byteOffset) + ", " + std::to_string(acc.count) +
         " elements, stride " + std::to_string(out.stride) + ") reads past the end of its " +
         std::to_string(view.byteLength) + "-byte bufferView " + std::to_string(acc.bufferView), fix);
  }
  return out;
}

std::vector<float> readFloats(const ElementView& v, std::size_t components) {
  std::vector<float> out(v.count * components);
  for (std::size_t i = 0; i < v.count; ++i) std::memcpy(&out[i * components], v.base + i * v.stride, components * 4);
  return out;
}

std::vector<glm::vec3> readVec3(const ElementView& v) {
  std::vector<glm::vec3> out(v.count);
  for (std::size_t i = 0; i < v.count; ++i) std::memcpy(&out[i], v.base + i * v.stride, sizeof(glm::vec3));  // little-endian host
  return out;
}

std::vector<std::uint32_t> readIndices(const ElementView& v) {
  std::vector<std::uint32_t> out(v.count);
  for (std::size_t i = 0; i < v.count; ++i) {
    const unsigned char* p = v.base + i * v.stride;
    if (v.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
      out[i] = *p;
    } else if (v.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
      std::uint16_t s;
      std::memcpy(&s, p, 2);
      out[i] = s;
    } else {
      std::memcpy(&out[i], p, 4);
    }
  }
  return out;
}

}  // namespace penumbra::gltf
