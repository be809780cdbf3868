// Textured materials from glTF, OBJ and assimp's formats. Alpha-tested ones: the cut-out, its
// texture (embedded or beside the model) and texture coordinates are loaded; images that cannot be
// read are a clear error, never a silent solid mesh. Colour textures: loaded the same way, and where
// one cannot be read, a named warning (only colour is lost).
#include <gtest/gtest.h>

#include "core/cutouts.h"
#include "core/image_io.h"
#include "core/texture.h"
#include "gltf_writer.h"

namespace {

using namespace loader_test;

// A 2 x 2 PNG: alpha 255 on the diagonal, 0 off it.
Bytes checkerPng(const TempDir& dir, int width = 2, int height = 2) {
  std::vector<std::uint8_t> rgba(std::size_t(width) * height * 4, 128);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) rgba[(std::size_t(y) * width + x) * 4 + 3] = (x + y) % 2 == 0 ? 255 : 0;
  }
  penumbra::writePngRgba8(dir.file("made.png"), width, height, rgba);
  std::ifstream in(dir.file("made.png"), std::ios::binary);
  return Bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The triangle with texture coordinates and an alpha-tested material on image 0 at `imageUri`.
json cutoutDoc(Bytes& bin, const std::string& imageUri, const std::string& alphaMode = "MASK") {
  json doc = meshDoc(kTriangle, {}, bin);
  const int uv = addFloats(doc, bin, {0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1.0f}, "VEC2", 3);
  doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = uv;
  doc["materials"][0]["alphaMode"] = alphaMode;
  doc["materials"][0]["alphaCutoff"] = 0.3;
  doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  doc["textures"] = {{{"source", 0}}};
  doc["images"] = {{{"uri", imageUri}}};
  return doc;
}

TEST(CutoutLoading, MaskMaterialWithAnEmbeddedImage) {
  TempDir dir;
  Bytes bin;
  const json doc = cutoutDoc(bin, "data:image/png;base64," + base64(checkerPng(dir)));
  const Scene s = penumbra::loadScene(writeGltf(dir, doc, bin));
  ASSERT_EQ(s.meshes.size(), 1u);
  const penumbra::Mesh& m = s.meshes[0];
  ASSERT_TRUE(m.cutout.has_value());
  EXPECT_FLOAT_EQ(m.cutout->cutoff, 0.3f);
  EXPECT_FLOAT_EQ(m.cutout->factor, 1.0f);
  ASSERT_EQ(m.cutout->texture, 0);
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures[0].width, 2u);
  EXPECT_EQ(s.textures[0].rgba[3], 255);   // texel (0, 0)
  EXPECT_EQ(s.textures[0].rgba[7], 0);     // texel (1, 0)
  EXPECT_EQ(m.uvs, (std::vector<glm::vec2>{{0, 0}, {1, 0}, {0, 1}}));
}

TEST(CutoutLoading, BlendIsCutAtOneHalfAndTextureTransformIsBaked) {
  TempDir dir;
  writeFile(dir.file("leaf.png"), checkerPng(dir));
  Bytes bin;
  json doc = cutoutDoc(bin, "leaf.png", "BLEND");
  doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
      {"KHR_texture_transform", {{"offset", {0.5, 0.25}}, {"scale", {2.0, 4.0}}}}};
  const Scene s = penumbra::loadScene(writeGltf(dir, doc, bin));
  const penumbra::Mesh& m = s.meshes[0];
  ASSERT_TRUE(m.cutout.has_value());
  EXPECT_FLOAT_EQ(m.cutout->cutoff, 0.5f);
  EXPECT_EQ(m.uvs, (std::vector<glm::vec2>{{0.5f, 0.25f}, {2.5f, 0.25f}, {0.5f, 4.25f}}));
}

TEST(CutoutLoading, OpaqueWhereTheFactorAloneIsOverTheCutoff) {
  TempDir dir;
  Bytes bin;
  json doc = cutoutDoc(bin, "unused.png");
  doc["materials"][0]["pbrMetallicRoughness"].erase("baseColorTexture");
  const Scene s = penumbra::loadScene(writeGltf(dir, doc, bin));
  EXPECT_FALSE(s.meshes[0].cutout.has_value()) << "alpha 1 over a cutoff of 0.3 everywhere: an opaque mesh";
  EXPECT_TRUE(s.textures.empty()) << "no image decoded that no cut-out needs";
}

TEST(CutoutLoading, ImagesThatCannotBeReadAreErrors) {
  TempDir dir;
  Bytes bin;
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, cutoutDoc(bin, "missing.png"), bin, "a")); },
                   {"missing.png", "could not be read"});
  bin.clear();
  writeFile(dir.file("broken.png"), std::string("not a png at all"));
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, cutoutDoc(bin, "broken.png"), bin, "b")); },
                   {"broken.png", "cannot be decoded"});
  bin.clear();
  writeFile(dir.file("wide.png"), checkerPng(dir, int(penumbra::kMaxTextureSide) + 1, 1));
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, cutoutDoc(bin, "wide.png"), bin, "c")); },
                   {"wide.png", "16385x1"});
  bin.clear();
  expectInputError([&] { penumbra::loadScene(writeGltf(dir, cutoutDoc(bin, "../outside.png"), bin, "d")); },
                   {"outside.png", "outside the model's folder"});
}

