#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/raster.h"
// Camera pass: world-space attributes for the G-buffer.
layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec3 inColor;
layout(push_constant) uniform PushBlock { GBufferPush push; };
layout(location = 0) out vec3 worldPosition;
layout(location = 1) out vec3 worldNormal;
layout(location = 2) out vec3 albedo;
layout(location = 3) out vec3 fromCamera;
void main() {
  worldPosition = inPosition;
  worldNormal = inNormal;
  albedo = inColor;
  fromCamera = inPosition - push.cameraPosition.xyz;
  gl_Position = push.viewProj * vec4(inPosition, 1.0);
}
