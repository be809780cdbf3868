#include "core/flip.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace penumbra {
namespace {

constexpr double kPi = std::numbers::pi;

// sRGB primaries, D65 (IEC 61966-2-1); the white point is the XYZ of linear (1, 1, 1).
constexpr double kRgbToXyz[3][3] = {{0.4124564, 0.3575761, 0.1804375},
                                    {0.2126729, 0.7151522, 0.0721750},
                                    {0.0193339, 0.1191920, 0.9503041}};
constexpr double kXyzToRgb[3][3] = {{3.2404542, -1.5371385, -0.4985314},
                                    {-0.9692660, 1.8760108, 0.0415560},
                                    {0.0556434, -0.2040259, 1.0572252}};
constexpr double kWhite[3] = {kRgbToXyz[0][0] + kRgbToXyz[0][1] + kRgbToXyz[0][2],
                              kRgbToXyz[1][0] + kRgbToXyz[1][1] + kRgbToXyz[1][2],
                              kRgbToXyz[2][0] + kRgbToXyz[2][1] + kRgbToXyz[2][2]};

// The paper's constants (LDR-FLIP).
constexpr double kQc = 0.7, kPc = 0.4, kPt = 0.95, kQf = 0.5;
constexpr double kFeatureWidthDegrees = 0.082;
struct CsfChannel {
  double a1, b1, a2, b2;
};
constexpr CsfChannel kCsf[3] = {{1.0, 0.0047, 0.0, 1e-5}, {1.0, 0.0053, 0.0, 1e-5}, {34.1, 0.04, 13.5, 0.025}};
constexpr double kCsfMaxB = 0.04;

using Vec3 = std::array<double, 3>;

double srgbToLinear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

Vec3 multiply(const double (&m)[3][3], const Vec3& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

Vec3 xyzToYcxcz(const Vec3& xyz) {
  const double x = xyz[0] / kWhite[0], y = xyz[1] / kWhite[1], z = xyz[2] / kWhite[2];
  return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}

Vec3 ycxczToXyz(const Vec3& c) {
  const double y = (c[0] + 16.0) / 116.0;
  return {(c[1] / 500.0 + y) * kWhite[0], y * kWhite[1], (y - c[2] / 200.0) * kWhite[2]};
}

double labF(double t) {
  constexpr double d = 6.0 / 29.0;
  return t > d * d * d ? std::cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
}

// Linear RGB -> CIELAB with the Hunt adjustment of a* and b*.
Vec3 huntLab(const Vec3& linearRgb) {
  const Vec3 xyz = multiply(kRgbToXyz, linearRgb);
  const double fx = labF(xyz[0] / kWhite[0]), fy = labF(xyz[1] / kWhite[1]), fz = labF(xyz[2] / kWhite[2]);
  const double l = 116.0 * fy - 16.0;
  return {l, 0.01 * l * 500.0 * (fx - fy), 0.01 * l * 200.0 * (fy - fz)};
}

double hyab(const Vec3& a, const Vec3& b) {
  return std::abs(a[0] - b[0]) + std::hypot(a[1] - b[1], a[2] - b[2]);
}

// A planar float image with edge-replicating separable convolution.
struct Plane {
  std::uint32_t w = 0, h = 0;
  std::vector<float> v;
  Plane(std::uint32_t width, std::uint32_t height) : w(width), h(height), v(std::size_t(width) * height, 0.0f) {}
  float& at(std::uint32_t x, std::uint32_t y) { return v[std::size_t(y) * w + x]; }
  float at(std::uint32_t x, std::uint32_t y) const { return v[std::size_t(y) * w + x]; }
};

// kernel has 2r+1 taps, centre at r; borders replicate the edge pixel.
Plane convolve(const Plane& in, const std::vector<double>& kx, const std::vector<double>& ky) {
  const int rx = int(kx.size() / 2), ry = int(ky.size() / 2);
  Plane tmp(in.w, in.h), out(in.w, in.h);
  const int w = int(in.w), h = int(in.h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      double s = 0.0;
      for (int i = -rx; i <= rx; ++i) s += kx[std::size_t(i + rx)] * in.at(std::uint32_t(std::clamp(x + i, 0, w - 1)), std::uint32_t(y));
      tmp.at(std::uint32_t(x), std::uint32_t(y)) = float(s);
    }
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      double s = 0.0;
      for (int i = -ry; i <= ry; ++i) s += ky[std::size_t(i + ry)] * tmp.at(std::uint32_t(x), std::uint32_t(std::clamp(y + i, 0, h - 1)));
      out.at(std::uint32_t(x), std::uint32_t(y)) = float(s);
    }
  }
  return out;
}

// exp(-pi^2 (i/ppd)^2 / b) for i in [-r, r]: one factor of a separable CSF Gaussian term.
std::vector<double> csfFactor(double b, double ppd, int r) {
  std::vector<double> k(std::size_t(2 * r + 1));
  for (int i = -r; i <= r; ++i) {
    const double x = double(i) / ppd;
    k[std::size_t(i + r)] = std::exp(-kPi * kPi * x * x / b);
  }
  return k;
}