// An OBJ quad whose material's map_d cuts it out; the map's alpha is the image's.
TEST(CutoutLoading, ObjAlphaMapCutsOutItsMaterial) {
  TempDir dir;
  writeFile(dir.file("net.png"), checkerPng(dir));
  writeFile(dir.file("m.mtl"), std::string("newmtl net\nKd 0.6 0.6 0.6\nd 0.9\nmap_d net.png\nnewmtl gone\nmap_d absent.png\n"));
  const std::string quad = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";
  writeFile(dir.file("a.obj"), quad + "usemtl net\nf 1/1 2/2 3/3 4/4\n");
  const Scene s = penumbra::loadScene(dir.file("a.obj"));
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_TRUE(s.meshes[0].cutout.has_value());
  EXPECT_FLOAT_EQ(s.meshes[0].cutout->factor, 0.9f);
  ASSERT_EQ(s.meshes[0].uvs.size(), 4u);
  EXPECT_EQ(s.meshes[0].uvs[0], glm::vec2(0.0f, 1.0f)) << "OBJ's v points up, the texture's rows down";
  writeFile(dir.file("b.obj"), quad + "usemtl gone\nf 1/1 2/2 3/3 4/4\n");
  expectInputError([&] { penumbra::loadScene(dir.file("b.obj")); }, {"absent.png", "could not be read"});
}

// An opaque glTF material's base colour texture is the mesh's colour texture, at its texCoord set;
// one that cannot be decoded is a named warning and the mesh keeps its base colour.
TEST(TextureLoading, GltfBaseColorTextureColoursAnOpaqueMesh) {
  TempDir dir;
  writeFile(dir.file("paint.png"), checkerPng(dir));
  Bytes bin;
  json doc = cutoutDoc(bin, "paint.png", "OPAQUE");
  const Scene s = penumbra::loadScene(writeGltf(dir, doc, bin, "a"));
  const penumbra::Mesh& m = s.meshes.at(0);
  EXPECT_FALSE(m.cutout.has_value());
  ASSERT_EQ(m.colorTexture, 0);
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(m.uvs, (std::vector<glm::vec2>{{0, 0}, {1, 0}, {0, 1}}));
  EXPECT_TRUE(s.warnings.empty());

  writeFile(dir.file("broken.png"), std::string("not a png at all"));
  bin.clear();
  const Scene broken = penumbra::loadScene(writeGltf(dir, cutoutDoc(bin, "broken.png", "OPAQUE"), bin, "b"));
  EXPECT_EQ(broken.meshes.at(0).colorTexture, -1);
  ASSERT_EQ(broken.warnings.size(), 1u);
  EXPECT_NE(broken.warnings[0].find("broken.png"), std::string::npos) << broken.warnings[0];
  EXPECT_NE(broken.warnings[0].find("only colour"), std::string::npos) << broken.warnings[0];

  // BLEND's alpha is a translucency: without its image the factor alone decides (with the warning).
  bin.clear();
  const Scene blend = penumbra::loadScene(writeGltf(dir, cutoutDoc(bin, "broken.png", "BLEND"), bin, "c"));
  EXPECT_FALSE(blend.meshes.at(0).cutout.has_value()) << "alpha factor 1: solid";
  EXPECT_EQ(blend.warnings.size(), 1u);
}

// OBJ's map_Kd: the colour texture, sharing the image with a map_d of the same name; a missing one
// warns, where a missing map_d is an error (ObjAlphaMapCutsOutItsMaterial).
TEST(TextureLoading, ObjDiffuseMapColoursItsMaterial) {
  TempDir dir;
  writeFile(dir.file("leaf.png"), checkerPng(dir));
  writeFile(dir.file("m.mtl"), std::string("newmtl leaf\nmap_Kd leaf.png\nmap_d leaf.png\n"
                                           "newmtl painted\nKd 0.5 0.5 0.5\nmap_Kd leaf.png\n"
                                           "newmtl lost\nKd 0.2 0.3 0.4\nmap_Kd absent.png\n"));
  const std::string quad = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";
  writeFile(dir.file("a.obj"), quad +
                                   "o a\nusemtl leaf\nf 1/1 2/2 3/3 4/4\no b\nusemtl painted\nf 1/4 2/3 3/2 4/1\n"
                                   "o c\nusemtl lost\nf 1/1 2/2 3/3 4/4\n");
  const Scene s = penumbra::loadScene(dir.file("a.obj"));
  ASSERT_EQ(s.meshes.size(), 3u);
  EXPECT_EQ(s.textures.size(), 1u) << "one image, decoded once";
  EXPECT_EQ(s.meshes[0].colorTexture, 0);
  ASSERT_TRUE(s.meshes[0].cutout.has_value());
  EXPECT_EQ(s.meshes[0].cutout->texture, 0);
  EXPECT_EQ(s.meshes[1].colorTexture, 0);
  EXPECT_FALSE(s.meshes[1].cutout.has_value());
  ASSERT_EQ(s.meshes[1].uvs.size(), 4u);
  EXPECT_EQ(s.meshes[1].uvs[0], glm::vec2(0.0f, 0.0f)) << "vt 4 (0, 1) with v flipped";
  EXPECT_EQ(s.meshes[2].colorTexture, -1);
  EXPECT_EQ(s.meshes[2].baseColor, glm::vec3(0.2f, 0.3f, 0.4f));
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("absent.png"), std::string::npos) << s.warnings[0];
  EXPECT_NE(s.warnings[0].find("only colour is lost"), std::string::npos) << s.warnings[0];
}

