#include "gdm/voxel_seed.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <queue>
#include <utility>

#include "gdm/distance_transform.h"
#include "gdm/error_lod.h"
#include "gdm/face_budget.h"
#include "gdm/largest_first_queue.h"
#include "gdm/voxel_flood.h"
#include "gdm/voxel_grid.h"
#include "gdm/voxel_topology.h"

namespace gdm {
namespace {

// Mean L1 norm of a unit normal over all directions: the cuberille's area
// over the surface's own (a staircase's faces are the normal's projections).
constexpr double kCuberilleAreaRatio = 1.5;
// The flat vertices' removal keeps new angles at least this (degrees): the
// reduction's own first floor (ReduceOptions::min_angle).
constexpr double kFlatMinAngle = 10.0;
// Voxels one step may take along with the one it adds to stay well-composed.
constexpr int kMaxCompanions = 8;
// The narrowest channel of background the ball leaves open, voxels.
constexpr double kChannelWidth = 2.0;

// Whether a value lies on the object's side of T (in double, as every
// decision of the seed reads it).
bool on_object_side(const VoxelSeedOptions& o, double v) { return o.object_brighter ? v > o.threshold : v < o.threshold; }

// The object the model grows in: the start's 6-connected region, as the
// cavity fill sees it (cavities.h; its handles are capped there). Object
// voxels joined to it only by an edge or a corner would bring handles the
// fill never saw: they count as background for the ball.
std::vector<char> object_region(const Volume& volume, const VoxelSeedOptions& o, const Index3& start) {
  const VoxelGrid grid{volume.dims()};
  const std::vector<float>& values = volume.values();
  const auto object = [&](std::size_t c) { return on_object_side(o, values[c]); };
  std::vector<char> region(grid.count(), 0);
  const std::size_t s = grid.index(start[0], start[1], start[2]);
  if (object(s)) {
    region[s] = 1;
    flood_by_runs(grid.n, false, region, {s}, object);
  }
  return region;
}

class BallGrower {
 public:
  // `region`: object_region(volume, o, start).
  BallGrower(const Volume& volume, const VoxelSeedOptions& o, std::vector<char> region)
      : grid_{volume.dims()}, offset_(neighbour_offsets(grid_.n)), region_(std::move(region)) {
    classify(volume, o);
    // Depth: the distance to the nearest voxel outside the region (the
    // background, and object voxels the region does not hold, which count as
    // background here): its nearest such voxel lies in the region's box grown
    // by one, so a crop of the grid holding that box gives the same depths
    // (make_voxel_seed grows the ball in one).
    std::vector<char> outside(region_.size());
    for (std::size_t c = 0; c < outside.size(); ++c) outside[c] = !region_[c];
    const std::vector<double> d2 = squared_distance_to(outside, grid_.n, volume.spacing(), o.threads);
    depth_.assign(d2.begin(), d2.end());
    mark_takeable(region_, thin_background(volume.spacing()));
  }

  VoxelBall grow(const Index3& start) {
    const std::size_t s = index(start[0], start[1], start[2]);
    if (state_[s] == kFree) {
      state_[s] = kReached;
      queue_around(s);
    }
    while (!queue_.empty()) {
      const std::size_t c = queue_.pop();
      if (state_[c] != kQueued) continue;  // taken meanwhile to keep the set well-composed
      state_[c] = kFree;
      take_if_simple(c);
    }
    return result();
  }

 private:
  // kFixed: outside the grid's inner part (never taken); kSpare: background,
  // taken only to keep the set well-composed; kFree / kQueued: object not
  // (yet) taken; kReached: in the ball.
  enum : char { kFixed = 0, kSpare = 1, kFree = 2, kQueued = 3, kReached = 4 };

