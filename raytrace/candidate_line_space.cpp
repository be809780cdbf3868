#include "raytrace/candidate_line_space.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cstdio>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <unordered_set>

#include <embree3/rtcore.h>

#include "core/units.h"
#include "raytrace/embree_handles.h"
#include "raytrace/line_space.h"
#include "shared/linespace.h"

namespace penumbra {
namespace {

// Runs body(i) for i in [0, count) on all cores, items handed out one at a time.
template <typename Body>
void parallelItems(std::size_t count, Body&& body) {
  std::atomic<std::size_t> next{0};
  auto run = [&] {
    for (std::size_t i = next++; i < count; i = next++) body(i);
  };
  const std::size_t workers = std::min<std::size_t>(std::max(1u, std::thread::hardware_concurrency()), count);
  std::vector<std::thread> pool;
  for (std::size_t w = 1; w < workers; ++w) pool.emplace_back(run);
  run();
  for (std::thread& t : pool) t.join();
}

// One box's dense row as bits (its csWordsPerBox words) and its filled shafts' candidates in order.
void packRow(std::span<const std::uint32_t> row, std::uint32_t* bits, std::vector<std::uint32_t>& packed) {
  for (std::size_t s = 0; s < row.size(); ++s) {
    if (row[s] == CS_NONE) continue;
    bits[s / 32] |= 1u << (s % 32);
    packed.push_back(row[s]);
  }
}

// Offsets (exclusive prefix sum of the popcounts over all words) and the packed candidates, from
// each box's packed list; fills the counting stats.
void finishLayout(CandidateLineSpace& out, const std::vector<std::vector<std::uint32_t>>& packed) {
  out.offsets.resize(out.bits.size());
  std::uint64_t sum = 0;
  for (std::size_t w = 0; w < out.bits.size(); ++w) {
    out.offsets[w] = std::uint32_t(sum);
    sum += std::uint64_t(std::popcount(out.bits[w]));
  }
  out.candidates.clear();
  out.candidates.reserve(sum);
  for (const auto& list : packed) out.candidates.insert(out.candidates.end(), list.begin(), list.end());
  if (out.candidates.size() != sum) throw std::logic_error("candidate line space: packed count differs from the bits");
  CandidateStats& s = out.stats;
  s.n = out.n;
  s.boxes = out.boxes.size();
  s.shafts = s.boxes * shared::csShaftCount(out.n);
  s.filled = sum;
  s.filledFraction = s.shafts ? double(sum) / double(s.shafts) : 0.0;
  const std::uint64_t boxBytes = out.boxes.size() * sizeof(shared::CsBox);
  s.sparseBytes = boxBytes + (out.bits.size() + out.offsets.size() + out.candidates.size()) * sizeof(std::uint32_t);
  s.denseBytes = boxBytes + s.shafts * sizeof(std::uint32_t);
}

void setWordBases(CandidateLineSpace& out) {
  const std::uint32_t words = out.wordsPerBox();
  for (std::size_t i = 0; i < out.boxes.size(); ++i) out.boxes[i].wordBase = std::uint32_t(i * words);
  out.bits.assign(out.boxes.size() * std::size_t(words), 0u);
}

// The meshes in `set` as one Embree scene; geomID -> scene-order index of the mesh's first triangle.
struct EmbreeScene {
  std::mutex errorMutex;
  std::string firstError;
  embree::DevicePtr device;
  embree::ScenePtr scene;
  std::vector<std::uint32_t> firstTriangle;

  static void onError(void* user, RTCError code, const char* message) {
    auto* self = static_cast<EmbreeScene*>(user);
    std::lock_guard lock(self->errorMutex);
    if (self->firstError.empty())
      self->firstError = std::string(embree::errorName(code)) + (message ? std::string(": ") + message : "");
  }
  void check(const char* stage) {
    std::lock_guard lock(errorMutex);
    if (!firstError.empty())
      throw std::runtime_error(std::string("candidate line space: Embree ") + stage + ": " + firstError);
  }

