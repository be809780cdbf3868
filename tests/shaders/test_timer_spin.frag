// Test-only (tests/test_gpu_timer.cpp): a raster pass whose cost is set by a push constant (the
// per-fragment loop of timer_spin.comp), so a test can make a draw deliberately slow.
#version 450
layout(push_constant) uniform Push {
  uint iterations;
  uint count;
} pc;
layout(location = 0) out vec4 colour;

void main() {
  float x = fract(gl_FragCoord.x * 0.0137 + gl_FragCoord.y * 0.0071);
  for (uint k = 0u; k < pc.iterations; ++k) x = fract(x * 1.618034 + 0.3183099);
  colour = vec4(x, 0.0, 0.0, 1.0);
}
