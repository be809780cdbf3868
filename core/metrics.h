// Error between two visibility buffers (fraction of light visible per pixel) and between two
// shaded images, over covered pixels.
#pragma once
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "core/flip.h"

namespace penumbra {

struct ErrorMetrics {
  double rmse = 0.0;
  double mae = 0.0;
  double max = 0.0;
  double wrongPixelFraction = 0.0;  // fraction of covered pixels with |test - ref| > threshold
  // 10 log10(peak^2 / MSE) with peak 1 (visibility is in [0,1]); +infinity when the buffers agree
  // on every covered pixel (or none is covered), written as null in JSON.
  double psnr = std::numeric_limits<double>::infinity();
  std::uint64_t pixels = 0;  // covered pixels compared
};

// Between two shaded RGBA8 sRGB images: rmse, mae, max and psnr over the R, G and B channels of
// covered pixels, on the encoded values scaled to [0,1] (peak 1; +infinity when identical), and the
// mean FLIP (core/flip.h) over covered pixels.
struct ImageErrorMetrics {
  double rmse = 0.0;
  double mae = 0.0;
  double max = 0.0;
  double psnr = std::numeric_limits<double>::infinity();
  double flipMean = 0.0;
  std::uint64_t pixels = 0;
};

// PSNR in dB of a mean squared error for signals with the given peak: +infinity for mse 0.
double psnrFromMse(double mse, double peak = 1.0);

// Threshold for wrongPixelFraction: 0.5 for hard shadows, 0.05 for soft ones.
inline constexpr float kWrongThresholdHard = 0.5f;
inline constexpr float kWrongThresholdSoft = 0.05f;

// covered[i] != 0 marks pixel i as covered by geometry. All spans have the same size.
ErrorMetrics compareVisibility(std::span<const float> test, std::span<const float> reference,
                               std::span<const std::uint8_t> covered, float wrongThreshold);

// test, reference: width*height*4 bytes; covered: width*height. `flip`, when given, receives the
// per-pixel FLIP map. Throws std::invalid_argument for mismatched sizes.
ImageErrorMetrics compareImages(std::span<const std::uint8_t> test, std::span<const std::uint8_t> reference,
                                std::span<const std::uint8_t> covered, std::uint32_t width, std::uint32_t height,
                                std::vector<float>* flip = nullptr, const FlipSettings& flipSettings = {});

// Of the covered pixels where `approx` is wrong (|approx - ref| > threshold), the fraction that is
// not `marked` (0 when approx is never wrong). For PIP classification: marked = traced.
double missFraction(std::span<const float> approx, std::span<const float> reference, std::span<const std::uint8_t> covered,
                    std::span<const std::uint8_t> marked, float threshold);

// Of the covered pixels in the reference's penumbra (0 < reference < 1), the fraction not `marked`
// (0 when there is no penumbra).
double penumbraMissFraction(std::span<const float> reference, std::span<const std::uint8_t> covered,
                            std::span<const std::uint8_t> marked);

// Temporal stability: the mean |current - previous| of the visibility over the pixels covered in
// both frames (0 when none is). Under a slowly moving light, a method's value above the
// reference's is flicker (shadow-map texels swimming, noise that is not shared between frames).
double temporalChange(std::span<const float> previous, std::span<const float> current,
                      std::span<const std::uint8_t> previousCovered, std::span<const std::uint8_t> currentCovered);

// RGBA8 heatmap of |test - ref|: black (0) -> red -> yellow -> white (>= fullScale);
// uncovered pixels dark blue-grey.
std::vector<std::uint8_t> errorHeatmap(std::span<const float> test, std::span<const float> reference,
                                       std::span<const std::uint8_t> covered, float fullScale = 1.0f);

}  // namespace penumbra
