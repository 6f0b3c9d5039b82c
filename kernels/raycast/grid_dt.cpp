#include "grid_dt.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace polyloc {
namespace {

constexpr float kBig = 1e20f;  // 'no occupied cell', finite so no inf - inf

// 1D squared distance transform of f (n samples, stride apart) in place.
void dt1(float* f, size_t n, size_t stride, std::vector<float>& d, std::vector<size_t>& v,
         std::vector<float>& z) {
  d.resize(n);
  v.resize(n);
  z.resize(n + 1);
  size_t k = 0;
  v[0] = 0;
  z[0] = -kBig;
  z[1] = kBig;
  const auto F = [&](size_t q) { return f[q * stride]; };
  const auto cross = [&](size_t q, size_t p) {
    return ((F(q) + float(q) * float(q)) - (F(p) + float(p) * float(p))) / (2.f * float(q) - 2.f * float(p));
  };
  for (size_t q = 1; q < n; ++q) {
    float s = cross(q, v[k]);
    while (s <= z[k]) s = cross(q, v[--k]);  // z[0] = -big ends the loop at k = 0
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = kBig;
  }
  k = 0;
  for (size_t q = 0; q < n; ++q) {
    while (z[k + 1] < float(q)) ++k;
    const float dq = float(q) - float(v[k]);
    d[q] = dq * dq + F(v[k]);
  }
  for (size_t q = 0; q < n; ++q) f[q * stride] = d[q];
}

}  // namespace

std::vector<float> gridDistanceTransform(const std::vector<uint8_t>& occupied, size_t nx,
                                         size_t ny, float resolution) {
  std::vector<float> f(nx * ny);
  bool any = false;
  for (size_t i = 0; i < f.size(); ++i) {
    f[i] = occupied[i] ? 0.f : kBig;
    any = any || occupied[i];
  }
  if (!any) return std::vector<float>(nx * ny, std::numeric_limits<float>::infinity());
  std::vector<float> d, z;
  std::vector<size_t> v;
  for (size_t x = 0; x < nx; ++x) dt1(f.data() + x, ny, nx, d, v, z);
  for (size_t y = 0; y < ny; ++y) dt1(f.data() + y * nx, nx, 1, d, v, z);
  for (size_t i = 0; i < f.size(); ++i)
    f[i] = occupied[i] ? 0.f : std::max(0.f, (std::sqrt(f[i]) - 0.5f) * resolution);
  return f;
}

}  // namespace polyloc
