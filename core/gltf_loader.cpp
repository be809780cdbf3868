// glTF 2.0 loader. Files are untrusted: the GLB container is validated before tinygltf sees it,
// external files are confined to the model's folder, and every accessor is bounds-checked.
#include <dlfcn.h>
#include <tiny_gltf.h>  // implementation lives in the shared libtinygltf

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>

#include "core/gltf_accessor.h"
#include "core/gltf_animation.h"
#include "core/gltf_document.h"
#include "core/gltf_draco.h"
#include "core/gltf_meshopt.h"
#include "core/gltf_rewrite.h"
#include "core/gltf_textures.h"
#include "core/scene_loader.h"
#include "core/texture.h"

namespace penumbra {

namespace fs = std::filesystem;

namespace {

using gltf::checkDocument;
using gltf::compressionUsed;
using gltf::fail;
using gltf::GlbChunks;
using gltf::parseDocument;
using gltf::readIndices;
using gltf::readVec3;
using gltf::validateGlb;

std::vector<unsigned char> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot be opened", "check the path and the file permissions");
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) fail(path, "could not be read", "check the file");
  return bytes;
}

// tinygltf reaches the file system only through these callbacks. tinygltf tries
// "<model folder>/<uri>" and then "./<uri>"; only the first form is ever allowed.
struct FsContext {
  std::string folder;  // absolute model folder as given to tinygltf
  std::string prefix;  // folder + "/"
  std::vector<std::string> refused;
};

bool allowedFile(FsContext& ctx, const std::string& candidate) {
  if (candidate.rfind(ctx.prefix, 0) != 0) return false;  // the working-directory fallback
  const std::string uri = candidate.substr(ctx.prefix.size());
  const std::string why = confinedPathProblem(ctx.folder, uri);
  if (why.empty()) return true;
  const std::string note = "'" + uri + "' (" + why + ")";
  if (std::find(ctx.refused.begin(), ctx.refused.end(), note) == ctx.refused.end()) ctx.refused.push_back(note);
  return false;
}

bool fsFileExists(const std::string& path, void* user) {
  std::error_code ec;
  return allowedFile(*static_cast<FsContext*>(user), path) && fs::is_regular_file(path, ec);
}

std::string fsExpandFilePath(const std::string& path, void*) { return path; }  // no ~ or $VAR expansion

bool fsReadWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  if (!allowedFile(*static_cast<FsContext*>(user), path)) {
    *err = "outside the model's folder";
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    *err = "cannot be opened";
    return false;
  }
  out->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return !in.bad();
}

bool fsWriteWholeFile(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  *err = "the loader never writes files";
  return false;
}

// A unit direction under a transform's linear part (`local` itself if it collapses or overflows).
glm::vec3 worldDirection(const glm::dmat3& linear, const glm::vec3& local) {
  const glm::vec3 d(linear * glm::dvec3(local));
  const float len = glm::length(d);
  return len > 0.0f && std::isfinite(len) ? d / len : local;
}

glm::vec3 rgb(const std::vector<double>& c, glm::vec3 fallback) {
  return c.size() >= 3 ? glm::vec3(float(c[0]), float(c[1]), float(c[2])) : fallback;
}

struct Converter {
  const tinygltf::Model& model;
  const std::string& path;
  Scene& scene;
  const gltf::NodeAnimations& animations;
  std::vector<char> onPath;  // cycle guard: a node that is its own ancestor would recurse forever
  std::vector<int> chain;    // the nodes from the root to the one being visited
  std::size_t animatedOnChain = 0;  // how many of them are animated
  struct Animated {
    std::size_t mesh;
    std::vector<int> chain;
  };
  std::vector<Animated> animated;  // meshes under animated nodes
  std::size_t visits = 0;
  // World transforms in double, applied once the walk has found the scene's origin: meshes hold
  // their local positions until then (meshWorld[i] belongs to scene.meshes[i]).
  std::vector<glm::dmat4> meshWorld;
  struct LightNode {
    const tinygltf::Node* node;
    glm::dmat4 world;
  };
  std::vector<LightNode> lightNodes;
  std::optional<glm::dmat4> cameraWorld;
  std::optional<gltf::Textures> textures;  // made by run()
  float yfov = 0.0f;
  bool warnedOrtho = false;

