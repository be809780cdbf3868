// Error metrics on small hand-computed buffers, and the FLIP-style perceptual metric's properties.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/flip.h"
#include "core/metrics.h"
#include "core/miss_explainer.h"
#include "shared/pip.h"

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

// ---- PSNR -------------------------------------------------------------------------------------

TEST(Metrics, PsnrHandComputed) {
  // |d| = {0.5, 0.5, 0, 0} on a 4x1 buffer: MSE 0.125, PSNR 10 log10(1 / 0.125) = 10 log10(8).
  const std::vector<float> test = {0.5f, 1.0f, 0.25f, 0.0f};
  const std::vector<float> ref = {0.0f, 0.5f, 0.25f, 0.0f};
  const std::vector<std::uint8_t> covered = {1, 1, 1, 1};
  const ErrorMetrics m = compareVisibility(test, ref, covered, kWrongThresholdHard);
  EXPECT_NEAR(m.psnr, 10.0 * std::log10(8.0), 1e-12);
  EXPECT_NEAR(m.psnr, 9.0309, 1e-4);
  // The earlier hand-computed case: MSE 0.328125.
  const ErrorMetrics h = compareVisibility(std::vector<float>{0.0f, 0.5f, 1.0f, 0.0f},
                                           std::vector<float>{0.0f, 0.25f, 0.5f, 1.0f}, covered, 0.3f);
  EXPECT_NEAR(h.psnr, -10.0 * std::log10(0.328125), 1e-12);
  // One pixel wrong by 1 of four: MSE 0.25, 6.02 dB.
  EXPECT_NEAR(psnrFromMse(0.25), 6.0206, 1e-4);
  EXPECT_NEAR(psnrFromMse(0.25, 2.0), 12.0412, 1e-4);  // the peak enters squared
}

TEST(Metrics, PsnrOfIdenticalOrEmptyIsInfinite) {
  const std::vector<float> v = {0.25f, 1.0f};
  const std::vector<std::uint8_t> covered = {1, 1}, none = {0, 0};
  EXPECT_TRUE(std::isinf(compareVisibility(v, v, covered, 0.5f).psnr));
  // Differences only where nothing is covered do not count.
  EXPECT_TRUE(std::isinf(compareVisibility(v, std::vector<float>{0.0f, 0.0f}, none, 0.5f).psnr));
  EXPECT_TRUE(std::isinf(psnrFromMse(0.0)));
}

// ---- Shaded images ----------------------------------------------------------------------------

std::vector<std::uint8_t> solid(std::size_t pixels, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  std::vector<std::uint8_t> rgba(4 * pixels);
  for (std::size_t i = 0; i < pixels; ++i) {
    rgba[4 * i] = r;
    rgba[4 * i + 1] = g;
    rgba[4 * i + 2] = b;
    rgba[4 * i + 3] = 255;
  }
  return rgba;
}

void setPixel(std::vector<std::uint8_t>& rgba, std::size_t i, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  rgba[4 * i] = r;
  rgba[4 * i + 1] = g;
  rgba[4 * i + 2] = b;
}

TEST(ImageMetrics, HandComputedValues) {
  // 2x2, reference black. Covered: pixel 0 pure red (channel diffs 1, 0, 0), pixel 1 grey 51 (0.2
  // in each channel), pixel 2 equal; pixel 3 differs but is not covered. Over 9 channel samples:
  // mae 1.6/9, mse (1 + 3 * 0.04)/9 = 1.12/9, max 1, psnr 10 log10(9/1.12).
  const std::vector<std::uint8_t> ref = solid(4, 0, 0, 0);
  std::vector<std::uint8_t> test = ref;
  setPixel(test, 0, 255, 0, 0);
  setPixel(test, 1, 51, 51, 51);
  setPixel(test, 3, 255, 255, 255);
  test[4 * 2 + 3] = 7;  // alpha is not compared
  const std::vector<std::uint8_t> covered = {1, 1, 1, 0};
  const ImageErrorMetrics m = compareImages(test, ref, covered, 2, 2);
  EXPECT_EQ(m.pixels, 3u);
  EXPECT_NEAR(m.mae, 1.6 / 9.0, 1e-12);
  EXPECT_NEAR(m.rmse, std::sqrt(1.12 / 9.0), 1e-12);
  EXPECT_DOUBLE_EQ(m.max, 1.0);
  EXPECT_NEAR(m.psnr, 10.0 * std::log10(9.0 / 1.12), 1e-9);
  EXPECT_GT(m.flipMean, 0.0);
  EXPECT_LE(m.flipMean, 1.0);
}

