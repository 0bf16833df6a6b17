// Tests of gdm/mesh_checks.h on meshes generated here.
#include "gdm/mesh_checks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <map>
#include <vector>

#include "gdm/errors.h"
#include "gdm/mesh_order.h"
#include "gdm/predicates.h"
#include "gdm/resampler.h"
#include "gdm/seed.h"

namespace {

using gdm::Mesh;
using gdm::Vec3;

constexpr double kPi = 3.14159265358979323846;

// Adds triangle (i, j, k) oriented so that its normal points away from
// `inside` (a point on the inner side of the face).
void add_outward_face(Mesh& mesh, const std::vector<Mesh::VertexHandle>& v, int i,
                      int j, int k, const Vec3& inside) {
  const Vec3 a = gdm::to_eigen(mesh.point(v[i])), b = gdm::to_eigen(mesh.point(v[j])),
             c = gdm::to_eigen(mesh.point(v[k]));
  const Vec3 normal = (b - a).cross(c - a);
  const Vec3 centroid = (a + b + c) / 3.0;
  const auto f = normal.dot(centroid - inside) >= 0
                     ? mesh.add_face(v[i], v[j], v[k])
                     : mesh.add_face(v[i], v[k], v[j]);
  ASSERT_TRUE(f.is_valid()) << "face " << i << " " << j << " " << k;
}

// Axis-aligned box as 8 vertices and 12 outward triangles; `skip_face` (0..5)
// leaves out the two triangles of one side.
void add_box(Mesh& mesh, const Vec3& lo, const Vec3& hi, int skip_face = -1) {
  std::vector<Mesh::VertexHandle> v;
  for (int i = 0; i < 8; ++i)
    v.push_back(mesh.add_vertex(Mesh::Point(i & 1 ? hi.x() : lo.x(),
                                            i & 2 ? hi.y() : lo.y(),
                                            i & 4 ? hi.z() : lo.z())));
  // Quads in cyclic order: -x, +x, -y, +y, -z, +z.
  const int quads[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
  const Vec3 centre = 0.5 * (lo + hi);
  for (int q = 0; q < 6; ++q) {
    if (q == skip_face) continue;
    add_outward_face(mesh, v, quads[q][0], quads[q][1], quads[q][2], centre);
    add_outward_face(mesh, v, quads[q][0], quads[q][2], quads[q][3], centre);
  }
}

Mesh make_tetrahedron() {
  Mesh mesh;
  std::vector<Mesh::VertexHandle> v = {
      mesh.add_vertex(Mesh::Point(0, 0, 0)), mesh.add_vertex(Mesh::Point(1, 0, 0)),
      mesh.add_vertex(Mesh::Point(0, 1, 0)), mesh.add_vertex(Mesh::Point(0, 0, 1))};
  const Vec3 inside(0.1, 0.1, 0.1);
  add_outward_face(mesh, v, 0, 1, 2, inside);
  add_outward_face(mesh, v, 0, 1, 3, inside);
  add_outward_face(mesh, v, 1, 2, 3, inside);
  add_outward_face(mesh, v, 2, 0, 3, inside);
  return mesh;
}

// Icosahedron with edge length 2: vertices (0, +-1, +-phi) and cyclic
// permutations; faces are the vertex triples at mutual distance 2.
Mesh make_icosahedron() {
  Mesh mesh;
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> p;
  for (const double s1 : {-1.0, 1.0})
    for (const double s2 : {-phi, phi}) {
      p.emplace_back(0, s1, s2);
      p.emplace_back(s1, s2, 0);
      p.emplace_back(s2, 0, s1);
    }
  std::vector<Mesh::VertexHandle> v;
  for (const Vec3& q : p) v.push_back(mesh.add_vertex(gdm::to_point(q)));
  auto adjacent = [&](int i, int j) { return std::abs((p[i] - p[j]).norm() - 2.0) < 1e-9; };
  for (int i = 0; i < 12; ++i)
    for (int j = i + 1; j < 12; ++j)
      for (int k = j + 1; k < 12; ++k)
        if (adjacent(i, j) && adjacent(j, k) && adjacent(i, k))
          add_outward_face(mesh, v, i, j, k, Vec3::Zero());
  return mesh;
}

// Torus with major radius R, minor radius r, n x m quads split in two.
Mesh make_torus(double R, double r, int n, int m) {
  Mesh mesh;
  std::vector<Mesh::VertexHandle> v;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = 2 * kPi * i / n, w = 2 * kPi * j / m;
      v.push_back(mesh.add_vertex(Mesh::Point((R + r * std::cos(w)) * std::cos(u),
                                              (R + r * std::cos(w)) * std::sin(u),
                                              r * std::sin(w))));
    }
  auto id = [&](int i, int j) { return ((i + n) % n) * m + (j + m) % m; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      // A point of the tube's core circle next to this quad lies inside.
      const double u = 2 * kPi * (i + 0.5) / n;
      const Vec3 inside(R * std::cos(u), R * std::sin(u), 0.0);
      add_outward_face(mesh, v, id(i, j), id(i + 1, j), id(i + 1, j + 1), inside);
      add_outward_face(mesh, v, id(i, j), id(i + 1, j + 1), id(i, j + 1), inside);
    }
  return mesh;
}

// Quadratic reference count of improperly intersecting face pairs.
std::size_t brute_force_pairs(const Mesh& mesh) {
  std::vector<std::array<Vec3, 3>> points;
  std::vector<std::array<int, 3>> ids;
  for (const auto f : mesh.faces()) {
    std::array<Vec3, 3> p;
    std::array<int, 3> id;
    int k = 0;
    for (const auto v : mesh.fv_range(f)) {
      p[k] = gdm::to_eigen(mesh.point(v));
      id[k] = v.idx();
      ++k;
    }
    points.push_back(p);
    ids.push_back(id);
  }
  std::size_t count = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
    for (std::size_t j = i + 1; j < points.size(); ++j)
      count += gdm::triangles_intersect_improperly(points[i], ids[i], points[j], ids[j]);
  return count;
}

TEST(MeshChecks, tetrahedron_is_closed_manifold_genus_zero) {
  const Mesh mesh = make_tetrahedron();
  const gdm::MeshReport r = gdm::measure(mesh);
  EXPECT_EQ(r.vertices, 4u);
  EXPECT_EQ(r.faces, 4u);
  EXPECT_EQ(r.edges, 6u);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.two_manifold);
  EXPECT_EQ(r.euler, 2);
  EXPECT_EQ(r.genus, 0);
  EXPECT_EQ(r.components, 1);
  EXPECT_EQ(r.self_intersections, 0u);
  EXPECT_NEAR(r.volume, 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(r.area, 1.5 + std::sqrt(3.0) / 2.0, 1e-14);
  EXPECT_NEAR(r.min_angle_deg, 45.0, 1e-12);
}

TEST(MeshChecks, cube_far_from_origin_has_analytic_volume_and_area) {
  Mesh mesh;
  const Vec3 lo(1000.0, -2000.0, 500.0);
  add_box(mesh, lo, lo + Vec3(2, 2, 2));
  const gdm::MeshReport r = gdm::measure(mesh);
  EXPECT_EQ(r.vertices, 8u);
  EXPECT_EQ(r.faces, 12u);
  EXPECT_EQ(r.edges, 18u);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.two_manifold);
  EXPECT_EQ(r.euler, 2);
  EXPECT_EQ(r.genus, 0);
  EXPECT_EQ(r.components, 1);
  // Coplanar neighbours within a side share an edge and do not fold.
  EXPECT_EQ(r.self_intersections, 0u);
  EXPECT_NEAR(r.volume, 8.0, 1e-9);
  EXPECT_NEAR(r.area, 24.0, 1e-9);
  EXPECT_NEAR(r.min_angle_deg, 45.0, 1e-9);
  // A cube's edges fold by a right angle, the diagonals within a side not at all.
  EXPECT_NEAR(r.max_fold_deg, 90.0, 1e-9);
  EXPECT_EQ(r.folds, 0u);
  EXPECT_EQ(gdm::folded_edges(mesh, 89.0), 12u);
  EXPECT_EQ(gdm::folded_edges(mesh, 0.5), 12u);
}

