#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include "core/camera.h"
#include "core/view.h"

namespace fs = std::filesystem;
using namespace penumbra;

namespace {

// Runs `f`, expects an InputError and returns its message ("" when none was thrown).
template <typename F>
std::string inputErrorOf(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

void expectVecNear(const glm::vec3& a, const glm::vec3& b, float tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

Bounds boundsOf(const glm::vec3& lo, const glm::vec3& hi) {
  Bounds b;
  b.extend(lo);
  b.extend(hi);
  return b;
}

// A fresh folder per test, removed afterwards.
class ViewFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("penumbra_view_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  fs::path dir_;
};

}  // namespace

TEST(ViewCamera, ParsesEyeTargetAndOptionalFov) {
  const Camera c = parseCamera("0,2,8:0,0.5,-1");
  EXPECT_EQ(c.eye, glm::vec3(0.0f, 2.0f, 8.0f));
  EXPECT_EQ(c.target, glm::vec3(0.0f, 0.5f, -1.0f));
  EXPECT_FLOAT_EQ(c.fovYDeg, 45.0f);
  EXPECT_EQ(c.up, glm::vec3(0.0f, 1.0f, 0.0f));
  const Camera d = parseCamera(" 1, -2.5e1 ,+3 : 0,0,0 : 30.5 ");
  EXPECT_EQ(d.eye, glm::vec3(1.0f, -25.0f, 3.0f));
  EXPECT_FLOAT_EQ(d.fovYDeg, 30.5f);
}

TEST(ViewCamera, StraightDownViewGetsAUsableUpVector) {
  const Camera c = parseCamera("0,10,0:0,0,0");
  const glm::vec3 forward = glm::normalize(c.target - c.eye);
  EXPECT_LT(std::abs(glm::dot(forward, glm::normalize(c.up))), 0.5f);
  const ViewMatrices m = cameraMatrices(c, boundsOf(glm::vec3(-1.0f), glm::vec3(1.0f)), 64, 64);
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) EXPECT_TRUE(std::isfinite(m.viewProj[i][j]));
  }
}

TEST(ViewCamera, FormatRoundTripsExactly) {
  std::vector<Camera> cameras(4);
  cameras[0] = Camera{};
  cameras[1].eye = {1.2345678e-3f, -98765.4321f, 3.14159265f};
  cameras[1].target = {0.1f, 0.2f, 0.3f};
  cameras[1].fovYDeg = 17.25f;
  cameras[2].eye = {-7.0f, 1e-7f, 2.5e6f};
  cameras[2].target = {1.0f / 3.0f, 2.0f / 3.0f, -1.0f / 7.0f};
  cameras[2].fovYDeg = 179.5f;
  cameras[3].eye = {0.0f, 5.0f, 0.0f};
  cameras[3].target = {0.0f, -1.0f, 0.0f};
  for (const Camera& c : cameras) {
    const std::string text = formatCamera(c);
    const Camera back = parseCamera(text);
    EXPECT_EQ(back.eye, c.eye) << text;
    EXPECT_EQ(back.target, c.target) << text;
    EXPECT_EQ(back.fovYDeg, c.fovYDeg) << text;
    EXPECT_EQ(formatCamera(back), text);
  }
  EXPECT_EQ(formatCamera(parseCamera("0,2,8:0,0,0:45")), "0,2,8:0,0,0:45");
}

