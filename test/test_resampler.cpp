#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <vector>

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

namespace {

// An irregular, bumpy closed mesh: many edges far from Delaunay.
Mesh bumpy_sphere(unsigned seed) {
  Mesh mesh = make_geodesic_sphere(Vec3(0.5, -1, 2), 10.0, 2);
  split_large_faces(mesh, 3.0, 1);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.4, 0.4);
  for (auto v : mesh.vertices()) mesh.set_point(v, mesh.point(v) + Mesh::Point(jitter(rng), jitter(rng), jitter(rng)));
  return mesh;
}

std::vector<int> face_corners(const Mesh& mesh) {
  std::vector<int> corners;
  for (auto f : mesh.faces())
    for (auto v : mesh.fv_range(f)) corners.push_back(v.idx());
  return corners;
}

// Flags every edge of the faces around v (what a caller of the flagged pass does).
void flag_around(const Mesh& mesh, Mesh::VertexHandle v, std::vector<char>& dirty) {
  dirty.resize(mesh.n_edges(), 1);
  for (auto f : mesh.vf_range(v))
    for (auto e : mesh.fe_range(f)) dirty[e.idx()] = 1;
}

}  // namespace

TEST(Resampler, flagged_flip_passes_make_the_same_flips_as_full_passes) {
  Mesh full = bumpy_sphere(7), flagged = full;
  std::vector<char> dirty;  // empty: every edge is looked at first
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(full.n_vertices()) - 1);
  std::uniform_real_distribution<double> jitter(-0.6, 0.6);
  std::size_t total = 0;
  for (int round = 0; round < 12; ++round) {
    // A veto that changes with the round though the quad does not (as the
    // guard's does when faces nearby move): vetoed edges must be asked again.
    const auto veto = [round](Mesh::EdgeHandle, const Mesh::VertexHandle(&quad)[4]) {
      return (quad[0].idx() + round) % 3 != 0;
    };
    const std::size_t a = flip_to_improve(full, 30.0, veto);
    const std::size_t b = flip_to_improve(flagged, 30.0, veto, &dirty);
    ASSERT_EQ(a, b) << "round " << round;
    ASSERT_EQ(face_corners(full), face_corners(flagged)) << "round " << round;
    total += a;
    // Some vertices move (the same in both), the flagged caller flags them.
    for (int k = 0; k < 20; ++k) {
      const Mesh::VertexHandle v(pick(rng));
      const Mesh::Point d(jitter(rng), jitter(rng), jitter(rng));
      full.set_point(v, full.point(v) + d);
      flagged.set_point(v, flagged.point(v) + d);
      flag_around(flagged, v, dirty);
    }
  }
  EXPECT_GT(total, 20u);  // the passes did flip
}

TEST(Resampler, splits_of_flagged_faces_are_those_of_a_full_pass_when_the_others_are_refused) {
  Mesh full = bumpy_sphere(3), flagged = full;
  const double limit = 2.0;
  const auto too_large = [](Mesh& m, double max_area) {
    return [&m, max_area](Mesh::FaceHandle f, Mesh::HalfedgeHandle) {
      auto it = m.cfv_iter(f);
      const Vec3 a = to_eigen(m.point(*it)), b = to_eigen(m.point(*++it)), c = to_eigen(m.point(*++it));
      return 0.5 * (b - a).cross(c - a).norm() > max_area;
    };
  };
  // Flagged: exactly the faces the select accepts, plus some it refuses.
  std::vector<char> flags(flagged.n_faces(), 0);
  std::size_t accepted = 0;
  for (auto f : flagged.faces()) {
    const bool yes = too_large(flagged, limit)(f, Mesh::HalfedgeHandle());
    accepted += yes;
    flags[f.idx()] = yes || f.idx() % 4 == 0;
  }
  ASSERT_GT(accepted, 10u);
  ASSERT_LT(accepted, flagged.n_faces());
  const std::size_t a = split_longest_edges(full, 2, too_large(full, limit));
  const std::size_t b = split_longest_edges(flagged, 2, too_large(flagged, limit), &flags);
  EXPECT_EQ(a, b);
  EXPECT_EQ(face_corners(full), face_corners(flagged));
  // Flags that leave out accepted faces leave them unsplit.
  std::vector<char> none(flagged.n_faces(), 0);
  EXPECT_EQ(split_longest_edges(flagged, 3, too_large(flagged, 0.0), &none), 0u);
}

