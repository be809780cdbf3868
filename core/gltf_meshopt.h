// EXT_meshopt_compression (what `gltfpack -c` / `-cc` writes): decodes a glTF document's
// compressed bufferViews with meshoptimizer into the rewrite's buffer 0 and points the views at
// them; the fallback buffers (which hold no data) are emptied. Every failure is an InputError
// naming the view.
#pragma once
#include <cstddef>

#include "core/gltf_rewrite.h"

namespace penumbra::gltf {

struct DecodeStats {
  std::size_t items = 0;         // bufferViews (meshopt) or primitives (Draco) decoded
  std::size_t decodedBytes = 0;  // their bytes
};

DecodeStats decodeMeshopt(GlbRewrite& rewrite);

}  // namespace penumbra::gltf
