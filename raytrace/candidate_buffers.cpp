#include "raytrace/candidate_buffers.h"

#include <string>

#include "gpu/upload.h"

namespace penumbra {
namespace {
constexpr vk::BufferUsageFlags kStorage = vk::BufferUsageFlagBits::eStorageBuffer;
}  // namespace

CandidateBuffers::CandidateBuffers(const gpu::Context& context, const CandidateLineSpace& ls,
                                   std::span<const std::uint32_t> nodeMap, CandidateBindings bindings)
    : at_(bindings),
      boxes_(gpu::uploadedBuffer(context, std::span<const shared::CsBox>(ls.boxes), kStorage, "candidate boxes")),
      bits_(gpu::uploadedBuffer(context, std::span<const std::uint32_t>(ls.bits), kStorage, "candidate bits")),
      offsets_(gpu::uploadedBuffer(context, std::span<const std::uint32_t>(ls.offsets), kStorage, "candidate offsets")),
      candidates_(gpu::uploadedBuffer(context, std::span<const std::uint32_t>(ls.candidates),
                                      kStorage | vk::BufferUsageFlagBits::eShaderDeviceAddress, "candidates")),
      nodeMap_(gpu::uploadedBuffer(context, nodeMap, kStorage, "candidate node map")) {}

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
