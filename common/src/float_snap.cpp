#include "gdm/float_snap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "gdm/intersection_guard.h"
#include "gdm/mesh_checks.h"
#include "gdm/parallel.h"

namespace gdm {
namespace {

bool float_exact(double x) { return round_to_float(x) == x; }

// x moved by `steps` floats (toward +infinity when positive), as a double.
double float_steps(double x, int steps) {
  float f = static_cast<float>(x);
  const float toward = steps > 0 ? std::numeric_limits<float>::infinity() : -std::numeric_limits<float>::infinity();
  for (int k = 0; k < std::abs(steps); ++k) f = std::nextafter(f, toward);
  return static_cast<double>(f);
}

// The float values bracketing x: {nearest, the other neighbour} (equal when x is a float).
std::array<double, 2> float_bracket(double x) {
  const double n = round_to_float(x);
  if (n == x) return {n, n};
  return {n, float_steps(n, n < x ? 1 : -1)};
}

// Beyond the float cell's corners: the float points up to kLatticeReach
// floats from the nearest one along each axis, nearest first (by the
// offset's length in floats, ties in a fixed order). A vertex on a fold the
// model made flat (two layers of faces a few micrometres apart, seen on the
// T1 head) can have every corner of its cell on the far side of the other
// layer; a few floats further one lies on its own side.
constexpr int kLatticeReach = 5;
const std::vector<Eigen::Vector3i>& lattice_offsets() {
  static const std::vector<Eigen::Vector3i> offsets = [] {
    std::vector<Eigen::Vector3i> all;
    for (int a = -kLatticeReach; a <= kLatticeReach; ++a)
      for (int b = -kLatticeReach; b <= kLatticeReach; ++b)
        for (int c = -kLatticeReach; c <= kLatticeReach; ++c) all.emplace_back(a, b, c);
    std::stable_sort(all.begin(), all.end(),
                     [](const Eigen::Vector3i& x, const Eigen::Vector3i& y) { return x.squaredNorm() < y.squaredNorm(); });
    return all;
  }();
  return offsets;
}

}  // namespace

double round_to_float(double x) {
  // Through memory, so the round trip is never folded away.
  volatile float f = static_cast<float>(x);
  return static_cast<double>(f);
}

Vec3 round_to_float(const Vec3& p) { return {round_to_float(p.x()), round_to_float(p.y()), round_to_float(p.z())}; }

bool is_float_exact(const Mesh& mesh) {
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    if (!float_exact(p[0]) || !float_exact(p[1]) || !float_exact(p[2])) return false;
  }
  return true;
}

std::size_t pairs_crossing_when_rounded(const Mesh& mesh, int threads) {
  if (is_float_exact(mesh)) return 0;
  Mesh rounded = mesh;
  for (auto v : rounded.vertices()) rounded.set_point(v, to_point(round_to_float(to_eigen(rounded.point(v)))));
  return self_intersecting_pairs(rounded, threads);
}

FloatSnapResult snap_to_float(Mesh& mesh, int threads) {
  FloatSnapResult result;
  // Every move is below kLatticeReach + 1 float spacings at the largest
  // coordinate along each axis (a corner's: below one).
  double largest = 0.0;
  for (auto v : mesh.vertices()) largest = std::max(largest, to_eigen(mesh.point(v)).cwiseAbs().maxCoeff());
  const double spacing = std::max(largest, 1.0) * std::ldexp(1.0, -23);
  IntersectionGuard guard(mesh, 2.0 * (kLatticeReach + 1) * spacing, 0.0);
  threads = resolve_thread_count(threads);
  // Corner 0 of each vertex's float cell is the nearest float point; the
  // rest are tried in order of their index by the vertices the guard sent
  // back, all vertices of a round at once (apply_moves(): checked in
  // parallel, a move sent back tried once more alone; the outcome does not
  // depend on the thread count).
  struct Pending {
    int vertex;
    Vec3 from;
    int corner;
  };
  // Candidates 0 to 7: the corners; from 8 on, the lattice's points
  // (lattice_offsets()) around the nearest float point.
  const std::vector<Eigen::Vector3i>& lattice = lattice_offsets();
  const int candidates = 8 + static_cast<int>(lattice.size());
  const auto corner_point = [&](const Vec3& p, int corner) {
    if (corner >= 8) {
      const Eigen::Vector3i& o = lattice[static_cast<std::size_t>(corner - 8)];
      const Vec3 n = round_to_float(p);
      return Vec3(float_steps(n.x(), o.x()), float_steps(n.y(), o.y()), float_steps(n.z(), o.z()));
    }
    const auto bx = float_bracket(p.x()), by = float_bracket(p.y()), bz = float_bracket(p.z());
    return Vec3(bx[corner & 1], by[(corner >> 1) & 1], bz[(corner >> 2) & 1]);
  };
  // The next candidate from w.corner on that is a point not tried yet (a
  // coordinate already a float has one value for both of its corners; the
  // lattice holds the cell's corners again).
  const auto tried = [&](const Pending& w, const Vec3& q) {
    for (int k = 0; k < std::min(w.corner, 8); ++k)
      if (corner_point(w.from, k) == q) return true;
    return false;
  };
  const auto next_corner = [&](Pending& w) {
    while (w.corner > 0 && w.corner < candidates && tried(w, corner_point(w.from, w.corner))) ++w.corner;
    return w.corner < candidates;
  };
  std::vector<Pending> pending;
  for (auto v : mesh.vertices()) {
    const Vec3 p = to_eigen(mesh.point(v));
    if (round_to_float(p) == p)
      ++result.snapped;
    else
      pending.push_back({v.idx(), p, 0});
  }
  std::vector<IntersectionGuard::Move> round;
  while (!pending.empty()) {
    round.clear();
    for (const Pending& w : pending) round.push_back({w.vertex, corner_point(w.from, w.corner)});
    const std::vector<char> kept = guard.apply_moves(mesh, round, threads);
    std::vector<Pending> next;
    for (std::size_t k = 0; k < round.size(); ++k) {
      Pending w = pending[k];
      if (kept[k]) {
        result.largest_move = std::max(result.largest_move, (round[k].to - w.from).norm());
        ++result.snapped;
        continue;
      }
      ++w.corner;
      if (next_corner(w))
        next.push_back(w);
      else
        ++result.refused;
    }
    pending.swap(next);
  }
  return result;
}

}  // namespace gdm
