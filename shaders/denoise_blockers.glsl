// The denoiser's shared reads (hybrid/denoise_pass.h), included by its kernels after `frame`, `push`
// (with useFlags), `flags` and `blockers` are declared.

// Whether the pixel's visibility is noisy: srt's penumbra mask, or every covered pixel for frt.
bool noisy(uint index) { return push.useFlags == 0u || flags[index] != 0u; }

// The blocker distances the trace found among the 3x3 noisy pixels 2 apart around pix: their mean
// (.x; 0: none), nearest (.y), farthest (.z) and how many (.w).
vec4 nearbyBlockers(ivec2 pix) {
  ivec2 size = ivec2(frame.width, frame.height);
  float sum = 0.0, count = 0.0, nearest = 1e30, farthest = 0.0;
  for (int dy = -2; dy <= 2; dy += 2) {
    for (int dx = -2; dx <= 2; dx += 2) {
      ivec2 q = clamp(pix + ivec2(dx, dy), ivec2(0), size - 1);
      uint qi = uint(q.y) * frame.width + uint(q.x);
      float b = noisy(qi) ? blockers[qi] : 0.0;
      if (b > 0.0) {
        sum += b;
        count += 1.0;
        nearest = min(nearest, b);
        farthest = max(farthest, b);
      }
    }
  }
  return count > 0.0 ? vec4(sum / count, nearest, farthest, count) : vec4(0.0);
}
