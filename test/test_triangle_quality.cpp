// Triangle quality (issue 16): the last geometric step removes faces with an
// angle below min_angle (10 degrees by default, up to 30) by guarded flips,
// cap splits, short-edge collapses and relaxation on the model's surface.
// On noisy phantoms (sphere, ellipsoid on 0.5 x 0.5 x 2 mm voxels, branching
// tube, C-shaped tube; Gaussian noise 3 to 10 % of the contrast): the
// smallest angle reaches the bound, the accuracy against the analytic
// surface stays within today's limits, every guarantee holds, and the mesh
// does not depend on the thread count.
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "gdm/deformer.h"
#include "gdm/intersection_guard.h"
#include "gdm/mesh_checks.h"
#include "gdm/phantoms.h"
#include "gdm/seed.h"
#include "gdm/triangle_quality.h"
#include "gdm/triangle_locator.h"
#include "anisotropic_ellipsoid.h"
#include "marching_cubes_surface.h"
#include "shared_data.h"
#include "mesh_expectations.h"
#include "surface_samples.h"

using namespace gdm;
namespace ph = gdm::phantoms;

namespace {

constexpr double kBackground = 50.0, kContrast = 150.0;
constexpr double kThreshold = kBackground + 0.5 * kContrast;

struct Case {
  const char* name;
  Volume volume;
  std::function<double(const Vec3&)> distance;  // to the analytic surface, mm
  Vec3 seed;
};

Case sphere(double noise) {
  ph::Grid grid;
  grid.dims = {48, 48, 48};
  const auto sdf = ph::sphere(grid.center(), 15.0);
  return {"sphere", ph::with_gaussian_noise(ph::voxelize(grid, sdf, kBackground, kContrast), noise * kContrast, 81),
          sdf, grid.center() + Vec3(1, -2, 0.5)};
}

Case ellipsoid(double noise) {
  const auto e = test::anisotropic_ellipsoid();
  const Vec3 c = e.center, radii = e.radii;
  return {"ellipsoid 0.5x0.5x2",
          ph::with_gaussian_noise(ph::voxelize(e.grid, ph::ellipsoid(c, radii), kBackground, kContrast),
                                  noise * kContrast, 82),
          [=](const Vec3& p) { return ph::distance_to_ellipsoid(p, c, radii); }, c};
}

Case branching(double noise) {
  ph::Grid grid;
  const Vec3 c = grid.center();
  const auto sdf = ph::branching(c);
  return {"branching", ph::with_gaussian_noise(ph::voxelize(grid, sdf, kBackground, kContrast), noise * kContrast, 83),
          sdf, c + Vec3(0, 0, 10)};
}

Case c_tube(double noise) {
  ph::Grid grid;
  const Vec3 c = grid.center();
  const auto sdf = ph::bent_tube(c, 18.0, 6.0, 1.5 * M_PI);
  return {"C tube", ph::with_gaussian_noise(ph::voxelize(grid, sdf, kBackground, kContrast), noise * kContrast, 84),
          sdf, c + Vec3(18.0, 0.5, 0.0)};
}

struct Outcome {
  Mesh mesh;
  DeformResult result;
  ph::DistanceStats distance;
  double min_angle = 0.0;
  double seconds = 0.0;
};

// The settings of the runs: the defaults, the error-driven level of detail at
// a tenth of a voxel, and without the local refinement into channels (the
// paper's model: the face size decides).
enum class Setting { defaults, lod_tolerance, no_refine_channels };

const char* name(Setting s) {
  return s == Setting::defaults ? "defaults" : s == Setting::lod_tolerance ? "lod_tolerance 0.1" : "refine_channels off";
}

Outcome run(const Case& c, double min_angle, Setting setting = Setting::defaults, int threads = 0) {
  DeformOptions o;
  o.threshold = kThreshold;
  o.min_angle = min_angle;
  o.threads = threads;
  if (setting == Setting::lod_tolerance) o.lod_tolerance = 0.1;
  if (setting == Setting::no_refine_channels) o.refine_channels = false;
  Outcome out;
  out.mesh = make_icosahedron(c.seed, 3.0);
  const auto start = std::chrono::steady_clock::now();
  out.result = deform(out.mesh, c.volume, o);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.distance = test::surface_distances(out.mesh, c.distance, c.volume.voxel_size());
  out.min_angle = smallest_angle_degrees(out.mesh);
  std::printf("%s, %s, min_angle %g: faces %zu; surface mean %.4f p95 %.4f voxel; smallest angle %.3f deg; "
              "flips %zu splits %zu collapses %zu moves %zu, %zu faces below; %.2f s\n",
              c.name, name(setting), min_angle, out.mesh.n_faces(), out.distance.mean, out.distance.p95, out.min_angle,
              out.result.quality_flips, out.result.quality_splits, out.result.quality_collapses,
              out.result.quality_moves, out.result.faces_below_min_angle, out.seconds);
  return out;
}

// Every phantom at min_angle 0 (the model before issue 16), the default 10
// and 20: the bound is reached, the guarantees hold, and the accuracy is
// within today's limits (the fit tests' 0.08 mean at 5 % noise, the
// phantoms' 0.25) and within a hundredth of a voxel (mean) and three
// hundredths (95th percentile) of the model without the pass.
void check_case(const Case& c, double mean_limit, Setting setting) {
  const Outcome off = run(c, 0.0, setting);
  for (const double bound : {10.0, 20.0}) {
    const Outcome on = run(c, bound, setting);
    EXPECT_EQ(on.result.reason, StopReason::converged) << c.name;
    test::expect_valid_closed_surface(on.mesh);
    EXPECT_GE(on.min_angle, bound) << c.name << " at min_angle " << bound;
    EXPECT_EQ(on.result.faces_below_min_angle, 0u) << c.name;
    EXPECT_LE(on.distance.mean, mean_limit) << c.name;
    EXPECT_LE(on.distance.mean, off.distance.mean + 0.01) << c.name << " at min_angle " << bound;
    EXPECT_LE(on.distance.p95, off.distance.p95 + 0.03) << c.name << " at min_angle " << bound;
  }
}

}  // namespace

