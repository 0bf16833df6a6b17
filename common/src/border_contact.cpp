#include "gdm/border_contact.h"

#include <vector>


namespace gdm {

double BorderContact::fraction() const {
  return border_total == 0 ? 0.0 : static_cast<double>(border_voxels) / static_cast<double>(border_total);
}

bool BorderContact::cut_by_scan() const {
  return measured && complete && border_voxels > 0 && fraction() <= kCutByScanBorderFraction;
}

std::string BorderContact::sides_text() const {
  static const char* names[6] = {"-x", "+x", "-y", "+y", "-z", "+z"};
  std::string s;
  for (int side = 0; side < 6; ++side) {
    if (per_side[side] == 0) continue;
    if (!s.empty()) s += ", ";
    s += std::string(names[side]) + " (" + std::to_string(per_side[side]) + " voxels)";
  }
  return s;
}

BorderContact measure_border_contact(const Volume& volume, const Index3& seed, double threshold, Polarity polarity,
                                     double stop_fraction) {
  BorderContact c;
  const Index3& n = volume.dims();
  const auto nx = static_cast<std::size_t>(n[0]), ny = static_cast<std::size_t>(n[1]),
             nz = static_cast<std::size_t>(n[2]);
  // The border is the two outermost layers: a region voxel on the second one
  // puts the object's surface within a voxel of the volume's edge, where a
  // growing model counts as reaching the border (Deformer's border vertices).
  const std::size_t inner = (nx > 4 && ny > 4 && nz > 4) ? (nx - 4) * (ny - 4) * (nz - 4) : 0;
  c.border_total = nx * ny * nz - inner;
  for (int a = 0; a < 3; ++a)
    if (seed[a] < 0 || seed[a] >= n[a]) return c;
  const bool brighter = polarity == Polarity::object_brighter;
  const auto inside = [&](std::size_t v) {
    const float x = volume.values()[v];
    return brighter ? x > threshold : x < threshold;
  };
  const std::size_t start = static_cast<std::size_t>(seed[0]) + nx * (static_cast<std::size_t>(seed[1]) + ny * seed[2]);
  if (!inside(start)) return c;
  c.measured = true;
  const auto limit = static_cast<std::size_t>(stop_fraction * static_cast<double>(c.border_total));
  std::vector<bool> seen(volume.voxel_count(), false);
  std::vector<std::size_t> stack{start};
  seen[start] = true;
  while (!stack.empty()) {
    const std::size_t v = stack.back();
    stack.pop_back();
    ++c.region_voxels;
    const std::size_t i = v % nx, j = (v / nx) % ny, k = v / (nx * ny);
    const bool on_side[6] = {i == 0, i + 1 == nx, j == 0, j + 1 == ny, k == 0, k + 1 == nz};
    const bool near_side[6] = {i <= 1, i + 2 >= nx, j <= 1, j + 2 >= ny, k <= 1, k + 2 >= nz};
    bool border = false;
    for (int side = 0; side < 6; ++side)
      if (near_side[side]) {
        ++c.per_side[side];
        border = true;
      }
    if (border && ++c.border_voxels > limit) {
      c.complete = false;
      return c;
    }
    const std::size_t step[3] = {1, nx, nx * ny};
    for (int a = 0; a < 3; ++a) {
      if (!on_side[2 * a] && !seen[v - step[a]] && inside(v - step[a])) {
        seen[v - step[a]] = true;
        stack.push_back(v - step[a]);
      }
      if (!on_side[2 * a + 1] && !seen[v + step[a]] && inside(v + step[a])) {
        seen[v + step[a]] = true;
        stack.push_back(v + step[a]);
      }
    }
  }
  return c;
}

}  // namespace gdm
