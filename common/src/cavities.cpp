#include "gdm/cavities.h"

#include <algorithm>
#include <cmath>

#include "gdm/distance_transform.h"
#include "gdm/passage.h"

namespace gdm {
namespace {

// A grid of n voxels (x fastest) with its 6-neighbour walk.
struct Grid {
  Index3 n;
  std::size_t count() const {
    return static_cast<std::size_t>(n[0]) * static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(n[2]);
  }
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(n[0]) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(k));
  }
  Index3 voxel(std::size_t c) const {
    const std::size_t nx = static_cast<std::size_t>(n[0]), ny = static_cast<std::size_t>(n[1]);
    return {static_cast<int>(c % nx), static_cast<int>((c / nx) % ny), static_cast<int>(c / (nx * ny))};
  }
  bool on_border(int i, int j, int k) const {
    return i == 0 || j == 0 || k == 0 || i == n[0] - 1 || j == n[1] - 1 || k == n[2] - 1;
  }
  // Marks every voxel 6-connected to the marked ones through `passable`
  // (marks only passable voxels); a stack, no recursion.
  template <typename Passable>
  void flood(std::vector<char>& marked, std::vector<std::size_t>& stack, Passable&& passable) const {
    while (!stack.empty()) {
      const Index3 c = voxel(stack.back());
      stack.pop_back();
      for (int a = 0; a < 3; ++a)
        for (const int step : {-1, 1}) {
          Index3 m = c;
          m[a] += step;
          if (m[a] < 0 || m[a] >= n[a]) continue;
          const std::size_t mi = index(m[0], m[1], m[2]);
          if (marked[mi] || !passable(mi)) continue;
          marked[mi] = 1;
          stack.push_back(mi);
        }
    }
  }
};

class CavityFinder {
 public:
  CavityFinder(const Volume& volume, const CavityOptions& o)
      : volume_(volume), o_(o), grid_{volume.dims()}, sign_(o.background_is_brighter ? 1.0 : -1.0) {}

  CavityFill run();

 private:
  bool is_background(std::size_t c) const { return sign_ * (volume_.values()[c] - o_.threshold) > 0.0; }
  std::vector<char> object_of_the_seed() const;
  std::vector<char> reached_by_paths() const;
  std::vector<char> reached_by_balls() const;
  std::vector<Cavity> label(const std::vector<char>& reached) const;
  Volume filled(const std::vector<char>& reached) const;

  const Volume& volume_;
  const CavityOptions& o_;
  Grid grid_;
  double sign_;  // +1 when the background lies above T
  std::vector<char> object_;  // the object the model grows in: the 6-connected object voxels of the seed
};

// The object's component of the seed points: the object the model grows in.
// What it encloses is a cavity; another object elsewhere (the outside of a
// closed bottle the model grows inside) is not, nor the wall between them.
std::vector<char> CavityFinder::object_of_the_seed() const {
  std::vector<char> object(grid_.count(), 0);
  std::vector<std::size_t> stack;
  for (const Vec3& p : o_.seed_points) {
    const Vec3 c = volume_.to_continuous_index(p);
    Index3 v;
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      if (!std::isfinite(c[a]) || c[a] < -0.5 || c[a] > grid_.n[a] - 0.5) inside = false;
      else v[a] = std::clamp(static_cast<int>(std::lround(c[a])), 0, grid_.n[a] - 1);
    }
    if (!inside) continue;
    const std::size_t i = grid_.index(v[0], v[1], v[2]);
    if (object[i] || is_background(i)) continue;
    object[i] = 1;
    stack.push_back(i);
  }
  grid_.flood(object, stack, [&](std::size_t c) { return !is_background(c); });
  return object;
}

// Voxels outside the seed's object joined to the volume's border by a
// 6-connected path outside it.
std::vector<char> CavityFinder::reached_by_paths() const {
  std::vector<char> reached(grid_.count(), 0);
  std::vector<std::size_t> stack;
  const Index3& n = grid_.n;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        if (!grid_.on_border(i, j, k)) continue;
        const std::size_t c = grid_.index(i, j, k);
        if (object_[c]) continue;
        reached[c] = 1;
        stack.push_back(c);
      }
  grid_.flood(reached, stack, [&](std::size_t c) { return !object_[c]; });
  return reached;
}

