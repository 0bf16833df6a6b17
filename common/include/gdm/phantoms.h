// Analytic phantoms for tests, benchmarks and demos: shapes with an exact (or
// exactly-zero-set) signed distance, voxelised with a CT-like partial-volume
// edge, plus noise and a marching-cubes triangle count for comparisons.
#pragma once

#include <functional>
#include <random>
#include <vector>

#include "gdm/mesh.h"
#include "gdm/volume.h"

namespace gdm::phantoms {

// Signed distance in mm (negative inside). Its zero set is the true surface.
using Sdf = std::function<double(const Vec3&)>;

struct Grid {
  Index3 dims{64, 64, 64};
  Vec3 spacing = Vec3::Ones();
  Vec3 origin = Vec3::Zero();
  Eigen::Matrix3d direction = Eigen::Matrix3d::Identity();
  Vec3 center() const;  // physical centre of the grid
};

// value = background + contrast * clamp(0.5 - sdf / edge_width, 0, 1): a
// partial-volume ramp whose mid-value (background + contrast / 2) lies on the
// surface. edge_width defaults to the largest spacing.
Volume voxelize(const Grid& grid, const Sdf& sdf, double background = 50.0, double contrast = 150.0,
                double edge_width = 0.0);

// Shapes.
Sdf sphere(const Vec3& center, double radius);
// Zero set exactly the ellipsoid; use distance_to_ellipsoid for distances.
Sdf ellipsoid(const Vec3& center, const Vec3& radii);
double distance_to_ellipsoid(const Vec3& p, const Vec3& center, const Vec3& radii);
Sdf box(const Vec3& lo, const Vec3& hi);
// The solid `a` without the solid `b`.
Sdf difference(Sdf a, Sdf b);
Sdf unite(std::vector<Sdf> parts);
// A capsule: the points within `radius` of the segment ab.
Sdf capsule(const Vec3& a, const Vec3& b, double radius);
// A tube of radius r around the arc of radius R in the plane z = center.z,
// from angle 0 to `sweep` radians, with round ends: a "C".
Sdf bent_tube(const Vec3& center, double R, double r, double sweep);

// Sets a fraction of the voxels inside the object (sdf < -margin) to the
// background value: salt-and-pepper holes in the object.
Volume with_pepper(const Volume& v, const Sdf& sdf, double fraction, double background, double margin,
                   unsigned seed);
// Adds zero-mean Gaussian noise of the given sigma to every voxel.
Volume with_gaussian_noise(const Volume& v, double sigma, unsigned seed);

// Statistics of |distance(vertex)| over the mesh vertices, in voxels.
struct DistanceStats {
  double mean = 0.0;
  double p95 = 0.0;
  double max = 0.0;
};
DistanceStats vertex_distances(const Mesh& mesh, const std::function<double(const Vec3&)>& distance,
                               double voxel_size, const std::function<bool(const Vec3&)>& include = {});
// Mean, 95th percentile and maximum of distances already in voxels.
DistanceStats distance_stats(std::vector<double> distances);

// The voxels 6-connected to `seed` (included) whose value is below
// `threshold`, as a 0/1 mask in the volume's index order (x fastest): a
// dark region such as the tooth's pulp, for reference volumes and surfaces.
std::vector<char> region_below(const Volume& volume, const Index3& seed, double threshold);

// The number of triangles classic marching cubes produces on the volume at
// the threshold (each cell's polygons, k corners giving k - 2 triangles;
// ambiguous faces separate the corners above the threshold).
std::size_t marching_cubes_triangle_count(const Volume& volume, double threshold);

}  // namespace gdm::phantoms
