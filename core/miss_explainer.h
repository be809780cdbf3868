// The miss explainer: for a method that classifies, every pixel whose shadow-map answer
// is wrong against the reference and that it did not trace, with the reason the classification gave
// for leaving it out (PIP_WHY_*, pip_classify.comp) split by which way the sm answer is wrong.
#pragma once
#include <array>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace penumbra {

enum class MissCause : std::uint8_t {
  None = 0,             // not a miss
  FacingAway,           // dark by the facing rule, yet the reference sees light
  Acne,                 // the map sees the receiver itself and shadows it (bias too small)
  BlockerWithinBias,    // the map sees the receiver itself, but a blocker within the bias hides it
  EdgeOutsideInterval,  // a depth edge above the threshold that the receiver's interval missed
  EdgeBelowThreshold,   // a depth edge below the threshold
  BlockerMissing,       // the map is flat and lights the receiver; a blocker it does not hold
  GapClosed,            // the map is flat and dark; light comes through a gap it closed
  Unexplained,          // the classification wrote no reason (e.g. area lights)
  BelowLightError,      // the light's shadow weighs less than --light-error there: the map's answer kept
  Count
};

struct MissReport {
  std::array<std::uint64_t, std::size_t(MissCause::Count)> counts{};  // [None] unused
  std::vector<MissCause> perPixel;                                     // None where not a miss
  std::uint64_t misses() const;
};

// Stable snake_case name, as written to metrics.json.
std::string missCauseName(MissCause cause);
// The report's counts by name, every cause listed (zeros too).
std::map<std::string, std::uint64_t> missCauseCounts(const MissReport& report);

// smVisibility/pip/why: the method's sm answer, flags and PIP_WHY_* codes; reference/covered: the
// reference's visibility and coverage; threshold: a wrong pixel's |difference|.
MissReport explainMisses(std::span<const float> smVisibility, std::span<const std::uint8_t> pip,
                         std::span<const std::uint8_t> why, std::span<const float> reference,
                         std::span<const std::uint8_t> covered, float threshold);

// The penumbra mask explained (area lights): for each rule that puts pixels in it (PIP_MASK_*, by
// name), the covered pixels where it holds and those where it alone holds (which the mask would
// lose without it), each split by what the reference with the same samples says there: a penumbra
// (0 < v < 1: the mask's job), or fully lit or fully dark (traced for nothing with these samples;
// a mask sound for every light sample must still keep some of them).
struct MaskPixels {
  std::uint64_t pixels = 0, penumbra = 0, lit = 0, dark = 0;
  void add(float reference);
};
struct MaskRule {
  MaskPixels holds, alone;
};
// pip/why: the method's flags and PIP_MASK_* bits; flagged pixels without a rule count as
// "outside_map" (PIP_OUTSIDE) or "unexplained".
std::map<std::string, MaskRule> explainMask(std::span<const std::uint8_t> pip, std::span<const std::uint8_t> why,
                                            std::span<const float> reference, std::span<const std::uint8_t> covered);

// RGBA8 image: misses coloured by cause over a dark grey of the covered pixels: facing away magenta,
// acne orange, blocker within bias yellow, edge outside interval blue, edge below threshold cyan,
// blocker missing red, gap closed green, unexplained white, below --light-error grey-blue.
std::vector<std::uint8_t> missImage(const MissReport& report, std::span<const std::uint8_t> covered);

}  // namespace penumbra