  std::size_t index(int i, int j, int k) const { return grid_.index(i, j, k); }
  Index3 voxel(std::size_t c) const { return grid_.voxel(c); }
  std::size_t neighbour(std::size_t c, int s) const {
    return static_cast<std::size_t>(static_cast<std::ptrdiff_t>(c) + offset_[static_cast<std::size_t>(s)]);
  }
  bool in(std::size_t c) const { return state_[c] == kReached; }
  bool takeable(std::size_t c) const { return state_[c] == kFree || state_[c] == kQueued || state_[c] == kSpare; }

  // Deepest first; among equals, the lower index (the key is unique).
  std::uint64_t key(std::size_t c) const {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &depth_[c], sizeof bits);  // a non-negative float's bits order as the float
    return (static_cast<std::uint64_t>(bits) << 32) | (0xffffffffu - static_cast<std::uint32_t>(c));
  }

  void queue_around(std::size_t c) {
    for (int s = 0; s < 27; ++s) {
      const std::size_t m = neighbour(c, s);
      if (state_[m] != kFree) continue;
      state_[m] = kQueued;
      queue_.push(key(m), m);
    }
  }

  // The voxels on the background's side of T.
  void classify(const Volume& volume, const VoxelSeedOptions& o) {
    background_.assign(volume.voxel_count(), 0);
    for (std::size_t c = 0; c < background_.size(); ++c) background_[c] = !on_object_side(o, volume.values()[c]);
  }

  // The region and the thin background may be taken as they come; other
  // voxels only to keep the set well-composed; the grid's outer layer never.
  void mark_takeable(const std::vector<char>& region, const std::vector<char>& thin) {
    state_.assign(background_.size(), kFixed);
    for (int k = 1; k < grid_.n[2] - 1; ++k)
      for (int j = 1; j < grid_.n[1] - 1; ++j)
        for (int i = 1; i < grid_.n[0] - 1; ++i) {
          const std::size_t c = index(i, j, k);
          state_[c] = region[c] || thin[c] ? kFree : kSpare;
        }
  }

  // Background no box of kChannelWidth voxel sizes a side (at least one
  // voxel along each axis) fits in: slits and canals narrower than the
  // channels a grown model enters (Deformer::object_ahead: two voxels
  // wide). The ball may take them like the object: a model started from it
  // bridges them as the grown model does, where following a crack one voxel
  // wide deep into the object would put faces far from the object's surface
  // (the tooth's root canals, open at the roots' tips at T = 115).
  std::vector<char> thin_background(const Vec3& spacing) const {
    const std::vector<char>& background = background_;
    Index3 b;
    const double least = std::min({spacing.x(), spacing.y(), spacing.z()});
    for (int a = 0; a < 3; ++a) b[a] = std::max(1, static_cast<int>(std::ceil(kChannelWidth * least / spacing[a] - 1e-9)));
    const std::size_t count = background.size();
    // A box with its lowest corner at c lies in the background (erosion),
    // then every voxel of such a box (dilation): the opening.
    std::vector<char> core(count, 0), open(count, 0);
    for (int k = 0; k + b[2] <= grid_.n[2]; ++k)
      for (int j = 0; j + b[1] <= grid_.n[1]; ++j)
        for (int i = 0; i + b[0] <= grid_.n[0]; ++i) {
          bool all = true;
          for (int dz = 0; dz < b[2] && all; ++dz)
            for (int dy = 0; dy < b[1] && all; ++dy)
              for (int dx = 0; dx < b[0] && all; ++dx) all = background[index(i + dx, j + dy, k + dz)] != 0;
          core[index(i, j, k)] = all;
        }
    for (int k = 0; k < grid_.n[2]; ++k)
      for (int j = 0; j < grid_.n[1]; ++j)
        for (int i = 0; i < grid_.n[0]; ++i) {
          if (!core[index(i, j, k)]) continue;
          for (int dz = 0; dz < b[2]; ++dz)
            for (int dy = 0; dy < b[1]; ++dy)
              for (int dx = 0; dx < b[0]; ++dx) open[index(i + dx, j + dy, k + dz)] = 1;
        }
    std::vector<char> thin(count, 0);
    for (std::size_t c = 0; c < count; ++c) thin[c] = background[c] && !open[c];
    return thin;
  }

