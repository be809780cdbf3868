// Test-only (tests/test_gpu_timer.cpp): a compute pass whose cost is set by a push constant, so a
// test can make one pass of a frame deliberately slow and check which timer row its time lands in.
#version 450
layout(local_size_x = 64) in;
layout(push_constant) uniform Push {
  uint iterations;
  uint count;
} pc;
layout(std430, binding = 0) buffer Values { float values[]; };

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  float x = values[i];
  // A dependent chain the compiler cannot shorten (the trip count is only known at run time).
  for (uint k = 0u; k < pc.iterations; ++k) x = fract(x * 1.618034 + 0.3183099);
  values[i] = x;
}
