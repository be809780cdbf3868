#include "raytrace/candidate_buffers.h"

#include <algorithm>
#include <cstring>
#include <string>

namespace penumbra {
namespace {

// At least one element: bindings need a non-empty buffer.
template <typename T>
gpu::Buffer uploaded(const gpu::Context& context, std::span<const T> values, const std::string& name,
                     vk::BufferUsageFlags usage = vk::BufferUsageFlagBits::eStorageBuffer) {
  gpu::Buffer buffer(context, std::max<std::size_t>(values.size(), 1) * sizeof(T), usage, name);
  std::memset(buffer.data(), 0, buffer.size());
  buffer.upload(values);
  return buffer;
}

}  // namespace

CandidateBuffers::CandidateBuffers(const gpu::Context& context, const CandidateLineSpace& ls,
                                   std::span<const std::uint32_t> nodeMap, CandidateBindings bindings)
    : at_(bindings),
      boxes_(uploaded(context, std::span<const shared::CsBox>(ls.boxes), "candidate boxes")),
      bits_(uploaded(context, std::span<const std::uint32_t>(ls.bits), "candidate bits")),
      offsets_(uploaded(context, std::span<const std::uint32_t>(ls.offsets), "candidate offsets")),
      candidates_(uploaded(context, std::span<const std::uint32_t>(ls.candidates), "candidates",
                           vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eShaderDeviceAddress)),
      nodeMap_(uploaded(context, nodeMap, "candidate node map")) {}

gpu::Descriptors& CandidateBuffers::addBindings(gpu::Descriptors& descriptors) const {
  return descriptors.buffer(at_.boxes, boxes_)
      .buffer(at_.bits, bits_)
      .buffer(at_.offsets, offsets_)
      .buffer(at_.nodeMap, nodeMap_);
}

std::uint64_t CandidateBuffers::bytes() const {
  return boxes_.size() + bits_.size() + offsets_.size() + candidates_.size() + nodeMap_.size();
}

}  // namespace penumbra