TEST(ViewCamera, RejectsMalformedSpecs) {
  const std::vector<std::string> bad = {
      "",          "1,2,3",         "1,2:0,0,0",        "1,2,3,4:0,0,0",      "a,b,c:0,0,0",
      "1,,3:0,0,0", "1 2 3:0,0,0",  "1,2,3:0,0,0:",     "1,2,3:0,0,0:45:1",   "1,2,3:0,0,0:0",
      "1,2,3:0,0,0:180", "1,2,3:0,0,0:-5", "nan,0,0:0,0,0", "inf,0,0:0,0,0", "1e40,0,0:0,0,0",
      "1,2,3:1,2,3", "1,2,3:0,0,0:nan", "1,2,3:0,0,0:45deg", "0x1,0,0:0,0,0", "+-1,0,0:0,0,0"};
  for (const std::string& spec : bad) {
    const std::string message = inputErrorOf([&] { parseCamera(spec); });
    ASSERT_FALSE(message.empty()) << "accepted camera '" << spec << "'";
    EXPECT_NE(message.find("camera '" + spec + "'"), std::string::npos) << message;
    EXPECT_NE(message.find("ex,ey,ez:tx,ty,tz[:fovy]"), std::string::npos) << message;
  }
  EXPECT_NE(inputErrorOf([] { parseCamera("1,2,3:1,2,3"); }).find("coincide"), std::string::npos);
  EXPECT_NE(inputErrorOf([] { parseCamera("1,2,3:0,0,0:200"); }).find("(0, 180)"), std::string::npos);
  EXPECT_NE(inputErrorOf([] { parseCamera("3e38,0,0:-3e38,0,0"); }).find("overflows"), std::string::npos);
}

TEST(ViewLight, ParsesEachType) {
  const Light dir = parseLight("dir:0,-2,0");
  EXPECT_EQ(dir.type, LightType::Directional);
  expectVecNear(dir.direction, {0.0f, -1.0f, 0.0f}, 1e-7f);

  const Light point = parseLight("point:1,2,3");
  EXPECT_EQ(point.type, LightType::Point);
  EXPECT_EQ(point.position, glm::vec3(1.0f, 2.0f, 3.0f));

  const Light spot = parseLight("spot:0,4,0:3,0,4");
  EXPECT_EQ(spot.type, LightType::Spot);
  expectVecNear(spot.direction, glm::normalize(glm::vec3(3.0f, -4.0f, 4.0f)), 1e-6f);
  EXPECT_FLOAT_EQ(spot.spotAngleDeg, 60.0f);
  EXPECT_FLOAT_EQ(parseLight("spot:0,4,0:3,0,4:25").spotAngleDeg, 25.0f);

  const Light rect = parseLight("rect:0,10,0:0,0,0");
  EXPECT_EQ(rect.type, LightType::Rect);
  expectVecNear(rect.direction, {0.0f, -1.0f, 0.0f}, 1e-7f);
  EXPECT_EQ(rect.size, 0.0f);

  const Light disk = parseLight("disk:5,10,5:0,0,0");
  EXPECT_EQ(disk.type, LightType::Disk);
  EXPECT_EQ(disk.position, glm::vec3(5.0f, 10.0f, 5.0f));
  expectVecNear(disk.direction, glm::normalize(glm::vec3(-5.0f, -10.0f, -5.0f)), 1e-6f);
}

TEST(ViewLight, FormatRoundTrips) {
  std::vector<Light> lights;
  Light l;
  l.type = LightType::Directional;
  l.direction = glm::normalize(glm::vec3(0.15f, -1.0f, 0.1f));
  lights.push_back(l);
  l.type = LightType::Point;
  l.position = {0.4f, 2.0f, 0.3f};
  lights.push_back(l);
  l.type = LightType::Spot;
  l.position = {-12345.678f, 250.5f, 1e-3f};
  l.direction = glm::normalize(glm::vec3(1.0f, -3.0f, 0.25f));
  l.spotAngleDeg = 33.3f;
  lights.push_back(l);
  l.type = LightType::Rect;
  l.position = {1.0f / 3.0f, 7.0f, -2.0f};
  l.direction = glm::normalize(glm::vec3(0.0f, -1.0f, 1e-3f));
  lights.push_back(l);
  l.type = LightType::Disk;
  l.position = {-5.0f, 36.0f, 9.0f};
  l.direction = glm::normalize(glm::vec3(5.0f, -34.0f, -9.0f));
  lights.push_back(l);
  for (const Light& light : lights) {
    const std::string text = formatLight(light);
    const Light back = parseLight(text);
    EXPECT_EQ(back.type, light.type) << text;
    EXPECT_EQ(text.rfind(std::string(lightTypeName(light.type)) + ":", 0), 0u) << text;
    if (light.type != LightType::Directional) {
      EXPECT_EQ(back.position, light.position) << text;
    }
    if (light.type != LightType::Point) {
      expectVecNear(back.direction, light.direction, 2e-6f);
    }
    if (light.type == LightType::Spot) {
      EXPECT_EQ(back.spotAngleDeg, light.spotAngleDeg) << text;
    }
  }
  EXPECT_EQ(formatLight(parseLight("dir:0,-1,0")), "dir:0,-1,0");
  EXPECT_EQ(formatLight(parseLight("point:1,2,3")), "point:1,2,3");
}