  void addPrimitive(const tinygltf::Mesh& mesh, std::size_t p, const glm::dmat4& world) {
    const tinygltf::Primitive& prim = mesh.primitives[p];
    const std::string name = (mesh.name.empty() ? "mesh" : mesh.name) + "/" + std::to_string(p);
    const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      scene.warnings.push_back("glTF primitive '" + name + "' skipped: mode " + std::to_string(mode) + " is points or lines");
      return;
    }
    const auto pos = prim.attributes.find("POSITION");
    if (pos == prim.attributes.end()) {
      scene.warnings.push_back("glTF primitive '" + name + "' skipped: no POSITION attribute");
      return;
    }
    Mesh out;
    out.name = name;
    out.positions = readVec3(model, pos->second, "POSITION", path);  // local until run() places them
    if (const auto nrm = prim.attributes.find("NORMAL"); nrm != prim.attributes.end()) {
      out.normals = readVec3(model, nrm->second, "NORMAL", path);
      const glm::dmat3 normalMatrix = glm::inverseTranspose(glm::dmat3(world));
      for (glm::vec3& n : out.normals) n = worldDirection(normalMatrix, n);
      if (out.normals.size() != out.positions.size()) out.normals.clear();  // cleanScene recomputes
    }
    std::vector<std::uint32_t> idx;
    if (prim.indices >= 0) {
      idx = readIndices(model, prim.indices, "indices", path);
    } else {
      idx.resize(out.positions.size());
      for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = std::uint32_t(i);
    }
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      out.indices = std::move(idx);
    } else {
      for (std::size_t i = 0; i + 2 < idx.size(); ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_FAN) out.indices.insert(out.indices.end(), {idx[0], idx[i + 1], idx[i + 2]});
        else if (i % 2 == 0) out.indices.insert(out.indices.end(), {idx[i], idx[i + 1], idx[i + 2]});
        else out.indices.insert(out.indices.end(), {idx[i + 1], idx[i], idx[i + 2]});  // keep strip winding
      }
    }
    if (prim.material >= 0 && std::size_t(prim.material) < model.materials.size()) {
      const tinygltf::Material& material = model.materials[std::size_t(prim.material)];
      out.baseColor = rgb(material.pbrMetallicRoughness.baseColorFactor, glm::vec3(1.0f));
      // MASK's texture is the mesh's shape: one that cannot be had is an error. BLEND's is a
      // translucency cut at 0.5 (docs/methods.md); without it the factor alone decides, with a warning.
      const bool cut = material.alphaMode == "MASK" || material.alphaMode == "BLEND";
      const tinygltf::TextureInfo& info = material.pbrMetallicRoughness.baseColorTexture;
      if (info.index >= 0 && readTextureCoordinates(prim, info, out)) {
        out.colorTexture = textures->texture(info.index, material.alphaMode == "MASK");
      }
      if (cut) addCutout(material, out);
    }
    scene.meshes.push_back(std::move(out));
    meshWorld.push_back(world);
    if (animatedOnChain > 0) animated.push_back({scene.meshes.size() - 1, chain});
  }

  // The base colour texture's coordinates (its texCoord set, KHR_texture_transform baked in) into
  // out.uvs; false, with a warning, when the primitive lacks that set.
  bool readTextureCoordinates(const tinygltf::Primitive& prim, const tinygltf::TextureInfo& info, Mesh& out) {
    const gltf::TextureTransform transform(info);
    const std::string set = "TEXCOORD_" + std::to_string(transform.texCoord);
    const auto uv = prim.attributes.find(set);
    if (uv == prim.attributes.end()) {
      scene.warnings.push_back("glTF primitive '" + out.name + "' has no " + set +
                               " for its base colour texture; its base colour (and alpha) factor alone is used");
      return false;
    }
    out.uvs = gltf::readVec2(model, uv->second, set, path);
    transform.bake(out.uvs);
    return true;
  }

  // alphaMode MASK cuts at alphaCutoff, BLEND by the same rule at 0.5 (docs/methods.md); the alpha
  // is baseColorFactor's times the base colour texture's.
  void addCutout(const tinygltf::Material& material, Mesh& out) {
    Cutout cutout;
    const std::vector<double>& factor = material.pbrMetallicRoughness.baseColorFactor;
    cutout.factor = factor.size() >= 4 ? float(factor[3]) : 1.0f;
    cutout.cutoff = material.alphaMode == "MASK" ? float(material.alphaCutoff) : 0.5f;
    if (!std::isfinite(cutout.factor) || !std::isfinite(cutout.cutoff)) {
      fail(path, "material '" + material.name + "' has a non-finite alpha factor or cutoff", "re-export it");
    }
    cutout.texture = out.colorTexture;
    out.cutout = cutout;
  }

  void addLight(const tinygltf::Node& node, const glm::dmat4& world) {
    const auto ext = node.extensions.find("KHR_lights_punctual");
    if (ext == node.extensions.end() || !ext->second.IsObject() || !ext->second.Has("light")) return;
    const tinygltf::Value& ref = ext->second.Get("light");
    const int index = ref.IsNumber() ? ref.GetNumberAsInt() : -1;
    if (index < 0 || std::size_t(index) >= model.lights.size()) {
      scene.warnings.push_back("glTF node '" + node.name + "' refers to missing light " + std::to_string(index) + "; ignored");
      return;
    }
    const tinygltf::Light& src = model.lights[std::size_t(index)];
    Light light;
    light.color = rgb(src.color, glm::vec3(1.0f));
    light.position = glm::vec3(world[3]);
    light.direction = worldDirection(glm::dmat3(world), glm::vec3(0.0f, 0.0f, -1.0f));
    light.intensity = float(src.intensity);
    light.range = float(src.range);
    if (!std::isfinite(light.intensity) || light.intensity < 0.0f || !std::isfinite(light.range) ||
        light.range < 0.0f) {
      fail(path, "light '" + src.name + "' has a negative or non-finite intensity or range", "re-export it");
    }
    if (src.type == "directional") {
      light.type = LightType::Directional;
    } else if (src.type == "spot") {
      light.type = LightType::Spot;
      light.inverseSquare = true;
      const double inner = src.spot.innerConeAngle, outer = src.spot.outerConeAngle;
      if (!(inner >= 0.0 && inner < outer && outer <= glm::half_pi<double>())) {
        fail(path, "spot light '" + src.name + "' needs 0 <= innerConeAngle < outerConeAngle <= pi/2", "re-export it");
      }
      light.spotAngleDeg = float(2.0 * glm::degrees(outer));
      light.innerAngleDeg = float(2.0 * glm::degrees(inner));
    } else if (src.type == "point") {
      light.type = LightType::Point;
      light.inverseSquare = true;
    } else {
      scene.warnings.push_back("glTF light type '" + src.type + "' is unknown; ignored");
      return;
    }
    scene.lights.push_back(light);
  }

  // glTF's intensities are physical (lux, candela) and the renderer has no exposure: they are scaled
  // together so that the brightest light gives irradiance 1 at the scene's centre, ratios kept.
  void exposeLights(const glm::vec3& centre) {
    float brightest = 0.0f;
    for (const Light& l : scene.lights) {
      const glm::vec3 v = l.position - centre;
      brightest = std::max(brightest, l.inverseSquare ? l.intensity / std::max(glm::dot(v, v), 1e-12f) : l.intensity);
    }
    if (brightest > 0.0f) {
      for (Light& l : scene.lights) l.intensity /= brightest;
    }
  }

  // A node entered on the way down (after its parent): its own content, then its children.
  struct Open {
    int index;
    glm::dmat4 world;
    std::size_t nextChild = 0;
  };

  void enter(int index, const glm::dmat4& parent, std::vector<Open>& open) {
    if (index < 0 || std::size_t(index) >= model.nodes.size()) {
      fail(path, "node " + std::to_string(index) + " does not exist", "the file is corrupt; re-export it");
    }
    if (onPath[std::size_t(index)]) fail(path, "node " + std::to_string(index) + " is its own ancestor", "remove the cycle");
    if (++visits > 1000000) fail(path, "node hierarchy expands to over a million instances", "flatten the scene");
    const tinygltf::Node& node = model.nodes[std::size_t(index)];
    chain.push_back(index);
    if (animations.animates(index)) ++animatedOnChain;
    const glm::dmat4 world = parent * gltf::localTransform(node);
    if (node.mesh >= 0) {
      if (std::size_t(node.mesh) >= model.meshes.size()) {
        fail(path, "node " + std::to_string(index) + " refers to missing mesh " + std::to_string(node.mesh), "re-export it");
      }
      const tinygltf::Mesh& mesh = model.meshes[std::size_t(node.mesh)];
      for (std::size_t p = 0; p < mesh.primitives.size(); ++p) addPrimitive(mesh, p, world);
    }
    if (node.camera >= 0 && std::size_t(node.camera) < model.cameras.size()) {
      const tinygltf::Camera& cam = model.cameras[std::size_t(node.camera)];
      if (cam.type == "perspective" && !cameraWorld) {
        cameraWorld = world;
        yfov = float(cam.perspective.yfov);
      } else if (cam.type != "perspective" && !warnedOrtho) {
        scene.warnings.push_back("glTF camera '" + cam.name + "' is " + cam.type + ", only perspective is used; ignored");
        warnedOrtho = true;
      }
    }
    lightNodes.push_back({&node, world});
    onPath[std::size_t(index)] = 1;
    open.push_back({index, world});
  }

  // Depth first from root with a stack of its own: a file can nest nodes deeper than the call
  // stack goes (20,000 levels crashed the recursive walk).
  void visit(int root) {
    std::vector<Open> open;
    enter(root, glm::dmat4(1.0), open);
    while (!open.empty()) {
      Open& top = open.back();
      const std::vector<int>& children = model.nodes[std::size_t(top.index)].children;
      if (top.nextChild < children.size()) {
        const int child = children[top.nextChild++];
        const glm::dmat4 parent = top.world;  // enter() grows `open`, which moves `top`
        enter(child, parent, open);
        continue;
      }
      onPath[std::size_t(top.index)] = 0;
      if (animations.animates(top.index)) --animatedOnChain;
      chain.pop_back();
      open.pop_back();
    }
  }

  std::vector<int> roots() const {
    if (!model.scenes.empty()) {
      const bool validDefault = model.defaultScene >= 0 && std::size_t(model.defaultScene) < model.scenes.size();
      return model.scenes[validDefault ? std::size_t(model.defaultScene) : 0].nodes;
    }
    std::vector<char> isChild(model.nodes.size(), 0);
    for (const tinygltf::Node& node : model.nodes) {
      for (int c : node.children) {
        if (c >= 0 && std::size_t(c) < isChild.size()) isChild[std::size_t(c)] = 1;
      }
    }
    std::vector<int> out;
    for (std::size_t i = 0; i < isChild.size(); ++i) {
      if (!isChild[i]) out.push_back(int(i));
    }
    return out;
  }

  void run() {
    textures.emplace(model, path, scene);  // decodes the base colours' images on all cores
    onPath.assign(model.nodes.size(), 0);
    for (int root : roots()) visit(root);
    const glm::dmat4 toScene = placeMeshes(scene, meshWorld);
    for (const LightNode& l : lightNodes) addLight(*l.node, toScene * l.world);
    // Rest positions are taken by cleanScene (after it cleaned the mesh), so they match the mesh.
    for (const Animated& a : animated) {
      const std::optional<std::vector<RigidKey>> keys =
          gltf::rigidKeys(model, animations, a.chain, scene.origin, scene.meshes[a.mesh].name, scene.warnings);
      if (!keys) continue;
      scene.meshes[a.mesh].dynamic = true;
      scene.animations.push_back({a.mesh, {}, {}, *keys});
    }
    Bounds finite;  // the scene's extent, ignoring NaN that cleanScene drops later
    for (const Mesh& m : scene.meshes) {
      for (const glm::vec3& p : m.positions) {
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) finite.extend(p);
      }
    }
    if (!finite.empty()) exposeLights(finite.center());
    if (!cameraWorld) return;
    const float distance = finite.empty() || !(finite.radius() > 0.0f) ? 1.0f : finite.radius();
    Camera camera;
    const glm::dmat4 cameraPlace = toScene * *cameraWorld;
    camera.eye = glm::vec3(cameraPlace[3]);
    camera.target = camera.eye + distance * worldDirection(glm::dmat3(cameraPlace), glm::vec3(0.0f, 0.0f, -1.0f));
    camera.up = worldDirection(glm::dmat3(cameraPlace), glm::vec3(0.0f, 1.0f, 0.0f));
    if (yfov > 0.0f && yfov < glm::pi<float>()) camera.fovYDeg = glm::degrees(yfov);
    scene.camera = camera;
  }
};