TEST(MeshChecks, inward_oriented_cube_has_negative_volume) {
  Mesh mesh;
  add_box(mesh, Vec3(0, 0, 0), Vec3(1, 2, 3));
  EXPECT_NEAR(gdm::enclosed_volume(mesh), 6.0, 1e-12);
  Mesh flipped;
  std::vector<Mesh::VertexHandle> v;
  for (const auto vh : mesh.vertices()) v.push_back(flipped.add_vertex(mesh.point(vh)));
  for (const auto f : mesh.faces()) {
    std::vector<Mesh::VertexHandle> corners;
    for (const auto vh : mesh.fv_range(f)) corners.push_back(v[vh.idx()]);
    flipped.add_face(corners[0], corners[2], corners[1]);
  }
  EXPECT_NEAR(gdm::enclosed_volume(flipped), -6.0, 1e-12);
}

TEST(MeshChecks, icosahedron_matches_analytic_values) {
  const Mesh mesh = make_icosahedron();
  const gdm::MeshReport r = gdm::measure(mesh);
  EXPECT_EQ(r.vertices, 12u);
  EXPECT_EQ(r.faces, 20u);
  EXPECT_EQ(r.edges, 30u);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.two_manifold);
  EXPECT_EQ(r.genus, 0);
  EXPECT_EQ(r.components, 1);
  EXPECT_EQ(r.self_intersections, 0u);
  const double a = 2.0;
  EXPECT_NEAR(r.volume, 5.0 / 12.0 * (3.0 + std::sqrt(5.0)) * a * a * a, 1e-12);
  EXPECT_NEAR(r.area, 5.0 * std::sqrt(3.0) * a * a, 1e-12);
  EXPECT_NEAR(r.min_angle_deg, 60.0, 1e-9);
}

