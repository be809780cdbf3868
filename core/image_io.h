// Image output: 8-bit PNG (stb) for pictures; visibility buffers losslessly as 32-bit float EXR
// (tinyexr) plus a 16-bit grey PNG for viewers. Row 0 is the top of the image.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace penumbra {

// rgba: width*height*4 bytes. Throws std::runtime_error naming the path on failure.
void writePngRgba8(const std::string& path, int width, int height, std::span<const std::uint8_t> rgba);
// values: width*height floats in [0,1] (clamped), written as 16-bit grey.
void writePngGray16(const std::string& path, int width, int height, std::span<const float> values);
void writeExrGray(const std::string& path, int width, int height, std::span<const float> values);
std::vector<float> readExrGray(const std::string& path, int& width, int& height);

}  // namespace penumbra