// Voxels outside the seed's object that a ball of diameter G reaches rolling
// in from outside the volume (passage.h's opening, seeded outside): the
// complement of the object, padded, eroded by the ball, the component of the
// pad, dilated again.
std::vector<char> CavityFinder::reached_by_balls() const {
  const double radius = 0.5 * o_.gap, r2 = radius * radius;
  Index3 pad, padded;
  for (int a = 0; a < 3; ++a) {
    pad[a] = static_cast<int>(std::ceil(radius / volume_.spacing()[a])) + 1;
    padded[a] = grid_.n[a] + 2 * pad[a];
  }
  const Grid big{padded};
  const auto inner = [&](const Index3& v) {
    return Index3{v[0] - pad[0], v[1] - pad[1], v[2] - pad[2]};
  };
  const auto inside = [&](const Index3& u) {
    return u[0] >= 0 && u[1] >= 0 && u[2] >= 0 && u[0] < grid_.n[0] && u[1] < grid_.n[1] && u[2] < grid_.n[2];
  };
  std::vector<char> sites(big.count(), 0);  // the seed's object
  for (std::size_t c = 0; c < big.count(); ++c) {
    const Index3 u = inner(big.voxel(c));
    if (inside(u)) sites[c] = object_[grid_.index(u[0], u[1], u[2])];
  }
  std::vector<double> d2 = squared_distance_to(sites, padded, volume_.spacing());
  std::vector<char> centres(big.count(), 0);
  std::vector<std::size_t> stack;
  for (std::size_t c = 0; c < big.count(); ++c) {
    if (d2[c] < r2) continue;
    centres[c] = 1;
    if (!inside(inner(big.voxel(c)))) stack.push_back(c);  // the pad: outside the volume
  }
  std::vector<char> component(big.count(), 0);
  for (const std::size_t c : stack) component[c] = 1;
  big.flood(component, stack, [&](std::size_t c) { return centres[c] != 0; });
  centres = {};
  d2 = squared_distance_to(component, padded, volume_.spacing());
  std::vector<char> reached(grid_.count(), 0);
  const double r2_dilate = r2 * (1.0 + 1e-9);
  for (std::size_t c = 0; c < grid_.count(); ++c) {
    const Index3 v = grid_.voxel(c);
    reached[c] = !object_[c] && d2[big.index(v[0] + pad[0], v[1] + pad[1], v[2] + pad[2])] <= r2_dilate;
  }
  return reached;
}

// The cavities: 6-connected components of the background not reached.
std::vector<Cavity> CavityFinder::label(const std::vector<char>& reached) const {
  std::vector<char> seen(reached);
  std::vector<Cavity> cavities;
  std::vector<std::size_t> stack, members;
  for (std::size_t c = 0; c < grid_.count(); ++c) {
    if (seen[c] || !is_background(c)) continue;
    seen[c] = 1;
    members.assign(1, c);
    stack.assign(1, c);
    // The members are collected as flood() admits them.
    grid_.flood(seen, stack, [&](std::size_t m) {
      if (!is_background(m)) return false;
      members.push_back(m);
      return true;
    });
    Cavity cavity;
    cavity.voxels = members.size();
    Vec3 sum = Vec3::Zero();
    for (const std::size_t m : members) {
      const Index3 v = grid_.voxel(m);
      sum += Vec3(v[0], v[1], v[2]);
    }
    cavity.centre = volume_.to_physical(sum / static_cast<double>(members.size()));
    cavities.push_back(cavity);
  }
  std::stable_sort(cavities.begin(), cavities.end(), [](const Cavity& a, const Cavity& b) { return a.voxels > b.voxels; });
  return cavities;
}

// Every background voxel not reached is mirrored about T to the object's
// side (as the gap gate closes what it closes), so the threshold crossing
// between a filled voxel and its object neighbours disappears.
Volume CavityFinder::filled(const std::vector<char>& reached) const {
  std::vector<float> values = volume_.values();
  const double least = 1e-3 * (volume_.max_value() - volume_.min_value());
  for (std::size_t c = 0; c < values.size(); ++c) {
    if (reached[c] || !is_background(c)) continue;
    values[c] = static_cast<float>(o_.threshold - sign_ * std::max(std::abs(values[c] - o_.threshold), least));
  }
  Volume out(grid_.n, std::move(values), volume_.spacing(), volume_.origin(), volume_.direction());
  out.set_outside_value(volume_.outside_value());
  return out;
}

CavityFill CavityFinder::run() {
  object_ = object_of_the_seed();
  if (std::none_of(object_.begin(), object_.end(), [](char c) { return c != 0; })) return {};
  const std::vector<char> reached = gap_gate_active(o_.gap, volume_) ? reached_by_balls() : reached_by_paths();
  CavityFill fill;
  fill.cavities = label(reached);
  for (const Cavity& c : fill.cavities) fill.voxels += c.voxels;
  if (fill.voxels == 0) return fill;
  fill.volume = filled(reached);
  fill.applied = true;
  return fill;
}

}  // namespace

CavityFill fill_cavities(const Volume& volume, const CavityOptions& options) {
  return CavityFinder(volume, options).run();
}

}  // namespace gdm
