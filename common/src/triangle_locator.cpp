#include "gdm/triangle_locator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gdm/parallel.h"

namespace gdm {

std::vector<Triangle> triangles_of(const Mesh& mesh) {
  std::vector<Triangle> out;
  out.reserve(mesh.n_faces());
  for (auto f : mesh.faces()) {
    Triangle t;
    int k = 0;
    for (auto v : mesh.fv_range(f)) t[k++] = to_eigen(mesh.point(v));
    out.push_back(t);
  }
  return out;
}

double point_triangle_distance(const Vec3& p, const Triangle& t) {
  // Closest point by the Voronoi regions of the vertices, edges and face.
  const Vec3& a = t[0];
  const Vec3& b = t[1];
  const Vec3& c = t[2];
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  if (!(ab.cross(ac).squaredNorm() > 1e-10 * ab.squaredNorm() * ac.squaredNorm())) {
    // A (nearly) collinear triangle, down to a point: the region tests below
    // would be rounding noise. It is no wider than 1e-5 of its edges: the
    // nearest of its three edges.
    const auto segment = [&p](const Vec3& s, const Vec3& e) {
      const Vec3 d = e - s;
      const double len2 = d.squaredNorm();
      const double t = len2 > 0.0 ? std::clamp((p - s).dot(d) / len2, 0.0, 1.0) : 0.0;
      return (p - (s + t * d)).norm();
    };
    return std::min({segment(a, b), segment(b, c), segment(c, a)});
  }
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return ap.norm();
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return bp.norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double len = d1 - d3;
    const double v = len > 0.0 ? d1 / len : 0.0;
    return (p - (a + v * ab)).norm();
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return cp.norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double len = d2 - d6;
    const double w = len > 0.0 ? d2 / len : 0.0;
    return (p - (a + w * ac)).norm();
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double len = (d4 - d3) + (d5 - d6);
    const double w = len > 0.0 ? (d4 - d3) / len : 0.0;
    return (p - (b + w * (c - b))).norm();
  }
  const double sum = va + vb + vc;  // |ab x ac|^2, positive (checked above)
  const double v = vb / sum, w = vc / sum;
  return (p - (a + v * ab + w * ac)).norm();
}

TriangleLocator::TriangleLocator(std::vector<Triangle> triangles) : triangles_(std::move(triangles)) {
  if (triangles_.empty()) return;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = -lo;
  double size = 0.0;
  for (const auto& t : triangles_)
    for (const auto& p : t) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  for (const auto& t : triangles_)
    size += ((t[1] - t[0]).norm() + (t[2] - t[1]).norm() + (t[0] - t[2]).norm()) / 3.0;
  size /= static_cast<double>(triangles_.size());
  const double diag = (hi - lo).norm();
  // About two mean edge lengths per bucket, and not more than ~2M buckets.
  bucket_ = std::max({2.0 * size, diag / 128.0, 1e-9});
  origin_ = lo;
  std::size_t count = 1;
  for (int i = 0; i < 3; ++i) {
    n_[i] = std::max(1, static_cast<int>(std::ceil((hi[i] - lo[i]) / bucket_)) + 1);
    count *= static_cast<std::size_t>(n_[i]);
  }
  buckets_.resize(count);
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const auto& tri = triangles_[t];
    const Vec3 tlo = tri[0].cwiseMin(tri[1]).cwiseMin(tri[2]);
    const Vec3 thi = tri[0].cwiseMax(tri[1]).cwiseMax(tri[2]);
    int a[3], b[3];
    for (int i = 0; i < 3; ++i) {
      a[i] = std::clamp(static_cast<int>(std::floor((tlo[i] - origin_[i]) / bucket_)), 0, n_[i] - 1);
      b[i] = std::clamp(static_cast<int>(std::floor((thi[i] - origin_[i]) / bucket_)), 0, n_[i] - 1);
    }
    for (int k = a[2]; k <= b[2]; ++k)
      for (int j = a[1]; j <= b[1]; ++j)
        for (int i = a[0]; i <= b[0]; ++i)
          buckets_[static_cast<std::size_t>(i) + static_cast<std::size_t>(n_[0]) * (j + static_cast<std::size_t>(n_[1]) * k)]
              .push_back(static_cast<int>(t));
  }
}

double TriangleLocator::distance(const Vec3& p) const {
  double best = std::numeric_limits<double>::infinity();
  if (triangles_.empty()) return best;
  int c[3];
  for (int i = 0; i < 3; ++i)
    c[i] = std::clamp(static_cast<int>(std::floor((p[i] - origin_[i]) / bucket_)), 0, n_[i] - 1);
  // Distance from p to the box of buckets already searched bounds any triangle outside it.
  const int max_ring = std::max({n_[0], n_[1], n_[2]});
  for (int r = 0; r <= max_ring; ++r) {
    for (int k = c[2] - r; k <= c[2] + r; ++k)
      for (int j = c[1] - r; j <= c[1] + r; ++j)
        for (int i = c[0] - r; i <= c[0] + r; ++i) {
          if (std::max({std::abs(i - c[0]), std::abs(j - c[1]), std::abs(k - c[2])}) != r) continue;
          if (i < 0 || j < 0 || k < 0 || i >= n_[0] || j >= n_[1] || k >= n_[2]) continue;
          for (int t : buckets_[static_cast<std::size_t>(i) +
                                static_cast<std::size_t>(n_[0]) * (j + static_cast<std::size_t>(n_[1]) * k)])
            best = std::min(best, point_triangle_distance(p, triangles_[t]));
        }
    // The searched cube of buckets [c - r, c + r]: anything outside it is at
    // least this far from p.
    double clearance = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i) {
      const double cube_lo = origin_[i] + (c[i] - r) * bucket_;
      const double cube_hi = origin_[i] + (c[i] + r + 1) * bucket_;
      if (c[i] - r > 0) clearance = std::min(clearance, p[i] - cube_lo);
      if (c[i] + r < n_[i] - 1) clearance = std::min(clearance, cube_hi - p[i]);
    }
    if (best <= clearance) break;
  }
  return best;
}

double mean_distance(const Mesh& mesh, const TriangleLocator& to, int threads) {
  const std::size_t nv = mesh.n_vertices(), n = nv + mesh.n_faces();
  std::vector<double> distance(n, 0.0);
  parallel_for(n, threads, [&](std::size_t i) {
    Vec3 p;
    if (i < nv) {
      p = to_eigen(mesh.point(Mesh::VertexHandle(static_cast<int>(i))));
    } else {
      auto it = mesh.cfv_iter(Mesh::FaceHandle(static_cast<int>(i - nv)));
      const Vec3 a = to_eigen(mesh.point(*it)), b = to_eigen(mesh.point(*++it)), c = to_eigen(mesh.point(*++it));
      p = (a + b + c) / 3.0;
    }
    distance[i] = to.distance(p);
  });
  double sum = 0.0;  // in index order: the same sum for any thread count
  for (const double d : distance) sum += d;
  return n > 0 ? sum / static_cast<double>(n) : 0.0;
}

}  // namespace gdm
