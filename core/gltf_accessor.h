// Bounds-checked reading of glTF accessors (files are untrusted), shared by the mesh loader and
// the animation reader. Every failure is an InputError naming the file, the accessor and the fix.
// One reader takes every form glTF 2.0 allows: float or integer components (normalized ones
// mapped to [-1, 1] or [0, 1] as the specification says, as KHR_mesh_quantization writes them),
// any byteStride, no bufferView (all zeros), and sparse substitutions on top.
#pragma once
#include <tiny_gltf.h>

#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "core/scene.h"

namespace penumbra::gltf {

[[noreturn]] void fail(const std::string& path, const std::string& problem, const std::string& fix);

// What a caller reads: VEC2, VEC3, VEC4 or SCALAR of float or (normalized) 8/16-bit integer components,
// or unsigned integer SCALAR indices.
enum class Kind { Vec3, Vec4, Scalar, Indices, Vec2 };

std::vector<float> readFloats(const tinygltf::Model& model, int index, const std::string& what, const std::string& path,
                              Kind kind);
std::vector<glm::vec3> readVec3(const tinygltf::Model& model, int index, const std::string& what,
                                const std::string& path);
std::vector<glm::vec2> readVec2(const tinygltf::Model& model, int index, const std::string& what,
                                const std::string& path);
std::vector<std::uint32_t> readIndices(const tinygltf::Model& model, int index, const std::string& what,
                                       const std::string& path);

}  // namespace penumbra::gltf
