#include "gdm/float_snap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "gdm/intersection_guard.h"
#include "gdm/parallel.h"

namespace gdm {
namespace {

bool float_exact(double x) { return round_to_float(x) == x; }

// The float values bracketing x: {nearest, the other neighbour} (equal when x is a float).
std::array<double, 2> float_bracket(double x) {
  const double n = round_to_float(x);
  const float nearest = static_cast<float>(n);
  if (n == x) return {n, n};
  const float other = std::nextafter(nearest, n < x ? std::numeric_limits<float>::infinity()
                                                    : -std::numeric_limits<float>::infinity());
  return {n, static_cast<double>(other)};
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

FloatSnapResult snap_to_float(Mesh& mesh, int threads) {
  FloatSnapResult result;
  // Every move is below one float spacing at the largest coordinate.
  double largest = 0.0;
  for (auto v : mesh.vertices()) largest = std::max(largest, to_eigen(mesh.point(v)).cwiseAbs().maxCoeff());
  const double spacing = std::max(largest, 1.0) * std::ldexp(1.0, -23);
  IntersectionGuard guard(mesh, 2.0 * spacing, 0.0);
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
  const auto corner_point = [](const Vec3& p, int corner) {
    const auto bx = float_bracket(p.x()), by = float_bracket(p.y()), bz = float_bracket(p.z());
    return Vec3(bx[corner & 1], by[(corner >> 1) & 1], bz[(corner >> 2) & 1]);
  };
  // The next corner from w.corner on that is a point of its own (a
  // coordinate already a float has one value for both of its corners).
  const auto next_corner = [&](Pending& w) {
    const Vec3 nearest = corner_point(w.from, 0);
    while (w.corner > 0 && w.corner < 8 && corner_point(w.from, w.corner) == nearest) ++w.corner;
    return w.corner < 8;
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
