#include "gdm/distance_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gdm/errors.h"

namespace gdm {

Volume distance_field(const std::vector<Triangle>& triangles, const Vec3& lo, const Vec3& hi,
                      const DistanceFieldOptions& o, const std::function<bool(double)>& progress) {
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
          const double d = gdm::point_triangle_distance(p, tri);
          if (d < v) v = static_cast<float>(d);
        }
  }
  return gdm::Volume(dims, std::move(values), gdm::Vec3::Constant(h), origin);
}

}  // namespace gdm
