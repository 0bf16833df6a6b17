#include "gdm/float_snap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "gdm/intersection_guard.h"

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

FloatSnapResult snap_to_float(Mesh& mesh) {
  FloatSnapResult result;
  // Every move is below one float spacing at the largest coordinate.
  double largest = 0.0;
  for (auto v : mesh.vertices()) largest = std::max(largest, to_eigen(mesh.point(v)).cwiseAbs().maxCoeff());
  const double spacing = std::max(largest, 1.0) * std::ldexp(1.0, -23);
  IntersectionGuard guard(mesh, 2.0 * spacing, 0.0);
  for (auto v : mesh.vertices()) {
    const Vec3 p = to_eigen(mesh.point(v));
    const auto bx = float_bracket(p.x()), by = float_bracket(p.y()), bz = float_bracket(p.z());
    bool done = false;
    // Corner 0 is the nearest float point; the rest in order of their index.
    for (int corner = 0; corner < 8 && !done; ++corner) {
      const Vec3 q(bx[corner & 1], by[(corner >> 1) & 1], bz[(corner >> 2) & 1]);
      if (corner > 0 && q == Vec3(bx[0], by[0], bz[0])) continue;
      if (q == p || guard.move_is_safe(v, q)) {
        result.largest_move = std::max(result.largest_move, (q - p).norm());
        mesh.set_point(v, to_point(q));
        done = true;
      }
    }
    if (done)
      ++result.snapped;
    else
      ++result.refused;
  }
  return result;
}

}  // namespace gdm
