// glTF base colour textures: the images materials take their base colour from, decoded on all cores
// before the node walk (decoding is most of loading a textured model), each becoming one scene
// texture however many materials use it; and texture references' KHR_texture_transform.
#pragma once
#include <tiny_gltf.h>

#include <cstdint>
#include <glm/glm.hpp>
#include <map>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include "core/scene.h"
#include "core/texture.h"

namespace penumbra::gltf {

// tinygltf's image loader that keeps images encoded: only those Textures decodes cost anything, so
// images for other maps (normals, roughness) are never decoded.
bool keepEncodedImage(tinygltf::Image* image, int, std::string*, std::string*, int, int, const unsigned char* bytes,
                      int size, void*);

// A texture reference's KHR_texture_transform (offset, rotation, scale, composed T * R * S, and the
// texCoord set it may select instead); identity without the extension.
struct TextureTransform {
  glm::dvec2 offset{0.0}, scale{1.0};
  double rotation = 0.0;
  int texCoord = 0;

  explicit TextureTransform(const tinygltf::TextureInfo& info);
  void bake(std::vector<glm::vec2>& uvs) const;
};

class Textures {
 public:
  // Decodes every image a primitive's material takes its base colour from; what fails keeps its
  // error for texture().
  Textures(const tinygltf::Model& model, const std::string& path, Scene& scene);

  // The scene texture of glTF texture `index`, its image decoded once however many materials use it.
  // Where the image cannot be had, a `required` one (MASK's) fails with InputError; any other warns
  // and returns -1 (the mesh keeps its base colour, and a BLEND mesh its alpha factor alone).
  std::int32_t texture(int index, bool required);

 private:
  std::int32_t decodedTexture(int index);
  Texture takeDecoded(int source);
  std::string imageName(int source) const;

  const tinygltf::Model& model_;
  const std::string& path_;
  Scene& scene_;
  std::map<int, std::int32_t> imageTexture_;                   // glTF image -> Scene::textures index, once decoded
  std::set<int> warned_;                                       // textures that could not be had, warned of once
  std::map<int, std::variant<Texture, std::string>> decoded_;  // glTF image -> its texture or error
  std::uint64_t bytes_ = 0;
};

}  // namespace penumbra::gltf
