#include "gdm/cavities.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>

#include "gdm/distance_transform.h"
#include "gdm/largest_first_queue.h"
#include "gdm/passage.h"
#include "gdm/voxel_flood.h"
#include "gdm/voxel_grid.h"
#include "gdm/voxel_topology.h"

namespace gdm {

std::string to_string(CavityKind kind) {
  switch (kind) {
    case CavityKind::enclosed: return "enclosed";
    case CavityKind::narrow_openings: return "narrow_openings";
    case CavityKind::handle: return "handle";
    case CavityKind::cut: return "cut";
  }
  return "unknown";
}

std::string to_string(HandleRepair repair) { return repair == HandleRepair::cut ? "cut" : "membrane"; }

double cavity_opening_width(const CavityOptions& o, const Volume& volume) {
  const double opening = o.opening > 0.0 ? o.opening : 3.0 * volume.voxel_size();
  return gap_gate_active(o.gap, volume) ? std::max(opening, o.gap) : opening;
}

namespace {

// The grid with its 6-neighbour walk.
struct Grid : VoxelGrid {
  Grid() = default;
  explicit Grid(const Index3& dims) : VoxelGrid{dims} {}
  // Marks every voxel 6-connected to the marked ones through `passable`
  // (marks only passable voxels); a stack, no recursion. Only the pockets
  // use it (fill_pockets): they collect their members as passable admits
  // each, once and in this order, which flood_by_runs (voxel_flood.h, for
  // the floods that need only the marks) does not promise.
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

// The order of a topology-preserving growth (cap_handles, cut_handles): the
// largest distance first. Distances between voxel centres tie in plateaus
// (at a hole's waist, for a voxel or two either side); ties broken by the
// index would let the front from one side take the whole plateau and put
// the membrane (or cut) at its far edge, so they are broken by a hash of the
// index: fixed (the same result every run), without a preferred direction.
// The key: the distance's bits (a non-negative float orders as its bits)
// above 32 bits of the hash; the index settles what is left.
std::uint64_t growth_key(float d2, std::size_t c) {
  std::uint64_t z = static_cast<std::uint64_t>(c) + 0x9e3779b97f4a7c15ull;  // splitmix64's finaliser
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  z ^= z >> 31;
  std::uint32_t bits = 0;
  std::memcpy(&bits, &d2, sizeof bits);
  return (static_cast<std::uint64_t>(bits) << 32) | (z & 0xffffffffull);
}

// Index offsets of the 27 voxels of a 3 x 3 x 3 neighbourhood (slot (dx + 1)
// + 3 (dy + 1) + 9 (dz + 1)) in a grid of n voxels, x fastest.
// The voxel offsets within t (mm) of a voxel on a grid of spacing h: an
// ellipsoid of voxels on an anisotropic grid; in z, y, x order.
std::vector<Index3> offsets_within(const Vec3& h, double t) {
  Index3 reach;
  for (int a = 0; a < 3; ++a) reach[a] = static_cast<int>(std::floor(t / h[a]));
  std::vector<Index3> ball;
  for (int dz = -reach[2]; dz <= reach[2]; ++dz)
    for (int dy = -reach[1]; dy <= reach[1]; ++dy)
      for (int dx = -reach[0]; dx <= reach[0]; ++dx)
        if ((dx * h[0]) * (dx * h[0]) + (dy * h[1]) * (dy * h[1]) + (dz * h[2]) * (dz * h[2]) <= t * t)
          ball.push_back({dx, dy, dz});
  return ball;
}

// What a voxel of the working box is.
enum : char {
  kObject = 0,      // the seed's object
  kBackground = 1,  // background inside the volume: may be filled
  kOther = 2,       // the object's side of T but not the seed's object: passable, never filled
  kOutside = 3,     // outside the volume: the outside itself
};

class CavityFinder {
 public:
  CavityFinder(const Volume& volume, const CavityOptions& o)
      : volume_(volume), o_(o), full_{volume.dims()}, sign_(o.background_is_brighter ? 1.0 : -1.0) {}

  CavityFill run();

