#include "hybrid/frame_output.h"

#include <fstream>
#include <stdexcept>

#include "core/image_io.h"
#include "core/metrics.h"

namespace penumbra {

void writeJson(const std::string& path, const nlohmann::json& value) {
  std::ofstream out(path);
  out << value.dump(2) << "\n";
  if (!out) throw std::runtime_error("cannot write '" + path + "'");
}

void writeFrame(const std::string& dir, const Frame& frame, const nlohmann::json& context) {
  const std::string base = dir + "/" + frame.stats.method;
  const int w = int(frame.width), h = int(frame.height);
  writePngRgba8(base + ".png", w, h, frame.rgba);
  writeExrGray(base + ".visibility.exr", w, h, frame.visibility);
  writePngGray16(base + ".visibility.png", w, h, frame.visibility);
  if (!frame.pip.empty()) {  // the pixels handed to the tracer, in red over the image (paper Fig. 4)
    std::vector<std::uint8_t> overlay = frame.rgba;
    for (std::size_t i = 0; i < frame.pip.size(); ++i) {
      if (!frame.pip[i]) continue;
      overlay[4 * i + 0] = std::uint8_t(0.35f * overlay[4 * i + 0] + 0.65f * 255.0f);
      overlay[4 * i + 1] = std::uint8_t(0.35f * overlay[4 * i + 1]);
      overlay[4 * i + 2] = std::uint8_t(0.35f * overlay[4 * i + 2]);
    }
    writePngRgba8(base + ".pip.png", w, h, overlay);
  }
  nlohmann::json stats = frame.stats.toJson();
  stats["context"] = context;
  writeJson(base + ".stats.json", stats);
}

void writeHeatmap(const std::string& dir, const Frame& frame, const Frame& reference, float fullScale) {
  const auto rgba = errorHeatmap(frame.visibility, reference.visibility, reference.covered, fullScale);
  writePngRgba8(dir + "/" + frame.stats.method + ".heatmap.png", int(frame.width), int(frame.height), rgba);
}

}  // namespace penumbra