namespace {

// Twice the mean over the faces of the circumradius squared: a face's
// sagitta over a sphere of radius R is its circumradius squared over 2R, so
// this is what the faces miss of the sphere, times R.
double mean_circumradius_squared(const Mesh& mesh) {
  double sum = 0.0;
  for (auto f : mesh.faces()) {
    auto it = mesh.cfv_iter(f);
    const Vec3 a = to_eigen(mesh.point(*it)), b = to_eigen(mesh.point(*++it)), c = to_eigen(mesh.point(*++it));
    const double la = (b - c).norm(), lb = (a - c).norm(), lc = (a - b).norm();
    const double twice_area = (b - a).cross(c - a).norm();
    sum += std::pow(la * lb * lc / (2.0 * twice_area), 2);
  }
  return sum / static_cast<double>(mesh.n_faces());
}

// A geodesic sphere whose vertices were pushed along it by up to a third of
// an edge (a fixed seed), as a reduction leaves a smooth surface's faces.
Mesh uneven_sphere(const Vec3& c, double radius) {
  Mesh mesh = make_geodesic_sphere(c, radius, 3);
  std::mt19937 rng(61);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double edge = mesh.calc_edge_length(*mesh.edges_begin());
  for (auto v : mesh.vertices()) {
    const Vec3 p = to_eigen(mesh.point(v)) - c;
    Vec3 t(u(rng), u(rng), u(rng));
    t -= t.dot(p.normalized()) * p.normalized();
    const Vec3 q = p + (edge / 3.0) * t.normalized() * std::abs(u(rng));
    mesh.set_point(v, to_point(c + radius * q.normalized()));
  }
  return mesh;
}

}  // namespace

// relax_tangentially on a sphere whose faces are uneven: the faces' sagitta
// falls (once the vertices are put back on the sphere, as the face budget's
// fit does) and the smallest angle rises, while the moves stay along the
// surface: no vertex leaves the sphere by more than t^2 / R for steps t of at
// most a voxel, and the sphere shrinks by less than a tenth of what the same
// passes toward the neighbours' centroid (relax_toward_neighbours) take.
TEST(Resampler, tangential_relaxation_evens_out_faces_along_the_surface) {
  const Vec3 c(3, -2, 5);
  const double radius = 12.0;
  Mesh mesh = uneven_sphere(c, radius);
  const auto radial_offsets = [&](const Mesh& m, double& worst, double& mean) {
    worst = 0.0;
    mean = 0.0;
    for (auto v : m.vertices()) {
      const double off = (to_eigen(m.point(v)) - c).norm() - radius;
      worst = std::max(worst, std::abs(off));
      mean += off / static_cast<double>(m.n_vertices());
    }
  };
  const auto anywhere = [](Mesh::VertexHandle, const Vec3&) { return true; };
  Mesh plain = mesh;
  std::vector<Mesh::VertexHandle> all(plain.vertices().begin(), plain.vertices().end());
  relax_toward_neighbours(plain, all, 0.5, 1.0, 3, nullptr, anywhere);
  double plain_worst = 0.0, plain_mean = 0.0;
  radial_offsets(plain, plain_worst, plain_mean);

  const double before = mean_circumradius_squared(mesh);
  const double angle_before = smallest_angle_degrees(mesh);
  const std::size_t moves = relax_tangentially(mesh, {}, 0.5, 1.0, 3, nullptr, anywhere);
  EXPECT_GT(moves, mesh.n_vertices());
  double worst = 0.0, mean = 0.0;
  radial_offsets(mesh, worst, mean);
  EXPECT_LE(worst, 1.0 / radius);
  EXPECT_LT(std::abs(mean), 0.1 * std::abs(plain_mean));
  for (auto v : mesh.vertices()) mesh.set_point(v, to_point(c + radius * (to_eigen(mesh.point(v)) - c).normalized()));
  const double after = mean_circumradius_squared(mesh);
  std::printf("mean circumradius^2 %.4f -> %.4f, smallest angle %.1f -> %.1f deg, moves %zu; off the sphere at most %.4f, "
              "mean %.5f (toward the centroid: %.4f, %.5f)\n",
              before, after, angle_before, smallest_angle_degrees(mesh), moves, worst, mean, plain_worst, plain_mean);
  EXPECT_LT(after, 0.9 * before);
  EXPECT_GT(smallest_angle_degrees(mesh), angle_before + 5.0);
  EXPECT_TRUE(is_two_manifold(mesh));
  EXPECT_EQ(genus(mesh), 0);
}