 private:
  bool is_background(std::size_t c) const { return sign_ * (volume_.values()[c] - o_.threshold) > 0.0; }
  bool object_of_the_seed(std::vector<char>& object, Index3& lo, Index3& hi) const;
  bool every_component(std::vector<char>& object, Index3& lo, Index3& hi) const;
  void make_box(const std::vector<char>& object, const Index3& lo, const Index3& hi);
  // Where the box starts out reached from outside: beyond the volume or on the box's border.
  bool outside_or_border(std::size_t c, const Index3& v) const { return kind_[c] == kOutside || box_.on_border(v); }
  template <typename Passable>
  std::vector<char> flooded_from_outside(Passable&& passable) const;
  std::vector<char> reached_by_paths(const std::vector<char>& blocked) const;
  std::vector<char> reached_by_balls(const std::vector<float>& d2) const;
  void fill_pockets(const std::vector<char>& reached, const std::vector<char>& by_path, const std::vector<float>& d2,
                    bool balls, CavityFill& fill);
  void cap_handles(CavityFill& fill);
  void cut_handles(CavityFill& fill);
  void widen_cut(const std::vector<char>& solid, std::vector<std::size_t>& members);
  template <typename Admits>
  void gather_26(std::size_t seed, Admits&& admits, std::vector<char>& seen, std::vector<std::size_t>& members) const;
  bool has_handles() const;
  void seal_pockets(CavityFill& fill);
  Cavity describe(const std::vector<std::size_t>& members, CavityKind kind) const;
  Vec3 physical(const Index3& box_voxel) const {
    return volume_.to_physical(Vec3(box_voxel[0] + lo_[0], box_voxel[1] + lo_[1], box_voxel[2] + lo_[2]));
  }
  std::vector<float> squared_distance(const std::vector<char>& sites) const;
  std::vector<float> distance_to_solid() const;
  Volume filled() const;

  const Volume& volume_;
  const CavityOptions& o_;
  Grid full_;
  double sign_;       // +1 when the background lies above T
  double radius_ = 0.0;  // W / 2, mm
  // The working box: the seed's object's bounding box and a margin wider
  // than W / 2 (it may reach past the volume, where the outside is). Beyond
  // it a ball of any size rolls freely, so nothing there is filled.
  Index3 lo_{0, 0, 0};
  Grid box_{Index3{0, 0, 0}};
  std::vector<char> kind_;  // kObject, kBackground, kOther, kOutside
  std::vector<char> fill_;  // filled (background given to the object)
  std::vector<char> cut_;   // cut (object given to the background; empty: none)
  std::vector<char> scratch_;  // zero between uses
};

// The object's component of the seed points: the object the model grows in.
// What it encloses is a cavity; another object elsewhere (the outside of a
// closed bottle the model grows inside) is not, nor the wall between them.
bool CavityFinder::object_of_the_seed(std::vector<char>& object, Index3& lo, Index3& hi) const {
  object.assign(full_.count(), 0);
  if (o_.every_component) return every_component(object, lo, hi);
  std::vector<std::size_t> stack;
  for (const Vec3& p : o_.seed_points) {
    const Vec3 c = volume_.to_continuous_index(p);
    Index3 v{0, 0, 0};
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      if (!std::isfinite(c[a]) || c[a] < -0.5 || c[a] > full_.n[a] - 0.5) inside = false;
      else v[a] = std::clamp(static_cast<int>(std::lround(c[a])), 0, full_.n[a] - 1);
    }
    if (!inside) continue;
    const std::size_t i = full_.index(v[0], v[1], v[2]);
    if (object[i] || is_background(i)) continue;
    object[i] = 1;
    stack.push_back(i);
  }
  if (stack.empty()) return false;
  flood_by_runs(full_.n, false, object, stack, [&](std::size_t c) { return !is_background(c); });
  lo = full_.n;
  hi = {-1, -1, -1};
  full_.for_each_voxel([&](std::size_t c, const Index3& v) {
    if (!object[c]) return;
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], v[a]), hi[a] = std::max(hi[a], v[a]);
  });
  return true;
}

