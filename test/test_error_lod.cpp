// The pieces of issue 7 alone (crossing search, split criterion, collapse
// checks), then the error-driven level of detail on the paper's cube with a
// corner missing (section 6.1) and on the real tooth's pulp (section 6.3).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "gdm/deformer.h"
#include "gdm/error_lod.h"
#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/phantoms.h"
#include "gdm/seed.h"
#include "gdm/surface_fit.h"
#include "marching_cubes_surface.h"
#include "shared_data.h"
#include "surface_samples.h"

using namespace gdm;
namespace ph = gdm::phantoms;

namespace {

constexpr double kBackground = 50.0, kContrast = 150.0;
constexpr double kThreshold = kBackground + 0.5 * kContrast;

// A plane z = z0 with a ramp wide enough (4 voxels) that the trilinear field
// is exactly linear near it.
Volume plane_ramp(double z0) {
  ph::Grid grid;
  grid.dims = {16, 16, 16};
  return ph::voxelize(grid, [=](const Vec3& p) { return p.z() - z0; }, kBackground, kContrast, 4.0);
}

Mesh single_closed_box(const Vec3& lo, const Vec3& hi) {
  // A closed mesh whose top face (two triangles) lies in z = hi.z.
  Mesh m;
  Mesh::VertexHandle v[8];
  for (int i = 0; i < 8; ++i)
    v[i] = m.add_vertex(to_point(Vec3(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z())));
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.add_face(v[q[0]], v[q[1]], v[q[2]]);
    m.add_face(v[q[0]], v[q[2]], v[q[3]]);
  }
  return m;
}

}  // namespace

TEST(CrossingSearch, is_exact_on_a_linear_ramp) {
  const Volume volume = plane_ramp(7.3);
  for (const Vec3& dir : {Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(0.3, -0.2, 1).normalized()}) {
    const Vec3 p(8.1, 7.7, 6.65);
    const auto t = find_crossing(volume, kThreshold, p, dir, 2.0, 0.25);
    ASSERT_TRUE(t.has_value());
    EXPECT_NEAR((p + *t * dir).z(), 7.3, 1e-9);
  }
}

// Off a linear field the search stops within a billionth of its step of the
// crossing a bisection finds to full precision (the bracket it stops on
// holds the crossing).
TEST(CrossingSearch, is_within_a_billionth_of_a_step_on_a_curved_field) {
  ph::Grid grid;
  grid.dims = {24, 24, 24};
  const Vec3 c(11.7, 12.2, 11.9);
  const Volume volume = ph::voxelize(grid, [&](const Vec3& p) { return (p - c).norm() - 6.3; }, kBackground, kContrast, 1.0);
  const double step = 0.25;
  int checked = 0, coarse_found = 0;
  for (int k = 0; k < 40; ++k) {
    const double a = 0.7 * k, b = 0.31 * k;
    const Vec3 dir = Vec3(std::cos(a) * std::sin(b + 0.4), std::sin(a) * std::sin(b + 0.4), std::cos(b + 0.4)).normalized();
    const Vec3 p = c + (6.3 + 0.4 * std::sin(1.3 * k)) * Vec3(std::cos(1.1 * k), std::sin(1.1 * k), 0.3).normalized();
    const auto t = find_crossing(volume, kThreshold, p, dir, 2.0, step);
    if (!t) continue;
    // Bisection on the bracket of one step around t.
    const auto g = [&](double s) { return volume.sample(p + s * dir) - kThreshold; };
    double lo = *t - step, hi = *t + step;
    if ((g(lo) <= 0.0) == (g(hi) <= 0.0)) continue;  // two crossings that close: not this test's case
    for (int it = 0; it < 200 && hi - lo > 1e-15; ++it) {
      const double mid = 0.5 * (lo + hi);
      ((g(mid) <= 0.0) == (g(lo) <= 0.0) ? lo : hi) = mid;
    }
    EXPECT_NEAR(*t, 0.5 * (lo + hi), 1e-9 * step) << "search " << k;
    ++checked;
    // Coarser steps bracket over several cells (past a few per axis the
    // cubics give way to sampling): what they find is still a crossing.
    for (const double coarse : {1.5, 3.0, 5.0}) {
      const auto tc = find_crossing(volume, kThreshold, p, dir, 10.0, coarse);
      if (!tc) continue;  // a step over two crossings finds neither
      EXPECT_NEAR(volume.sample(p + *tc * dir), kThreshold, 1e-6 * kContrast) << "search " << k << ", step " << coarse;
      ++coarse_found;
    }
  }
  EXPECT_GE(checked, 30);
  EXPECT_GE(coarse_found, 40);
}

