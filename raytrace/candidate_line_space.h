// The candidate line space (Keul et al. 2018, 3): for each chosen box of a hierarchy (BVH inner
// nodes at depth D, N-tree nodes at depth D or with fewer than T triangles) one representative
// triangle per directed shaft, the triangle Embree hits first along the segment from the entry
// patch's centroid to the exit patch's centroid; none leaves the shaft empty. Stored in the
// paper's sparse layout (shared/candidates.h): bits, one offset per 32-bit word, packed
// candidates. The worst-case size (every shaft filled) is checked against the budget and the
// device's per-buffer limit before any ray is cast.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "raytrace/bvh_builder.h"
#include "raytrace/ntree_builder.h"
#include "shared/candidates.h"

namespace penumbra {

static_assert(sizeof(shared::CsBox) == 32, "CsBox must match std430");
static_assert(sizeof(shared::CsParams) == 32, "CsParams must match std430");
static_assert(sizeof(shared::CsRaysPush) == 80, "CsRaysPush must match std430");

// A box that gets a line space, and the index of its node in its hierarchy.
struct CandidateBox {
  glm::vec3 lo{0.0f}, hi{0.0f};
  std::uint32_t node = 0;
};

struct CandidateSettings {
  std::uint32_t n = 6;            // patches per face edge N, LS_MIN_N..LS_MAX_N
  std::uint64_t budgetBytes = 0;  // bits + offsets + worst-case candidates; 0 = defaultLineSpaceBudget()
  bool keepDense = false;         // also keep the dense table (30 N^4 per box), for tests
  // The packed candidates are read through a device address: at most this many bytes in their one
  // buffer (the device's maxBufferSize / maxMemoryAllocationSize); 0 = no limit.
  std::uint64_t maxCandidateBytes = 0;
};

struct CandidateStats {
  std::uint32_t n = 0;
  std::uint64_t boxes = 0;
  std::uint64_t shafts = 0;       // boxes * 30 N^4
  std::uint64_t filled = 0;       // shafts with a candidate
  double filledFraction = 0.0;
  std::uint64_t sparseBytes = 0;  // bits + offsets + packed candidates (+ boxes)
  std::uint64_t denseBytes = 0;   // one 32-bit index per shaft (+ boxes)
  std::uint64_t raysCast = 0;
  double embreeMs = 0.0;          // Embree scene build
  double buildMs = 0.0;           // all of it: Embree scene, rays, packing
};

// Sizes before building: bits and offsets exactly, candidates for every shaft filled.
struct CandidateSizes {
  std::uint64_t boxBytes = 0, bitBytes = 0, offsetBytes = 0, candidateBytes = 0;
  std::uint64_t total() const { return boxBytes + bitBytes + offsetBytes + candidateBytes; }
};
CandidateSizes candidateWorstCaseSizes(std::uint32_t n, std::uint64_t boxes);

struct CandidateLineSpace {
  std::uint32_t n = 0;
  std::vector<shared::CsBox> boxes;
  std::vector<std::uint32_t> bits;        // csWordsPerBox(n) per box
  std::vector<std::uint32_t> offsets;     // one per word of bits
  std::vector<std::uint32_t> candidates;  // packed, scene-order triangle indices
  std::vector<std::uint32_t> dense;       // CandidateSettings::keepDense: 30 N^4 per box, CS_NONE = empty
  CandidateStats stats;

  std::uint32_t wordsPerBox() const { return shared::csWordsPerBox(n); }
  // The candidate of shaft `shaft` of line space `box` through the sparse layout, or CS_NONE.
  std::uint32_t lookup(std::uint32_t box, std::uint32_t shaft) const;
  // The same from the dense table (keepDense only).
  std::uint32_t lookupDense(std::uint32_t box, std::uint32_t shaft) const {
    return dense[std::size_t(box) * shared::csShaftCount(n) + shaft];
  }
};

// The sparse layout of a dense table (30 N^4 entries per box, CS_NONE = empty), in box order;
// fills bits, offsets, candidates and the counting stats (not the timing). boxes[i].wordBase is set.
void packCandidates(std::uint32_t n, std::span<const std::uint32_t> dense, CandidateLineSpace& out);

// Builds the candidate line space of `boxes` over the meshes in `set` (triangle indices stay
// scene order over all meshes). Throws InputError before casting a ray when N is out of range,
// when the worst-case size exceeds the budget, one bound buffer (bits, offsets, boxes) would exceed
// maxBufferBytes (the device's maxStorageBufferRange; 0 = no limit) or the candidates
// settings.maxCandidateBytes, naming N, the box count, the MB and what to change.
CandidateLineSpace buildCandidateLineSpace(const Scene& scene, std::span<const CandidateBox> boxes,
                                           const CandidateSettings& settings, std::uint64_t maxBufferBytes,
                                           MeshSet set = MeshSet::All);

// The segment end points the builder uses: the centroid of patch `patch` of face `face` of box
// [lo, hi] (a point on the box surface).
glm::vec3 candidatePatchCentroid(const glm::vec3& lo, const glm::vec3& hi, std::uint32_t face, std::uint32_t patch,
                                 std::uint32_t n);

// ---- Placement ------------------------------------------------------------------------------

// N-tree nodes that get a line space: the subdivided nodes at level `depth` (0 = the root, up to
// tree.depth - 1), and, the paper's T rule, shallower subdivided nodes whose subtree holds fewer
// than `minTriangles` distinct triangles (0: no such rule). A chosen node acts as a leaf for rays
// using the line space, so nothing below it is chosen. CandidateBox::node = the N-tree node index.
// Throws InputError for a depth the tree does not have.
std::vector<CandidateBox> boxesAtDepth(const NTree& tree, std::uint32_t depth, std::uint32_t minTriangles);

// BVH inner nodes at depth `depth` (the root at 0) and their boxes (the parent's child slot; the
// root's: the union of its slots). Leaves shallower than that get none and stay exact.
struct BvhLineSpaceNodes {
  std::vector<CandidateBox> boxes;     // CandidateBox::node = the BVH node index
  std::vector<std::uint32_t> nodeMap;  // per BVH node: its line space index, or CS_NONE
};
BvhLineSpaceNodes bvhNodesAtDepth(const Bvh& bvh, std::uint32_t depth);

}  // namespace penumbra
