// Scene loader tests for bad input and the other loaders: malformed and truncated files, lying
// lengths, references outside the model's folder, cycles; OBJ; assimp's confinement; the
// scene-spec dispatch. Every
// model is written by the test into a fresh temporary folder (gltf_writer.h). What valid glTF
// files hold: test_gltf_content.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "gltf_writer.h"

using namespace loader_test;

TEST(GltfLoader, EmptyUriSaysSo) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["buffers"][0]["uri"] = "";
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "empty")); }, {"empty.gltf", "uri is empty"});
}

TEST(GltfLoader, MalformedOrTruncatedJsonNamesFile) {
  TempDir dir;
  writeFile(dir.file("bad.gltf"), std::string("{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [,]}"));
  expectInputError([&] { penumbra::loadScene(dir.file("bad.gltf")); }, {"bad.gltf", "JSON"});
  Bytes bin;
  const std::string text = meshDoc(kTriangle, {0, 1, 2}, bin).dump();
  writeFile(dir.file("cut.gltf"), text.substr(0, text.size() / 2));
  expectInputError([&] { penumbra::loadGltf(dir.file("cut.gltf")); }, {"cut.gltf"});
}

TEST(GltfLoader, BufferFileShortOrMissing) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["buffers"][0]["uri"] = "short.bin";
  writeFile(dir.file("short.bin"), Bytes(bin.begin(), bin.end() - 8));
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin)); }, {"model.gltf", "short.bin"});
  doc["buffers"][0]["uri"] = "absent.bin";
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin)); }, {"model.gltf", "absent.bin"});
}

TEST(GltfLoader, GlbTotalLengthLies) {
  TempDir dir;
  Bytes bin;
  const std::string text = meshDoc(kTriangle, {0, 1, 2}, bin).dump();  // fills bin first
  const Bytes good = makeGlb(text, bin);
  for (const std::int64_t delta : {64, -4}) {
    Bytes glb = good;
    const std::uint32_t lie = std::uint32_t(std::int64_t(glb.size()) + delta);
    std::memcpy(glb.data() + 8, &lie, 4);
    writeFile(dir.file("lie.glb"), glb);
    expectInputError([&] { penumbra::loadScene(dir.file("lie.glb")); }, {"lie.glb", "header length"});
  }
}

TEST(GltfLoader, GlbChunkLengthsExceedFile) {
  TempDir dir;
  Bytes bin;
  const std::string text = meshDoc(kTriangle, {0, 1, 2}, bin).dump();  // fills bin first
  const Bytes good = makeGlb(text, bin);
  Bytes glb = good;
  const std::uint32_t jsonLie = std::uint32_t(glb.size());
  std::memcpy(glb.data() + 12, &jsonLie, 4);
  writeFile(dir.file("json.glb"), glb);
  expectInputError([&] { penumbra::loadGltf(dir.file("json.glb")); }, {"json.glb", "chunk 0 (JSON) length"});

  glb = good;
  std::uint32_t jsonLength;
  std::memcpy(&jsonLength, glb.data() + 12, 4);
  const std::uint32_t binLie = 1u << 30;
  std::memcpy(glb.data() + 20 + jsonLength, &binLie, 4);
  writeFile(dir.file("bin.glb"), glb);
  expectInputError([&] { penumbra::loadGltf(dir.file("bin.glb")); }, {"bin.glb", "chunk 1 (BIN) length"});

  glb = good;
  glb[4] = 1;  // version 1
  writeFile(dir.file("v1.glb"), glb);
  expectInputError([&] { penumbra::loadGltf(dir.file("v1.glb")); }, {"v1.glb", "version 1"});
  writeFile(dir.file("text.glb"), std::string("{\"asset\": {\"version\": \"2.0\"}}"));
  expectInputError([&] { penumbra::loadGltf(dir.file("text.glb")); }, {"text.glb", "magic"});

  writeFile(dir.file("tiny.glb"), Bytes(good.begin(), good.begin() + 7));
  expectInputError([&] { penumbra::loadGltf(dir.file("tiny.glb")); }, {"tiny.glb", "12-byte"});
}

