// The GPU BVH against its own invariants and against Embree (robust mode, the reference).
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <random>
#include <tuple>
#include <vector>

#include "core/camera.h"
#include "core/gpu_light.h"
#include "raytrace/bvh_tracer.h"
#include "raytrace/embree_tracer.h"
#include "embree_rays.h"
#include "render_fixture.h"
#include "shared/frame.h"
#include "shared/trace.h"

namespace penumbra {
namespace {

using shared::RayHit;
using shared::RayQuery;
using test::expectValidationSilent;
using test::validatedContext;

// Disagreements with Embree must be numerical ties: the ray crosses the triangle's plane within
// kTieEps * scene radius of one of its edges, or of either end of the ray interval.
constexpr double kTieEps = 1e-5;
constexpr double kMinAgreement = 0.9999;

struct Tri {
  glm::dvec3 v[3];
};

std::vector<Tri> sceneTriangles(const Scene& scene) {
  std::vector<Tri> out;
  for (const Mesh& m : scene.meshes) {
    for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3) {
      out.push_back({{m.positions[m.indices[i]], m.positions[m.indices[i + 1]], m.positions[m.indices[i + 2]]}});
    }
  }
  return out;
}

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// ---- Builder invariants --------------------------------------------------------------------

struct TreeCheck {
  const Bvh& bvh;
  std::vector<int> seenTriangles, seenNodes;
  std::uint32_t depth = 0;

