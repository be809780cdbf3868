#include "raytrace/acceleration_structures.h"

#include <algorithm>
#include <chrono>
#include <cstring>

#include "core/cutouts.h"
#include "core/units.h"
#include "shared/ray_query.h"

namespace penumbra {
namespace {

using Usage = vk::BufferUsageFlagBits;
using Stage = vk::PipelineStageFlagBits2;
using Access = vk::AccessFlagBits2;
using BuildFlags = vk::BuildAccelerationStructureFlagBitsKHR;

constexpr vk::DeviceSize kStorageAlignment = 256;  // VkAccelerationStructureCreateInfoKHR::offset
const vk::BufferUsageFlags kInput = Usage::eAccelerationStructureBuildInputReadOnlyKHR | Usage::eShaderDeviceAddress;
const vk::BufferUsageFlags kStorage = Usage::eAccelerationStructureStorageKHR | Usage::eShaderDeviceAddress;

vk::DeviceSize alignUp(vk::DeviceSize value, vk::DeviceSize alignment) { return (value + alignment - 1) / alignment * alignment; }

std::uint32_t triangles(const Mesh& mesh) { return std::uint32_t(mesh.indices.size() / 3); }

// Spreads the low 10 bits of v to every third bit.
std::uint32_t spreadBits(std::uint32_t v) {
  v = (v * 0x00010001u) & 0xFF0000FFu;
  v = (v * 0x00000101u) & 0x0F00F00Fu;
  v = (v * 0x00000011u) & 0xC30C30C3u;
  return (v * 0x00000005u) & 0x49249249u;
}

// The mesh's triangles sorted by the 30-bit Morton code of their centroids in the mesh's bounds.
std::vector<std::uint32_t> spatialOrder(const Mesh& mesh) {
  Bounds bounds;
  for (const glm::vec3& p : mesh.positions) bounds.extend(p);
  const glm::vec3 scale = 1023.0f / glm::max(bounds.hi - bounds.lo, glm::vec3(1e-30f));
  std::vector<std::pair<std::uint32_t, std::uint32_t>> keyed(triangles(mesh));
  for (std::uint32_t t = 0; t < keyed.size(); ++t) {
    const glm::vec3 centroid =
        (mesh.positions[mesh.indices[3 * t]] + mesh.positions[mesh.indices[3 * t + 1]] + mesh.positions[mesh.indices[3 * t + 2]]) / 3.0f;
    const glm::uvec3 q(glm::clamp((centroid - bounds.lo) * scale, glm::vec3(0.0f), glm::vec3(1023.0f)));
    keyed[t] = {(spreadBits(q.x) << 2) | (spreadBits(q.y) << 1) | spreadBits(q.z), t};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::uint32_t> order(keyed.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
  return order;
}

// The mesh's indices in `order`.
void writeIndices(const Mesh& mesh, const std::vector<std::uint32_t>& order, std::uint32_t* out) {
  for (std::uint32_t t : order) {
    for (int k = 0; k < 3; ++k) *out++ = mesh.indices[3 * t + k];
  }
}

// One mesh's triangles as build input: float3 positions, uint32 indices; opaque (the driver commits
// its hits) unless the mesh is cut out (its candidates go to the shader's proceed loop).
vk::AccelerationStructureGeometryKHR triangleGeometry(vk::DeviceAddress vertices, vk::DeviceAddress indices,
                                                      std::size_t vertexCount, bool opaque) {
  return {.geometryType = vk::GeometryTypeKHR::eTriangles,
          .geometry = {.triangles = {.vertexFormat = vk::Format::eR32G32B32Sfloat,
                                     .vertexData = {.deviceAddress = vertices},
                                     .vertexStride = sizeof(glm::vec3),
                                     .maxVertex = std::uint32_t(std::max<std::size_t>(vertexCount, 1) - 1),
                                     .indexType = vk::IndexType::eUint32,
                                     .indexData = {.deviceAddress = indices}}},
          .flags = opaque ? vk::GeometryFlagBitsKHR::eOpaque : vk::GeometryFlagsKHR{}};
}

// Orders one build's writes (its structure and the shared scratch) before the next build.
void buildToBuild(const vk::raii::CommandBuffer& cmd) {
  gpu::memoryBarrier(cmd, Stage::eAccelerationStructureBuildKHR, Access::eAccelerationStructureWriteKHR,
                     Stage::eAccelerationStructureBuildKHR,
                     Access::eAccelerationStructureReadKHR | Access::eAccelerationStructureWriteKHR);
}

vk::AccelerationStructureBuildSizesInfoKHR buildSizes(const gpu::Context& context,
                                                      const vk::AccelerationStructureBuildGeometryInfoKHR& info,
                                                      std::uint32_t primitives) {
  return context.device().getAccelerationStructureBuildSizesKHR(vk::AccelerationStructureBuildTypeKHR::eDevice, info,
                                                                primitives);
}

}  // namespace

std::string defaultTracer(const gpu::Context& context) {
  const bool cpu = context.physicalDevice().getProperties().deviceType == vk::PhysicalDeviceType::eCpu;
  return context.rayQuery() && !cpu ? "rq" : "bvh";
}

SceneAccelerationStructures::SceneAccelerationStructures(const gpu::Context& context, const Scene& scene,
                                                         const BvhBuildSettings& settings, MeshSet set)
    : context_((context.requireRayQuery("ray queries"), context)),
      cutouts_(context, scene),
      policy_(scene, settings),
      instanceTargets_(scene.meshes.size(), 0),
      order_(scene.meshes.size()) {
  if (triangleCount(scene, set) == 0) throw InputError("rq: scene '" + scene.name + "' has no triangles to trace");
  const auto start = std::chrono::steady_clock::now();
  buildStatic(scene, set);
  buildMoving(scene, set);
  // Instances in mesh order, skipping meshes without structures; then the ids of their triangles
  // after the cut-outs' addresses and two words per instance (shared/ray_query.h).
  std::vector<vk::AccelerationStructureInstanceKHR> instances;
  std::vector<std::uint32_t> head, ids;
  for (glm::uvec2 a : {cutouts_.trianglesAddress(), cutouts_.texelsAddress()}) head.insert(head.end(), {a.x, a.y});
  const std::vector<std::uint32_t> firstCutout = cutoutIndices(scene);
  std::uint32_t id = 0;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    if (instanceTargets_[m]) {
      vk::AccelerationStructureInstanceKHR instance{};
      const float identity[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
      std::memcpy(&instance.transform, identity, sizeof(identity));
      instance.mask = 0xff;
      using InstanceFlag = vk::GeometryInstanceFlagBitsKHR;
      instance.flags = VkGeometryInstanceFlagsKHR(InstanceFlag::eTriangleFacingCullDisable);
      if (!scene.meshes[m].cutout) instance.flags |= VkGeometryInstanceFlagsKHR(InstanceFlag::eForceOpaque);
      instance.accelerationStructureReference = instanceTargets_[m];
      instances.push_back(instance);
      head.insert(head.end(), {std::uint32_t(ids.size()), firstCutout[m] ? firstCutout[m] - id : 0u});
      for (std::uint32_t t : order_[m]) ids.push_back(id + t);
    }
    id += triangles(scene.meshes[m]);
  }
  for (std::size_t i = RQ_IDS_INSTANCES; i < head.size(); i += 2) head[i] += std::uint32_t(head.size());
  head.insert(head.end(), ids.begin(), ids.end());
  order_ = {};
  triangleIds_.emplace(context_, head.size() * sizeof(std::uint32_t), vk::BufferUsageFlagBits::eStorageBuffer,
                       "rq triangle ids");
  triangleIds_->upload(std::span<const std::uint32_t>(head));
  instances_.emplace(context_, instances.size() * sizeof(vk::AccelerationStructureInstanceKHR), kInput, "rq instances");
  instances_->upload(std::span<const vk::AccelerationStructureInstanceKHR>(instances));
  context_.submitAndWait([&](const vk::raii::CommandBuffer& cmd) { buildTop(cmd, false); });
  if (moving_.empty()) scratch_.reset();  // updates need it again; static scenes never do
  stats_.bytes += instances_->size() + topStorage_->size() + triangleIds_->size() + cutouts_.bytes();
  stats_.buildMs = msSince(start);
}

vk::DeviceAddress SceneAccelerationStructures::scratch(vk::DeviceSize bytes) {
  if (!scratchAlignment_) {  // asked once: update() calls this every frame
    const auto props = context_.physicalDevice()
                           .getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceAccelerationStructurePropertiesKHR>()
                           .get<vk::PhysicalDeviceAccelerationStructurePropertiesKHR>();
    scratchAlignment_ = std::max<vk::DeviceSize>(props.minAccelerationStructureScratchOffsetAlignment, 1);
  }
  const vk::DeviceSize alignment = scratchAlignment_;
  if (!scratch_ || scratch_->size() < bytes + alignment) {
    scratch_.emplace(context_, bytes + alignment, Usage::eStorageBuffer | Usage::eShaderDeviceAddress, "rq scratch");
    stats_.scratchBytes = std::max(stats_.scratchBytes, bytes);
  }
  return alignUp(scratch_->address(), alignment);
}

void SceneAccelerationStructures::buildStatic(const Scene& scene, MeshSet set) {
  std::vector<std::size_t> meshes;
  std::size_t vertexCount = 0, indexCount = 0;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    if (scene.meshes[m].dynamic || !inMeshSet(scene.meshes[m], set) || triangles(scene.meshes[m]) == 0) continue;
    meshes.push_back(m);
    vertexCount += scene.meshes[m].positions.size();
    indexCount += scene.meshes[m].indices.size();
  }
  if (meshes.empty()) return;
  // Inputs in two buffers shared by all static meshes, freed once the structures are built.
  gpu::Buffer vertices(context_, vertexCount * sizeof(glm::vec3), kInput, "rq static vertices");
  gpu::Buffer indices(context_, indexCount * sizeof(std::uint32_t), kInput, "rq static indices");
  std::vector<vk::AccelerationStructureGeometryKHR> geometries;
  std::vector<vk::AccelerationStructureBuildGeometryInfoKHR> infos;
  std::vector<vk::DeviceSize> offsets;
  geometries.reserve(meshes.size());
  vk::DeviceSize storageBytes = 0, scratchBytes = 0;
  std::size_t v = 0, i = 0;
  for (std::size_t m : meshes) {
    const Mesh& mesh = scene.meshes[m];
    std::memcpy(static_cast<glm::vec3*>(vertices.data()) + v, mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3));
    order_[m] = spatialOrder(mesh);
    writeIndices(mesh, order_[m], static_cast<std::uint32_t*>(indices.data()) + i);
    geometries.push_back(triangleGeometry(vertices.address() + v * sizeof(glm::vec3),
                                          indices.address() + i * sizeof(std::uint32_t), mesh.positions.size(),
                                          !mesh.cutout));
    v += mesh.positions.size();
    i += mesh.indices.size();
    infos.push_back({.type = vk::AccelerationStructureTypeKHR::eBottomLevel,
                     .flags = BuildFlags::ePreferFastTrace | BuildFlags::eAllowCompaction,
                     .mode = vk::BuildAccelerationStructureModeKHR::eBuild,
                     .geometryCount = 1,
                     .pGeometries = &geometries.back()});
    const auto sizes = buildSizes(context_, infos.back(), triangles(mesh));
    offsets.push_back(storageBytes);
    storageBytes += alignUp(sizes.accelerationStructureSize, kStorageAlignment);
    scratchBytes = std::max(scratchBytes, sizes.buildScratchSize);
  }
  gpu::Buffer storage(context_, storageBytes, kStorage, "rq static structures (uncompacted)");
  std::vector<vk::raii::AccelerationStructureKHR> built;
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    const vk::DeviceSize next = k + 1 < meshes.size() ? offsets[k + 1] : storageBytes;
    built.emplace_back(context_.device(), vk::AccelerationStructureCreateInfoKHR{.buffer = storage.handle(),
                                                                                 .offset = offsets[k],
                                                                                 .size = next - offsets[k],
                                                                                 .type = vk::AccelerationStructureTypeKHR::eBottomLevel});
  }
  const vk::DeviceAddress scratchAddress = scratch(scratchBytes);
  vk::raii::QueryPool sizes(context_.device(), {.queryType = vk::QueryType::eAccelerationStructureCompactedSizeKHR,
                                                .queryCount = std::uint32_t(meshes.size())});
  sizes.reset(0, std::uint32_t(meshes.size()));
  std::vector<vk::AccelerationStructureKHR> handles;
  context_.submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
    for (std::size_t k = 0; k < meshes.size(); ++k) {
      infos[k].dstAccelerationStructure = *built[k];
      infos[k].scratchData.deviceAddress = scratchAddress;
      const vk::AccelerationStructureBuildRangeInfoKHR range{.primitiveCount = triangles(scene.meshes[meshes[k]])};
      cmd.buildAccelerationStructuresKHR(infos[k], &range);
      buildToBuild(cmd);
      handles.push_back(*built[k]);
    }
    cmd.writeAccelerationStructuresPropertiesKHR(handles, vk::QueryType::eAccelerationStructureCompactedSizeKHR, *sizes, 0);
  });
  const auto [result, compacted] = sizes.getResults<vk::DeviceSize>(0, std::uint32_t(meshes.size()),
                                                                   meshes.size() * sizeof(vk::DeviceSize), sizeof(vk::DeviceSize),
                                                                   vk::QueryResultFlagBits::e64 | vk::QueryResultFlagBits::eWait);
  if (result != vk::Result::eSuccess) throw std::runtime_error("rq: compacted sizes of the acceleration structures not available");
  // Compaction: copy each structure into its compacted size, all in one buffer.
  vk::DeviceSize compactBytes = 0;
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    offsets[k] = compactBytes;
    compactBytes += alignUp(compacted[k], kStorageAlignment);
  }
  staticStorage_.emplace(context_, compactBytes, kStorage, "rq static structures");
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    static_.emplace_back(context_.device(), vk::AccelerationStructureCreateInfoKHR{.buffer = staticStorage_->handle(),
                                                                                   .offset = offsets[k],
                                                                                   .size = compacted[k],
                                                                                   .type = vk::AccelerationStructureTypeKHR::eBottomLevel});
  }
  context_.submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
    for (std::size_t k = 0; k < meshes.size(); ++k) {
      cmd.copyAccelerationStructureKHR({.src = *built[k], .dst = *static_[k], .mode = vk::CopyAccelerationStructureModeKHR::eCompact});
    }
  });
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    instanceTargets_[meshes[k]] = context_.device().getAccelerationStructureAddressKHR({.accelerationStructure = *static_[k]});
  }
  stats_.bottomLevels += std::uint32_t(meshes.size());
  stats_.uncompactedBytes = storageBytes;
  stats_.bytes += compactBytes;
}

