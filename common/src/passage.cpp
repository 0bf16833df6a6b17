#include "gdm/passage.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "gdm/distance_transform.h"
#include "gdm/errors.h"
#include "gdm/text.h"

namespace gdm {
namespace {

// An inclusive box of voxel indices.
struct Box {
  Index3 lo{0, 0, 0};
  Index3 hi{-1, -1, -1};
  Index3 size() const { return {hi[0] - lo[0] + 1, hi[1] - lo[1] + 1, hi[2] - lo[2] + 1}; }
  std::size_t count() const {
    const Index3 n = size();
    return static_cast<std::size_t>(n[0]) * static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(n[2]);
  }
  std::size_t index(int i, int j, int k) const {
    const Index3 n = size();
    return static_cast<std::size_t>(i - lo[0]) +
           static_cast<std::size_t>(n[0]) * (static_cast<std::size_t>(j - lo[1]) + static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(k - lo[2]));
  }
  bool contains(int i, int j, int k) const {
    return i >= lo[0] && i <= hi[0] && j >= lo[1] && j <= hi[1] && k >= lo[2] && k <= hi[2];
  }
};

Box grown(const Box& b, const Index3& by, const Index3& dims) {
  Box g;
  for (int a = 0; a < 3; ++a) {
    g.lo[a] = std::max(0, b.lo[a] - by[a]);
    g.hi[a] = std::min(dims[a] - 1, b.hi[a] + by[a]);
  }
  return g;
}

// Visits every voxel of `box` in raster order.
template <typename F>
void for_each_voxel(const Box& box, F&& f) {
  for (int k = box.lo[2]; k <= box.hi[2]; ++k)
    for (int j = box.lo[1]; j <= box.hi[1]; ++j)
      for (int i = box.lo[0]; i <= box.hi[0]; ++i) f(i, j, k);
}

class Gate {
 public:
  Gate(const Volume& volume, const PassageOptions& o)
      : volume_(volume), o_(o), radius_(0.5 * o.gap), sign_(o.blocked_is_brighter ? 1.0 : -1.0) {
    for (int a = 0; a < 3; ++a) reach_[a] = static_cast<int>(std::ceil(radius_ / volume.spacing()[a])) + 1;
  }

  PassageGate build(const std::vector<Vec3>& seed_points);

 private:
  bool is_free(int i, int j, int k) const { return sign_ * (volume_.at(i, j, k) - o_.threshold) <= 0.0; }
  std::vector<Index3> seed_voxels(const std::vector<Vec3>& points) const;
  bool grow_component(const Box& box, const std::vector<Index3>& seeds, std::array<bool, 6>& touches);
  void find_component(const std::vector<Index3>& seeds);
  PassageGate close_unreached() const;

