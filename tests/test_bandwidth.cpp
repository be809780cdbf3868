// The bandwidth model (raytrace/bandwidth_model.h): the coalescing model on hand-counted warps, the
// lockstep replay on a hand-built BVH, and the replay against the GPU kernel's own counters and
// answers on real frames (same traversal: same node visits, triangle tests, rays and visibility).
#include <gtest/gtest.h>

#include <vector>

#include "core/view.h"
#include "raytrace/bandwidth_model.h"
#include "render_fixture.h"
#include "shared/trace.h"

namespace penumbra::test {
namespace {

constexpr std::uint32_t kNode = 64, kTriangle = 48;

std::vector<LaneAccess> lanes(std::uint32_t count, std::uint64_t first, std::uint64_t stride, std::uint32_t bytes) {
  std::vector<LaneAccess> out;
  for (std::uint32_t i = 0; i < count; ++i) out.push_back({first + i * stride, bytes});
  return out;
}

TEST(Coalescing, ConsecutiveNodesAreFullyCoalesced) {
  // 32 lanes, nodes 0..31: 2048 contiguous bytes = 64 sectors in 16 lines.
  const MemoryTraffic t = coalesce(lanes(32, 0, kNode, kNode));
  EXPECT_EQ(t.sectors, 64u);
  EXPECT_EQ(t.bytes(), 2048u);
  EXPECT_EQ(t.lines, 16u);
  EXPECT_EQ(t.accesses, 1u);
  EXPECT_EQ(t.laneAccesses, 32u);
}

TEST(Coalescing, OneNodeForAllLanesIsTwoSectors) {
  const MemoryTraffic t = coalesce(lanes(32, 5 * kNode, 0, kNode));
  EXPECT_EQ(t.sectors, 2u);
  EXPECT_EQ(t.bytes(), 64u);
  EXPECT_EQ(t.lines, 1u);
}

TEST(Coalescing, ScatteredNodesCostTwoSectorsEach) {
  // Nodes 4 KB apart: no two lanes share a sector or a line.
  const MemoryTraffic t = coalesce(lanes(32, 0, 4096, kNode));
  EXPECT_EQ(t.sectors, 64u);
  EXPECT_EQ(t.bytes(), 32u * 2u * 32u);
  EXPECT_EQ(t.lines, 32u);
}

TEST(Coalescing, PartiallyActiveWarp) {
  // 10 active lanes on nodes 3..12: bytes 192..831 = sectors 6..25 (20), lines 1..6 (6). The other
  // 22 lanes are inactive and are simply not part of the access.
  const MemoryTraffic t = coalesce(lanes(10, 3 * kNode, kNode, kNode));
  EXPECT_EQ(t.sectors, 20u);
  EXPECT_EQ(t.lines, 6u);
  EXPECT_EQ(t.laneAccesses, 10u);
  // No active lane: no access at all.
  const MemoryTraffic none = coalesce({});
  EXPECT_EQ(none.accesses, 0u);
  EXPECT_EQ(none.sectors, 0u);
}

TEST(Coalescing, TrianglesStraddleSectorsAndLines) {
  // 48-byte triangles: 32 consecutive ones = 1536 bytes = 48 sectors, 12 lines.
  const MemoryTraffic all = coalesce(lanes(32, 0, kTriangle, kTriangle));
  EXPECT_EQ(all.sectors, 48u);
  EXPECT_EQ(all.lines, 12u);
  // Triangle 1 = bytes 48..95: sectors 1 and 2, one line; triangle 2 = bytes 96..143: sectors 3
  // and 4, which lie in lines 0 and 1.
  const MemoryTraffic one = coalesce(lanes(1, kTriangle, 0, kTriangle));
  EXPECT_EQ(one.sectors, 2u);
  EXPECT_EQ(one.lines, 1u);
  const MemoryTraffic two = coalesce(lanes(1, 2 * kTriangle, 0, kTriangle));
  EXPECT_EQ(two.sectors, 2u);
  EXPECT_EQ(two.lines, 2u);
  // Scattered 4-byte stores: one sector each.
  EXPECT_EQ(coalesce(lanes(32, 0, 400, 4)).sectors, 32u);
  EXPECT_EQ(coalesce(lanes(32, 0, 4, 4)).sectors, 4u);
}

// ---- The lockstep replay on a hand-built BVH ---------------------------------------------------
// A root with two leaves. Leaf 0: triangle 0 in the plane y = 1 over x in [-0.34, 15.5] at z = 0.
// Leaf 1: triangle 1, tiny and far away (z = 200: every ray misses it), then triangle 2 in y = 2
// over x in [15.84, 40] at z = 0. Points at (x, 0, 0), x = 0, 1, ..., facing +y, under a light
// shining straight down: lanes 0..15 hit triangle 0 (and stop), lanes 16..31 miss leaf 0's box,
// test triangle 1 (miss) and triangle 2 (hit).
struct HandBvh {
  std::vector<shared::BvhNode> nodes;
  std::vector<shared::BvhTriangle> triangles;
  shared::GpuLight light{};

