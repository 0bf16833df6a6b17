#include "smooth_volume.h"

#include <algorithm>
#include <cmath>
#include <vector>

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
