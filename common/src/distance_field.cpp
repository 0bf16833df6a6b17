#include "gdm/distance_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gdm/errors.h"

namespace gdm {

namespace {

// The grid of distance_field: origin, cells per axis, spacing and the clamp.
struct Grid {
  Vec3 origin;
  Index3 dims;
  double cells = 1.0;
  double h = 1.0;
  double cap = 0.0;

  // The cells [a, b] (inclusive, per axis) within `cap` of the triangle's box.
  void box_of(const Triangle& tri, int a[3], int b[3]) const {
    const Vec3 tlo = tri[0].cwiseMin(tri[1]).cwiseMin(tri[2]) - Vec3::Constant(cap);
    const Vec3 thi = tri[0].cwiseMax(tri[1]).cwiseMax(tri[2]) + Vec3::Constant(cap);
    for (int i = 0; i < 3; ++i) {
      a[i] = std::max(0, static_cast<int>(std::floor((tlo[i] - origin[i]) / h)));
      b[i] = std::min(dims[i] - 1, static_cast<int>(std::ceil((thi[i] - origin[i]) / h)));
    }
  }
};

Grid grid_of(const std::vector<Triangle>& triangles, const Vec3& lo, const Vec3& hi, const DistanceFieldOptions& o) {
  if (!(std::isfinite(o.cell_size) && o.cell_size > 0.0))
    throw gdm::InvalidOption("the grid cell size must be positive");
  if (!(std::isfinite(o.offset) && o.offset > 0.0)) throw gdm::InvalidOption("the wrap offset must be positive");
  if (triangles.empty()) throw gdm::InvalidOption("the mesh has no faces and no vertices to wrap");
  Grid g;
  g.h = o.cell_size;
  g.origin = lo - Vec3::Constant(o.padding + 2.0 * g.h);
  const Vec3 extent = (hi - lo) + Vec3::Constant(2.0 * (o.padding + 2.0 * g.h));
  for (int i = 0; i < 3; ++i) {
    const double n = std::ceil(extent[i] / g.h) + 1.0;
    g.dims[i] = n < 2.0 ? 2 : n > 1e9 ? 1000000000 : static_cast<int>(n);
    g.cells *= g.dims[i];
  }
  g.cap = o.offset + 3.0 * g.h;
  return g;
}

}  // namespace

DistanceFieldSize distance_field_size(const std::vector<Triangle>& triangles, const Vec3& lo, const Vec3& hi,
                                      const DistanceFieldOptions& options) {
  const Grid g = grid_of(triangles, lo, hi, options);
  DistanceFieldSize s;
  s.dims = g.dims;
  s.cells = g.cells;
  int a[3], b[3];
  for (const auto& t : triangles) {
    g.box_of(t, a, b);
    double n = 1.0;
    for (int i = 0; i < 3; ++i) n *= std::max(0, b[i] - a[i] + 1);
    s.evaluations += n;
  }
  return s;
}

Volume distance_field(const std::vector<Triangle>& triangles, const Vec3& lo, const Vec3& hi,
                      const DistanceFieldOptions& o, const std::function<bool(double)>& progress) {
  const Grid g = grid_of(triangles, lo, hi, o);
  const Index3 dims = g.dims;
  if (g.cells > 400.0e6)
    throw gdm::InvalidOption("the wrap grid would have " + std::to_string(static_cast<long long>(g.cells)) +
                             " cells; increase the cell size");
  std::vector<float> values(static_cast<std::size_t>(g.cells), static_cast<float>(g.cap));
  const auto index = [&](int i, int j, int k) {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(dims[0]) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(dims[1]) * k);
  };
  // Each triangle writes the cells within `cap` of its bounding box: the exact
  // distance wherever it matters, the cap elsewhere.
  const std::size_t report_every = std::max<std::size_t>(1, triangles.size() / 50);
  int a[3], b[3];
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    if (progress && t % report_every == 0 && !progress(static_cast<double>(t) / triangles.size()))
      return gdm::Volume();
    const Triangle& tri = triangles[t];
    g.box_of(tri, a, b);
    for (int k = a[2]; k <= b[2]; ++k)
      for (int j = a[1]; j <= b[1]; ++j)
        for (int i = a[0]; i <= b[0]; ++i) {
          const gdm::Vec3 p = g.origin + g.h * gdm::Vec3(i, j, k);
          float& v = values[index(i, j, k)];
          const double d = gdm::point_triangle_distance(p, tri);
          if (d < v) v = static_cast<float>(d);
        }
  }
  return gdm::Volume(dims, std::move(values), gdm::Vec3::Constant(g.h), g.origin);
}

}  // namespace gdm
