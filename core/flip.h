// A perceptual image difference in the spirit of FLIP (Andersson, Nilsson, Akenine-Möller, Oskarsson,
// Åström and Fairchild 2020, "FLIP: A Difference Evaluator for Alternating Images"), implemented
// here from the paper's description of LDR-FLIP (no code taken from its reference implementation).
// What is computed, per pixel, for a reference and a test image (RGBA8 sRGB, alpha ignored):
//  Colour pipeline
//   1. sRGB -> linear RGB (the sRGB transfer function) -> CIE XYZ (sRGB primaries, D65 white:
//      the XYZ of linear (1,1,1)) -> the opponent space YyCxCz (Yy = 116 Y/Yn - 16,
//      Cx = 500 (X/Xn - Y/Yn), Cz = 200 (Y/Yn - Z/Zn)).
//   2. Contrast-sensitivity filtering of each channel with the paper's sums of Gaussians in the
//      spatial domain, S(r) = a1 sqrt(pi/b1) exp(-pi^2 r^2/b1) + a2 sqrt(pi/b2) exp(-pi^2 r^2/b2),
//      r in degrees of visual angle (pixel distance / pixels per degree); achromatic (a1 1,
//      b1 0.0047), red-green (a1 1, b1 0.0053), blue-yellow (a1 34.1, b1 0.04, a2 13.5,
//      b2 0.025). One radius for all channels, ceil(3 sqrt(0.04 / (2 pi^2)) ppd) pixels; every
//      kernel is normalised to sum 1, so flat regions keep their colour. Each Gaussian is separable
//      and is applied as two 1-D passes; the two terms of blue-yellow are summed.
//   3. Back to linear RGB, clamped to [0,1] (the displayable gamut), -> XYZ -> CIELAB, then the
//      Hunt adjustment a* <- 0.01 L* a*, b* <- 0.01 L* b*.
//   4. HyAB distance |dL*| + sqrt(da*^2 + db*^2), raised to qc = 0.7, and compressed to [0,1] with
//      cmax = (HyAB between Hunt-adjusted pure green and pure blue)^qc, pc = 0.4, pt = 0.95: linear
//      up to pt at pc cmax, then the remaining 1 - pt spread over (pc cmax, cmax].
//  Feature pipeline (on the achromatic channel y = Y/Yn of the unfiltered images)
//   5. Edges: first derivatives of a Gaussian, points: second derivatives, sigma = 0.5 * 0.082 degrees
//      (in pixels: 0.5 * 0.082 * ppd), radius ceil(3 sigma). The derivative factor of each kernel is
//      normalised so that its positive weights sum to 1 and its negative ones to -1 (the Gaussian
//      factor sums to 1), so flat regions give exactly 0; magnitudes |(d/dx, d/dy)|.
//   6. Feature difference (max(| |e_ref| - |e_test| |, | |p_ref| - |p_test| |) / sqrt(2))^qf, qf = 0.5.
//  Combination
//   7. FLIP = colourDiff^(1 - featureDiff), in [0,1].
// Simplifications: LDR only (no HDR-FLIP exposures); image borders replicate the edge pixel; sums
// in float. The viewing setup is given as pixels per degree (default 67: a 0.7 m wide 3840-pixel
// display seen from 0.7 m, the paper's setting).
#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace penumbra {

struct FlipSettings {
  double pixelsPerDegree = 67.0;
};

// Pixels per degree of visual angle of a display `widthMeters` wide with `widthPixels` columns,
// seen from `distanceMeters`: distance * (pixels / width) * pi / 180 (67.0 for 0.7, 0.7, 3840).
double flipPixelsPerDegree(double distanceMeters, double widthMeters, double widthPixels);

// Per-pixel FLIP of `test` against `reference` (RGBA8 sRGB, width*height*4 bytes each), width*height
// values in [0,1]. Throws std::invalid_argument for mismatched sizes or a non-positive ppd.
std::vector<float> flipMap(std::span<const std::uint8_t> testRgba, std::span<const std::uint8_t> referenceRgba,
                           std::uint32_t width, std::uint32_t height, const FlipSettings& settings = {});

// Mean of `map` over covered pixels (0 when none is covered).
double flipMean(std::span<const float> map, std::span<const std::uint8_t> covered);

// RGBA8 heatmap of a FLIP map on a magma-like ramp (black -> purple -> orange -> pale yellow at 1);
// uncovered pixels dark blue-grey, as errorHeatmap draws them.
std::vector<std::uint8_t> flipHeatmap(std::span<const float> map, std::span<const std::uint8_t> covered);

}  // namespace penumbra
