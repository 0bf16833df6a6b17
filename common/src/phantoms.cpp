#include "gdm/phantoms.h"

#include <algorithm>
#include <deque>
#include <cmath>

namespace gdm::phantoms {

Vec3 Grid::center() const {
  const Vec3 mid(0.5 * (dims[0] - 1), 0.5 * (dims[1] - 1), 0.5 * (dims[2] - 1));
  return origin + direction * spacing.asDiagonal() * mid;
}

Volume voxelize(const Grid& grid, const Sdf& sdf, double background, double contrast, double edge_width) {
  if (edge_width <= 0.0) edge_width = grid.spacing.maxCoeff();
  const auto& d = grid.dims;
  std::vector<float> values(static_cast<std::size_t>(d[0]) * d[1] * d[2]);
  const Eigen::Matrix3d m = grid.direction * grid.spacing.asDiagonal();
  std::size_t i = 0;
  for (int z = 0; z < d[2]; ++z)
    for (int y = 0; y < d[1]; ++y)
      for (int x = 0; x < d[0]; ++x) {
        const Vec3 p = grid.origin + m * Vec3(x, y, z);
        const double cover = std::clamp(0.5 - sdf(p) / edge_width, 0.0, 1.0);
        values[i++] = static_cast<float>(background + contrast * cover);
      }
  return Volume(d, std::move(values), grid.spacing, grid.origin, grid.direction);
}

Sdf sphere(const Vec3& center, double radius) {
  return [=](const Vec3& p) { return (p - center).norm() - radius; };
}

Sdf ellipsoid(const Vec3& center, const Vec3& radii) {
  const double r = radii.minCoeff();
  return [=](const Vec3& p) { return ((p - center).cwiseQuotient(radii).norm() - 1.0) * r; };
}

double distance_to_ellipsoid(const Vec3& p, const Vec3& center, const Vec3& radii) {
  // The closest point x = a^2 y / (a^2 + t) (per axis), with t solving
  // sum (a y / (a^2 + t))^2 = 1; Newton from a bracketing start.
  const Vec3 y = (p - center).cwiseAbs();
  const Vec3 a2 = radii.cwiseProduct(radii);
  const auto f = [&](double t) {
    double s = 0.0;
    for (int k = 0; k < 3; ++k) s += std::pow(radii[k] * y[k] / (a2[k] + t), 2);
    return s - 1.0;
  };
  const double amin = radii.minCoeff();
  double lo = -amin * amin + 1e-12, hi = y.norm() * radii.maxCoeff() + 1.0;
  if (f(lo) < 0.0) lo = -amin * amin * (1.0 - 1e-12);
  for (int it = 0; it < 200; ++it) {  // bisection: slow but certain
    const double mid = 0.5 * (lo + hi);
    (f(mid) > 0.0 ? lo : hi) = mid;
  }
  const double t = 0.5 * (lo + hi);
  Vec3 x;
  for (int k = 0; k < 3; ++k) x[k] = a2[k] * y[k] / (a2[k] + t);
  return (x - y).norm();
}

Sdf box(const Vec3& lo, const Vec3& hi) {
  return [=](const Vec3& p) {
    const Vec3 c = 0.5 * (lo + hi), h = 0.5 * (hi - lo);
    const Vec3 q = (p - c).cwiseAbs() - h;
    return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
  };
}

Sdf difference(Sdf a, Sdf b) {
  return [=](const Vec3& p) { return std::max(a(p), -b(p)); };
}

Sdf unite(std::vector<Sdf> parts) {
  return [=](const Vec3& p) {
    double d = std::numeric_limits<double>::infinity();
    for (const auto& s : parts) d = std::min(d, s(p));
    return d;
  };
}

Sdf capsule(const Vec3& a, const Vec3& b, double radius) {
  return [=](const Vec3& p) {
    const Vec3 ab = b - a;
    const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    return (p - (a + t * ab)).norm() - radius;
  };
}

Sdf bent_tube(const Vec3& center, double R, double r, double sweep) {
  return [=](const Vec3& p) {
    const Vec3 q = p - center;
    double angle = std::atan2(q.y(), q.x());
    if (angle < 0.0) angle += 2.0 * M_PI;
    Vec3 nearest;
    if (angle <= sweep) {
      const Vec3 radial(q.x(), q.y(), 0.0);
      const double len = radial.norm();
      nearest = len > 0.0 ? Vec3(R * radial / len) : Vec3(R, 0, 0);
    } else {
      const Vec3 e0(R, 0, 0), e1(R * std::cos(sweep), R * std::sin(sweep), 0);
      nearest = (q - e0).norm() < (q - e1).norm() ? e0 : e1;
    }
    return (q - nearest).norm() - r;
  };
}

Volume with_pepper(const Volume& v, const Sdf& sdf, double fraction, double background, double margin,
                   unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<float> values = v.values();
  const auto& d = v.dims();
  std::size_t i = 0;
  for (int z = 0; z < d[2]; ++z)
    for (int y = 0; y < d[1]; ++y)
      for (int x = 0; x < d[0]; ++x, ++i)
        if (sdf(v.to_physical(Vec3(x, y, z))) < -margin && u(rng) < fraction)
          values[i] = static_cast<float>(background);
  return Volume(d, std::move(values), v.spacing(), v.origin(), v.direction());
}

Volume with_gaussian_noise(const Volume& v, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, sigma);
  std::vector<float> values = v.values();
  for (auto& x : values) x = static_cast<float>(x + n(rng));
  return Volume(v.dims(), std::move(values), v.spacing(), v.origin(), v.direction());
}