  // Returns the bounds of the subtree's vertices; every child box must contain its subtree's.
  Bounds visit(std::uint32_t index, std::uint32_t level) {
    seenNodes.at(index)++;
    depth = std::max(depth, level);
    Bounds all;
    for (const shared::BvhChild& c : bvh.nodes[index].child) {
      if (c.count == 0 && c.index == 0) continue;  // the empty slot of a one-leaf tree
      Bounds sub;
      if (c.count == 0) sub = visit(c.index, level + 1);
      for (std::uint32_t i = c.index; i < c.index + c.count; ++i) {
        const shared::BvhTriangle& t = bvh.triangles.at(i);
        seenTriangles.at(t.id)++;
        for (const glm::vec3& v : {t.v0, t.v1, t.v2}) sub.extend(v);
      }
      EXPECT_TRUE(glm::all(glm::lessThanEqual(c.lo, sub.lo)) && glm::all(glm::greaterThanEqual(c.hi, sub.hi)))
          << "child box of node " << index << " does not contain its subtree";
      all.extend(sub.lo);
      all.extend(sub.hi);
    }
    return all;
  }
};

void checkTree(const Scene& scene, const Bvh& bvh) {
  const std::vector<Tri> tris = sceneTriangles(scene);
  TreeCheck check{bvh, std::vector<int>(tris.size(), 0), std::vector<int>(bvh.nodes.size(), 0)};
  check.visit(0, 1);
  for (std::size_t i = 0; i < tris.size(); ++i) ASSERT_EQ(check.seenTriangles[i], 1) << "triangle " << i;
  for (std::size_t i = 0; i < bvh.nodes.size(); ++i) ASSERT_EQ(check.seenNodes[i], 1) << "node " << i;
  for (const shared::BvhTriangle& t : bvh.triangles) {  // reordered, not altered
    EXPECT_TRUE(glm::dvec3(t.v0) == tris[t.id].v[0] && glm::dvec3(t.v2) == tris[t.id].v[2]) << t.id;
  }
  const BvhStats& s = bvh.stats;
  EXPECT_EQ(s.triangles, tris.size());
  EXPECT_EQ(s.nodes, bvh.nodes.size());
  EXPECT_EQ(s.nodes, std::max<std::uint64_t>(s.leaves, 2) - 1);  // binary; a one-leaf tree keeps its root
  EXPECT_EQ(s.bytes, s.nodes * sizeof(shared::BvhNode) + s.triangles * sizeof(shared::BvhTriangle));
  EXPECT_TRUE(std::isfinite(s.sahCost) && s.sahCost >= 1.0) << s.sahCost;
  EXPECT_EQ(s.maxDepth, check.depth);
  EXPECT_LE(s.maxDepth, std::uint32_t(BVH_STACK_SIZE));
}

TEST(BvhBuilder, LeavesHoldEveryTriangleOnceInsideEveryBox) {
  for (const char* spec : {"builtin:courtyard:2", "builtin:room", "builtin:wires"}) {
    const Scene scene = loadScene(spec);
    for (std::uint32_t leafSize : {1u, 4u, 8u}) {
      SCOPED_TRACE(std::string(spec) + " leaf size " + std::to_string(leafSize));
      checkTree(scene, BvhBuilder({.maxLeafSize = leafSize}).build(scene));
    }
  }
}

Scene oneTriangle() {
  Scene s{.name = "one triangle"};
  s.meshes.push_back({.name = "tri", .positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, .indices = {0, 1, 2}});
  return s;
}

TEST(BvhBuilder, OneLeafRootAndEmptySceneAndBadSettings) {
  const Bvh bvh = BvhBuilder().build(oneTriangle());
  checkTree(oneTriangle(), bvh);
  EXPECT_EQ(bvh.stats.leaves, 1u);
  EXPECT_THROW(BvhBuilder().build(Scene{.name = "empty"}), InputError);
  Scene bad = oneTriangle();
  bad.meshes[0].indices[2] = 7;
  EXPECT_THROW(BvhBuilder().build(bad), InputError);
  EXPECT_THROW(BvhBuilder({.maxLeafSize = 0}), std::invalid_argument);
  EXPECT_THROW(BvhBuilder({.maxLeafSize = 9}), std::invalid_argument);
}

TEST(BvhTracer, OneTriangleHitsAndMisses) {
  BvhTracer tracer(validatedContext(), oneTriangle());
  const std::vector<RayQuery> rays = {{{0.25f, 0.25f, 2.0f}, 0.0f, {0, 0, -1}, 10.0f},   // hit at t = 2
                                      {{0.75f, 0.75f, 2.0f}, 0.0f, {0, 0, -1}, 10.0f},   // beside it
                                      {{0.25f, 0.25f, 2.0f}, 0.0f, {0, 0, -1}, 1.5f},    // stops short
                                      {{0.25f, 0.25f, 2.0f}, 2.5f, {0, 0, -1}, 10.0f}};  // starts beyond
  for (bool anyHit : {true, false}) {
    const std::vector<RayHit> hits = tracer.traceRays(rays, anyHit);
    EXPECT_FLOAT_EQ(hits[0].t, 2.0f);
    EXPECT_EQ(hits[0].triangle, 0u);
    for (int i = 1; i < 4; ++i) EXPECT_TRUE(hits[i].triangle == BVH_NO_HIT && hits[i].t < 0.0f) << i;
  }
  expectValidationSilent();
}

// Degenerate input (issue 20): a million copies of one triangle cannot be split by area, so the
// builder stacks them in leaves of at most kMaxLeafSize; the tree stays shallow, and rays through
// the stack hit its plane while rays beside it miss, for both queries.
TEST(BvhTracer, MillionIdenticalTrianglesTrace) {
  Scene stack = oneTriangle();
  stack.meshes[0].indices.resize(3 * 1000000);
  for (std::size_t i = 0; i < stack.meshes[0].indices.size(); ++i) stack.meshes[0].indices[i] = std::uint32_t(i % 3);
  BvhTracer tracer(validatedContext(), stack);
  EXPECT_EQ(tracer.stats().triangles, 1000000u);
  EXPECT_LE(tracer.stats().maxDepth, std::uint32_t(BVH_STACK_SIZE));
  const std::vector<RayQuery> rays = {{{0.25f, 0.25f, 2.0f}, 0.0f, {0, 0, -1}, 10.0f},
                                      {{0.75f, 0.75f, 2.0f}, 0.0f, {0, 0, -1}, 10.0f}};
  for (bool anyHit : {true, false}) {
    const std::vector<RayHit> hits = tracer.traceRays(rays, anyHit);
    EXPECT_FLOAT_EQ(hits[0].t, 2.0f);
    EXPECT_LT(hits[0].triangle, 1000000u);
    EXPECT_TRUE(hits[1].triangle == BVH_NO_HIT && hits[1].t < 0.0f);
  }
  expectValidationSilent();
}

// The kernels read the tree through device addresses, so one buffer bounds it (lavapipe: 2 GiB,
// 44 M triangles), not one binding's range; a scene beyond that is refused before building.
TEST(BvhTracer, RefusesSceneBeyondOneBuffer) {
  const std::uint64_t limit = validatedContext().maxBufferBytes();
  if (limit > (std::uint64_t(1) << 31)) GTEST_SKIP() << "this device holds " << limit << " bytes: too many to make";
  Scene huge = oneTriangle();
  huge.name = "huge";
  huge.meshes[0].indices.assign(3 * (limit / sizeof(shared::BvhTriangle) + 1), 0u);
  try {
    BvhTracer tracer(validatedContext(), huge);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {  // names the scene, its size and the limit
    const std::string what = e.what();
    EXPECT_TRUE(what.find("'huge'") != std::string::npos && what.find("maxMemoryAllocationSize") != std::string::npos)
        << what;
  }
  expectValidationSilent();
}

// On a device whose storage bindings span only 64 KiB (ContextOptions' test limit; lavapipe's are
// 128 MiB), the courtyard's 1.3 MiB tree still traces, and srt's trace list (48 bytes a pixel)
// still holds every flagged pixel of a 128^2 frame, since the kernels read both through device
// addresses: frt and srt make the same frames as on the full device. Before, the tracer refused
// any tree over one binding, and srt any frame that flagged more pixels than one binding holds.
TEST(BvhTracer, TreeLargerThanOneBindingTraces) {
  gpu::Context limited({.validate = true, .printMessages = true, .storageBufferRangeLimit = 64 * 1024});
  ASSERT_EQ(limited.storageBufferRange(), 64u * 1024u);
  const Scene scene = loadScene("builtin:courtyard");
  RenderSettings settings = test::smallSettings(128, 1024);
  settings.tracer = "bvh";
  Renderer full(validatedContext(), scene, settings), small(limited, scene, settings);
  const Camera camera = *scene.camera;
  const Light light = scene.lights.front();
  EXPECT_EQ(small.render("frt", camera, light).visibility, full.render("frt", camera, light).visibility);
  const Frame srt = full.render("srt", camera, light);
  EXPECT_GT(srt.stats.pipPixels.value() * sizeof(shared::ShadingPoint), limited.storageBufferRange());
  EXPECT_EQ(small.render("srt", camera, light).visibility, srt.visibility);
  const auto messages = limited.validationMessages();
  EXPECT_TRUE(messages.empty()) << messages.front();
  expectValidationSilent();
}

// ---- Arbitrary rays against Embree ---------------------------------------------------------

double segmentDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  return glm::length(p - (a + glm::clamp(glm::dot(p - a, ab) / std::max(glm::dot(ab, ab), 1e-300), 0.0, 1.0) * ab));
}

glm::dvec3 normalOf(const Tri& t) { return glm::normalize(glm::cross(t.v[1] - t.v[0], t.v[2] - t.v[0])); }

// Whether a hit on `tri` that one tracer saw and the other did not is a numerical tie: where the
// ray crosses the triangle's plane (in double precision) lies within eps of an edge, or that
// crossing lies within eps of an end of the ray interval.
bool isTie(const RayQuery& q, const Tri& tri, double eps) {
  const glm::dvec3 o(q.origin), d(q.direction), n = normalOf(tri);
  if (glm::dot(n, d) == 0.0) return true;  // in the plane: every answer is a tie
  const double t = glm::dot(tri.v[0] - o, n) / glm::dot(n, d);
  const glm::dvec3 p = o + t * d;
  const double edge = std::min({segmentDistance(p, tri.v[0], tri.v[1]), segmentDistance(p, tri.v[1], tri.v[2]),
                                segmentDistance(p, tri.v[2], tri.v[0])});
  const double len = glm::length(d);
  return edge <= eps || std::abs(t - q.tMin) * len <= eps || std::abs(t - q.tMax) * len <= eps;
}

// Edges (triangle, edge index) whose two triangles share both vertices and lie in one plane: a
// ray through such an edge crosses the surface, so a watertight test must report a hit.
std::vector<std::pair<std::uint32_t, int>> flatSharedEdges(const std::vector<Tri>& tris) {
  std::map<std::array<double, 6>, std::vector<std::pair<std::uint32_t, int>>> edges;
  for (std::uint32_t t = 0; t < tris.size(); ++t) {
    for (int e = 0; e < 3; ++e) {
      glm::dvec3 a = tris[t].v[e], b = tris[t].v[(e + 1) % 3];
      if (std::tie(b.x, b.y, b.z) < std::tie(a.x, a.y, a.z)) std::swap(a, b);
      edges[{a.x, a.y, a.z, b.x, b.y, b.z}].push_back({t, e});
    }
  }
  std::vector<std::pair<std::uint32_t, int>> out;
  for (const auto& [key, list] : edges) {
    if (list.size() == 2 && std::abs(glm::dot(normalOf(tris[list[0].first]), normalOf(tris[list[1].first]))) > 0.9999) {
      out.push_back(list[0]);
    }
  }
  return out;
}

enum RayKind { kRandom, kEdgeOn, kFlatEdge, kAnyEdgeOrVertex, kOnSurface, kKinds };
const char* kKindNames[kKinds] = {"random", "edge-on", "flat shared edge", "edge/vertex", "on surface"};

// Rays of every kind in turn: random; nearly parallel to a triangle (1e-2..1e-4 rad off its
// plane) through a point of it; through a shared edge of two coplanar triangles, >= 45 degrees off
// their plane (must hit); aimed at any edge point or vertex (silhouettes included); starting
// exactly on a surface.
std::vector<RayQuery> makeRays(const Scene& scene, const std::vector<Tri>& tris, std::size_t count) {
  const Bounds b = scene.bounds();
  const float r = b.radius();
  const auto flat = flatSharedEdges(tris);
  std::mt19937 rng(7u);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  auto pick = [&](std::size_t n) { return std::min(std::size_t(uni(rng) * float(n)), n - 1); };
  auto sphere = [&] {
    const float z = 2.0f * uni(rng) - 1.0f, phi = 6.2831853f * uni(rng), s = std::sqrt(std::max(0.0f, 1.0f - z * z));
    return glm::vec3(s * std::cos(phi), s * std::sin(phi), z);
  };
  auto onEdge = [&](const Tri& t, int e, float u) {
    return glm::vec3(t.v[e] + double(u) * (t.v[(e + 1) % 3] - t.v[e]));
  };
  auto aimAt = [&](RayQuery& q, glm::vec3 target, glm::vec3 from) {
    q.origin = target + from * (r * (0.02f + uni(rng)));
    q.direction = glm::normalize(target - q.origin);
    q.tMax = 2.0f * glm::distance(target, q.origin);
  };
  std::vector<RayQuery> rays(count);
  for (std::size_t i = 0; i < count; ++i) {
    RayQuery& q = rays[i];
    const Tri& t = tris[pick(tris.size())];
    float u = uni(rng), v = uni(rng);
    if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
    const glm::vec3 inside(t.v[0] + double(u) * (t.v[1] - t.v[0]) + double(v) * (t.v[2] - t.v[0]));
    if (i % kKinds == kRandom) {  // in and around the scene, some starting later, some unbounded
      q.origin = b.lo + (b.hi - b.lo) * (glm::vec3(uni(rng), uni(rng), uni(rng)) * 1.2f - 0.1f);
      q.direction = sphere() * (i % 3 == 0 ? 0.5f + 2.0f * uni(rng) : 1.0f);  // not always unit
      q.tMin = i % 4 == 0 ? 0.3f * r * uni(rng) : 0.0f;
      q.tMax = i % 2 ? 3.0e38f : q.tMin + 2.0f * r * uni(rng);
    } else if (i % kKinds == kEdgeOn) {
      const glm::vec3 n = normalOf(t);
      const float tilt = std::pow(10.0f, -2.0f - 2.0f * uni(rng)) * (uni(rng) < 0.5f ? -1.0f : 1.0f);
      q.direction = glm::normalize(glm::normalize(glm::cross(n, sphere())) + tilt * n);
      q.tMax = r * (0.01f + uni(rng));
      q.origin = inside - q.tMax * q.direction;
      q.tMax *= 2.0f;
    } else if (i % kKinds == kFlatEdge) {
      const auto [tri, e] = flat[pick(flat.size())];
      const glm::vec3 n = normalOf(tris[tri]);
      aimAt(q, onEdge(tris[tri], e, uni(rng)),
            glm::normalize(n * (uni(rng) < 0.5f ? -1.0f : 1.0f) + glm::cross(n, sphere())));
    } else if (i % kKinds == kAnyEdgeOrVertex) {
      aimAt(q, onEdge(t, int(pick(3)), i % 4 == 0 ? 0.0f : uni(rng)), sphere());  // a vertex one time in four
    } else {
      q.origin = inside;
      q.direction = sphere();
      q.tMax = r * (0.1f + 2.0f * uni(rng));
    }
  }
  return rays;
}

struct Agreement {
  std::size_t rays = 0, agree = 0, untied = 0, leaks = 0, sameTriangle = 0, tOff = 0;
  std::size_t disagree[kKinds] = {};
};

void compareWithEmbree(const std::string& spec, std::size_t count, Agreement& a) {
  const Scene scene = loadScene(spec);
  const std::vector<Tri> tris = sceneTriangles(scene);
  const test::EmbreeRays embree(scene, validatedContext());
  BvhTracer tracer(validatedContext(), scene);
  const std::vector<RayQuery> rays = makeRays(scene, tris, count);
  const float radius = scene.bounds().radius();
  const auto start = std::chrono::steady_clock::now();
  const std::vector<RayHit> anyHits = tracer.traceRays(rays, true);
  const double anyMs = msSince(start);
  const TraceReport anyReport = tracer.lastRaysReport();
  const std::vector<RayHit> closestHits = tracer.traceRays(rays, false);
  a.rays = rays.size();
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const RayQuery& q = rays[i];
    const RTCRayHit ref = embree.closest(q);
    const bool refHit = ref.hit.geomID != RTC_INVALID_GEOMETRY_ID, occluded = embree.occluded(q);
    const RayHit& gpu = closestHits[i];
    const bool gpuHit = gpu.triangle != BVH_NO_HIT, gpuAny = anyHits[i].triangle != BVH_NO_HIT;
    ASSERT_EQ(occluded, refHit) << "Embree's any-hit and closest-hit disagree on ray " << i;
    ASSERT_EQ(gpuAny, gpuHit) << "the GPU's any-hit and closest-hit disagree on ray " << i;
    if (i % kKinds == kFlatEdge) a.leaks += !gpuHit;
    const bool sameT = gpuHit && refHit && std::abs(gpu.t - ref.ray.tfar) <= 1e-4f * ref.ray.tfar;
    if (gpuAny == occluded && (!gpuHit || gpu.triangle == ref.hit.primID || sameT)) {
      ++a.agree;
    } else {
      ++a.disagree[i % kKinds];
      // The nearer of the two hits is the one the other tracer missed; it must be a tie.
      const bool gpuNearer = gpuHit && (!refHit || gpu.t < ref.ray.tfar);
      if (!isTie(q, tris[gpuNearer ? gpu.triangle : ref.hit.primID], kTieEps * radius) && ++a.untied <= 5) {
        ADD_FAILURE() << spec << ": " << kKindNames[i % kKinds] << " ray " << i << " disagrees away from any edge";
      }
    }
    if (gpuHit && refHit && gpu.triangle == ref.hit.primID) {
      ++a.sameTriangle;
      a.tOff += std::abs(gpu.t - ref.ray.tfar) > 1e-4f * std::max(ref.ray.tfar, 1e-3f * radius);
    }
  }
  EXPECT_EQ(anyReport.rays, rays.size());
  std::printf("[ %s ] %zu rays, %zu disagree (", spec.c_str(), a.rays, a.rays - a.agree);
  for (int k = 0; k < kKinds; ++k) std::printf("%s%s %zu", k ? ", " : "", kKindNames[k], a.disagree[k]);
  std::printf(
      "; %zu not ties), %zu leaks; closest t off > 1e-4 on %zu of %zu; any-hit %.2f Mrays/s, %.1f nodes and "
      "%.1f triangles per ray\n",
      a.untied, a.leaks, a.tOff, a.sameTriangle, double(rays.size()) / anyMs * 1e-3,
      double(*anyReport.nodeVisits) / double(anyReport.rays),
      double(*anyReport.triangleTests) / double(anyReport.rays));
}

