// Penumbra as a library: load a scene, configure a renderer with the command line's options, render
// a method into a frame (visibility, shaded image, PIP flags, stats), compare methods against the
// Embree reference. The frames are the CLI's own, bit for bit: the same code resolves the options,
// renders and judges. Link Penumbra::penumbra (find_package(Penumbra CONFIG REQUIRED)).
#pragma once
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

// The API's symbols are the library's only exported ones (the internal libraries are hidden).
#define PENUMBRA_API __attribute__((visibility("default")))

namespace penumbra::api {

// Bad input (a file, an option, a method): the message is the CLI's.
class PENUMBRA_API Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Options as the command line spells them: {{"--res", "512x512"}, {"--light-size", "0.1"}, {"--spp", "16"}}
// (`penumbra render --help`, docs/options.md).
using Options = std::vector<std::pair<std::string, std::string>>;

// A loaded scene: "builtin:NAME[:LEVEL]", a .gltf/.glb, .obj or a format assimp reads.
class PENUMBRA_API Scene {
 public:
  explicit Scene(const std::string& spec);
  ~Scene();
  const std::string& spec() const;
  std::uint64_t triangles() const;
  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  std::shared_ptr<const Impl> impl_;
};

struct Frame {
  std::uint32_t width = 0, height = 0;
  std::vector<float> visibility;      // width * height, row 0 at the top; 1 = lit
  std::vector<std::uint8_t> rgba;     // the shaded image, sRGB, width * height * 4
  std::vector<std::uint8_t> covered;  // 1 where geometry covers the pixel
  std::vector<std::uint8_t> pip;      // methods that classify: PIP flags per pixel (0 = not traced)
  std::string stats;                  // JSON: the method's entry of metrics.json
};

// A renderer of one scene on this machine's Vulkan device, with the options resolved and checked as
// `penumbra render` does (camera and light default to the scene's). Not thread-safe; one at a time
// per device is best.
class PENUMBRA_API Renderer {
 public:
  Renderer(const Scene& scene, const Options& options = {});
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // A method of `penumbra render --method` (sm, pcf, pcss, msm, srt, frt, ref, ...), after the
  // options' --warmup frames on its first call.
  Frame render(const std::string& method);
  // The reference and each method, every method judged against it as `penumbra compare` does (the
  // median of --repeat frames): metrics.json's object as JSON text ("scene", "reference", "methods").
  std::string compare(const std::vector<std::string>& methods);

  // Per frame, for animations: "ex,ey,ez:tx,ty,tz[:fovy]"; a --light string (dir:, point:, spot:, ...).
  void setCamera(const std::string& camera);
  void setLight(const std::string& light);
  std::string camera() const;
  std::string light() const;
  // The run's settings as metrics.json's "scene" object records them (JSON text).
  std::string settings() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra::api
