// What the presenter draws over the frame. Shared by the script options, the UI and the presenter,
// so the names on the command line and in the panel are the same.
#pragma once
#include <array>
#include <string>

#include "core/scene.h"

namespace penumbra::demo {

enum class Overlay { None, Pip, PenumbraMask, Thin, Error, Tiles };

inline constexpr std::array<const char*, 6> kOverlayNames = {"none", "pip", "mask", "thin", "error", "tiles"};

inline const char* overlayName(Overlay overlay) { return kOverlayNames[std::size_t(overlay)]; }

inline Overlay parseOverlay(const std::string& name) {
  for (std::size_t i = 0; i < kOverlayNames.size(); ++i) {
    if (name == kOverlayNames[i]) return Overlay(i);
  }
  throw InputError("--overlay '" + name + "' is not an overlay; use none, pip, mask, thin, error or tiles");
}

}  // namespace penumbra::demo
