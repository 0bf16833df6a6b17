#include "shrink_wrap_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gdm/errors.h"

namespace gdm_meshlab {

double point_triangle_distance(const gdm::Vec3& p, const Triangle& t) {
  // Closest point by the Voronoi regions of the vertices, edges and face.
  const gdm::Vec3& a = t[0];
  const gdm::Vec3& b = t[1];
  const gdm::Vec3& c = t[2];
  const gdm::Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return ap.norm();
  const gdm::Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return bp.norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double len = d1 - d3;
    const double v = len > 0.0 ? d1 / len : 0.0;
    return (p - (a + v * ab)).norm();
  }
  const gdm::Vec3 cp = p - c;
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
  const double sum = va + vb + vc;
  if (!(std::abs(sum) > 0.0)) {
    // Degenerate (collinear) triangle that slipped through: nearest of its edges' ends.
    return std::min({ap.norm(), bp.norm(), cp.norm()});
  }
  const double v = vb / sum, w = vc / sum;
  return (p - (a + v * ab + w * ac)).norm();
}

gdm::Volume make_wrap_field(const std::vector<Triangle>& triangles, const gdm::Vec3& lo, const gdm::Vec3& hi,
                            const WrapFieldOptions& o, const std::function<bool(double)>& progress) {
  if (!(std::isfinite(o.cell_size) && o.cell_size > 0.0))
    throw gdm::InvalidOption("the grid cell size must be positive");
  if (!(std::isfinite(o.offset) && o.offset > 0.0)) throw gdm::InvalidOption("the wrap offset must be positive");
  if (triangles.empty()) throw gdm::InvalidOption("the mesh has no faces and no vertices to wrap");
  const double h = o.cell_size;
  const gdm::Vec3 origin = lo - gdm::Vec3::Constant(o.padding + 2.0 * h);
  const gdm::Vec3 extent = (hi - lo) + gdm::Vec3::Constant(2.0 * (o.padding + 2.0 * h));
  gdm::Index3 dims;
  double voxels = 1.0;
  for (int i = 0; i < 3; ++i) {
    dims[i] = std::max(2, static_cast<int>(std::ceil(extent[i] / h)) + 1);
    voxels *= dims[i];
  }
  if (voxels > 400.0e6)
    throw gdm::InvalidOption("the wrap grid would have " + std::to_string(static_cast<long long>(voxels)) +
                             " cells; increase the cell size");
  const double cap = o.offset + 3.0 * h;
  std::vector<float> values(static_cast<std::size_t>(voxels), static_cast<float>(cap));
  const auto index = [&](int i, int j, int k) {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(dims[0]) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(dims[1]) * k);
  };
  // Each triangle writes the cells within `cap` of its bounding box: the exact
  // distance wherever it matters, the cap elsewhere.
  const std::size_t report_every = std::max<std::size_t>(1, triangles.size() / 50);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    if (progress && t % report_every == 0 && !progress(static_cast<double>(t) / triangles.size()))
      return gdm::Volume();
    const Triangle& tri = triangles[t];
    gdm::Vec3 tlo = tri[0].cwiseMin(tri[1]).cwiseMin(tri[2]) - gdm::Vec3::Constant(cap);
    gdm::Vec3 thi = tri[0].cwiseMax(tri[1]).cwiseMax(tri[2]) + gdm::Vec3::Constant(cap);
    int a[3], b[3];
    for (int i = 0; i < 3; ++i) {
      a[i] = std::max(0, static_cast<int>(std::floor((tlo[i] - origin[i]) / h)));
      b[i] = std::min(dims[i] - 1, static_cast<int>(std::ceil((thi[i] - origin[i]) / h)));
    }
    for (int k = a[2]; k <= b[2]; ++k)
      for (int j = a[1]; j <= b[1]; ++j)
        for (int i = a[0]; i <= b[0]; ++i) {
          const gdm::Vec3 p = origin + h * gdm::Vec3(i, j, k);
          float& v = values[index(i, j, k)];
          const double d = point_triangle_distance(p, tri);
          if (d < v) v = static_cast<float>(d);
        }
  }
  return gdm::Volume(dims, std::move(values), gdm::Vec3::Constant(h), origin);
}

}  // namespace gdm_meshlab

namespace gdm_meshlab {

TriangleLocator::TriangleLocator(std::vector<Triangle> triangles) : triangles_(std::move(triangles)) {
  if (triangles_.empty()) return;
  gdm::Vec3 lo = gdm::Vec3::Constant(std::numeric_limits<double>::infinity());
  gdm::Vec3 hi = -lo;
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
    const gdm::Vec3 tlo = tri[0].cwiseMin(tri[1]).cwiseMin(tri[2]);
    const gdm::Vec3 thi = tri[0].cwiseMax(tri[1]).cwiseMax(tri[2]);
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

double TriangleLocator::distance(const gdm::Vec3& p) const {
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

gdm::Volume smooth_volume(const gdm::Volume& volume, double sigma_mm) {
  if (!(sigma_mm > 0.0)) return volume;
  const gdm::Index3 d = volume.dims();
  std::vector<float> a = volume.values(), b(a.size());
  const std::size_t stride[3] = {1, static_cast<std::size_t>(d[0]), static_cast<std::size_t>(d[0]) * d[1]};
  for (int axis = 0; axis < 3; ++axis) {
    const double sigma = sigma_mm / volume.spacing()[axis];
    const int radius = std::max(1, static_cast<int>(std::ceil(3.0 * sigma)));
    std::vector<double> kernel(2 * radius + 1);
    double sum = 0.0;
    for (int i = -radius; i <= radius; ++i) sum += kernel[i + radius] = std::exp(-0.5 * i * i / (sigma * sigma));
    for (double& w : kernel) w /= sum;
    const int n = d[axis];
    for (std::size_t idx = 0; idx < a.size(); ++idx) {
      const int pos = static_cast<int>((idx / stride[axis]) % static_cast<std::size_t>(n));
      double acc = 0.0;
      for (int i = -radius; i <= radius; ++i) {
        const int q = std::clamp(pos + i, 0, n - 1);  // replicate the border
        acc += kernel[i + radius] * a[idx + (static_cast<long>(q) - pos) * static_cast<long>(stride[axis])];
      }
      b[idx] = static_cast<float>(acc);
    }
    a.swap(b);
  }
  gdm::Volume out(d, std::move(a), volume.spacing(), volume.origin(), volume.direction());
  out.set_outside_value(volume.outside_value());
  return out;
}

}  // namespace gdm_meshlab