// Shrinking (CavityOptions::every_component): every voxel on the object's
// side of T within the box around the seed points (clipped to the volume).
// The seed of a shrinking model lies round the object, in the background, so
// no seed point names a region; the model closes round all it encloses, and
// background enclosed by one component or reachable only through a handle of
// several (two roots joined at their tips) is what it cannot enter.
bool CavityFinder::every_component(std::vector<char>& object, Index3& lo, Index3& hi) const {
  Index3 from = full_.n, to{-1, -1, -1};
  for (const Vec3& p : o_.seed_points) {
    const Vec3 c = volume_.to_continuous_index(p);
    for (int a = 0; a < 3; ++a) {
      if (!std::isfinite(c[a])) return false;
      const double lower = std::clamp(std::floor(c[a]), -1.0, static_cast<double>(full_.n[a]));
      const double upper = std::clamp(std::ceil(c[a]), -1.0, static_cast<double>(full_.n[a]));
      from[a] = std::min(from[a], std::max(0, static_cast<int>(lower)));
      to[a] = std::max(to[a], std::min(full_.n[a] - 1, static_cast<int>(upper)));
    }
  }
  lo = full_.n;
  hi = {-1, -1, -1};
  bool any = false;
  for (int k = from[2]; k <= to[2]; ++k)
    for (int j = from[1]; j <= to[1]; ++j)
      for (int i = from[0]; i <= to[0]; ++i) {
        const std::size_t c = full_.index(i, j, k);
        if (is_background(c)) continue;
        object[c] = 1;
        any = true;
        const Index3 v{i, j, k};
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], v[a]), hi[a] = std::max(hi[a], v[a]);
      }
  return any;
}

void CavityFinder::make_box(const std::vector<char>& object, const Index3& lo, const Index3& hi) {
  Index3 n;
  for (int a = 0; a < 3; ++a) {
    const int margin = static_cast<int>(std::ceil(radius_ / volume_.spacing()[a])) + 2;
    lo_[a] = lo[a] - margin;
    n[a] = hi[a] - lo[a] + 1 + 2 * margin;
  }
  box_ = Grid{n};
  kind_.assign(box_.count(), kOutside);
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const Index3 v{i + lo_[0], j + lo_[1], k + lo_[2]};
        if (v[0] < 0 || v[1] < 0 || v[2] < 0 || v[0] >= full_.n[0] || v[1] >= full_.n[1] || v[2] >= full_.n[2]) continue;
        const std::size_t c = full_.index(v[0], v[1], v[2]);
        kind_[box_.index(i, j, k)] = object[c] ? kObject : is_background(c) ? kBackground : kOther;
      }
  fill_.assign(box_.count(), 0);
  scratch_.assign(box_.count(), 0);
}

// Voxels joined to the outside (the box's border and everything outside the
// volume) by a 6-connected path of voxels for which passable(index) holds.
template <typename Passable>
std::vector<char> CavityFinder::flooded_from_outside(Passable&& passable) const {
  std::vector<char> reached(box_.count(), 0);
  std::vector<std::size_t> seeds;
  box_.for_each_voxel([&](std::size_t c, const Index3& v) {
    if (!passable(c) || !outside_or_border(c, v)) return;
    reached[c] = 1;
    seeds.push_back(c);
  });
  flood_by_runs(box_.n, false, reached, seeds, passable);
  return reached;
}

// ... through voxels not `blocked`.
std::vector<char> CavityFinder::reached_by_paths(const std::vector<char>& blocked) const {
  return flooded_from_outside([&](std::size_t c) { return !blocked[c]; });
}

// Voxels outside the seed's object that a ball of diameter W reaches rolling
// in from outside (passage.h's opening, seeded outside): the complement of
// the object eroded by the ball (d2: squared distance to the object), the
// component of the outside, dilated again.
std::vector<char> CavityFinder::reached_by_balls(const std::vector<float>& d2) const {
  const double r2 = radius_ * radius_;
  const std::vector<char> component = flooded_from_outside([&](std::size_t c) { return d2[c] >= r2; });
  const std::vector<double> dilated = squared_distance_to(component, box_.n, volume_.spacing(), o_.threads);
  const double r2_dilate = r2 * (1.0 + 1e-9);
  std::vector<char> reached(box_.count(), 0);
  for (std::size_t c = 0; c < box_.count(); ++c) reached[c] = kind_[c] != kObject && dilated[c] <= r2_dilate;
  return reached;
}