  EmbreeScene(const Scene& input, MeshSet set) {
    device.reset(rtcNewDevice(nullptr));
    if (!device) throw std::runtime_error("candidate line space: Embree device creation failed");
    rtcSetDeviceErrorFunction(device.get(), &onError, this);
    scene.reset(rtcNewScene(device.get()));
    rtcSetSceneFlags(scene.get(), RTC_SCENE_FLAG_ROBUST);
    std::uint32_t base = 0;
    for (const Mesh& mesh : input.meshes) {
      const std::size_t triangles = mesh.triangleCount();
      const std::uint32_t first = base;
      base += std::uint32_t(triangles);
      if (triangles == 0 || !inMeshSet(mesh, set)) continue;
      embree::GeometryPtr geom(rtcNewGeometry(device.get(), RTC_GEOMETRY_TYPE_TRIANGLE));
      auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geom.get(), RTC_BUFFER_TYPE_VERTEX, 0,
                                                                   RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                                   triangles * 3));
      auto* indices = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
          geom.get(), RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), triangles));
      check("buffer allocation");
      float extent = 0.0f;
      for (std::size_t t = 0; t < triangles; ++t) {
        glm::vec3 v[3];
        triangleVertices(input, mesh, t, v, extent);  // InputError for bad indices or vertices
        for (int k = 0; k < 3; ++k) {
          vertices[9 * t + 3 * k + 0] = v[k].x;
          vertices[9 * t + 3 * k + 1] = v[k].y;
          vertices[9 * t + 3 * k + 2] = v[k].z;
          indices[3 * t + k] = std::uint32_t(3 * t + k);
        }
      }
      rtcCommitGeometry(geom.get());
      const unsigned id = rtcAttachGeometry(scene.get(), geom.get());
      if (id >= firstTriangle.size()) firstTriangle.resize(id + 1, 0);
      firstTriangle[id] = first;
    }
    rtcCommitScene(scene.get());
    check("scene build");
  }
};

}  // namespace

CandidateSizes candidateWorstCaseSizes(std::uint32_t n, std::uint64_t boxes) {
  CandidateSizes s;
  s.boxBytes = boxes * sizeof(shared::CsBox);
  s.bitBytes = boxes * shared::csWordsPerBox(n) * sizeof(std::uint32_t);
  s.offsetBytes = s.bitBytes;
  s.candidateBytes = boxes * shared::csShaftCount(n) * sizeof(std::uint32_t);
  return s;
}

std::uint32_t CandidateLineSpace::lookup(std::uint32_t box, std::uint32_t shaft) const {
  const std::uint32_t w = boxes[box].wordBase + shaft / 32, b = shaft % 32;
  if (!((bits[w] >> b) & 1u)) return CS_NONE;
  return candidates[shared::csDataIndex(offsets[w], bits[w], b)];
}

void packCandidates(std::uint32_t n, std::span<const std::uint32_t> dense, CandidateLineSpace& out) {
  const std::size_t shafts = shared::csShaftCount(n);
  if (dense.size() % shafts != 0) throw std::invalid_argument("packCandidates: dense table is not whole boxes");
  out.n = n;
  if (out.boxes.size() != dense.size() / shafts) out.boxes.assign(dense.size() / shafts, shared::CsBox{});
  setWordBases(out);
  std::vector<std::vector<std::uint32_t>> packed(out.boxes.size());
  for (std::size_t i = 0; i < out.boxes.size(); ++i)
    packRow(dense.subspan(i * shafts, shafts), out.bits.data() + out.boxes[i].wordBase, packed[i]);
  finishLayout(out, packed);
}

glm::vec3 candidatePatchCentroid(const glm::vec3& lo, const glm::vec3& hi, std::uint32_t face, std::uint32_t patch,
                                 std::uint32_t n) {
  const std::uint32_t a = face / 2, u = (a + 1) % 3, v = (a + 2) % 3;
  glm::vec3 p;
  p[a] = (face % 2) ? hi[a] : lo[a];
  p[u] = lo[u] + (float(patch % n) + 0.5f) / float(n) * (hi[u] - lo[u]);
  p[v] = lo[v] + (float(patch / n) + 0.5f) / float(n) * (hi[v] - lo[v]);
  return p;
}

