#include "gdm/distance_field.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

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
    for (int i = 0; i < 3; ++i) {  // clamped as doubles: no int overflow for absurdly small cells
      const double top = dims[i] - 1;
      a[i] = static_cast<int>(std::clamp(std::floor((tlo[i] - origin[i]) / h), 0.0, top + 1.0));
      b[i] = static_cast<int>(std::clamp(std::ceil((thi[i] - origin[i]) / h), -1.0, top));
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

// The squared Euclidean distance transform of one line (Felzenszwalb and
// Huttenlocher, "Distance transforms of sampled functions", 2012): f holds 0
// (a feature) or a large value; on return f[i] = min_j (i - j)^2 + f[j].
void edt_line(std::vector<double>& f, std::vector<double>& d, std::vector<int>& v, std::vector<double>& z) {
  const int n = static_cast<int>(f.size());
  const double inf = std::numeric_limits<double>::infinity();
  int k = 0;
  v[0] = 0;
  z[0] = -inf;
  z[1] = inf;
  for (int q = 1; q < n; ++q) {
    double s;
    while (true) {
      const int p = v[k];
      s = ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * (q - p));
      if (s <= z[k] && k > 0) {
        --k;
        continue;
      }
      break;
    }
    if (s <= z[k]) {  // k == 0: the new parabola is lower everywhere
      v[0] = q;
      z[0] = -inf;
      z[1] = inf;
      continue;
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = inf;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q) ++k;
    d[q] = (q - v[k]) * double(q - v[k]) + f[v[k]];
  }
  f.swap(d);
}