TEST(MeshChecks, torus_has_genus_one) {
  const double R = 3.0, r = 1.0;
  const Mesh mesh = make_torus(R, r, 32, 16);
  const gdm::MeshReport rep = gdm::measure(mesh);
  EXPECT_EQ(rep.vertices, 512u);
  EXPECT_EQ(rep.faces, 1024u);
  EXPECT_TRUE(rep.closed);
  EXPECT_TRUE(rep.two_manifold);
  EXPECT_EQ(rep.euler, 0);
  EXPECT_EQ(rep.genus, 1);
  EXPECT_EQ(rep.components, 1);
  EXPECT_EQ(rep.self_intersections, 0u);
  // Inscribed polyhedron: a little less than the smooth torus' 2 pi^2 R r^2.
  const double smooth = 2.0 * kPi * kPi * R * r * r;
  EXPECT_LT(rep.volume, smooth);
  EXPECT_GT(rep.volume, 0.95 * smooth);
}

TEST(MeshChecks, cube_missing_a_face_is_open) {
  Mesh mesh;
  add_box(mesh, Vec3(0, 0, 0), Vec3(1, 1, 1), /*skip_face=*/5);
  EXPECT_FALSE(gdm::is_closed(mesh));
  EXPECT_FALSE(gdm::is_two_manifold(mesh));
  EXPECT_EQ(gdm::euler_characteristic(mesh), 1);  // a disc: 8 - 17 + 10
  EXPECT_EQ(gdm::connected_components(mesh), 1);
  EXPECT_EQ(gdm::self_intersecting_pairs(mesh), 0u);
}

TEST(MeshChecks, empty_mesh_is_not_closed) {
  const Mesh mesh;
  EXPECT_FALSE(gdm::is_closed(mesh));
  EXPECT_FALSE(gdm::is_two_manifold(mesh));
  EXPECT_EQ(gdm::connected_components(mesh), 0);
  EXPECT_EQ(gdm::self_intersecting_pairs(mesh), 0u);
  EXPECT_TRUE(std::isnan(gdm::smallest_angle_degrees(mesh)));
}

TEST(MeshChecks, two_disjoint_cubes_are_two_components) {
  Mesh mesh;
  add_box(mesh, Vec3(0, 0, 0), Vec3(1, 1, 1));
  add_box(mesh, Vec3(3, 0, 0), Vec3(4, 1, 1));
  const gdm::MeshReport r = gdm::measure(mesh);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.two_manifold);
  EXPECT_EQ(r.components, 2);
  EXPECT_EQ(r.euler, 4);
  EXPECT_EQ(r.genus, 0);
  EXPECT_EQ(r.self_intersections, 0u);
  EXPECT_NEAR(r.volume, 2.0, 1e-12);
}

TEST(MeshChecks, sphere_and_torus_genus_sums) {
  Mesh mesh = make_torus(3.0, 1.0, 16, 8);
  add_box(mesh, Vec3(10, 10, 10), Vec3(11, 11, 11));
  EXPECT_EQ(gdm::connected_components(mesh), 2);
  EXPECT_EQ(gdm::euler_characteristic(mesh), 2);
  EXPECT_EQ(gdm::genus(mesh), 1);
}

// Cube A = [0,1]^3 and box B = [.25,.75]^2 x [.5,1.5] poking through A's top.
// Only A's two top triangles meet B's eight side triangles. Each side face of
// B crosses the plane z = 1 along one side of the square [.25,.75]^2, split at
// its midpoint between B's two triangles of that side. A's top diagonal runs
// through two opposite corners of that square, so each square side has
// exactly one end on the diagonal: the B triangle holding that end touches
// both top triangles of A, the other B triangle only one. 4 sides x 3 = 12.
TEST(MeshChecks, box_poking_through_cube_has_twelve_intersecting_pairs) {
  Mesh mesh;
  add_box(mesh, Vec3(0, 0, 0), Vec3(1, 1, 1));
  add_box(mesh, Vec3(0.25, 0.25, 0.5), Vec3(0.75, 0.75, 1.5));
  EXPECT_EQ(gdm::self_intersecting_pairs(mesh), 12u);
  EXPECT_EQ(brute_force_pairs(mesh), 12u);
  EXPECT_EQ(gdm::connected_components(mesh), 2);
}