TEST(CrossingSearch, finds_nothing_out_of_reach) {
  const Volume volume = plane_ramp(7.3);
  EXPECT_FALSE(find_crossing(volume, kThreshold, Vec3(8, 8, 11.0), Vec3(0, 0, 1), 1.0, 0.25).has_value());
  EXPECT_FALSE(find_crossing(volume, kThreshold, Vec3(8, 8, 11.0), Vec3(1, 0, 0), 3.0, 0.25).has_value());
  // Within reach from the other side.
  const auto t = find_crossing(volume, kThreshold, Vec3(8, 8, 8.0), Vec3(0, 0, 1), 1.0, 0.25);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, -0.7, 1e-9);
}

TEST(SplitCriterion, measures_the_offset_of_a_face_from_the_surface) {
  const Volume volume = plane_ramp(7.3);
  for (double offset : {0.0, 0.05, 0.3}) {
    Mesh box = single_closed_box(Vec3(4, 4, 3), Vec3(10, 10, 7.3 + offset));
    for (auto f : box.faces()) {
      Vec3 n = Vec3::Zero();
      auto it = box.cfv_iter(f);
      const Vec3 a = to_eigen(box.point(*it)), b = to_eigen(box.point(*++it)), c = to_eigen(box.point(*++it));
      n = (b - a).cross(c - a).normalized();
      if (n.z() > 0.9) EXPECT_NEAR(face_deviation(box, f, volume, kThreshold, 1.5), offset, 1e-9);
    }
    // The two top faces are split at 0.1 only when they are off by more.
    Mesh copy = box;
    const std::size_t top_splits = split_deviating_faces(copy, volume, kThreshold, 0.1, 0.5, 1);
    // Only the top's shared longest edge: the other faces find no crossing
    // within reach along their normals and are left alone.
    EXPECT_EQ(top_splits, offset > 0.1 ? 1u : 0u) << "offset " << offset;
    std::size_t top_split = 0;
    for (auto v : copy.vertices())
      if (std::abs(to_eigen(copy.point(v)).z() - (7.3 + offset)) < 1e-12 && v.idx() >= 8) ++top_split;
    EXPECT_EQ(top_split > 0, offset > 0.1) << "offset " << offset;
  }
}

TEST(SplitCriterion, noise_estimate_is_the_same_for_any_thread_count) {
  ph::Grid grid;
  grid.dims = {36, 36, 36};
  const Volume noisy =
      ph::with_gaussian_noise(ph::voxelize(grid, ph::sphere(grid.center(), 11.0), kBackground, kContrast), 0.07 * kContrast, 9);
  const Mesh mesh = make_geodesic_sphere(grid.center(), 11.0, 4);
  const double one = estimate_crossing_noise(mesh, noisy, kThreshold, 1.5, 1);
  EXPECT_GT(one, 0.0);
  for (const int threads : {2, 3, 8}) EXPECT_EQ(estimate_crossing_noise(mesh, noisy, kThreshold, 1.5, threads), one) << threads;
}