// Squared Euclidean distance transform of a grid, in cells^2, in place: 0 at
// features, `big` elsewhere on entry.
void squared_edt(std::vector<float>& sq, const Index3& dims, double big) {
  const std::size_t sy = static_cast<std::size_t>(dims[0]), sz = sy * static_cast<std::size_t>(dims[1]);
  const std::size_t stride[3] = {1, sy, sz};
  for (int axis = 0; axis < 3; ++axis) {
    const int m = dims[axis];
    std::vector<double> f(m), d(m), z(m + 1);
    std::vector<int> v(m);
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    for (int j = 0; j < dims[b]; ++j)
      for (int i = 0; i < dims[a]; ++i) {
        const std::size_t base = stride[a] * i + stride[b] * j;
        bool any = false;
        for (int q = 0; q < m; ++q) {
          f[q] = sq[base + stride[axis] * q];
          any = any || f[q] < big;
        }
        if (!any) continue;  // no feature on this line yet
        edt_line(f, d, v, z);
        for (int q = 0; q < m; ++q) sq[base + stride[axis] * q] = static_cast<float>(std::min(f[q], big));
      }
  }
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

Volume bridged_distance_field(const Volume& distance, double offset, double radius, const std::vector<Vec3>& input,
                              double hidden_depth, std::size_t* reopened) {
  const Index3 dims = distance.dims();
  const double h = distance.voxel_size();
  const std::vector<float>& dist = distance.values();
  const std::size_t n = dist.size();
  const std::size_t sy = static_cast<std::size_t>(dims[0]), sz = sy * static_cast<std::size_t>(dims[1]);
  const double big = 1e30;
  // Distance to the input beyond distance_field's clamp: from the cells
  // within a cell of the input (within a cell of the truth).
  std::vector<float> sq(n);
  for (std::size_t c = 0; c < n; ++c) sq[c] = dist[c] <= h ? 0.0f : static_cast<float>(big);
  squared_edt(sq, dims, big);
  const double centre_sq = std::pow((offset + radius) / h, 2.0);
  // Reachable centres: a flood fill (6-neighbours) from the border cells.
  std::vector<unsigned char> reached(n, 0);
  std::vector<std::uint32_t> queue;  // cell indices (the grid is below 2^32 cells)
  const auto is_border = [&](int i, int j, int k) {
    return i == 0 || j == 0 || k == 0 || i == dims[0] - 1 || j == dims[1] - 1 || k == dims[2] - 1;
  };
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
        if (is_border(i, j, k)) {
          const std::size_t c = i + sy * j + sz * k;
          if (sq[c] <= centre_sq) continue;  // a ball there would touch the input
          reached[c] = 1;
          queue.push_back(static_cast<std::uint32_t>(c));
        }
  for (std::size_t q = 0; q < queue.size(); ++q) {
    const std::size_t c = queue[q];
    const int i = static_cast<int>(c % sy), j = static_cast<int>((c / sy) % dims[1]), k = static_cast<int>(c / sz);
    const auto visit = [&](std::size_t e) {
      if (!reached[e] && sq[e] > centre_sq) {
        reached[e] = 1;
        queue.push_back(static_cast<std::uint32_t>(e));
      }
    };
    if (i > 0) visit(c - 1);
    if (i + 1 < dims[0]) visit(c + 1);
    if (j > 0) visit(c - sy);
    if (j + 1 < dims[1]) visit(c + sy);
    if (k > 0) visit(c - sz);
    if (k + 1 < dims[2]) visit(c + sz);
  }
  std::vector<std::uint32_t>().swap(queue);
  // Distance to the nearest reachable centre, then the balls' field.
  for (std::size_t c = 0; c < n; ++c) sq[c] = reached[c] ? 0.0f : static_cast<float>(big);
  std::vector<unsigned char>().swap(reached);
  squared_edt(sq, dims, big);
  // Input the balls' envelope would hide deeper than hidden_depth: the field
  // is reopened (no bridging) within its depth, the offset and two cells of
  // it, deepest first; a point already in a reopened ball is skipped.
  if (reopened) *reopened = 0;
  if (hidden_depth > 0.0 && !input.empty()) {
    const auto cell_index = [&](const Vec3& p, int i) {
      const double x = std::round((p[i] - distance.origin()[i]) / h);
      return static_cast<int>(std::clamp(x, 0.0, static_cast<double>(dims[i] - 1)));
    };
    const auto index_of = [&](const Vec3& p) {
      return static_cast<std::size_t>(cell_index(p, 0)) + sy * cell_index(p, 1) + sz * cell_index(p, 2);
    };
    std::vector<std::pair<double, std::size_t>> hidden;  // depth, input point
    for (std::size_t k = 0; k < input.size(); ++k) {
      const double depth = h * std::sqrt(static_cast<double>(sq[index_of(input[k])])) - (radius + h);
      if (depth > hidden_depth) hidden.emplace_back(depth, k);
    }
    std::sort(hidden.begin(), hidden.end(), [](const auto& a, const auto& b) {
      return a.first > b.first || (a.first == b.first && a.second < b.second);
    });
    std::vector<unsigned char> open(n, 0);
    for (const auto& [depth, k] : hidden) {
      const Vec3& p = input[k];
      if (open[index_of(p)]) continue;
      ++*reopened;
      const double r = (depth + offset + 2.0 * h) / h;
      int a[3], b[3];
      double c[3];
      for (int i = 0; i < 3; ++i) {
        c[i] = (p[i] - distance.origin()[i]) / h;
        a[i] = static_cast<int>(std::clamp(std::floor(c[i] - r), 0.0, static_cast<double>(dims[i] - 1)));
        b[i] = static_cast<int>(std::clamp(std::ceil(c[i] + r), 0.0, static_cast<double>(dims[i] - 1)));
      }
      for (int z = a[2]; z <= b[2]; ++z)
        for (int y = a[1]; y <= b[1]; ++y)
          for (int x = a[0]; x <= b[0]; ++x) {
            const double d2 = (x - c[0]) * (x - c[0]) + (y - c[1]) * (y - c[1]) + (z - c[2]) * (z - c[2]);
            if (d2 > r * r) continue;
            const std::size_t e = x + sy * y + sz * z;
            sq[e] = 0.0f;  // free as far as the balls go: the plain distance decides
            open[e] = 1;
          }
    }
  }
  const double top = offset + radius + h;
  for (std::size_t c = 0; c < n; ++c)
    sq[c] = std::min(dist[c], static_cast<float>(top - h * std::sqrt(static_cast<double>(sq[c]))));
  Volume out(dims, std::move(sq), distance.spacing(), distance.origin(), distance.direction());
  out.set_outside_value(distance.outside_value());
  return out;
}

void reopen_field(Volume& field, const Volume& distance, const std::vector<Vec3>& points,
                  const std::vector<double>& radii) {
  const Index3 dims = field.dims();
  const double h = field.voxel_size();
  const Vec3 origin = field.origin(), spacing = field.spacing();
  const Eigen::Matrix3d direction = field.direction();
  const double outside = field.outside_value();
  const std::vector<float>& dist = distance.values();
  std::vector<float> values = field.take_values();
  const std::size_t sy = static_cast<std::size_t>(dims[0]), sz = sy * static_cast<std::size_t>(dims[1]);
  for (std::size_t p = 0; p < points.size(); ++p) {
    const Vec3 c = (points[p] - origin) / h;
    const double r = radii[p] / h;
    int a[3], b[3];
    for (int i = 0; i < 3; ++i) {
      a[i] = std::max(0, static_cast<int>(std::floor(c[i] - r)));
      b[i] = std::min(dims[i] - 1, static_cast<int>(std::ceil(c[i] + r)));
    }
    for (int k = a[2]; k <= b[2]; ++k)
      for (int j = a[1]; j <= b[1]; ++j)
        for (int i = a[0]; i <= b[0]; ++i)
          if ((Vec3(i, j, k) - c).squaredNorm() <= r * r) {
            const std::size_t e = i + sy * j + sz * k;
            values[e] = dist[e];
          }
  }
  field = Volume(dims, std::move(values), spacing, origin, direction);
  field.set_outside_value(outside);
}

}  // namespace gdm
