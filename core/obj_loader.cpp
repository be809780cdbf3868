// Wavefront OBJ loader. tinyobj parses from memory so that it never opens files itself: the
// material libraries and their images (map_Kd: colour; map_d: cut-outs, docs/methods.md) are read
// here, and only from the OBJ's own folder. Coordinates are parsed in
// double (tinyobjloader_double) and stored relative to the scene's origin, so that georeferenced
// files keep their detail.
#include <array>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <unordered_map>

#include <tiny_obj_loader.h>

#include "core/scene_loader.h"
#include "core/texture.h"

namespace penumbra {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem, const std::string& fix) {
  throw InputError("OBJ '" + path + "': " + problem + "; " + fix);
}

bool readText(const std::string& path, std::string& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  out.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return !in.bad();
}

std::string trimmed(const std::string& s) {
  const std::size_t b = s.find_first_not_of(" \t\r\n");
  return b == std::string::npos ? std::string() : s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

// Collects the text of every mtllib the OBJ names that stays inside its folder. Libraries that
// would leave the folder are ignored with a warning (the geometry is still usable without them).
std::string materialText(const std::string& objText, const std::string& path, const std::string& folder,
                         std::vector<std::string>& warnings) {
  std::string text;
  std::istringstream lines(objText);
  for (std::string line; std::getline(lines, line);) {
    line = trimmed(line);
    if (line.rfind("mtllib", 0) != 0 || line.size() < 7 || !std::isspace(static_cast<unsigned char>(line[6]))) continue;
    std::istringstream names(line.substr(7));
    for (std::string name; names >> name;) {
      const std::string why = confinedPathProblem(folder, name);
      if (!why.empty()) {
        warnings.push_back("OBJ '" + path + "': ignored material library '" + name +
                           "' outside the OBJ's folder (" + why + "); default colours used");
        continue;
      }
      std::string mtl;
      if (!readText((fs::path(folder) / name).string(), mtl)) {
        warnings.push_back("OBJ '" + path + "': material library '" + name + "' not found next to it; default colours used");
        continue;
      }
      text += mtl + "\n";
    }
  }
  return text;
}

// A material's image as a Scene texture (readTexture), decoded once per file.
struct Images {
  const std::string& path;
  const std::string& folder;
  Scene& scene;
  std::map<std::string, std::int32_t> loaded;
  std::uint64_t bytes = 0;  // decoded so far

  std::int32_t operator()(const std::string& name) {
    // (-1: a colour map that failed; a map_d of the same image tries again, to fail loudly)
    if (const auto known = loaded.find(name); known != loaded.end() && known->second >= 0) return known->second;
    Texture t = readTexture(folder, name, path);
    if (bytes + t.rgba.size() > kMaxTextureBytes) {
      fail(path, "its images decode to over " + std::to_string(kMaxTextureBytes >> 30) + " GiB", "downscale them");
    }
    bytes += t.rgba.size();
    scene.textures.push_back(std::move(t));
    return loaded[name] = std::int32_t(scene.textures.size() - 1);
  }

  // A map_Kd: where it cannot be had, a warning (once per image) and -1, the material's Kd alone.
  std::int32_t color(const std::string& name) {
    try {
      return (*this)(name);
    } catch (const InputError& e) {
      if (loaded.emplace(name, -1).second)
        scene.warnings.push_back(std::string(e.what()) + " (only colour is lost: Kd alone drawn)");
      return -1;
    }
  }
};

std::string firstLines(const std::string& message) {
  std::string s = trimmed(message);
  for (char& c : s) c = c == '\n' ? ' ' : c;
  return s;
}

}  // namespace