Cavity CavityFinder::describe(const std::vector<std::size_t>& members, CavityKind kind) const {
  Cavity cavity;
  cavity.kind = kind;
  cavity.voxels = members.size();
  Vec3 sum = Vec3::Zero();
  for (const std::size_t m : members) {
    const Index3 v = box_.voxel(m);
    sum += Vec3(v[0] + lo_[0], v[1] + lo_[1], v[2] + lo_[2]);
  }
  cavity.centre = volume_.to_physical(sum / static_cast<double>(std::max<std::size_t>(1, members.size())));
  return cavity;
}

// The pockets: 6-connected components of the background not reached. One
// that no path leads out of is an enclosed cavity; one a path leads out of
// but no ball of diameter W is a chamber behind narrow openings when a ball
// fits somewhere inside it (d2 >= r^2 at one of its voxels: a centre the
// rolling ball could not reach), else a groove or slit, left open.
void CavityFinder::fill_pockets(const std::vector<char>& reached, const std::vector<char>& by_path,
                                const std::vector<float>& d2, bool balls, CavityFill& fill) {
  const double r2 = radius_ * radius_;
  std::vector<char> seen(reached);
  std::vector<std::size_t> stack, members;
  for (std::size_t c = 0; c < box_.count(); ++c) {
    if (seen[c] || kind_[c] != kBackground || fill_[c]) continue;
    seen[c] = 1;
    members.assign(1, c);
    stack.assign(1, c);
    // The members are collected as flood() admits them.
    box_.flood(seen, stack, [&](std::size_t m) {
      if (kind_[m] != kBackground || fill_[m]) return false;
      members.push_back(m);
      return true;
    });
    CavityKind kind = CavityKind::enclosed;
    if (by_path[c]) {  // all members or none: they are one component of the background
      const bool wide = balls && std::any_of(members.begin(), members.end(), [&](std::size_t m) { return d2[m] >= r2; });
      if (!wide) continue;
      kind = CavityKind::narrow_openings;
    }
    for (const std::size_t m : members) fill_[m] = 1;
    Cavity cavity = describe(members, kind);
    if (kind == CavityKind::narrow_openings) {
      // The openings: members next to reached background, in 26-connected groups.
      cavity.width = 2.0 * radius_;
      // scratch_ (zero outside this block): 1 = a mouth, 2 = a mouth grouped.
      std::vector<char>& mark = scratch_;
      std::vector<std::size_t> mouths;
      for (const std::size_t m : members) {
        const Index3 v = box_.voxel(m);
        for (int a = 0; a < 3 && !mark[m]; ++a)
          for (const int step : {-1, 1}) {
            Index3 u = v;
            u[a] += step;
            if (u[a] < 0 || u[a] >= box_.n[a]) continue;
            if (reached[box_.index(u[0], u[1], u[2])]) {
              mark[m] = 1;
              mouths.push_back(m);
              break;
            }
          }
      }
      std::size_t largest = 0;
      std::vector<std::size_t> group, queue;
      for (const std::size_t m : mouths) {
        if (mark[m] == 2) continue;
        mark[m] = 2;
        group.assign(1, m);
        for (std::size_t q = 0; q < group.size(); ++q) {
          const Index3 v = box_.voxel(group[q]);
          for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                const Index3 u{v[0] + dx, v[1] + dy, v[2] + dz};
                if (u[0] < 0 || u[1] < 0 || u[2] < 0 || u[0] >= box_.n[0] || u[1] >= box_.n[1] || u[2] >= box_.n[2]) continue;
                const std::size_t ui = box_.index(u[0], u[1], u[2]);
                if (mark[ui] != 1) continue;
                mark[ui] = 2;
                group.push_back(ui);
              }
        }
        ++cavity.openings;
        if (group.size() > largest) {
          largest = group.size();
          cavity.opening_centre = describe(group, kind).centre;
        }
      }
      for (const std::size_t m : mouths) mark[m] = 0;
    }
    fill.cavities.push_back(cavity);
  }
}

// Squared distance (mm^2) of every voxel of the box to the nearest site,
// kept as float: half the memory of the transform's doubles, which are freed
// at once (distances are compared and ordered, never accumulated).
std::vector<float> CavityFinder::squared_distance(const std::vector<char>& sites) const {
  const std::vector<double> exact = squared_distance_to(sites, box_.n, volume_.spacing(), o_.threads);
  return std::vector<float>(exact.begin(), exact.end());
}

