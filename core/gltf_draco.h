// KHR_draco_mesh_compression (what Blender's exporter, gltf-pipeline, glTF-Transform and
// draco_transcoder write): decodes each compressed primitive's Draco stream with Debian's libdraco
// into the rewrite's buffer 0 and points the primitive's accessors at it - attributes in the
// component type their accessor declares, indices as 32-bit - so tinygltf reads a plain triangle
// list. Every failure, a stream that does not decode or counts that disagree with it, is an
// InputError naming the primitive.
#pragma once
#include "core/gltf_meshopt.h"
#include "core/gltf_rewrite.h"

namespace penumbra::gltf {

DecodeStats decodeDraco(GlbRewrite& rewrite);

}  // namespace penumbra::gltf
