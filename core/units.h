// Small formatting and timing helpers that reports and error messages share.
#pragma once
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace penumbra {

// "12.3 MB" (10^6 bytes), as memory figures are given in messages and notes.
inline std::string megabytes(std::uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f MB", double(bytes) / 1e6);
  return text;
}

// Milliseconds of wall time since `start`.
inline double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace penumbra