// Squared distance (mm^2) to the seed's object with what is filled so far.
std::vector<float> CavityFinder::distance_to_solid() const {
  std::vector<char> solid(box_.count(), 0);
  for (std::size_t c = 0; c < box_.count(); ++c) solid[c] = kind_[c] == kObject || fill_[c];
  return squared_distance(solid);
}

// How far (voxels, each side) a membrane across a handle's hole is
// thickened unless the options say: a membrane one voxel thin is a slit of
// object the model's faces cannot enter at the default level of detail, and
// a thin one is entered so slowly that the model's fronts go round the tube
// and meet across it first. Measured on the torus and double torus of
// test_cavities.cpp at the default level of detail: 1.5 voxels left contacts
// of 180 to 250 mm^2, 2.5 one of 51 mm^2, 3.5 none.
constexpr double kMembraneHalfThickness = 3.5;

// The reached background grown from outside by simple points only, the
// widest places first (see the header); what it cannot take is the
// membranes, given to the object and thickened.
void CavityFinder::cap_handles(CavityFill& fill) {
  enum : char { kFixed = 0, kFree = 1, kQueued = 2, kReached = 3 };
  // Each voxel's squared distance to the solid (the queue's key) beside its
  // state: the growth reads both for the 27 voxels around each one it takes,
  // in the queue's order, not the memory's, and side by side they share
  // cache lines (two arrays: two misses for most of them; the T1 head's 5.3
  // million pops, issue 17).
  struct Voxel {
    float d2 = 0.0f;
    char state = kFixed;
  };
  std::vector<Voxel> at(box_.count());
  {
    const std::vector<float> d2 = distance_to_solid();
    for (std::size_t c = 0; c < d2.size(); ++c) at[c].d2 = d2[c];
  }
  box_.for_each_voxel([&](std::size_t c, const Index3& v) {
    if (kind_[c] == kObject || fill_[c]) return;
    at[c].state = outside_or_border(c, v) ? kReached : kFree;
  });
  // Largest distance first (growth_key).
  const auto key = [&](std::size_t c) { return growth_key(at[c].d2, c); };
  LargestFirstQueue queue;
  const Index3& n = box_.n;
  const std::ptrdiff_t sx = 1, sy = n[0], sz = static_cast<std::ptrdiff_t>(n[0]) * n[1];
  const std::array<std::ptrdiff_t, 27> offset = neighbour_offsets(n);
  // Every free voxel is interior (those on the box's border start reached):
  // its 26 neighbours are in the box, a fixed index offset away.
  // Queues the free 26-neighbours of c: their simplicity may have changed.
  const auto requeue = [&](std::size_t c) {
    for (int s = 0; s < 27; ++s) {
      const std::size_t m = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(c) + offset[static_cast<std::size_t>(s)]);
      if (at[m].state != kFree) continue;
      at[m].state = kQueued;
      queue.push(key(m), m);
    }
  };
  for (std::size_t c = 0; c < box_.count(); ++c) {
    if (at[c].state != kFree) continue;
    for (const std::ptrdiff_t step : {-sx, sx, -sy, sy, -sz, sz})
      if (at[static_cast<std::size_t>(static_cast<std::ptrdiff_t>(c) + step)].state == kReached) {
        at[c].state = kQueued;
        queue.push(key(c), c);
        break;
      }
  }
  const SimplePointTest hood;
  while (!queue.empty()) {
    const std::size_t c = queue.pop();
    at[c].state = kFree;
    std::uint32_t reached = 0;
    for (int s = 0; s < 27; ++s)
      if (at[static_cast<std::size_t>(static_cast<std::ptrdiff_t>(c) + offset[static_cast<std::size_t>(s)])].state == kReached)
        reached |= 1u << s;
    if (!hood.simple_for_background(reached)) continue;
    at[c].state = kReached;
    requeue(c);
  }

  // The membranes: background left free, in 26-connected groups.
  std::vector<char> seen(box_.count(), 0);
  std::vector<std::size_t> members;
  std::vector<std::size_t> thick;
  const Vec3& h = volume_.spacing();
  const double t = o_.membrane > 0.0 ? o_.membrane : kMembraneHalfThickness * volume_.voxel_size();
  // Whether the segment from membrane voxel a to voxel b crosses the object:
  // the membrane thickens across the hole only, not over the handle's
  // surface beside it (which would bulge the cap past the handle).
  const auto in_sight = [&](const Index3& a, const Index3& b) {
    const int steps = 2 * std::max({std::abs(b[0] - a[0]), std::abs(b[1] - a[1]), std::abs(b[2] - a[2])});
    for (int q = 1; q < steps; ++q) {
      const double f = static_cast<double>(q) / steps;
      Index3 p;
      for (int k = 0; k < 3; ++k) p[k] = static_cast<int>(std::lround(a[k] + f * (b[k] - a[k])));
      if (kind_[box_.index(p[0], p[1], p[2])] == kObject) return false;
    }
    return true;
  };
  const std::vector<Index3> ball = offsets_within(h, t);
  const auto left_free = [&](std::size_t m) { return at[m].state == kFree && kind_[m] == kBackground; };
  for (std::size_t c = 0; c < box_.count(); ++c) {
    if (seen[c] || !left_free(c)) continue;
    gather_26(c, left_free, seen, members);
    double widest = 0.0;
    for (const std::size_t m : members) widest = std::max(widest, static_cast<double>(at[m].d2));
    for (const std::size_t m : members) fill_[m] = 1;
    Cavity cap = describe(members, CavityKind::handle);
    cap.openings = 1;
    cap.opening_centre = cap.centre;
    cap.width = 2.0 * std::sqrt(widest);
    if (members.size() >= kCavitySpeckVoxels) {
      // Thickened into the reached background within t of the membrane, in its sight.
      for (const std::size_t m : members) {
        const Index3 v = box_.voxel(m);
        for (const Index3& d : ball) {
          const Index3 u{v[0] + d[0], v[1] + d[1], v[2] + d[2]};
          if (u[0] < 0 || u[1] < 0 || u[2] < 0 || u[0] >= n[0] || u[1] >= n[1] || u[2] >= n[2]) continue;
          const std::size_t ui = box_.index(u[0], u[1], u[2]);
          if (kind_[ui] != kBackground || fill_[ui] || at[ui].state != kReached || !in_sight(v, u)) continue;
          fill_[ui] = 1;
          thick.push_back(ui);
          ++cap.voxels;
        }
      }
    }
    fill.cavities.push_back(cap);
  }
  if (!thick.empty()) seal_pockets(fill);
}

