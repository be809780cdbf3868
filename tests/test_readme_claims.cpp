// docs/validation.md's table "What the tests hold it to" (the README's until it moved there) against
// the bounds the tests use (tests/bounds.h): each claimed bound is written from its constant here, so
// a row whose number disagrees with what the tests assert (or a constant changed without its row)
// fails.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bounds.h"

namespace penumbra::test {
namespace {

// How docs/validation.md writes a bound: "exact (0)" for 0, else "≤ " and the number (a percentage for
// fractions of pixels), shortest first: 0.1%, 0.0095, 6e-6.
std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  std::string s = text;
  const std::size_t e = s.find("e-0");
  if (e != std::string::npos) s.erase(e + 2, 1);  // 6e-06 -> 6e-6
  return s;
}
std::string fraction(double v) { return v == 0.0 ? "exact (0)" : "≤ " + number(100.0 * v) + "%"; }
std::string value(double v) { return v == 0.0 ? "exact (0)" : "≤ " + number(v); }

struct Claim {
  std::string row;                     // how the row's first cell starts
  std::vector<std::string> snippets;   // what the row must say
};

std::vector<Claim> claims() {
  using namespace bound;
  return {
      {"`srt` vs `ref`, courtyard and wires", {"`wrong_pixel_fraction` " + fraction(kSrtWrong)}},
      {"soft `srt` vs `frt` (same samples)", {"pixels differing by > 0.05: " + fraction(kSoftSrtVsFrt)}},
      {"`ao` / `indirect` on `bvh`, `rq` and `ntree` vs Embree",
       {"off by > 0.05: " + fraction(kIndirectWrong), "rmse " + value(kIndirectRmse)}},
      {"line space, exact shadows", {"rmse " + value(kExactLineSpaceRmse)}},
      {"`bitmask` vs `ref` with the same samples",
       {"off by > 0.05: " + fraction(kBitmaskWrong), "rmse " + value(kBitmaskRmse)}},
      {"`bitmask` on a ground and a wall", {"off by > 0.05: " + fraction(kBitmaskTwoReceiversWrong)}},
      {"`bitmask` on a height-field terrain",
       {"off by > 0.05: " + fraction(kBitmaskTerrainWrong), "terrain rmse " + value(kBitmaskTerrainRmse)}},
      {"candidate line space: sparse layout", {"plane hits within " + number(kCandidatePlaneHit) + " of the box"}},
      {"line space vs Embree", {"brighter than `ref` on " + fraction(kLineSpaceBrighter)}},
      {"`penumbra visibility`'s pass between two 4×4 rectangles", {"within " + number(kPatchVisibility) + " of Embree"}},
  };
}

TEST(ReadmeClaims, EveryQuotedBoundIsTheTestsOwn) {
  std::ifstream in(std::string(PENUMBRA_SOURCE_DIR) + "/docs/validation.md");
  ASSERT_TRUE(in) << "docs/validation.md not found in " << PENUMBRA_SOURCE_DIR;
  std::vector<std::string> rows;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("| ", 0) == 0) rows.push_back(line);
  }
  for (const Claim& claim : claims()) {
    SCOPED_TRACE(claim.row);
    std::vector<const std::string*> found;
    for (const std::string& row : rows) {
      if (row.rfind("| " + claim.row, 0) == 0) found.push_back(&row);
    }
    ASSERT_EQ(found.size(), 1u) << "docs/validation.md's table needs exactly one row starting '| " << claim.row << "'";
    for (const std::string& snippet : claim.snippets) {
      EXPECT_NE(found.front()->find(snippet), std::string::npos) << "the row should say '" << snippet << "':\n" << *found.front();
    }
  }
}

// The formatting itself, on values whose text is known (the test keeps its ReadmeClaims name).
TEST(ReadmeClaims, BoundsAreWrittenAsTheReadmeWritesThem) {
  EXPECT_EQ(fraction(0.0), "exact (0)");
  EXPECT_EQ(fraction(0.001), "≤ 0.1%");
  EXPECT_EQ(fraction(0.0012), "≤ 0.12%");
  EXPECT_EQ(value(0.0095), "≤ 0.0095");
  EXPECT_EQ(number(6e-6), "6e-6");
  EXPECT_EQ(number(1.8e-4), "0.00018");
}

}  // namespace
}  // namespace penumbra::test