TEST(TriangleQuality, noisy_sphere) {
  for (Setting s : {Setting::defaults, Setting::lod_tolerance, Setting::no_refine_channels}) check_case(sphere(0.05), 0.08, s);
}

TEST(TriangleQuality, noisy_ellipsoid_with_anisotropic_spacing) {
  for (Setting s : {Setting::defaults, Setting::lod_tolerance, Setting::no_refine_channels}) check_case(ellipsoid(0.03), 0.25, s);
}

TEST(TriangleQuality, noisy_branching_tube) {
  for (Setting s : {Setting::defaults, Setting::lod_tolerance, Setting::no_refine_channels}) check_case(branching(0.10), 0.25, s);
}

TEST(TriangleQuality, noisy_c_shaped_tube) {
  for (Setting s : {Setting::defaults, Setting::lod_tolerance, Setting::no_refine_channels}) check_case(c_tube(0.05), 0.25, s);
}

TEST(TriangleQuality, same_mesh_for_one_and_two_threads) {
  const Case c = branching(0.10);
  const Outcome one = run(c, 10.0, Setting::lod_tolerance, 1), two = run(c, 10.0, Setting::lod_tolerance, 2);
  test::expect_same_mesh(one.mesh, two.mesh);
}

namespace {

// A geodesic sphere (radius 10 mm, level 3) whose every 7th vertex went 95 %
// of the way to its first neighbour (a needle), every 11th onto the middle
// of the edge between two of its neighbours (nearly: a cap), both projected
// back onto the sphere's radius, each move checked by the guard.
Mesh damaged_sphere() {
  Mesh mesh = make_geodesic_sphere(Vec3::Zero(), 10.0, 3);
  IntersectionGuard guard(mesh, 10.0, 0.0);
  for (auto v : mesh.vertices()) {
    const Vec3 p = to_eigen(mesh.point(v));
    auto it = mesh.cvv_iter(v);
    const Vec3 a = to_eigen(mesh.point(*it)), b = to_eigen(mesh.point(*++it));
    Vec3 q = p;
    if (v.idx() % 7 == 3) q = p + 0.95 * (a - p);
    else if (v.idx() % 11 == 5) q = 0.5 * (a + b) + 0.02 * (p - 0.5 * (a + b));
    if (q != p && guard.move_is_safe(v, q.normalized() * p.norm())) {
      mesh.set_point(v, to_point(q.normalized() * p.norm()));
      guard.rebuild();
    }
  }
  return mesh;
}

}  // namespace