// The 26-connected group around `seed` of the voxels `admits` (each marked
// in `seen`), into `members` in the order a breadth-first walk takes them.
// Every voxel admitted lies inside the box's border: its 26 neighbours are
// in the box, a fixed index offset away.
template <typename Admits>
void CavityFinder::gather_26(std::size_t seed, Admits&& admits, std::vector<char>& seen,
                             std::vector<std::size_t>& members) const {
  const std::array<std::ptrdiff_t, 27> offset = neighbour_offsets(box_.n);
  seen[seed] = 1;
  members.assign(1, seed);
  for (std::size_t q = 0; q < members.size(); ++q)
    for (const std::ptrdiff_t o : offset) {
      const std::size_t m = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(members[q]) + o);
      if (seen[m] || !admits(m)) continue;
      seen[m] = 1;
      members.push_back(m);
    }
}

// How far (voxels of the finest spacing, each side) a cut is widened: a cut
// one voxel thin leaves the model's two sheets there a voxel apart, closer
// than the report's contact distance and than a 1-to-4 resampling keeps
// apart (measured on the CT series: the global refinement refused).
constexpr double kCutHalfWidth = 1.0;

// The object within kCutHalfWidth of the cut's voxels `members` (ellipsoidal
// reach on an anisotropic grid) joins the cut: appended to `members`.
void CavityFinder::widen_cut(const std::vector<char>& solid, std::vector<std::size_t>& members) {
  const std::vector<Index3> ball = offsets_within(volume_.spacing(), kCutHalfWidth * volume_.voxel_size());
  const Index3& n = box_.n;
  const std::size_t core = members.size();
  for (std::size_t k = 0; k < core; ++k) {
    const Index3 v = box_.voxel(members[k]);
    for (const Index3& d : ball) {
      const Index3 u{v[0] + d[0], v[1] + d[1], v[2] + d[2]};
      if (u[0] < 1 || u[1] < 1 || u[2] < 1 || u[0] >= n[0] - 1 || u[1] >= n[1] - 1 || u[2] >= n[2] - 1) continue;
      const std::size_t ui = box_.index(u[0], u[1], u[2]);
      if (!solid[ui] || cut_[ui]) continue;
      cut_[ui] = 1;
      members.push_back(ui);
    }
  }
}