// One channel's CSF filter: sum over its Gaussian terms of a sqrt(pi/b) G(x) G(y), normalised so
// the whole 2-D kernel sums to 1.
Plane csfFilter(const Plane& in, const CsfChannel& c, double ppd, int r) {
  struct Term {
    double weight;
    std::vector<double> factor;
  };
  std::vector<Term> terms;
  double total = 0.0;
  for (auto [a, b] : {std::pair{c.a1, c.b1}, std::pair{c.a2, c.b2}}) {
    if (a == 0.0) continue;
    Term t{a * std::sqrt(kPi / b), csfFactor(b, ppd, r)};
    double s = 0.0;
    for (double v : t.factor) s += v;
    total += t.weight * s * s;
    terms.push_back(std::move(t));
  }
  Plane out(in.w, in.h);
  for (const Term& t : terms) {
    const Plane part = convolve(in, t.factor, t.factor);
    const float scale = float(t.weight / total);
    for (std::size_t i = 0; i < out.v.size(); ++i) out.v[i] += scale * part.v[i];
  }
  return out;
}

// Feature kernels: Gaussian (sums to 1), its first derivative and its second derivative, the
// derivatives with positive weights summing to 1 and negative ones to -1.
struct FeatureKernels {
  std::vector<double> gauss, edge, point;
};

FeatureKernels featureKernels(double ppd) {
  const double sigma = 0.5 * kFeatureWidthDegrees * ppd;
  const int r = std::max(1, int(std::ceil(3.0 * sigma)));
  FeatureKernels k;
  for (int i = -r; i <= r; ++i) {
    const double x = double(i), g = std::exp(-x * x / (2.0 * sigma * sigma));
    k.gauss.push_back(g);
    k.edge.push_back(-x * g);
    k.point.push_back((x * x / (sigma * sigma) - 1.0) * g);
  }
  auto normalise = [](std::vector<double>& v, bool signedParts) {
    double pos = 0.0, neg = 0.0;
    for (double w : v) (w > 0.0 ? pos : neg) += w;
    for (double& w : v) {
      if (w > 0.0) w /= pos;
      else if (w < 0.0 && signedParts) w /= -neg;
    }
  };
  normalise(k.gauss, false);
  normalise(k.edge, true);
  normalise(k.point, true);
  return k;
}

void checkImage(const char* what, std::size_t bytes, std::uint32_t width, std::uint32_t height) {
  if (bytes != std::size_t(width) * height * 4) {
    throw std::invalid_argument(std::string("flipMap: ") + what + " has " + std::to_string(bytes) + " bytes, expected " +
                                std::to_string(width) + "x" + std::to_string(height) + "x4");
  }
}

struct Prepared {
  Plane channel[3];  // YyCxCz, unfiltered
  Plane luminance;   // Y / Yn, for the feature detectors
};

Prepared prepare(std::span<const std::uint8_t> rgba, std::uint32_t w, std::uint32_t h) {
  Prepared p{{Plane(w, h), Plane(w, h), Plane(w, h)}, Plane(w, h)};
  std::array<double, 256> linear;
  for (int i = 0; i < 256; ++i) linear[std::size_t(i)] = srgbToLinear(double(i) / 255.0);
  for (std::size_t i = 0; i < std::size_t(w) * h; ++i) {
    const Vec3 rgb = {linear[rgba[4 * i]], linear[rgba[4 * i + 1]], linear[rgba[4 * i + 2]]};
    const Vec3 xyz = multiply(kRgbToXyz, rgb);
    const Vec3 c = xyzToYcxcz(xyz);
    for (int k = 0; k < 3; ++k) p.channel[k].v[i] = float(c[std::size_t(k)]);
    p.luminance.v[i] = float(xyz[1] / kWhite[1]);
  }
  return p;
}

// Per pixel: Hunt-adjusted L*a*b* of the CSF-filtered image.
std::vector<Vec3> filteredLab(const Prepared& p, double ppd) {
  const int r = std::max(1, int(std::ceil(3.0 * std::sqrt(kCsfMaxB / (2.0 * kPi * kPi)) * ppd)));
  Plane filtered[3] = {csfFilter(p.channel[0], kCsf[0], ppd, r), csfFilter(p.channel[1], kCsf[1], ppd, r),
                       csfFilter(p.channel[2], kCsf[2], ppd, r)};
  std::vector<Vec3> lab(p.luminance.v.size());
  for (std::size_t i = 0; i < lab.size(); ++i) {
    Vec3 rgb = multiply(kXyzToRgb, ycxczToXyz({filtered[0].v[i], filtered[1].v[i], filtered[2].v[i]}));
    for (double& c : rgb) c = std::clamp(c, 0.0, 1.0);
    lab[i] = huntLab(rgb);
  }
  return lab;
}

