#include "gdm/volume.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include <Eigen/LU>

#include "gdm/errors.h"

namespace gdm {

namespace {

std::string vec_string(const Vec3& v) {
  std::ostringstream s;
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}

}  // namespace

Volume::Volume(Index3 dims, std::vector<float> values, Vec3 spacing, Vec3 origin,
               Eigen::Matrix3d direction)
    : dims_(dims),
      values_(std::move(values)),
      spacing_(spacing),
      origin_(origin),
      direction_(direction) {
  for (int a = 0; a < 3; ++a) {
    if (dims_[a] < 2)
      throw InvalidVolume("volume dimension " + std::to_string(a) + " is " +
                          std::to_string(dims_[a]) + "; every dimension needs at least 2 voxels");
    if (!std::isfinite(spacing_[a]) || spacing_[a] <= 0.0)
      throw InvalidVolume("volume spacing " + vec_string(spacing_) +
                          " is not usable: every spacing must be finite and positive");
    if (!std::isfinite(origin_[a]))
      throw InvalidVolume("volume origin " + vec_string(origin_) + " is not finite");
  }
  const std::size_t expected = static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2];
  if (values_.size() != expected)
    throw InvalidVolume("volume has " + std::to_string(values_.size()) + " values but " +
                        std::to_string(dims_[0]) + "x" + std::to_string(dims_[1]) + "x" +
                        std::to_string(dims_[2]) + " needs " + std::to_string(expected));
  if (!direction_.allFinite() || std::abs(direction_.determinant()) < 1e-6)
    throw InvalidVolume("volume direction matrix is singular or not finite");

  to_physical_ = direction_ * spacing_.asDiagonal();
  to_index_ = to_physical_.inverse();
  voxel_size_ = spacing_.minCoeff();

  const ValueRange range = value_range(values_.data(), values_.size());
  if (range.non_finite > 0)
    throw InvalidVolume("volume holds " + std::to_string(range.non_finite) + " NaN or infinite values");
  min_value_ = range.min;
  max_value_ = range.max;
}

ValueRange value_range(const float* values, std::size_t count) {
  // Eight lanes, each a running min, max and count over every eighth value:
  // a value that is not finite (|x| <= FLT_MAX is false for NaN and +-inf)
  // leaves the lane's min and max as they were. Min and max commute, so the
  // lanes' results combined are the plain loop's (up to the sign of a zero
  // extreme, when 0 and -0 both occur).
  constexpr std::size_t kLanes = 8;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  float lo[kLanes], hi[kLanes];
  std::size_t bad[kLanes] = {};
  for (std::size_t k = 0; k < kLanes; ++k) {
    lo[k] = kInf;
    hi[k] = -kInf;
  }
  const auto take = [&](std::size_t k, float x) {
    const bool finite = std::abs(x) <= std::numeric_limits<float>::max();
    bad[k] += finite ? 0 : 1;
    lo[k] = finite && x < lo[k] ? x : lo[k];
    hi[k] = finite && x > hi[k] ? x : hi[k];
  };
  std::size_t i = 0;
  for (; i + kLanes <= count; i += kLanes)
    for (std::size_t k = 0; k < kLanes; ++k) take(k, values[i + k]);
  for (std::size_t k = 0; i < count; ++i, ++k) take(k, values[i]);
  ValueRange r;
  r.min = kInf;
  r.max = -kInf;
  for (std::size_t k = 0; k < kLanes; ++k) {
    r.min = std::min(r.min, lo[k]);
    r.max = std::max(r.max, hi[k]);
    r.non_finite += bad[k];
  }
  // Only a volume that is refused needs its NaN counted.
  if (r.non_finite > 0)
    for (std::size_t j = 0; j < count; ++j) r.nan += std::isnan(values[j]) ? 1 : 0;
  return r;
}

bool Volume::contains(const Vec3& physical, double margin_voxels) const {
  const Vec3 c = to_continuous_index(physical);
  for (int a = 0; a < 3; ++a) {
    if (!(c[a] >= margin_voxels && c[a] <= dims_[a] - 1 - margin_voxels)) return false;
  }
  return true;
}

double Volume::sample(const Vec3& physical) const {
  double value;
  return sample_inside(physical, value) ? value : outside_value_;
}

bool Volume::sample_inside(const Vec3& physical, double& value) const {
  const Vec3 c = to_continuous_index(physical);
  int base[3];
  double frac[3];
  for (int a = 0; a < 3; ++a) {
    // The negated test also sends NaN coordinates outside.
    if (!(c[a] >= 0.0 && c[a] <= dims_[a] - 1)) return false;
    int b = static_cast<int>(c[a]);
    if (b >= dims_[a] - 1) b = dims_[a] - 2;  // the upper face of the grid
    base[a] = b;
    frac[a] = c[a] - b;
  }
  const std::size_t sx = 1, sy = static_cast<std::size_t>(dims_[0]),
                    sz = sy * static_cast<std::size_t>(dims_[1]);
  const float* p = values_.data() + base[0] * sx + base[1] * sy + base[2] * sz;
  const double fx = frac[0], fy = frac[1], fz = frac[2];
  const double c00 = p[0] + fx * (p[sx] - p[0]);
  const double c10 = p[sy] + fx * (p[sy + sx] - p[sy]);
  const double c01 = p[sz] + fx * (p[sz + sx] - p[sz]);
  const double c11 = p[sz + sy] + fx * (p[sz + sy + sx] - p[sz + sy]);
  const double c0 = c00 + fy * (c10 - c00);
  const double c1 = c01 + fy * (c11 - c01);
  const double r = c0 + fz * (c1 - c0);
  if (std::isfinite(r)) {
    value = r;
    return true;
  }
  // The float differences overflowed (neighbours near -FLT_MAX and FLT_MAX):
  // the same interpolation in double, where no float value overflows.
  const auto lerp = [](double a, double b, double f) { return a + f * (b - a); };
  const double d00 = lerp(p[0], p[sx], fx), d10 = lerp(p[sy], p[sy + sx], fx);
  const double d01 = lerp(p[sz], p[sz + sx], fx), d11 = lerp(p[sz + sy], p[sz + sy + sx], fx);
  value = lerp(lerp(d00, d10, fy), lerp(d01, d11, fy), fz);
  return true;
}