// The pass alone on a sphere whose vertices were pushed onto their
// neighbours (needles) and onto the middle of edges (caps): every such face
// is removed, and the result is a valid surface.
TEST(TriangleQuality, removes_needles_and_caps_of_a_damaged_sphere) {
  Mesh mesh = damaged_sphere();
  ASSERT_GT(mesh.n_faces(), 1000u);
  test::expect_valid_closed_surface(mesh);
  const double before = smallest_angle_degrees(mesh);
  ASSERT_LT(before, 5.0);
  QualityOptions o;
  o.min_angle = 20.0;
  const QualityResult r = improve_triangle_quality(mesh, o);
  std::printf("damaged sphere: smallest angle %.3f -> %.3f deg; flips %zu splits %zu collapses %zu moves %zu\n",
              r.min_angle_before, r.min_angle_after, r.flips, r.splits, r.collapses, r.moves);
  test::expect_valid_closed_surface(mesh);
  EXPECT_GE(smallest_angle_degrees(mesh), 20.0);
  EXPECT_EQ(r.faces_below, 0u);
  EXPECT_DOUBLE_EQ(r.min_angle_after, smallest_angle_degrees(mesh));
  // Every vertex stays on (or, for chords, just inside) the sphere.
  for (auto v : mesh.vertices()) EXPECT_NEAR(to_eigen(mesh.point(v)).norm(), 10.0, 0.2);
}

// Faces below the bound on a sheet pressed against another (as where a
// model meets itself): the damaged sphere above and a copy of it scaled by
// 1 + 1e-7 about its centre (star-shaped, so the two nest without
// crossing), a micrometre apart. Every operation that mends a face of the
// outer sphere bends it inward across the inner one and one of the inner
// sphere outward across the outer: the guard refuses them until the
// corners step back from the contact (QualityResult::retreats).
TEST(TriangleQuality, faces_against_another_sheet_are_mended_after_a_step_back) {
  const Mesh damaged = damaged_sphere();
  Mesh mesh;
  for (const double scale : {1.0, 1.0 + 1e-7}) {
    const auto first = static_cast<int>(mesh.n_vertices());
    for (auto v : damaged.vertices()) mesh.add_vertex(to_point(scale * to_eigen(damaged.point(v))));
    for (auto f : damaged.faces()) {
      std::vector<Mesh::VertexHandle> c;
      for (auto v : damaged.fv_range(f)) c.emplace_back(first + v.idx());
      mesh.add_face(c);
    }
  }
  ASSERT_EQ(self_intersecting_pairs(mesh), 0u);
  ASSERT_LT(smallest_angle_degrees(mesh), 5.0);
  QualityOptions o;
  o.min_angle = 10.0;
  o.max_error = 0.1;
  const QualityResult r = improve_triangle_quality(mesh, o);
  std::printf("nested damaged spheres: smallest angle %.3f -> %.3f deg; retreats %zu, moves %zu, faces below %zu\n",
              r.min_angle_before, r.min_angle_after, r.retreats, r.moves, r.faces_below);
  EXPECT_GT(r.retreats, 0u);
  EXPECT_EQ(r.faces_below, 0u);
  EXPECT_GE(smallest_angle_degrees(mesh), 10.0);
  const MeshReport m = measure(mesh);
  EXPECT_TRUE(m.closed);
  EXPECT_TRUE(m.two_manifold);
  EXPECT_EQ(m.components, 2);
  EXPECT_EQ(m.self_intersections, 0u);
}