TEST(ImageMetrics, IdenticalImagesScoreZeroAndInfinitePsnr) {
  std::vector<std::uint8_t> img = solid(6 * 5, 10, 200, 90);
  for (std::size_t i = 0; i < 30; ++i) setPixel(img, i, std::uint8_t(i * 8), std::uint8_t(255 - i * 5), std::uint8_t(i * i % 256));
  std::vector<float> flip;
  const ImageErrorMetrics m = compareImages(img, img, std::vector<std::uint8_t>(30, 1), 6, 5, &flip);
  EXPECT_EQ(m.rmse, 0.0);
  EXPECT_EQ(m.mae, 0.0);
  EXPECT_EQ(m.max, 0.0);
  EXPECT_TRUE(std::isinf(m.psnr));
  EXPECT_EQ(m.flipMean, 0.0);
  ASSERT_EQ(flip.size(), 30u);
  for (float v : flip) EXPECT_EQ(v, 0.0f);
}

TEST(ImageMetrics, BadSizesThrow) {
  const std::vector<std::uint8_t> a = solid(4, 0, 0, 0), b = solid(3, 0, 0, 0);
  const std::vector<std::uint8_t> c4(4, 1), c3(3, 1);
  EXPECT_THROW(compareImages(a, b, c4, 2, 2), std::invalid_argument);
  EXPECT_THROW(compareImages(a, a, c3, 2, 2), std::invalid_argument);
  EXPECT_THROW(compareImages(a, a, c4, 4, 1 + 1), std::invalid_argument);
  EXPECT_THROW(flipMap(a, a, 2, 2, FlipSettings{0.0}), std::invalid_argument);
  EXPECT_THROW(flipMap(a, b, 2, 2), std::invalid_argument);
  EXPECT_THROW(flipHeatmap(std::vector<float>(3), c4), std::invalid_argument);
}

// ---- FLIP ---------------------------------------------------------------------------------------

constexpr std::uint32_t kSide = 48;

// A grey image with a centred square of side `patch` whose value differs by `amplitude`.
std::vector<std::uint8_t> greyWithPatch(std::uint32_t patch, int amplitude, int base = 128) {
  std::vector<std::uint8_t> img = solid(kSide * kSide, std::uint8_t(base), std::uint8_t(base), std::uint8_t(base));
  const std::uint32_t first = (kSide - patch) / 2;
  const auto v = std::uint8_t(std::clamp(base + amplitude, 0, 255));
  for (std::uint32_t y = first; y < first + patch; ++y)
    for (std::uint32_t x = first; x < first + patch; ++x) setPixel(img, y * kSide + x, v, v, v);
  return img;
}

const std::vector<std::uint8_t>& allCovered() {
  static const std::vector<std::uint8_t> covered(kSide * kSide, 1);
  return covered;
}

float centre(const std::vector<float>& map) { return map[(kSide / 2) * kSide + kSide / 2]; }

TEST(Flip, PixelsPerDegreeOfThePapersSetup) {
  EXPECT_NEAR(flipPixelsPerDegree(0.7, 0.7, 3840.0), 67.02, 0.01);
  EXPECT_THROW(flipPixelsPerDegree(0.0, 0.7, 3840.0), std::invalid_argument);
}