TEST(GltfLoader, AccessorOutOfBounds) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["accessors"][0]["count"] = 1000;
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "a")); }, {"a.gltf", "POSITION accessor 0"});

  doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["bufferViews"][1]["byteLength"] = 4096;  // view larger than the buffer
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "b")); }, {"b.gltf", "bufferView 1"});

  doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["accessors"][0]["componentType"] = 5125;  // POSITION: float or 8/16-bit integers, never 32-bit ones
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "c")); },
                   {"c.gltf", "float or 8/16-bit integers"});

  doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["meshes"][0]["primitives"][0]["indices"] = 7;
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "d")); }, {"d.gltf", "accessor"});
}

TEST(GltfLoader, NanAndDegenerateTrianglesAreCleanedOrRefused) {
  TempDir dir;
  Bytes bin;
  const float nan = std::nanf("");
  const json doc = meshDoc({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {nan, 0, 0}, {2, 0, 0}}, {0, 1, 2, 0, 3, 1, 0, 1, 4}, bin);
  const Scene s = penumbra::loadScene(writeGltf(dir, doc, bin));
  EXPECT_EQ(s.triangleCount(), 1u);
  EXPECT_TRUE(anyWarningContains(s, "non-finite"));
  EXPECT_TRUE(anyWarningContains(s, "degenerate"));
  const json flat = meshDoc({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {0, 1, 2}, bin);  // nothing drawable left
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, flat, bin, "flat")); }, {"flat.gltf", "no drawable"});
  const std::vector<std::uint16_t> many(3000, 0);  // 1,000 triangles, every vertex in one point
  const json point = meshDoc({{5, 5, 5}}, many, bin);
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, point, bin, "point")); }, {"point.gltf", "no drawable"});
}

TEST(GltfLoader, BufferUriOutsideFolderRefused) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  writeFile(dir.file("secret.bin"), bin);  // a real file: only the confinement rule can stop it
  doc["buffers"][0]["uri"] = "../secret.bin";
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "sub/m")); },
                   {"m.gltf", "buffer URI '../secret.bin'", "outside the model's folder"});
  doc["buffers"][0]["uri"] = dir.file("secret.bin");
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "sub/m")); },
                   {"m.gltf", dir.file("secret.bin"), "absolute"});
  // Percent-encoding hides the climb from a raw check; the file-system callbacks still refuse it.
  doc["buffers"][0]["uri"] = "%2E%2E/secret.bin";
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "sub/m")); },
                   {"m.gltf", "'../secret.bin'", "outside the model's folder"});
  // A link inside the folder that leads out is refused too.
  fs::create_symlink(dir.path / "secret.bin", dir.path / "sub" / "link.bin");
  doc["buffers"][0]["uri"] = "link.bin";
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "sub/m")); },
                   {"m.gltf", "buffer URI 'link.bin'", "through a link"});
  fs::copy_file(dir.path / "secret.bin", dir.path / "sub" / "copy.bin");
  doc["buffers"][0]["uri"] = "./copy.bin";  // inside: fine
  EXPECT_EQ(penumbra::loadScene(writeGltf(dir, doc, bin, "sub/m")).triangleCount(), 1u);
}

TEST(GltfLoader, ImageUriOutsideFolderRefusedInsideAccepted) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin);
  writeFile(dir.file("secret.png"), std::string("not really a png"));
  writeFile(dir.file("sub/tex.png"), std::string("not really a png either"));
  doc["images"] = {{{"uri", "tex.png"}}};  // inside: loads, and is never decoded
  EXPECT_EQ(penumbra::loadScene(writeGltf(dir, doc, bin, "sub/m")).triangleCount(), 1u);
  doc["images"] = {{{"uri", "../secret.png"}}};
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "sub/m")); },
                   {"m.gltf", "image URI '../secret.png'", "outside the model's folder"});
  doc["images"] = {{{"uri", "%2e%2e/secret.png"}}};
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "sub/m")); },
                   {"m.gltf", "'../secret.png'", "outside the model's folder"});
}

