// Lights as JSON (core/lights_file.h): every field of a light survives a round trip, through a view
// file too, and every bad field is refused naming the light and the field.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/lights_file.h"
#include "core/view.h"

namespace penumbra::test {
namespace {

std::vector<Light> mixedLights() {
  Light disk = parseLight("disk:5,10,5:0,0,0");
  disk.size = 0.75f;
  disk.color = {1.0f, 0.5f, 0.25f};
  Light lamp = parseLight("point:1,3,-2");
  lamp.range = 7.0f;
  lamp.inverseSquare = true;
  lamp.intensity = 12.5f;
  Light spot = parseLight("spot:0,4,0:1,0,0:60");
  spot.innerAngleDeg = 35.0f;
  return {disk, lamp, spot, parseLight("dir:0.3,-1,0.2")};
}

void expectSame(const Light& a, const Light& b, std::size_t i) {
  EXPECT_EQ(a.type, b.type) << i;
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(a.position[k], b.position[k], 1e-5f) << i;
    EXPECT_NEAR(a.direction[k], b.direction[k], 1e-5f) << i;
    EXPECT_FLOAT_EQ(a.color[k], b.color[k]) << i;
  }
  EXPECT_FLOAT_EQ(a.size, b.size) << i;
  EXPECT_FLOAT_EQ(a.intensity, b.intensity) << i;
  EXPECT_FLOAT_EQ(a.range, b.range) << i;
  EXPECT_EQ(a.inverseSquare, b.inverseSquare) << i;
  EXPECT_FLOAT_EQ(a.spotAngleDeg, b.spotAngleDeg) << i;
  EXPECT_FLOAT_EQ(a.innerAngleDeg, b.innerAngleDeg) << i;
}

class LightsFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("penumbra_lights_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const std::filesystem::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  std::filesystem::path dir_;
};

TEST_F(LightsFile, EveryFieldRoundTrips) {
  const std::vector<Light> lights = mixedLights();
  const glm::dvec3 origin(1000.0, 0.0, -2000.0);
  nlohmann::json array = nlohmann::json::array();
  for (const Light& l : lights) array.push_back(nlohmann::json::parse(lightToJson(l, origin).dump()));
  const std::vector<Light> back = readLightsFile(write("lights.json", array.dump(2)), origin);
  ASSERT_EQ(back.size(), lights.size());
  for (std::size_t i = 0; i < lights.size(); ++i) expectSame(back[i], lights[i], i);
  // only what differs from a default light is written
  EXPECT_EQ(lightToJson(parseLight("point:0,1,0")).size(), 1u);

  View view;
  view.light = lights.front();
  view.lights = lights;
  const std::string path = (dir_ / "view.json").string();
  writeViewFile(path, view, origin);
  const View read = readViewFile(path, origin);
  ASSERT_EQ(read.lights.size(), lights.size());
  for (std::size_t i = 0; i < lights.size(); ++i) expectSame(read.lights[i], lights[i], i);
  EXPECT_EQ(readLightsFile(path, origin).size(), lights.size()) << "a view file is a lights file too";
}

TEST_F(LightsFile, BadFieldsAreRefusedByName) {
  const std::pair<const char*, const char*> cases[] = {
      {R"([{"range": 3}])", "\"light\""},
      {R"([{"light": "lamp:0,1,0"}])", "unknown light type"},
      {R"([{"light": "point:0,1,0", "brightness": 2}])", "unknown field \"brightness\""},
      {R"([{"light": "point:0,1,0", "range": -1}])", "\"range\""},
      {R"([{"light": "point:0,1,0", "intensity": "high"}])", "\"intensity\""},
      {R"([{"light": "point:0,1,0", "size": 0.5}])", "area light"},
      {R"([{"light": "point:0,1,0", "color": [1, 1]}])", "\"color\""},
      {R"([{"light": "point:0,1,0", "color": [1, -1, 0]}])", "\"color\""},
      {R"([{"light": "point:0,1,0", "inner_angle": 10}])", "spot lights only"},
      {R"([{"light": "spot:0,4,0:0,0,0:40", "inner_angle": 50}])", "must not exceed"},
      {R"([{"light": "point:0,1,0", "inverse_square": 1}])", "true or false"},
      {R"([{"light": "point:0,1,0"}, 3])", "light 1"},
      {R"([])", "non-empty array"},
      {R"({"camera": "0,1,5:0,0,0"})", "without \"lights\""},
      {R"([{"light": "point:0,1,0",)", "not valid JSON"},
  };
  for (const auto& [text, expected] : cases) {
    try {
      readLightsFile(write("bad.json", text));
      ADD_FAILURE() << text << " was read";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(expected), std::string::npos) << text << " -> " << message;
      EXPECT_NE(message.find("bad.json"), std::string::npos) << message;
    }
  }
  EXPECT_THROW(readLightsFile((dir_ / "none.json").string()), InputError);
}

}  // namespace
}  // namespace penumbra::test