// The dual of cap_handles (handle_repair cut): the seed's object with what
// is filled, grown from its deepest voxel by simple points (26 / 6), the
// deepest first (growth_key on the distance to the background); what it
// cannot take is a cut across a handle's body at its thinnest place (the
// last place the deepest-first growth reaches from both sides), given to the
// background. The reached object keeps the topology of a ball: no handle is
// left, and no pocket is closed (every cut voxel touches the background).
// Each 26-connected group of cut voxels is reported as a cut.
void CavityFinder::cut_handles(CavityFill& fill) {
  enum : char { kFixed = 0, kFree = 1, kQueued = 2, kReached = 3 };
  std::vector<char> solid(box_.count(), 0), open(box_.count(), 0);
  for (std::size_t c = 0; c < box_.count(); ++c) {
    solid[c] = kind_[c] == kObject || fill_[c];
    open[c] = !solid[c];
  }
  const std::vector<float> d2 = squared_distance(open);
  // Every object voxel lies inside the box's margin, so its 26 neighbours
  // are in the box, a fixed index offset away.
  std::vector<char> state(box_.count(), kFixed);
  std::size_t start = box_.count();
  box_.for_each_voxel([&](std::size_t c, const Index3& v) {
    if (!solid[c] || box_.on_border(v)) return;
    state[c] = kFree;
    if (start == box_.count() || d2[c] > d2[start]) start = c;
  });
  if (start == box_.count()) return;
  LargestFirstQueue queue;
  const std::array<std::ptrdiff_t, 27> offset = neighbour_offsets(box_.n);
  const auto neighbour = [&](std::size_t c, int s) {
    return static_cast<std::size_t>(static_cast<std::ptrdiff_t>(c) + offset[static_cast<std::size_t>(s)]);
  };
  // Takes c and queues its free 26-neighbours: their simplicity may have changed.
  const auto take = [&](std::size_t c) {
    state[c] = kReached;
    for (int s = 0; s < 27; ++s) {
      const std::size_t m = neighbour(c, s);
      if (state[m] != kFree) continue;
      state[m] = kQueued;
      queue.push(growth_key(d2[m], m), m);
    }
  };
  take(start);
  const SimplePointTest hood;
  while (!queue.empty()) {
    const std::size_t c = queue.pop();
    state[c] = kFree;
    std::uint32_t reached = 0;
    for (int s = 0; s < 27; ++s)
      if (state[neighbour(c, s)] == kReached) reached |= 1u << s;
    if (hood.simple_for_object(reached)) take(c);
  }
  // The cuts: object left free (never taken), in 26-connected groups; each
  // but a speck of noise widened by kCutHalfWidth on either side.
  cut_.assign(box_.count(), 0);
  for (std::size_t c = 0; c < box_.count(); ++c) cut_[c] = state[c] == kFree;
  std::vector<char> seen(box_.count(), 0);
  std::vector<std::size_t> members;
  const auto never_taken = [&](std::size_t m) { return state[m] == kFree; };
  for (std::size_t c = 0; c < box_.count(); ++c) {
    if (seen[c] || !never_taken(c)) continue;
    gather_26(c, never_taken, seen, members);
    float thickest = 0.0f;
    for (const std::size_t m : members) thickest = std::max(thickest, d2[m]);
    if (members.size() >= kCavitySpeckVoxels) widen_cut(solid, members);
    Cavity cut = describe(members, CavityKind::cut);
    cut.openings = 1;
    cut.opening_centre = cut.centre;
    cut.width = 2.0 * std::sqrt(static_cast<double>(thickest));
    fill.cavities.push_back(cut);
  }
}

