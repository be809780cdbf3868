#include "core/miss_explainer.h"

#include <bit>
#include <cmath>
#include <stdexcept>

#include "shared/pip.h"

namespace penumbra {

std::uint64_t MissReport::misses() const {
  std::uint64_t n = 0;
  for (std::size_t i = 1; i < counts.size(); ++i) n += counts[i];
  return n;
}

std::string missCauseName(MissCause cause) {
  switch (cause) {
    case MissCause::None: return "none";
    case MissCause::FacingAway: return "facing_away";
    case MissCause::Acne: return "acne";
    case MissCause::BlockerWithinBias: return "blocker_within_bias";
    case MissCause::EdgeOutsideInterval: return "edge_outside_interval";
    case MissCause::EdgeBelowThreshold: return "edge_below_threshold";
    case MissCause::BlockerMissing: return "blocker_missing_from_map";
    case MissCause::GapClosed: return "gap_closed_by_map";
    case MissCause::Unexplained: return "unexplained";
    case MissCause::BelowLightError:
      return "below_light_error";
    case MissCause::Count: break;
  }
  return "?";
}

std::map<std::string, std::uint64_t> missCauseCounts(const MissReport& report) {
  std::map<std::string, std::uint64_t> counts;
  for (std::size_t i = 1; i < report.counts.size(); ++i) counts[missCauseName(MissCause(i))] = report.counts[i];
  return counts;
}

namespace {

MissCause causeOf(std::uint8_t why, bool smLit) {
  switch (why) {
    case PIP_WHY_FACING: return MissCause::FacingAway;
    case PIP_WHY_BIAS: return smLit ? MissCause::BlockerWithinBias : MissCause::Acne;
    case PIP_WHY_INTERVAL: return MissCause::EdgeOutsideInterval;
    case PIP_WHY_DELTA: return MissCause::EdgeBelowThreshold;
    case PIP_WHY_FLAT: return smLit ? MissCause::BlockerMissing : MissCause::GapClosed;
    case PIP_WHY_LIGHT_ERROR:
      return MissCause::BelowLightError;
    default: return MissCause::Unexplained;
  }
}

}  // namespace

MissReport explainMisses(std::span<const float> smVisibility, std::span<const std::uint8_t> pip,
                         std::span<const std::uint8_t> why, std::span<const float> reference,
                         std::span<const std::uint8_t> covered, float threshold) {
  const std::size_t n = reference.size();
  if (smVisibility.size() != n || pip.size() != n || why.size() != n || covered.size() != n) {
    throw std::invalid_argument("explainMisses: buffers differ in size");
  }
  MissReport report;
  report.perPixel.assign(n, MissCause::None);
  for (std::size_t i = 0; i < n; ++i) {
    if (!covered[i] || pip[i] || !(std::abs(smVisibility[i] - reference[i]) > threshold)) continue;
    const MissCause cause = causeOf(why[i], smVisibility[i] > reference[i]);
    report.perPixel[i] = cause;
    ++report.counts[std::size_t(cause)];
  }
  return report;
}

std::map<std::string, MaskRule> explainMask(std::span<const std::uint8_t> pip, std::span<const std::uint8_t> why,
                                            std::span<const float> reference, std::span<const std::uint8_t> covered) {
  const std::size_t n = reference.size();
  if (pip.size() != n || why.size() != n || covered.size() != n) {
    throw std::invalid_argument("explainMask: buffers differ in size");
  }
  // PIP_MASK_* bit by bit
  static const char* const kNames[] = {"edge_doubt", "thin_doubt", "contact_doubt", "tangent_plane",
                                       "own_depth",  "edge_splat", "surface_over",  "corner_map"};
  static_assert(std::size(kNames) == PIP_MASK_RULES);
  std::map<std::string, MaskRule> rules;
  for (std::size_t i = 0; i < n; ++i) {
    if (!covered[i] || !pip[i]) continue;
    if (why[i] == 0u) {
      MaskRule& r = rules[(pip[i] & PIP_OUTSIDE) ? "outside_map" : "unexplained"];
      r.holds.add(reference[i]);
      r.alone.add(reference[i]);
      continue;
    }
    const bool alone = std::has_single_bit(unsigned(why[i]));
    for (std::uint32_t bit = 0; bit < PIP_MASK_RULES; ++bit) {
      if (!(why[i] & (1u << bit))) continue;
      MaskRule& r = rules[kNames[bit]];
      r.holds.add(reference[i]);
      if (alone) r.alone.add(reference[i]);
    }
  }
  return rules;
}

void MaskPixels::add(float reference) {
  ++pixels;
  ++(reference <= 0.0f ? dark : reference >= 1.0f ? lit : penumbra);
}

std::vector<std::uint8_t> missImage(const MissReport& report, std::span<const std::uint8_t> covered) {
  // One colour per cause, in MissCause order (None unused).
  static constexpr std::uint8_t kColours[][3] = {{0, 0, 0},       {255, 0, 255},  {255, 140, 0}, {255, 255, 0},
                                                 {0, 160, 255},   {0, 255, 255},  {255, 0, 0},   {0, 255, 0},
                                                 {255, 255, 255}, {110, 130, 170}};
  static_assert(std::size(kColours) == std::size_t(MissCause::Count));
  std::vector<std::uint8_t> rgba(report.perPixel.size() * 4, 0);
  for (std::size_t i = 0; i < report.perPixel.size(); ++i) {
    const MissCause cause = report.perPixel[i];
    const std::uint8_t grey = covered[i] ? 60 : 0;
    for (int c = 0; c < 3; ++c) rgba[4 * i + c] = cause == MissCause::None ? grey : kColours[std::size_t(cause)][c];
    rgba[4 * i + 3] = 255;
  }
  return rgba;
}

}  // namespace penumbra