TEST(MeshChecks, interpenetrating_cubes_self_intersect) {
  Mesh mesh;
  add_box(mesh, Vec3(0, 0, 0), Vec3(1, 1, 1));
  add_box(mesh, Vec3(0.5, 0.3, 0.2), Vec3(1.5, 1.3, 1.2));
  const std::size_t pairs = gdm::self_intersecting_pairs(mesh);
  EXPECT_GT(pairs, 0u);
  EXPECT_EQ(pairs, brute_force_pairs(mesh));
  EXPECT_TRUE(gdm::is_two_manifold(mesh));  // topology alone cannot tell
}

TEST(MeshChecks, cubes_touching_along_a_face_count_as_intersecting) {
  Mesh mesh;
  add_box(mesh, Vec3(0, 0, 0), Vec3(1, 1, 1));
  add_box(mesh, Vec3(1, 0, 0), Vec3(2, 1, 1));  // own vertices, same positions
  const std::size_t pairs = gdm::self_intersecting_pairs(mesh);
  EXPECT_GT(pairs, 0u);
  EXPECT_EQ(pairs, brute_force_pairs(mesh));
}

// A tetrahedron whose apex is moved into its base: each of the three side
// faces folds over onto the base (shared edge, coplanar, apexes on the same
// side) while side faces sharing an edge lie on opposite sides of it: 3.
TEST(MeshChecks, apex_flattened_into_base_gives_three_fold_overs) {
  Mesh mesh = make_tetrahedron();
  mesh.set_point(Mesh::VertexHandle(3), Mesh::Point(0.25, 0.25, 0.0));
  EXPECT_EQ(gdm::self_intersecting_pairs(mesh), 3u);
  EXPECT_NEAR(gdm::enclosed_volume(mesh), 0.0, 1e-15);
  // Pushed through the base the tetrahedron is merely inside out.
  mesh.set_point(Mesh::VertexHandle(3), Mesh::Point(0.25, 0.25, -0.5));
  EXPECT_EQ(gdm::self_intersecting_pairs(mesh), 0u);
  EXPECT_LT(gdm::enclosed_volume(mesh), 0.0);
}

TEST(MeshChecks, icosahedron_vertex_pushed_through_opposite_face) {
  Mesh mesh = make_icosahedron();
  const auto v = Mesh::VertexHandle(0);
  EXPECT_EQ(gdm::self_intersecting_pairs(mesh), 0u);
  const double before = gdm::enclosed_volume(mesh);
  // Through the centre and out beyond the opposite side.
  mesh.set_point(v, mesh.point(v) * -1.6);
  const std::size_t pairs = gdm::self_intersecting_pairs(mesh);
  EXPECT_GT(pairs, 0u);
  EXPECT_EQ(pairs, brute_force_pairs(mesh));
  EXPECT_LT(gdm::enclosed_volume(mesh), before);
  EXPECT_TRUE(gdm::is_closed(mesh));
  EXPECT_TRUE(gdm::is_two_manifold(mesh));
}

TEST(MeshChecks, back_to_back_triangles_are_a_duplicate_face) {
  Mesh mesh;
  const auto a = mesh.add_vertex(Mesh::Point(0, 0, 0));
  const auto b = mesh.add_vertex(Mesh::Point(1, 0, 0));
  const auto c = mesh.add_vertex(Mesh::Point(0, 1, 0));
  ASSERT_TRUE(mesh.add_face(a, b, c).is_valid());
  ASSERT_TRUE(mesh.add_face(a, c, b).is_valid());
  EXPECT_TRUE(gdm::is_closed(mesh));
  EXPECT_EQ(gdm::self_intersecting_pairs(mesh), 1u);
}

