#include "gdm/volume_ops.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "gdm/errors.h"

namespace gdm {

namespace {

Volume with_values(const Volume& like, Index3 dims, std::vector<float> values, const Vec3& origin) {
  Volume out(dims, std::move(values), like.spacing(), origin, like.direction());
  out.set_outside_value(like.outside_value());
  return out;
}

}  // namespace

Volume crop(const Volume& volume, const VoxelBox& box) {
  const Index3& n = volume.dims();
  for (int d = 0; d < 3; ++d) {
    if (box.lo[d] < 0 || box.hi[d] > n[d] - 1 || box.lo[d] > box.hi[d]) {
      std::ostringstream s;
      s << "roi " << box.lo[0] << "," << box.lo[1] << "," << box.lo[2] << " .. " << box.hi[0] << "," << box.hi[1]
        << "," << box.hi[2] << " is not inside the volume (size " << n[0] << " x " << n[1] << " x " << n[2]
        << " voxels; indices start at 0)";
      throw InvalidOption(s.str());
    }
  }
  for (int d = 0; d < 3; ++d)
    if (box.hi[d] - box.lo[d] + 1 < 2)
      throw InvalidOption("roi must span at least 2 voxels along every axis (axis " + std::to_string(d) + " spans " +
                          std::to_string(box.hi[d] - box.lo[d] + 1) + ")");
  const Index3 dims{box.hi[0] - box.lo[0] + 1, box.hi[1] - box.lo[1] + 1, box.hi[2] - box.lo[2] + 1};
  std::vector<float> values;
  values.reserve(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2]);
  for (int k = box.lo[2]; k <= box.hi[2]; ++k)
    for (int j = box.lo[1]; j <= box.hi[1]; ++j)
      for (int i = box.lo[0]; i <= box.hi[0]; ++i) values.push_back(volume.at(i, j, k));
  const Vec3 origin = volume.to_physical(Vec3(box.lo[0], box.lo[1], box.lo[2]));
  return with_values(volume, dims, std::move(values), origin);
}

Volume gaussian_smooth(const Volume& volume, double sigma_mm) {
  if (!std::isfinite(sigma_mm) || sigma_mm < 0.0)
    throw InvalidOption("smooth: the Gaussian sigma must be a finite number >= 0 mm (got " +
                        std::to_string(sigma_mm) + ")");
  const Index3& n = volume.dims();
  // A sigma wider than the volume along an axis smooths nothing meaningful
  // and its kernel (4 sigma each side) can be astronomically long: 1000 mm at
  // a spacing of 1e-6 mm is 4e9 taps, a hang (found by fuzz_pipeline).
  for (int axis = 0; axis < 3; ++axis)
    if (sigma_mm / volume.spacing()[axis] > n[axis])
      throw InvalidOption("smooth", "smooth: the Gaussian sigma " + std::to_string(sigma_mm) + " mm is " +
                                        std::to_string(sigma_mm / volume.spacing()[axis]) + " voxels along axis " +
                                        std::to_string(axis) + " (spacing " + std::to_string(volume.spacing()[axis]) +
                                        " mm), wider than the volume's " + std::to_string(n[axis]) +
                                        " voxels: lower smooth or resample the volume");
  std::vector<float> a = volume.values();
  if (sigma_mm == 0.0) return with_values(volume, volume.dims(), std::move(a), volume.origin());
  const std::size_t stride[3] = {1, static_cast<std::size_t>(n[0]), static_cast<std::size_t>(n[0]) * n[1]};
  std::vector<float> b(a.size());
  std::vector<double> line, padded;
  for (int axis = 0; axis < 3; ++axis) {
    const double sigma = sigma_mm / volume.spacing()[axis];  // voxels
    const int radius = static_cast<int>(std::ceil(4.0 * sigma));
    if (radius < 1) continue;  // the kernel is a single tap
    std::vector<double> kernel(2 * static_cast<std::size_t>(radius) + 1);
    double sum = 0.0;
    for (int i = -radius; i <= radius; ++i)
      sum += kernel[static_cast<std::size_t>(i + radius)] = std::exp(-0.5 * i * i / (sigma * sigma));
    for (double& w : kernel) w /= sum;

    const int len = n[axis];
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    padded.assign(static_cast<std::size_t>(len) + 2 * static_cast<std::size_t>(radius), 0.0);
    for (int q = 0; q < n[v]; ++q)
      for (int p = 0; p < n[u]; ++p) {
        const std::size_t base = static_cast<std::size_t>(p) * stride[u] + static_cast<std::size_t>(q) * stride[v];
        // The line with its border voxels repeated `radius` times on each side.
        for (int i = -radius; i < len + radius; ++i) {
          const int c = std::clamp(i, 0, len - 1);
          padded[static_cast<std::size_t>(i + radius)] = a[base + static_cast<std::size_t>(c) * stride[axis]];
        }
        for (int i = 0; i < len; ++i) {
          double acc = 0.0;
          const double* src = padded.data() + i;
          for (std::size_t t = 0; t < kernel.size(); ++t) acc += kernel[t] * src[t];
          b[base + static_cast<std::size_t>(i) * stride[axis]] = static_cast<float>(acc);
        }
      }
    a.swap(b);
  }
  return with_values(volume, volume.dims(), std::move(a), volume.origin());
}

