// Scene spec dispatch: built-in scenes by name, model files by extension; always cleaned.
#include "core/scene_loader.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>

#include "core/builtin_scenes.h"

namespace penumbra {

namespace fs = std::filesystem;

std::string confinedPathProblem(const std::string& folder, const std::string& reference) {
  if (reference.empty()) return "it is empty";
  const bool driveLetter = reference.size() >= 2 && std::isalpha(static_cast<unsigned char>(reference[0])) &&
                           reference[1] == ':';
  if (reference[0] == '/' || reference[0] == '\\' || driveLetter) return "it is an absolute path";
  const fs::path relative = fs::path(reference).lexically_normal();
  if (!relative.empty() && *relative.begin() == "..") return "it climbs out with ../";
  // Lexically inside; a symbolic link on the way could still lead out, so compare real paths.
  std::error_code ec;
  const fs::path root = fs::weakly_canonical(fs::absolute(folder), ec);
  if (ec) return "the folder '" + folder + "' cannot be resolved (" + ec.message() + ")";
  const fs::path real = fs::weakly_canonical(root / relative, ec);
  if (ec) return "it cannot be resolved (" + ec.message() + ")";
  const fs::path inside = real.lexically_relative(root);
  if (inside.empty() || *inside.begin() == "..") return "it resolves through a link to '" + real.string() + "'";
  return {};
}

namespace {

std::string lowercase(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string supportedForms() {
  std::string names;
  for (const std::string& name : builtinSceneNames()) names += (names.empty() ? "" : ", ") + name;
  return "builtin:NAME[:LEVEL] (NAME one of: " + names + "), a .gltf/.glb file, an .obj file or a model in a format "
         "assimp reads (.ply, .stl, .off, .dae, .fbx, .3ds, ...)";
}

}  // namespace

Scene loadScene(const std::string& spec) {
  static const std::string kBuiltin = "builtin:";
  const auto start = std::chrono::steady_clock::now();
  Scene scene;
  if (spec.rfind(kBuiltin, 0) == 0) {
    const std::string nameAndLevel = spec.substr(kBuiltin.size());
    scene = makeBuiltinScene(nameAndLevel);
    if (scene.name.empty()) scene.name = nameAndLevel.substr(0, nameAndLevel.find(':'));
  } else {
    const fs::path path(spec);
    const std::string ext = lowercase(path.extension().string());
    const bool gltf = ext == ".gltf" || ext == ".glb";
    if (!gltf && ext != ".obj" && !assimpReads(ext)) {
      throw InputError("scene '" + spec + "' has " +
                       (ext.empty() ? std::string("no file extension") : "the unsupported extension '" + ext + "'") +
                       "; give " + supportedForms());
    }
    std::error_code ec;
    if (!fs::exists(path, ec)) {
      throw InputError("scene file '" + spec + "' not found; check the path or give " + supportedForms());
    }
    if (!fs::is_regular_file(path, ec)) {
      throw InputError("scene file '" + spec + "' is not a regular file; give the path of the model file itself");
    }
    try {
      scene = gltf ? loadGltf(spec) : ext == ".obj" ? loadObj(spec) : loadAssimp(spec);
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {
      // Library surprises (allocation, parser exceptions) still reach the user as input errors.
      throw InputError("scene file '" + spec + "' could not be loaded: " + e.what() +
                       "; check that the file is a valid model");
    }
    scene.name = path.stem().string();
  }
  cleanScene(scene, spec);
  scene.loadMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return scene;
}

}  // namespace penumbra
