#include "raytrace/ray_batches.h"

#include <algorithm>

namespace penumbra {
namespace {
constexpr std::size_t kRaysPerSubmit = std::size_t(1) << 20;  // staging: 32 MiB in, 16 MiB out
}

std::vector<shared::RayHit> RayBatches::trace(std::span<const shared::RayQuery> rays, std::uint32_t groupSize,
                                              const Dispatch& dispatch) {
  std::vector<shared::RayHit> out(rays.size());
  const std::size_t batchCapacity = std::min(rays.size(), kRaysPerSubmit);
  if (batchCapacity > 0 && (!queries_ || queries_->size() < batchCapacity * sizeof(shared::RayQuery))) {
    queries_.emplace(context_, batchCapacity * sizeof(shared::RayQuery), vk::BufferUsageFlagBits::eStorageBuffer,
                     name_ + " ray queries");
    hits_.emplace(context_, batchCapacity * sizeof(shared::RayHit), vk::BufferUsageFlagBits::eStorageBuffer,
                  name_ + " ray hits");
  }
  const std::uint32_t maxGroups =
      std::min(context_.physicalDevice().getProperties().limits.maxComputeWorkGroupCount[0], 65535u);
  for (std::size_t begin = 0; begin < rays.size(); begin += kRaysPerSubmit) {
    const auto batch = rays.subspan(begin, std::min(kRaysPerSubmit, rays.size() - begin));
    queries_->upload(batch);
    context_.submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
      // Dispatches write disjoint ranges, so they need no barriers between them.
      const std::size_t perDispatch = std::size_t(maxGroups) * groupSize;
      for (std::size_t first = 0; first < batch.size(); first += perDispatch) {
        dispatch(cmd, *queries_, *hits_, std::uint32_t(first), std::uint32_t(std::min(perDispatch, batch.size() - first)));
      }
      gpu::computeToComputeAndHost(cmd);
    });
    const auto hits = hits_->download<shared::RayHit>(batch.size());
    std::copy(hits.begin(), hits.end(), out.begin() + std::ptrdiff_t(begin));
  }
  return out;
}

}  // namespace penumbra