  bool simple(std::size_t c) const {
    std::uint32_t reached = 0;
    for (int s = 0; s < 27; ++s)
      if (in(neighbour(c, s))) reached |= 1u << s;
    return test_.simple_for_object(reached);
  }

  // The voxels that could undo the first critical configuration (see
  // critical_configurations) among the windows holding c, object voxels
  // first; false when there is none.
  bool first_critical(std::size_t c, std::vector<std::size_t>& remedies) const {
    const Index3 v = voxel(c);
    remedies.clear();
    const auto candidates = [&](const std::size_t* w, int count, bool only_pair, int t) {
      for (int pass = 0; pass < 2; ++pass)
        for (int u = 0; u < count; ++u) {
          if (only_pair && u != t && u != count - 1 - t) continue;
          const std::size_t m = w[u];
          if (in(m) || !takeable(m) || (state_[m] == kSpare) != (pass == 1)) continue;
          remedies.push_back(m);
        }
    };
    for (int a = 0; a < 3; ++a) {
      const int b = (a + 1) % 3;
      for (int da = -1; da <= 0; ++da)
        for (int db = -1; db <= 0; ++db) {
          std::size_t w[4];
          for (int t = 0; t < 4; ++t) {
            Index3 u = v;
            u[a] += da + (t & 1);
            u[b] += db + (t >> 1);
            w[t] = index(u[0], u[1], u[2]);
          }
          if (in(w[0]) == in(w[3]) && in(w[1]) == in(w[2]) && in(w[0]) != in(w[1])) {
            candidates(w, 4, false, 0);
            return true;
          }
        }
    }
    for (int dz = -1; dz <= 0; ++dz)
      for (int dy = -1; dy <= 0; ++dy)
        for (int dx = -1; dx <= 0; ++dx) {
          std::size_t w[8];
          int count = 0;
          for (int t = 0; t < 8; ++t) {
            w[t] = index(v[0] + dx + (t & 1), v[1] + dy + ((t >> 1) & 1), v[2] + dz + (t >> 2));
            count += in(w[t]);
          }
          if (count != 2 && count != 6) continue;
          for (int t = 0; t < 4; ++t) {
            if (in(w[t]) != in(w[7 - t]) || in(w[t]) != (count == 2)) continue;
            // Two opposite corners in the set: any other voxel joins them; all
            // but two opposite corners: one of those two.
            candidates(w, 8, count == 6, t);
            return true;
          }
        }
    return false;
  }

  // Takes c when it is simple and, with at most kMaxCompanions simple
  // companions taken after it, the set stays well-composed; else leaves
  // everything as it was.
  void take_if_simple(std::size_t c) {
    if (!simple(c)) return;
    std::vector<std::pair<std::size_t, char>> taken{{c, state_[c]}};
    state_[c] = kReached;
    std::vector<std::size_t> remedies;
    while (true) {
      bool critical = false, remedied = false;
      for (const auto& [m, old] : taken) {
        if (!first_critical(m, remedies)) continue;
        critical = true;
        if (static_cast<int>(taken.size()) <= kMaxCompanions)
          for (const std::size_t r : remedies)
            if (simple(r)) {
              taken.push_back({r, state_[r]});
              state_[r] = kReached;
              remedied = true;
              break;
            }
        break;
      }
      if (!critical) break;
      if (!remedied) {
        for (auto it = taken.rbegin(); it != taken.rend(); ++it) state_[it->first] = it->second;
        return;
      }
    }
    for (const auto& [m, old] : taken) queue_around(m);
  }