  const Volume& volume_;
  const PassageOptions& o_;
  double radius_;  // mm
  double sign_;    // +1 when the blocked region lies above T
  Index3 reach_;   // voxels per axis a ball of radius G / 2 spans, plus one
  Box box_;        // where the erosion's component lies
  std::vector<char> component_;  // over box_: centres of balls that fit and roll from the seed
};

std::vector<Index3> Gate::seed_voxels(const std::vector<Vec3>& points) const {
  std::vector<Index3> voxels;
  const Index3& n = volume_.dims();
  for (const Vec3& p : points) {
    const Vec3 c = volume_.to_continuous_index(p);
    Index3 v;
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      if (!std::isfinite(c[a])) inside = false;
      else v[a] = static_cast<int>(std::lround(std::clamp(c[a], 0.0, static_cast<double>(n[a] - 1))));
    }
    if (inside && is_free(v[0], v[1], v[2])) voxels.push_back(v);
  }
  std::sort(voxels.begin(), voxels.end());
  voxels.erase(std::unique(voxels.begin(), voxels.end()), voxels.end());
  return voxels;
}

// The erosion (free voxels whose nearest blocked voxel is at least G / 2 away)
// inside `box`, and its 6-connected component of the seeds. `touches` says on
// which faces of the box (not the volume's) the component arrived: the box
// must grow there. Returns false when no seed voxel is a ball centre.
bool Gate::grow_component(const Box& box, const std::vector<Index3>& seeds, std::array<bool, 6>& touches) {
  const Box domain = grown(box, reach_, volume_.dims());
  std::vector<char> blocked(domain.count());
  for_each_voxel(domain, [&](int i, int j, int k) { blocked[domain.index(i, j, k)] = !is_free(i, j, k); });
  const std::vector<double> d2 = squared_distance_to(blocked, domain.size(), volume_.spacing(), o_.threads);
  blocked = {};
  const double r2 = radius_ * radius_;
  const auto centre = [&](int i, int j, int k) { return d2[domain.index(i, j, k)] >= r2; };

  component_.assign(box.count(), 0);
  std::vector<Index3> stack;
  for (const Index3& s : seeds)
    if (box.contains(s[0], s[1], s[2]) && centre(s[0], s[1], s[2]) && !component_[box.index(s[0], s[1], s[2])]) {
      component_[box.index(s[0], s[1], s[2])] = 1;
      stack.push_back(s);
    }
  if (stack.empty()) return false;
  touches.fill(false);
  const Index3& n = volume_.dims();
  while (!stack.empty()) {
    const Index3 c = stack.back();
    stack.pop_back();
    for (int a = 0; a < 3; ++a) {
      if (c[a] == box.lo[a] && box.lo[a] > 0) touches[2 * a] = true;
      if (c[a] == box.hi[a] && box.hi[a] < n[a] - 1) touches[2 * a + 1] = true;
      for (const int step : {-1, 1}) {
        Index3 m = c;
        m[a] += step;
        if (!box.contains(m[0], m[1], m[2])) continue;
        char& seen = component_[box.index(m[0], m[1], m[2])];
        if (seen || !is_free(m[0], m[1], m[2]) || !centre(m[0], m[1], m[2])) continue;
        seen = 1;
        stack.push_back(m);
      }
    }
  }
  return true;
}

void Gate::find_component(const std::vector<Index3>& seeds) {
  // Start around the seed; grow the box only where the component reaches its
  // faces, doubling, so the work follows the component and not the volume.
  for (const Index3& s : seeds)
    for (int a = 0; a < 3; ++a) {
      box_.lo[a] = box_.hi[a] < box_.lo[a] ? s[a] : std::min(box_.lo[a], s[a]);
      box_.hi[a] = box_.hi[a] < s[a] ? s[a] : box_.hi[a];
    }
  Index3 margin;
  for (int a = 0; a < 3; ++a) margin[a] = 4 * reach_[a] + 8;
  box_ = grown(box_, margin, volume_.dims());
  while (true) {
    std::array<bool, 6> touches{};
    if (!grow_component(box_, seeds, touches)) {
      std::ostringstream s;
      s << "the seed lies where no ball of the gap size " << format_number(o_.gap)
        << " mm fits (an opening or channel narrower than the gap): move the seed into a wider part of the object "
           "or lower the gap";
      throw InvalidSeed(s.str());
    }
    if (std::none_of(touches.begin(), touches.end(), [](bool t) { return t; })) return;
    const Index3 size = box_.size();
    for (int a = 0; a < 3; ++a) {
      if (touches[2 * a]) box_.lo[a] = std::max(0, box_.lo[a] - std::max(size[a], 16));
      if (touches[2 * a + 1]) box_.hi[a] = std::min(volume_.dims()[a] - 1, box_.hi[a] + std::max(size[a], 16));
    }
  }
}

// The component dilated by G / 2 is what the model may reach; every other
// free voxel of the crop is mirrored to the blocked side of T.
PassageGate Gate::close_unreached() const {
  const Box domain = grown(box_, reach_, volume_.dims());
  std::vector<char> sites(domain.count(), 0);
  for_each_voxel(box_, [&](int i, int j, int k) { sites[domain.index(i, j, k)] = component_[box_.index(i, j, k)]; });
  const std::vector<double> d2 = squared_distance_to(sites, domain.size(), volume_.spacing(), o_.threads);
  sites = {};
  const double r2 = radius_ * radius_ * (1.0 + 1e-9);
  std::vector<char> reachable(domain.count(), 0);
  Box extent;  // of the reachable voxels
  PassageGate gate;
  for_each_voxel(domain, [&](int i, int j, int k) {
    const std::size_t c = domain.index(i, j, k);
    if (d2[c] > r2 || !is_free(i, j, k)) return;
    reachable[c] = 1;
    ++gate.reachable_voxels;
    const Index3 v{i, j, k};
    for (int a = 0; a < 3; ++a) {
      extent.lo[a] = extent.hi[a] < extent.lo[a] ? v[a] : std::min(extent.lo[a], v[a]);
      extent.hi[a] = extent.hi[a] < v[a] ? v[a] : extent.hi[a];
    }
  });
  const Index3& n = volume_.dims();
  for (int a = 0; a < 3; ++a)
    if (extent.lo[a] == 0 || extent.hi[a] == n[a] - 1) gate.reaches_border = true;
  const Box crop = grown(extent, {2, 2, 2}, n);
  const Index3 size = crop.size();
  for (int a = 0; a < 3; ++a)  // the model needs a grid of at least 2 voxels per axis
    if (size[a] < 2) throw InvalidSeed("the region a ball of the gap size reaches from the seed is a single slice thick");
  // A closed voxel lies at least this far on the blocked side: a voxel exactly at T stays off it.
  const double least = 1e-3 * (volume_.max_value() - volume_.min_value());
  std::vector<float> values(crop.count());
  for_each_voxel(crop, [&](int i, int j, int k) {
    const float v = volume_.at(i, j, k);
    float& out = values[crop.index(i, j, k)];
    out = v;
    if (!is_free(i, j, k)) return;
    if (domain.contains(i, j, k) && reachable[domain.index(i, j, k)]) return;
    out = static_cast<float>(o_.threshold + sign_ * std::max(std::abs(v - o_.threshold), least));
    ++gate.closed_voxels;
  });
  const Vec3 origin = volume_.to_physical(Vec3(crop.lo[0], crop.lo[1], crop.lo[2]));
  gate.volume = Volume(size, std::move(values), volume_.spacing(), origin, volume_.direction());
  gate.volume.set_outside_value(volume_.outside_value());
  gate.applied = true;
  return gate;
}

PassageGate Gate::build(const std::vector<Vec3>& seed_points) {
  const std::vector<Index3> seeds = seed_voxels(seed_points);
  if (seeds.empty()) throw InvalidSeed("no seed point lies in the volume on the side of the threshold the model moves through");
  find_component(seeds);
  return close_unreached();
}

}  // namespace

bool gap_gate_active(double gap, const Volume& volume) {
  return std::isfinite(gap) && 0.5 * gap > volume.voxel_size();
}

PassageGate gate_passages(const Volume& volume, const PassageOptions& options, const std::vector<Vec3>& seed_points) {
  if (!gap_gate_active(options.gap, volume)) return {};
  return Gate(volume, options).build(seed_points);
}

}  // namespace gdm