TEST(SplitCriterion, noise_estimate_follows_the_image_noise) {
  // A sphere's threshold crossings, seen from a fine mesh on it: on a clean
  // volume only the faces' chords scatter the distances; the noise adds in
  // quadrature, in proportion to its sigma.
  ph::Grid grid;
  grid.dims = {40, 40, 40};
  const auto sdf = ph::sphere(grid.center(), 12.0);
  const Volume clean = ph::voxelize(grid, sdf, kBackground, kContrast);
  const Mesh mesh = make_geodesic_sphere(grid.center(), 12.0, 4);
  const double none = estimate_crossing_noise(mesh, clean, kThreshold, 1.5);
  const double low = estimate_crossing_noise(mesh, ph::with_gaussian_noise(clean, 0.05 * kContrast, 5), kThreshold, 1.5);
  const double high = estimate_crossing_noise(mesh, ph::with_gaussian_noise(clean, 0.10 * kContrast, 5), kThreshold, 1.5);
  std::printf("crossing noise: clean %.4f, sigma 5%% %.4f, sigma 10%% %.4f mm\n", none, low, high);
  EXPECT_LT(none, 0.05);
  ASSERT_GT(low, none);
  ASSERT_GT(high, low);
  EXPECT_NEAR(std::sqrt(high * high - none * none) / std::sqrt(low * low - none * none), 2.0, 0.4);
  // A face is not split to follow that noise: with the estimate discounted,
  // the faces of the (exact) mesh deviate less than without it.
  const Volume noisy = ph::with_gaussian_noise(clean, 0.05 * kContrast, 5);
  double with = 0.0, without = 0.0;
  for (auto f : mesh.faces()) {
    with += face_deviation(mesh, f, noisy, kThreshold, 1.5, low);
    without += face_deviation(mesh, f, noisy, kThreshold, 1.5);
  }
  EXPECT_LT(with, 0.75 * without);
}

TEST(CollapseChecks, link_condition_refuses_a_collapse_that_pinches) {
  // A triangular bipyramid: the equator a, b, c is a triangle without a face.
  Mesh m;
  const auto top = m.add_vertex({0, 0, 1}), bottom = m.add_vertex({0, 0, -1});
  const auto a = m.add_vertex({1, 0, 0}), b = m.add_vertex({-0.5, 0.8, 0}), c = m.add_vertex({-0.5, -0.8, 0});
  for (auto [p, q] : {std::pair{a, b}, {b, c}, {c, a}}) {
    m.add_face(top, p, q);
    m.add_face(bottom, q, p);
  }
  m.request_vertex_status();
  m.request_edge_status();
  m.request_halfedge_status();
  m.request_face_status();
  ASSERT_TRUE(is_closed(m) && is_two_manifold(m));
  // a-b shares c besides the two apexes: collapsing it would glue two edges.
  EXPECT_FALSE(collapse_keeps_topology(m, m.find_halfedge(a, b)));
  EXPECT_FALSE(collapse_keeps_topology(m, m.find_halfedge(b, a)));
  // top-a only shares b and c, the vertices opposite the edge.
  EXPECT_TRUE(collapse_keeps_topology(m, m.find_halfedge(top, a)));
  m.collapse(m.find_halfedge(top, a));
  m.garbage_collection();
  EXPECT_TRUE(is_closed(m));
  EXPECT_TRUE(is_two_manifold(m));
  EXPECT_EQ(genus(m), 0);
}

namespace {

// A sphere squashed into a thin pancake (0.8 mm) with a rippled top, its
// status attributes requested for collapses: many collapses would push
// faces through the other sheet.
Mesh rippled_pancake() {
  Mesh pancake = make_geodesic_sphere(Vec3::Zero(), 10.0, 2);
  for (auto v : pancake.vertices()) {
    Vec3 p = to_eigen(pancake.point(v));
    p.z() *= 0.04;
    if (p.z() > 0) p.z() *= 1.0 + 0.9 * std::sin(1.7 * p.x()) * std::cos(1.3 * p.y());
    pancake.set_point(v, to_point(p));
  }
  pancake.request_vertex_status();
  pancake.request_edge_status();
  pancake.request_halfedge_status();
  pancake.request_face_status();
  return pancake;
}

// Collapse checks on the geometry alone: no quality floor, any turn short of a flip.
CollapseOptions only_geometry() {
  CollapseOptions o;
  o.min_angle = 0.0;
  o.max_normal_change = 179.9;
  return o;
}

}  // namespace

