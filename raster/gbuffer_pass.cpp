#include "raster/gbuffer_pass.h"

#include "gbuffer_cutout_frag.h"
#include "gbuffer_frag.h"
#include "gbuffer_textured_frag.h"
#include "gbuffer_textured_vert.h"
#include "gbuffer_vert.h"
#include "shared/gbuffer.h"
#include "shared/raster.h"

namespace penumbra::raster {
namespace {

using Usage = vk::ImageUsageFlagBits;
constexpr vk::Format kPositionFormat = vk::Format::eR32G32B32A32Sfloat;
constexpr vk::Format kNormalFormat = vk::Format::eR32G32B32A32Sfloat;
constexpr vk::Format kAlbedoFormat = vk::Format::eR8G8B8A8Unorm;
constexpr vk::Format kFaceNormalFormat = vk::Format::eR32Uint;

enum class Draws { Plain, Textured, Cutout };

// The camera pass's pipeline for meshes without textures, with a colour texture, or cut out (with
// the alpha test, and a colour texture or white).
gpu::GraphicsPipelineDesc pipelineDesc(Draws draws) {
  using Spirv = std::span<const std::uint32_t>;
  gpu::GraphicsPipelineDesc d;
  d.vertexSpirv = draws == Draws::Plain ? Spirv(gbuffer_vert) : Spirv(gbuffer_textured_vert);
  d.fragmentSpirv = draws == Draws::Plain      ? Spirv(gbuffer_frag)
                    : draws == Draws::Textured ? Spirv(gbuffer_textured_frag)
                                               : Spirv(gbuffer_cutout_frag);
  d.vertexBindings = {{.binding = 0, .stride = sizeof(RasterVertex), .inputRate = vk::VertexInputRate::eVertex}};
  d.vertexAttributes = {{0, 0, vk::Format::eR32G32B32Sfloat, offsetof(RasterVertex, position)},
                        {1, 0, vk::Format::eR32G32B32Sfloat, offsetof(RasterVertex, normal)},
                        {2, 0, vk::Format::eR32G32B32Sfloat, offsetof(RasterVertex, color)}};
  d.colorFormats = {kPositionFormat, kNormalFormat, kAlbedoFormat, kFaceNormalFormat};  // GBUFFER_POSITION, _NORMAL, _ALBEDO, _FACE_NORMAL
  d.depthCompare = vk::CompareOp::eGreater;  // reversed depth (ViewMatrices::reversedDepthViewProj)
  d.pushConstantBytes = draws == Draws::Plain ? sizeof(shared::GBufferPush) : sizeof(shared::CutoutDrawPush);
  d.name = draws == Draws::Plain      ? "gbuffer pipeline"
           : draws == Draws::Textured ? "gbuffer textured pipeline"
                                      : "gbuffer cutout pipeline";
  if (draws != Draws::Plain) {
    readTextureCoordinates(d);
    d.bindings = {{GBUFFER_BINDING_COLOR, vk::DescriptorType::eCombinedImageSampler}};
  }
  return d;
}

}  // namespace

GBufferPass::GBufferPass(const gpu::Context& context, const Scene& scene, std::uint32_t width, std::uint32_t height)
    : width_(width),
      height_(height),
      position_(context, {kPositionFormat, width, height, 1,
                          Usage::eColorAttachment | Usage::eStorage | Usage::eTransferSrc, "gbuffer position"}),
      normal_(context, {kNormalFormat, width, height, 1,
                        Usage::eColorAttachment | Usage::eStorage | Usage::eTransferSrc, "gbuffer normal"}),
      albedo_(context, {kAlbedoFormat, width, height, 1, Usage::eColorAttachment | Usage::eStorage, "gbuffer albedo"}),
      faceNormal_(context, {kFaceNormalFormat, width, height, 1, Usage::eColorAttachment | Usage::eStorage,
                            "gbuffer face normal"}),
      depth_(context, {vk::Format::eD32Sfloat, width, height, 1, Usage::eDepthStencilAttachment, "gbuffer depth"}),
      positionReadback_(context, position_.bytes(), vk::BufferUsageFlagBits::eTransferDst, "gbuffer position readback"),
      normalReadback_(context, normal_.bytes(), vk::BufferUsageFlagBits::eTransferDst, "gbuffer normal readback"),
      textures_(context, scene),
      pipeline_(context, pipelineDesc(Draws::Plain)),
      texturedPipeline_(context, pipelineDesc(Draws::Textured)),
      cutoutPipeline_(context, pipelineDesc(Draws::Cutout)) {}

void GBufferPass::record(const vk::raii::CommandBuffer& cmd, const SceneGeometry& geometry, const ViewMatrices& view,
                         const glm::vec3& cameraPosition) const {
  using Stage = vk::PipelineStageFlagBits2;
  using Access = vk::AccessFlagBits2;
  const gpu::Transition toAttachment{vk::ImageLayout::eUndefined, vk::ImageLayout::eColorAttachmentOptimal,
                                     Stage::eAllCommands, Access::eMemoryRead | Access::eMemoryWrite,
                                     Stage::eColorAttachmentOutput, Access::eColorAttachmentWrite};
  for (const gpu::Image* image : {&position_, &normal_, &albedo_, &faceNormal_}) gpu::transition(cmd, *image, toAttachment);
  gpu::transition(cmd, depth_, {vk::ImageLayout::eUndefined, vk::ImageLayout::eDepthAttachmentOptimal, Stage::eAllCommands,
                                Access::eMemoryWrite, Stage::eEarlyFragmentTests | Stage::eLateFragmentTests,
                                Access::eDepthStencilAttachmentWrite | Access::eDepthStencilAttachmentRead});

  // Position w = 0 and a zero normal mark pixels no triangle covers.
  auto colorAttachment = [](const gpu::Image& image) {
    return vk::RenderingAttachmentInfo{.imageView = image.view(),
                                       .imageLayout = vk::ImageLayout::eColorAttachmentOptimal,
                                       .loadOp = vk::AttachmentLoadOp::eClear,
                                       .storeOp = vk::AttachmentStoreOp::eStore,
                                       .clearValue = vk::ClearColorValue(std::array<float, 4>{0, 0, 0, 0})};
  };
  const std::array<vk::RenderingAttachmentInfo, GBUFFER_COUNT> colors{colorAttachment(position_), colorAttachment(normal_),
                                                                      colorAttachment(albedo_), colorAttachment(faceNormal_)};
  const vk::RenderingAttachmentInfo depth{.imageView = depth_.view(),
                                          .imageLayout = vk::ImageLayout::eDepthAttachmentOptimal,
                                          .loadOp = vk::AttachmentLoadOp::eClear,
                                          .storeOp = vk::AttachmentStoreOp::eDontCare,
                                          .clearValue = vk::ClearValue{.depthStencil = {.depth = 0.0f, .stencil = 0}}};
  const vk::Rect2D area{{0, 0}, {width_, height_}};
  cmd.beginRendering({.renderArea = area, .layerCount = 1, .colorAttachmentCount = std::uint32_t(colors.size()),
                      .pColorAttachments = colors.data(), .pDepthAttachment = &depth});
  cmd.setViewport(0, vk::Viewport{0.0f, 0.0f, float(width_), float(height_), 0.0f, 1.0f});
  cmd.setScissor(0, area);
  pipeline_.bind(cmd, gpu::Descriptors{});
  pipeline_.pushConstants(cmd, shared::GBufferPush{view.reversedDepthViewProj, glm::vec4(cameraPosition, 1.0f)});
  geometry.bind(cmd);
  geometry.drawPlain(cmd);
  const glm::vec4 camera(cameraPosition, 1.0f);
  // Each draw pushes its colour texture to the bound pipeline (Descriptors point into themselves:
  // made in place).
  const auto pushTexture = [&](const gpu::GraphicsPipeline& pipeline, std::int32_t texture) {
    gpu::Descriptors color;
    color.sampledImage(GBUFFER_BINDING_COLOR, textures_.view(texture), textures_.sampler());
    pipeline.pushDescriptors(cmd, color);
  };
  texturedPipeline_.bind(cmd, gpu::Descriptors{});
  texturedPipeline_.pushConstants(
      cmd, shared::CutoutDrawPush{.viewProj = view.reversedDepthViewProj, .cameraPosition = camera});
  geometry.drawTextured(cmd, [&](const TexturedDraw& draw) { pushTexture(texturedPipeline_, draw.colorTexture); });
  cutoutPipeline_.bind(cmd, gpu::Descriptors{});
  geometry.drawCutouts(cmd, [&](const CutoutDraw& draw) {
    pushTexture(cutoutPipeline_, draw.colorTexture);
    cutoutPipeline_.pushConstants(cmd, geometry.cutoutPush(view.reversedDepthViewProj, camera, draw));
  });
  cmd.endRendering();

  const gpu::Transition toGeneral{vk::ImageLayout::eColorAttachmentOptimal, vk::ImageLayout::eGeneral,
                                  Stage::eColorAttachmentOutput, Access::eColorAttachmentWrite,
                                  Stage::eComputeShader | Stage::eCopy, Access::eShaderStorageRead | Access::eTransferRead};
  for (const gpu::Image* image : {&position_, &normal_, &albedo_, &faceNormal_}) gpu::transition(cmd, *image, toGeneral);
}

void GBufferPass::recordReadback(const vk::raii::CommandBuffer& cmd) const {
  gpu::copyImageToBuffer(cmd, position_, positionReadback_);
  gpu::copyImageToBuffer(cmd, normal_, normalReadback_);
}

std::vector<glm::vec4> GBufferPass::positions() const { return positionReadback_.download<glm::vec4>(std::size_t(width_) * height_); }
std::vector<glm::vec4> GBufferPass::normals() const { return normalReadback_.download<glm::vec4>(std::size_t(width_) * height_); }

}  // namespace penumbra::raster