// Two tetrahedra sharing only one vertex: every edge has two faces but the
// shared vertex has two separate fans. OpenMesh's add_face refuses to build
// this, so two separate tetrahedra are built and the apex of the second is
// merged into the apex of the first by re-pointing its halfedges.
TEST(MeshChecks, tetrahedra_touching_at_a_vertex_are_not_manifold) {
  Mesh mesh;
  std::vector<Mesh::VertexHandle> v = {
      mesh.add_vertex(Mesh::Point(0, 0, 0)),  mesh.add_vertex(Mesh::Point(1, 0, 0)),
      mesh.add_vertex(Mesh::Point(0, 1, 0)),  mesh.add_vertex(Mesh::Point(0, 0, 1)),
      mesh.add_vertex(Mesh::Point(0, 0, 0)),  mesh.add_vertex(Mesh::Point(-1, 0, 0)),
      mesh.add_vertex(Mesh::Point(0, -1, 0)), mesh.add_vertex(Mesh::Point(0, 0, -1))};
  const Vec3 in1(0.1, 0.1, 0.1), in2(-0.1, -0.1, -0.1);
  for (const auto& f : {std::array<int, 3>{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 2, 3}})
    add_outward_face(mesh, v, f[0], f[1], f[2], in1);
  for (const auto& f : {std::array<int, 3>{4, 5, 6}, {4, 6, 7}, {4, 7, 5}, {5, 6, 7}})
    add_outward_face(mesh, v, f[0], f[1], f[2], in2);
  ASSERT_TRUE(gdm::is_two_manifold(mesh));
  ASSERT_EQ(gdm::connected_components(mesh), 2);
  const std::size_t touching_apart = gdm::self_intersecting_pairs(mesh);
  EXPECT_EQ(touching_apart, 9u);  // the 3 + 3 faces at the two coincident apexes
  for (const auto h : mesh.halfedges())
    if (mesh.to_vertex_handle(h) == v[4]) mesh.set_vertex_handle(h, v[0]);
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_halfedge_status();
  mesh.request_face_status();
  mesh.status(v[4]).set_deleted(true);
  mesh.garbage_collection();
  ASSERT_EQ(mesh.n_vertices(), 7u);
  EXPECT_TRUE(gdm::is_closed(mesh));
  EXPECT_FALSE(gdm::is_two_manifold(mesh));
  EXPECT_EQ(gdm::connected_components(mesh), 2);
  EXPECT_EQ(gdm::euler_characteristic(mesh), 3);  // 7 - 12 + 8
  // Now the apex is one vertex: the fans touch only there, no improper pair.
  EXPECT_EQ(gdm::self_intersecting_pairs(mesh), 0u);
}

TEST(MeshChecks, isolated_vertex_is_not_manifold) {
  Mesh mesh = make_tetrahedron();
  EXPECT_TRUE(gdm::is_two_manifold(mesh));
  mesh.add_vertex(Mesh::Point(5, 5, 5));
  EXPECT_FALSE(gdm::is_two_manifold(mesh));
  EXPECT_EQ(gdm::genus(mesh), 0);
}

TEST(MeshChecks, grid_broad_phase_matches_brute_force_on_mixed_sizes) {
  // Many small faces plus a few huge ones (kept out of the grid).
  Mesh mesh = make_torus(3.0, 1.0, 48, 24);
  add_box(mesh, Vec3(-100, -100, -0.2), Vec3(100, 100, 0.2));  // slices the torus
  const std::size_t pairs = gdm::self_intersecting_pairs(mesh);
  EXPECT_GT(pairs, 0u);
  EXPECT_EQ(pairs, brute_force_pairs(mesh));
}

// The grid's cells are listed by counting over the dense grid when it has
// few cells per face, else by sorting (cell, face) pairs: two sliced tori
// far apart along a diagonal leave the grid too sparse to count over; both
// ways must find the pairs a test of every pair finds, and the same count.
TEST(MeshChecks, grid_broad_phase_matches_brute_force_on_a_sparse_grid) {
  Mesh near = make_torus(3.0, 1.0, 48, 24);
  add_box(near, Vec3(-1, -1, -0.2), Vec3(1, 5, 0.2));  // cuts one side of the tube
  const std::size_t dense_pairs = gdm::self_intersecting_pairs(near, 2);
  EXPECT_GT(dense_pairs, 0u);
  EXPECT_EQ(dense_pairs, brute_force_pairs(near));
  Mesh apart = near;
  const Vec3 offset(4.0e4, 3.0e4, 2.0e4);
  std::vector<Mesh::VertexHandle> copy;
  for (const auto v : near.vertices()) copy.push_back(apart.add_vertex(gdm::to_point(gdm::to_eigen(near.point(v)) + offset)));
  for (const auto f : near.faces()) {
    std::vector<Mesh::VertexHandle> corners;
    for (const auto v : near.fv_range(f)) corners.push_back(copy[static_cast<std::size_t>(v.idx())]);
    apart.add_face(corners);
  }
  ASSERT_EQ(apart.n_faces(), 2 * near.n_faces());
  // (Not twice the near count: the copy's rounded coordinates touch or
  // cross in a few other places.)
  const std::size_t expected = brute_force_pairs(apart);
  EXPECT_GT(expected, dense_pairs);
  for (int threads : {1, 2}) EXPECT_EQ(gdm::self_intersecting_pairs(apart, threads), expected) << threads << " threads";
}