// Thin spikes as the T1 head's model had them: a vertex of valence three
// 3 mm above a triangle a quarter of a millimetre across, set into a face of
// a sphere (faces of about 1.3 mm). With spike_radius they are removed and
// the rest of the sphere kept; without, or when wider than spike_radius,
// they stay (here flips of their bases mend their angles; on the T1 head
// nothing did).
namespace {

Mesh spiked_sphere() {
  const Mesh sphere = make_geodesic_sphere(Vec3::Zero(), 10.0, 3);
  Mesh mesh;
  for (auto v : sphere.vertices()) mesh.add_vertex(sphere.point(v));
  for (auto f : sphere.faces()) {
    std::array<Mesh::VertexHandle, 3> c;
    int i = 0;
    for (auto v : sphere.fv_range(f)) c[static_cast<std::size_t>(i++)] = Mesh::VertexHandle(v.idx());
    if (f.idx() % 400 != 0) {
      mesh.add_face(c[0], c[1], c[2]);
      continue;
    }
    // The face ABC around a small triangle abc (0.15 mm from its centroid
    // toward A, B, C), the apex above abc's centroid.
    Vec3 m = Vec3::Zero();
    for (auto v : c) m += to_eigen(mesh.point(v)) / 3.0;
    std::array<Mesh::VertexHandle, 3> s;
    for (std::size_t k = 0; k < 3; ++k)
      s[k] = mesh.add_vertex(to_point(m + 0.15 * (to_eigen(mesh.point(c[k])) - m).normalized()));
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t n = (k + 1) % 3;
      mesh.add_face(c[k], c[n], s[n]);
      mesh.add_face(c[k], s[n], s[k]);
    }
    const auto apex = mesh.add_vertex(to_point(m + 3.0 * m.normalized()));
    for (std::size_t k = 0; k < 3; ++k) mesh.add_face(s[k], s[(k + 1) % 3], apex);
  }
  return mesh;
}

// A geodesic sphere (radius 10 mm) whose edge from vertex 0 to its first
// neighbour is raised `height` mm along the outward normal: a fin, the two
// faces across that edge a wedge folded beyond kFoldDegrees (as where a
// model's fronts met).
Mesh finned_sphere(double height) {
  Mesh mesh = make_geodesic_sphere(Vec3::Zero(), 10.0, 3);
  const Mesh::VertexHandle a(0);
  const Mesh::VertexHandle b = *mesh.vv_range(a).begin();
  for (auto v : {a, b}) {
    const Vec3 p = to_eigen(mesh.point(v));
    mesh.set_point(v, to_point(p + height * p.normalized()));
  }
  return mesh;
}

// A geodesic sphere (radius 10 mm) with a face folded back over its
// neighbour: across the edge pq of the faces (p, q, r) and (q, p, s), s is
// moved over pq to 0.6 of the way from pq's midpoint to r and 0.2 mm
// outward; the two faces then lie on each other, folded beyond kFoldDegrees.
Mesh folded_over_sphere() {
  Mesh mesh = make_geodesic_sphere(Vec3::Zero(), 10.0, 3);
  const auto h = mesh.halfedge_handle(Mesh::EdgeHandle(0), 0);
  const Vec3 p = to_eigen(mesh.point(mesh.from_vertex_handle(h))), q = to_eigen(mesh.point(mesh.to_vertex_handle(h)));
  const Vec3 r = to_eigen(mesh.point(mesh.to_vertex_handle(mesh.next_halfedge_handle(h))));
  const auto s = mesh.to_vertex_handle(mesh.next_halfedge_handle(mesh.opposite_halfedge_handle(h)));
  const Vec3 m = 0.5 * (p + q);
  mesh.set_point(s, to_point(m + 0.6 * (r - m) + 0.2 * m.normalized()));
  return mesh;
}

}  // namespace