// Debian's libdraco, which assimp loads, carries a tinygltf of its own, of another version: were
// this program's tinygltf calls bound to it (the dynamic linker takes the first library that
// defines a symbol), every model would be read with the wrong structure layouts. Refuse instead.
void requireDebiansTinygltf() {
  static const std::string where = [] {
    Dl_info info{};
    return dladdr(reinterpret_cast<void*>(&tinygltf::FileExists), &info) && info.dli_fname ? std::string(info.dli_fname)
                                                                                           : std::string();
  }();
  if (where.find("libtinygltf") == std::string::npos) {
    throw std::runtime_error("tinygltf calls are bound to '" + where + "', not to libtinygltf: link TinyGLTF::TinyGLTF "
                             "before assimp (whose libdraco carries another tinygltf)");
  }
}

}  // namespace

Scene loadGltf(const std::string& path) {
  requireDebiansTinygltf();
  const std::vector<unsigned char> bytes = readBytes(path);
  if (bytes.size() > std::numeric_limits<unsigned int>::max()) fail(path, "is larger than 4 GiB", "split the model");
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  const bool binary = ext == ".glb" || (bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0);
  std::error_code ec;
  FsContext ctx;
  ctx.folder = fs::absolute(path, ec).parent_path().string();
  ctx.prefix = ctx.folder.empty() || ctx.folder.back() == '/' ? ctx.folder : ctx.folder + "/";
  const GlbChunks chunks = binary ? validateGlb(bytes, path) : GlbChunks{std::string(bytes.begin(), bytes.end())};
  const nlohmann::json doc = parseDocument(chunks.json, path);
  std::vector<std::string> notes = checkDocument(doc, path, ctx.folder);
  // Compressed views and primitives are decoded first, into a GLB tinygltf reads as a plain one.
  std::vector<unsigned char> decoded;
  const std::vector<std::string> compression = compressionUsed(doc);
  if (!compression.empty()) {
    const auto start = std::chrono::steady_clock::now();
    gltf::GlbRewrite rewrite(doc, std::span(bytes.data() + chunks.binOffset, chunks.binSize), ctx.folder, path);
    for (const std::string& name : compression) {
      const bool meshopt = name == "EXT_meshopt_compression";
      const gltf::DecodeStats stats = meshopt ? gltf::decodeMeshopt(rewrite) : gltf::decodeDraco(rewrite);
      notes.push_back(name + ": " + std::to_string(stats.items) + (meshopt ? " bufferView" : " primitive") +
                      (stats.items == 1 ? "" : "s") + " decoded (" + std::to_string(stats.decodedBytes >> 10) + " KiB)");
    }
    decoded = rewrite.finish(compression);
    notes.back() += " in " + std::to_string(int(std::chrono::duration<double, std::milli>(
                                                    std::chrono::steady_clock::now() - start).count())) + " ms";
  }
  const std::vector<unsigned char>& input = compression.empty() ? bytes : decoded;
  if (input.size() > std::numeric_limits<unsigned int>::max()) fail(path, "decodes to more than 4 GiB", "split the model");

  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks({&fsFileExists, &fsExpandFilePath, &fsReadWholeFile, &fsWriteWholeFile, &ctx});
  loader.SetImageLoader(&gltf::keepEncodedImage, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = binary || !compression.empty()
                     ? loader.LoadBinaryFromMemory(&model, &err, &warn, input.data(), unsigned(input.size()), ctx.folder)
                     : loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(input.data()),
                                                  unsigned(input.size()), ctx.folder);
  if (!ctx.refused.empty()) {  // also catches image URIs, whose read failures tinygltf only warns about
    fail(path, "refuses external file " + ctx.refused.front() + ": outside the model's folder",
         "copy the file into '" + ctx.folder + "' and refer to it relatively, or embed it as a data: URI");
  }
  while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
  if (err.size() > 400) err = err.substr(0, 400) + "...";  // tinygltf quotes whole data: URIs
  if (!ok) fail(path, "could not be parsed: " + (err.empty() ? std::string("unknown tinygltf error") : err),
                "check that the file and the buffers it names are complete");

  Scene scene;
  scene.warnings = notes;
  for (std::size_t start = 0; start < warn.size();) {
    const std::size_t end = std::min(warn.find('\n', start), warn.size());
    if (end > start) scene.warnings.push_back("glTF: " + warn.substr(start, end - start));
    start = end + 1;
  }
  const gltf::NodeAnimations animations(model, path, scene.warnings);
  Converter{model, path, scene, animations}.run();
  return scene;
}

}  // namespace penumbra
