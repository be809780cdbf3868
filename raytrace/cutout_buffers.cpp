#include "raytrace/cutout_buffers.h"

#include "gpu/upload.h"

namespace penumbra {

CutoutBuffers::CutoutBuffers(const gpu::Context& context, const Scene& scene)
    : CutoutBuffers(context, cutoutData(scene)) {}

CutoutBuffers::CutoutBuffers(const gpu::Context& context, const CutoutData& data)
    : triangles_(gpu::uploadedBuffer(context, std::span(data.triangles), vk::BufferUsageFlagBits::eShaderDeviceAddress,
                                     "cutout triangles")),
      texels_(gpu::uploadedBuffer(context, std::span(data.texels), vk::BufferUsageFlagBits::eShaderDeviceAddress,
                                  "cutout texels")) {}

shared::BvhAddresses CutoutBuffers::with(shared::BvhAddresses bvh) const {
  bvh.cutouts = trianglesAddress();
  bvh.cutoutTexels = texelsAddress();
  return bvh;
}

}  // namespace penumbra
