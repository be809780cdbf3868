// A host-visible buffer holding `values`, for data uploaded once (trees, tables, cut-outs).
#pragma once
#include <algorithm>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>

#include "gpu/resources.h"

namespace penumbra::gpu {

// Never empty (bindings and device addresses need a buffer): at least 16 bytes, zeros past the values.
template <typename T>
Buffer uploadedBuffer(const Context& context, std::span<T> values, vk::BufferUsageFlags usage, const std::string& name) {
  Buffer buffer(context, std::max<vk::DeviceSize>(16, values.size_bytes()), usage, name);
  std::memset(buffer.data(), 0, buffer.size());
  buffer.upload(std::span<const std::remove_const_t<T>>(values));
  return buffer;
}

}  // namespace penumbra::gpu
