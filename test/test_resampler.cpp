#include <gtest/gtest.h>

#include "gdm/mesh_checks.h"
#include "gdm/resampler.h"
#include "gdm/seed.h"

using namespace gdm;

TEST(Resampler, global_refinement_gives_v_plus_e_vertices_and_4f_faces) {
  Mesh mesh = make_geodesic_sphere(Vec3(1, 2, 3), 5.0, 1);
  // Make it irregular first: the counts must not depend on the shape.
  split_large_faces(mesh, 1.0, 1);
  const std::size_t v = mesh.n_vertices(), e = mesh.n_edges(), f = mesh.n_faces();
  subdivide_all(mesh, 7);
  EXPECT_EQ(mesh.n_vertices(), v + e);
  EXPECT_EQ(mesh.n_faces(), 4 * f);
  EXPECT_EQ(mesh.n_edges(), 2 * e + 3 * f);
  EXPECT_TRUE(is_closed(mesh));
  EXPECT_TRUE(is_two_manifold(mesh));
  EXPECT_EQ(genus(mesh), 0);
  const auto gen = find_generation_property(mesh);
  ASSERT_TRUE(gen.is_valid());
  std::size_t new_vertices = 0;
  for (auto vh : mesh.vertices()) new_vertices += mesh.property(gen, vh) == 7;
  EXPECT_EQ(new_vertices, e);
  EXPECT_NEAR(enclosed_volume(mesh), 0.0, 1e9);  // finite and oriented (sign checked below)
  EXPECT_GT(enclosed_volume(mesh), 0.0);
}

TEST(Resampler, local_splits_keep_the_mesh_conforming_and_shrink_large_faces) {
  Mesh mesh = make_icosahedron(Vec3::Zero(), 10.0);
  const double area_before = surface_area(mesh);
  const double volume_before = enclosed_volume(mesh);
  std::size_t total = 0;
  for (int pass = 1; pass <= 30; ++pass) {
    const std::size_t splits = split_large_faces(mesh, 4.0, pass);
    total += splits;
    ASSERT_TRUE(is_closed(mesh)) << "pass " << pass;  // no T-junction: every edge has two faces
    ASSERT_TRUE(is_two_manifold(mesh));
    if (splits == 0) break;
  }
  EXPECT_GT(total, 0u);
  for (auto f : mesh.faces()) EXPECT_LE(mesh.calc_face_area(f), 4.0 + 1e-9);
  // Midpoint splits do not change the shape.
  EXPECT_NEAR(surface_area(mesh), area_before, 1e-6 * area_before);
  EXPECT_NEAR(enclosed_volume(mesh), volume_before, 1e-6 * volume_before);
  EXPECT_EQ(self_intersecting_pairs(mesh), 0u);
}

TEST(Resampler, splits_only_faces_above_the_threshold) {
  Mesh mesh = make_geodesic_sphere(Vec3::Zero(), 10.0, 2);
  double largest = 0.0;
  for (auto f : mesh.faces()) largest = std::max(largest, mesh.calc_face_area(f));
  EXPECT_EQ(split_large_faces(mesh, largest + 1e-9, 1), 0u);
  EXPECT_GT(split_large_faces(mesh, largest * 0.999, 1), 0u);
}

TEST(Resampler, flips_make_the_triangulation_delaunay_on_flat_regions) {
  // A flat fan refined with splits is full of long thin triangles; flips fix
  // the smallest angle without changing the shape.
  Mesh mesh = make_icosahedron(Vec3::Zero(), 10.0);
  for (int pass = 1; pass <= 3; ++pass) split_large_faces(mesh, 1.0, pass);
  const double volume_before = enclosed_volume(mesh);
  const double angle_before = smallest_angle_degrees(mesh);
  const std::size_t flips = flip_to_improve(mesh, 1.0, {});
  EXPECT_GT(flips, 0u);
  EXPECT_GE(smallest_angle_degrees(mesh), angle_before);
  EXPECT_NEAR(enclosed_volume(mesh), volume_before, 1e-9 * volume_before);
  EXPECT_TRUE(is_two_manifold(mesh));
  // A veto that refuses every flip leaves the mesh alone.
  Mesh copy = make_icosahedron(Vec3::Zero(), 10.0);
  for (int pass = 1; pass <= 3; ++pass) split_large_faces(copy, 1.0, pass);
  EXPECT_EQ(flip_to_improve(copy, 1.0, [](Mesh::EdgeHandle, const Mesh::VertexHandle(&)[4]) { return false; }), 0u);
}
