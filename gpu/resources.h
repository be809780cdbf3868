// GPU memory owners: buffers (host-visible, persistently mapped) and images (device-local),
// plus the barrier and readback helpers every pass uses.
#pragma once
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "gpu/context.h"

namespace penumbra::gpu {

// Host-visible, coherent and mapped: on lavapipe all memory is host memory, and on a discrete
// GPU this is still correct (just not the fastest place for big read-only data).
class Buffer {
 public:
  Buffer(const Context& context, vk::DeviceSize size, vk::BufferUsageFlags usage, const std::string& name);
  vk::Buffer handle() const { return *buffer_; }
  // Buffers made with eShaderDeviceAddress usage (acceleration-structure inputs, and what kernels
  // read through addresses): queried once, at creation. std::logic_error for other buffers.
  vk::DeviceAddress address() const;
  vk::DeviceSize size() const { return size_; }
  void* data() const { return mapped_; }

  template <typename T>
  void upload(std::span<const T> values) {
    checkFits(values.size_bytes());
    if (!values.empty()) std::memcpy(mapped_, values.data(), values.size_bytes());  // an empty span's data() may be null
  }
  template <typename T>
  std::vector<T> download(std::size_t count) const {
    checkFits(count * sizeof(T));
    std::vector<T> out(count);
    if (count != 0) std::memcpy(out.data(), mapped_, count * sizeof(T));  // an empty vector's data() may be null
    return out;
  }

 private:
  void checkFits(std::size_t bytes) const;
  vk::DeviceSize size_;
  vk::raii::Buffer buffer_;
  vk::raii::DeviceMemory memory_{nullptr};
  void* mapped_ = nullptr;
  vk::DeviceAddress address_ = 0;  // 0: no eShaderDeviceAddress usage
};

// A buffer's device address as the shaders take it: (low, high) 32-bit halves, for
// GL_EXT_buffer_reference_uvec2. The buffer needs eShaderDeviceAddress usage.
inline glm::uvec2 addressHalves(const Buffer& buffer) {
  const vk::DeviceAddress a = buffer.address();
  return {std::uint32_t(a), std::uint32_t(a >> 32)};
}

struct ImageDesc {
  vk::Format format = vk::Format::eR32G32B32A32Sfloat;
  std::uint32_t width = 1;
  std::uint32_t height = 1;
  std::uint32_t layers = 1;
  vk::ImageUsageFlags usage;
  std::string name;
  bool arrayView = false;  // view() is a 2D array even with one layer (for sampler2DArray)
  std::uint32_t mipLevels = 1;  // views and transitions cover them all
};

class Image {
 public:
  Image(const Context& context, const ImageDesc& desc);
  vk::Image handle() const { return *image_; }
  vk::ImageView view() const { return *view_; }  // 2D for one layer unless desc.arrayView, 2D array otherwise
  vk::ImageView layerView(std::uint32_t layer) const { return *layerViews_.at(layer); }
  const ImageDesc& desc() const { return desc_; }
  vk::ImageAspectFlags aspect() const;
  vk::DeviceSize bytes() const;  // texel storage, for memory reports

 private:
  ImageDesc desc_;
  vk::raii::Image image_;
  vk::raii::DeviceMemory memory_{nullptr};
  vk::raii::ImageView view_{nullptr};
  std::vector<vk::raii::ImageView> layerViews_;
};

// One image layout transition with the hazards it must order (synchronization2).
struct Transition {
  vk::ImageLayout from;
  vk::ImageLayout to;
  vk::PipelineStageFlags2 srcStage;
  vk::AccessFlags2 srcAccess;
  vk::PipelineStageFlags2 dstStage;
  vk::AccessFlags2 dstAccess;
};
void transition(const vk::raii::CommandBuffer& cmd, const Image& image, const Transition& t);

// Makes compute-shader buffer writes visible to later compute reads and host reads.
void computeToComputeAndHost(const vk::raii::CommandBuffer& cmd);

// One global memory barrier.
void memoryBarrier(const vk::raii::CommandBuffer& cmd, vk::PipelineStageFlags2 srcStage, vk::AccessFlags2 srcAccess,
                   vk::PipelineStageFlags2 dstStage, vk::AccessFlags2 dstAccess);

// Copies every layer of `image` (in GENERAL layout, left so) into `buffer`, tightly packed.
void copyImageToBuffer(const vk::raii::CommandBuffer& cmd, const Image& image, const Buffer& buffer);

std::uint32_t bytesPerTexel(vk::Format format);

}  // namespace penumbra::gpu
