#include "gdm/distance_transform.h"

#include <algorithm>
#include <limits>

namespace gdm {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// One line of the separable squared Euclidean distance transform
// (Felzenszwalb and Huttenlocher): d[i] = min_j f[j] + ((i - j) h)^2 over the
// sites j with a finite f[j]; d stays infinite when there is none.
// `v` and `z` are work arrays of at least n and n + 1 entries.
void distance_line(const double* f, double* d, int n, double h, std::vector<int>& v, std::vector<double>& z) {
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (!(f[q] < kInf)) continue;
    const double xq = q * h;
    if (k < 0) {
      k = 0;
      v[0] = q;
      z[0] = -kInf;
      z[1] = kInf;
      continue;
    }
    double s;
    while (true) {
      const double xv = v[static_cast<std::size_t>(k)] * h;
      s = ((f[q] + xq * xq) - (f[v[static_cast<std::size_t>(k)]] + xv * xv)) / (2.0 * (xq - xv));
      if (s <= z[static_cast<std::size_t>(k)]) {  // z[0] = -inf ends the loop
        --k;
        continue;
      }
      break;
    }
    ++k;
    v[static_cast<std::size_t>(k)] = q;
    z[static_cast<std::size_t>(k)] = s;
    z[static_cast<std::size_t>(k) + 1] = kInf;
  }
  if (k < 0) {
    for (int q = 0; q < n; ++q) d[q] = kInf;
    return;
  }
  int j = 0;
  for (int q = 0; q < n; ++q) {
    const double xq = q * h;
    while (z[static_cast<std::size_t>(j) + 1] < xq) ++j;
    const double dx = xq - v[static_cast<std::size_t>(j)] * h;
    d[q] = dx * dx + f[v[static_cast<std::size_t>(j)]];
  }
}

}  // namespace

std::vector<double> squared_distance_to(const std::vector<char>& sites, const Index3& n, const Vec3& spacing) {
  std::vector<double> dist(sites.size());
  for (std::size_t i = 0; i < sites.size(); ++i) dist[i] = sites[i] ? 0.0 : kInf;
  const std::size_t stride[3] = {1, static_cast<std::size_t>(n[0]), static_cast<std::size_t>(n[0]) * n[1]};
  const int longest = std::max({n[0], n[1], n[2]});
  std::vector<double> f(static_cast<std::size_t>(longest)), d(static_cast<std::size_t>(longest));
  std::vector<int> v(static_cast<std::size_t>(longest));
  std::vector<double> z(static_cast<std::size_t>(longest) + 1);
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, w = (axis + 2) % 3;
    for (int q = 0; q < n[w]; ++q)
      for (int p = 0; p < n[u]; ++p) {
        const std::size_t base = static_cast<std::size_t>(p) * stride[u] + static_cast<std::size_t>(q) * stride[w];
        for (int i = 0; i < n[axis]; ++i) f[static_cast<std::size_t>(i)] = dist[base + static_cast<std::size_t>(i) * stride[axis]];
        distance_line(f.data(), d.data(), n[axis], spacing[axis], v, z);
        for (int i = 0; i < n[axis]; ++i) dist[base + static_cast<std::size_t>(i) * stride[axis]] = d[static_cast<std::size_t>(i)];
      }
  }
  return dist;
}

}  // namespace gdm
