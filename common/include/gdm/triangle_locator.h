// Exact nearest distances from points to a triangle soup: how far an input
// lies from a wrap, or a model from a reference surface.
#pragma once

#include <array>
#include <vector>

#include "gdm/mesh.h"

namespace gdm {

using Triangle = std::array<Vec3, 3>;

// The faces of a mesh as a triangle soup (deleted faces skipped).
std::vector<Triangle> triangles_of(const Mesh& mesh);

// Distance from p to the closest point of t (degenerate triangles, down to
// single points, are handled).
double point_triangle_distance(const Vec3& p, const Triangle& t);

// Nearest-triangle distance queries through a uniform grid of buckets (about
// two mean edges each), searched ring by ring until the nearest triangle found
// is closer than anything outside the searched rings: exact.
class TriangleLocator {
 public:
  explicit TriangleLocator(std::vector<Triangle> triangles);
  // Distance from p to the nearest triangle; infinity when there are none.
  double distance(const Vec3& p) const;

 private:
  std::vector<Triangle> triangles_;
  Vec3 origin_ = Vec3::Zero();
  double bucket_ = 1.0;
  std::array<int, 3> n_{1, 1, 1};
  std::vector<std::vector<int>> buckets_;
};

// The mean distance from the vertices and face centroids of `mesh` to the
// triangles of `to`; the same for any thread count.
double mean_distance(const Mesh& mesh, const TriangleLocator& to, int threads);

}  // namespace gdm