TEST(ViewLight, RejectsMalformedSpecs) {
  const std::vector<std::string> bad = {"",
                                        "sun:0,-1,0",
                                        "DIR:0,-1,0",
                                        "dir",
                                        "dir:0,0,0",
                                        "dir:1,2",
                                        "dir:0,-1,0:5",
                                        "dir:nan,-1,0",
                                        "point:inf,0,0",
                                        "point:1,2,3:4,5,6",
                                        "point:1,2,x",
                                        "spot:0,1,0:0,1,0",
                                        "spot:0,1,0:0,0,0:0",
                                        "spot:0,1,0:0,0,0:180",
                                        "spot:0,1,0:0,0,0:30:1",
                                        "spot:0,1,0",
                                        "rect:0,1,0",
                                        "rect:0,1,0:0,1,0",
                                        "disk:0,1,0:0,0,0:30",
                                        "disk:0,1,0:0,0"};
  for (const std::string& spec : bad) {
    const std::string message = inputErrorOf([&] { parseLight(spec); });
    ASSERT_FALSE(message.empty()) << "accepted light '" << spec << "'";
    EXPECT_NE(message.find("light '" + spec + "'"), std::string::npos) << message;
    EXPECT_NE(message.find("dir:dx,dy,dz"), std::string::npos) << message;
  }
  EXPECT_NE(inputErrorOf([] { parseLight("sun:0,-1,0"); }).find("unknown light type 'sun'"), std::string::npos);
  EXPECT_NE(inputErrorOf([] { parseLight("dir:0,0,0"); }).find("zero length"), std::string::npos);
}

TEST(ViewDefaults, CameraFramesTheWholeBounds) {
  for (const Bounds& b : {boundsOf({-1.0f, 0.0f, -1.0f}, {1.0f, 0.5f, 1.0f}),
                          boundsOf({100.0f, -3.0f, 7.0f}, {140.0f, 60.0f, 9.0f}),
                          boundsOf({-1e-3f, -1e-3f, -1e-3f}, {1e-3f, 1e-3f, 1e-3f})}) {
    const Camera c = defaultCamera(b);
    EXPECT_FLOAT_EQ(c.fovYDeg, 45.0f);
    EXPECT_GT(c.eye.y, b.center().y);  // from above
    const ViewMatrices m = cameraMatrices(c, b, 256, 256);
    for (int corner = 0; corner < 8; ++corner) {
      const glm::vec3 p{corner & 1 ? b.hi.x : b.lo.x, corner & 2 ? b.hi.y : b.lo.y, corner & 4 ? b.hi.z : b.lo.z};
      const glm::vec4 clip = m.viewProj * glm::vec4(p, 1.0f);
      ASSERT_GT(clip.w, 0.0f);
      EXPECT_LE(std::abs(clip.x / clip.w), 1.0f);
      EXPECT_LE(std::abs(clip.y / clip.w), 1.0f);
    }
    // The sphere fills most of the frame rather than a corner of it.
    const float distance = glm::length(c.eye - b.center());
    EXPECT_LT(distance, 3.0f * b.radius());
  }
}

TEST(ViewDefaults, LightIsAPointLikeDiskAboveFacingTheCentre) {
  const Bounds b = boundsOf({-2.0f, 0.0f, -3.0f}, {4.0f, 2.0f, 1.0f});
  const Light l = defaultLight(b);
  EXPECT_EQ(l.type, LightType::Disk);
  EXPECT_EQ(l.size, 0.0f);
  EXPECT_GT(l.position.y, b.hi.y);
  EXPECT_NEAR(glm::length(l.position - b.center()), 2.5f * b.radius(), 1e-3f * b.radius());
  expectVecNear(l.direction, glm::normalize(b.center() - l.position), 1e-6f);
  // Off to the side, so shadows are not hidden under their casters.
  EXPECT_GT(glm::length(glm::vec2(l.position.x, l.position.z) - glm::vec2(b.center().x, b.center().z)),
            0.5f * b.radius());
}

