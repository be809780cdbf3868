// Models as optimizers write them (issue 22): the courtyard written as an OBJ, passed through
// Debian's gltfpack (installed by scripts/setup.sh) in its modes - quantized (its default),
// float (-noq), meshopt-compressed (-c, -cc) - loaded and rendered beside the original. Quantized
// positions move by at most half a quantization step (gltfpack's default 14 bits: 1/32768 of the
// model's extent, 0.001 units here, against 0.2 units per pixel at 128^2), so shadow edges move by
// far less than a pixel: at most 0.2% of the covered pixels may differ.
#include <assimp/scene.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <nlohmann/json.hpp>
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

const Scene& loadCourtyard() {
  static const Scene courtyard = loadScene("builtin:courtyard");
  return courtyard;
}

// The courtyard as an OBJ in `dir`, the original every variant is compared with; its path.
std::string courtyardObj(const Folder& dir) {
  writeObj(loadCourtyard().meshes, dir.file("courtyard.obj"));
  return dir.file("courtyard.obj");
}

// sm, srt and frt of the model at `path`, in the courtyard's view at 128^2.
std::vector<Frame> renderCourtyardView(const std::string& path) {
  const Scene& courtyard = loadCourtyard();
  const Scene scene = loadScene(path);
  Renderer renderer(validatedContext(), scene, smallSettings(128, 1024));
  std::vector<Frame> frames;
  for (const char* method : {"sm", "srt", "frt"}) {
    frames.push_back(renderer.render(method, *courtyard.camera, courtyard.lights.front()));
  }
  return frames;
}

// Each of `frames` differs from the original's on at most 0.2% of the covered pixels (printed).
void expectLikeOriginal(const std::vector<Frame>& original, const std::vector<Frame>& frames, const std::string& name) {
  for (std::size_t m = 0; m < frames.size(); ++m) {
    const double d = differingPixels(original[m], frames[m]);
    std::cout << "[ " << name << " " << frames[m].stats.method << " ] " << 100.0 * d << "% of covered pixels differ\n";
    EXPECT_LE(d, 0.002) << name << " " << frames[m].stats.method;
  }
}

TEST(OptimizedModels, GltfpackOutputRendersAsTheOriginal) {
  Folder dir;
  const std::string obj = courtyardObj(dir);
  ASSERT_TRUE(gltfpack("-i " + obj + " -o " + dir.file("quantized.glb")));
  ASSERT_TRUE(gltfpack("-i " + obj + " -o " + dir.file("float.glb") + " -noq"));
  ASSERT_TRUE(gltfpack("-i " + obj + " -o " + dir.file("meshopt.glb") + " -c"));
  ASSERT_TRUE(gltfpack("-i " + obj + " -o " + dir.file("meshopt-cc.glb") + " -cc"));

  const std::vector<Frame> original = renderCourtyardView(obj);
  for (const char* variant : {"quantized.glb", "float.glb", "meshopt.glb", "meshopt-cc.glb"}) {
    EXPECT_EQ(loadScene(dir.file(variant)).origin, glm::dvec3(0.0)) << variant;
    expectLikeOriginal(original, renderCourtyardView(dir.file(variant)), variant);
  }
  expectValidationSilent();
}

// The other formats of the field through assimp: the courtyard exported by assimp's own exporters
// (binary PLY and STL, COLLADA, ASCII FBX: assimp 5.2 cannot read back its binary FBX, and its 3DS
// round trip turns the scene to 3DS's axes) renders as the OBJ it came from. STL keeps only face
// normals, so its shading normals differ where the original's are smooth; the bound is the same
// as for quantization.
TEST(OptimizedModels, OtherFormatsThroughAssimp) {
  Folder dir;
  const std::string obj = courtyardObj(dir);
  Assimp::Importer importer;
  const aiScene* source = importer.ReadFile(obj, 0);
  ASSERT_NE(source, nullptr) << importer.GetErrorString();
  const std::vector<Frame> original = renderCourtyardView(obj);
  Assimp::Exporter exporter;
  for (const auto& [format, name] : {std::pair{"plyb", "courtyard.ply"}, std::pair{"stlb", "courtyard.stl"},
                                     std::pair{"collada", "courtyard.dae"}, std::pair{"fbxa", "courtyard.fbx"}}) {
    ASSERT_EQ(exporter.Export(source, format, dir.file(name)), AI_SUCCESS)
        << format << ": " << exporter.GetErrorString();
    expectLikeOriginal(original, renderCourtyardView(dir.file(name)), name);
  }
  // A file cut short is refused by name, not loaded as a part of itself.
  std::filesystem::resize_file(dir.file("courtyard.ply"), 600);
  try {
    loadScene(dir.file("courtyard.ply"));
    ADD_FAILURE() << "a truncated PLY loaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("courtyard.ply"), std::string::npos) << e.what();
  }
  expectValidationSilent();
}

