// Error between two visibility buffers (fraction of light visible per pixel), over covered pixels.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace penumbra {

struct ErrorMetrics {
  double rmse = 0.0;
  double mae = 0.0;
  double max = 0.0;
  double wrongPixelFraction = 0.0;  // fraction of covered pixels with |test - ref| > threshold
  std::uint64_t pixels = 0;         // covered pixels compared
};

// Threshold for wrongPixelFraction: 0.5 for hard shadows, 0.05 for soft ones.
inline constexpr float kWrongThresholdHard = 0.5f;
inline constexpr float kWrongThresholdSoft = 0.05f;

// covered[i] != 0 marks pixel i as covered by geometry. All spans have the same size.
ErrorMetrics compareVisibility(std::span<const float> test, std::span<const float> reference,
                               std::span<const std::uint8_t> covered, float wrongThreshold);

// Of the covered pixels where `approx` is wrong (|approx - ref| > threshold), the fraction that is
// not `marked` (0 when approx is never wrong). For PIP classification: marked = traced.
double missFraction(std::span<const float> approx, std::span<const float> reference, std::span<const std::uint8_t> covered,
                    std::span<const std::uint8_t> marked, float threshold);

// Of the covered pixels in the reference's penumbra (0 < reference < 1), the fraction not `marked`
// (0 when there is no penumbra).
double penumbraMissFraction(std::span<const float> reference, std::span<const std::uint8_t> covered,
                            std::span<const std::uint8_t> marked);

// RGBA8 heatmap of |test - ref|: black (0) -> red -> yellow -> white (>= fullScale);
// uncovered pixels dark blue-grey.
std::vector<std::uint8_t> errorHeatmap(std::span<const float> test, std::span<const float> reference,
                                       std::span<const std::uint8_t> covered, float fullScale = 1.0f);

}  // namespace penumbra