TEST(TriangleQuality, unfold_flips_a_face_folded_over_its_neighbour) {
  QualityOptions o;
  o.min_angle = 0.0;  // no angle rounds: the fold phase alone
  o.max_error = 0.0;
  Mesh kept = folded_over_sphere();
  test::expect_valid_closed_surface(kept);
  const std::size_t folds = folded_edges(kept);
  ASSERT_GE(folds, 1u);
  EXPECT_EQ(improve_triangle_quality(kept, o).flips, 0u) << "off: nothing changes";
  EXPECT_EQ(folded_edges(kept), folds);
  Mesh mesh = folded_over_sphere();
  o.unfold = true;
  const QualityResult on = improve_triangle_quality(mesh, o);
  std::printf("folded-over sphere: %zu folded edges (sharpest %.1f deg) -> %zu (%.1f), %zu flips, %zu collapses\n",
              folds, sharpest_fold_degrees(kept), folded_edges(mesh), sharpest_fold_degrees(mesh), on.unfold_flips,
              on.unfolds);
  EXPECT_GE(on.unfold_flips, 1u);
  EXPECT_EQ(on.flips, on.unfold_flips);
  EXPECT_EQ(on.unfolds, 0u);
  EXPECT_EQ(folded_edges(mesh), 0u);
  test::expect_valid_closed_surface(mesh);
  // A flip moves no vertex.
  ASSERT_EQ(mesh.n_vertices(), kept.n_vertices());
  for (auto v : mesh.vertices()) EXPECT_EQ(to_eigen(mesh.point(v)), to_eigen(kept.point(v)));
}

TEST(TriangleQuality, unfold_collapses_the_folded_edges_of_a_fin) {
  QualityOptions o;
  o.min_angle = 0.0;  // no angle rounds: the fold phase alone
  o.max_error = 0.0;  // unbounded: the fin's ridge is 16 mm above the sphere
  Mesh kept = finned_sphere(16.0);
  test::expect_valid_closed_surface(kept);
  const std::size_t folds = folded_edges(kept);
  ASSERT_GE(folds, 1u);
  ASSERT_GT(sharpest_fold_degrees(kept), kFoldDegrees);
  // Off (the default for direct callers): nothing changes.
  const QualityResult off = improve_triangle_quality(kept, o);
  EXPECT_EQ(off.unfolds, 0u);
  EXPECT_EQ(folded_edges(kept), folds);
  // On: the ridge's edge collapsed into one end, a spike left, no fold.
  Mesh mesh = finned_sphere(16.0);
  o.unfold = true;
  const QualityResult on = improve_triangle_quality(mesh, o);
  std::printf("finned sphere: %zu folded edges (sharpest %.1f deg) -> %zu (%.1f), %zu collapses\n", folds,
              sharpest_fold_degrees(kept), folded_edges(mesh), sharpest_fold_degrees(mesh), on.unfolds);
  EXPECT_GE(on.unfolds, 1u);
  EXPECT_EQ(on.collapses, on.unfolds);
  EXPECT_EQ(folded_edges(mesh), 0u);
  EXPECT_LT(sharpest_fold_degrees(mesh), sharpest_fold_degrees(kept));
  EXPECT_EQ(mesh.n_vertices() + on.unfolds, kept.n_vertices());
  test::expect_valid_closed_surface(mesh);
  // Every vertex but the ridge's kept end is where it was, on the sphere.
  std::size_t raised = 0;
  for (auto v : mesh.vertices()) {
    const double r = to_eigen(mesh.point(v)).norm();
    if (r > 10.5)
      ++raised;
    else
      EXPECT_NEAR(r, 10.0, 1e-9);
  }
  EXPECT_EQ(raised, 1u);
}

