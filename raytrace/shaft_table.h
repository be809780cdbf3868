// Which child cells each shaft of a node meets (Keul et al. 2017, 3): for the 15 N^4 symmetric
// shafts of the unit cube (numbered as in shared/linespace.h), the set of the N^3 cells that the
// shaft's volume, the convex hull of its two patches, intersects. Computed once per N and cached.
//
// The test is exact: the hull of two boxes A and B is the union over t in [0, 1] of the boxes
// (1 - t) A + t B, whose bounds are linear in t, so a cell meets the hull iff the t-intervals of
// its three axis constraints share a point. "Meets" means the interiors overlap: a ray that
// crosses a cell's interior inside the (closed) hull makes the interiors overlap, since the hull
// has volume, while cells the hull only touches on a face (the neighbours of a straight shaft)
// stay out. Geometry on a shared cell face is in both cells (the N-tree builder's slack), so no
// blocker is lost on such faces. Rays within float rounding of a patch border on the GPU may
// look up the neighbouring shaft and miss a cell they clip by that rounding; that is the only
// non-conservative case.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace penumbra {

class ShaftTable {
 public:
  // The table for N (built on first use, thread-safe, kept for the process). Throws InputError
  // for N outside [LS_MIN_N, LS_MAX_N].
  static const ShaftTable& get(std::uint32_t n);
  explicit ShaftTable(std::uint32_t n);  // builds now, on all cores

  std::uint32_t n() const { return n_; }
  std::uint32_t shaftCount() const { return shafts_; }
  std::uint32_t cellCount() const { return n_ * n_ * n_; }
  std::uint32_t shaftWords() const { return shaftWords_; }  // 64-bit words of a set of shafts

  bool contains(std::uint32_t shaft, std::uint32_t cell) const {
    return (shaftCells_[std::size_t(shaft) * cellWords_ + cell / 64] >> (cell % 64)) & 1u;
  }
  // The shafts that meet `cell`, as a bit set of shaftWords() words (bit s = shaft s). The line
  // space of a node is the OR of these over its non-empty cells.
  std::span<const std::uint64_t> cellShafts(std::uint32_t cell) const {
    return {cellShafts_.data() + std::size_t(cell) * shaftWords_, shaftWords_};
  }
  std::uint32_t cellsOf(std::uint32_t shaft) const;  // how many cells the shaft meets

  // The shaft's two patches as boxes in node coordinates ([0, 1]^3, flat along the face's axis).
  struct Patch {
    std::uint32_t face = 0;
    glm::dvec3 lo{0.0}, hi{0.0};
  };
  static void decode(std::uint32_t shaft, std::uint32_t n, Patch& a, Patch& b);

  double buildMs() const { return buildMs_; }
  std::uint64_t bytes() const { return (shaftCells_.size() + cellShafts_.size()) * sizeof(std::uint64_t); }

 private:
  std::uint32_t n_, shafts_, cellWords_, shaftWords_;
  std::vector<std::uint64_t> shaftCells_;  // per shaft cellWords_ words
  std::vector<std::uint64_t> cellShafts_;  // per cell shaftWords_ words
  double buildMs_ = 0.0;
};

}  // namespace penumbra