  // The ball, taking the region with it (the grower is done).
  VoxelBall result() {
    VoxelBall ball;
    ball.dims = grid_.n;
    ball.region = std::move(region_);
    ball.inside.assign(state_.size(), 0);
    for (std::size_t c = 0; c < state_.size(); ++c) {
      if (in(c)) {
        ball.inside[c] = 1;
        ++ball.voxels;
        if (background_[c]) ++ball.background_voxels;
        continue;
      }
      if (state_[c] != kFree) continue;
      for (int s = 0; s < 27; ++s)
        if (in(neighbour(c, s))) {
          ++ball.left_out;
          break;
        }
    }
    return ball;
  }

  VoxelGrid grid_;
  std::array<std::ptrdiff_t, 27> offset_;
  std::vector<float> depth_;  // squared distance to the nearest voxel outside the region, mm^2
  std::vector<char> state_;
  LargestFirstQueue queue_;  // the binary heap's order; its sift-downs missed the cache (issue 17)
  SimplePointTest test_;
  std::vector<char> background_;  // the voxels on the background's side of T
  std::vector<char> region_;      // the start's 6-connected object region (object_region)
};

}  // namespace

// The volume with its object voxels outside `region` mirrored across T
// (v -> 2T - v): on the background's side by as much as they were on the
// object's (at least by a float's step: the ball's classification, in
// double, must see them there too). The model started from the ball grows
// in the ball's object alone: a speck of impulse noise a voxel off its
// surface, or touching it only by an edge or a corner, no longer draws its
// vertices out (the study's salt-and-pepper phantoms at 5 / 10 / 20 % of
// flying edges' faces: sphere mean 0.048 / 0.053 / 0.035 -> 0.022 / 0.018 /
// 0.017 voxel, bent tube 0.048 / 0.046 / 0.033 -> 0.034 / 0.026 / 0.021;
// the clean and Gaussian cases within 0.004, the real scans within 0.003).
Volume outside_region_mirrored(const Volume& volume, const VoxelSeedOptions& o, const std::vector<char>& region) {
  std::vector<float> values = volume.values();
  const auto object = [&](double v) { return on_object_side(o, v); };
  const float away = o.object_brighter ? -std::numeric_limits<float>::infinity() : std::numeric_limits<float>::infinity();
  for (std::size_t c = 0; c < values.size(); ++c) {
    if (!object(values[c]) || region[c]) continue;
    float m = static_cast<float>(2.0 * o.threshold - static_cast<double>(values[c]));
    while (object(m) || m == o.threshold) m = std::nextafter(m, away);
    values[c] = m;
  }
  Volume out(volume.dims(), std::move(values), volume.spacing(), volume.origin(), volume.direction());
  out.set_outside_value(volume.outside_value());
  return out;
}

VoxelBall grow_voxel_ball(const Volume& volume, const VoxelSeedOptions& options, const Index3& start) {
  return BallGrower(volume, options, object_region(volume, options, start)).grow(start);
}

std::size_t critical_configurations(const std::vector<char>& set, const Index3& n) {
  const VoxelGrid grid{n};
  const auto at = [&](int i, int j, int k) { return set[grid.index(i, j, k)] != 0; };
  std::size_t count = 0;
  for (int k = 0; k + 1 < n[2]; ++k)
    for (int j = 0; j + 1 < n[1]; ++j)
      for (int i = 0; i + 1 < n[0]; ++i) {
        bool w[8];
        int inside = 0;
        for (int t = 0; t < 8; ++t) inside += (w[t] = at(i + (t & 1), j + ((t >> 1) & 1), k + (t >> 2)));
        // The cube's three squares through its lower corner (the others are
        // some other cube's), plus the squares on the grid's last planes.
        const int squares[3][4] = {{0, 1, 2, 3}, {0, 1, 4, 5}, {0, 2, 4, 6}};
        for (const auto& q : squares)
          if (w[q[0]] == w[q[3]] && w[q[1]] == w[q[2]] && w[q[0]] != w[q[1]]) ++count;
        if (inside == 2 || inside == 6)
          for (int t = 0; t < 4; ++t)
            if (w[t] == w[7 - t] && w[t] == (inside == 2)) ++count;
      }
  // Squares in the last plane of each axis.
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int u = 0; u + 1 < n[b]; ++u)
      for (int v = 0; v + 1 < n[c]; ++v) {
        bool w[4];
        for (int t = 0; t < 4; ++t) {
          Index3 p{0, 0, 0};
          p[a] = n[a] - 1;
          p[b] = u + (t & 1);
          p[c] = v + (t >> 1);
          w[t] = at(p[0], p[1], p[2]);
        }
        if (w[0] == w[3] && w[1] == w[2] && w[0] != w[1]) ++count;
      }
  }
  return count;
}

