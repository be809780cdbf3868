// Image output: EXR round trips, a hand-written 16-bit PNG decoded by stb_image, error paths.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <unistd.h>

#include "core/image_io.h"

#include "png_check.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

class ImageIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("penumbra_image_io_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const char* name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

std::vector<std::uint8_t> readBytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

std::uint32_t bigEndian32(const std::uint8_t* p) {
  return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) | p[3];
}

// Bitwise CRC-32, independent of the table version in image_io.cpp.
std::uint32_t slowCrc(const std::uint8_t* data, std::size_t size) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) {
    c ^= data[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}

TEST_F(ImageIo, ExrRoundTripIsBitExact) {
  const int w = 7, h = 5;
  std::vector<float> values(w * h);
  for (int i = 0; i < w * h; ++i) values[i] = std::sin(float(i) * 0.37f) * 0.5f + 0.5f;
  values[0] = 0.0f;
  values[1] = 1.0f;
  values[2] = 0.1f;  // not representable as half: checks that FLOAT is stored
  values[3] = std::numeric_limits<float>::denorm_min();
  values[4] = -3.5e7f;
  const std::string file = path("vis.exr");
  writeExrGray(file, w, h, values);
  int rw = 0, rh = 0;
  const std::vector<float> back = readExrGray(file, rw, rh);
  EXPECT_EQ(rw, w);
  EXPECT_EQ(rh, h);
  ASSERT_EQ(back.size(), values.size());
  EXPECT_EQ(std::memcmp(back.data(), values.data(), values.size() * sizeof(float)), 0);
}

TEST_F(ImageIo, Png16IsValidGreyAndRoundTrips) {
  const int w = 13, h = 6;
  std::vector<float> values(w * h);
  for (int i = 0; i < w * h; ++i) values[i] = float(i) / float(w * h - 1);
  values[5] = -0.5f;  // clamped to 0
  values[6] = 2.0f;   // clamped to 1
  const std::string file = path("vis.png");
  writePngGray16(file, w, h, values);

  const std::vector<std::uint8_t> bytes = readBytes(file);
  ASSERT_GT(bytes.size(), 8u + 25u + 12u);
  const std::uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  EXPECT_EQ(std::memcmp(bytes.data(), signature, 8), 0);
  const std::uint8_t* ihdr = bytes.data() + 8;
  EXPECT_EQ(bigEndian32(ihdr), 13u);
  EXPECT_EQ(std::memcmp(ihdr + 4, "IHDR", 4), 0);
  EXPECT_EQ(bigEndian32(ihdr + 8), std::uint32_t(w));
  EXPECT_EQ(bigEndian32(ihdr + 12), std::uint32_t(h));
  EXPECT_EQ(ihdr[16], 16);  // bit depth
  EXPECT_EQ(ihdr[17], 0);   // colour type: grey
  EXPECT_EQ(bigEndian32(ihdr + 21), slowCrc(ihdr + 4, 17));
  EXPECT_EQ(std::memcmp(bytes.data() + bytes.size() - 8, "IEND", 4), 0);

  int rw = 0, rh = 0, channels = 0;
  stbi_us* decoded = stbi_load_16(file.c_str(), &rw, &rh, &channels, 0);
  ASSERT_NE(decoded, nullptr) << stbi_failure_reason();
  EXPECT_EQ(rw, w);
  EXPECT_EQ(rh, h);
  EXPECT_EQ(channels, 1);
  for (int i = 0; i < w * h; ++i) {
    const float c = std::min(std::max(values[i], 0.0f), 1.0f);
    EXPECT_EQ(decoded[i], std::lround(c * 65535.0f)) << i;
  }
  stbi_image_free(decoded);
}

TEST_F(ImageIo, Png8RoundTrips) {
  const int w = 4, h = 3;
  std::vector<std::uint8_t> rgba(w * h * 4);
  for (std::size_t i = 0; i < rgba.size(); ++i) rgba[i] = std::uint8_t(i * 19 + 7);
  const std::string file = path("pic.png");
  writePngRgba8(file, w, h, rgba);
  int rw = 0, rh = 0, channels = 0;
  stbi_uc* decoded = stbi_load(file.c_str(), &rw, &rh, &channels, 4);
  ASSERT_NE(decoded, nullptr);
  EXPECT_EQ(rw, w);
  EXPECT_EQ(rh, h);
  EXPECT_EQ(std::memcmp(decoded, rgba.data(), rgba.size()), 0);
  stbi_image_free(decoded);
}

void expectThrowsNaming(const std::string& path, const std::function<void()>& f) {
  try {
    f();
    ADD_FAILURE() << "no exception for " << path;
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST_F(ImageIo, FailuresNameThePath) {
  const std::string missing = (dir_ / "no_such_folder" / "out").string();
  const std::vector<float> grey(4, 0.5f);
  const std::vector<std::uint8_t> rgba(16, 255);
  expectThrowsNaming(missing + ".png", [&] { writePngRgba8(missing + ".png", 2, 2, rgba); });
  expectThrowsNaming(missing + "16.png", [&] { writePngGray16(missing + "16.png", 2, 2, grey); });
  expectThrowsNaming(missing + ".exr", [&] { writeExrGray(missing + ".exr", 2, 2, grey); });
  int w = 0, h = 0;
  expectThrowsNaming(missing + ".exr", [&] { readExrGray(missing + ".exr", w, h); });
  // Wrong buffer sizes and non-EXR input are failures too.
  const std::string ok = path("ok.png");
  expectThrowsNaming(ok, [&] { writePngGray16(ok, 3, 2, grey); });
  expectThrowsNaming(ok, [&] { writePngRgba8(ok, 2, 2, std::vector<std::uint8_t>(3)); });
  writePngGray16(ok, 2, 2, grey);
  expectThrowsNaming(ok, [&] { readExrGray(ok, w, h); });
}

}  // namespace
}  // namespace penumbra