void SceneAccelerationStructures::recordMoving(const vk::raii::CommandBuffer& cmd, Moving& m, bool update) {
  const vk::AccelerationStructureGeometryKHR geometry =
      triangleGeometry(m.vertices.address(), m.indices.address(), m.vertices.size() / sizeof(glm::vec3), m.opaque);
  const vk::AccelerationStructureBuildGeometryInfoKHR info{
      .type = vk::AccelerationStructureTypeKHR::eBottomLevel,
      .flags = BuildFlags::ePreferFastTrace | BuildFlags::eAllowUpdate,
      .mode = update ? vk::BuildAccelerationStructureModeKHR::eUpdate : vk::BuildAccelerationStructureModeKHR::eBuild,
      .srcAccelerationStructure = update ? *m.structure : vk::AccelerationStructureKHR{},
      .dstAccelerationStructure = *m.structure,
      .geometryCount = 1,
      .pGeometries = &geometry,
      .scratchData = {.deviceAddress = scratch(0)}};
  const vk::AccelerationStructureBuildRangeInfoKHR range{.primitiveCount = m.triangles};
  cmd.buildAccelerationStructuresKHR(info, &range);
  buildToBuild(cmd);
}

void SceneAccelerationStructures::buildMoving(const Scene& scene, MeshSet set) {
  vk::DeviceSize scratchBytes = 0;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (!mesh.dynamic || !inMeshSet(mesh, set) || triangles(mesh) == 0) continue;
    const vk::AccelerationStructureGeometryKHR geometry = triangleGeometry(0, 0, mesh.positions.size(), !mesh.cutout);
    const vk::AccelerationStructureBuildGeometryInfoKHR info{.type = vk::AccelerationStructureTypeKHR::eBottomLevel,
                                                             .flags = BuildFlags::ePreferFastTrace | BuildFlags::eAllowUpdate,
                                                             .geometryCount = 1,
                                                             .pGeometries = &geometry};
    const auto sizes = buildSizes(context_, info, triangles(mesh));
    scratchBytes = std::max({scratchBytes, sizes.buildScratchSize, sizes.updateScratchSize});
    Moving& moving = moving_.emplace_back(Moving{
        m, triangles(mesh), !mesh.cutout,
        gpu::Buffer(context_, mesh.positions.size() * sizeof(glm::vec3), kInput, "rq moving vertices"),
        gpu::Buffer(context_, mesh.indices.size() * sizeof(std::uint32_t), kInput, "rq moving indices"),
        gpu::Buffer(context_, sizes.accelerationStructureSize, kStorage, "rq moving structure")});
    moving.structure = vk::raii::AccelerationStructureKHR(
        context_.device(), vk::AccelerationStructureCreateInfoKHR{.buffer = moving.storage.handle(),
                                                                  .size = sizes.accelerationStructureSize,
                                                                  .type = vk::AccelerationStructureTypeKHR::eBottomLevel});
    moving.vertices.upload(std::span<const glm::vec3>(mesh.positions));
    order_[m] = spatialOrder(mesh);
    writeIndices(mesh, order_[m], static_cast<std::uint32_t*>(moving.indices.data()));
    instanceTargets_[m] = context_.device().getAccelerationStructureAddressKHR({.accelerationStructure = *moving.structure});
    stats_.bytes += moving.vertices.size() + moving.indices.size() + moving.storage.size();
  }
  if (moving_.empty()) return;
  scratch(scratchBytes);
  context_.submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
    for (Moving& m : moving_) recordMoving(cmd, m, false);
  });
  stats_.bottomLevels += std::uint32_t(moving_.size());
}