Mesh voxel_surface(const VoxelBall& ball, const Volume& volume) {
  Mesh mesh;
  const Index3& n = ball.dims;
  const std::size_t cx = static_cast<std::size_t>(n[0]) + 1, cy = static_cast<std::size_t>(n[1]) + 1;
  std::vector<int> corner_vertex(cx * cy * (static_cast<std::size_t>(n[2]) + 1), -1);
  // Corner (i, j, k) of the grid of corners lies at continuous index (i, j, k) - 1/2.
  const auto corner = [&](const Index3& p) {
    int& id = corner_vertex[static_cast<std::size_t>(p[0]) + cx * (static_cast<std::size_t>(p[1]) + cy * static_cast<std::size_t>(p[2]))];
    if (id < 0) {
      const Index3& o = ball.offset;  // the corner's index in the volume's grid: p + o
      id = mesh.add_vertex(to_point(volume.to_physical(Vec3(p[0] + o[0] - 0.5, p[1] + o[1] - 0.5, p[2] + o[2] - 0.5)))).idx();
    }
    return Mesh::VertexHandle(id);
  };
  // Index space to physical space may mirror (a direction of determinant -1,
  // a negative spacing never): the faces' order is then reversed.
  const bool mirrored = volume.direction().determinant() < 0.0;
  const auto inside = [&](int i, int j, int k) {
    return ball.inside[static_cast<std::size_t>(i) + static_cast<std::size_t>(n[0]) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(k))] != 0;
  };
  for (int k = 1; k + 1 < n[2]; ++k)
    for (int j = 1; j + 1 < n[1]; ++j)
      for (int i = 1; i + 1 < n[0]; ++i) {
        if (!inside(i, j, k)) continue;
        for (int a = 0; a < 3; ++a)
          for (const int side : {-1, 1}) {
            Index3 u{i, j, k};
            u[a] += side;
            if (inside(u[0], u[1], u[2])) continue;
            // The face's corners counter-clockwise seen from outside: around
            // axis a, (b, c) = (a + 1, a + 2) is right-handed.
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            Index3 base{i, j, k};
            base[a] += side > 0 ? 1 : 0;
            Mesh::VertexHandle h[4];
            const int db[4] = {0, 1, 1, 0}, dc[4] = {0, 0, 1, 1};
            for (int t = 0; t < 4; ++t) {
              Index3 p = base;
              p[b] += db[t];
              p[c] += dc[t];
              h[t] = corner(p);
            }
            if ((side < 0) != mirrored) std::swap(h[1], h[3]);
            mesh.add_face(h[0], h[1], h[2]);
            mesh.add_face(h[0], h[2], h[3]);
          }
      }
  return mesh;
}

