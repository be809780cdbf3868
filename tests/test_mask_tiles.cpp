// The penumbra mask's tiles of 8x8 pixels (PIP_MASK_TILE_SIZE): its tile test, which searches once
// for all of a tile's receivers, and the tile choice, which traces a doubtful tile whole instead of
// classifying its pixels. Both change what a frame costs, never the pixels it traces less of.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/metrics.h"
#include "core/scene_loader.h"
#include "hybrid/cheaper_of.h"
#include "hybrid/frame_output.h"
#include "mask_scenes.h"
#include "png_check.h"
#include "render_fixture.h"
#include "shared/pip.h"

namespace penumbra::test {
namespace {

// A frame's tiles (Frame::maskTiles: rows of ceil(width / PIP_MASK_TILE_SIZE)), and pixel i's.
std::size_t tileCount(const Frame& frame) {
  return std::size_t((frame.width + PIP_MASK_TILE_SIZE - 1) / PIP_MASK_TILE_SIZE) *
         ((frame.height + PIP_MASK_TILE_SIZE - 1) / PIP_MASK_TILE_SIZE);
}
std::size_t tileOf(const Frame& frame, std::size_t i) {
  const std::size_t columns = (frame.width + PIP_MASK_TILE_SIZE - 1) / PIP_MASK_TILE_SIZE;
  return i / frame.width / PIP_MASK_TILE_SIZE * columns + i % frame.width / PIP_MASK_TILE_SIZE;
}

// The mask's tile test (--tile-test, maskTile in pip_tiles.glsl) searches once for the
// receivers of an 8x8 tile of pixels together, in windows that hold each of theirs: the bounds of
// their cones, their farthest depth, the highest of their planes. Where it finds no blocker, no
// pixel of the tile searches. It must leave every pixel's mask as it was, explained too (every
// rule's bits), and it must clear tiles, or it is only a cost. The cases: edge splats of boxes,
// columns, a sphere and a torus (the courtyard, a disk and a square light, and the rail view of
// its fence under light 6 degrees off its side faces), of thin leaves (the foliage), and smooth
// surfaces rising over lit receivers (the groove: the surface channel). Loosened, the test fails:
// bounding the blockers by the tile's nearest receiver instead of its farthest changes the
// courtyard's mask, dropping the surface channel the groove's. (The spread of the receivers'
// cone slopes decides no tile here: the first receiver's slopes for all of them change nothing.)
// The frame carries the tile test's verdicts (one per tile, as many clear as its count says; none
// without the test), and srt.pip.png shows them: the untraced pixels of cleared tiles tinted blue,
// every other untraced pixel as the image has it.
void expectTileOverlay(const Frame& frame, std::uint64_t clear) {
  ASSERT_EQ(frame.maskTiles.size(), tileCount(frame));
  EXPECT_EQ(std::uint64_t(std::count(frame.maskTiles.begin(), frame.maskTiles.end(), PIP_TILE_CLEAR)), clear);
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "penumbra_tile_overlay";
  std::filesystem::create_directories(dir);
  writeFrame(dir.string(), frame, nlohmann::json::object());
  const Image png = readPng(dir / (frame.stats.method + ".pip.png"));
  ASSERT_EQ(png.rgba.size(), frame.rgba.size());
  std::size_t blue = 0, wrong = 0;
  for (std::size_t i = 0; i < frame.pip.size(); ++i) {
    if (frame.pip[i]) continue;
    const bool cleared = frame.maskTiles[tileOf(frame, i)] == PIP_TILE_CLEAR;
    const bool asImage = std::equal(&png.rgba[4 * i], &png.rgba[4 * i + 4], &frame.rgba[4 * i]);
    blue += cleared;
    wrong += cleared ? asImage || png.rgba[4 * i + 2] <= png.rgba[4 * i] : !asImage;
  }
  EXPECT_EQ(wrong, 0u) << "of " << frame.pip.size() << " pixels";
  EXPECT_EQ(blue > 0, clear > 0);
  std::filesystem::remove_all(dir);
}

TEST(PenumbraMask, TileTestLeavesEveryPixelsMaskAsItWas) {
  struct Case {
    std::string name;
    Scene scene;
    float size;
    std::optional<Camera> camera;
    LightType type = LightType::Disk;
    bool explain = false;
  };
  const std::vector<Case> cases = {
      {"courtyard", loadScene("builtin:courtyard"), 0.1f, std::nullopt},
      {"courtyard explained", loadScene("builtin:courtyard"), 0.1f, std::nullopt, LightType::Disk, true},
      {"courtyard square light", loadScene("builtin:courtyard"), 0.1f, std::nullopt, LightType::Rect},
      {"courtyard rail", loadScene("builtin:courtyard"), 0.1f,
       Camera{.eye = {7.0f, 17.0f, 22.0f}, .target = {6.6939f, 11.0691f, 13.7044f}, .fovYDeg = 23.402f}},
      {"foliage", loadScene("builtin:foliage"), 0.1f, std::nullopt},
      {"groove", grooveScene({2.0f, 4.0f, 0.0f}), 0.8f, std::nullopt},
  };
  std::uint64_t clearOverAll = 0;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    RenderSettings settings = maskSettings(384);
    settings.pip.explain = c.explain;
    Frame with, without;
    for (const bool test : {true, false}) {
      settings.pip.tileTest = test ? raster::TileTest::On : raster::TileTest::Off;
      SceneRun run(c.scene, settings);
      if (c.camera) run.camera = *c.camera;
      run.light.type = c.type;
      run.light.size = c.size * c.scene.bounds().radius();
      (test ? with : without) = run.render("srt");
    }
    EXPECT_EQ(without.stats.counts.count("mask_tiles"), 0u);
    ASSERT_EQ(with.stats.counts.count("mask_tiles"), 1u) << "the tile test did not run";
    const std::uint64_t tiles = with.stats.counts.at("mask_tiles"), clear = with.stats.counts.at("mask_tiles_clear");
    std::cout << c.name << ": " << clear << " of " << tiles << " tiles with receivers clear\n";
    EXPECT_LT(clear, tiles);
    clearOverAll += clear;
    std::size_t differ = 0, masked = 0;
    for (std::size_t i = 0; i < with.pip.size(); ++i) {
      differ += with.pip[i] != without.pip[i];
      masked += with.pip[i] != 0;
    }
    EXPECT_EQ(differ, 0u) << "of " << masked << " masked pixels";
    EXPECT_GT(masked, 0u);
    if (c.explain) EXPECT_EQ(with.pipWhy, without.pipWhy);
    EXPECT_TRUE(without.maskTiles.empty()) << "verdicts without the tile test";
    expectTileOverlay(with, clear);
  }
  EXPECT_GT(clearOverAll, 0u);
  expectValidationSilent();
}

// --tile-test auto (CheaperOf): the light's first frame warms with the test, the next two time the
// classification without and with it, then each frame takes the cheaper by their last times, and
// every 32nd the other, which times it again. Taking the dearer one, or never timing the other
// again, fails.
TEST(PenumbraMask, TileTestAutoTakesTheCheaperAndTimesTheOtherAgain) {
  CheaperOf choice;
  EXPECT_TRUE(choice.take());
  choice.timed(1000.0);  // the warming take's time is dropped
  EXPECT_FALSE(choice.ms(true));
  EXPECT_FALSE(choice.take());
  choice.timed(50.0);
  EXPECT_TRUE(choice.take());
  choice.timed(40.0);
  std::vector<std::uint64_t> others;
  for (std::uint64_t take = 4; take <= 100; ++take) {
    const bool way = choice.take();
    if (!way) others.push_back(take);
    choice.timed(way ? 40.0 : 50.0);
  }
  EXPECT_EQ(others, (std::vector<std::uint64_t>{32, 64, 96}));
  // Content changes: the way without the test turns cheaper when it is timed again.
  std::uint64_t take = 101;
  for (; take % CheaperOf::kRemeasure != 0; ++take) EXPECT_TRUE(choice.take());
  EXPECT_FALSE(choice.take());
  choice.timed(30.0);
  EXPECT_FALSE(choice.take());
  EXPECT_EQ(choice.ms(false), 30.0);
  EXPECT_EQ(choice.ms(true), 40.0);
}

// The same in the renderer: its frames take the test as CheaperOf says (with it, without, with),
// the mask the same in each, and say so in their notes.
TEST(PenumbraMask, TileTestAutoKeepsTheMaskInEveryFrame) {
  RenderSettings settings = maskSettings(256);
  settings.pip.tileTest = raster::TileTest::Auto;
  SceneRun run("builtin:courtyard", settings);
  run.light.size = 0.1f * run.scene.bounds().radius();
  std::vector<Frame> frames;
  for (int i = 0; i < 4; ++i) frames.push_back(run.render("srt"));
  for (std::size_t i = 0; i < frames.size(); ++i) {
    SCOPED_TRACE("frame " + std::to_string(i));
    const bool tested = frames[i].stats.counts.count("mask_tiles") != 0;
    if (i < 3) {
      EXPECT_EQ(tested, i != 1);
    }
    EXPECT_EQ(frames[i].pip, frames[0].pip);
    EXPECT_TRUE(hasNote(frames[i], "--tile-test auto"));
  }
  EXPECT_GT(std::count_if(frames[0].pip.begin(), frames[0].pip.end(), [](std::uint32_t f) { return f != 0u; }), 0);
  expectValidationSilent();
}

// The tile choice (--tile-choice on) with its threshold fixed: the light's first frame is the
// paper's; from then on each frame traces whole exactly the tiles whose last classification left
// fewer than the threshold of their covered pixels unflagged - counts carried over where a tile was
// traced whole - but for the tiles of the frame's refresh phase, which classify again; every pixel
// the paper's path traces is traced, the rest keep the map's answer, and srt.pip.png tints the
// pixels of the tiles traced whole orange instead of red.
TEST(PenumbraMask, TileChoiceTracesWholeTheTilesFoundDoubtful) {
  constexpr std::uint32_t kBelow = 9;
  for (const char* spec : {"builtin:courtyard", "builtin:foliage"}) {
    SCOPED_TRACE(spec);
    RenderSettings settings = maskSettings(256);
    settings.pip.tileChoice = true;
    settings.pip.tileTraceBelow = kBelow;
    SceneRun run(spec, settings);
    run.light.size = 0.1f * run.scene.bounds().radius();
    std::vector<Frame> frames;
    for (int i = 0; i < 3; ++i) frames.push_back(run.render("srt"));
    settings.pip.tileChoice = false;
    SceneRun paperRun(spec, settings);
    paperRun.light = run.light;
    const Frame paper = paperRun.render("srt");
    const Frame frt = paperRun.render("frt");

    const Frame& first = frames[0];
    EXPECT_EQ(first.stats.counts.at("tiles_traced_whole"), 0u);
    EXPECT_EQ(first.pip, paper.pip);
    EXPECT_EQ(first.visibility, paper.visibility);
    // The paper's counts per tile, which every later frame sees (the view stands still).
    const std::size_t tiles = tileCount(first);
    ASSERT_EQ(first.maskTiles.size(), tiles);
    std::vector<std::uint32_t> covered(tiles, 0), unflagged(tiles, 0);
    for (std::size_t i = 0; i < paper.pip.size(); ++i) {
      covered[tileOf(paper, i)] += paper.covered[i];
      unflagged[tileOf(paper, i)] += paper.covered[i] && !paper.pip[i];
    }
    for (std::uint32_t phase = 1; phase < frames.size(); ++phase) {
      SCOPED_TRACE("frame " + std::to_string(phase));
      const Frame& f = frames[phase];
      std::uint64_t expected = 0;
      std::size_t wrongTiles = 0, lost = 0, changed = 0, untraced = 0;
      for (std::size_t t = 0; t < tiles; ++t) {
        const bool whole = covered[t] > 0 && unflagged[t] < kBelow && (t + phase) % PIP_TILE_REFRESH != 0;
        expected += whole;
        wrongTiles += whole != (f.maskTiles[t] == PIP_TILE_TRACE);
      }
      for (std::size_t i = 0; i < f.pip.size(); ++i) {
        lost += paper.pip[i] && !f.pip[i];                               // the paper traced it: so must this
        changed += !f.pip[i] && f.visibility[i] != paper.visibility[i];  // the map's answer
        untraced += f.maskTiles[tileOf(f, i)] == PIP_TILE_TRACE && f.covered[i] && !f.pip[i] && f.visibility[i] != 0.0f;
      }
      EXPECT_GT(expected, 0u);
      EXPECT_EQ(f.stats.counts.at("tiles_traced_whole"), expected);
      EXPECT_EQ(wrongTiles, 0u) << "of " << expected << " tiles to trace whole";
      EXPECT_EQ(lost, 0u);
      EXPECT_EQ(changed, 0u);
      EXPECT_EQ(untraced, 0u) << "lit pixels of tiles traced whole left to the map";
      EXPECT_EQ(penumbraMissFraction(frt.visibility, frt.covered, f.pip), 0.0);
    }
    // The overlay: flagged pixels orange in tiles traced whole, red elsewhere.
    const Frame& last = frames.back();
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "penumbra_tile_choice_overlay";
    std::filesystem::create_directories(dir);
    writeFrame(dir.string(), last, nlohmann::json::object());
    const Image png = readPng(dir / "srt.pip.png");
    ASSERT_EQ(png.rgba.size(), last.rgba.size());
    std::size_t orange = 0, wrong = 0;
    for (std::size_t i = 0; i < last.pip.size(); ++i) {
      if (!last.pip[i]) continue;
      const bool whole = last.maskTiles[tileOf(last, i)] == PIP_TILE_TRACE;
      orange += whole;
      wrong += whole != (png.rgba[4 * i + 1] >= 99);  // 0.65 * 0.6 * 255: the tint's green alone
    }
    EXPECT_GT(orange, 0u);
    EXPECT_EQ(wrong, 0u);
    std::filesystem::remove_all(dir);
  }
  expectValidationSilent();
}

// The tile choice's cost model prices what the frame itself took, on a GPU tracer and on Embree
// (whose trace no GPU timestamp sees): its note's classification and trace times are the frame's
// passes, and its threshold follows from them.
TEST(PenumbraMask, TileChoicePricesTheFramesOwnPasses) {
  for (const char* tracer : {"bvh", "embree"}) {
    SCOPED_TRACE(tracer);
    RenderSettings settings = maskSettings(128);
    settings.tracer = tracer;
    settings.pip.tileChoice = true;
    settings.pip.tileTest = raster::TileTest::On;
    SceneRun run("builtin:courtyard", settings);
    run.light.size = 0.1f * run.scene.bounds().radius();
    run.render("srt");
    const Frame f = run.render("srt");
    const auto note = std::find_if(f.stats.notes.begin(), f.stats.notes.end(),
                                   [](const std::string& n) { return n.find("the tile choice traced") == 0; });
    ASSERT_NE(note, f.stats.notes.end());
    unsigned long long whole = 0, tiles = 0, classified = 0, pixels = 0;
    double classifyMs = 0.0, traceMs = 0.0;
    unsigned below = 0;
    ASSERT_EQ(std::sscanf(note->c_str(),
                          "the tile choice traced %llu of %llu tiles whole (--tile-choice on): classifying took %lf ms "
                          "for %llu tiles, the trace %lf ms for %llu pixels, so a tile with fewer than %u",
                          &whole, &tiles, &classifyMs, &classified, &traceMs, &pixels, &below),
              7)
        << *note;
    std::map<std::string, double> passes(f.stats.passMs.begin(), f.stats.passMs.end());
    EXPECT_NEAR(classifyMs, passes["classify"] + passes["mask_tiles"], 0.002);
    EXPECT_NEAR(traceMs, passes["trace"], 0.002 + 1e-3 * passes["trace"]);
    EXPECT_EQ(whole, f.stats.counts.at("tiles_traced_whole"));
    EXPECT_EQ(classified, f.stats.counts.at("tiles_classified"));
    EXPECT_EQ(pixels, f.stats.pipPixels.value_or(0));
    // The times are rounded to the microsecond: the floor may land one either side.
    const double perTile = classifyMs / double(classified), perPixel = traceMs / double(pixels);
    EXPECT_NEAR(double(below), std::min(65.0, 1.0 + std::floor(perTile / perPixel)), 1.0);
  }
  expectValidationSilent();
}

}  // namespace
}  // namespace penumbra::test