TEST(CollapseChecks, refuses_exactly_the_collapses_that_would_self_intersect) {
  // A sphere squashed into a thin pancake with a rippled top: many collapses
  // would push faces through the other sheet.
  Mesh pancake = rippled_pancake();
  ASSERT_EQ(self_intersecting_pairs(pancake), 0u);
  CollapseChecker checker(pancake, 2.0);
  const CollapseOptions geometric_only = only_geometry();
  std::size_t intersecting = 0, accepted = 0;
  for (auto h : pancake.halfedges()) {
    if (!collapse_keeps_topology(pancake, h)) continue;
    const bool ok = checker.geometry_ok(h, geometric_only);
    Mesh copy = pancake;
    copy.collapse(copy.find_halfedge(pancake.from_vertex_handle(h), pancake.to_vertex_handle(h)));
    copy.garbage_collection();
    const bool intersects = self_intersecting_pairs(copy) > 0;
    intersecting += intersects;
    accepted += ok;
    EXPECT_FALSE(ok && intersects) << "accepted a collapse that self-intersects, halfedge " << h.idx();
  }
  std::printf("pancake: %zu collapses would self-intersect, %zu accepted\n", intersecting, accepted);
  EXPECT_GT(intersecting, 0u) << "the test shape gives no intersecting collapse: it proves nothing";
  EXPECT_GT(accepted, 0u);
}

TEST(CollapseChecks, a_collapse_to_a_point_is_refused_exactly_when_it_would_self_intersect) {
  // The thin rippled pancake again, each edge merged into a point near its
  // midpoint pushed up or down by about half the pancake's thickness: the
  // checker (one look at the grid over the moved faces, the faces around
  // both ends tested against each other and against the rest) must refuse
  // every collapse that leaves intersecting faces and accept every other
  // one whose faces stay non-degenerate and turn by less than 179.9 degrees.
  Mesh pancake = rippled_pancake();
  ASSERT_EQ(self_intersecting_pairs(pancake), 0u);
  CollapseChecker checker(pancake, 2.0);
  const CollapseOptions geometric_only = only_geometry();
  std::size_t intersecting = 0, accepted = 0, refused_clean = 0;
  for (auto h : pancake.halfedges()) {
    if (!collapse_keeps_topology(pancake, h)) continue;
    const auto from = pancake.from_vertex_handle(h), to = pancake.to_vertex_handle(h);
    const double lift = (h.idx() % 3 == 0 ? 0.4 : (h.idx() % 3 == 1 ? -0.4 : 0.0));
    const Vec3 target = 0.5 * (to_eigen(pancake.point(from)) + to_eigen(pancake.point(to))) + Vec3(0.0, 0.0, lift);
    const bool ok = checker.geometry_ok(h, geometric_only, target);
    Mesh copy = pancake;
    const auto kept = copy.to_vertex_handle(copy.find_halfedge(from, to));
    copy.collapse(copy.find_halfedge(from, to));
    copy.set_point(kept, to_point(target));
    copy.garbage_collection();
    const bool intersects = self_intersecting_pairs(copy) > 0;
    intersecting += intersects;
    accepted += ok;
    EXPECT_FALSE(ok && intersects) << "accepted a collapse that self-intersects, halfedge " << h.idx();
    refused_clean += !ok && !intersects && smallest_angle_degrees(copy) > 0.0;
  }
  std::printf("pancake, collapses to points: %zu would self-intersect, %zu accepted, %zu refused without\n",
              intersecting, accepted, refused_clean);
  EXPECT_GT(intersecting, 0u) << "the test shape gives no intersecting collapse: it proves nothing";
  EXPECT_GT(accepted, 0u);
  EXPECT_EQ(refused_clean, 0u) << "refused collapses that leave a clean, non-degenerate mesh";
}

