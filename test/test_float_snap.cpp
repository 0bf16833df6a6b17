#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "gdm/float_snap.h"
#include "gdm/mesh_checks.h"
#include "gdm/seed.h"

namespace {

// A geodesic sphere squashed along z into a pancake `thickness` mm thick, far
// from the origin, so its two sheets lie a few float spacings apart.
gdm::Mesh pancake(double thickness, int level) {
  const gdm::Vec3 centre(100.3, 100.7, 100.1);
  gdm::Mesh mesh = gdm::make_geodesic_sphere(gdm::Vec3::Zero(), 10.0, level);
  for (auto v : mesh.vertices()) {
    gdm::Vec3 p = gdm::to_eigen(mesh.point(v));
    p.z() *= thickness / 20.0;
    mesh.set_point(v, gdm::to_point(centre + p));
  }
  return mesh;
}

// `layers` pancakes `thickness` mm thick stacked `gap` mm apart (each a
// geodesic sphere of level 2 squashed, a little smaller than the one below),
// turned by `turn`, near (75, 32, -31) where the float spacing is 7.6e-6 mm
// along x: six sheets within a few float spacings, as where a model folds
// flat onto itself and another sheet lies in the fold.
gdm::Mesh stacked_pancakes(int layers, double thickness, double gap, const Eigen::Matrix3d& turn) {
  const gdm::Vec3 centre(75.3, 31.7, -30.9);
  gdm::Mesh mesh;
  for (int l = 0; l < layers; ++l) {
    const gdm::Mesh one = gdm::make_geodesic_sphere(gdm::Vec3::Zero(), 10.0 - 0.37 * l, 2);
    std::vector<gdm::Mesh::VertexHandle> added;
    for (auto v : one.vertices()) {
      gdm::Vec3 p = gdm::to_eigen(one.point(v));
      p.z() = p.z() * thickness / 20.0 + l * (thickness + gap);
      added.push_back(mesh.add_vertex(gdm::to_point(centre + turn * p)));
    }
    for (auto f : one.faces()) {
      std::vector<gdm::Mesh::VertexHandle> corners;
      for (auto w : one.fv_range(f)) corners.push_back(added[static_cast<std::size_t>(w.idx())]);
      mesh.add_face(corners);
    }
  }
  return mesh;
}

gdm::Mesh naively_rounded(gdm::Mesh mesh) {
  for (auto v : mesh.vertices()) mesh.set_point(v, gdm::to_point(gdm::round_to_float(gdm::to_eigen(mesh.point(v)))));
  return mesh;
}

}  // namespace

TEST(FloatSnap, naive_rounding_of_a_thin_pancake_crosses_and_snapping_does_not) {
  // Float spacing near 100 is 2^-17 mm (7.6e-6); the sheets are ~3 spacings apart.
  const gdm::Mesh original = pancake(2.5e-5, 3);
  ASSERT_EQ(gdm::self_intersecting_pairs(original), 0u);
  ASSERT_FALSE(gdm::is_float_exact(original));
  EXPECT_GT(gdm::self_intersecting_pairs(naively_rounded(original)), 0u) << "the case no longer exercises rounding";

  gdm::Mesh snapped = original;
  const auto result = gdm::snap_to_float(snapped);
  EXPECT_EQ(result.refused, 0u);
  EXPECT_EQ(result.snapped, snapped.n_vertices());
  EXPECT_TRUE(gdm::is_float_exact(snapped));
  EXPECT_EQ(gdm::self_intersecting_pairs(snapped), 0u);
  // Rounding the snapped mesh to float is now lossless.
  EXPECT_EQ(gdm::self_intersecting_pairs(naively_rounded(snapped)), 0u);
  EXPECT_LE(result.largest_move, std::sqrt(3.0) * std::ldexp(1.0, -16));
  const auto report = gdm::measure(snapped);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.two_manifold);
  EXPECT_EQ(report.genus, 0);
}

TEST(FloatSnap, a_mesh_already_in_float_is_unchanged) {
  gdm::Mesh mesh = gdm::make_geodesic_sphere(gdm::Vec3(1.5, 2.25, -3.0), 4.0, 2);
  mesh = naively_rounded(mesh);
  const gdm::Mesh before = mesh;
  const auto result = gdm::snap_to_float(mesh);
  EXPECT_EQ(result.largest_move, 0.0);
  EXPECT_EQ(result.refused, 0u);
  for (auto v : mesh.vertices()) EXPECT_EQ(gdm::to_eigen(mesh.point(v)), gdm::to_eigen(before.point(v)));
}

