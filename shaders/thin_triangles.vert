#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/thin.h"
// Thin-triangle pass: clip-space and world positions for the geometry shader, which decides.
layout(location = 0) in vec3 inPosition;
layout(location = 0) out vec3 outWorld;
layout(push_constant) uniform PushBlock { ThinTrianglePush push; };
void main() {
  outWorld = inPosition;
  gl_Position = push.viewProj * vec4(inPosition, 1.0);
}