void SceneAccelerationStructures::buildTop(const vk::raii::CommandBuffer& cmd, bool update) {
  const auto count = std::uint32_t(instances_->size() / sizeof(vk::AccelerationStructureInstanceKHR));
  const vk::AccelerationStructureGeometryKHR geometry{
      .geometryType = vk::GeometryTypeKHR::eInstances,
      .geometry = {.instances = {.arrayOfPointers = VK_FALSE, .data = {.deviceAddress = instances_->address()}}},
      .flags = vk::GeometryFlagBitsKHR::eOpaque};
  vk::AccelerationStructureBuildGeometryInfoKHR info{.type = vk::AccelerationStructureTypeKHR::eTopLevel,
                                                    .flags = BuildFlags::ePreferFastTrace,
                                                    .mode = vk::BuildAccelerationStructureModeKHR::eBuild,
                                                    .geometryCount = 1,
                                                    .pGeometries = &geometry};
  const auto sizes = buildSizes(context_, info, count);
  if (!update) {  // first build: the top level's storage; rebuilds reuse it (same instance count)
    topStorage_.emplace(context_, sizes.accelerationStructureSize, kStorage, "rq top level");
    top_ = vk::raii::AccelerationStructureKHR(context_.device(),
                                              vk::AccelerationStructureCreateInfoKHR{.buffer = topStorage_->handle(),
                                                                                     .size = sizes.accelerationStructureSize,
                                                                                     .type = vk::AccelerationStructureTypeKHR::eTopLevel});
  }
  info.dstAccelerationStructure = *top_;
  info.scratchData.deviceAddress = scratch(sizes.buildScratchSize);
  const vk::AccelerationStructureBuildRangeInfoKHR range{.primitiveCount = count};
  buildToBuild(cmd);  // the bottom levels it references are complete
  cmd.buildAccelerationStructuresKHR(info, &range);
  buildToBuild(cmd);
}

BvhRefitReport SceneAccelerationStructures::update(const Scene& scene) {
  if (moving_.empty()) return {};
  const auto start = std::chrono::steady_clock::now();
  BvhRefitReport report = policy_.update(scene);  // throws when the moving meshes changed size
  for (Moving& m : moving_) m.vertices.upload(std::span<const glm::vec3>(scene.meshes[m.mesh].positions));
  context_.submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
    for (Moving& m : moving_) recordMoving(cmd, m, !report.rebuilt);
    buildTop(cmd, true);
  });
  report.ms = msSince(start);
  return report;
}

void SceneAccelerationStructures::recordBuildToTrace(const vk::raii::CommandBuffer& cmd) {
  gpu::memoryBarrier(cmd, Stage::eAccelerationStructureBuildKHR, Access::eAccelerationStructureWriteKHR,
                     Stage::eComputeShader, Access::eAccelerationStructureReadKHR);
}

}  // namespace penumbra