DistanceStats vertex_distances(const Mesh& mesh, const std::function<double(const Vec3&)>& distance,
                               double voxel_size, const std::function<bool(const Vec3&)>& include) {
  std::vector<double> d;
  for (auto v : mesh.vertices()) {
    const Vec3 p = to_eigen(mesh.point(v));
    if (include && !include(p)) continue;
    d.push_back(std::abs(distance(p)) / voxel_size);
  }
  return distance_stats(std::move(d));
}

DistanceStats distance_stats(std::vector<double> d) {
  DistanceStats s;
  if (d.empty()) return s;
  double sum = 0.0;
  for (double x : d) sum += x;
  s.mean = sum / static_cast<double>(d.size());
  std::sort(d.begin(), d.end());
  s.p95 = d[static_cast<std::size_t>(0.95 * static_cast<double>(d.size() - 1))];
  s.max = d.back();
  return s;
}

std::vector<char> region_below(const Volume& volume, const Index3& seed, double threshold) {
  const auto& d = volume.dims();
  const std::size_t nx = d[0], ny = d[1], nz = d[2];
  const auto& values = volume.values();
  std::vector<char> region(nx * ny * nz, 0);
  std::deque<std::size_t> queue{seed[0] + nx * (seed[1] + ny * seed[2])};
  region[queue.front()] = 1;
  while (!queue.empty()) {
    const std::size_t i = queue.front();
    queue.pop_front();
    const std::size_t x = i % nx, y = (i / nx) % ny, z = i / (nx * ny);
    const std::size_t next[6] = {x > 0 ? i - 1 : i,       x + 1 < nx ? i + 1 : i,       y > 0 ? i - nx : i,
                                 y + 1 < ny ? i + nx : i, z > 0 ? i - nx * ny : i, z + 1 < nz ? i + nx * ny : i};
    for (const auto j : next)
      if (!region[j] && values[j] < threshold) {
        region[j] = 1;
        queue.push_back(j);
      }
  }
  return region;
}

std::size_t marching_cubes_triangle_count(const Volume& volume, double threshold) {
  // Cube corners (x, y, z bits) and the 12 edges as corner pairs.
  static const int edge_corner[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                         {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  // Each cube face as its 4 corners in cyclic order and its 4 edges (edge k
  // joins corner k and k+1 of the cycle).
  static const int face_corner[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                        {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
  int edge_of[8][8];
  for (int e = 0; e < 12; ++e) {
    edge_of[edge_corner[e][0]][edge_corner[e][1]] = e;
    edge_of[edge_corner[e][1]][edge_corner[e][0]] = e;
  }
  const auto& d = volume.dims();
  std::size_t triangles = 0;
  for (int z = 0; z + 1 < d[2]; ++z)
    for (int y = 0; y + 1 < d[1]; ++y)
      for (int x = 0; x + 1 < d[0]; ++x) {
        bool in[8];
        int count = 0;
        for (int c = 0; c < 8; ++c) {
          in[c] = volume.at(x + (c & 1), y + ((c >> 1) & 1), z + ((c >> 2) & 1)) >= threshold;
          count += in[c];
        }
        if (count == 0 || count == 8) continue;
        int parent[12];
        for (int e = 0; e < 12; ++e) parent[e] = e;
        const auto find = [&](int e) {
          while (parent[e] != e) e = parent[e] = parent[parent[e]];
          return e;
        };
        int crossed = 0;
        bool is_crossed[12];
        for (int e = 0; e < 12; ++e) {
          is_crossed[e] = in[edge_corner[e][0]] != in[edge_corner[e][1]];
          crossed += is_crossed[e];
        }
        for (const auto& f : face_corner) {
          int es[4], n = 0;
          for (int k = 0; k < 4; ++k) {
            const int e = edge_of[f[k]][f[(k + 1) % 4]];
            if (is_crossed[e]) es[n++] = e;
          }
          if (n == 2) {
            parent[find(es[0])] = find(es[1]);
          } else if (n == 4) {
            // Ambiguous face: cut off each corner above the threshold, i.e.
            // join the two crossed edges around that corner.
            for (int k = 0; k < 4; ++k)
              if (in[f[k]]) {
                const int before = edge_of[f[(k + 3) % 4]][f[k]], after = edge_of[f[k]][f[(k + 1) % 4]];
                parent[find(before)] = find(after);
              }
          }
        }
        int loops = 0;
        for (int e = 0; e < 12; ++e)
          if (is_crossed[e] && find(e) == e) ++loops;
        triangles += static_cast<std::size_t>(crossed - 2 * loops);
      }
  return triangles;
}

}  // namespace gdm::phantoms