TEST(GltfLoader, NodeCycleRefused) {
  TempDir dir;
  Bytes bin;
  json doc = meshDoc(kTriangle, {0, 1, 2}, bin);
  doc["nodes"] = {{{"mesh", 0}, {"children", {1}}}, {{"children", {0}}}};
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, doc, bin, "loop")); }, {"loop.gltf", "ancestor"});
}

namespace {
const char* kCubeObj =
    "mtllib cube.mtl\no cube\n"
    "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
    "usemtl red\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nf 1 5 8 4\n";
}  // namespace

TEST(ObjLoader, CubeWithMaterial) {
  TempDir dir;
  writeFile(dir.file("cube.obj"), std::string(kCubeObj));
  writeFile(dir.file("cube.mtl"), std::string("newmtl red\nKd 0.9 0.1 0.2\n"));
  const Scene s = penumbra::loadScene(dir.file("cube.obj"));
  EXPECT_EQ(s.name, "cube");
  EXPECT_EQ(s.triangleCount(), 12u);
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.meshes[0].positions.size(), 8u);
  EXPECT_TRUE(near(s.meshes[0].baseColor, {0.9f, 0.1f, 0.2f}));
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
}

TEST(ObjLoader, MissingMtlIsAWarning) {
  TempDir dir;
  writeFile(dir.file("cube.obj"), std::string(kCubeObj));
  const Scene s = penumbra::loadScene(dir.file("cube.obj"));
  EXPECT_EQ(s.triangleCount(), 12u);
  EXPECT_TRUE(anyWarningContains(s, "cube.mtl"));
  EXPECT_TRUE(near(s.meshes[0].baseColor, glm::vec3(0.8f)));
}

TEST(ObjLoader, MtllibOutsideFolderIgnored) {
  TempDir dir;
  std::string obj = kCubeObj;
  obj.replace(0, obj.find('\n'), "mtllib ../evil.mtl");
  writeFile(dir.file("sub/cube.obj"), obj);
  writeFile(dir.file("evil.mtl"), std::string("newmtl red\nKd 0 1 0\n"));
  const Scene s = penumbra::loadScene(dir.file("sub/cube.obj"));
  EXPECT_EQ(s.triangleCount(), 12u);
  EXPECT_TRUE(anyWarningContains(s, "'../evil.mtl' outside"));
  EXPECT_TRUE(near(s.meshes[0].baseColor, glm::vec3(0.8f)));
}

TEST(ObjLoader, NormalsKept) {
  TempDir dir;
  writeFile(dir.file("tri.obj"), std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n"));
  const Scene s = penumbra::loadScene(dir.file("tri.obj"));
  ASSERT_EQ(s.triangleCount(), 1u);
  ASSERT_EQ(s.meshes[0].normals.size(), 3u);
  EXPECT_TRUE(near(s.meshes[0].normals[2], {0, 0, 1}));
}

// Georeferenced OBJ coordinates are read in double and stored relative to Scene::origin: a
// millimetre triangle 5e6 units out keeps its shape (float steps there are half a unit).
TEST(ObjLoader, GeoreferencedCoordinatesKeepTheirDetail) {
  TempDir dir;
  writeFile(dir.file("far.obj"), std::string("v 5000000.123 20.5 -4000000.456\nv 5000000.124 20.5 -4000000.456\n"
                                             "v 5000000.123 20.501 -4000000.456\nf 1 2 3\n"));
  const Scene s = penumbra::loadScene(dir.file("far.obj"));
  ASSERT_EQ(s.triangleCount(), 1u);
  const glm::dvec3 want[3] = {
      {5000000.123, 20.5, -4000000.456}, {5000000.124, 20.5, -4000000.456}, {5000000.123, 20.501, -4000000.456}};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_LT(glm::length(s.origin + glm::dvec3(s.meshes[0].positions[i]) - want[i]), 1e-7) << i;
  }
}

