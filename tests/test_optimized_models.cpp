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

// Runs `tool` (gltfpack, draco_transcoder) with `options`; fails the test (with the fix) when it
// is missing or fails.
bool run(const std::string& tool, const std::string& options) {
  const int rc = std::system((tool + " " + options + " >/dev/null 2>&1").c_str());
  if (rc != 0) ADD_FAILURE() << tool << " " << options << " failed (" << rc << "); install it with scripts/setup.sh";
  return rc == 0;
}
bool gltfpack(const std::string& options) { return run("gltfpack", options); }

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

// gltfpack's simplifier (-si 0.5: half the triangles) changes the geometry, so its shadows are
// compared with its own reference: srt and frt on the simplified model are as exact as on any.
TEST(OptimizedModels, GltfpackSimplifiedModelRenders) {
  Folder dir;
  const std::string obj = courtyardObj(dir);
  ASSERT_TRUE(gltfpack("-i " + obj + " -o " + dir.file("simplified.glb") + " -si 0.5"));
  const Scene simplified = loadScene(dir.file("simplified.glb"));
  const std::size_t original = loadCourtyard().triangleCount();
  EXPECT_GT(simplified.triangleCount(), original / 4);
  EXPECT_LT(simplified.triangleCount(), original * 3 / 5);
  const Scene& courtyard = loadCourtyard();
  Renderer renderer(validatedContext(), simplified, smallSettings(128, 1024));
  const Frame reference = renderer.render("ref", *courtyard.camera, courtyard.lights.front());
  for (const char* method : {"srt", "frt"}) {
    EXPECT_LE(differingPixels(reference, renderer.render(method, *courtyard.camera, courtyard.lights.front())), 0.001)
        << method;
  }
  expectValidationSilent();
}

// Draco as users make it: the float GLB passed through the draco library's own transcoder, to a
// .glb and to a .gltf with its .bin (the decoded bytes then go to a new first buffer), at
// gltfpack's default precision (14-bit positions: the bound above). At the transcoder's own
// default (11-bit positions, 0.012 units here, and 8-bit normals) 0.6% of the pixels differ: a
// loss of that precision, not of the loader, so it is not tested against this bound.
TEST(OptimizedModels, DracoTranscoderOutputRendersAsTheOriginal) {
  Folder dir;
  const std::string obj = courtyardObj(dir);
  ASSERT_TRUE(gltfpack("-i " + obj + " -o " + dir.file("float.glb") + " -noq"));
  ASSERT_TRUE(run("draco_transcoder", "-i " + dir.file("float.glb") + " -o " + dir.file("draco.glb") + " -qp 14 -qn 10"));
  ASSERT_TRUE(run("draco_transcoder", "-i " + dir.file("float.glb") + " -o " + dir.file("draco.gltf") + " -qp 14 -qn 10"));

  const std::vector<Frame> original = renderCourtyardView(obj);
  for (const char* variant : {"draco.glb", "draco.gltf"}) {
    const Scene scene = loadScene(dir.file(variant));
    EXPECT_EQ(scene.triangleCount(), loadCourtyard().triangleCount()) << variant;
    EXPECT_TRUE(std::any_of(scene.warnings.begin(), scene.warnings.end(), [](const std::string& w) {
      return w.find("KHR_draco_mesh_compression: ") != std::string::npos && w.find(" decoded") != std::string::npos;
    })) << variant;
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

// Writes `g` as `path` and expects loading it to fail with a message containing every one of `needles`.
void expectRefused(const Glb& g, const std::string& path, const std::vector<std::string>& needles) {
  g.write(path);
  try {
    loadScene(path);
    ADD_FAILURE() << path << " loaded";
  } catch (const InputError& e) {
    for (const std::string& n : needles) EXPECT_NE(std::string(e.what()).find(n), std::string::npos) << e.what();
  }
}

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
  const std::string view = "bufferView " + std::to_string(compressed);
  Glb cut = original;
  ext(cut, compressed)["byteLength"] = 8;
  expectRefused(cut, dir.file("cut.glb"), {"does not decode", view});
  Glb overwritten = original;
  const std::size_t at = ext(overwritten, compressed).value("byteOffset", std::size_t(0));
  std::memset(overwritten.bin.data() + at, 0xff, std::min<std::size_t>(64, overwritten.bin.size() - at));
  expectRefused(overwritten, dir.file("overwritten.glb"), {"does not decode", view});
  Glb past = original;
  ext(past, compressed)["byteLength"] = past.bin.size() + 1;
  expectRefused(past, dir.file("past.glb"), {"outside its buffer", view});
}

// The same for Draco: a stream cut short or overwritten, accessors whose counts disagree with the
// stream, an attribute id the stream lacks, a view past its buffer - each refused, naming the primitive.
TEST(OptimizedModels, CorruptDracoStreamsAreRefused) {
  Folder dir;
  const std::string obj = courtyardObj(dir);
  ASSERT_TRUE(gltfpack("-i " + obj + " -o " + dir.file("float.glb") + " -noq"));
  ASSERT_TRUE(run("draco_transcoder", "-i " + dir.file("float.glb") + " -o " + dir.file("draco.glb")));
  const Glb original(dir.file("draco.glb"));
  const nlohmann::json& primitive = original.json["meshes"][0]["primitives"][0];
  const std::size_t view = primitive["extensions"]["KHR_draco_mesh_compression"]["bufferView"];
  const std::size_t positions = primitive["attributes"]["POSITION"], indices = primitive["indices"];
  const std::string where = "mesh 0 primitive 0 (KHR_draco_mesh_compression)";

  Glb cut = original;
  cut.json["bufferViews"][view]["byteLength"] = 8;
  expectRefused(cut, dir.file("cut.glb"), {where, "does not decode"});
  Glb overwritten = original;
  const std::size_t at = overwritten.json["bufferViews"][view].value("byteOffset", std::size_t(0));
  std::memset(overwritten.bin.data() + at, 0xff, 32);
  expectRefused(overwritten, dir.file("overwritten.glb"), {where, "does not decode"});
  Glb morePoints = original;
  morePoints.json["accessors"][positions]["count"] = morePoints.json["accessors"][positions]["count"].get<int>() + 1;
  expectRefused(morePoints, dir.file("points.glb"), {where, "POSITION accessor claims"});
  Glb fewerIndices = original;
  fewerIndices.json["accessors"][indices]["count"] = fewerIndices.json["accessors"][indices]["count"].get<int>() - 3;
  expectRefused(fewerIndices, dir.file("indices.glb"), {where, "indices accessor claims"});
  Glb noAttribute = original;
  noAttribute.json["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]["POSITION"] = 99;
  expectRefused(noAttribute, dir.file("attribute.glb"), {where, "has no attribute 99"});
  Glb past = original;
  past.json["bufferViews"][view]["byteLength"] = past.bin.size() + 1;
  expectRefused(past, dir.file("past.glb"), {where, "outside its buffer"});
}

}  // namespace
}  // namespace penumbra::test
