#include "hybrid/frame_output.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <unistd.h>

#include "core/image_io.h"
#include "core/metrics.h"
#include "shared/pip.h"

namespace penumbra {

void writeJson(const std::string& path, const nlohmann::json& value) {
  std::ofstream out(path);
  out << value.dump(2) << "\n";
  if (!out) throw std::runtime_error("cannot write '" + path + "'");
}

namespace {

// The pixels handed to the tracer in red over the image (paper Fig. 4), those of tiles the tile choice
// traced whole in orange; with the penumbra mask's tile test, the tiles it cleared (none of their
// pixels classified) in blue, as the demo's tiles overlay.
void writePipOverlay(const std::string& path, const Frame& frame, const Frame& light) {
  std::vector<std::uint8_t> overlay = frame.rgba;
  const auto tint = [&](std::size_t i, glm::vec3 colour) {
    for (int c = 0; c < 3; ++c)
      overlay[4 * i + c] = std::uint8_t(0.35f * float(overlay[4 * i + c]) + 0.65f * 255.0f * colour[c]);
  };
  const std::uint32_t tilesPerRow = (frame.width + PIP_MASK_TILE_SIZE - 1) / PIP_MASK_TILE_SIZE;
  for (std::size_t i = 0; i < light.pip.size(); ++i) {
    const std::size_t x = i % frame.width, y = i / frame.width;
    const std::size_t tile = y / PIP_MASK_TILE_SIZE * tilesPerRow + x / PIP_MASK_TILE_SIZE;
    const std::uint8_t verdict = tile < light.maskTiles.size() ? light.maskTiles[tile] : PIP_TILE_NONE;
    if (light.pip[i]) {
      tint(i, verdict == PIP_TILE_TRACE ? glm::vec3(1.0f, 0.6f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f));
    } else if (verdict == PIP_TILE_CLEAR) {
      tint(i, {0.25f, 0.5f, 1.0f});
    }
  }
  writePngRgba8(path, int(frame.width), int(frame.height), overlay);
}

// A frame of several lights: where light i's own images go (dir/lights/<method>.<i>.*).
std::string lightBase(const std::string& dir, const Frame& frame, std::size_t i) {
  return dir + "/lights/" + frame.stats.method + "." + std::to_string(i);
}

}  // namespace

void writeFrame(const std::string& dir, const Frame& frame, const nlohmann::json& context) {
  const std::string base = dir + "/" + frame.stats.method;
  const int w = int(frame.width), h = int(frame.height);
  writePngRgba8(base + ".png", w, h, frame.rgba);
  writeExrGray(base + ".visibility.exr", w, h, frame.visibility);
  writePngGray16(base + ".visibility.png", w, h, frame.visibility);
  if (!frame.pip.empty()) writePipOverlay(base + ".pip.png", frame, frame);
  if (frame.lights.size() > 1) std::filesystem::create_directories(dir + "/lights");
  for (std::size_t i = 0; i < frame.lights.size(); ++i) {
    const Frame& light = frame.lights[i];
    if (light.visibility.empty()) continue;  // its buffers were not kept
    writePngGray16(lightBase(dir, frame, i) + ".visibility.png", w, h, light.visibility);
    if (!light.pip.empty()) writePipOverlay(lightBase(dir, frame, i) + ".pip.png", frame, light);
  }
  nlohmann::json stats = frame.stats.toJson();
  stats["context"] = context;
  writeJson(base + ".stats.json", stats);
}

void writeHeatmap(const std::string& dir, const Frame& frame, const Frame& reference, float fullScale) {
  const int w = int(frame.width), h = int(frame.height);
  writePngRgba8(dir + "/" + frame.stats.method + ".heatmap.png", w, h,
                errorHeatmap(frame.visibility, reference.visibility, reference.covered, fullScale));
  for (std::size_t i = 0; i < frame.lights.size(); ++i) {  // a frame of several lights (one keeps none)
    const Frame& light = frame.lights[i];
    if (light.visibility.empty() || i >= reference.lights.size() || reference.lights[i].visibility.empty()) continue;
    writePngRgba8(lightBase(dir, frame, i) + ".heatmap.png", w, h,
                  errorHeatmap(light.visibility, reference.lights[i].visibility, reference.covered, fullScale));
  }
}

namespace fs = std::filesystem;

namespace {
std::string stagingFor(const std::string& dir) {
  fs::path p = fs::path(dir).lexically_normal();
  if (!p.has_filename()) p = p.parent_path();  // "out/": beside out, not in it
  return p.string() + ".partial-" + std::to_string(getpid());
}
}  // namespace

StagedOutput::StagedOutput(const std::string& dir) : dir_(dir), staging_(stagingFor(dir)) {
  fs::remove_all(staging_);
  fs::create_directories(staging_);
}

StagedOutput::~StagedOutput() {
  std::error_code ignored;
  if (!committed_) fs::remove_all(staging_, ignored);
}

void StagedOutput::commit() {
  fs::create_directories(dir_);
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(staging_)) {
    const fs::path to = fs::path(dir_) / fs::relative(e.path(), staging_);
    if (e.is_directory()) fs::create_directories(to);
    else files.push_back(e.path());
  }
  // metrics.json last: its presence says the folder is complete.
  std::stable_partition(files.begin(), files.end(), [](const fs::path& f) { return f.filename() != "metrics.json"; });
  for (const fs::path& f : files) fs::rename(f, fs::path(dir_) / fs::relative(f, staging_));
  fs::remove_all(staging_);
  committed_ = true;
}

}  // namespace penumbra