// A port of ITK 5.2's itk::OtsuThresholdImageFilter (float image, so
// AutoMinimumMaximum on): ImageToHistogramFilter's bins over [min, max + margin]
// with margin = (max - min) / bins / 100, bin edges computed with a float
// interval as itk::Histogram::Initialize does, the bin of a value found by
// itk::Histogram::GetIndex's search, then OtsuMultipleThresholdsCalculator with
// one threshold (bin midpoints as class values, the 1-ulp "clearly larger"
// test) returning the bin maximum (ReturnBinMidpoint off), cast to float.
double otsu_threshold(const Volume& volume, int bins) {
  if (bins < 2) throw InvalidOption("otsu: the histogram needs at least 2 bins (got " + std::to_string(bins) + ")");
  const std::vector<float>& values = volume.values();
  if (values.empty()) throw InvalidVolume("otsu: the volume is empty");
  double lo = std::numeric_limits<float>::max();
  double hi = std::numeric_limits<float>::lowest();
  for (float x : values) {
    lo = std::min(lo, static_cast<double>(x));
    hi = std::max(hi, static_cast<double>(x));
  }
  if (!(hi > lo))
    throw InvalidVolume("otsu: the volume is constant (every voxel is " + std::to_string(lo) +
                        "): there are no two classes to separate");
  const auto size = static_cast<std::size_t>(bins);
  // ApplyMarginalScale (the histogram's measurement type is double).
  const double margin = ((hi - lo) / static_cast<double>(bins)) / 100.0;
  const double upper = hi + margin;
  std::vector<double> bin_min(size), bin_max(size);
  // Histogram::Initialize: a float interval, edges lower + float(j * interval).
  // Near FLT_MAX (values spanning more than FLT_MAX, or a maximum whose margin
  // passes FLT_MAX) ITK's float interval overflows to inf and every edge with
  // it; there the same bins are computed in double instead (no float value can
  // overflow a double), so the threshold stays finite and inside the range.
  const bool float_bins = upper <= static_cast<double>(std::numeric_limits<float>::max()) &&
                          std::isfinite(static_cast<float>(upper) - static_cast<float>(lo));
  if (float_bins) {
    const float interval = (static_cast<float>(upper) - static_cast<float>(lo)) / static_cast<float>(bins);
    for (std::size_t j = 0; j + 1 < size; ++j) {
      bin_min[j] = lo + static_cast<float>(static_cast<float>(j) * interval);
      bin_max[j] = lo + static_cast<float>((static_cast<float>(j) + 1.0f) * interval);
    }
    bin_min[size - 1] = lo + static_cast<float>((static_cast<float>(bins) - 1.0f) * interval);
  } else {
    const double interval = (upper - lo) / static_cast<double>(bins);
    for (std::size_t j = 0; j + 1 < size; ++j) {
      bin_min[j] = lo + static_cast<double>(j) * interval;
      bin_max[j] = lo + (static_cast<double>(j) + 1.0) * interval;
    }
    bin_min[size - 1] = lo + (static_cast<double>(bins) - 1.0) * interval;
  }
  bin_max[size - 1] = upper;

  // Histogram::GetIndex (ClipBinsAtEnds on; no value lies below the first bin
  // and none at or above `upper`).
  std::vector<std::uint64_t> freq(size, 0);
  const auto end_bin = static_cast<long>(size) - 1;
  for (float x : values) {
    const double m = x;
    long index;
    if (m >= bin_max[static_cast<std::size_t>(end_bin)]) {
      index = end_bin;
    } else {
      long begin = 0, end = end_bin;
      long mid = (end + 1) / 2;
      double median = bin_min[static_cast<std::size_t>(mid)];
      while (true) {
        if (m < median) {
          end = mid - 1;
        } else if (m > median) {
          if (m < bin_max[static_cast<std::size_t>(mid)] && m >= bin_min[static_cast<std::size_t>(mid)]) {
            index = mid;
            break;
          }
          begin = mid + 1;
        } else {
          index = mid;
          break;
        }
        mid = begin + (end - begin) / 2;
        median = bin_min[static_cast<std::size_t>(mid)];
      }
    }
    ++freq[static_cast<std::size_t>(index)];
  }

  // OtsuMultipleThresholdsCalculator::Compute with one threshold.
  std::vector<double> measurement(size);
  for (std::size_t j = 0; j < size; ++j) measurement[j] = (bin_min[j] + bin_max[j]) / 2.0;
  std::uint64_t total = 0;
  double global_mean = 0.0;
  for (std::size_t j = 0; j < size; ++j) {
    global_mean += measurement[j] * static_cast<double>(freq[j]);
    total += freq[j];
  }
  global_mean /= static_cast<double>(total);

  std::size_t threshold_index = 0;
  std::uint64_t freq0 = freq[0];
  std::uint64_t freq1 = total - freq0;
  double mean0 = freq0 > 0 ? measurement[0] : 0.0;
  double mean1 = freq1 > 0 ? (global_mean * static_cast<double>(total) - mean0 * static_cast<double>(freq0)) /
                                 static_cast<double>(freq1)
                           : 0.0;
  const auto between = [&] {
    double s = static_cast<double>(freq0) * (mean0 * mean0);
    s += static_cast<double>(freq1) * (mean1 * mean1);
    return s / static_cast<double>(total);
  };
  // itk::Math::FloatAlmostEqual(a, b, 1 ulp, 0.1 * epsilon).
  const auto almost_equal = [](double x1, double x2) {
    if (std::abs(x1 - x2) <= 0.1 * std::numeric_limits<double>::epsilon()) return true;
    std::int64_t i1, i2;
    std::memcpy(&i1, &x1, sizeof x1);
    std::memcpy(&i2, &x2, sizeof x2);
    if ((i1 < 0) != (i2 < 0)) return false;
    const std::int64_t ulps = i1 > i2 ? i1 - i2 : i2 - i1;
    return ulps <= 1;
  };
  double best = between();
  std::size_t best_index = 0;
  while (threshold_index < size - 2) {
    ++threshold_index;
    const double mean_old = mean0;
    const std::uint64_t freq_old = freq0;
    const std::uint64_t f = freq[threshold_index];
    freq0 += f;
    mean0 = freq0 > 0 ? (mean_old * static_cast<double>(freq_old) + measurement[threshold_index] * static_cast<double>(f)) /
                            static_cast<double>(freq0)
                      : 0.0;
    freq1 = total - freq0;
    mean1 = global_mean * static_cast<double>(total) - mean0 * static_cast<double>(freq0);
    mean1 = freq1 > 0 ? mean1 / static_cast<double>(freq1) : 0.0;
    const double v = between();
    if (v > best && !almost_equal(best, v)) {
      best = v;
      best_index = threshold_index;
    }
  }
  // best_index <= bins - 2: the edge lies below the maximum, so it is a finite float.
  return static_cast<double>(static_cast<float>(bin_max[best_index]));
}

}  // namespace gdm
