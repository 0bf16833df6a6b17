#include "gdm/distance_transform.h"

#include <algorithm>
#include <limits>

#include "gdm/parallel.h"

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

std::vector<double> squared_distance_to(const std::vector<char>& sites, const Index3& n, const Vec3& spacing,
                                        int threads) {
  std::vector<double> dist(sites.size());
  for (std::size_t i = 0; i < sites.size(); ++i) dist[i] = sites[i] ? 0.0 : kInf;
  const std::size_t stride[3] = {1, static_cast<std::size_t>(n[0]), static_cast<std::size_t>(n[0]) * n[1]};
  const int workers = resolve_thread_count(threads);
  for (int axis = 0; axis < 3; ++axis) {
    // Lines next to each other in memory first (u the faster of the two
    // other axes): the workers read and write them in runs of adjacent
    // lines, whose cache lines are shared (the y pass went along z: the
    // whole transform of a 208 x 276 x 210 box took 0.48 s instead of 0.43).
    const int u = axis == 0 ? 1 : 0, w = axis == 2 ? 1 : 2;
    const std::size_t length = static_cast<std::size_t>(n[axis]);
    // One line per index, each written by one worker: the same result on
    // any number of them (an axis's lines share no voxel).
    parallel_for(static_cast<std::size_t>(n[u]) * static_cast<std::size_t>(n[w]), workers, [&](std::size_t line) {
      thread_local std::vector<double> f, d, z;
      thread_local std::vector<int> v;
      f.resize(length);
      d.resize(length);
      v.resize(length);
      z.resize(length + 1);
      const std::size_t p = line % static_cast<std::size_t>(n[u]), q = line / static_cast<std::size_t>(n[u]);
      const std::size_t base = p * stride[u] + q * stride[w];
      for (std::size_t i = 0; i < length; ++i) f[i] = dist[base + i * stride[axis]];
      distance_line(f.data(), d.data(), n[axis], spacing[axis], v, z);
      for (std::size_t i = 0; i < length; ++i) dist[base + i * stride[axis]] = d[i];
    });
  }
  return dist;
}

}  // namespace gdm