// faces_meet_mesh answers for the listed faces what the pair count answers
// for the whole mesh when the rest is free of intersections: a torus (none)
// and a box added at places that miss it, slice it, touch it or sit in its
// hole; the box's faces listed. Two boxes that cross only each other count
// too; an empty list meets nothing.
TEST(MeshChecks, faces_meet_mesh_agrees_with_the_pair_count) {
  const Mesh torus = make_torus(3.0, 1.0, 48, 24);
  ASSERT_EQ(brute_force_pairs(torus), 0u);
  const std::vector<std::pair<Vec3, Vec3>> boxes = {
      {Vec3(10, 10, 10), Vec3(11, 11, 11)},      // far away
      {Vec3(-1, -1, -0.2), Vec3(1, 5, 0.2)},     // slices one side of the tube
      {Vec3(-0.5, -0.5, -0.5), Vec3(0.5, 0.5, 0.5)},  // in the hole, clear of the tube
      {Vec3(2.5, -0.3, -0.3), Vec3(3.5, 0.3, 0.3)},   // inside the tube, clear of its wall
      {Vec3(3.5, -0.5, -2.0), Vec3(4.5, 0.5, 2.0)},   // pierces the tube's wall
  };
  int meeting = 0;
  for (const auto& [lo, hi] : boxes) {
    Mesh mesh = torus;
    const std::size_t before = mesh.n_faces();
    add_box(mesh, lo, hi);
    std::vector<Mesh::FaceHandle> box;
    for (std::size_t f = before; f < mesh.n_faces(); ++f) box.emplace_back(static_cast<int>(f));
    const bool meets = gdm::faces_meet_mesh(mesh, box);
    EXPECT_EQ(meets, brute_force_pairs(mesh) > 0) << lo.transpose() << " .. " << hi.transpose();
    meeting += meets ? 1 : 0;
    EXPECT_FALSE(gdm::faces_meet_mesh(mesh, {}));
  }
  EXPECT_EQ(meeting, 2);  // the slice and the piercing box
  Mesh two;
  add_box(two, Vec3(0, 0, 0), Vec3(1, 1, 1));
  add_box(two, Vec3(0.5, 0.3, 0.2), Vec3(1.5, 1.3, 1.2));
  std::vector<Mesh::FaceHandle> all;
  for (auto f : two.faces()) all.push_back(f);
  EXPECT_TRUE(gdm::faces_meet_mesh(two, all));
}

// measure() gathers the faces, counts the intersecting pairs and finds the
// smallest angle on several threads: every field the same for any count,
// bit for bit, also with deleted faces left in the mesh (not yet collected).
TEST(MeshChecks, measure_is_the_same_for_any_thread_count) {
  Mesh mesh = make_torus(3.0, 1.0, 96, 48);  // 9,216 faces: several chunks per thread
  add_box(mesh, Vec3(-100, -100, -0.2), Vec3(100, 100, 0.2));  // slices the torus
  mesh.request_face_status();
  mesh.request_edge_status();
  mesh.request_halfedge_status();
  mesh.request_vertex_status();
  mesh.delete_face(Mesh::FaceHandle(7), false);
  const gdm::MeshReport one = gdm::measure(mesh, 1);
  EXPECT_GT(one.self_intersections, 0u);
  EXPECT_EQ(one.faces, mesh.n_faces() - 1);
  for (int threads : {2, 3, 8}) {
    const gdm::MeshReport r = gdm::measure(mesh, threads);
    EXPECT_EQ(gdm::to_string(r), gdm::to_string(one)) << threads << " threads";
    EXPECT_EQ(r.self_intersections, one.self_intersections) << threads << " threads";
    EXPECT_EQ(r.volume, one.volume) << threads << " threads";
    EXPECT_EQ(r.area, one.area) << threads << " threads";
    EXPECT_EQ(r.min_angle_deg, one.min_angle_deg) << threads << " threads";
    EXPECT_EQ(r.max_fold_deg, one.max_fold_deg) << threads << " threads";
    EXPECT_EQ(r.folds, one.folds) << threads << " threads";
  }
  EXPECT_EQ(one.max_fold_deg, gdm::sharpest_fold_degrees(mesh));
  EXPECT_EQ(one.folds, gdm::folded_edges(mesh));
  EXPECT_EQ(one.min_angle_deg, gdm::smallest_angle_degrees(mesh));
  EXPECT_EQ(one.volume, gdm::enclosed_volume(mesh));
  EXPECT_EQ(one.area, gdm::surface_area(mesh));
}