// Any-hit and closest-hit agree with Embree on >= 99.99% of rays; every disagreement is a tie
// within kTieEps of the scene radius; no ray leaks through a shared edge; closest t agrees.
TEST(BvhTracer, MillionRaysAgreeWithEmbree) {
  std::size_t total = 0;
  for (const auto& [spec, count] : {std::pair<const char*, std::size_t>{"builtin:courtyard:2", 800000},
                                    {"builtin:room", 100000},
                                    {"builtin:wires", 100000}}) {
    Agreement a;
    ASSERT_NO_FATAL_FAILURE(compareWithEmbree(spec, count, a));
    total += a.rays;
    EXPECT_GE(double(a.agree), kMinAgreement * double(a.rays)) << spec;
    EXPECT_EQ(a.untied, 0u) << spec;
    EXPECT_EQ(a.leaks, 0u) << spec;
    EXPECT_LE(double(a.tOff), (1.0 - kMinAgreement) * double(a.sameTriangle)) << spec;
  }
  EXPECT_GE(total, 1000000u);
  expectValidationSilent();
}

// ---- Shadow rays through the ShadowTracer interface against EmbreeTracer::traceShadows -----

TEST(BvhTracer, ShadowRaysMatchEmbreeTracer) {
  gpu::Context& context = validatedContext();
  const Scene scene = loadScene("builtin:courtyard:2");
  const Bounds bounds = scene.bounds();
  constexpr int kWidth = 800, kHeight = 600;
  const EmbreeTracer reference(scene);
  const std::vector<PrimaryHit> primary =
      reference.tracePrimary(cameraMatrices(*scene.camera, bounds, kWidth, kHeight), kWidth, kHeight);
  BvhTracer tracer(context, scene);

  using Usage = vk::BufferUsageFlagBits;
  gpu::Buffer points(context, primary.size() * sizeof(shared::ShadingPoint), Usage::eShaderDeviceAddress, "test points");
  gpu::Buffer count(context, sizeof(shared::TraceCount), Usage::eStorageBuffer | Usage::eIndirectBuffer, "test count");
  gpu::Buffer frame(context, sizeof(shared::FrameData), Usage::eStorageBuffer, "test frame");
  gpu::Buffer visibility(context, primary.size() * sizeof(float), Usage::eStorageBuffer, "test visibility");
  // The job traces this list, never in place; the G-buffer bindings still need an image each.
  const gpu::Image unread(context, {.format = vk::Format::eR32G32B32A32Sfloat, .usage = vk::ImageUsageFlagBits::eStorage,
                                    .name = "test unread G-buffer"});
  context.submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
    gpu::transition(cmd, unread, {vk::ImageLayout::eUndefined, vk::ImageLayout::eGeneral, vk::PipelineStageFlagBits2::eNone,
                                  vk::AccessFlagBits2::eNone, vk::PipelineStageFlagBits2::eComputeShader,
                                  vk::AccessFlagBits2::eShaderStorageRead});
  });
  const TraceJob job{points, count, frame, visibility, unread.view(), unread.view()};

  Light point = scene.lights.front(), area = point;
  point.type = LightType::Point;
  area.type = LightType::Rect;
  area.size = 3.0f;
  for (const auto& [light, spp] : {std::pair{point, 1u}, std::pair{area, 4u}}) {
    std::vector<shared::ShadingPoint> list;
    for (std::uint32_t i = 0; i < primary.size(); ++i) {
      // Every seventh point traces a bounded interval, as selective methods do.
      const float rayMax = i % 7 == 0 ? 0.2f * bounds.radius() : 0.0f;
      if (primary[i].hit) list.push_back({primary[i].position, i, primary[i].normal, spp, rayMax});
    }
    ASSERT_GT(list.size(), 200000u);
    shared::FrameData frameData{.light = toGpuLight(light, bounds),
                                .spp = spp,
                                .traceCapacity = std::uint32_t(list.size()),
                                .tracePoints = gpu::addressHalves(points)};  // the kernel reads the list through it
    const auto groups = std::uint32_t((list.size() + TRACE_GROUP_SIZE - 1) / TRACE_GROUP_SIZE);
    const shared::TraceCount tc{std::uint32_t(list.size()), groups, 1, 1};
    points.upload(std::span<const shared::ShadingPoint>(list));
    count.upload(std::span<const shared::TraceCount>(&tc, 1));
    frame.upload(std::span<const shared::FrameData>(&frameData, 1));
    visibility.upload(std::span<const float>(std::vector<float>(primary.size(), -1.0f)));

    const auto start = std::chrono::steady_clock::now();
    context.submitAndWait([&](const vk::raii::CommandBuffer& cmd) { tracer.record(cmd, job); });
    const double ms = msSince(start);
    const TraceReport report = tracer.finish(job);
    const std::vector<float> gpu = visibility.download<float>(primary.size());

    std::vector<float> expected(list.size());
    EXPECT_EQ(report.rays, reference.traceShadows(list, frameData.light, expected));
    std::size_t same = 0, written = 0;  // pixels without a point must keep their value
    for (std::size_t i = 0; i < list.size(); ++i) same += gpu[list[i].pixel] == expected[i];
    for (std::size_t i = 0; i < primary.size(); ++i) written += !primary[i].hit && gpu[i] != -1.0f;
    EXPECT_EQ(written, 0u);
    EXPECT_GE(double(same), kMinAgreement * double(list.size())) << lightTypeName(light.type);
    ASSERT_TRUE(report.nodeVisits && report.triangleTests);
    EXPECT_TRUE(*report.nodeVisits > report.rays && *report.triangleTests > 0);
    std::printf(
        "[ %s, spp %u ] %zu points, %zu identical, %llu rays as Embree, %.2f Mrays/s, %.1f node visits and "
        "%.2f triangle tests per ray\n",
        lightTypeName(light.type), spp, list.size(), same, (unsigned long long)report.rays,
        double(report.rays) / ms * 1e-3, double(*report.nodeVisits) / double(report.rays),
        double(*report.triangleTests) / double(report.rays));
  }

  // An empty list dispatches nothing, and the counters start from zero again.
  const shared::TraceCount none{0, 0, 1, 1};
  count.upload(std::span<const shared::TraceCount>(&none, 1));
  context.submitAndWait([&](const vk::raii::CommandBuffer& cmd) { tracer.record(cmd, job); });
  const TraceReport empty = tracer.finish(job);
  EXPECT_TRUE(empty.rays == 0 && *empty.nodeVisits == 0 && *empty.triangleTests == 0);
  expectValidationSilent();
}

}  // namespace
}  // namespace penumbra