  HandBvh() {
    auto tri = [](glm::vec3 a, glm::vec3 b, glm::vec3 c, std::uint32_t id) {
      return shared::BvhTriangle{a, id, b, 0u, c, 0u};
    };
    triangles = {tri({-0.5f, 1.0f, -1.0f}, {15.5f, 1.0f, -1.0f}, {15.5f, 1.0f, 100.0f}, 0),
                 tri({16.0f, 2.0f, 200.0f}, {17.0f, 2.0f, 200.0f}, {16.0f, 2.0f, 201.0f}, 1),
                 tri({15.6f, 2.0f, -1.0f}, {40.0f, 2.0f, -1.0f}, {40.0f, 2.0f, 100.0f}, 2)};
    shared::BvhNode root{};
    root.child[0] = {{-0.5f, 0.9f, -1.1f}, 0u, {15.5f, 1.1f, 100.1f}, 1u};
    root.child[1] = {{15.6f, 1.9f, -1.1f}, 1u, {40.0f, 2.1f, 201.1f}, 2u};
    nodes = {root};
    light.type = LIGHT_DIRECTIONAL;
    light.direction = glm::vec4(0.0f, -1.0f, 0.0f, 0.0f);
    light.tangent = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
    light.cosHalfAngle = -1.0f;
    light.rayEpsilon = 1e-4f;
  }