Scene loadObj(const std::string& path) {
  std::string objText;
  if (!readText(path, objText)) fail(path, "cannot be opened", "check the path and the file permissions");
  std::error_code ec;
  const std::string folder = fs::absolute(path, ec).parent_path().string();

  Scene scene;
  const std::string mtlText = materialText(objText, path, folder, scene.warnings);
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;  // ParseFromString ignores mtllib names and reads mtlText instead
  if (!reader.ParseFromString(objText, mtlText, config)) {
    fail(path, "could not be parsed: " + firstLines(reader.Error()), "fix the reported line");
  }
  // tinyobj only warns about out-of-range indices (or silently drops such quads): refuse them.
  const std::string warning = reader.Warning();
  if (warning.find("out of bounds") != std::string::npos || warning.find("invalid vertex index") != std::string::npos) {
    fail(path, "face index out of range (" + firstLines(warning) + ")", "fix the 'f' lines to use existing vertices");
  }
  if (!trimmed(warning).empty()) scene.warnings.push_back("OBJ '" + path + "': " + firstLines(warning));

  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  const std::vector<tinyobj::material_t>& materials = reader.GetMaterials();
  const long vertexCount = long(attrib.vertices.size() / 3);
  const long normalCount = long(attrib.normals.size() / 3);
  const std::vector<tinyobj::shape_t>& shapes = reader.GetShapes();
  const auto vertex = [&](int i) {
    const tinyobj::real_t* v = &attrib.vertices[3 * std::size_t(i)];
    return glm::dvec3(v[0], v[1], v[2]);
  };
  WorldBounds world;  // of the vertices the faces use
  for (const tinyobj::shape_t& shape : shapes) {
    for (const tinyobj::index_t& idx : shape.mesh.indices) {
      if (idx.vertex_index >= 0 && idx.vertex_index < vertexCount) world.extend(vertex(idx.vertex_index));
    }
  }
  scene.origin = world.origin();
  Images images{path, folder, scene, {}, 0};
  const auto image = [&](int material, std::string tinyobj::material_t::*name) {
    return material >= 0 && std::size_t(material) < materials.size() ? trimmed(materials[std::size_t(material)].*name)
                                                                     : std::string();
  };
  std::vector<char> textured(materials.size());  // per material: whether it has an image (map_Kd, map_d)
  for (std::size_t m = 0; m < materials.size(); ++m) {
    textured[m] = !image(int(m), &tinyobj::material_t::alpha_texname).empty() ||
                  !image(int(m), &tinyobj::material_t::diffuse_texname).empty();
  }
  for (std::size_t s = 0; s < shapes.size(); ++s) {
    const tinyobj::mesh_t& src = shapes[s].mesh;
    const std::string shapeName = shapes[s].name.empty() ? "shape" + std::to_string(s) : shapes[s].name;
    // One Mesh per (shape, material); vertices deduplicated by (position, normal) index pair, and
    // by texture coordinate too where the material has an image (map_Kd, map_d), which keeps them.
    struct Part {
      Mesh mesh;
      std::unordered_map<std::uint64_t, std::uint32_t> remap;
      std::map<std::array<int, 3>, std::uint32_t> texturedRemap;
      bool allNormals = true;
    };
    std::map<int, Part> parts;
    for (std::size_t i = 0; i < src.indices.size(); ++i) {
      const tinyobj::index_t& idx = src.indices[i];
      if (idx.vertex_index < 0 || idx.vertex_index >= vertexCount) {
        fail(path, "shape '" + shapeName + "' uses vertex " + std::to_string(long(idx.vertex_index) + 1) + " but only " +
             std::to_string(vertexCount) + " exist", "fix the 'f' lines to use existing vertices");
      }
      if (idx.normal_index < -1 || idx.normal_index >= normalCount) {
        fail(path, "shape '" + shapeName + "' uses normal " + std::to_string(long(idx.normal_index) + 1) + " but only " +
             std::to_string(normalCount) + " exist", "fix the 'f' lines to use existing normals");
      }
      const int material = i / 3 < src.material_ids.size() ? src.material_ids[i / 3] : -1;
      Part& part = parts[material];
      const auto next = std::uint32_t(part.mesh.positions.size());
      const std::uint64_t key = std::uint64_t(std::uint32_t(idx.vertex_index)) << 32 | std::uint32_t(idx.normal_index + 1);
      const bool withUv = material >= 0 && std::size_t(material) < textured.size() && textured[std::size_t(material)];
      std::uint32_t index = next;
      bool inserted = true;
      if (withUv) {
        const auto [at, added] =
            part.texturedRemap.try_emplace({idx.vertex_index, idx.normal_index, idx.texcoord_index}, next);
        index = at->second;
        inserted = added;
      } else {
        const auto [at, added] = part.remap.try_emplace(key, next);
        index = at->second;
        inserted = added;
      }
      if (inserted && withUv) {
        const bool has = idx.texcoord_index >= 0 && std::size_t(2 * idx.texcoord_index + 1) < attrib.texcoords.size();
        const tinyobj::real_t* t = has ? &attrib.texcoords[2 * std::size_t(idx.texcoord_index)] : nullptr;
        part.mesh.uvs.emplace_back(has ? float(t[0]) : 0.0f, has ? 1.0f - float(t[1]) : 0.0f);  // OBJ's v points up
      }
      if (inserted) {
        part.mesh.positions.emplace_back(vertex(idx.vertex_index) - scene.origin);
        if (idx.normal_index >= 0) {
          const tinyobj::real_t* n = &attrib.normals[3 * std::size_t(idx.normal_index)];
          part.mesh.normals.emplace_back(n[0], n[1], n[2]);
        } else {
          part.allNormals = false;
        }
      }
      part.mesh.indices.push_back(index);
    }
    for (auto& [material, part] : parts) {
      Mesh& mesh = part.mesh;
      mesh.name = shapeName;
      if (material >= 0 && std::size_t(material) < materials.size()) {
        const tinyobj::material_t& m = materials[std::size_t(material)];
        if (parts.size() > 1) mesh.name += "/" + m.name;
        mesh.baseColor = glm::vec3(m.diffuse[0], m.diffuse[1], m.diffuse[2]);
        if (const std::string alpha = image(material, &tinyobj::material_t::alpha_texname); !alpha.empty()) {
          mesh.cutout = Cutout{images(alpha), float(m.dissolve), 0.5f};
        }
        if (const std::string color = image(material, &tinyobj::material_t::diffuse_texname); !color.empty()) {
          mesh.colorTexture = images.color(color);
        }
      }
      if (!part.allNormals) mesh.normals.clear();  // cleanScene derives them from the faces
      scene.meshes.push_back(std::move(mesh));
    }
  }
  return scene;
}

}  // namespace penumbra