// assimp's formats: a PLY whose header names its texture (and gives per-vertex s, t).
TEST(TextureLoading, AssimpFormatsReadTheirTextures) {
  TempDir dir;
  writeFile(dir.file("paint.png"), checkerPng(dir));
  const std::string header =
      "ply\nformat ascii 1.0\ncomment TextureFile paint.png\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nproperty float s\nproperty float t\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  writeFile(dir.file("a.ply"), header + "0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n");
  const Scene s = penumbra::loadScene(dir.file("a.ply"));
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_EQ(s.meshes[0].colorTexture, 0);
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures[0].width, 2u);
  EXPECT_EQ(s.meshes[0].uvs, (std::vector<glm::vec2>{{0, 1}, {1, 1}, {0, 0}})) << "v flipped: row 0 is the top";

  writeFile(dir.file("b.ply"), std::string(header).replace(header.find("paint.png"), 9, "gone.png") +
                                   "0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n");
  const Scene lost = penumbra::loadScene(dir.file("b.ply"));
  EXPECT_EQ(lost.meshes.at(0).colorTexture, -1);
  ASSERT_FALSE(lost.warnings.empty());
  EXPECT_NE(lost.warnings[0].find("gone.png"), std::string::npos) << lost.warnings[0];
}

// The alpha ranges the thin-triangle pass reads (shared/alpha.h): every cell of every level holds
// the least and greatest alpha of the texels it covers, on a texture of odd sides.
TEST(CutoutData, AlphaRangesBoundTheirTexels) {
  penumbra::Scene scene;
  penumbra::Texture& t = scene.textures.emplace_back();
  t.width = 13, t.height = 6;
  for (std::uint32_t i = 0; i < t.width * t.height; ++i) t.rgba.insert(t.rgba.end(), {0, 0, 0, std::uint8_t(i * 37 % 251)});
  penumbra::Mesh& mesh = scene.meshes.emplace_back();
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.uvs = {{0, 0}, {1, 0}, {0, 1}};
  mesh.indices = {0, 1, 2};
  mesh.cutout = penumbra::Cutout{.texture = 0};
  const penumbra::CutoutData data = penumbra::cutoutData(scene);
  ASSERT_EQ(data.triangles.size(), 1u);
  const auto alpha = [&](std::uint32_t x, std::uint32_t y) {
    const std::uint32_t texel = data.firstTexel[0] + y * t.width + x;
    return penumbra::shared::cutoutAlpha(data.texels.at(texel / 4), texel);
  };
  for (std::uint32_t y = 0; y < t.height; ++y) {
    for (std::uint32_t x = 0; x < t.width; ++x) ASSERT_EQ(alpha(x, y), t.rgba[(y * t.width + x) * 4 + 3]);
  }
  std::uint32_t at = data.triangles[0].ranges, level = 1;
  ASSERT_EQ(at, data.firstRange[0]);
  for (;; ++level) {
    const std::uint32_t w = penumbra::shared::cutoutLevelSize(t.width, level), h = penumbra::shared::cutoutLevelSize(t.height, level);
    for (std::uint32_t cy = 0; cy < h; ++cy) {
      for (std::uint32_t cx = 0; cx < w; ++cx, ++at) {
        glm::uvec2 want(255, 0);
        for (std::uint32_t y = cy << level; y < std::min(t.height, (cy + 1) << level); ++y) {
          for (std::uint32_t x = cx << level; x < std::min(t.width, (cx + 1) << level); ++x) {
            want = glm::uvec2(std::min(want.x, alpha(x, y)), std::max(want.y, alpha(x, y)));
          }
        }
        ASSERT_EQ(penumbra::shared::cutoutRange(data.texels.at(at / 2), at), want) << "level " << level << " cell " << cx << "," << cy;
      }
    }
    if (w == 1 && h == 1) break;
  }
  EXPECT_EQ(level, 4u);  // 13 -> 7 -> 4 -> 2 -> 1
  EXPECT_LE(at, 2 * data.texels.size());
  // the memory estimate's count of the same
  const std::uint64_t built = data.texels.size() * 4 + data.triangles.size() * sizeof(data.triangles[0]);
  EXPECT_GE(penumbra::cutoutDataBytes(scene), built);
  EXPECT_LE(penumbra::cutoutDataBytes(scene), built + 8);
}

}  // namespace
