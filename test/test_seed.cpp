#include <cmath>

#include <gtest/gtest.h>

#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/seed.h"

using namespace gdm;

TEST(Seed, icosahedron_has_12_vertices_on_the_sphere) {
  const Vec3 c(3, -2, 7);
  const Mesh m = make_icosahedron(c, 4.0);
  EXPECT_EQ(m.n_vertices(), 12u);
  EXPECT_EQ(m.n_faces(), 20u);
  for (auto v : m.vertices()) EXPECT_NEAR((to_eigen(m.point(v)) - c).norm(), 4.0, 1e-12);
  const MeshReport r = measure(m);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.two_manifold);
  EXPECT_EQ(r.genus, 0);
  EXPECT_GT(r.volume, 0.0);  // outward orientation
}

TEST(Seed, geodesic_spheres_have_20_times_4_to_the_k_faces) {
  for (int level = 0; level <= 3; ++level) {
    const Mesh m = make_geodesic_sphere(Vec3::Zero(), 10.0, level);
    EXPECT_EQ(m.n_faces(), 20u * (1u << (2 * level)));
    for (auto v : m.vertices()) EXPECT_NEAR(to_eigen(m.point(v)).norm(), 10.0, 1e-9);
    const double sphere_volume = 4.0 / 3.0 * M_PI * 1000.0;
    EXPECT_LT(enclosed_volume(m), sphere_volume);
    if (level == 3) EXPECT_GT(enclosed_volume(m), 0.97 * sphere_volume);
  }
}

TEST(Seed, bad_seeds_are_refused_with_a_reason) {
  EXPECT_THROW(make_icosahedron(Vec3::Zero(), 0.0), InvalidSeed);
  EXPECT_THROW(make_icosahedron(Vec3::Zero(), NAN), InvalidSeed);
  EXPECT_THROW(make_geodesic_sphere(Vec3::Zero(), 1.0, 12), InvalidSeed);
  Mesh open = make_icosahedron(Vec3::Zero(), 1.0);
  open.request_face_status();
  open.request_edge_status();
  open.request_vertex_status();
  open.delete_face(*open.faces_begin(), false);
  open.garbage_collection();
  try {
    check_seed_mesh(open);
    FAIL() << "an open seed was accepted";
  } catch (const InvalidSeed& e) {
    EXPECT_NE(std::string(e.what()).find("not closed"), std::string::npos) << e.what();
  }
  EXPECT_THROW(check_seed_mesh(Mesh()), InvalidSeed);
  EXPECT_NO_THROW(check_seed_mesh(make_geodesic_sphere(Vec3::Zero(), 1.0, 1)));
}
