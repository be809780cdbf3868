#include "core/metrics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace penumbra {
namespace {

void checkSizes(const char* who, std::size_t test, std::size_t reference, std::size_t covered) {
  if (test != reference || test != covered) {
    throw std::invalid_argument(std::string(who) + ": buffer sizes differ (test " + std::to_string(test) +
                                ", reference " + std::to_string(reference) + ", covered " +
                                std::to_string(covered) + ")");
  }
}

std::uint8_t toByte(double v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); }

}  // namespace

ErrorMetrics compareVisibility(std::span<const float> test, std::span<const float> reference,
                               std::span<const std::uint8_t> covered, float wrongThreshold) {
  checkSizes("compareVisibility", test.size(), reference.size(), covered.size());
  ErrorMetrics m;
  double sumSq = 0.0;
  double sumAbs = 0.0;
  std::uint64_t wrong = 0;
  for (std::size_t i = 0; i < test.size(); ++i) {
    if (covered[i] == 0) continue;
    // Double keeps exact float differences exact, so the threshold comparison is not blurred.
    double d = std::abs(double(test[i]) - double(reference[i]));
    // A NaN would vanish from max and the wrong count; score it as the worst visibility error.
    if (std::isnan(d)) d = 1.0;
    sumSq += d * d;
    sumAbs += d;
    m.max = std::max(m.max, d);
    if (d > double(wrongThreshold)) ++wrong;  // strictly greater: equal to the threshold is right
    ++m.pixels;
  }
  if (m.pixels == 0) return m;
  const double n = double(m.pixels);
  m.rmse = std::sqrt(sumSq / n);
  m.mae = sumAbs / n;
  m.wrongPixelFraction = double(wrong) / n;
  m.psnr = psnrFromMse(sumSq / n);
  return m;
}

double psnrFromMse(double mse, double peak) {
  if (!(mse > 0.0)) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(peak * peak / mse);
}

ImageErrorMetrics compareImages(std::span<const std::uint8_t> test, std::span<const std::uint8_t> reference,
                                std::span<const std::uint8_t> covered, std::uint32_t width, std::uint32_t height,
                                std::vector<float>* flip, const FlipSettings& flipSettings) {
  const std::size_t pixels = std::size_t(width) * height;
  if (test.size() != 4 * pixels || reference.size() != 4 * pixels || covered.size() != pixels) {
    throw std::invalid_argument("compareImages: sizes differ from " + std::to_string(width) + "x" +
                                std::to_string(height) + " (test " + std::to_string(test.size()) + " bytes, reference " +
                                std::to_string(reference.size()) + " bytes, covered " + std::to_string(covered.size()) + ")");
  }
  ImageErrorMetrics m;
  double sumSq = 0.0, sumAbs = 0.0;
  for (std::size_t i = 0; i < pixels; ++i) {
    if (covered[i] == 0) continue;
    for (std::size_t c = 0; c < 3; ++c) {
      const double d = std::abs(double(test[4 * i + c]) - double(reference[4 * i + c])) / 255.0;
      sumSq += d * d;
      sumAbs += d;
      m.max = std::max(m.max, d);
    }
    ++m.pixels;
  }
  std::vector<float> map = flipMap(test, reference, width, height, flipSettings);
  m.flipMean = flipMean(map, covered);
  if (flip) *flip = std::move(map);
  if (m.pixels == 0) return m;
  const double samples = 3.0 * double(m.pixels);
  m.rmse = std::sqrt(sumSq / samples);
  m.mae = sumAbs / samples;
  m.psnr = psnrFromMse(sumSq / samples);
  return m;
}

std::vector<std::uint8_t> errorHeatmap(std::span<const float> test, std::span<const float> reference,
                                       std::span<const std::uint8_t> covered, float fullScale) {
  checkSizes("errorHeatmap", test.size(), reference.size(), covered.size());
  if (!(fullScale > 0.0f)) throw std::invalid_argument("errorHeatmap: fullScale must be positive");
  std::vector<std::uint8_t> rgba(test.size() * 4);
  for (std::size_t i = 0; i < test.size(); ++i) {
    std::uint8_t* px = &rgba[4 * i];
    px[3] = 255;
    if (covered[i] == 0) {
      px[0] = 40;
      px[1] = 44;
      px[2] = 60;
      continue;
    }
    const double d = std::abs(double(test[i]) - double(reference[i]));
    // NaN counts as the worst error so broken pixels stand out.
    const double e = std::isnan(d) ? 1.0 : std::min(d / double(fullScale), 1.0);
    // Three equal ramps: red rises, then green (-> yellow), then blue (-> white).
    const double t = 3.0 * e;
    px[0] = toByte(t);
    px[1] = toByte(t - 1.0);
    px[2] = toByte(t - 2.0);
  }
  return rgba;
}

double temporalChange(std::span<const float> previous, std::span<const float> current,
                      std::span<const std::uint8_t> previousCovered, std::span<const std::uint8_t> currentCovered) {
  if (current.size() != previous.size() || previousCovered.size() != previous.size() ||
      currentCovered.size() != previous.size()) {
    throw std::invalid_argument("temporalChange: frames differ in size");
  }
  double sum = 0.0;
  std::uint64_t n = 0;
  for (std::size_t i = 0; i < previous.size(); ++i) {
    if (!previousCovered[i] || !currentCovered[i]) continue;
    sum += std::abs(double(current[i]) - double(previous[i]));
    ++n;
  }
  return n ? sum / double(n) : 0.0;
}

double missFraction(std::span<const float> approx, std::span<const float> reference, std::span<const std::uint8_t> covered,
                    std::span<const std::uint8_t> marked, float threshold) {
  if (approx.size() != reference.size() || covered.size() != reference.size() || marked.size() != reference.size()) {
    throw std::invalid_argument("missFraction: buffers differ in size");
  }
  std::uint64_t wrong = 0, missed = 0;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    if (!covered[i] || !(std::abs(approx[i] - reference[i]) > threshold)) continue;
    ++wrong;
    missed += marked[i] == 0;
  }
  return wrong ? double(missed) / double(wrong) : 0.0;
}

double penumbraMissFraction(std::span<const float> reference, std::span<const std::uint8_t> covered,
                            std::span<const std::uint8_t> marked) {
  if (covered.size() != reference.size() || marked.size() != reference.size()) {
    throw std::invalid_argument("penumbraMissFraction: buffers differ in size");
  }
  std::uint64_t penumbra = 0, missed = 0;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    if (!covered[i] || !(reference[i] > 0.0f && reference[i] < 1.0f)) continue;
    ++penumbra;
    missed += marked[i] == 0;
  }
  return penumbra ? double(missed) / double(penumbra) : 0.0;
}

}  // namespace penumbra
