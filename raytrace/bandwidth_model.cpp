// Built with -ffp-contract=off (raytrace/CMakeLists.txt): every multiply and add below must round on
// its own, exactly as the shader's arithmetic does on the device, or the replay could take another
// branch than the kernel on a ray that grazes an edge.
#include "raytrace/bandwidth_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "raytrace/bvh_tracer.h"
#include "shared/trace.h"

namespace penumbra {
namespace {

using glm::vec3;

// The replay of bvh_traverse.glsl. Names follow the shader.
const float kBvhExitScale = 1.0f + 1.0e-6f;

struct Arithmetic {
  bool fused;
  float fma(float a, float b, float c) const { return fused ? std::fma(a, b, c) : a * b + c; }
  vec3 cross(vec3 a, vec3 b) const {
    return {fma(a.y, b.z, -(a.z * b.y)), fma(a.z, b.x, -(a.x * b.z)), fma(a.x, b.y, -(a.y * b.x))};
  }
  float dot(vec3 a, vec3 b) const { return fma(a.x, b.x, fma(a.y, b.y, a.z * b.z)); }
  vec3 stableNormal(vec3 a, vec3 b, vec3 c) const {
    const vec3 abTerm(a.z * b.y, a.x * b.z, a.y * b.x);
    const vec3 bcTerm(b.z * c.y, b.x * c.z, b.y * c.x);
    const vec3 ab(fma(a.y, b.z, -abTerm.x), fma(a.z, b.x, -abTerm.y), fma(a.x, b.y, -abTerm.z));
    const vec3 bc(fma(b.y, c.z, -bcTerm.x), fma(b.z, c.x, -bcTerm.y), fma(b.x, c.y, -bcTerm.z));
    return {std::abs(abTerm.x) < std::abs(bcTerm.x) ? ab.x : bc.x, std::abs(abTerm.y) < std::abs(bcTerm.y) ? ab.y : bc.y,
            std::abs(abTerm.z) < std::abs(bcTerm.z) ? ab.z : bc.z};
  }
  // bvhTriangleHit: distance, or a negative value for a miss.
  float triangleHit(const shared::BvhTriangle& tri, vec3 origin, vec3 dir, float tMin, float tMax) const {
    const vec3 v0 = tri.v0 - origin, v1 = tri.v1 - origin, v2 = tri.v2 - origin;
    const vec3 e0 = v2 - v0, e1 = v0 - v1, e2 = v1 - v2;
    const float u = dot(cross(e0, v2 + v0), dir);
    const float v = dot(cross(e1, v0 + v1), dir);
    const float w = dot(cross(e2, v1 + v2), dir);
    const float eps = 1.1920929e-7f * std::abs(u + v + w);
    if (!(std::min(u, std::min(v, w)) >= -eps || std::max(u, std::max(v, w)) <= eps)) return -1.0f;
    const vec3 n = stableNormal(e0, e1, e2);
    const float den = 2.0f * dot(n, dir);
    if (den == 0.0f) return -1.0f;
    const float t = (2.0f * dot(v0, n)) / den;
    return (t >= tMin && t <= tMax) ? t : -1.0f;
  }
};

// GLSL min/max: y < x ? y : x and x < y ? y : x (no NaN reaches them: see bvhInverseDirection).
float gmin(float x, float y) { return y < x ? y : x; }
float gmax(float x, float y) { return x < y ? y : x; }

bool slab(vec3 lo, vec3 hi, vec3 origin, vec3 invDir, float tMin, float tMax, float& enter) {
  const vec3 t0 = (lo - origin) * invDir;
  const vec3 t1 = (hi - origin) * invDir;
  const vec3 tNear(gmin(t0.x, t1.x), gmin(t0.y, t1.y), gmin(t0.z, t1.z));
  const vec3 tFar(gmax(t0.x, t1.x), gmax(t0.y, t1.y), gmax(t0.z, t1.z));
  enter = gmax(gmax(tNear.x, tNear.y), gmax(tNear.z, tMin));
  const float exit = gmin(gmin(tFar.x, tFar.y), gmin(tFar.z, tMax)) * kBvhExitScale;
  return enter <= exit;
}

vec3 inverseDirection(vec3 dir) {
  const float tiny = 1.0e-20f;
  auto safe = [&](float d) { return std::abs(d) < tiny ? (d < 0.0f ? -tiny : tiny) : d; };
  return {1.0f / safe(dir.x), 1.0f / safe(dir.y), 1.0f / safe(dir.z)};
}

// One iteration of the traversal loop of one lane: the node it fetched and the triangles it tested
// in the child-0 and child-1 leaf loops.
struct Iteration {
  std::uint32_t node;
  std::uint32_t leafFirst[2];
  std::uint32_t leafTested[2];
};

class Replay {
 public:
  Replay(std::span<const shared::BvhNode> nodes, std::span<const shared::BvhTriangle> triangles, bool fused)
      : nodes_(nodes), triangles_(triangles), math_{fused} {}

