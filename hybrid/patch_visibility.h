// Patch-to-patch visibility (Eisemann & Décoret 2007, section 6) with the bitmask machinery: which
// pairs of sample points on two rectangles see each other past the scene. The source patch takes
// the place of the light (its samples: the shared pattern, n x n strata), the target patch that of
// the receiver (its samples: the centres of an n x n map laid on it).
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/scene.h"
#include "core/view.h"
#include "gpu/context.h"

namespace penumbra {

struct PatchVisibility {
  std::uint32_t n = 0;                // samples per side of each patch
  std::vector<std::uint32_t> hidden;  // per target sample (row-major), words of blocked source samples
  std::uint32_t words = 0;
  std::uint64_t unblockedPairs = 0, pairs = 0;
  double fraction() const { return pairs ? double(unblockedPairs) / double(pairs) : 0.0; }
  bool blocked(std::uint32_t target, std::uint32_t source) const {
    return (hidden[std::size_t(target) * words + source / 32] >> (source % 32)) & 1u;
  }
};

// Refuses (InputError) n outside 1..32, patches that face each other edge-on or cross each
// other's plane.
PatchVisibility patchVisibility(const gpu::Context& context, const Scene& scene, const Patch& from, const Patch& to,
                                std::uint32_t n);

// The sample points the answer is about, for checks (Embree rays between them).
glm::vec3 sourceSample(const Patch& from, const Patch& to, std::uint32_t n, std::uint32_t s);
glm::vec3 targetSample(const Patch& to, std::uint32_t n, std::uint32_t i);
// How far from either patch's plane (world units) a caster is ignored: scene geometry lying on a
// patch (a wall the patch is laid on) is not a blocker of its own samples.
float patchMargin(const Scene& scene);

}  // namespace penumbra
