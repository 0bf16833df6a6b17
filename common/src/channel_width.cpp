#include "gdm/channel_width.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "gdm/cell_lists.h"

namespace gdm {

namespace {

// The 13 directions of a 3x3x3 neighbourhood, one of each opposite pair.
const std::array<Vec3, 13>& chord_directions() {
  static const std::array<Vec3, 13> d = [] {
    std::array<Vec3, 13> r;
    int n = 0;
    for (int z = -1; z <= 1; ++z)
      for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x) {
          const Vec3 v(x, y, z);
          // Keep the half whose first non-zero coordinate is positive.
          if (z > 0 || (z == 0 && (y > 0 || (y == 0 && x > 0)))) r[n++] = v.normalized();
        }
    return r;
  }();
  return d;
}

// Free run from p along d (unit), sampled every half voxel, up to `limit`.
double free_run(const ImageEvent& image, const Vec3& p, const Vec3& d, double step, double limit) {
  double t = step;
  while (t <= limit && !image.is_blocked(p + t * d)) t += step;
  return std::min(t, limit + step) - 0.5 * step;
}

// A walk's storage, one per thread and kept (the walks are many).
struct WalkScratch {
  CellSet seen;  // lattice offsets from the walk's start (cell_key)
  struct Open {
    double height;
    std::size_t order;
    std::array<int, 3> c;
    bool operator<(const Open& o) const { return height < o.height || (height == o.height && order > o.order); }
  };
  std::vector<Open> open;  // a heap (std::push_heap / pop_heap)
};

// Out of line: the caller keeps the address it returns, where GCC looked a
// thread_local up again at every use inside the walk's loops.
[[gnu::noinline]] WalkScratch& walk_scratch() {
  thread_local WalkScratch scratch;
  return scratch;
}

}  // namespace

double narrowest_chord(const ImageEvent& image, const Vec3& p, const ChannelWidthOptions& o) {
  if (image.is_blocked(p)) return 0.0;
  const double step = 0.5 * o.voxel, half = 0.5 * o.cap;
  double narrowest = o.cap;
  for (const Vec3& d : chord_directions()) {
    const double forward = free_run(image, p, d, step, half);
    if (forward >= narrowest) continue;
    narrowest = std::min(narrowest, forward + free_run(image, p, -d, step, std::min(half, narrowest - forward)));
  }
  return narrowest;
}

double room_width(const ImageEvent& image, const Vec3& p, const Vec3& ahead, const ChannelWidthOptions& o) {
  const double sense = image.is_blocked(p + o.voxel * ahead) ? -1.0 : 1.0;
  double widest = 0.0;
  for (double t = 0.5 * o.voxel; t <= 0.5 * o.cap + 1e-9; t += 0.5 * o.voxel) {
    const Vec3 q = p + (sense * t) * ahead;
    if (image.is_blocked(q)) break;  // across the room: its far wall
    widest = std::max(widest, narrowest_chord(image, q, o));
    if (widest >= o.cap) break;
  }
  return widest;
}

bool free_room_reaches(const ImageEvent& image, const Vec3& start, const Vec3& ahead, double depth,
                       const Vec3& spacing, std::size_t max_points) {
  if (image.is_blocked(start)) return false;
  const Vec3 step = 0.5 * spacing;
  // Lattice offsets from start, one key each (cell_hash.h).
  WalkScratch& scratch = walk_scratch();
  CellSet& seen = scratch.seen;
  seen.start_pass();
  seen.insert(cell_key(0, 0, 0));
  // The walk goes deepest point first (ties: the point found first): where
  // the room reaches the depth it gets there in a few steps instead of
  // after every shallower point. The answer does not depend on the order:
  // it is whether the free component of the lattice ahead of the plane has
  // a point that deep or more than max_points points, and either is found
  // by any order that stops at the first deep point or at max_points.
  std::vector<WalkScratch::Open>& open = scratch.open;
  open.clear();
  open.push_back({0.0, 0, {0, 0, 0}});
  std::size_t found = 1;  // points accepted into the walk
  while (!open.empty()) {
    std::pop_heap(open.begin(), open.end());
    const std::array<int, 3> c = open.back().c;
    open.pop_back();
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
          // Behind the plane: never part of the walk (tested before the
          // set, which then holds only points ahead).
          const Vec3 q = start + Vec3(x, y, z).cwiseProduct(step);
          const double height = (q - start).dot(ahead);
          if (height < 0.0 || !seen.insert(cell_key(x, y, z))) continue;
          if (image.is_blocked(q)) continue;
          if (height >= depth || found >= max_points) return true;
          open.push_back({height, found++, {x, y, z}});
          std::push_heap(open.begin(), open.end());
        }
  }
  return false;
}

double area_for_width(double width, const ChannelWidthOptions& o, double finest, double coarse) {
  const double edge = o.edge_per_width * width;
  return std::clamp(0.25 * std::sqrt(3.0) * edge * edge, finest, coarse);
}

}  // namespace gdm