  // bvhTraverse with anyHit: whether something was hit; appends the loop's iterations.
  bool anyHit(vec3 origin, vec3 dir, float tMin, float tMax, std::vector<Iteration>& out) const {
    const vec3 invDir = inverseDirection(dir);
    std::uint32_t stack[BVH_STACK_SIZE];
    std::uint32_t depth = 0, node = 0;
    for (;;) {
      if (node >= nodes_.size()) throw std::invalid_argument("bandwidth model: node index " + std::to_string(node) + " outside the BVH");
      const shared::BvhNode& n = nodes_[node];
      Iteration& it = out.emplace_back(Iteration{node, {0, 0}, {0, 0}});
      float enter0 = 0.0f, enter1 = 0.0f;
      bool go0 = slab(n.child[0].lo, n.child[0].hi, origin, invDir, tMin, tMax, enter0);
      bool go1 = slab(n.child[1].lo, n.child[1].hi, origin, invDir, tMin, tMax, enter1);
      for (int c = 0; c < 2; ++c) {
        bool& go = c == 0 ? go0 : go1;
        if (!(go && n.child[c].count > 0u)) continue;
        it.leafFirst[c] = n.child[c].index;
        if (leaf(n.child[c].index, n.child[c].count, origin, dir, tMin, tMax, it.leafTested[c])) return true;
        go = false;
      }
      go1 = go1 && n.child[1].index != 0u;
      if (go0 && go1) {
        if (depth >= BVH_STACK_SIZE) throw std::invalid_argument("bandwidth model: BVH deeper than the kernel's stack");
        const bool firstNearer = enter0 <= enter1;
        stack[depth++] = firstNearer ? n.child[1].index : n.child[0].index;
        node = firstNearer ? n.child[0].index : n.child[1].index;
      } else if (go0 || go1) {
        node = go0 ? n.child[0].index : n.child[1].index;
      } else {
        if (depth == 0u) break;
        node = stack[--depth];
      }
    }
    return false;
  }

 private:
  bool leaf(std::uint32_t first, std::uint32_t count, vec3 origin, vec3 dir, float tMin, float tMax,
            std::uint32_t& tested) const {
    for (std::uint32_t i = first; i < first + count; ++i) {
      if (i >= triangles_.size()) throw std::invalid_argument("bandwidth model: triangle index " + std::to_string(i) + " outside the BVH");
      ++tested;
      if (math_.triangleHit(triangles_[i], origin, dir, tMin, tMax) >= 0.0f) return true;  // any hit: stop
    }
    return false;
  }

  std::span<const shared::BvhNode> nodes_;
  std::span<const shared::BvhTriangle> triangles_;
  Arithmetic math_;
};

// Collects the lanes of one warp-wide access and adds its coalesced traffic to a stream.
class WarpAccess {
 public:
  void add(std::uint64_t offset, std::uint32_t bytes) { lanes_.push_back({offset, bytes}); }
  void issue(MemoryTraffic& stream) {
    stream += coalesce(lanes_);
    lanes_.clear();
  }

