#include "core/gltf_accessor.h"

#include <algorithm>
#include <cstring>

namespace penumbra::gltf {

[[noreturn]] void fail(const std::string& path, const std::string& problem, const std::string& fix) {
  throw InputError("glTF '" + path + "': " + problem + "; " + fix);
}

namespace {

const std::string kCorrupt = "the file is corrupt; re-export it";

// `count` elements of `elementSize` bytes, `stride` apart, from byte `offset` of a bufferView.
struct Span {
  const unsigned char* base = nullptr;
  std::size_t stride = 0;
};

// The bytes of `count` elements in bufferView `viewIndex` from `offset`; `strided`: the view's
// byteStride applies (vertex attributes; sparse indices and values are tightly packed).
Span checkedSpan(const tinygltf::Model& model, int viewIndex, std::size_t offset, std::size_t count,
                 std::size_t elementSize, bool strided, const std::string& name, const std::string& path) {
  if (viewIndex < 0 || std::size_t(viewIndex) >= model.bufferViews.size()) {
    fail(path, name + " refers to bufferView " + std::to_string(viewIndex) + ", which does not exist", kCorrupt);
  }
  const tinygltf::BufferView& view = model.bufferViews[std::size_t(viewIndex)];
  if (view.buffer < 0 || std::size_t(view.buffer) >= model.buffers.size()) {
    fail(path, "bufferView " + std::to_string(viewIndex) + " refers to missing buffer " + std::to_string(view.buffer),
         kCorrupt);
  }
  const std::size_t bufferSize = model.buffers[std::size_t(view.buffer)].data.size();
  if (view.byteOffset > bufferSize || view.byteLength > bufferSize - view.byteOffset) {
    fail(path,
         "bufferView " + std::to_string(viewIndex) + " (offset " + std::to_string(view.byteOffset) + ", length " +
             std::to_string(view.byteLength) + ") lies outside its " + std::to_string(bufferSize) + "-byte buffer",
         kCorrupt);
  }
  Span span;
  span.stride = strided && view.byteStride != 0 ? view.byteStride : elementSize;
  span.base = model.buffers[std::size_t(view.buffer)].data.data() + view.byteOffset;
  if (count == 0) return span;
  // offset + stride * (count - 1) + elementSize <= byteLength, written so nothing can overflow.
  const bool fits = offset <= view.byteLength && elementSize <= view.byteLength - offset &&
                    count - 1 <= (view.byteLength - offset - elementSize) / span.stride;
  if (!fits) {
    fail(path,
         name + " (offset " + std::to_string(offset) + ", " + std::to_string(count) + " elements, stride " +
             std::to_string(span.stride) + ") reads past the end of its " + std::to_string(view.byteLength) +
             "-byte bufferView " + std::to_string(viewIndex),
         kCorrupt);
  }
  span.base += offset;
  return span;
}

bool isIndexType(int componentType) {
  return componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
         componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
         componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

bool isAttributeType(int componentType) {
  return componentType == TINYGLTF_COMPONENT_TYPE_FLOAT || componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
         componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || componentType == TINYGLTF_COMPONENT_TYPE_SHORT ||
         componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
}

// One component as the specification reads it (little-endian host); normalized integers map to
// [0, 1] (unsigned) or [-1, 1] (signed, the most negative value clamped).
double component(const unsigned char* p, int componentType, bool normalized) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float f;
      std::memcpy(&f, p, 4);
      return f;
    }
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const auto v = static_cast<std::int8_t>(*p);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return normalized ? *p / 255.0 : *p;
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      std::int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    default: {  // UNSIGNED_INT (indices only)
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

// Elements an accessor without a bufferView may declare: it holds no data to bound its count.
constexpr std::size_t kMaxZeroFilled = std::size_t(1) << 26;

// Checks accessor `index` against `kind` and the bytes it reads, calls begin(components), then
// sink(i, value) for every component i (element * width + c): the bufferView's values (zeros
// without one), then the sparse substitutions.
template <typename Begin, typename Sink>
void visit(const tinygltf::Model& model, int index, const std::string& what, const std::string& path, Kind kind,
           Begin begin, Sink sink) {
  const std::string name = what + " accessor " + std::to_string(index);
  if (index < 0 || std::size_t(index) >= model.accessors.size()) {
    fail(path, name + " does not exist (the file has " + std::to_string(model.accessors.size()) + " accessors)",
         kCorrupt);
  }
  const tinygltf::Accessor& acc = model.accessors[std::size_t(index)];
  const bool indices = kind == Kind::Indices;
  const int type = kind == Kind::Vec3   ? TINYGLTF_TYPE_VEC3
                   : kind == Kind::Vec4 ? TINYGLTF_TYPE_VEC4
                   : kind == Kind::Vec2 ? TINYGLTF_TYPE_VEC2
                                        : TINYGLTF_TYPE_SCALAR;
  if (acc.type != type ||
      !(indices ? isIndexType(acc.componentType) && !acc.normalized : isAttributeType(acc.componentType))) {
    static const char* const expected[] = {"a VEC3", "a VEC4", "a SCALAR", "an unsigned integer SCALAR", "a VEC2"};
    fail(path,
         name + " has type " + std::to_string(acc.type) + " / componentType " + std::to_string(acc.componentType) +
             (acc.normalized ? " (normalized)" : "") + ", expected " + expected[int(kind)] +
             (indices ? "" : " of float or 8/16-bit integers"),
         "re-export with standard formats");
  }
  const std::size_t width = std::size_t(tinygltf::GetNumComponentsInType(std::uint32_t(acc.type)));
  const std::size_t size = std::size_t(tinygltf::GetComponentSizeInBytes(std::uint32_t(acc.componentType)));
  Span data;
  if (acc.bufferView >= 0) {
    data = checkedSpan(model, acc.bufferView, acc.byteOffset, acc.count, size * width, true, name, path);
  } else if (acc.count > kMaxZeroFilled) {
    fail(path, name + " has no bufferView but declares " + std::to_string(acc.count) + " elements", kCorrupt);
  }
  const auto& sparse = acc.sparse;
  if (sparse.isSparse &&
      (sparse.count < 1 || std::size_t(sparse.count) > acc.count || !isIndexType(sparse.indices.componentType) ||
       sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0)) {
    fail(path,
         name + " has a sparse part of " + std::to_string(sparse.count) + " elements with index type " +
             std::to_string(sparse.indices.componentType) + " (1.." + std::to_string(acc.count) +
             " unsigned ones expected)",
         kCorrupt);
  }
  const std::size_t count = sparse.isSparse ? std::size_t(sparse.count) : 0;
  const std::size_t indexSize =
      count ? std::size_t(tinygltf::GetComponentSizeInBytes(std::uint32_t(sparse.indices.componentType))) : 0;
  const Span is = count ? checkedSpan(model, sparse.indices.bufferView, std::size_t(sparse.indices.byteOffset), count,
                                      indexSize, false, name + "'s sparse indices", path)
                        : Span{};
  const Span vs = count ? checkedSpan(model, sparse.values.bufferView, std::size_t(sparse.values.byteOffset), count,
                                      size * width, false, name + "'s sparse values", path)
                        : Span{};

  begin(acc.count * width);
  for (std::size_t e = 0; e < acc.count; ++e) {  // without a bufferView: zeros (glTF 2.0, 3.6.2.3)
    for (std::size_t c = 0; c < width; ++c) {
      sink(e * width + c,
           data.base ? component(data.base + e * data.stride + c * size, acc.componentType, acc.normalized) : 0.0);
    }
  }
  for (std::size_t k = 0; k < count; ++k) {
    const auto e = std::size_t(component(is.base + k * indexSize, sparse.indices.componentType, false));
    if (e >= acc.count) {
      fail(path,
           name + "'s sparse index " + std::to_string(e) + " is past its " + std::to_string(acc.count) + " elements",
           kCorrupt);
    }
    for (std::size_t c = 0; c < width; ++c) {
      sink(e * width + c, component(vs.base + k * size * width + c * size, acc.componentType, acc.normalized));
    }
  }
}

}  // namespace

std::vector<float> readFloats(const tinygltf::Model& model, int index, const std::string& what, const std::string& path,
                              Kind kind) {
  std::vector<float> out;
  visit(
      model, index, what, path, kind, [&](std::size_t n) { out.resize(n); },
      [&](std::size_t i, double v) { out[i] = float(v); });
  return out;
}

std::vector<glm::vec3> readVec3(const tinygltf::Model& model, int index, const std::string& what,
                                const std::string& path) {
  const std::vector<float> f = readFloats(model, index, what, path, Kind::Vec3);
  std::vector<glm::vec3> out(f.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {f[3 * i], f[3 * i + 1], f[3 * i + 2]};
  return out;
}

std::vector<glm::vec2> readVec2(const tinygltf::Model& model, int index, const std::string& what,
                                const std::string& path) {
  const std::vector<float> f = readFloats(model, index, what, path, Kind::Vec2);
  std::vector<glm::vec2> out(f.size() / 2);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {f[2 * i], f[2 * i + 1]};
  return out;
}

std::vector<std::uint32_t> readIndices(const tinygltf::Model& model, int index, const std::string& what,
                                       const std::string& path) {
  std::vector<std::uint32_t> out;
  visit(
      model, index, what, path, Kind::Indices, [&](std::size_t n) { out.resize(n); },
      [&](std::size_t i, double v) { out[i] = std::uint32_t(v); });
  return out;
}

}  // namespace penumbra::gltf
