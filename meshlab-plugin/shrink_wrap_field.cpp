#include "shrink_wrap_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gdm/errors.h"

namespace gdm_meshlab {

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
          const double d = gdm::point_triangle_distance(p, tri);
          if (d < v) v = static_cast<float>(d);
        }
  }
  return gdm::Volume(dims, std::move(values), gdm::Vec3::Constant(h), origin);
}

}  // namespace gdm_meshlab

namespace gdm_meshlab {

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
