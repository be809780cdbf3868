// Error metrics on small hand-computed buffers.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "core/metrics.h"

namespace penumbra {
namespace {

TEST(Metrics, HandComputedValues) {
  // |d| over covered pixels = {0, 0.25, 0.5, 1}: mae 1.75/4, rmse sqrt(1.3125/4), max 1.
  const std::vector<float> test = {0.0f, 0.5f, 1.0f, 0.0f};
  const std::vector<float> ref = {0.0f, 0.25f, 0.5f, 1.0f};
  const std::vector<std::uint8_t> covered = {1, 1, 1, 1};
  const ErrorMetrics m = compareVisibility(test, ref, covered, 0.3f);
  EXPECT_EQ(m.pixels, 4u);
  EXPECT_DOUBLE_EQ(m.mae, 0.4375);
  EXPECT_DOUBLE_EQ(m.rmse, std::sqrt(0.328125));
  EXPECT_DOUBLE_EQ(m.max, 1.0);
  EXPECT_DOUBLE_EQ(m.wrongPixelFraction, 0.5);  // 0.5 and 1 exceed 0.3
}

TEST(Metrics, UncoveredPixelsIgnored) {
  const std::vector<float> test = {1.0f, 0.25f, 0.0f, 0.75f, 0.5f};
  const std::vector<float> ref = {0.0f, 0.0f, 1.0f, 0.75f, 0.0f};
  const std::vector<std::uint8_t> covered = {0, 1, 0, 1, 0};  // only |d| = 0.25 and 0 count
  const ErrorMetrics m = compareVisibility(test, ref, covered, kWrongThresholdSoft);
  EXPECT_EQ(m.pixels, 2u);
  EXPECT_DOUBLE_EQ(m.mae, 0.125);
  EXPECT_DOUBLE_EQ(m.rmse, std::sqrt(0.0625 / 2.0));
  EXPECT_DOUBLE_EQ(m.max, 0.25);
  EXPECT_DOUBLE_EQ(m.wrongPixelFraction, 0.5);
}

TEST(Metrics, AllUncoveredGivesZeros) {
  const std::vector<float> test = {1.0f, 0.0f};
  const std::vector<float> ref = {0.0f, 1.0f};
  const std::vector<std::uint8_t> covered = {0, 0};
  const ErrorMetrics m = compareVisibility(test, ref, covered, kWrongThresholdHard);
  EXPECT_EQ(m.pixels, 0u);
  EXPECT_EQ(m.rmse, 0.0);
  EXPECT_EQ(m.mae, 0.0);
  EXPECT_EQ(m.max, 0.0);
  EXPECT_EQ(m.wrongPixelFraction, 0.0);
  const ErrorMetrics empty = compareVisibility({}, {}, {}, kWrongThresholdHard);
  EXPECT_EQ(empty.pixels, 0u);
}

TEST(Metrics, ThresholdIsStrict) {
  // Differences exactly equal to the threshold are right; one ulp above is wrong.
  const float above = std::nextafter(0.5f, 1.0f);
  const std::vector<float> test = {0.75f, 0.5f, above, 0.05f};
  const std::vector<float> ref = {0.25f, 0.0f, 0.0f, 0.0f};
  const std::vector<std::uint8_t> covered = {1, 1, 1, 1};
  EXPECT_DOUBLE_EQ(compareVisibility(test, ref, covered, kWrongThresholdHard).wrongPixelFraction, 0.25);
  // 0.05f - 0 is exactly kWrongThresholdSoft: not wrong; the other three are.
  EXPECT_DOUBLE_EQ(compareVisibility(test, ref, covered, kWrongThresholdSoft).wrongPixelFraction, 0.75);
}

TEST(Metrics, NanCountsAsWorstError) {
  const std::vector<float> test = {std::numeric_limits<float>::quiet_NaN(), 0.0f};
  const std::vector<float> ref = {0.0f, 0.0f};
  const std::vector<std::uint8_t> covered = {1, 1};
  const ErrorMetrics m = compareVisibility(test, ref, covered, kWrongThresholdHard);
  EXPECT_DOUBLE_EQ(m.max, 1.0);
  EXPECT_DOUBLE_EQ(m.wrongPixelFraction, 0.5);
}

TEST(Metrics, SizeMismatchThrows) {
  const std::vector<float> a(3), b(4);
  const std::vector<std::uint8_t> c3(3, 1), c4(4, 1);
  EXPECT_THROW(compareVisibility(a, b, c3, 0.5f), std::invalid_argument);
  EXPECT_THROW(compareVisibility(a, a, c4, 0.5f), std::invalid_argument);
  EXPECT_THROW(errorHeatmap(a, b, c3), std::invalid_argument);
  EXPECT_THROW(errorHeatmap(a, a, c3, 0.0f), std::invalid_argument);
}

TEST(Metrics, HeatmapRamp) {
  // Errors 0, 1/3, 2/3, 1 (and beyond) hit the ramp's corners: black, red, yellow, white.
  const std::vector<float> test = {0.5f, 0.5f, 0.5f, 0.5f, 0.0f, 0.5f};
  const std::vector<float> ref = {0.5f, 0.5f - 0.1f, 0.5f + 0.2f, 0.2f, 0.9f, 0.0f};
  const std::vector<std::uint8_t> covered = {1, 1, 1, 1, 1, 0};
  const std::vector<std::uint8_t> rgba = errorHeatmap(test, ref, covered, 0.3f);
  ASSERT_EQ(rgba.size(), test.size() * 4);
  auto px = [&](std::size_t i) { return std::vector<int>(rgba.begin() + 4 * i, rgba.begin() + 4 * i + 4); };
  EXPECT_EQ(px(0), (std::vector<int>{0, 0, 0, 255}));
  EXPECT_EQ(px(1), (std::vector<int>{255, 0, 0, 255}));
  EXPECT_EQ(px(2), (std::vector<int>{255, 255, 0, 255}));
  EXPECT_EQ(px(3), (std::vector<int>{255, 255, 255, 255}));
  EXPECT_EQ(px(4), (std::vector<int>{255, 255, 255, 255}));
  // Uncovered: dark blue-grey, distinct from any ramp colour.
  EXPECT_LT(px(5)[0], px(5)[2]);
  EXPECT_LT(px(5)[2], 100);
  EXPECT_EQ(px(5)[3], 255);
}

}  // namespace
}  // namespace penumbra