TEST(Flip, BlackAgainstWhiteIsNearOne) {
  // HyAB(black, white) = 100 (L* 0 vs 100, no chroma): 100^0.7 = 25.1 lies above pc * cmax
  // (0.4 * 203^0.7 = 16.5), so the value is 0.95 + (25.1 - 16.5) / (41.2 - 16.5) * 0.05 = 0.967.
  const auto black = solid(kSide * kSide, 0, 0, 0), white = solid(kSide * kSide, 255, 255, 255);
  const std::vector<float> map = flipMap(white, black, kSide, kSide);
  for (float v : map) {
    EXPECT_GT(v, 0.96f);
    EXPECT_LT(v, 0.975f);
  }
  // Pure green against pure blue is the normalising maximum: 1.
  const auto green = solid(kSide * kSide, 0, 255, 0), blue = solid(kSide * kSide, 0, 0, 255);
  EXPECT_NEAR(flipMean(flipMap(green, blue, kSide, kSide), allCovered()), 1.0, 1e-5);
}

TEST(Flip, MonotoneInTheAmplitudeOfADifference) {
  const auto ref = greyWithPatch(16, 0);
  double lastMean = 0.0;
  float lastCentre = 0.0f;
  for (int amplitude : {4, 8, 16, 32, 64, 127}) {
    const std::vector<float> map = flipMap(greyWithPatch(16, amplitude), ref, kSide, kSide);
    const double mean = flipMean(map, allCovered());
    EXPECT_GT(mean, lastMean) << "amplitude " << amplitude;
    EXPECT_GT(centre(map), lastCentre) << "amplitude " << amplitude;
    lastMean = mean;
    lastCentre = centre(map);
  }
}

TEST(Flip, MonotoneInTheAreaOfADifference) {
  const auto ref = greyWithPatch(1, 0);
  double lastMean = 0.0;
  for (std::uint32_t patch : {1u, 2u, 4u, 8u, 16u, 32u}) {
    const double mean = flipMean(flipMap(greyWithPatch(patch, 64), ref, kSide, kSide), allCovered());
    EXPECT_GT(mean, lastMean) << "patch " << patch;
    lastMean = mean;
  }
}

TEST(Flip, OnePixelScoresLowerThanALargeAreaOfTheSameAmplitude) {
  const auto ref = greyWithPatch(1, 0);
  const std::vector<float> one = flipMap(greyWithPatch(1, 64), ref, kSide, kSide);
  const std::vector<float> large = flipMap(greyWithPatch(24, 64), ref, kSide, kSide);
  EXPECT_LT(flipMean(one, allCovered()), flipMean(large, allCovered()));
  // Per pixel too: the contrast-sensitivity filter spreads a lone pixel's difference thin, so it
  // scores below the inside of a large patch with the same difference.
  EXPECT_LT(centre(one), centre(large));
  EXPECT_GT(centre(one), 0.0f);
}

TEST(Flip, SymmetricWithinFloatRounding) {
  // The colour and feature differences are symmetric by construction; the two orders differ only
  // by float rounding of the filtered planes. Tolerance: 1e-5 per pixel.
  std::vector<std::uint8_t> a = solid(kSide * kSide, 0, 0, 0), b = a;
  for (std::uint32_t i = 0; i < kSide * kSide; ++i) {
    setPixel(a, i, std::uint8_t((i * 37) % 256), std::uint8_t((i * 11) % 200), std::uint8_t((i / kSide) * 5));
    setPixel(b, i, std::uint8_t((i * 37 + (i % 7) * 20) % 256), std::uint8_t((i * 13) % 230), std::uint8_t((i % kSide) * 5));
  }
  const std::vector<float> ab = flipMap(a, b, kSide, kSide), ba = flipMap(b, a, kSide, kSide);
  double maxDiff = 0.0, mean = 0.0;
  for (std::size_t i = 0; i < ab.size(); ++i) {
    maxDiff = std::max(maxDiff, std::abs(double(ab[i]) - double(ba[i])));
    mean += ab[i];
  }
  EXPECT_LE(maxDiff, 1e-5);
  EXPECT_GT(mean / double(ab.size()), 0.05) << "the images must differ for this to test anything";
}

TEST(Flip, ValuesStayInUnitRange) {
  std::vector<std::uint8_t> a = solid(kSide * kSide, 0, 0, 0), b = solid(kSide * kSide, 255, 255, 255);
  for (std::uint32_t i = 0; i < kSide * kSide; i += 2) setPixel(a, i, 255, 0, 255);  // stripes: strong features
  for (float v : flipMap(a, b, kSide, kSide)) {
    EXPECT_GE(v, 0.0f);
    EXPECT_LE(v, 1.0f);
  }
}