namespace {

using Corner = std::array<std::int64_t, 3>;

Corner minus(const Corner& a, const Corner& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Corner cross(const Corner& a, const Corner& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
std::int64_t dot(const Corner& a, const Corner& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
bool is_zero(const Corner& a) { return a[0] == 0 && a[1] == 0 && a[2] == 0; }
// Same direction and sense (both non-zero).
bool same_sense(const Corner& a, const Corner& b) { return !is_zero(a) && is_zero(cross(a, b)) && dot(a, b) > 0; }

}  // namespace

std::size_t remove_flat_vertices(Mesh& mesh, const Volume& volume, double min_angle) {
  // The corners' integer coordinates: voxel_surface puts corner (i, j, k)
  // at continuous index (i, j, k) - 1/2.
  std::vector<Corner> q(mesh.n_vertices());
  for (auto v : mesh.vertices()) {
    const Vec3 c = volume.to_continuous_index(to_eigen(mesh.point(v))) + Vec3::Constant(0.5);
    for (int a = 0; a < 3; ++a) {
      const double r = std::round(c[a]);
      if (!(std::abs(c[a] - r) < 1e-6)) return 0;
      q[static_cast<std::size_t>(v.idx())][static_cast<std::size_t>(a)] = static_cast<std::int64_t>(r);
    }
  }
  // Face f's normal (twice its area, in corner units), vertex `from` read as `to`.
  const auto normal = [&](Mesh::FaceHandle f, Mesh::VertexHandle from, Mesh::VertexHandle to) {
    Corner p[3];
    int i = 0;
    for (auto w : mesh.fv_range(f)) p[i++] = q[static_cast<std::size_t>((w == from ? to : w).idx())];
    return cross(minus(p[1], p[0]), minus(p[2], p[0]));
  };
  const auto point_of = [&](Mesh::FaceHandle f, Mesh::VertexHandle from, Mesh::VertexHandle to, Vec3 (&p)[3]) {
    int i = 0;
    for (auto w : mesh.fv_range(f)) p[i++] = to_eigen(mesh.point(w == from ? to : w));
  };
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_halfedge_status();
  mesh.request_face_status();
  std::vector<Corner> planes;                 // the distinct normal directions around a vertex
  std::vector<Mesh::HalfedgeHandle> targets;  // the collapses tried for it
  std::size_t removed = 0;
  // A collapse refused (a fan that is not convex from any neighbour, an
  // angle) may pass once its neighbours are gone: a second sweep.
  for (int sweep = 0; sweep < 2; ++sweep) {
    const std::size_t before = removed;
    for (auto v0 : mesh.vertices()) {
      if (mesh.status(v0).deleted()) continue;
      planes.clear();
      bool few = true;
      for (auto f : mesh.vf_range(v0)) {
        const Corner n = normal(f, v0, v0);
        if (std::none_of(planes.begin(), planes.end(), [&](const Corner& m) { return same_sense(m, n); }))
          planes.push_back(n);
        if (planes.size() > 2) {
          few = false;
          break;
        }
      }
      if (!few || planes.empty()) continue;
      targets.clear();
      const auto plane_of = [&](Mesh::FaceHandle f) { return same_sense(planes[0], normal(f, v0, v0)) ? 0 : 1; };
      for (auto h : mesh.voh_range(v0)) {
        if (planes.size() == 1 ||
            plane_of(mesh.face_handle(h)) != plane_of(mesh.face_handle(mesh.opposite_halfedge_handle(h))))
          targets.push_back(h);
      }
      if (planes.size() == 2) {
        // On a crease: only along it, and only where it runs straight through v0.
        if (targets.size() != 2) continue;
        const Corner a = minus(q[static_cast<std::size_t>(mesh.to_vertex_handle(targets[0]).idx())], q[static_cast<std::size_t>(v0.idx())]);
        const Corner b = minus(q[static_cast<std::size_t>(mesh.to_vertex_handle(targets[1]).idx())], q[static_cast<std::size_t>(v0.idx())]);
        if (!is_zero(cross(a, b)) || dot(a, b) >= 0) continue;
      }
      for (const auto h : targets) {
        if (!collapse_keeps_topology(mesh, h)) continue;
        const auto v1 = mesh.to_vertex_handle(h);
        const auto gone0 = mesh.face_handle(h), gone1 = mesh.face_handle(mesh.opposite_halfedge_handle(h));
        bool keeps = true;
        for (auto f : mesh.vf_range(v0)) {
          if (f == gone0 || f == gone1) continue;
          if (!same_sense(normal(f, v0, v0), normal(f, v0, v1))) {
            keeps = false;
            break;
          }
          Vec3 was[3], now[3];
          point_of(f, v0, v0, was);
          point_of(f, v0, v1, now);
          const double floor = std::min(min_angle, smallest_angle(was[0], was[1], was[2]));
          if (smallest_angle(now[0], now[1], now[2]) < floor) {
            keeps = false;
            break;
          }
        }
        if (!keeps) continue;
        mesh.collapse(h);
        ++removed;
        break;
      }
    }
    if (removed == before) break;
  }
  mesh.garbage_collection();
  mesh.release_vertex_status();
  mesh.release_edge_status();
  mesh.release_halfedge_status();
  mesh.release_face_status();
  return removed;
}

namespace {

// How far the region's box is grown for the crop the ball grows in, and how
// far from a side of the crop inside the grid every voxel of the ball must
// stay for the crop's ball to be the whole grid's, voxels. What a step of
// the growth reads lies within two voxels of the voxels it takes or tries
// (their 27-neighbourhoods and 2 x 2 x 2 windows), its companions within a
// window of each other (at most kMaxCompanions of them); the thin
// background (thin_background) differs from the whole grid's only on the
// crop's outer layer, which the crop never lets the ball take.
constexpr int kBallClearance = kMaxCompanions + 4;
constexpr int kCropMargin = kBallClearance + 4;

// The ball grown in a crop of the grid around the region (issue 17: the
// distance transform, the thin background's opening and the surface's scan
// ran over the whole grid, 10 s of the study's sphere of radius 20 in
// 512^3, against 0.1 s in 64^3), when that crop is smaller than the grid
// and the ball stays kBallClearance voxels off every side of it inside the
// grid: then every voxel the growth read had its whole grid's state and
// depth (BallGrower), and the ball is the whole grid's, its box at
// `offset`. Else an empty ball (dims 0): the caller grows it on the grid.
VoxelBall grow_in_box(const Volume& volume, const VoxelSeedOptions& o, const Index3& start, const std::vector<char>& region) {
  const VoxelGrid grid{volume.dims()};
  const Index3& n = grid.n;
  Index3 lo = n, hi{-1, -1, -1};
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j) {
      const char* row = region.data() + grid.index(0, j, k);
      const char* first = std::find(row, row + n[0], 1);
      if (first == row + n[0]) continue;
      const int a = static_cast<int>(first - row);
      int b = n[0] - 1;
      while (!row[b]) --b;
      lo = {std::min(lo[0], a), std::min(lo[1], j), std::min(lo[2], k)};
      hi = {std::max(hi[0], b), std::max(hi[1], j), std::max(hi[2], k)};
    }
  if (hi[0] < 0) return {};
  Index3 size;
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(0, lo[a] - kCropMargin);
    hi[a] = std::min(n[a] - 1, hi[a] + kCropMargin);
    size[a] = hi[a] - lo[a] + 1;
  }
  if (static_cast<std::size_t>(size[0]) * size[1] * size[2] >= grid.count()) return {};  // no smaller than the grid
  // The crop's values and its part of the region (the whole region: it
  // lies inside the crop, so flooding the crop again would give the same).
  const std::size_t count = static_cast<std::size_t>(size[0]) * size[1] * size[2];
  std::vector<float> values;
  std::vector<char> part_region;
  values.reserve(count);
  part_region.reserve(count);
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j) {
      const std::size_t row = grid.index(lo[0], j, k);
      values.insert(values.end(), volume.values().data() + row, volume.values().data() + row + size[0]);
      part_region.insert(part_region.end(), region.data() + row, region.data() + row + size[0]);
    }
  // Only the grid's shape and spacing matter to the growth, not where it lies.
  const Volume part(size, std::move(values), volume.spacing(), Vec3::Zero(), volume.direction());
  VoxelBall ball = BallGrower(part, o, std::move(part_region)).grow({start[0] - lo[0], start[1] - lo[1], start[2] - lo[2]});
  ball.offset = lo;
  // Per axis, the range of the crop's coordinates the ball may use.
  Index3 from, to;
  for (int a = 0; a < 3; ++a) {
    from[a] = lo[a] > 0 ? kBallClearance : 0;
    to[a] = hi[a] < n[a] - 1 ? size[a] - 1 - kBallClearance : size[a] - 1;
  }
  const VoxelGrid box{size};
  for (std::size_t c = 0; c < ball.inside.size(); ++c) {
    if (!ball.inside[c]) continue;
    const Index3 v = box.voxel(c);
    for (int a = 0; a < 3; ++a)
      if (v[a] < from[a] || v[a] > to[a]) return {};
  }
  return ball;
}

}  // namespace