void Volume::physical_bounds(Vec3& lo, Vec3& hi) const {
  lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 idx((corner & 1) ? dims_[0] - 1 : 0, (corner & 2) ? dims_[1] - 1 : 0,
                   (corner & 4) ? dims_[2] - 1 : 0);
    const Vec3 p = to_physical(idx);
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
}

Volume reduce_by_two(const Volume& volume, bool keep_minimum) {
  const Index3& n = volume.dims();
  Index3 factor{1, 1, 1}, dims = n;
  for (int d = 0; d < 3; ++d)
    if (volume.spacing()[d] < 1.5 * volume.voxel_size() && n[d] >= 4) {
      factor[d] = 2;
      dims[d] = n[d] / 2;
    }
  std::vector<float> values(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2]);
  std::size_t out = 0;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) {
        float v = volume.at(factor[0] * i, factor[1] * j, factor[2] * k);
        for (int c = 0; c < factor[2]; ++c)
          for (int b = 0; b < factor[1]; ++b)
            for (int a = 0; a < factor[0]; ++a) {
              const float w = volume.at(factor[0] * i + a, factor[1] * j + b, factor[2] * k + c);
              v = keep_minimum ? std::min(v, w) : std::max(v, w);
            }
        values[out++] = v;
      }
  // The coarse voxel sits at its block's centre: half a fine voxel in along a reduced axis.
  const Vec3 shift(0.5 * (factor[0] - 1), 0.5 * (factor[1] - 1), 0.5 * (factor[2] - 1));
  const Vec3 spacing(volume.spacing()[0] * factor[0], volume.spacing()[1] * factor[1], volume.spacing()[2] * factor[2]);
  Volume coarse(dims, std::move(values), spacing, volume.to_physical(shift), volume.direction());
  coarse.set_outside_value(volume.outside_value());
  return coarse;
}

double estimate_voxel_noise(const Volume& volume) {
  Vec3 lo, hi;
  volume.physical_bounds(lo, hi);
  return estimate_voxel_noise(volume, lo, hi);
}

double estimate_voxel_noise(const Volume& volume, const Vec3& lo, const Vec3& hi) {
  const auto& d = volume.dims();
  // The box's voxels with all six neighbours in the grid: the index range
  // of its eight corners, rounded outward.
  Vec3 qlo = Vec3::Constant(std::numeric_limits<double>::infinity()), qhi = -qlo;
  for (int c = 0; c < 8; ++c) {
    const Vec3 q = volume.to_continuous_index(Vec3(c & 1 ? hi.x() : lo.x(), c & 2 ? hi.y() : lo.y(), c & 4 ? hi.z() : lo.z()));
    if (!q.allFinite()) return 0.0;
    qlo = qlo.cwiseMin(q);
    qhi = qhi.cwiseMax(q);
  }
  int first[3], last[3];
  for (int a = 0; a < 3; ++a) {
    first[a] = static_cast<int>(std::max(1.0, std::floor(std::max(qlo[a], -1.0))));
    last[a] = static_cast<int>(std::min(d[a] - 2.0, std::ceil(std::min(qhi[a], static_cast<double>(d[a])))));
    if (first[a] > last[a]) return 0.0;
  }
  const double inner = static_cast<double>(last[0] - first[0] + 1) * (last[1] - first[1] + 1) * (last[2] - first[2] + 1);
  const int stride = std::max(1, static_cast<int>(std::ceil(std::cbrt(inner / 2.0e6))));
  std::vector<float> r;
  r.reserve(static_cast<std::size_t>(inner / (static_cast<double>(stride) * stride * stride)) + 1);
  for (int k = first[2]; k <= last[2]; k += stride)
    for (int j = first[1]; j <= last[1]; j += stride)
      for (int i = first[0]; i <= last[0]; i += stride) {
        const double mean = (static_cast<double>(volume.at(i - 1, j, k)) + volume.at(i + 1, j, k) +
                             volume.at(i, j - 1, k) + volume.at(i, j + 1, k) + volume.at(i, j, k - 1) +
                             volume.at(i, j, k + 1)) / 6.0;
        r.push_back(static_cast<float>(std::abs(volume.at(i, j, k) - mean)));
      }
  if (r.empty()) return 0.0;
  const auto mid = r.begin() + static_cast<long>(r.size() / 2);
  std::nth_element(r.begin(), mid, r.end());
  return *mid / 0.6745 / std::sqrt(7.0 / 6.0);
}

}  // namespace gdm