// A closed triangular prism whose cross-section has an apex angle of
// `apex` degrees: its two sides at the apex meet in a wedge, their normals
// turn by 180 - apex across the apex edge.
Mesh make_wedge(double apex, double length) {
  Mesh mesh;
  const double half = 0.5 * apex * M_PI / 180.0;
  const Vec3 tip(0, 0, 0), b(std::cos(half), std::sin(half), 0), c(std::cos(half), -std::sin(half), 0);
  std::array<Mesh::VertexHandle, 6> v;
  for (int k = 0; k < 2; ++k) {
    const Vec3 z(0, 0, k * length);
    v[3 * k] = mesh.add_vertex(gdm::to_point(tip + z));
    v[3 * k + 1] = mesh.add_vertex(gdm::to_point(b + z));
    v[3 * k + 2] = mesh.add_vertex(gdm::to_point(c + z));
  }
  mesh.add_face(v[0], v[1], v[2]);  // bottom, normal -z
  mesh.add_face(v[3], v[5], v[4]);  // top, normal +z
  const auto side = [&](int i, int j) {  // the quad between bottom edge i-j and its top copy
    mesh.add_face(v[i], v[j], v[j + 3]);
    mesh.add_face(v[i], v[j + 3], v[i + 3]);
  };
  side(0, 2);
  side(2, 1);
  side(1, 0);
  return mesh;
}

TEST(MeshChecks, wedge_folds_by_its_supplement_at_the_apex) {
  for (const double apex : {10.0, 30.0}) {
    const Mesh mesh = make_wedge(apex, 3.0);
    const gdm::MeshReport r = gdm::measure(mesh);
    ASSERT_TRUE(r.closed && r.two_manifold) << apex;
    ASSERT_GT(r.volume, 0.0) << apex;  // outward faces: the folds are the solid's own
    EXPECT_NEAR(r.max_fold_deg, 180.0 - apex, 1e-9) << apex;
    EXPECT_EQ(r.max_fold_deg, gdm::sharpest_fold_degrees(mesh)) << apex;
    // Beyond kFoldDegrees (160): the 10-degree wedge's apex edge only.
    EXPECT_EQ(r.folds, apex < 20.0 ? 1u : 0u) << apex;
    // The other edges: the caps' six rims fold by 90 degrees, the sides'
    // diagonals by nothing, the two other long edges by 180 minus the base
    // angle (85 or 75 degrees): 95 or 105.
    EXPECT_EQ(gdm::folded_edges(mesh, 100.0), apex < 20.0 ? 1u : 3u) << apex;
    EXPECT_EQ(gdm::folded_edges(mesh, 80.0), 9u) << apex;
    EXPECT_EQ(gdm::folded_edges(mesh, 1.0), 9u) << apex;
  }
}

TEST(MeshChecks, report_line_names_every_field) {
  const std::string line = gdm::to_string(gdm::measure(make_tetrahedron()));
  for (const char* key : {"V=4", "F=4", "E=6", "closed=yes", "two_manifold=yes", "chi=2",
                          "genus=0", "components=1", "self_intersections=0", "volume=",
                          "area=", "min_angle_deg=45", "max_fold_deg=", "folds=0"})
    EXPECT_NE(line.find(key), std::string::npos) << key << " in " << line;
  EXPECT_EQ(line.find('\n'), std::string::npos);
}

}  // namespace

// grow_by_rings (mesh.h) flags exactly what vertices_within finds around each
// flagged vertex, for several rings and a scattered start.
TEST(Mesh, grow_by_rings_flags_exactly_the_vertices_within_the_rings) {
  const gdm::Mesh mesh = gdm::make_geodesic_sphere(gdm::Vec3(0, 0, 0), 10.0, 3);
  std::vector<char> start(mesh.n_vertices(), 0);
  for (std::size_t i = 0; i < start.size(); i += 97) start[i] = 1;
  for (int rings = 0; rings <= 4; ++rings) {
    std::vector<char> expected(mesh.n_vertices(), 0);
    for (std::size_t i = 0; i < start.size(); ++i)
      if (start[i])
        for (int w : gdm::vertices_within(mesh, gdm::Mesh::VertexHandle(static_cast<int>(i)), rings))
          expected[static_cast<std::size_t>(w)] = 1;
    EXPECT_EQ(gdm::grow_by_rings(mesh, start, rings), expected) << rings << " rings";
  }
  EXPECT_EQ(gdm::grow_by_rings(mesh, std::vector<char>(mesh.n_vertices(), 0), 3), std::vector<char>(mesh.n_vertices(), 0));
}