CandidateLineSpace buildCandidateLineSpace(const Scene& scene, std::span<const CandidateBox> boxes,
                                           const CandidateSettings& settings, std::uint64_t maxBufferBytes,
                                           MeshSet set) {
  const auto start = std::chrono::steady_clock::now();
  const std::uint32_t n = settings.n;
  const std::string what = "candidate line space (N=" + std::to_string(n) + ", " + std::to_string(boxes.size()) +
                           " boxes) of scene '" + scene.name + "'";
  if (n < LS_MIN_N || n > LS_MAX_N) {
    throw InputError(what + ": N must be in " + std::to_string(LS_MIN_N) + ".." + std::to_string(LS_MAX_N));
  }
  const CandidateSizes sizes = candidateWorstCaseSizes(n, boxes.size());
  const std::uint64_t budget = settings.budgetBytes ? settings.budgetBytes : defaultLineSpaceBudget();
  if (sizes.total() > budget) {
    throw InputError(what + " may need " + megabytes(sizes.total()) + " (bits " + megabytes(sizes.bitBytes) +
                     ", offsets " + megabytes(sizes.offsetBytes) + ", candidates up to " +
                     megabytes(sizes.candidateBytes) + ") but the budget is " + megabytes(budget) +
                     "; lower N, or choose fewer boxes (a shallower line-space depth D), or raise the budget");
  }
  const std::uint64_t largest = std::max(sizes.offsetBytes, std::max(sizes.bitBytes, sizes.boxBytes));
  if (maxBufferBytes && largest > maxBufferBytes) {
    throw InputError(what + " may need " + megabytes(largest) + " in one buffer but the device binds at most " +
                     megabytes(maxBufferBytes) +
                     " per storage buffer (maxStorageBufferRange); lower N or choose fewer boxes (a shallower depth D)");
  }
  if (settings.maxCandidateBytes && sizes.candidateBytes > settings.maxCandidateBytes) {
    throw InputError(what + " may need " + megabytes(sizes.candidateBytes) + " of candidates in one buffer but the device "
                     "holds at most " + megabytes(settings.maxCandidateBytes) +
                     " in one (maxBufferSize, maxMemoryAllocationSize); lower N or choose fewer boxes (a shallower depth D)");
  }
  if (sizes.candidateBytes / sizeof(std::uint32_t) >= CS_NONE) throw InputError(what + ": too many shafts for 32-bit offsets; lower N or D");

  CandidateLineSpace out;
  out.n = n;
  out.boxes.resize(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    out.boxes[i] = shared::CsBox{boxes[i].lo, 0u, boxes[i].hi, boxes[i].node};
  }
  setWordBases(out);
  const std::size_t shafts = shared::csShaftCount(n);
  if (settings.keepDense) out.dense.assign(boxes.size() * shafts, CS_NONE);

  const auto embreeStart = std::chrono::steady_clock::now();
  EmbreeScene embree(scene, set);
  out.stats.embreeMs = msSince(embreeStart);

  // The segments of one box: centroids of every patch; each directed pair of faces.
  std::vector<std::vector<std::uint32_t>> packed(boxes.size());
  const std::uint32_t patches = n * n;
  parallelItems(boxes.size(), [&](std::size_t i) {
    const glm::vec3 lo = boxes[i].lo, hi = boxes[i].hi;
    std::vector<glm::vec3> centroid(6 * patches);
    for (std::uint32_t f = 0; f < 6; ++f)
      for (std::uint32_t p = 0; p < patches; ++p) centroid[f * patches + p] = candidatePatchCentroid(lo, hi, f, p, n);
    std::vector<std::uint32_t> row(shafts, CS_NONE);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (std::uint32_t fi = 0; fi < 6; ++fi) {
      for (std::uint32_t fo = 0; fo < 6; ++fo) {
        if (fo == fi) continue;
        for (std::uint32_t pi = 0; pi < patches; ++pi) {
          const glm::vec3 a = centroid[fi * patches + pi];
          for (std::uint32_t po = 0; po < patches; ++po) {
            const glm::vec3 d = centroid[fo * patches + po] - a;
            RTCRayHit rh{};
            rh.ray.org_x = a.x;
            rh.ray.org_y = a.y;
            rh.ray.org_z = a.z;
            rh.ray.dir_x = d.x;
            rh.ray.dir_y = d.y;
            rh.ray.dir_z = d.z;
            rh.ray.tnear = 0.0f;
            rh.ray.tfar = 1.0f;
            rh.ray.mask = ~0u;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(embree.scene.get(), &context, &rh);
            if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
            row[shared::csShaft(fi, pi, fo, po, n)] = embree.firstTriangle[rh.hit.geomID] + rh.hit.primID;
          }
        }
      }
    }
    packRow(row, out.bits.data() + out.boxes[i].wordBase, packed[i]);
    if (settings.keepDense) std::copy(row.begin(), row.end(), out.dense.begin() + std::ptrdiff_t(i * shafts));
  });
  embree.check("tracing");
  finishLayout(out, packed);
  out.stats.raysCast = out.stats.shafts;
  out.stats.buildMs = msSince(start);
  return out;
}

