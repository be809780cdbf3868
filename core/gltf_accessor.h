// Bounds-checked reading of glTF accessors (files are untrusted), shared by the mesh loader and
// the animation reader. Every failure is an InputError naming the file, the accessor and the fix.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <tiny_gltf.h>

#include "core/scene.h"

namespace penumbra::gltf {

[[noreturn]] void fail(const std::string& path, const std::string& problem, const std::string& fix);

struct ElementView {
  const unsigned char* base = nullptr;
  std::size_t count = 0, stride = 0;
  int componentType = 0;
};

enum class Kind { Vec3, Vec4, Scalar, Indices };  // FLOAT VEC3 / VEC4 / SCALAR; unsigned SCALAR indices

ElementView viewAccessor(const tinygltf::Model& model, int index, const std::string& what, const std::string& path,
                         Kind kind = Kind::Vec3);
std::vector<float> readFloats(const ElementView& v, std::size_t components);
std::vector<glm::vec3> readVec3(const ElementView& v);
std::vector<std::uint32_t> readIndices(const ElementView& v);

}  // namespace penumbra::gltf
