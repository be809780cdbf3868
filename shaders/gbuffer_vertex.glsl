// The camera pass's vertex stage (gbuffer.vert, gbuffer_textured.vert): world-space attributes for
// the G-buffer. The includer declares the push constants `push` (viewProj, cameraPosition).
layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec3 inColor;
layout(location = 0) out vec3 worldPosition;
layout(location = 1) out vec3 worldNormal;
layout(location = 2) out vec3 albedo;
layout(location = 3) out vec3 fromCamera;
void gbufferVertex() {
  worldPosition = inPosition;
  worldNormal = inNormal;
  albedo = inColor;
  fromCamera = inPosition - push.cameraPosition.xyz;
  gl_Position = push.viewProj * vec4(inPosition, 1.0);
}
