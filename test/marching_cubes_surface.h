// Test helper: the marching-cubes iso-surface of a volume as a triangle soup
// (the same cell polygons phantoms::marching_cubes_triangle_count counts), and
// the unsigned distance from points to a triangle soup.
#pragma once

#include <array>
#include <unordered_map>
#include <vector>

#include "gdm/volume.h"

namespace gdm::test {

using Triangle = std::array<Vec3, 3>;

// Each cell's polygons (corners at the linearly interpolated crossings on
// the cell edges, ambiguous faces separating the corners at or above the
// threshold), fan-triangulated; physical coordinates.
std::vector<Triangle> marching_cubes(const Volume& volume, double threshold);

// Unsigned distance to the nearest triangle (a uniform grid of cell `cell`
// mm, searched ring by ring).
class TriangleDistance {
 public:
  TriangleDistance(std::vector<Triangle> triangles, double cell);
  double operator()(const Vec3& p) const;

 private:
  std::array<long, 3> key(const Vec3& p) const;
  static long long hash(long i, long j, long k);
  std::vector<Triangle> triangles_;
  double cell_;
  std::unordered_map<long long, std::vector<int>> grid_;
};

}  // namespace gdm::test
