// The accuracy bounds the tests hold the methods to, in one place, each with what it measured
// (lavapipe, Mesa 25.0.7, 2-core AMD EPYC, Release, 2026-11-28). Where the method and its oracle
// trace the same rays with the same triangle test the answer is exact and the bound is 0; elsewhere
// a bound is at most 3x what was measured, or its comment says why it is wider.
// docs/validation.md's table "What the tests hold it to" quotes these: test_readme_claims.cpp fails
// when a quote and its bound disagree.
#pragma once

namespace penumbra::test::bound {

// Hard shadows, srt vs the Embree reference (wrong pixel fraction): the pixels srt traces get the
// GPU BVH's answer, which is Embree's (same rays, Embree's robust triangle test; frt on both is
// bit-identical), and the rest keep sm's answer where the classification proves it right. Exact.
// Measured 0 on courtyard, wires and square at 256^2/512^2, the moving drone, stress scenes.
inline constexpr double kSrtWrong = 0.0;
// Soft srt vs frt with the same samples on the same tracer: they differ only where the penumbra
// mask misses a penumbra pixel. Exact. Measured 0 for lights 0.02 / 0.1 / 0.3 / 1.5 radii.
inline constexpr double kSoftSrtVsFrt = 0.0;
// ao and indirect on the GPU tracers vs Embree, same rays: the sampled directions come from cos and
// sin on the CPU and the GPU, which may round a ray grazing an edge to the other side (a flipped
// ray moves a 16-ray pixel by 1/16). Measured 0 wrong and rmse 0.000000 on bvh, rq and ntree; the
// bounds allow a few such rays in 128^2 pixels, not a wrong hit shading.
inline constexpr double kIndirectWrong = 1e-4;
inline constexpr double kIndirectRmse = 1e-3;
// Exact line-space shadows (--ls-shadows exact) vs the reference, courtyard, light 0.1, 25 spp:
// the BVH's triangle test on the same samples, so the same answer per sample: measured wrong 0 and
// rmse 0 on lavapipe; on an NVIDIA H200 rmse 1.1e-8, the GPU summing the 25 samples' 1/25 in
// another order (float rounding, at most 25 x 2^-24 = 1.5e-6 in a pixel). The bound allows that
// rounding and not one sample's flip (1/25 in one pixel of 256^2 is rmse 1.6e-4).
inline constexpr double kExactLineSpaceRmse = 1e-6;
// Bitmask visibility sampling vs the reference with the same samples: the map is evaluated at
// texel centres and the Hough table bins sample lines, so edges move by a fraction of a texel.
// Measured on the ground under the floating square: 0.034% / 0.017% of pixels off by > 0.05 at
// 32 / 128 samples, rmse 0.0033 / 0.0022; under the large light 0.017%, rmse 0.0036.
inline constexpr double kBitmaskWrong = 0.001;
inline constexpr double kBitmaskRmse = 0.0095;
// Ground and wall, each its own map: measured 0.042%.
inline constexpr double kBitmaskTwoReceiversWrong = 0.0012;
// A height-field terrain: measured 0.031% wrong, rmse 0.0071 on the terrain.
inline constexpr double kBitmaskTerrainWrong = 0.001;
inline constexpr double kBitmaskTerrainRmse = 0.02;
// Patch-to-patch visibility (penumbra visibility's pass) vs Embree's rays between the same sample
// points, 32x32 samples on each rectangle: measured 0, 6.1e-5 and 0 for open, half, fully blocked.
inline constexpr double kPatchVisibility = 1.8e-4;
// Candidate line spaces: a ray's hit on a plane crossing the node vs the exact hit, in box edges.
// Measured 1.97e-6.
inline constexpr double kCandidatePlaneHit = 6e-6;
// The binary line space may only be brighter than the reference where its start-node skip or
// offset drops a blocker: measured 0.20% of the courtyard's pixels (25 spp, light 0.1).
inline constexpr double kLineSpaceBrighter = 0.006;

}  // namespace penumbra::test::bound
