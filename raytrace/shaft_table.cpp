#include "raytrace/shaft_table.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

#include "raytrace/ntree_builder.h"
#include "shared/linespace.h"

namespace penumbra {
namespace {

ShaftTable::Patch patchBox(std::uint32_t face, std::uint32_t patch, std::uint32_t n) {
  const std::uint32_t axis = face / 2, u = (axis + 1) % 3, v = (axis + 2) % 3;
  ShaftTable::Patch p;
  p.face = face;
  p.lo[axis] = p.hi[axis] = double(face % 2);
  p.lo[u] = double(patch % n) / n;
  p.hi[u] = double(patch % n + 1) / n;
  p.lo[v] = double(patch / n) / n;
  p.hi[v] = double(patch / n + 1) / n;
  return p;
}

constexpr double kNever = std::numeric_limits<double>::infinity();

// Narrows the open interval (t0, t1) to the t where alpha + beta t < gamma.
void constrain(double alpha, double beta, double gamma, double& t0, double& t1) {
  if (beta > 0.0) t1 = std::min(t1, (gamma - alpha) / beta);
  else if (beta < 0.0) t0 = std::max(t0, (gamma - alpha) / beta);
  else if (!(alpha < gamma)) t0 = kNever;
}

}  // namespace

void ShaftTable::decode(std::uint32_t shaft, std::uint32_t n, Patch& a, Patch& b) {
  const std::uint32_t n2 = n * n, n4 = n2 * n2;
  const std::uint32_t pair = shaft / n4, rest = shaft % n4;
  std::uint32_t fa = 0, fb = 1;
  for (std::uint32_t i = 0; i < 6; ++i) {
    for (std::uint32_t j = i + 1; j < 6; ++j) {
      if (shared::lsFacePair(i, j) == pair) fa = i, fb = j;
    }
  }
  a = patchBox(fa, rest / n2, n);
  b = patchBox(fb, rest % n2, n);
}

ShaftTable::ShaftTable(std::uint32_t n)
    : n_(n),
      shafts_((NTreeBuilder::validate(n, LS_MIN_DEPTH), shared::lsShaftCount(n))),  // before any allocation
      cellWords_((n * n * n + 63) / 64),
      shaftWords_((shared::lsShaftCount(n) + 63) / 64),
      shaftCells_(std::size_t(shafts_) * cellWords_, 0),
      cellShafts_(std::size_t(n * n * n) * shaftWords_, 0) {
  const auto start = std::chrono::steady_clock::now();
  // Work items of 64 shafts: each owns whole words of cellShafts_, so workers never share a word.
  std::atomic<std::uint32_t> next{0};
  auto work = [&] {
    std::vector<double> t0(3 * n), t1(3 * n);
    for (std::uint32_t word = next++; word < shaftWords_; word = next++) {
      for (std::uint32_t s = word * 64; s < std::min(shafts_, word * 64 + 64); ++s) {
        Patch a, b;
        decode(s, n, a, b);
        const glm::dvec3 loA = a.lo, hiA = a.hi, loB = b.lo, hiB = b.hi;
        // Per axis and cell row c: the open t-interval in which the slice (1-t)A + tB overlaps the
        // open slab (c/N, (c+1)/N).
        for (int k = 0; k < 3; ++k) {
          for (std::uint32_t c = 0; c < n; ++c) {
            double lo = -kNever, hi = kNever;
            constrain(loA[k], loB[k] - loA[k], double(c + 1) / n, lo, hi);  // slice low < cell high
            constrain(-hiA[k], hiA[k] - hiB[k], -double(c) / n, lo, hi);   // slice high > cell low
            t0[k * n + c] = lo;
            t1[k * n + c] = hi;
          }
        }
        for (std::uint32_t z = 0; z < n; ++z) {
          for (std::uint32_t y = 0; y < n; ++y) {
            for (std::uint32_t x = 0; x < n; ++x) {
              const double lo = std::max(t0[x], std::max(t0[n + y], t0[2 * n + z]));
              const double hi = std::min(t1[x], std::min(t1[n + y], t1[2 * n + z]));
              if (!(lo < hi && lo < 1.0 && hi > 0.0)) continue;  // (lo, hi) misses [0, 1]
              const std::uint32_t cell = shared::lsCellIndex(x, y, z, n);
              shaftCells_[std::size_t(s) * cellWords_ + cell / 64] |= std::uint64_t(1) << (cell % 64);
              cellShafts_[std::size_t(cell) * shaftWords_ + s / 64] |= std::uint64_t(1) << (s % 64);
            }
          }
        }
      }
    }
  };
  std::vector<std::thread> threads;
  for (unsigned w = 1; w < std::max(1u, std::thread::hardware_concurrency()); ++w) threads.emplace_back(work);
  work();
  for (std::thread& thread : threads) thread.join();
  buildMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

std::uint32_t ShaftTable::cellsOf(std::uint32_t shaft) const {
  std::uint32_t count = 0;
  for (std::uint32_t w = 0; w < cellWords_; ++w) count += std::uint32_t(std::popcount(shaftCells_[std::size_t(shaft) * cellWords_ + w]));
  return count;
}

const ShaftTable& ShaftTable::get(std::uint32_t n) {
  NTreeBuilder::validate(n, LS_MIN_DEPTH);
  static std::mutex mutex;
  static std::map<std::uint32_t, std::unique_ptr<ShaftTable>> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  auto& table = cache[n];
  if (!table) table = std::make_unique<ShaftTable>(n);
  return *table;
}

}  // namespace penumbra