// Whether the seed's object with what is filled so far has a handle. The
// growth takes a voxel only when that keeps the topology of both sides, and
// what it cannot take is left as a membrane across a handle's hole; on a
// region without a handle (first Betti number 0) it takes every background
// voxel it reaches, so skipping it changes nothing (checked voxel for voxel
// in test_cavities.cpp). In theory a handle-free region shaped so that no
// background voxel next to it is simple (Bing's house) would stall the
// growth; what it left there would cap no handle, so the skip is right there
// too. Cost: the Euler characteristic and two floods, a few passes over the
// box; the growth is a priority queue and a 27-voxel test per background
// voxel of the box plus a distance transform (issue 17: a sixth of the nerve
// phantom's model time).
bool CavityFinder::has_handles() const {
  std::vector<char> solid(box_.count(), 0);
  for (std::size_t c = 0; c < box_.count(); ++c) solid[c] = kind_[c] == kObject || fill_[c];
  return voxel_topology(solid, box_.n).handles() != 0;
}

// Background a thickened membrane cut off from the outside: an enclosed
// cavity now, filled as one.
void CavityFinder::seal_pockets(CavityFill& fill) {
  std::vector<char> blocked(box_.count(), 0);
  for (std::size_t c = 0; c < box_.count(); ++c) blocked[c] = kind_[c] == kObject || fill_[c];
  const std::vector<char> reached = reached_by_paths(blocked);
  const std::vector<float> none;
  fill_pockets(reached, reached, none, false, fill);
}

// Every filled voxel is mirrored about T to the object's side (as the gap
// gate closes what it closes), so the threshold crossing between a filled
// voxel and its object neighbours disappears.
Volume CavityFinder::filled() const {
  std::vector<float> values = volume_.values();
  const double least = 1e-3 * (volume_.max_value() - volume_.min_value());
  // Filled voxels mirrored to the object's side of T, cut ones to the background's.
  for (std::size_t b = 0; b < box_.count(); ++b) {
    const bool cut = !cut_.empty() && cut_[b];
    if (!fill_[b] && !cut) continue;
    const Index3 v = box_.voxel(b);
    const std::size_t c = full_.index(v[0] + lo_[0], v[1] + lo_[1], v[2] + lo_[2]);
    const double side = cut ? sign_ : -sign_;
    values[c] = static_cast<float>(o_.threshold + side * std::max(std::abs(values[c] - o_.threshold), least));
  }
  Volume out(full_.n, std::move(values), volume_.spacing(), volume_.origin(), volume_.direction());
  out.set_outside_value(volume_.outside_value());
  return out;
}

CavityFill CavityFinder::run() {
  CavityFill fill;
  fill.opening = cavity_opening_width(o_, volume_);
  radius_ = 0.5 * fill.opening;
  Index3 lo, hi;
  {
    std::vector<char> object;
    if (!object_of_the_seed(object, lo, hi)) return fill;
    make_box(object, lo, hi);
  }
  std::vector<char> blocked(box_.count(), 0);
  for (std::size_t c = 0; c < box_.count(); ++c) blocked[c] = kind_[c] == kObject;
  const std::vector<char> by_path = reached_by_paths(blocked);
  // The ball rolls only when it is wider than the voxels (as the gap gate):
  // a ball of at most two voxels passes wherever a path does.
  const bool balls = gap_gate_active(fill.opening, volume_);
  if (balls) {
    const std::vector<float> d2 = squared_distance(blocked);
    const std::vector<char> reached = reached_by_balls(d2);
    fill_pockets(reached, by_path, d2, true, fill);
  } else {
    fill_pockets(by_path, by_path, {}, false, fill);
  }
  if (o_.cap_handles && (!o_.skip_growth_without_handles || has_handles())) {
    fill.grew = true;
    if (o_.handle_repair == HandleRepair::cut)
      cut_handles(fill);
    else
      cap_handles(fill);
  }
  std::stable_sort(fill.cavities.begin(), fill.cavities.end(),
                   [](const Cavity& a, const Cavity& b) { return a.voxels > b.voxels; });
  for (const Cavity& c : fill.cavities) (c.kind == CavityKind::cut ? fill.cut_voxels : fill.voxels) += c.voxels;
  if (fill.voxels == 0 && fill.cut_voxels == 0) return fill;
  fill.volume = filled();
  fill.applied = true;
  return fill;
}

}  // namespace

CavityFill fill_cavities(const Volume& volume, const CavityOptions& options) {
  return CavityFinder(volume, options).run();
}

}  // namespace gdm