TEST(ViewDefaults, EmptyBoundsStayFinite) {
  const Camera c = defaultCamera(Bounds{});
  const Light l = defaultLight(Bounds{});
  for (const glm::vec3& v : {c.eye, c.target, l.position, l.direction}) {
    EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
  }
  EXPECT_NE(c.eye, c.target);
}

TEST(ViewLightSize, ScalesAreaLightsByTheRadius) {
  const Bounds b = boundsOf({-3.0f, 0.0f, -4.0f}, {3.0f, 0.0f, 4.0f});  // radius 5
  Light disk = parseLight("disk:0,10,0:0,0,0");
  applyLightSize(disk, 0.1f, b);
  EXPECT_FLOAT_EQ(disk.size, 0.5f);
  Light rect = parseLight("rect:0,10,0:0,0,0");
  applyLightSize(rect, 0.02f, b);
  EXPECT_FLOAT_EQ(rect.size, 0.1f);
  applyLightSize(rect, 0.0f, b);
  EXPECT_EQ(rect.size, 0.0f);
}

TEST(ViewLightSize, RefusesSizeForLightsWithoutExtent) {
  const Bounds b = boundsOf(glm::vec3(-1.0f), glm::vec3(1.0f));
  for (const char* spec : {"dir:0,-1,0", "spot:0,4,0:0,0,0", "point:0,4,0"}) {
    Light l = parseLight(spec);
    const std::string message = inputErrorOf([&] { applyLightSize(l, 0.05f, b); });
    ASSERT_FALSE(message.empty()) << spec;
    EXPECT_NE(message.find("rect:"), std::string::npos) << message;
    EXPECT_NE(message.find("disk:"), std::string::npos) << message;
    EXPECT_NE(message.find(lightTypeName(l.type)), std::string::npos) << message;
    applyLightSize(l, 0.0f, b);  // zero stays allowed: a point is what these lights are
    EXPECT_EQ(l.size, 0.0f);
  }
}

TEST(ViewLightSize, RefusesNegativeAndNonFinite) {
  const Bounds b = boundsOf(glm::vec3(-1.0f), glm::vec3(1.0f));
  Light l = parseLight("disk:0,4,0:0,0,0");
  for (const float bad : {-0.1f, std::nanf(""), INFINITY, -INFINITY}) {
    const std::string message = inputErrorOf([&] { applyLightSize(l, bad, b); });
    EXPECT_FALSE(message.empty()) << bad;
    EXPECT_NE(message.find("light-size"), std::string::npos) << message;
  }
  EXPECT_EQ(l.size, 0.0f);
}

TEST_F(ViewFile, RoundTrips) {
  View view;
  view.camera = parseCamera("9,19,23:0,0,0.5:40");
  view.light = parseLight("disk:-5,36,9:0.1,2,0.3");
  view.lightSizeFraction = 0.1f;
  view.width = 640;
  view.height = 360;
  const std::string path = (dir_ / "view.json").string();
  writeViewFile(path, view);

  // The file is the documented JSON, readable by people and other tools.
  std::ifstream in(path);
  const nlohmann::json json = nlohmann::json::parse(in);
  EXPECT_EQ(json.at("camera"), "9,19,23:0,0,0.5:40");
  EXPECT_EQ(json.at("light").get<std::string>().rfind("disk:-5,36,9:", 0), 0u);
  EXPECT_EQ(json.at("light_size").get<double>(), 0.1);
  EXPECT_EQ(json.at("resolution"), nlohmann::json::array({640, 360}));

  const View back = readViewFile(path);
  EXPECT_EQ(formatCamera(back.camera), formatCamera(view.camera));
  EXPECT_EQ(back.light.type, LightType::Disk);
  EXPECT_EQ(back.light.position, view.light.position);
  expectVecNear(back.light.direction, view.light.direction, 2e-6f);
  EXPECT_EQ(back.lightSizeFraction, 0.1f);
  EXPECT_EQ(back.width, 640);
  EXPECT_EQ(back.height, 360);
}

