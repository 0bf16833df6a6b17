#include <gtest/gtest.h>

#include <cmath>

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