TEST(CollapseChecks, keeps_a_closed_genus_0_mesh_within_the_tolerance) {
  ph::Grid grid;
  grid.dims = {40, 40, 40};
  const auto sdf = ph::sphere(grid.center(), 12.0);
  const Volume volume = ph::voxelize(grid, sdf, kBackground, kContrast);
  Mesh mesh = make_geodesic_sphere(grid.center(), 12.0, 4);
  const std::size_t before = mesh.n_faces();
  CollapseOptions o;
  o.tolerance = 0.1;
  const std::size_t collapses = collapse_flat_edges(mesh, &volume, kThreshold, o);
  mesh.garbage_collection();
  EXPECT_GT(collapses, 0u);
  EXPECT_EQ(mesh.n_faces(), before - 2 * collapses);
  const MeshReport r = measure(mesh);
  EXPECT_TRUE(r.closed && r.two_manifold) << to_string(r);
  EXPECT_EQ(r.genus, 0);
  EXPECT_EQ(r.self_intersections, 0u);
  for (auto f : mesh.faces()) EXPECT_LE(face_deviation(mesh, f, volume, kThreshold, 1.5), 0.1 + 1e-9);
}

TEST(ErrorLod, options_are_validated_with_named_messages) {
  ph::Grid grid;
  grid.dims = {16, 16, 16};
  const Volume volume = ph::voxelize(grid, ph::sphere(grid.center(), 5.0));
  const auto message = [&](auto change) {
    DeformOptions o;
    o.threshold = kThreshold;
    change(o);
    try {
      validate(o, volume);
    } catch (const InvalidOption& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message([](DeformOptions& o) { o.lod_tolerance = -0.1; }).find("lod_tolerance"), std::string::npos);
  EXPECT_NE(message([](DeformOptions& o) { o.lod_tolerance = 0.001; }).find("lod_tolerance"), std::string::npos);
  EXPECT_NE(message([](DeformOptions& o) { o.lod_tolerance = NAN; }).find("lod_tolerance"), std::string::npos);
  EXPECT_NE(message([](DeformOptions& o) { o.fit_passes = 0; }).find("fit_passes"), std::string::npos);
  EXPECT_NE(message([](DeformOptions& o) { o.fit_smoothing = -0.1; }).find("fit_smoothing"), std::string::npos);
  EXPECT_NE(message([](DeformOptions& o) { o.fit_smoothing = 6.0; }).find("fit_smoothing"), std::string::npos);
  EXPECT_NE(message([](DeformOptions& o) { o.fit_max_distance = 0.0; }).find("fit_max_distance"), std::string::npos);
  EXPECT_NE(message([](DeformOptions& o) { o.lod_min_angle = 70.0; }).find("lod_min_angle"), std::string::npos);
  EXPECT_NE(message([](DeformOptions& o) { o.lod_rounds = 0; }).find("lod_rounds"), std::string::npos);
  EXPECT_EQ(message([](DeformOptions& o) { o.lod_tolerance = 0.1; }), "");
}

TEST(ErrorLod, cube_with_a_corner_missing_keeps_sharp_edges_with_fewer_faces) {
  // Section 6.1: 64^3, a cube with one corner removed; the paper's model has
  // 4,080 faces and rounded edges (Fig. 8).
  ph::Grid grid;
  const auto sdf = ph::difference(ph::box(Vec3(12, 12, 12), Vec3(52, 52, 52)), ph::box(Vec3(32, 32, 32), Vec3(60, 60, 60)));
  const Volume volume = ph::voxelize(grid, sdf, kBackground, kContrast);
  Mesh mesh = make_icosahedron(Vec3(24, 24, 24), 3.0);
  DeformOptions o;
  o.threshold = kThreshold;
  o.lod_tolerance = 0.1;
  const DeformResult result = deform(mesh, volume, o);
  EXPECT_EQ(result.reason, StopReason::converged);
  const MeshReport r = measure(mesh);
  EXPECT_TRUE(r.closed && r.two_manifold) << to_string(r);
  EXPECT_EQ(r.genus, 0);
  EXPECT_EQ(r.self_intersections, 0u);
  const auto d = test::surface_distances(mesh, sdf, 1.0);
  const auto dv = ph::vertex_distances(mesh, sdf, 1.0);
  std::printf("cube: faces %zu; surface mean %.4f p95 %.4f max %.4f; vertices max %.4f; splits %zu, collapses %zu\n",
              mesh.n_faces(), d.mean, d.p95, d.max, dv.max, result.lod_splits, result.lod_collapses);
  EXPECT_LE(d.max, 0.5);
  EXPECT_LT(mesh.n_faces(), 4080u);
}


TEST(ErrorLod, tooth_pulp_against_marching_cubes) {
  Volume volume;
  std::string why;
  if (!test::load_tooth(GDM_TEST_SHARED_DIR, volume, why)) GTEST_SKIP() << why;
  constexpr double kToothThreshold = test::kToothPulpThreshold;
  const Index3 seed_voxel = test::kToothPulpSeed;
  Mesh mesh = make_icosahedron(volume.to_physical(Vec3(seed_voxel[0], seed_voxel[1], seed_voxel[2])), 2.0);
  DeformOptions o;
  o.threshold = kToothThreshold;
  o.polarity = Polarity::object_darker;
  o.lod_tolerance = 0.1;
  const DeformResult result = deform(mesh, volume, o);
  const MeshReport r = measure(mesh);
  EXPECT_TRUE(r.closed && r.two_manifold) << to_string(r);
  EXPECT_EQ(r.genus, 0);
  EXPECT_EQ(r.self_intersections, 0u);
  EXPECT_EQ(result.border_vertices, 0u);

  auto triangles = test::tooth_pulp_surface(volume);
  const std::size_t mc_faces = triangles.size();
  const TriangleLocator mc_surface(std::move(triangles));
  double sum = 0.0, worst = 0.0;
  const auto samples = test::surface_samples(mesh);
  for (const Vec3& p : samples) {
    const double e = mc_surface.distance(p) / volume.voxel_size();
    sum += e;
    worst = std::max(worst, e);
  }
  const double mean = sum / static_cast<double>(samples.size());
  const double ratio = static_cast<double>(mesh.n_faces()) / static_cast<double>(mc_faces);
  std::printf("tooth pulp: %s; %zu faces = %.1f%% of marching cubes' %zu; surface to MC: mean %.4f max %.4f voxel\n",
              to_string(r).c_str(), mesh.n_faces(), 100.0 * ratio, mc_faces, mean, worst);
  EXPECT_LE(mean, 0.15);
  EXPECT_LE(ratio, 0.40);
}

TEST(EdgeNoise, follows_the_voxel_noise_where_the_crossings_understate_it) {
  // A sphere's edge seen from a fine mesh on it: the voxels' noise over the
  // edge's slope is 0 on a clean volume and doubles with the noise's sigma;
  // at 10 % of the contrast it exceeds the crossings' own scatter (which
  // reads crossings a voxel apart, made of the same voxels).
  ph::Grid grid;
  grid.dims = {40, 40, 40};
  const Volume clean = ph::voxelize(grid, ph::sphere(grid.center(), 12.0), kBackground, kContrast);
  const Mesh mesh = make_geodesic_sphere(grid.center(), 12.0, 4);
  const auto edge_noise = [&](const Volume& v, int threads) {
    return estimate_edge_noise(mesh, v, estimate_voxel_noise(v), threads);
  };
  EXPECT_EQ(edge_noise(clean, 1), 0.0);
  const Volume low = ph::with_gaussian_noise(clean, 0.05 * kContrast, 5);
  const Volume high = ph::with_gaussian_noise(clean, 0.10 * kContrast, 5);
  const double a = edge_noise(low, 1), b = edge_noise(high, 1);
  std::printf("edge noise: sigma 5%% %.4f, sigma 10%% %.4f mm; crossing noise at 10%% %.4f mm\n", a, b,
              estimate_crossing_noise(mesh, high, kThreshold, 1.5));
  ASSERT_GT(a, 0.0);
  EXPECT_NEAR(b / a, 2.0, 0.25);
  EXPECT_GT(b, estimate_crossing_noise(mesh, high, kThreshold, 1.5));
  for (const int threads : {2, 3, 8}) EXPECT_EQ(edge_noise(high, threads), b) << threads;
}