// A model stored relative to a far origin (Scene::origin): specs and view files stay in world
// coordinates, and reading them keeps detail that a float world coordinate would round away
// (at 1e7 one float step is a whole unit).
TEST_F(ViewFile, WorldCoordinatesThroughASceneOrigin) {
  const glm::dvec3 origin(1e7, 0.0, -2.5e7);
  View view;
  view.camera = parseCamera("10000014.125,12,-24999984.5:10000000.25,0.5,-25000000:30", origin);
  EXPECT_EQ(view.camera.eye, glm::vec3(14.125f, 12.0f, 15.5f));
  EXPECT_EQ(view.camera.target, glm::vec3(0.25f, 0.5f, 0.0f));
  EXPECT_EQ(formatCamera(view.camera, origin), "10000014.125,12,-24999984.5:10000000.25,0.5,-25000000:30");
  view.light = parseLight("point:9999994.1,18,-24999996.3", origin);
  EXPECT_EQ(formatLight(view.light, origin), "point:9999994.1,18,-24999996.3") << "the shortest world text";
  EXPECT_EQ(parseLight(formatLight(view.light, origin), origin).position, view.light.position);
  const std::string path = (dir_ / "far.json").string();
  writeViewFile(path, view, origin);
  const View back = readViewFile(path, origin);
  EXPECT_EQ(back.camera.eye, view.camera.eye);
  EXPECT_EQ(back.light.position, view.light.position);
  EXPECT_EQ(readViewFile(path).camera.eye.x, 10000014.0f) << "read without the origin, float rounds it";
}

TEST_F(ViewFile, AnimationTimeRoundTripsAndIsChecked) {
  View view;
  view.camera = parseCamera("9,19,23:0,0,0.5:40");
  view.light = parseLight("point:1,8,2");
  view.time = 2.125;
  const std::string path = (dir_ / "view.json").string();
  writeViewFile(path, view);
  EXPECT_EQ(readViewFile(path).time, 2.125);
  for (const char* bad : {"-1", "\"soon\"", "null"}) {
    const std::string text = std::string(R"({"camera": "0,2,8:0,0,0", "light": "dir:0,-1,0", "resolution": [8, 8], "time": )") + bad + "}";
    try {
      readViewFile(write("bad.json", text));
      FAIL() << "time " << bad << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("time"), std::string::npos) << e.what();
    }
  }
}

TEST(ViewOrbitLight, TurnsPositionAndDirectionAboutTheCentreAxis) {
  Bounds bounds;
  bounds.extend({-2.0f, 0.0f, -2.0f});
  bounds.extend({4.0f, 3.0f, 2.0f});
  const Light light = parseLight("spot:5,9,1:1,0,0:40");
  const glm::vec3 centre = bounds.center();
  const Light quarter = orbitLight(light, bounds, 90.0f);
  EXPECT_NEAR(glm::distance(quarter.position, centre), glm::distance(light.position, centre), 1e-4f);
  EXPECT_FLOAT_EQ(quarter.position.y, light.position.y);
  EXPECT_GT(glm::distance(quarter.position, light.position), 1.0f);
  // Still aimed at the same point, turned with it.
  const glm::vec3 aim = glm::vec3(1.0f, 0.0f, 0.0f);
  const glm::vec3 turnedAim = orbitLight(Light{.position = aim}, bounds, 90.0f).position;
  EXPECT_LT(glm::length(glm::normalize(turnedAim - quarter.position) - quarter.direction), 1e-4f);
  const Light full = orbitLight(light, bounds, 360.0f);
  expectVecNear(full.position, light.position, 1e-4f);
  expectVecNear(full.direction, light.direction, 1e-5f);
}