namespace {

// Each face as its three points, rotated to start at the smallest (so the
// orientation is kept), with the generation of each point.
using Corner = std::array<double, 3>;
std::map<std::array<Corner, 3>, int> oriented_faces(const Mesh& mesh) {
  std::map<std::array<Corner, 3>, int> faces;
  for (auto f : mesh.faces()) {
    std::array<Corner, 3> c;
    int k = 0;
    for (auto v : mesh.fv_range(f)) {
      const auto p = mesh.point(v);
      c[static_cast<std::size_t>(k++)] = {p[0], p[1], p[2]};
    }
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    ++faces[c];
  }
  return faces;
}

std::map<Corner, int> generation_by_point(const Mesh& mesh) {
  std::map<Corner, int> g;
  const auto h = gdm::find_generation_property(mesh);
  for (auto v : mesh.vertices()) g[{mesh.point(v)[0], mesh.point(v)[1], mesh.point(v)[2]}] = mesh.property(h, v);
  return g;
}

// Mean index distance between the ends of an edge.
double mean_edge_span(const Mesh& mesh) {
  double sum = 0.0;
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    sum += std::abs(mesh.from_vertex_handle(h).idx() - mesh.to_vertex_handle(h).idx());
  }
  return sum / static_cast<double>(mesh.n_edges());
}

// A sphere refined the way a deforming model is: 1-to-4 subdivisions and
// splits of large faces, each appending its vertices (with a generation).
Mesh refined_sphere() {
  Mesh mesh = gdm::make_geodesic_sphere(Vec3(3.0, -2.0, 1.0), 20.0, 2);
  gdm::generation_property(mesh);
  gdm::subdivide_all(mesh, 1);
  gdm::subdivide_all(mesh, 2);
  gdm::split_large_faces(mesh, 0.2, 3);
  return mesh;
}

}  // namespace

// sort_spatially (mesh_order.h) renumbers a mesh without changing it: the
// same oriented faces on the same points, each point with its generation,
// and the same measures; the returned indices say where each vertex went.
TEST(MeshOrder, sorting_keeps_every_face_its_orientation_and_every_generation) {
  for (Mesh mesh : {refined_sphere(), make_torus(3.0, 1.0, 48, 24)}) {
    if (!gdm::find_generation_property(mesh).is_valid()) gdm::generation_property(mesh);
    const Mesh before = mesh;
    const std::vector<int> to = gdm::sort_spatially(mesh, 0.5);
    ASSERT_EQ(to.size(), before.n_vertices());
    EXPECT_EQ(mesh.n_vertices(), before.n_vertices());
    EXPECT_EQ(mesh.n_faces(), before.n_faces());
    EXPECT_EQ(oriented_faces(mesh), oriented_faces(before));
    EXPECT_EQ(generation_by_point(mesh), generation_by_point(before));
    for (auto v : before.vertices()) EXPECT_EQ(mesh.point(Mesh::VertexHandle(to[static_cast<std::size_t>(v.idx())])), before.point(v));
    const gdm::MeshReport a = gdm::measure(before), b = gdm::measure(mesh);
    EXPECT_TRUE(b.closed);
    EXPECT_TRUE(b.two_manifold);
    EXPECT_EQ(b.genus, a.genus);
    EXPECT_EQ(b.self_intersections, 0u);
    EXPECT_NEAR(b.volume, a.volume, 1e-9 * std::abs(a.volume));
  }
}

// What it is for: after subdivisions append their midpoints, the two ends of
// an edge lie far apart in the arrays; sorted, they lie close. Sorting a
// sorted mesh changes nothing (the order depends on the points alone).
TEST(MeshOrder, neighbours_end_up_near_each_other_and_a_sorted_mesh_stays_as_it_is) {
  Mesh mesh = refined_sphere();
  const double scattered = mean_edge_span(mesh);
  gdm::sort_spatially(mesh, 1.0);
  const double sorted = mean_edge_span(mesh);
  EXPECT_LT(sorted, 0.25 * scattered) << scattered << " -> " << sorted;
  const Mesh once = mesh;
  const std::vector<int> to = gdm::sort_spatially(mesh, 1.0);
  for (std::size_t i = 0; i < to.size(); ++i) EXPECT_EQ(to[i], static_cast<int>(i));
  EXPECT_EQ(oriented_faces(mesh), oriented_faces(once));
  for (auto f : mesh.faces()) {  // the same faces in the same order
    auto a = mesh.cfv_iter(f);
    auto b = once.cfv_iter(f);
    for (int k = 0; k < 3; ++k, ++a, ++b) EXPECT_EQ(a->idx(), b->idx());
  }
}

TEST(MeshOrder, a_cell_that_is_not_a_positive_length_is_refused) {
  Mesh mesh = gdm::make_geodesic_sphere(Vec3(0, 0, 0), 5.0, 1);
  for (double cell : {0.0, -1.0, std::nan("")}) EXPECT_THROW(gdm::sort_spatially(mesh, cell), gdm::InvalidOption);
}
