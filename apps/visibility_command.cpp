#include "apps/visibility_command.h"

#include <chrono>
#include <iostream>

#include "core/image_io.h"
#include "core/scene_loader.h"
#include "hybrid/frame_output.h"
#include "hybrid/patch_visibility.h"

namespace penumbra {

VisibilityCommand::VisibilityCommand(CLI::App& app) {
  command_ = app.add_subcommand("visibility",
                                "Patch-to-patch visibility: the fraction of unblocked pairs of sample points on two "
                                "rectangles, and images of it (bitmask visibility sampling)");
  command_->add_option("--scene", scene_, "Scene: builtin:NAME[:LEVEL], a .gltf/.glb or .obj file")->capture_default_str();
  command_->add_option("--from", from_, "Source rectangle 'x,y,z:ux,uy,uz:vx,vy,vz' (a corner and two perpendicular edges)")
      ->required();
  command_->add_option("--to", to_, "Target rectangle, as --from")->required();
  command_->add_option("--samples", samples_, "Samples on each rectangle, NxN (or N), N <= 32")->capture_default_str();
  command_->add_option("--out", outDir_, "Output folder")->capture_default_str();
  command_->add_flag("--validate", validate_, "Enable the Vulkan validation layers");
}

int VisibilityCommand::run() {
  // "N" or "NxN": a square grid (the target's samples are a square map's texel centres).
  const std::size_t x = samples_.find('x');
  std::uint32_t n = 0;
  try {
    std::size_t used = 0;
    n = std::uint32_t(std::stoul(samples_.substr(0, x), &used));
    if (used != samples_.substr(0, x).size() || (x != std::string::npos && samples_.substr(x + 1) != samples_.substr(0, x))) n = 0;
  } catch (const std::exception&) {
    n = 0;
  }
  if (n < 1 || n > 32) throw InputError("visibility: --samples '" + samples_ + "' is not N or NxN with N in 1..32 (e.g. 32x32)");
  const Scene scene = loadScene(scene_);
  const Patch from = parsePatch(from_, scene.origin), to = parsePatch(to_, scene.origin);
  gpu::Context context({.validate = validate_});
  StagedOutput out(outDir_);
  const auto start = std::chrono::steady_clock::now();
  const PatchVisibility v = patchVisibility(context, scene, from, to, n);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  const std::uint32_t count = n * n;
  std::vector<float> perTarget(count);
  std::vector<std::uint8_t> mask(std::size_t(count) * count * 4, 255);
  for (std::uint32_t i = 0; i < count; ++i) {
    std::uint32_t seen = 0;
    for (std::uint32_t s = 0; s < count; ++s) {
      const bool blocked = v.blocked(i, s);
      seen += !blocked;
      for (int c = 0; c < 3; ++c) mask[(std::size_t(i) * count + s) * 4 + c] = blocked ? 0 : 255;
    }
    perTarget[i] = float(seen) / float(count);
  }
  writePngGray16(out.path() + "/visibility.png", int(n), int(n), perTarget);
  writePngRgba8(out.path() + "/mask.png", int(count), int(count), mask);
  writeJson(out.path() + "/visibility.json", {{"scene", scene_},
                                              {"from", from_},
                                              {"to", to_},
                                              {"samples_per_side", n},
                                              {"pairs", v.pairs},
                                              {"unblocked_pairs", v.unblockedPairs},
                                              {"unblocked_fraction", v.fraction()},
                                              {"ms", ms},
                                              {"device", context.deviceName()}});
  out.commit();
  std::cout << "unblocked pairs: " << v.unblockedPairs << " of " << v.pairs << " (" << v.fraction() << "), " << n << "x" << n
            << " samples per patch, " << ms << " ms\nwrote " << outDir_ << "/\n";
  const auto messages = context.validationMessages();
  if (!messages.empty()) {
    std::cerr << "penumbra: " << messages.size() << " Vulkan validation message(s), see above\n";
    return 3;
  }
  return 0;
}

}  // namespace penumbra
