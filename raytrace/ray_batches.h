// Arbitrary rays (shared::RayQuery in, shared::RayHit out) through a GPU kernel, in batches that
// fit host-visible staging buffers grown on demand: the part of traceRays every GPU tracer shares.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gpu/resources.h"
#include "shared/bvh.h"

namespace penumbra {

class RayBatches {
 public:
  // Records one dispatch of `count` rays starting at ray `first` of the staged batch.
  using Dispatch = std::function<void(const vk::raii::CommandBuffer& cmd, const gpu::Buffer& queries,
                                      const gpu::Buffer& hits, std::uint32_t first, std::uint32_t count)>;

  RayBatches(const gpu::Context& context, std::string name) : context_(context), name_(std::move(name)) {}
  // Stages the rays batch by batch, records `dispatch` for ranges of at most the device's
  // workgroup-count limit times groupSize rays, submits, waits and gathers the hits.
  std::vector<shared::RayHit> trace(std::span<const shared::RayQuery> rays, std::uint32_t groupSize,
                                    const Dispatch& dispatch);

 private:
  const gpu::Context& context_;
  std::string name_;
  std::optional<gpu::Buffer> queries_, hits_;
};

}  // namespace penumbra