  std::vector<shared::ShadingPoint> points(std::uint32_t count, std::uint32_t pixelStride) const {
    std::vector<shared::ShadingPoint> out;
    for (std::uint32_t i = 0; i < count; ++i) {
      shared::ShadingPoint p{};
      p.position = {float(i), 0.0f, 0.0f};
      p.normal = {0.0f, 1.0f, 0.0f};
      p.pixel = i * pixelStride;
      p.spp = 1;
      out.push_back(p);
    }
    return out;
  }
};

TEST(BandwidthReplay, HandCountedWarp) {
  const HandBvh bvh;
  std::vector<float> visibility;
  const BandwidthReport r = simulateTraceBandwidth(bvh.nodes, bvh.triangles, bvh.points(32, 1), bvh.light, {}, &visibility);
  EXPECT_EQ(r.warps, 1u);
  EXPECT_EQ(r.rays, 32u);
  EXPECT_EQ(r.nodeVisits, 32u);            // one root visit per lane
  EXPECT_EQ(r.triangleTests, 16u + 32u);   // lanes 0..15 test one triangle, 16..31 two
  for (float v : visibility) EXPECT_EQ(v, 0.0f);
  // Node: one warp-wide load of the same 64-byte node.
  EXPECT_EQ(r.nodes.accesses, 1u);
  EXPECT_EQ(r.nodes.sectors, 2u);
  EXPECT_EQ(r.nodes.lines, 1u);
  // Triangles: leaf 0 slot 0 (triangle 0: sectors 0-1), leaf 1 slot 0 (triangle 1: sectors 1-2),
  // leaf 1 slot 1 (triangle 2: sectors 3-4, lines 0 and 1).
  EXPECT_EQ(r.triangles.accesses, 3u);
  EXPECT_EQ(r.triangles.laneAccesses, 48u);
  EXPECT_EQ(r.triangles.sectors, 6u);
  EXPECT_EQ(r.triangles.lines, 4u);
  // 32 consecutive 48-byte points: 48 sectors, 12 lines; visibility of pixels 0..31: 4 sectors, 1 line.
  EXPECT_EQ(r.points.sectors, 48u);
  EXPECT_EQ(r.points.lines, 12u);
  EXPECT_EQ(r.visibility.sectors, 4u);
  EXPECT_EQ(r.visibility.lines, 1u);
  EXPECT_EQ(r.bytes(), 32u * (2 + 6 + 48 + 4));
  EXPECT_EQ(r.lines(), 1u + 4u + 12u + 1u);
}

TEST(BandwidthReplay, PartialWarpAndScatteredWrites) {
  const HandBvh bvh;
  // 8 points (lanes 8..31 inactive), all under triangle 0, pixels 100 apart.
  const BandwidthReport r = simulateTraceBandwidth(bvh.nodes, bvh.triangles, bvh.points(8, 100), bvh.light);
  EXPECT_EQ(r.warps, 1u);
  EXPECT_EQ(r.nodes.laneAccesses, 8u);
  EXPECT_EQ(r.nodes.sectors, 2u);
  EXPECT_EQ(r.triangles.accesses, 1u);  // leaf 1 is entered by no lane: no access
  EXPECT_EQ(r.triangles.sectors, 2u);
  EXPECT_EQ(r.points.sectors, 12u);     // 384 bytes
  EXPECT_EQ(r.points.lines, 3u);
  EXPECT_EQ(r.visibility.sectors, 8u);  // 400 bytes apart: a sector each
  // 40 points: a full warp and one of 8 lanes.
  const BandwidthReport two = simulateTraceBandwidth(bvh.nodes, bvh.triangles, bvh.points(40, 1), bvh.light);
  EXPECT_EQ(two.warps, 2u);
  EXPECT_EQ(two.nodes.accesses, 2u);
  EXPECT_EQ(two.rays, 40u);
}

TEST(BandwidthReplay, LightBehindTheSurfaceTracesNothing) {
  HandBvh bvh;
  bvh.light.direction = glm::vec4(0.0f, 1.0f, 0.0f, 0.0f);  // from below: no point faces it
  std::vector<float> visibility;
  const BandwidthReport r = simulateTraceBandwidth(bvh.nodes, bvh.triangles, bvh.points(32, 1), bvh.light, {}, &visibility);
  EXPECT_EQ(r.rays, 0u);
  EXPECT_EQ(r.nodes.accesses, 0u);
  EXPECT_EQ(r.points.accesses, 1u);  // points are still loaded and visibility written
  EXPECT_EQ(r.visibility.accesses, 1u);
  for (float v : visibility) EXPECT_EQ(v, 0.0f);
}

TEST(BandwidthReplay, RejectsBrokenBvh) {
  HandBvh bvh;
  EXPECT_THROW(simulateTraceBandwidth({}, bvh.triangles, bvh.points(1, 1), bvh.light), std::invalid_argument);
  bvh.nodes[0].child[1].index = 7;  // a leaf past the triangles
  EXPECT_THROW(simulateTraceBandwidth(bvh.nodes, bvh.triangles, bvh.points(32, 1), bvh.light), std::invalid_argument);
}

// ---- The replay against the GPU kernel -------------------------------------------------------

RenderSettings bandwidthSettings(std::uint32_t size) {
  RenderSettings s = smallSettings(size, 1024);
  s.simulateBandwidth = true;
  return s;
}

// The frame's simulated counts must be the GPU counters, and the replay's answers the kernel's.
void expectReplayMatchesKernel(SceneRun& run, const Frame& frame) {
  ASSERT_FALSE(frame.stats.bandwidth.is_null()) << frame.stats.method;
  ASSERT_TRUE(frame.stats.nodeVisits && frame.stats.triangleTests && frame.stats.raysTraced);
  const nlohmann::json& bw = frame.stats.bandwidth;
  EXPECT_GT(*frame.stats.nodeVisits, 0u);
  EXPECT_EQ(bw["node_visits"].get<std::uint64_t>(), *frame.stats.nodeVisits) << frame.stats.method;
  EXPECT_EQ(bw["triangle_tests"].get<std::uint64_t>(), *frame.stats.triangleTests) << frame.stats.method;
  EXPECT_EQ(bw["rays"].get<std::uint64_t>(), *frame.stats.raysTraced) << frame.stats.method;
  EXPECT_EQ(bw["invocations"].get<std::uint64_t>(), *frame.stats.pipPixels);
  ASSERT_TRUE(frame.stats.traceBytesSimulated && frame.stats.rasterBytesEstimated);
  EXPECT_EQ(*frame.stats.traceBytesSimulated, bw["trace_bytes"].get<std::uint64_t>());
  // Per ray, next to the total (a list in coherent order moves fewer bytes per ray).
  EXPECT_DOUBLE_EQ(frame.stats.toJson()["trace_bytes_per_ray"].get<double>(),
                   double(*frame.stats.traceBytesSimulated) / double(*frame.stats.raysTraced));
  // Every node visit fetches at least... nothing less than one sector per warp-wide load, and at
  // most two sectors per lane.
  const std::uint64_t nodeSectors = bw["streams"]["nodes"]["sectors"].get<std::uint64_t>();
  EXPECT_GE(nodeSectors, 2 * bw["streams"]["nodes"]["warp_accesses"].get<std::uint64_t>());
  EXPECT_LE(nodeSectors, 2 * *frame.stats.nodeVisits);

  // Replay directly and compare the answers point by point with the visibility the kernel wrote.
  FrameStats scratch;
  const auto& tracer = dynamic_cast<const BvhTracer&>(run.renderer->frameContext().tracer(scratch));
  const TraceJob job = run.renderer->frameContext().traceJob(tracer, TraceList::Doubtful);  // the srt frame's list
  const std::uint32_t count = job.count.download<shared::TraceCount>(1).front().count;
  const auto points = job.points.download<shared::ShadingPoint>(count);
  const auto nodes = tracer.nodeBuffer().download<shared::BvhNode>(tracer.nodeBuffer().size() / sizeof(shared::BvhNode));
  const auto tris = tracer.triangleBuffer().download<shared::BvhTriangle>(tracer.triangleBuffer().size() / sizeof(shared::BvhTriangle));
  std::vector<float> visibility;
  const BandwidthReport direct = simulateTraceBandwidth(nodes, tris, points, run.renderer->frameContext().frameData().light,
                                                        bandwidthSettingsFor(validatedContext().deviceName()), &visibility);
  EXPECT_EQ(direct.nodeVisits, *frame.stats.nodeVisits);
  std::size_t differing = 0;
  for (std::size_t i = 0; i < points.size(); ++i) differing += visibility[i] != frame.visibility[points[i].pixel];
  EXPECT_EQ(differing, 0u) << "of " << points.size() << " points";
}

TEST(BandwidthReplay, NodeVisitsEqualTheGpuCountersOnCourtyard) {
  SceneRun run("builtin:courtyard:2", bandwidthSettings(96));
  const Frame frt = run.render("frt");
  expectReplayMatchesKernel(run, frt);
  const Frame srt = run.render("srt");
  expectReplayMatchesKernel(run, srt);
  // Selective tracing moves less data through the trace kernel than full tracing.
  EXPECT_LT(*srt.stats.traceBytesSimulated, *frt.stats.traceBytesSimulated);
  std::cout << "courtyard:2 96^2: trace bytes frt " << *frt.stats.traceBytesSimulated << ", srt "
            << *srt.stats.traceBytesSimulated << "; raster estimate frt " << *frt.stats.rasterBytesEstimated << ", srt "
            << *srt.stats.rasterBytesEstimated << "\n";
  // Without the flag nothing is simulated.
  SceneRun plain("builtin:square", smallSettings(64, 512));
  const Frame off = plain.render("frt");
  EXPECT_TRUE(off.stats.bandwidth.is_null());
  EXPECT_FALSE(off.stats.traceBytesSimulated);
  EXPECT_TRUE(off.stats.toJson()["trace_bytes_simulated"].is_null());
  EXPECT_TRUE(off.stats.toJson()["trace_bytes_per_ray"].is_null());
  expectValidationSilent();
}

TEST(BandwidthReplay, NodeVisitsEqualTheGpuCountersWithAnAreaLight) {
  RenderSettings settings = bandwidthSettings(64);
  settings.spp = 4;
  SceneRun run("builtin:courtyard:2", settings);
  run.light.type = LightType::Rect;
  applyLightSize(run.light, 0.1f, run.scene.bounds());
  const Frame frt = run.render("frt");
  expectReplayMatchesKernel(run, frt);
  const Frame srt = run.render("srt");
  expectReplayMatchesKernel(run, srt);
  expectValidationSilent();
}

TEST(BandwidthReplay, EmbreeTracerIsNotSimulated) {
  RenderSettings settings = bandwidthSettings(64);
  settings.tracer = "embree";
  SceneRun run("builtin:square", settings);
  const Frame frt = run.render("frt");
  EXPECT_TRUE(frt.stats.bandwidth.is_null());
  EXPECT_FALSE(frt.stats.traceBytesSimulated);
  expectValidationSilent();
}

}  // namespace
}  // namespace penumbra::test
