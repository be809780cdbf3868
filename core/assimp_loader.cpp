// The other formats of the field (PLY scans, STL, OFF, COLLADA, FBX, 3DS, ...) through the Open
// Asset Import Library. The same rules as the glTF loader: the file is untrusted, only the model's
// own folder may be read (a confining IOSystem), node transforms are composed in double and the
// scene is stored relative to its origin (placeMeshes), lines and points are dropped with a note.
#include <assimp/DefaultIOSystem.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <filesystem>
#include <glm/gtc/matrix_inverse.hpp>
#include <map>
#include <memory>
#include <optional>
#include <utility>

#include "core/scene_loader.h"
#include "core/texture.h"

namespace penumbra {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem, const std::string& fix) {
  throw InputError("model '" + path + "': " + problem + "; " + fix);
}

// Opens files for assimp only inside the model's folder (the model itself included), read-only.
// Names an importer takes from inside the file (an Ogre mesh's skeleton, ...) are relative to the
// model's folder, as in glTF, not to the working directory.
class ConfinedIOSystem : public Assimp::DefaultIOSystem {
 public:
  explicit ConfinedIOSystem(std::string folder) : folder_(std::move(folder)) {}
  bool Exists(const char* file) const override {
    const std::string path = confined(file);
    return !path.empty() && DefaultIOSystem::Exists(path.c_str());
  }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    const std::string m = mode ? mode : "";
    const std::string path = m.find_first_of("wa+") == std::string::npos ? confined(file) : refuse(file);
    return path.empty() ? nullptr : DefaultIOSystem::Open(path.c_str(), mode);
  }
  mutable std::vector<std::string> refused;  // asked for, in Exists or Open

 private:
  // `file` resolved against the model's folder, or empty (and noted in `refused`) when it is outside.
  std::string confined(const char* file) const {
    if (!file) return refuse(file);
    const fs::path path = (folder_ / fs::path(file)).lexically_normal();
    const fs::path relative = path.lexically_relative(folder_);
    if (relative.empty() || !confinedPathProblem(folder_.string(), relative.string()).empty()) return refuse(file);
    return path.string();
  }
  std::string refuse(const char* file) const {
    refused.emplace_back(file ? file : "");
    return {};
  }
  fs::path folder_;
};

glm::dmat4 toGlm(const aiMatrix4x4& a) {
  glm::dmat4 m;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) m[c][r] = a[r][c];
  }
  return m;
}

// A material's images as Scene textures, each decoded once: the base colour (aiTextureType_BASE_COLOR,
// else _DIFFUSE) and the opacity map (_OPACITY, a cut-out by OBJ map_d's rule), embedded ("*N") or
// files in the model's folder, with the texture coordinate set each reads.
struct MaterialImages {
  const aiScene& ai;
  const std::string& path;
  const std::string folder;
  Scene& scene;
  std::map<std::string, std::int32_t> loaded;
  std::uint64_t bytes = 0;

  struct Image {
    std::int32_t texture = -1;
    unsigned uvSet = 0;
  };

  // InputError where the image cannot be had; nullopt where the material has none (or maps it
  // other than by texture coordinates, with a warning).
  std::optional<Image> find(const aiMaterial& material, std::initializer_list<aiTextureType> types) {
    for (const aiTextureType type : types) {
      aiString name;
      aiTextureMapping mapping = aiTextureMapping_UV;
      unsigned uvSet = 0;
      if (material.GetTextureCount(type) == 0 || material.GetTexture(type, 0, &name, &mapping, &uvSet) != AI_SUCCESS)
        continue;
      if (mapping != aiTextureMapping_UV) {
        scene.warnings.push_back("material '" + std::string(material.GetName().C_Str()) + "' projects its image '" +
                                 name.C_Str() + "' (not by texture coordinates); ignored");
        return std::nullopt;
      }
      return Image{texture(name.C_Str()), uvSet};
    }
    return std::nullopt;
  }

  std::int32_t texture(const std::string& name) {
    if (const auto known = loaded.find(name); known != loaded.end()) return known->second;
    Texture t = decode(name);
    if (bytes + t.rgba.size() > kMaxTextureBytes) {
      fail(path, "its images decode to over " + std::to_string(kMaxTextureBytes >> 30) + " GiB", "downscale them");
    }
    bytes += t.rgba.size();
    scene.textures.push_back(std::move(t));
    return loaded[name] = std::int32_t(scene.textures.size() - 1);
  }

  Texture decode(const std::string& name) {
    const aiTexture* embedded = ai.GetEmbeddedTexture(name.c_str());
    if (!embedded) return readTexture(folder, name, path);
    if (embedded->mHeight == 0) {  // compressed: mWidth bytes of PNG, JPEG, ...
      return decodeTexture({reinterpret_cast<const std::uint8_t*>(embedded->pcData), embedded->mWidth},
                           path + ": " + name);
    }
    if (embedded->mWidth > kMaxTextureSide || embedded->mHeight > kMaxTextureSide) {
      fail(path, "embedded image '" + name + "' is over " + std::to_string(kMaxTextureSide) + " texels a side",
           "downscale it");
    }
    Texture t{path + ": " + name, embedded->mWidth, embedded->mHeight, {}};
    t.rgba.reserve(std::size_t(t.width) * t.height * 4);
    for (std::size_t i = 0; i < std::size_t(t.width) * t.height; ++i) {
      const aiTexel& x = embedded->pcData[i];
      t.rgba.insert(t.rgba.end(), {x.r, x.g, x.b, x.a});
    }
    return t;
  }
};

// The texture coordinates of `set` for every vertex (v flipped: row 0 is the top), or none.
std::vector<glm::vec2> textureCoordinates(const aiMesh& mesh, unsigned set) {
  std::vector<glm::vec2> uvs;
  if (set >= AI_MAX_NUMBER_OF_TEXTURECOORDS || !mesh.mTextureCoords[set]) return uvs;
  for (unsigned v = 0; v < mesh.mNumVertices; ++v)
    uvs.emplace_back(mesh.mTextureCoords[set][v].x, 1.0f - mesh.mTextureCoords[set][v].y);
  return uvs;
}

}  // namespace

Scene loadAssimp(const std::string& path) {
  std::error_code ec;
  const fs::path file = fs::absolute(path, ec).lexically_normal();
  Assimp::Importer importer;
  auto owned = std::make_unique<ConfinedIOSystem>(file.parent_path().string());
  ConfinedIOSystem* io = owned.get();
  importer.SetIOHandler(owned.release());  // assimp takes ownership (and deletes it with the importer)
  const aiScene* ai =
      importer.ReadFile(file.string(), aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure);
  if (!io->refused.empty()) {
    fail(path, "refuses to read '" + io->refused.front() + "': outside the model's folder",
         "copy what it refers to beside the model and refer to it relatively");
  }
  if (!ai || !ai->mRootNode || (ai->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
    const std::string why = importer.GetErrorString();
    fail(path,
         why.empty() ? "holds no complete scene assimp can read (files it names may be missing or outside its folder)"
                     : "could not be read by assimp (" + why + ")",
         "check that the file and what it names are complete, beside it, and in a format assimp reads");
  }

  Scene scene;
  std::vector<glm::dmat4> meshWorld;
  std::size_t dropped = 0;
  MaterialImages images{*ai, path, file.parent_path().string(), scene, {}, 0};
  // Depth first with a stack of our own: a file can nest nodes deeper than the call stack goes.
  std::vector<std::pair<const aiNode*, glm::dmat4>> open{{ai->mRootNode, toGlm(ai->mRootNode->mTransformation)}};
  while (!open.empty()) {
    const auto [node, world] = open.back();
    open.pop_back();
    for (unsigned i = 0; i < node->mNumChildren; ++i)
      open.emplace_back(node->mChildren[i], world * toGlm(node->mChildren[i]->mTransformation));
    const glm::dmat3 normalMatrix = glm::inverseTranspose(glm::dmat3(world));
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      const aiMesh* src = ai->mMeshes[node->mMeshes[k]];
      if (!(src->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) {  // sorted by type: lines or points only
        dropped += src->mNumFaces;
        continue;
      }
      Mesh mesh;
      mesh.name = src->mName.length ? src->mName.C_Str() : "mesh" + std::to_string(node->mMeshes[k]);
      mesh.positions.reserve(src->mNumVertices);
      for (unsigned v = 0; v < src->mNumVertices; ++v)
        mesh.positions.emplace_back(src->mVertices[v].x, src->mVertices[v].y, src->mVertices[v].z);
      if (src->mNormals) {
        for (unsigned v = 0; v < src->mNumVertices; ++v) {
          const glm::dvec3 n = normalMatrix * glm::dvec3(src->mNormals[v].x, src->mNormals[v].y, src->mNormals[v].z);
          mesh.normals.emplace_back(glm::length(n) > 0.0 ? glm::normalize(n) : n);  // cleanScene fixes zero ones
        }
      }
      for (unsigned f = 0; f < src->mNumFaces; ++f) {
        const aiFace& face = src->mFaces[f];
        if (face.mNumIndices != 3) {
          ++dropped;
          continue;
        }
        mesh.indices.insert(mesh.indices.end(), {face.mIndices[0], face.mIndices[1], face.mIndices[2]});
      }
      if (src->mMaterialIndex < ai->mNumMaterials) {
        const aiMaterial& material = *ai->mMaterials[src->mMaterialIndex];
        aiColor4D colour;
        if (material.Get(AI_MATKEY_COLOR_DIFFUSE, colour) == AI_SUCCESS)
          mesh.baseColor = {colour.r, colour.g, colour.b};
        // The colour's image: where it cannot be had, a warning (once; only colour is lost).
        std::optional<unsigned> colorSet;
        try {
          if (const auto image = images.find(material, {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE})) {
            mesh.uvs = textureCoordinates(*src, image->uvSet);
            mesh.colorTexture = image->texture;
            colorSet = image->uvSet;
          }
        } catch (const InputError& e) {
          const std::string warning = std::string(e.what()) + " (only colour is lost: drawn in its base colour)";
          if (std::find(scene.warnings.begin(), scene.warnings.end(), warning) == scene.warnings.end()) {
            scene.warnings.push_back(warning);
          }
        }
        if (const auto image = images.find(material, {aiTextureType_OPACITY})) {
          if (colorSet && *colorSet != image->uvSet) {
            scene.warnings.push_back("mesh '" + mesh.name +
                                     "': its opacity and colour images use different texture "
                                     "coordinate sets; the opacity's is used for both");
          }
          mesh.uvs = textureCoordinates(*src, image->uvSet);
          mesh.cutout = Cutout{image->texture, 1.0f, 0.5f};
        }
      }
      scene.meshes.push_back(std::move(mesh));
      meshWorld.push_back(world);
    }
  }
  placeMeshes(scene, meshWorld);
  if (dropped)
    scene.warnings.push_back(std::to_string(dropped) + " lines and points dropped (only triangles cast shadows)");
  return scene;
}

bool assimpReads(const std::string& extension) { return Assimp::Importer().IsExtensionSupported(extension); }

}  // namespace penumbra