// The JSON and BIN chunks of a .glb and back.
struct Glb {
  nlohmann::json json;
  std::vector<unsigned char> bin;
  explicit Glb(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    const std::vector<unsigned char> b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::uint32_t jsonLength = 0, binLength = 0;
    std::memcpy(&jsonLength, b.data() + 12, 4);
    json = nlohmann::json::parse(b.begin() + 20, b.begin() + 20 + jsonLength);
    std::memcpy(&binLength, b.data() + 20 + jsonLength, 4);
    bin.assign(b.begin() + 28 + jsonLength, b.begin() + 28 + jsonLength + binLength);
  }
  void write(const std::string& path) const {
    std::string text = json.dump();
    while (text.size() % 4) text += ' ';
    std::ofstream out(path, std::ios::binary);
    const auto u32 = [&](std::size_t v) {
      const auto w = std::uint32_t(v);
      out.write(reinterpret_cast<const char*>(&w), 4);
    };
    u32(0x46546C67u), u32(2), u32(28 + text.size() + bin.size()), u32(text.size()), u32(0x4E4F534Au);
    out << text;
    u32(bin.size()), u32(0x004E4942u);
    out.write(reinterpret_cast<const char*>(bin.data()), std::streamsize(bin.size()));
  }
};

// A compressed stream cut short, one whose bytes are overwritten, and one that claims bytes past its
// buffer each get a clear error naming the view, never a crash or a silent wrong mesh.
TEST(OptimizedModels, CorruptMeshoptStreamsAreRefused) {
  Folder dir;
  const std::string obj = courtyardObj(dir);
  ASSERT_TRUE(gltfpack("-i " + obj + " -o " + dir.file("meshopt.glb") + " -c"));
  const Glb original(dir.file("meshopt.glb"));
  std::size_t compressed = 0;
  while (compressed < original.json["bufferViews"].size() &&
         !original.json["bufferViews"][compressed]["extensions"].contains("EXT_meshopt_compression")) {
    ++compressed;
  }
  ASSERT_LT(compressed, original.json["bufferViews"].size());
  auto ext = [](Glb& g, std::size_t v) -> nlohmann::json& {
    return g.json["bufferViews"][v]["extensions"]["EXT_meshopt_compression"];
  };
  auto expectRefused = [&](const Glb& g, const std::string& name, const std::string& needle) {
    g.write(dir.file(name));
    try {
      loadScene(dir.file(name));
      ADD_FAILURE() << name << " loaded";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bufferView " + std::to_string(compressed)), std::string::npos) << e.what();
    }
  };
  Glb cut = original;
  ext(cut, compressed)["byteLength"] = 8;
  expectRefused(cut, "cut.glb", "does not decode");
  Glb overwritten = original;
  const std::size_t at = ext(overwritten, compressed).value("byteOffset", std::size_t(0));
  std::memset(overwritten.bin.data() + at, 0xff, std::min<std::size_t>(64, overwritten.bin.size() - at));
  expectRefused(overwritten, "overwritten.glb", "does not decode");
  Glb past = original;
  ext(past, compressed)["byteLength"] = past.bin.size() + 1;
  expectRefused(past, "past.glb", "outside its buffer");
}

}  // namespace
}  // namespace penumbra::test