struct Features {
  Plane edge, point;  // magnitudes
};

Features features(const Plane& y, const FeatureKernels& k) {
  const Plane ex = convolve(y, k.edge, k.gauss), ey = convolve(y, k.gauss, k.edge);
  const Plane px = convolve(y, k.point, k.gauss), py = convolve(y, k.gauss, k.point);
  Features f{Plane(y.w, y.h), Plane(y.w, y.h)};
  for (std::size_t i = 0; i < y.v.size(); ++i) {
    f.edge.v[i] = std::hypot(ex.v[i], ey.v[i]);
    f.point.v[i] = std::hypot(px.v[i], py.v[i]);
  }
  return f;
}

std::uint8_t toByte(double v) { return std::uint8_t(std::lround(std::clamp(v, 0.0, 255.0))); }

}  // namespace

double flipPixelsPerDegree(double distanceMeters, double widthMeters, double widthPixels) {
  if (!(distanceMeters > 0.0 && widthMeters > 0.0 && widthPixels > 0.0)) {
    throw std::invalid_argument("flipPixelsPerDegree: distance, width and pixels must be positive");
  }
  return distanceMeters * (widthPixels / widthMeters) * kPi / 180.0;
}

std::vector<float> flipMap(std::span<const std::uint8_t> testRgba, std::span<const std::uint8_t> referenceRgba,
                           std::uint32_t width, std::uint32_t height, const FlipSettings& settings) {
  checkImage("test image", testRgba.size(), width, height);
  checkImage("reference image", referenceRgba.size(), width, height);
  const double ppd = settings.pixelsPerDegree;
  if (!(ppd > 0.0) || !std::isfinite(ppd)) throw std::invalid_argument("flipMap: pixels per degree must be positive");
  if (width == 0 || height == 0) return {};

  const Prepared ref = prepare(referenceRgba, width, height), test = prepare(testRgba, width, height);
  const std::vector<Vec3> refLab = filteredLab(ref, ppd), testLab = filteredLab(test, ppd);
  const FeatureKernels kernels = featureKernels(ppd);
  const Features refF = features(ref.luminance, kernels), testF = features(test.luminance, kernels);

  // The largest colour difference: Hunt-adjusted pure green against pure blue.
  const double cmax = std::pow(hyab(huntLab({0.0, 1.0, 0.0}), huntLab({0.0, 0.0, 1.0})), kQc);
  std::vector<float> out(refLab.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double c = std::pow(hyab(refLab[i], testLab[i]), kQc);
    const double colour = c < kPc * cmax ? kPt / (kPc * cmax) * c
                                         : std::min(1.0, kPt + (c - kPc * cmax) / (cmax - kPc * cmax) * (1.0 - kPt));
    const double edge = std::abs(double(refF.edge.v[i]) - double(testF.edge.v[i]));
    const double point = std::abs(double(refF.point.v[i]) - double(testF.point.v[i]));
    const double feature = std::min(1.0, std::pow(std::max(edge, point) / std::numbers::sqrt2, kQf));
    // 0^0 would be 1: a pixel with no colour difference scores 0 whatever its features.
    out[i] = colour == 0.0 ? 0.0f : float(std::pow(colour, 1.0 - feature));
  }
  return out;
}

double flipMean(std::span<const float> map, std::span<const std::uint8_t> covered) {
  if (map.size() != covered.size()) throw std::invalid_argument("flipMean: map and coverage differ in size");
  double sum = 0.0;
  std::uint64_t n = 0;
  for (std::size_t i = 0; i < map.size(); ++i) {
    if (!covered[i]) continue;
    sum += map[i];
    ++n;
  }
  return n ? sum / double(n) : 0.0;
}

std::vector<std::uint8_t> flipHeatmap(std::span<const float> map, std::span<const std::uint8_t> covered) {
  if (map.size() != covered.size()) throw std::invalid_argument("flipHeatmap: map and coverage differ in size");
  // Anchors of a magma-like ramp at 0, 1/4, 1/2, 3/4, 1, interpolated linearly.
  constexpr double kRamp[5][3] = {{0, 0, 4}, {81, 18, 124}, {183, 55, 121}, {252, 137, 97}, {252, 253, 191}};
  std::vector<std::uint8_t> rgba(map.size() * 4);
  for (std::size_t i = 0; i < map.size(); ++i) {
    std::uint8_t* px = &rgba[4 * i];
    px[3] = 255;
    if (!covered[i]) {
      px[0] = 40;
      px[1] = 44;
      px[2] = 60;
      continue;
    }
    const double v = std::isnan(map[i]) ? 1.0 : std::clamp(double(map[i]), 0.0, 1.0);
    const double t = v * 4.0;
    const int k = std::min(3, int(t));
    const double f = t - double(k);
    for (int c = 0; c < 3; ++c) px[c] = toByte(kRamp[k][c] + f * (kRamp[k + 1][c] - kRamp[k][c]));
  }
  return rgba;
}

}  // namespace penumbra
