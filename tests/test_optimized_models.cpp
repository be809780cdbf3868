// Models as optimizers write them (issue 22): the courtyard written as an OBJ, passed through
// Debian's gltfpack (installed by scripts/setup.sh) in its modes, loaded and rendered beside the
// original. Quantized positions move by at most half a quantization step (gltfpack's default 14
// bits: 1/32768 of the model's extent, 0.001 units here, against 0.2 units per pixel at 128^2), so
// shadow edges move by far less than a pixel: at most 0.2% of the covered pixels may differ.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <iostream>
#include <filesystem>
#include <string>

#include "mesh_checks.h"
#include "render_fixture.h"

namespace penumbra::test {
namespace {

namespace fs = std::filesystem;

struct Folder {
  fs::path path = fs::temp_directory_path() / ("penumbra_gltfpack_" + std::to_string(::getpid()));
  Folder() { fs::create_directories(path); }
  ~Folder() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string file(const std::string& name) const { return (path / name).string(); }
};

// Runs gltfpack with `options`; fails the test (with the fix) when it is missing or fails.
bool gltfpack(const std::string& options) {
  const int rc = std::system(("gltfpack " + options + " >/dev/null 2>&1").c_str());
  if (rc != 0) ADD_FAILURE() << "gltfpack " << options << " failed (" << rc << "); install it with scripts/setup.sh";
  return rc == 0;
}

// Fraction of covered pixels whose visibility differs by more than 0.5.
double differing(const Frame& a, const Frame& b) {
  std::size_t covered = 0, differ = 0;
  for (std::size_t i = 0; i < a.visibility.size(); ++i) {
    if (!a.covered[i]) continue;
    ++covered;
    differ += std::abs(a.visibility[i] - b.visibility[i]) > 0.5f;
  }
  return covered ? double(differ) / double(covered) : 1.0;
}

TEST(OptimizedModels, GltfpackOutputRendersAsTheOriginal) {
  Folder dir;
  const Scene courtyard = loadScene("builtin:courtyard");
  writeObj(courtyard.meshes, dir.file("courtyard.obj"));
  ASSERT_TRUE(gltfpack("-i " + dir.file("courtyard.obj") + " -o " + dir.file("quantized.glb")));
  ASSERT_TRUE(gltfpack("-i " + dir.file("courtyard.obj") + " -o " + dir.file("float.glb") + " -noq"));
  ASSERT_TRUE(gltfpack("-i " + dir.file("courtyard.obj") + " -o " + dir.file("meshopt.glb") + " -cc"));

  const Camera camera = *courtyard.camera;
  const Light light = courtyard.lights.front();
  auto render = [&](const std::string& path) {
    const Scene scene = loadScene(path);
    EXPECT_EQ(scene.origin, glm::dvec3(0.0)) << path;
    Renderer renderer(validatedContext(), scene, smallSettings(128, 1024));
    std::vector<Frame> frames;
    for (const char* method : {"sm", "srt", "frt"}) frames.push_back(renderer.render(method, camera, light));
    return frames;
  };
  const std::vector<Frame> original = render(dir.file("courtyard.obj"));
  for (const char* variant : {"quantized.glb", "float.glb"}) {
    const std::vector<Frame> frames = render(dir.file(variant));
    for (std::size_t m = 0; m < frames.size(); ++m) {
      const double d = differing(original[m], frames[m]);
      std::cout << "[ " << variant << " " << frames[m].stats.method << " ] " << 100.0 * d << "% of covered pixels differ\n";
      EXPECT_LE(d, 0.002) << variant << " " << frames[m].stats.method;
    }
  }
  // Meshopt-compressed buffers are named, not reported as a truncated file.
  try {
    loadScene(dir.file("meshopt.glb"));
    ADD_FAILURE() << "meshopt.glb loaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("EXT_meshopt_compression"), std::string::npos) << e.what();
  }
  expectValidationSilent();
}

}  // namespace
}  // namespace penumbra::test
