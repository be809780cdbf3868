#version 450
// Bitmask visibility sampling: world positions for the geometry shader, which places each caster's
// influence region on the receiver's hidden-samples map.
layout(location = 0) in vec3 inPosition;
layout(location = 0) out vec3 outWorld;
void main() {
  outWorld = inPosition;
  gl_Position = vec4(0.0, 0.0, 0.0, 1.0);  // the geometry shader places the region
}
