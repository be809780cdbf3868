#include "core/gltf_textures.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

#include "core/gltf_accessor.h"

namespace penumbra::gltf {

bool keepEncodedImage(tinygltf::Image* image, int, std::string*, std::string*, int, int, const unsigned char* bytes,
                      int size, void*) {
  image->image.assign(bytes, bytes + std::max(size, 0));
  image->as_is = true;
  return true;
}

TextureTransform::TextureTransform(const tinygltf::TextureInfo& info) : texCoord(info.texCoord) {
  const auto ext = info.extensions.find("KHR_texture_transform");
  if (ext == info.extensions.end() || !ext->second.IsObject()) return;
  const tinygltf::Value& t = ext->second;
  const auto number = [](const tinygltf::Value& v, double fallback) {
    return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
  };
  const auto pair = [&](const char* key, glm::dvec2 fallback) {
    const tinygltf::Value& v = t.Get(key);
    return v.IsArray() && v.ArrayLen() == 2 ? glm::dvec2(number(v.Get(0), fallback.x), number(v.Get(1), fallback.y))
                                            : fallback;
  };
  offset = pair("offset", offset);
  scale = pair("scale", scale);
  rotation = number(t.Get("rotation"), 0.0);
  if (t.Get("texCoord").IsNumber()) texCoord = t.Get("texCoord").GetNumberAsInt();
}

void TextureTransform::bake(std::vector<glm::vec2>& uvs) const {
  const double c = std::cos(rotation), s = std::sin(rotation);
  for (glm::vec2& uv : uvs) {
    const glm::dvec2 scaled = glm::dvec2(uv) * scale;
    uv = glm::vec2(offset.x + c * scaled.x + s * scaled.y, offset.y - s * scaled.x + c * scaled.y);
  }
}

Textures::Textures(const tinygltf::Model& model, const std::string& path, Scene& scene)
    : model_(model), path_(path), scene_(scene) {
  std::vector<int> sources;
  for (const tinygltf::Mesh& mesh : model.meshes) {
    for (const tinygltf::Primitive& prim : mesh.primitives) {
      if (prim.material < 0 || std::size_t(prim.material) >= model.materials.size()) continue;
      const int t = model.materials[std::size_t(prim.material)].pbrMetallicRoughness.baseColorTexture.index;
      if (t < 0 || std::size_t(t) >= model.textures.size()) continue;
      const int source = model.textures[std::size_t(t)].source;
      if (source >= 0 && std::size_t(source) < model.images.size() &&
          !model.images[std::size_t(source)].image.empty()) {
        sources.push_back(source);
      }
    }
  }
  std::sort(sources.begin(), sources.end());
  sources.erase(std::unique(sources.begin(), sources.end()), sources.end());
  std::vector<std::variant<Texture, std::string>> results(sources.size());
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t i; (i = next++) < sources.size();) {
      const tinygltf::Image& image = model.images[std::size_t(sources[i])];
      try {
        results[i] = decodeTexture(image.image, path + ": " + imageName(sources[i]));
      } catch (const InputError& e) {
        results[i] = std::string(e.what());
      }
    }
  };
  std::vector<std::jthread> workers(
      std::min<std::size_t>(sources.size(), std::max(1u, std::thread::hardware_concurrency())));
  for (std::jthread& w : workers) w = std::jthread(work);
  workers.clear();  // joins
  for (std::size_t i = 0; i < sources.size(); ++i) decoded_.emplace(sources[i], std::move(results[i]));
}

std::int32_t Textures::texture(int index, bool required) {
  try {
    return decodedTexture(index);
  } catch (const InputError& e) {
    if (required) throw;
    if (warned_.insert(index).second) {
      scene_.warnings.push_back(std::string(e.what()) +
                                " (only colour and translucency are lost: drawn in its base colour)");
    }
    return -1;
  }
}

// Image `source`'s decoded texture, or its error (the constructor took every image a primitive's
// base colour names that has bytes; decodedTexture refuses those without before asking).
Texture Textures::takeDecoded(int source) {
  std::variant<Texture, std::string>& result = decoded_.at(source);
  if (const std::string* error = std::get_if<std::string>(&result)) throw InputError(*error);
  return std::move(std::get<Texture>(result));
}

std::string Textures::imageName(int source) const {
  const tinygltf::Image& image = model_.images[std::size_t(source)];
  return !image.uri.empty()    ? (image.uri.rfind("data:", 0) == 0 ? "data URI " + std::to_string(source) : image.uri)
         : !image.name.empty() ? image.name
                               : "image " + std::to_string(source);
}

std::int32_t Textures::decodedTexture(int index) {
  if (std::size_t(index) >= model_.textures.size()) {
    fail(path_, "texture " + std::to_string(index) + " does not exist", "the file is corrupt; re-export it");
  }
  const tinygltf::Texture& texture = model_.textures[std::size_t(index)];
  const int source = texture.source;
  if (source < 0 || std::size_t(source) >= model_.images.size()) {
    fail(path_, "texture " + std::to_string(index) + " has no image (or a KHR/EXT image format this loader lacks)",
         "re-export it with PNG or JPEG images");
  }
  if (const auto known = imageTexture_.find(source); known != imageTexture_.end()) return known->second;
  if (texture.sampler >= 0 && std::size_t(texture.sampler) < model_.samplers.size()) {
    const tinygltf::Sampler& sampler = model_.samplers[std::size_t(texture.sampler)];
    if (sampler.wrapS != TINYGLTF_TEXTURE_WRAP_REPEAT || sampler.wrapT != TINYGLTF_TEXTURE_WRAP_REPEAT) {
      scene_.warnings.push_back("glTF texture " + std::to_string(index) +
                                " clamps or mirrors; every method repeats it (docs/methods.md)");
    }
  }
  const tinygltf::Image& image = model_.images[std::size_t(source)];
  if (image.image.empty()) {
    fail(path_, "image '" + imageName(source) + "' could not be read", "put it in the model's folder or embed it");
  }
  Texture decoded = takeDecoded(source);
  if (bytes_ + decoded.rgba.size() > kMaxTextureBytes) {
    fail(path_, "its textures decode to over " + std::to_string(kMaxTextureBytes >> 30) + " GiB",
         "downscale the textures");
  }
  bytes_ += decoded.rgba.size();
  scene_.textures.push_back(std::move(decoded));
  return imageTexture_[source] = std::int32_t(scene_.textures.size() - 1);
}

}  // namespace penumbra::gltf
