// Memory traffic of the BVH trace kernel, simulated on the CPU (Lauterbach et al. 2009, section 4.2:
// "a simple software simulator that emulates the behavior of the memory unit for global memory
// accesses"), and a stated estimate for the raster passes that feed it.
//
// Replay: bvh_trace.comp runs one invocation per ShadingPoint of the dense list, in list order;
// invocations 32w .. 32w+31 form warp w (the workgroup of TRACE_GROUP_SIZE = 64 holds two), lanes
// past the count are inactive. Each lane loads its ShadingPoint, then for each of its light samples
// (lanes reconverge after every sample's traversal, as SIMT hardware does after a loop) runs the
// traversal of shaders/bvh_traverse.glsl, replayed here operation for operation (same slab test, same
// watertight triangle test, same child order, same stack, same any-hit exit), and finally stores
// visibility[pixel]. Within one sample the warp's lanes step in lockstep through the traversal loop:
// iteration k issues one warp-wide node load for every lane still traversing, then the child-0 leaf
// loop (one warp-wide triangle load per leaf slot j, for the lanes that test a j-th triangle there),
// then the child-1 leaf loop likewise. Lanes that have finished (a hit, or an empty stack) idle.
//
// Coalescing model (stated, NVIDIA-like): a warp-wide access of the active lanes is served by the
// distinct 32-byte sectors its lanes' bytes touch; bytes = distinct sectors x 32 per access, summed
// over accesses (no cache reuse between accesses: every access goes to DRAM). Distinct 128-byte lines
// are reported too. Buffers start at 256-byte aligned addresses. Nodes are 64 bytes (2 sectors when
// aligned), triangles 48, shading points 48, visibility 4 (a store; counted the same way).
// Not counted: the uniform reads of the count and the light (one address per warp, cached), the
// per-subgroup counter atomics, and the traversal stack (registers / on-chip local memory).
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "shared/bvh.h"
#include "shared/light.h"
#include "shared/shading_point.h"

namespace penumbra {

class BvhTracer;
struct TraceJob;

inline constexpr std::uint32_t kWarpSize = 32;
inline constexpr std::uint64_t kSectorBytes = 32;
inline constexpr std::uint64_t kLineBytes = 128;

// Traffic of one stream, summed over its warp-wide accesses.
struct MemoryTraffic {
  std::uint64_t accesses = 0;      // warp-wide instructions with at least one active lane
  std::uint64_t laneAccesses = 0;  // active lanes over those instructions
  std::uint64_t sectors = 0;       // distinct 32-byte sectors per access, summed
  std::uint64_t lines = 0;         // distinct 128-byte lines per access, summed
  std::uint64_t bytes() const { return sectors * kSectorBytes; }
  MemoryTraffic& operator+=(const MemoryTraffic& o);
};

// One active lane's part of a warp-wide access: byte offset into the buffer and size.
struct LaneAccess {
  std::uint64_t offset = 0;
  std::uint32_t bytes = 0;
};

// The sectors and lines of one warp-wide access by `lanes` (the active lanes only; empty: nothing).
MemoryTraffic coalesce(std::span<const LaneAccess> lanes);

struct BandwidthSettings {
  // Whether fma() in the triangle test is fused (one rounding), as on GPUs, or a multiply and an
  // add, as lavapipe lowers it: the replay must round like the device to take the same decisions.
  bool fusedMultiplyAdd = true;
};

// lavapipe (llvmpipe) lowers fma() to a multiply and an add; real GPUs fuse it.
BandwidthSettings bandwidthSettingsFor(const std::string& deviceName);

struct BandwidthReport {
  MemoryTraffic nodes, triangles, points, visibility;
  std::uint64_t invocations = 0, warps = 0;
  std::uint64_t rays = 0, nodeVisits = 0, triangleTests = 0;  // the same totals the GPU counters report
  std::uint64_t bytes() const { return nodes.bytes() + triangles.bytes() + points.bytes() + visibility.bytes(); }
  std::uint64_t lines() const { return nodes.lines + triangles.lines + points.lines + visibility.lines; }
};

// Replays bvh_trace.comp for `points` (the dense list, in dispatch order) against the BVH. Throws
// std::invalid_argument for an empty node list, an index outside the BVH or a stack overflow (a
// BVH the kernel could not trace either). `visibility`, when given, receives each point's answer
// (visible samples / samples), index for index with `points`.
BandwidthReport simulateTraceBandwidth(std::span<const shared::BvhNode> nodes,
                                       std::span<const shared::BvhTriangle> triangles,
                                       std::span<const shared::ShadingPoint> points, const shared::GpuLight& light,
                                       const BandwidthSettings& settings = {}, std::vector<float>* visibility = nullptr);

// The same for a recorded and finished BvhTracer job: downloads the points and count (host visible)
// and the tracer's BVH. `light` must be the light of the traced frame. Throws InputError for a
// tracer with a dynamic tree (scenes with moving meshes): the replay follows the static tree only.
BandwidthReport simulateTraceBandwidth(const BvhTracer& tracer, const TraceJob& job, const shared::GpuLight& light,
                                       const BandwidthSettings& settings = {});

// What the raster and compute passes before the trace read and write, estimated from resolutions
// and formats (see estimateRasterBytes for the formula).
struct RasterEstimateInput {
  std::uint64_t pixels = 0;         // width * height
  std::uint64_t triangles = 0;      // scene triangles
  std::uint32_t shadowMapRes = 0;   // texels per side of a face
  std::uint32_t faces = 1;          // shadow-map faces (6 for a cube)
  bool selective = true;            // srt (shadow map, thin mask, classification) or frt (none)
  bool thinPass = true;             // srt's thin-triangle mask
  std::uint64_t tracedPoints = 0;   // ShadingPoints the compaction wrote
};

struct RasterEstimate {
  std::uint64_t gbuffer = 0, shadowMap = 0, thinMask = 0, classify = 0, compaction = 0;
  std::uint64_t total() const { return gbuffer + shadowMap + thinMask + classify + compaction; }
};

RasterEstimate estimateRasterBytes(const RasterEstimateInput& in);

nlohmann::json toJson(const MemoryTraffic& traffic);
// The breakdown written as FrameStats "bandwidth": streams, totals, counts and the models' words.
nlohmann::json toJson(const BandwidthReport& report, const RasterEstimate& raster);

}  // namespace penumbra