TEST(FloatSnap, round_to_float_rounds_every_coordinate) {
  const gdm::Vec3 p(-0.60292444847653481, 5.6526032334081595, -3.3);
  const gdm::Vec3 q = gdm::round_to_float(p);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NE(q[i], p[i]);
    EXPECT_EQ(q[i], static_cast<double>(static_cast<float>(p[i])));
  }
}

TEST(FloatSnap, every_move_is_below_one_float_spacing) {
  gdm::Mesh mesh = gdm::make_geodesic_sphere(gdm::Vec3(1000.1, -2000.2, 3000.3), 7.3, 3);
  const gdm::Mesh before = mesh;
  gdm::snap_to_float(mesh);
  EXPECT_TRUE(gdm::is_float_exact(mesh));
  for (auto v : mesh.vertices())
    for (int i = 0; i < 3; ++i) {
      const double x = before.point(v)[i];
      const double spacing = std::nextafter(static_cast<float>(std::abs(x)), 1e30f) - static_cast<float>(std::abs(x));
      EXPECT_LE(std::abs(mesh.point(v)[i] - x), spacing);
    }
}

// Where the sheets lie closer than a float spacing in several layers, every
// corner of some vertices' float cells is on the far side of a sheet (with
// the corners alone, 1 to 40 vertices of each of these stacks were left in
// double precision, measured); the float points a few spacings off are
// tried next, and every vertex finds a safe one.
TEST(FloatSnap, vertices_between_sheets_closer_than_a_float_spacing_find_a_float_point) {
  for (int k = 0; k < 12; ++k) {
    const Eigen::Matrix3d turn = (Eigen::AngleAxisd(0.37 * k + 0.1, gdm::Vec3(0.3, 0.5, 0.8).normalized()) *
                                  Eigen::AngleAxisd(0.91 * k, gdm::Vec3::UnitX()))
                                     .toRotationMatrix();
    const gdm::Mesh original = stacked_pancakes(3, 1e-6, 1e-6, turn);
    ASSERT_EQ(gdm::self_intersecting_pairs(original), 0u) << "turn " << k;
    EXPECT_GT(gdm::self_intersecting_pairs(naively_rounded(original)), 0u) << "turn " << k << " no longer needs the snap";
    gdm::Mesh snapped = original;
    const auto result = gdm::snap_to_float(snapped, 2);
    EXPECT_EQ(result.refused, 0u) << "turn " << k;
    EXPECT_TRUE(gdm::is_float_exact(snapped)) << "turn " << k;
    EXPECT_EQ(gdm::self_intersecting_pairs(snapped), 0u) << "turn " << k;
    // Some vertex needed a point beyond its cell's corners (a corner is
    // less than one spacing away along each axis: 2^-17 mm along x, 2^-19
    // along y and z here), none one further than the lattice's reach.
    const double cell_diagonal = std::ldexp(1.0, -17) * std::sqrt(1.0 + 2.0 / 16.0);
    EXPECT_GT(result.largest_move, cell_diagonal) << "turn " << k;
    EXPECT_LE(result.largest_move, 6.0 * cell_diagonal) << "turn " << k;
  }
}

// What a run checks when the snap refused vertices: the pairs that cross once
// every vertex is rounded to float, as PLY and STL store them.
TEST(FloatSnap, pairs_crossing_when_rounded_counts_what_a_float_file_holds) {
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.4, gdm::Vec3(0.3, 0.5, 0.8).normalized()).toRotationMatrix();
  gdm::Mesh mesh = stacked_pancakes(3, 1e-6, 1e-6, turn);
  ASSERT_FALSE(gdm::is_float_exact(mesh));
  EXPECT_EQ(gdm::pairs_crossing_when_rounded(mesh), gdm::self_intersecting_pairs(naively_rounded(mesh)));
  EXPECT_GT(gdm::pairs_crossing_when_rounded(mesh, 2), 0u);
  gdm::snap_to_float(mesh, 2);
  EXPECT_EQ(gdm::pairs_crossing_when_rounded(mesh, 2), 0u);
}
