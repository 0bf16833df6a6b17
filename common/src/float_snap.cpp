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
  // parallel, the outcome independent of the thread count).
  struct Pending {
    int vertex;
    Vec3 from;
    int corner;
  };
  std::vector<Pending> pending;
  for (auto v : mesh.vertices()) {
    const Vec3 p = to_eigen(mesh.point(v));
    if (round_to_float(p) == p) {
      ++result.snapped;
      continue;
    }
    pending.push_back({v.idx(), p, 0});
  }
  std::vector<IntersectionGuard::Move> round;
  std::vector<Pending> refused;
  while (!pending.empty()) {
    round.clear();
    std::vector<Pending> next;
    for (Pending& w : pending) {
      const auto bx = float_bracket(w.from.x()), by = float_bracket(w.from.y()), bz = float_bracket(w.from.z());
      const Vec3 nearest(bx[0], by[0], bz[0]);
      Vec3 q = nearest;
      for (; w.corner < 8; ++w.corner) {
        q = Vec3(bx[w.corner & 1], by[(w.corner >> 1) & 1], bz[(w.corner >> 2) & 1]);
        if (w.corner == 0 || q != nearest) break;
      }
      if (w.corner == 8) {
        refused.push_back(w);
        continue;
      }
      round.push_back({w.vertex, q});
      next.push_back(w);
    }
    const std::vector<char> kept = guard.apply_moves(mesh, round, threads, false);
    pending.clear();
    for (std::size_t k = 0; k < round.size(); ++k) {
      if (kept[k]) {
        result.largest_move = std::max(result.largest_move, (round[k].to - next[k].from).norm());
        ++result.snapped;
      } else {
        ++next[k].corner;
        pending.push_back(next[k]);
      }
    }
  }
  // A vertex every corner of whose cell was sent back, each time beside
  // other moves of its round, tries them all once more alone, against the
  // final places of the others (the one-at-a-time check, as before batches).
  for (const Pending& w : refused) {
    const Mesh::VertexHandle v(w.vertex);
    const auto bx = float_bracket(w.from.x()), by = float_bracket(w.from.y()), bz = float_bracket(w.from.z());
    bool done = false;
    for (int corner = 0; corner < 8 && !done; ++corner) {
      const Vec3 q(bx[corner & 1], by[(corner >> 1) & 1], bz[(corner >> 2) & 1]);
      if (corner > 0 && q == Vec3(bx[0], by[0], bz[0])) continue;
      if (guard.move_is_safe(v, q)) {
        result.largest_move = std::max(result.largest_move, (q - w.from).norm());
        mesh.set_point(v, to_point(q));
        done = true;
      }
    }
    ++(done ? result.snapped : result.refused);
  }
  return result;
}

}  // namespace gdm
