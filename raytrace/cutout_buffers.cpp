#include "raytrace/cutout_buffers.h"

#include <algorithm>

namespace penumbra {
namespace {

// A buffer of `values` read through its address; one unused word when there are none.
template <typename T>
gpu::Buffer uploaded(const gpu::Context& context, const std::vector<T>& values, const char* name) {
  gpu::Buffer buffer(context, std::max<vk::DeviceSize>(16, values.size() * sizeof(T)),
                     vk::BufferUsageFlagBits::eShaderDeviceAddress, name);
  buffer.upload(std::span<const T>(values));
  return buffer;
}

}  // namespace

CutoutBuffers::CutoutBuffers(const gpu::Context& context, const Scene& scene)
    : CutoutBuffers(context, cutoutData(scene)) {}

CutoutBuffers::CutoutBuffers(const gpu::Context& context, const CutoutData& data)
    : triangles_(uploaded(context, data.triangles, "cutout triangles")),
      texels_(uploaded(context, data.texels, "cutout texels")) {}

shared::BvhAddresses CutoutBuffers::with(shared::BvhAddresses bvh) const {
  bvh.cutouts = gpu::addressHalves(triangles_);
  bvh.cutoutTexels = gpu::addressHalves(texels_);
  return bvh;
}

}  // namespace penumbra