TEST(TriangleQuality, same_result_for_any_thread_count) {
  // The pass with its fold phase on 1, 2 and 3 threads: a crumpled sphere
  // (every seventh vertex raised 2 to 8 mm, star-shaped about the centre so
  // nothing intersects), a face folded back over its neighbour, a fin.
  Mesh crumpled = make_geodesic_sphere(Vec3::Zero(), 10.0, 3);
  for (auto v : crumpled.vertices())
    if (v.idx() % 7 == 0) crumpled.set_point(v, crumpled.point(v) * (1.0 + 0.2 + 0.6 * ((v.idx() * 37) % 11) / 10.0));
  const auto ids = [](const Mesh& m, Mesh::FaceHandle f) {
    std::vector<int> out;
    for (auto v : m.fv_range(f)) out.push_back(v.idx());
    return out;
  };
  QualityOptions o;
  o.min_angle = 10.0;
  o.max_error = 0.5;
  o.unfold = true;
  for (const Mesh& input : {crumpled, folded_over_sphere(), finned_sphere(16.0)}) {
    test::expect_valid_closed_surface(input);
    Mesh one = input;
    o.threads = 1;
    const QualityResult r1 = improve_triangle_quality(one, o);
    std::printf("%zu edges folded beyond %.0f deg: %zu flips, %zu collapses (%zu unfolds, %zu unfolding flips)\n",
                folded_edges(input), kFoldDegrees, r1.flips, r1.collapses, r1.unfolds, r1.unfold_flips);
    EXPECT_GT(r1.flips + r1.collapses, 0u);
    test::expect_valid_closed_surface(one);
    for (const int threads : {2, 3}) {
      Mesh mesh = input;
      o.threads = threads;
      const QualityResult r = improve_triangle_quality(mesh, o);
      EXPECT_EQ(r.flips, r1.flips) << threads;
      EXPECT_EQ(r.collapses, r1.collapses) << threads;
      EXPECT_EQ(r.unfolds, r1.unfolds) << threads;
      ASSERT_EQ(mesh.n_vertices(), one.n_vertices()) << threads;
      ASSERT_EQ(mesh.n_faces(), one.n_faces()) << threads;
      for (auto v : mesh.vertices()) EXPECT_EQ(to_eigen(mesh.point(v)), to_eigen(one.point(Mesh::VertexHandle(v.idx()))));
      for (auto f : mesh.faces()) EXPECT_EQ(ids(mesh, f), ids(one, Mesh::FaceHandle(f.idx())));
    }
  }
}

TEST(TriangleQuality, removes_thin_spikes_narrower_than_spike_radius) {
  const auto farthest = [](const Mesh& m) {
    double r = 0.0;
    for (auto v : m.vertices()) r = std::max(r, to_eigen(m.point(v)).norm());
    return r;
  };
  QualityOptions o;
  o.min_angle = 10.0;
  o.max_error = 0.1;
  for (const double radius : {0.0, 0.1}) {  // the bases' corners lie 0.15 mm from their centroids
    Mesh mesh = spiked_sphere();
    test::expect_valid_closed_surface(mesh);
    ASSERT_LT(smallest_angle_degrees(mesh), 6.0);
    o.spike_radius = radius;
    EXPECT_EQ(improve_triangle_quality(mesh, o).spikes, 0u) << radius;
    EXPECT_GT(farthest(mesh), 12.5) << "the spikes stay, spike_radius " << radius;
  }
  Mesh mesh = spiked_sphere();
  o.spike_radius = 0.5;
  const QualityResult r = improve_triangle_quality(mesh, o);
  std::printf("spiked sphere: smallest angle %.3f -> %.3f deg; spikes %zu, collapses %zu, faces %zu\n",
              r.min_angle_before, r.min_angle_after, r.spikes, r.collapses, mesh.n_faces());
  EXPECT_GE(r.spikes, 3u);
  EXPECT_EQ(r.faces_below, 0u);
  EXPECT_GE(smallest_angle_degrees(mesh), 10.0);
  test::expect_valid_closed_surface(mesh);
  EXPECT_LT(farthest(mesh), 10.2) << "every apex removed";
  for (auto v : mesh.vertices()) EXPECT_NEAR(to_eigen(mesh.point(v)).norm(), 10.0, 0.2);
}