// ---- Placement ------------------------------------------------------------------------------

namespace {

// Adds the distinct triangles under child entry `entry` to `seen` until it holds `limit`.
void collectTriangles(const NTree& tree, std::uint32_t entry, std::size_t limit,
                      std::unordered_set<std::uint32_t>& seen) {
  if (entry == NTree::kEmpty || seen.size() >= limit) return;
  if (entry & NTree::kLeafBit) {
    const NTree::Leaf& leaf = tree.leaves[entry & ~NTree::kLeafBit];
    for (std::uint32_t k = 0; k < leaf.count && seen.size() < limit; ++k) seen.insert(tree.leafTriangles[leaf.first + k]);
    return;
  }
  const std::uint32_t cells = tree.n * tree.n * tree.n;
  for (std::uint32_t c = 0; c < cells && seen.size() < limit; ++c) collectTriangles(tree, tree.child(entry, c), limit, seen);
}

}  // namespace

std::vector<CandidateBox> boxesAtDepth(const NTree& tree, std::uint32_t depth, std::uint32_t minTriangles) {
  if (tree.nodes.empty() || depth >= tree.depth) {
    throw InputError("candidate line space: N-tree depth " + std::to_string(depth) +
                     " has no subdivided nodes (the tree's subdivided nodes are at levels 0.." +
                     std::to_string(tree.depth ? tree.depth - 1 : 0) + "); choose a smaller D");
  }
  std::vector<CandidateBox> out;
  const std::uint32_t cells = tree.n * tree.n * tree.n;
  std::vector<std::uint32_t> stack{0};
  std::unordered_set<std::uint32_t> seen;
  while (!stack.empty()) {
    const std::uint32_t node = stack.back();
    stack.pop_back();
    const NTree::Node& nd = tree.nodes[node];
    bool chosen = nd.level == depth;
    if (!chosen && minTriangles > 0) {
      seen.clear();
      collectTriangles(tree, node, minTriangles, seen);
      chosen = seen.size() < minTriangles;
    }
    if (chosen) {
      out.push_back({nd.lo, nd.lo + glm::vec3(nd.size), node});
      continue;
    }
    for (std::uint32_t c = cells; c-- > 0;) {
      const std::uint32_t entry = tree.child(node, c);
      if (entry != NTree::kEmpty && !(entry & NTree::kLeafBit)) stack.push_back(entry);
    }
  }
  return out;
}

BvhLineSpaceNodes bvhNodesAtDepth(const Bvh& bvh, std::uint32_t depth) {
  BvhLineSpaceNodes out;
  out.nodeMap.assign(bvh.nodes.size(), CS_NONE);
  if (bvh.nodes.empty()) return out;
  struct Item {
    std::uint32_t node, depth;
    glm::vec3 lo, hi;
  };
  auto isSlot = [](const shared::BvhChild& c) { return c.count > 0 || c.index != 0; };
  const shared::BvhNode& root = bvh.nodes[0];
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const shared::BvhChild& c : root.child) {
    if (!isSlot(c)) continue;
    lo = glm::min(lo, c.lo);
    hi = glm::max(hi, c.hi);
  }
  std::vector<Item> stack{{0u, 0u, lo, hi}};
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    if (item.depth == depth) {
      out.nodeMap[item.node] = std::uint32_t(out.boxes.size());
      out.boxes.push_back({item.lo, item.hi, item.node});
      continue;
    }
    const shared::BvhNode& node = bvh.nodes[item.node];
    for (int k = 1; k >= 0; --k) {
      const shared::BvhChild& c = node.child[k];
      if (c.count == 0 && c.index != 0) stack.push_back({c.index, item.depth + 1, c.lo, c.hi});
    }
  }
  return out;
}

}  // namespace penumbra