TEST_F(ViewFile, LightSizeIsOptional) {
  const View v = readViewFile(write("v.json", R"({"camera": "0,2,8:0,0,0", "light": "dir:0,-1,0", "resolution": [8, 16]})"));
  EXPECT_EQ(v.lightSizeFraction, 0.0f);
  EXPECT_EQ(v.time, 0.0);
  EXPECT_EQ(v.light.type, LightType::Directional);
  EXPECT_EQ(v.width, 8);
  EXPECT_EQ(v.height, 16);
}

TEST_F(ViewFile, RejectsBadFilesNamingFileAndField) {
  struct Case {
    const char* text;
    const char* mentions;  // the field (or problem) the message must name
  };
  const std::vector<Case> cases = {
      {"{", "not valid JSON"},
      {"[1, 2]", "JSON object"},
      {R"({"light": "dir:0,-1,0", "resolution": [8, 8]})", "\"camera\""},
      {R"({"camera": "0,2,8:0,0,0", "resolution": [8, 8]})", "\"light\""},
      {R"({"camera": "0,2,8:0,0,0", "light": "dir:0,-1,0"})", "\"resolution\""},
      {R"({"camera": 5, "light": "dir:0,-1,0", "resolution": [8, 8]})", "\"camera\""},
      {R"({"camera": "0,2,8:0,2,8", "light": "dir:0,-1,0", "resolution": [8, 8]})", "\"camera\""},
      {R"({"camera": "0,2,8:0,0,0", "light": "sun:0,-1,0", "resolution": [8, 8]})", "\"light\""},
      {R"({"camera": "0,2,8:0,0,0", "light": "dir:0,-1,0", "resolution": [0, 8]})", "\"resolution\""},
      {R"({"camera": "0,2,8:0,0,0", "light": "dir:0,-1,0", "resolution": [8, 16385]})", "\"resolution\""},
      {R"({"camera": "0,2,8:0,0,0", "light": "dir:0,-1,0", "resolution": [8]})", "\"resolution\""},
      {R"({"camera": "0,2,8:0,0,0", "light": "dir:0,-1,0", "resolution": [8.5, 8]})", "\"resolution\""},
      {R"({"camera": "0,2,8:0,0,0", "light": "dir:0,-1,0", "resolution": "8x8"})", "\"resolution\""},
      {R"({"camera": "0,2,8:0,0,0", "light": "dir:0,-1,0", "light_size": 0.1, "resolution": [8, 8]})",
       "\"light_size\""},
      {R"({"camera": "0,2,8:0,0,0", "light": "disk:0,4,0:0,0,0", "light_size": -1, "resolution": [8, 8]})",
       "\"light_size\""},
      {R"({"camera": "0,2,8:0,0,0", "light": "disk:0,4,0:0,0,0", "light_size": "big", "resolution": [8, 8]})",
       "\"light_size\""},
      {R"({"camera": "0,2,8:0,0,0", "light": "dir:0,-1,0", "resolution": [8, 8], "lightsize": 1})", "\"lightsize\""},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string path = write("bad" + std::to_string(i) + ".json", cases[i].text);
    const std::string message = inputErrorOf([&] { readViewFile(path); });
    ASSERT_FALSE(message.empty()) << "accepted " << cases[i].text;
    EXPECT_NE(message.find("'" + path + "'"), std::string::npos) << message;
    EXPECT_NE(message.find(cases[i].mentions), std::string::npos) << message;
  }
}

TEST_F(ViewFile, MissingFileAndUnwritableFolder) {
  const std::string missing = (dir_ / "nope.json").string();
  const std::string message = inputErrorOf([&] { readViewFile(missing); });
  EXPECT_NE(message.find("'" + missing + "'"), std::string::npos) << message;
  EXPECT_NE(inputErrorOf([&] { readViewFile(dir_.string()); }).find("not a regular file"), std::string::npos);

  View view;
  view.light = parseLight("dir:0,-1,0");
  const std::string unwritable = (dir_ / "no_such_folder" / "v.json").string();
  EXPECT_NE(inputErrorOf([&] { writeViewFile(unwritable, view); }).find(unwritable), std::string::npos);
  view.width = 0;
  EXPECT_FALSE(inputErrorOf([&] { writeViewFile((dir_ / "w.json").string(), view); }).empty());
}