VoxelSeed make_voxel_seed(const Volume& volume, const VoxelSeedOptions& options, const std::vector<Vec3>& seed_points) {
  VoxelSeed seed;
  const Index3& n = volume.dims();
  // The deepest seed point on the object's side, inside the grid's inner part.
  Index3 start{0, 0, 0};
  double best = -1.0;
  for (const Vec3& p : seed_points) {
    const Vec3 c = volume.to_continuous_index(p);
    const Index3 v{static_cast<int>(std::lround(c.x())), static_cast<int>(std::lround(c.y())),
                   static_cast<int>(std::lround(c.z()))};
    bool inner = true;
    for (int a = 0; a < 3; ++a) inner = inner && v[a] >= 1 && v[a] + 1 < n[a];
    if (!inner) continue;
    const double value = volume.at(v[0], v[1], v[2]);
    const bool object = options.object_brighter ? value > options.threshold : value < options.threshold;
    if (!object) continue;
    // Depth: the value's distance from T (the seed points lie close together).
    const double depth = std::abs(value - options.threshold);
    if (depth > best) {
      best = depth;
      start = v;
    }
  }
  if (best < 0.0) return seed;
  const std::vector<char> region = object_region(volume, options, start);
  VoxelBall ball;
  if (options.crop) ball = grow_in_box(volume, options, start, region);
  seed.cropped = ball.dims[0] > 0;
  if (!seed.cropped) ball = BallGrower(volume, options, region).grow(start);
  // A copy of the volume only when some object voxel lies outside the
  // region (a 512^3 grid's copy was half the seed's time and a third of the
  // run's peak memory for an object alone in it).
  bool elsewhere = false;
  for (std::size_t c = 0; c < region.size() && !elsewhere; ++c) elsewhere = !region[c] && on_object_side(options, volume.values()[c]);
  if (elsewhere) seed.grow_in = outside_region_mirrored(volume, options, region);
  seed.voxels = ball.voxels;
  seed.background_voxels = ball.background_voxels;
  seed.left_out = ball.left_out;
  seed.mesh = voxel_surface(ball, volume);
  seed.surface_faces = seed.mesh.n_faces();
  if (options.reduce && seed.mesh.n_faces() > 0) {
    double area = 0.0;
    for (auto f : seed.mesh.faces()) area += seed.mesh.calc_face_area(f);
    remove_flat_vertices(seed.mesh, volume, kFlatMinAngle);
    const double voxel_area = volume.voxel_size() * volume.voxel_size();
    ReduceOptions r;
    r.threads = options.threads;
    r.faces = static_cast<std::size_t>(std::ceil(area / kCuberilleAreaRatio / (options.face_area * voxel_area)));
    // Collapses that stay within half a voxel of the faces' planes (the
    // staircase's steps) count as free and go shortest edge first.
    r.noise = 0.5 * volume.voxel_size();
    if (r.faces < seed.mesh.n_faces()) reduce_to_faces(seed.mesh, r);
  }
  seed.applied = true;
  return seed;
}

}  // namespace gdm