TEST(Flip, MeanCountsCoveredPixelsOnly) {
  const std::vector<float> map = {0.5f, 1.0f, 0.25f};
  EXPECT_DOUBLE_EQ(flipMean(map, std::vector<std::uint8_t>{1, 0, 1}), 0.375);
  EXPECT_EQ(flipMean(map, std::vector<std::uint8_t>{0, 0, 0}), 0.0);
}

TEST(Flip, HeatmapRamp) {
  const std::vector<float> map = {0.0f, 0.5f, 1.0f, 2.0f, 0.3f};
  const std::vector<std::uint8_t> rgba = flipHeatmap(map, std::vector<std::uint8_t>{1, 1, 1, 1, 0});
  auto px = [&](std::size_t i) { return std::vector<int>(rgba.begin() + 4 * i, rgba.begin() + 4 * i + 4); };
  EXPECT_EQ(px(0), (std::vector<int>{0, 0, 4, 255}));        // magma's near-black
  EXPECT_EQ(px(1), (std::vector<int>{183, 55, 121, 255}));   // its middle
  EXPECT_EQ(px(2), (std::vector<int>{252, 253, 191, 255}));  // its pale yellow end
  EXPECT_EQ(px(3), px(2));                                   // clamped
  EXPECT_EQ(px(4), (std::vector<int>{40, 44, 60, 255}));     // uncovered, as errorHeatmap
  // Brightness rises along the ramp.
  int last = -1;
  for (int k = 0; k <= 20; ++k) {
    const auto one = flipHeatmap(std::vector<float>{float(k) / 20.0f}, std::vector<std::uint8_t>{1});
    const int sum = one[0] + one[1] + one[2];
    EXPECT_GT(sum, last);
    last = sum;
  }
}

// The miss explainer counts only covered, untraced pixels whose sm answer is wrong, and names the
// cause from the classification's reason and the direction of the error.
TEST(MissExplainer, CountsOnlyUntracedWrongPixelsByCause) {
  //                                 lit-miss  dark-miss traced  right   uncovered facing  interval
  const std::vector<float> sm = {1.0f, 0.0f, 1.0f, 1.0f, 1.0f, 0.0f, 1.0f};
  const std::vector<float> ref = {0.0f, 1.0f, 0.0f, 1.0f, 0.0f, 1.0f, 0.0f};
  const std::vector<std::uint8_t> covered = {1, 1, 1, 1, 0, 1, 1};
  const std::vector<std::uint8_t> pip = {0, 0, PIP_EDGE, 0, 0, 0, 0};
  const std::vector<std::uint8_t> why = {PIP_WHY_FLAT, PIP_WHY_FLAT, PIP_WHY_NONE, PIP_WHY_BIAS,
                                         PIP_WHY_FLAT, PIP_WHY_FACING, PIP_WHY_INTERVAL};
  const MissReport report = explainMisses(sm, pip, why, ref, covered, 0.5f);
  EXPECT_EQ(report.misses(), 4u);
  EXPECT_EQ(report.perPixel[0], MissCause::BlockerMissing);
  EXPECT_EQ(report.perPixel[1], MissCause::GapClosed);
  EXPECT_EQ(report.perPixel[2], MissCause::None);  // traced
  EXPECT_EQ(report.perPixel[3], MissCause::None);  // right
  EXPECT_EQ(report.perPixel[4], MissCause::None);  // not covered
  EXPECT_EQ(report.perPixel[5], MissCause::FacingAway);
  EXPECT_EQ(report.perPixel[6], MissCause::EdgeOutsideInterval);
  const auto counts = missCauseCounts(report);
  EXPECT_EQ(counts.at("blocker_missing_from_map"), 1u);
  EXPECT_EQ(counts.at("gap_closed_by_map"), 1u);
  EXPECT_EQ(counts.at("acne"), 0u);
  EXPECT_EQ(counts.size(), std::size_t(MissCause::Count) - 1);
  EXPECT_THROW(explainMisses(sm, pip, why, ref, std::vector<std::uint8_t>(3, 1), 0.5f), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra
