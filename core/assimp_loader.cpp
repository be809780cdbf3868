// The other formats of the field (PLY scans, STL, OFF, COLLADA, FBX, 3DS, ...) through the Open
// Asset Import Library. The same rules as the glTF loader: the file is untrusted, only the model's
// own folder may be read (a confining IOSystem), node transforms are composed in double and the
// scene is stored relative to its origin (placeMeshes), lines and points are dropped with a note.
#include <assimp/DefaultIOSystem.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <filesystem>
#include <glm/gtc/matrix_inverse.hpp>
#include <memory>
#include <utility>

#include "core/scene_loader.h"

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
      aiColor4D colour;
      if (src->mMaterialIndex < ai->mNumMaterials &&
          ai->mMaterials[src->mMaterialIndex]->Get(AI_MATKEY_COLOR_DIFFUSE, colour) == AI_SUCCESS) {
        mesh.baseColor = {colour.r, colour.g, colour.b};
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
