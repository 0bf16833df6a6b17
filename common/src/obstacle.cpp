#include "gdm/obstacle.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gdm/errors.h"
#include "gdm/predicates.h"

namespace gdm {
namespace {
// Distinct ids: the model and the obstacle share no vertex, so any contact
// counts, degenerate obstacle triangles (points, segments) included.
constexpr std::array<int, 3> kModelIds{-1, -2, -3};
constexpr std::array<int, 3> kObstacleIds{-4, -5, -6};
}  // namespace

Obstacle::Obstacle(std::vector<Triangle> triangles) : triangles_(std::move(triangles)) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  double edges = 0.0;
  for (const auto& t : triangles_) {
    for (const auto& p : t) {
      if (!p.allFinite()) throw InvalidOption("an obstacle triangle has a non-finite vertex");
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    edges += ((t[1] - t[0]).norm() + (t[2] - t[1]).norm() + (t[0] - t[2]).norm()) / 3.0;
  }
  if (triangles_.empty()) return;
  // About two mean edges a cell, and at most ~2 million cells over the box.
  const double mean_edge = edges / static_cast<double>(triangles_.size());
  double cell = std::max(2.0 * mean_edge, (hi - lo).maxCoeff() / 128.0);
  if (!(cell > 0.0)) cell = 1.0;  // a single point (or copies of it)
  grid_.reset(cell, 0.0);
  for (std::size_t i = 0; i < triangles_.size(); ++i) {
    const auto& t = triangles_[i];
    grid_.insert_box(static_cast<int>(i), t[0].cwiseMin(t[1]).cwiseMin(t[2]), t[0].cwiseMax(t[1]).cwiseMax(t[2]));
  }
}

bool Obstacle::blocks(const Triangle& t) const {
  if (triangles_.empty()) return false;
  const Vec3 lo = t[0].cwiseMin(t[1]).cwiseMin(t[2]);
  const Vec3 hi = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
  const auto touches = [&](int i) {
    return triangles_intersect_improperly(t, kModelIds, triangles_[i], kObstacleIds);
  };
  // A box far larger than the obstacle's cells: test every triangle once.
  const Vec3 span = (hi - lo) / grid_.cell_size();
  if (!((span.array() + 1.0).prod() < static_cast<double>(4 * grid_.cell_count() + 64))) {
    for (std::size_t i = 0; i < triangles_.size(); ++i)
      if (grid_.box_meets(static_cast<int>(i), lo, hi) && touches(static_cast<int>(i))) return true;
    return false;
  }
  return grid_.any_near(lo, hi, touches);
}

bool Obstacle::blocks_move(const Mesh& mesh, Mesh::VertexHandle v, const Vec3& p) const {
  for (auto h : mesh.voh_range(v)) {
    if (mesh.is_boundary(h)) continue;
    const Triangle t{p, to_eigen(mesh.point(mesh.to_vertex_handle(h))),
                     to_eigen(mesh.point(mesh.to_vertex_handle(mesh.next_halfedge_handle(h))))};
    if (blocks(t)) return true;
  }
  return false;
}

}  // namespace gdm