// The tooth's pulp (../shared/data; skipped when absent) at the defaults (with
// refine_channels) and without it, min_angle 0, 10 and 20: distance to marching cubes'
// surface (mean, 95th percentile, voxels), faces, smallest angle, time. The
// guarantees hold; the bound is asserted as far as the pass reaches it here
// (best effort: the report says what is left).
TEST(TriangleQuality, tooth_pulp_against_marching_cubes) {
  Volume volume;
  std::string why;
  if (!test::load_tooth(GDM_TEST_SHARED_DIR, volume, why)) GTEST_SKIP() << why;
  const Index3 s = test::kToothPulpSeed;
  const TriangleLocator mc(test::tooth_pulp_surface(volume));
  for (const bool channels : {false, true})
    for (const double bound : {0.0, 10.0, 20.0}) {
      Mesh mesh = make_icosahedron(volume.to_physical(Vec3(s[0], s[1], s[2])), 2.0);
      DeformOptions o = test::tooth_pulp_options();
      o.refine_channels = channels;
      o.min_angle = bound;
      const auto start = std::chrono::steady_clock::now();
      const DeformResult r = deform(mesh, volume, o);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      test::expect_valid_closed_surface(mesh);
      std::vector<double> d;
      for (const Vec3& p : test::surface_samples(mesh)) d.push_back(mc.distance(p) / volume.voxel_size());
      const auto stats = ph::distance_stats(std::move(d));
      const double angle = smallest_angle_degrees(mesh);
      std::printf("tooth pulp, %s, min_angle %g: faces %zu; to marching cubes mean %.4f p95 %.4f voxel; smallest "
                  "angle %.2f deg, %zu faces below; %.2f s\n",
                  channels ? "defaults" : "refine_channels off", bound, mesh.n_faces(), stats.mean, stats.p95, angle,
                  r.faces_below_min_angle, seconds);
      EXPECT_EQ(r.faces_below_min_angle == 0, angle >= bound) << "the report tells the truth";
      EXPECT_LE(stats.mean, channels ? 0.15 : 0.5);
      // Measured: with refine_channels and 20 degrees one face is left at 17.8.
      if (channels && bound == 20.0) {
        EXPECT_GE(angle, 17.5);
        EXPECT_LE(r.faces_below_min_angle, 1u);
      } else {
        EXPECT_GE(angle, bound);
      }
    }
}

// CGAL's facet_angle goes up to 30 degrees; the issue asks for bounds up to
// 25. Each phantom at 3 and 10 % noise, with the error-driven level of
// detail at a tenth of a voxel (the largest faces, the hardest case): the
// bound is reached everywhere (before the collapses into a point between an
// edge's ends and the relaxation's tangential steps, the noisy ellipsoid kept
// 2 faces below it), the guarantees hold, and the model stays within 0.02
// voxel (mean) and 0.06 (95th percentile) of the one without the pass.
TEST(TriangleQuality, a_25_degree_bound_is_reached_on_every_phantom) {
  for (const double noise : {0.03, 0.10})
    for (const Case& c : {sphere(noise), ellipsoid(noise), branching(noise), c_tube(noise)}) {
      const Outcome off = run(c, 0.0, Setting::lod_tolerance);
      const Outcome on = run(c, 25.0, Setting::lod_tolerance);
      test::expect_valid_closed_surface(on.mesh);
      EXPECT_EQ(on.result.faces_below_min_angle, 0u) << c.name << ", noise " << noise;
      EXPECT_GE(on.min_angle, 25.0) << c.name << ", noise " << noise;
      EXPECT_LE(on.distance.mean, off.distance.mean + 0.02) << c.name << ", noise " << noise;
      EXPECT_LE(on.distance.p95, off.distance.p95 + 0.06) << c.name << ", noise " << noise;
    }
}