 private:
  std::vector<LaneAccess> lanes_;
};

}  // namespace

MemoryTraffic& MemoryTraffic::operator+=(const MemoryTraffic& o) {
  accesses += o.accesses;
  laneAccesses += o.laneAccesses;
  sectors += o.sectors;
  lines += o.lines;
  return *this;
}

MemoryTraffic coalesce(std::span<const LaneAccess> lanes) {
  MemoryTraffic t;
  if (lanes.empty()) return t;
  std::vector<std::uint64_t> sectors;
  sectors.reserve(lanes.size() * 3);
  for (const LaneAccess& lane : lanes) {
    if (lane.bytes == 0) continue;
    for (std::uint64_t s = lane.offset / kSectorBytes; s <= (lane.offset + lane.bytes - 1) / kSectorBytes; ++s) sectors.push_back(s);
  }
  std::sort(sectors.begin(), sectors.end());
  sectors.erase(std::unique(sectors.begin(), sectors.end()), sectors.end());
  t.accesses = 1;
  t.laneAccesses = lanes.size();
  t.sectors = sectors.size();
  constexpr std::uint64_t sectorsPerLine = kLineBytes / kSectorBytes;
  for (std::size_t i = 0; i < sectors.size(); ++i) t.lines += i == 0 || sectors[i] / sectorsPerLine != sectors[i - 1] / sectorsPerLine;
  return t;
}

BandwidthSettings bandwidthSettingsFor(const std::string& deviceName) {
  return {.fusedMultiplyAdd = deviceName.find("llvmpipe") == std::string::npos};
}

BandwidthReport simulateTraceBandwidth(std::span<const shared::BvhNode> nodes,
                                       std::span<const shared::BvhTriangle> triangles,
                                       std::span<const shared::ShadingPoint> points, const shared::GpuLight& light,
                                       const BandwidthSettings& settings, std::vector<float>* visibility) {
  if (nodes.empty()) throw std::invalid_argument("bandwidth model: the BVH has no nodes");
  const Replay replay(nodes, triangles, settings.fusedMultiplyAdd);
  BandwidthReport report;
  report.invocations = points.size();
  if (visibility) visibility->assign(points.size(), 0.0f);
  const bool directional = light.type == LIGHT_DIRECTIONAL;

  WarpAccess access;
  std::vector<std::vector<Iteration>> lanes(kWarpSize);  // one sample's iterations per lane
  std::uint32_t visible[kWarpSize];
  for (std::size_t first = 0; first < points.size(); first += kWarpSize) {
    const std::size_t active = std::min<std::size_t>(kWarpSize, points.size() - first);
    ++report.warps;
    // ShadingPoint point = points[index];
    for (std::size_t l = 0; l < active; ++l) access.add((first + l) * sizeof(shared::ShadingPoint), sizeof(shared::ShadingPoint));
    access.issue(report.points);

    std::uint32_t maxSamples = 0;
    for (std::size_t l = 0; l < active; ++l) maxSamples = std::max(maxSamples, std::max(points[first + l].spp, 1u));
    std::fill(std::begin(visible), std::end(visible), 0u);
    for (std::uint32_t s = 0; s < maxSamples; ++s) {
      // Every lane's traversal for sample s (none where the lane has fewer samples or the light
      // cannot reach the point), then the warp's lockstep over the loop iterations.
      std::size_t longest = 0;
      for (std::size_t l = 0; l < active; ++l) {
        lanes[l].clear();
        const shared::ShadingPoint& point = points[first + l];
        const std::uint32_t n = std::max(point.spp, 1u);
        if (s >= n) continue;
        const vec3 origin = shared::shadowRayOrigin(light, point.position, point.normal);
        const vec3 q = shared::lightSamplePoint(light, point.pixel, s, n);
        if (!shared::lightReaches(light, point.position, point.normal, q)) continue;
        const vec3 dir = shared::directionToLight(light, point.position, q);
        const float tMax = shared::shadowRayEnd(glm::distance(origin, q), directional, point.rayMax);
        ++report.rays;
        if (!replay.anyHit(origin, dir, 0.0f, tMax, lanes[l])) ++visible[l];
        longest = std::max(longest, lanes[l].size());
      }
      for (std::size_t k = 0; k < longest; ++k) {
        for (std::size_t l = 0; l < active; ++l) {
          if (k < lanes[l].size()) access.add(std::uint64_t(lanes[l][k].node) * sizeof(shared::BvhNode), sizeof(shared::BvhNode));
        }
        access.issue(report.nodes);
        for (int c = 0; c < 2; ++c) {
          std::uint32_t slots = 0;
          for (std::size_t l = 0; l < active; ++l) {
            if (k < lanes[l].size()) slots = std::max(slots, lanes[l][k].leafTested[c]);
          }
          for (std::uint32_t j = 0; j < slots; ++j) {
            for (std::size_t l = 0; l < active; ++l) {
              if (k >= lanes[l].size() || j >= lanes[l][k].leafTested[c]) continue;
              access.add(std::uint64_t(lanes[l][k].leafFirst[c] + j) * sizeof(shared::BvhTriangle), sizeof(shared::BvhTriangle));
            }
            access.issue(report.triangles);
          }
        }
      }
      for (std::size_t l = 0; l < active; ++l) {
        report.nodeVisits += lanes[l].size();
        for (const Iteration& it : lanes[l]) report.triangleTests += it.leafTested[0] + it.leafTested[1];
      }
    }
    // visibility[point.pixel] = ...;
    for (std::size_t l = 0; l < active; ++l) {
      const shared::ShadingPoint& point = points[first + l];
      access.add(std::uint64_t(point.pixel) * sizeof(float), sizeof(float));
      if (visibility) (*visibility)[first + l] = float(visible[l]) / float(std::max(point.spp, 1u));
    }
    access.issue(report.visibility);
  }
  return report;
}

BandwidthReport simulateTraceBandwidth(const BvhTracer& tracer, const TraceJob& job, const shared::GpuLight& light,
                                       const BandwidthSettings& settings) {
  if (tracer.dynamicRoot() != BVH_NO_TREE) {
    throw InputError("--simulate-bandwidth replays the static scene's BVH only, but this scene has moving meshes "
                     "(a second, dynamic tree); run it without --simulate-bandwidth");
  }
  const std::uint32_t count = job.count.download<shared::TraceCount>(1).front().count;
  const auto points = job.points.download<shared::ShadingPoint>(count);
  const auto nodes = tracer.nodeBuffer().download<shared::BvhNode>(tracer.nodeBuffer().size() / sizeof(shared::BvhNode));
  const auto triangles =
      tracer.triangleBuffer().download<shared::BvhTriangle>(tracer.triangleBuffer().size() / sizeof(shared::BvhTriangle));
  return simulateTraceBandwidth(nodes, triangles, points, light, settings);
}

// The estimate counts what each pass's shaders and fixed-function stages read and write once, with
// no cache reuse, no compression and no overdraw (one fragment per pixel or texel):
//   G-buffer   3 vertices x 36 bytes per triangle (no post-transform reuse) + per pixel a depth test
//              read and write (4 + 4) and the position, normal and albedo writes (16 + 16 + 4)
//   shadow map per face: 3 x 12-byte positions per triangle + per texel a depth read and write (8)
//   thin mask  per face: 3 x 12-byte positions per triangle + per texel its clear (4); the few
//              thin triangles' own writes are left out
//   classify   srt: per pixel position + normal (32) and four 4-byte writes (visibility, sm
//              visibility, flags, ray interval), plus each shadow-map and mask texel fetched once:
//              min(texels, 9 x pixels) x 4 and min(texels, pixels) x 4 (3x3 neighbourhoods, cached)
//              frt: the two 4-byte fills (visibility, ray interval) per pixel
//   compaction scan: per pixel the flag (4, srt) or the position (16, frt), mask bits written and
//              read back (2 x pixels / 8); scatter: per traced point position + normal + ray
//              interval read (36) and its 48-byte ShadingPoint written
RasterEstimate estimateRasterBytes(const RasterEstimateInput& in) {
  RasterEstimate e;
  const std::uint64_t vertexBytes = in.triangles * 3;
  e.gbuffer = vertexBytes * 36 + in.pixels * (8 + 16 + 16 + 4);
  const std::uint64_t texels = std::uint64_t(in.shadowMapRes) * in.shadowMapRes * in.faces;
  if (in.selective) {
    e.shadowMap = std::uint64_t(in.faces) * vertexBytes * 12 + texels * 8;
    if (in.thinPass) e.thinMask = std::uint64_t(in.faces) * vertexBytes * 12 + texels * 4;
    e.classify = in.pixels * (32 + 16) + std::min(texels, 9 * in.pixels) * 4 +
                 (in.thinPass ? std::min(texels, in.pixels) * 4 : 0);
  } else {
    e.classify = in.pixels * 8;
  }
  e.compaction = in.pixels * (in.selective ? 4 : 16) + 2 * ((in.pixels + 7) / 8) + in.tracedPoints * (36 + 48);
  return e;
}

nlohmann::json toJson(const MemoryTraffic& t) {
  return {{"bytes", t.bytes()}, {"sectors", t.sectors}, {"lines", t.lines}, {"warp_accesses", t.accesses},
          {"lane_accesses", t.laneAccesses}};
}

nlohmann::json toJson(const BandwidthReport& r, const RasterEstimate& raster) {
  return {{"trace_bytes", r.bytes()},
          {"trace_lines", r.lines()},
          {"streams", {{"nodes", toJson(r.nodes)}, {"triangles", toJson(r.triangles)}, {"shading_points", toJson(r.points)},
                       {"visibility_writes", toJson(r.visibility)}}},
          {"warps", r.warps},
          {"invocations", r.invocations},
          {"rays", r.rays},
          {"node_visits", r.nodeVisits},
          {"triangle_tests", r.triangleTests},
          {"model", "warps of 32 in dispatch order, lanes in lockstep per traversal iteration; bytes = distinct 32-byte "
                    "sectors x 32 per warp-wide access, no cache reuse (raytrace/bandwidth_model.h)"},
          {"raster_bytes", {{"gbuffer", raster.gbuffer}, {"shadow_map", raster.shadowMap}, {"thin_mask", raster.thinMask},
                            {"classify", raster.classify}, {"compaction", raster.compaction}, {"total", raster.total()}}},
          {"raster_model", "each pass's reads and writes once per vertex, pixel and texel, no caches, compression or "
                           "overdraw (raytrace/bandwidth_model.cpp, estimateRasterBytes)"}};
}

}  // namespace penumbra