TEST(ObjLoader, BadIndicesRefused) {
  TempDir dir;
  writeFile(dir.file("range.obj"), std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"));
  expectInputError([&] { penumbra::loadScene(dir.file("range.obj")); }, {"range.obj", "out of"});
  writeFile(dir.file("quad.obj"), std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 -9\n"));
  expectInputError([&] { penumbra::loadScene(dir.file("quad.obj")); }, {"quad.obj"});
  writeFile(dir.file("zero.obj"), std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"));
  expectInputError([&] { penumbra::loadScene(dir.file("zero.obj")); }, {"zero.obj", "zero value"});
  writeFile(dir.file("vn.obj"), std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//5\n"));
  expectInputError([&] { penumbra::loadScene(dir.file("vn.obj")); }, {"vn.obj"});
}

// Assimp importers open the files a model names (an Ogre mesh its skeleton, by a name taken from
// inside the file) through the loader's file system: a name beside the model is read relative to
// the model's folder whatever the working directory (a corrupt skeleton there is reported); names
// that climb out or are absolute elsewhere are refused by name before assimp reads them.
TEST(AssimpLoader, NamedFilesConfinedToTheModelsFolder) {
  TempDir dir;
  const auto mesh = [&](const std::string& skeleton) {
    writeFile(dir.file("model/model.mesh.xml"),
              "<mesh><sharedgeometry vertexcount=\"3\"><vertexbuffer positions=\"true\">"
              "<vertex><position x=\"0\" y=\"0\" z=\"0\"/></vertex><vertex><position x=\"1\" y=\"0\" z=\"0\"/></vertex>"
              "<vertex><position x=\"0\" y=\"1\" z=\"0\"/></vertex></vertexbuffer></sharedgeometry><submeshes>"
              "<submesh material=\"m\" usesharedvertices=\"true\" operationtype=\"triangle_list\">"
              "<faces count=\"1\"><face v1=\"0\" v2=\"1\" v3=\"2\"/></faces></submesh></submeshes>"
              "<skeletonlink name=\"" + skeleton + "\"/></mesh>");
    return dir.file("model/model.mesh.xml");
  };
  writeFile(dir.file("model/bones.skeleton"), std::string("not a skeleton"));  // read: a clear error
  writeFile(dir.file("outside.skeleton"), std::string("not a skeleton"));
  const fs::path cwd = fs::current_path();
  fs::current_path(fs::temp_directory_path());
  expectInputError([&] { penumbra::loadScene(mesh("bones.skeleton")); }, {"model.mesh.xml", "Skeleton file header"});
  EXPECT_EQ(penumbra::loadScene(mesh("missing.skeleton")).triangleCount(), 1u);  // assimp goes on without it
  expectInputError([&] { penumbra::loadScene(mesh("../outside.skeleton")); },
                   {"model.mesh.xml", "refuses to read '../outside.skeleton", "outside the model's folder"});
  expectInputError([&] { penumbra::loadScene(mesh(dir.file("outside.skeleton"))); },
                   {"model.mesh.xml", "refuses to read '" + dir.file("outside.skeleton"), "outside the model's folder"});
  fs::current_path(cwd);
}

TEST(SceneLoader, MissingFileAndUnknownExtension) {
  TempDir dir;
  expectInputError([&] { penumbra::loadScene(dir.file("nope.gltf")); },
                   {"scene file '" + dir.file("nope.gltf") + "' not found"});
  expectInputError([&] { penumbra::loadScene(dir.file("nope.obj")); }, {"nope.obj", "not found"});
  writeFile(dir.file("model.xyzzy"), std::string("x"));
  expectInputError([&] { penumbra::loadScene(dir.file("model.xyzzy")); },
                   {"model.xyzzy", ".xyzzy", "builtin:", ".gltf", ".obj", "assimp"});
  writeFile(dir.file("model.fbx"), std::string("x"));  // a format assimp reads, but not this file
  expectInputError([&] { penumbra::loadScene(dir.file("model.fbx")); }, {"model.fbx", "could not be read by assimp"});
  expectInputError([&] { penumbra::loadScene("courtyard"); }, {"'courtyard'", "builtin:"});
}

TEST(SceneLoader, BuiltinDispatch) {
  const Scene s = penumbra::loadScene("builtin:square");
  EXPECT_GT(s.triangleCount(), 0u);
  EXPECT_FALSE(s.name.empty());
}
