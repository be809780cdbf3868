// The shadow denoiser for few-sample soft shadows. With --denoise temporal, each noisy
// pixel's samples are first averaged over frames, reprojected through the G-buffer, the history
// dropped on disocclusion and clipped where the current neighbourhood disagrees with it
// (shaders/denoise_accumulate.comp); then a spatial filter inside the penumbra mask gathers about
// targetSamples samples per pixel, within the penumbra's width from the blocker distances the trace
// wrote, with depth and normal edge-stopping (shaders/denoise_spatial.comp). --denoise spatial is
// the filter alone. Pixels outside the mask stay exact; so do pixels whose taps reach only 8x8 tiles
// of one value (the accumulation writes each tile's range): the filter leaves them as they are. One
// pass object per method, so that each method's history is its own.
#pragma once
#include <cstdint>
#include <glm/glm.hpp>
#include <string>

#include "core/camera.h"
#include "core/options.h"
#include "gpu/pipeline.h"
#include "raster/gbuffer_pass.h"
#include "shared/light.h"

namespace penumbra {

enum class DenoiseMode { Off, Spatial, Temporal };
std::string denoiseModeName(DenoiseMode mode);

struct DenoiseSettings {
  DenoiseMode mode = DenoiseMode::Off;
  float maxRadius = 16.0f;      // pixels
  float maxHistory = 32.0f;     // frames the temporal average spans at most (a still view converges over them)
  // While the light moves, the history follows the shadows (each pixel's is fetched where the
  // shadow now on it fell, from its blocker distance) and spans at most the frames over which the
  // light moves by this fraction of its own angular size (seen from the scene's centre): what the
  // shift misses (penumbrae widening, blockers of another distance) fades within them (1 frame
  // when it jumps). 0.7: under a light circling 0.25 degrees a frame, courtyard and bunny at 512^2,
  // lights 0.05 and 0.1, 1 spp, the shadows change from frame to frame 1.07-1.19x as much as the
  // reference's and the moving frames' rmse is 0.023-0.033 (0.35 without following them: flicker
  // 0.93-1.56x, rmse 0.028-0.046; 1.0 flickers a little less but keeps a trail after a light that
  // jumps 3 degrees a frame stops).
  float motionFraction = 0.7f;
  bool followShadows = true;  // false: the history stays at its surface point (tests show what following buys)
  // false: the spatial filter runs on every noisy pixel, also where the values all around agree
  // (tests: skipping those changes no pixel by more than DENOISE_UNIFORM)
  bool skipAgreeing = true;
  // Shadows are followed only where the nearby blocker distances span at most this fraction of
  // their mean: on the maple's foliage one shift for blockers at many distances moved the history
  // wrongly (moving frames' rmse at light 0.1: 0.060 not following, 0.081 following everywhere,
  // 0.065 with 0.5; courtyard 0.033, 0.026, 0.028; bunny 0.029, 0.023, 0.024).
  float followSpread = 0.5f;
  // Tuned on the courtyard at 512^2, light 0.1, 1 spp, 8th frame (bench/results/denoise.md): a
  // tighter clip (1.5) biases the average; a wider radius blurs the wires' shadows.
  float clipSigmas = 3.0f;      // after the light, the geometry or the camera moved: history clipped to
                                // the current neighbourhood's mean +- this many deviations
  float targetSamples = 64.0f;  // light samples the spatial filter gathers per pixel (with earlier frames')
  float widthFraction = 0.25f;  // its radius stays below this fraction of the penumbra's width
};

// The command line's options of the denoiser (--denoise).
const Options<DenoiseSettings>& denoiseOptions();

class DenoisePass {
 public:
  DenoisePass(const gpu::Context& context, std::uint32_t width, std::uint32_t height);

  struct Inputs {
    const raster::GBufferPass& gbuffer;
    const gpu::Buffer& frameData;   // shared::FrameData
    const gpu::Buffer& visibility;  // denoised in place
    const gpu::Buffer& flags;       // trace flags per pixel (srt's mask), read when useFlags
    const gpu::Buffer& blockers;    // mean blocker distance per traced pixel (0: none known)
    bool useFlags;
    const ViewMatrices& view;
    const shared::GpuLight& light;  // a light that moved since the previous frame shortens the history
    std::uint64_t sceneVersion;     // changes when the geometry moves (Renderer::sceneMoved)
  };
  // Records the filter (settings.mode Spatial or Temporal) over inputs.visibility.
  void record(const vk::raii::CommandBuffer& cmd, const Inputs& inputs, const DenoiseSettings& settings);
  std::uint64_t bytes() const;

 private:
  std::uint32_t width_, height_;
  gpu::ComputePipeline accumulate_, spatial_;
  gpu::Buffer accumulated_;
  gpu::Buffer history_[2];
  gpu::Buffer ranges_;         // per DENOISE_GROUP_SIZE^2 tile: its accumulated values' range (float bits)
  std::uint32_t current_ = 0;  // history_[current_] holds the last frame's
  bool historyValid_ = false;
  glm::mat4 previousViewProj_{1.0f};
  shared::GpuLight previousLight_{};
  std::uint64_t previousSceneVersion_ = 0;
};

}  // namespace penumbra