// crease_vertices on a cube built from a geodesic sphere (each vertex pushed
// out onto the cube of half-width 10): at 30 degrees the creases' vertices
// are some of those with a neighbour on another side of the cube, none of
// those whose neighbours all lie on their side. relax_tangentially with the
// latter free: each moves within its flat side (the cube keeps its shape
// exactly), the held ones and those whose moves `accept` refuses stay where
// they are.
TEST(Resampler, tangential_relaxation_keeps_held_vertices_and_flat_sides) {
  Mesh mesh = make_geodesic_sphere(Vec3::Zero(), 1.0, 3);
  for (auto v : mesh.vertices()) {
    const Vec3 p = to_eigen(mesh.point(v));
    mesh.set_point(v, to_point(10.0 * p / p.cwiseAbs().maxCoeff()));
  }
  const auto on_side = [](const Vec3& p, int axis, double sign) { return sign * p[axis] > 10.0 - 1e-9; };
  const std::vector<char> creases = crease_vertices(mesh, 30.0);
  std::vector<char> held(mesh.n_vertices(), 1);
  std::size_t on_creases = 0, inside_sides = 0;
  for (auto v : mesh.vertices()) {
    const Vec3 p = to_eigen(mesh.point(v));
    const auto i = static_cast<std::size_t>(v.idx());
    int axis = 0;
    p.cwiseAbs().maxCoeff(&axis);
    const double sign = p[axis] > 0.0 ? 1.0 : -1.0;
    bool flat = true;
    for (auto w : mesh.vv_range(v)) flat = flat && on_side(to_eigen(mesh.point(w)), axis, sign);
    on_creases += creases[i] ? 1 : 0;
    if (!flat) continue;
    ++inside_sides;
    EXPECT_FALSE(creases[i]) << p.transpose();
    held[i] = 0;
  }
  ASSERT_GT(on_creases, 50u);
  ASSERT_GT(inside_sides, 100u);
  std::vector<Vec3> before;
  for (auto v : mesh.vertices()) before.push_back(to_eigen(mesh.point(v)));
  // Every third vertex refuses to move.
  const auto accept = [](Mesh::VertexHandle v, const Vec3&) { return v.idx() % 3 != 0; };
  const std::size_t moves = relax_tangentially(mesh, held, 0.5, 1.0, 3, nullptr, accept);
  EXPECT_GT(moves, 100u);
  for (auto v : mesh.vertices()) {
    const Vec3 p = to_eigen(mesh.point(v));
    const auto i = static_cast<std::size_t>(v.idx());
    if (held[i] || v.idx() % 3 == 0) EXPECT_EQ(p, before[i]);
    int axis = 0;
    before[i].cwiseAbs().maxCoeff(&axis);
    EXPECT_NEAR(p[axis], before[i][axis], 1e-9) << p.transpose();
  }
}
