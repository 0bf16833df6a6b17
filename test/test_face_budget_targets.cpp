// The face budget's targets (issue 16), at budgets given as a share of
// marching cubes' faces on the same volume: the count within 5 %; on noisy
// phantoms (Gaussian noise 5 to 10 % of the contrast) at 10 % of marching
// cubes' faces the mean distance to the analytic surface (over vertices, face
// centroids and edge midpoints) at most 0.07 voxel and its 95th percentile at
// most 0.18 (met on three of the four phantoms, see below); the creases of
// the cube with a corner missing (section 6.1) at 5 %; impulse noise (dark
// specks inside the object) pulls the reduced model less into the specks;
// the budget in shrink mode. Phantoms built here; distances in voxels.
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "gdm/deformer.h"
#include "gdm/mesh_checks.h"
#include "gdm/phantoms.h"
#include "gdm/pipeline.h"
#include "gdm/seed.h"
#include "gdm/triangle_locator.h"
#include "anisotropic_ellipsoid.h"
#include "mesh_expectations.h"
#include "phantom_case.h"
#include "surface_samples.h"

using namespace gdm;
namespace ph = gdm::phantoms;

namespace {

constexpr double kBackground = test::kPhantomBackground, kContrast = test::kPhantomContrast;
constexpr double kThreshold = test::kPhantomThreshold;
using Case = test::PhantomCase;

Case noisy_sphere() {
  ph::Grid grid;
  const Vec3 c = grid.center();
  return {"sphere r 20, noise 8 %", ph::with_gaussian_noise(ph::voxelize(grid, ph::sphere(c, 20.0), kBackground, kContrast), 0.08 * kContrast, 301),
          [c](const Vec3& p) { return (p - c).norm() - 20.0; }, c};
}

Case noisy_ellipsoid() {
  const auto e = test::anisotropic_ellipsoid();
  const Vec3 c = e.center, radii = e.radii;
  return {"ellipsoid 0.5x0.5x2, noise 5 %",
          ph::with_gaussian_noise(ph::voxelize(e.grid, ph::ellipsoid(c, radii), kBackground, kContrast), 0.05 * kContrast, 302),
          [=](const Vec3& p) { return ph::distance_to_ellipsoid(p, c, radii); }, c};
}

Case noisy_branching() {
  ph::Grid grid;
  const Vec3 c = grid.center();
  const auto sdf = ph::branching(c);
  return {"branching, noise 10 %", ph::with_gaussian_noise(ph::voxelize(grid, sdf, kBackground, kContrast), 0.10 * kContrast, 303),
          sdf, c + Vec3(0, 0, 10)};
}

Case noisy_c_tube() {
  ph::Grid grid;
  const Vec3 c = grid.center();
  const auto sdf = ph::bent_tube(c, 18.0, 6.0, 1.5 * M_PI);
  return {"C tube, noise 5 %", ph::with_gaussian_noise(ph::voxelize(grid, sdf, kBackground, kContrast), 0.05 * kContrast, 304),
          sdf, c + Vec3(18.0, 0.5, 0.0)};
}

struct Outcome {
  Mesh mesh;
  DeformResult result;
  std::size_t budget = 0;
  ph::DistanceStats distance;  // over vertices, face centroids and edge midpoints, voxels
};

// gdm with a budget of `share` of marching cubes' faces on the case's volume.
Outcome run(const Case& c, double share) {
  DeformOptions o;
  o.threshold = kThreshold;
  Outcome out;
  out.budget = static_cast<std::size_t>(
      std::lround(share * static_cast<double>(ph::marching_cubes_triangle_count(c.volume, kThreshold))));
  o.face_budget = out.budget;
  out.mesh = make_icosahedron(c.seed, 3.0);
  out.result = deform(out.mesh, c.volume, o);
  out.distance = test::surface_distances(out.mesh, c.distance, c.volume.voxel_size());
  std::printf("%s: budget %zu (%.0f %% of marching cubes), faces %zu; mean %.4f p95 %.4f max %.4f voxel; smallest angle %.2f deg; "
              "evened out: %zu moves\n",
              c.name.c_str(), out.budget, 100.0 * share, out.mesh.n_faces(), out.distance.mean, out.distance.p95,
              out.distance.max, smallest_angle_degrees(out.mesh), out.result.budget_relax_moves);
  return out;
}

void expect_budget_met(const Outcome& out, const std::string& name) {
  EXPECT_EQ(out.result.reason, StopReason::converged) << name;
  test::expect_valid_closed_surface(out.mesh);
  EXPECT_NEAR(static_cast<double>(out.mesh.n_faces()), static_cast<double>(out.budget), 0.05 * static_cast<double>(out.budget))
      << name;
}

}  // namespace

// The accuracy target at 10 % of marching cubes' faces: mean at most
// 0.07 voxel, p95 at most 0.18. Met on the noisy sphere (measured 0.0265 /
// 0.060, its faces evened out; 0.029 / 0.066 before that step, stop 61), the
// noisy C tube (0.047 / 0.116, evened; 0.049 / 0.118) and the noisy
// ellipsoid on 0.5 x 0.5 x 2 mm voxels (0.063 / 0.145: the collapses' own
// placement kept, nearer the fine model, though the evened candidate was
// nearer the truth, 0.055 / 0.121; 0.091 / 0.208 when this test was
// written), asserted there. Not met yet, so only the budget and the
// guarantees are asserted (issue 16 stays open): the branching tube with
// 10 % noise (0.075 / 0.203).
TEST(FaceBudgetTargets, noisy_phantoms_at_a_tenth_of_marching_cubes_faces) {
  for (const Case& c : {noisy_sphere(), noisy_c_tube(), noisy_ellipsoid()}) {
    const Outcome out = run(c, 0.10);
    expect_budget_met(out, c.name);
    EXPECT_LE(out.distance.mean, 0.07) << c.name;
    EXPECT_LE(out.distance.p95, 0.18) << c.name;
  }
  expect_budget_met(run(noisy_branching(), 0.10), "branching");
}

// The reduced model's faces evened out along its surface before the last fit
// (Deformer::even_out_faces, stop 61): on smooth phantoms at 5 % of marching
// cubes' faces, where each face's sagitta is most of the error, the faces'
// shapes decide how close they sit, and the evened candidate is the one kept
// (nearer the fine fitted model). Measured with / without: noisy sphere
// mean 0.0394 / 0.0485 voxel, p95 0.106 / 0.119, smallest angle 31.3 / 16.6
// degrees; noisy ellipsoid on 0.5 x 0.5 x 2 mm voxels 0.0757 / 0.0972, p95
// 0.198 / 0.228, smallest angle 33.0 / 12.9. Asserted: mean at most 0.044 and
// 0.085, smallest angle at least 25 degrees.
TEST(FaceBudgetTargets, smooth_phantoms_faces_evened_out_at_a_twentieth_of_marching_cubes_faces) {
  const std::pair<Case, double> cases[] = {{noisy_sphere(), 0.044}, {noisy_ellipsoid(), 0.085}};
  for (const auto& [c, limit] : cases) {
    const Outcome out = run(c, 0.05);
    expect_budget_met(out, c.name);
    EXPECT_GT(out.result.budget_relax_moves, out.mesh.n_vertices()) << c.name;
    EXPECT_LE(out.distance.mean, limit) << c.name;
    EXPECT_GE(smallest_angle_degrees(out.mesh), 25.0) << c.name;
  }
}

// Section 6.1's cube with a corner missing (convex edges and corners, concave
// edges and the notch's concave corner), clean, at 5 % of marching cubes'
// faces: the budget is met, and the true creases are measured against the
// mesh. With sharp edges (creases.h) the fine model gets vertices on the
// edges and corners before the reduction, whose quadrics then keep them, and
// again after the last fit: measured mean 0.0045 voxel, 99.2 % of the crease
// points within the 0.2 voxel, max 0.85 (next to the notch's saddle
// corner (52, 32, 32), where an edge's first segment is not split); without,
// mean 0.35, max 1.29. Asserted: mean at most 0.05, 95 % within 0.2, all
// within 1.0 voxel; the vertices near them (within 3 voxels of two of the
// planes) within 0.2 voxel of the surface at the 95th percentile (measured
// 0.075; 0.40 without).
TEST(FaceBudgetTargets, cube_edges_and_corners_kept_at_five_percent) {
  ph::Grid grid;
  const auto sdf = ph::difference(ph::box(Vec3(12, 12, 12), Vec3(52, 52, 52)), ph::box(Vec3(32, 32, 32), Vec3(60, 60, 60)));
  const Case c{"cube with a corner missing", ph::voxelize(grid, sdf, kBackground, kContrast), sdf, Vec3(24, 24, 24)};
  const Outcome out = run(c, 0.05);
  expect_budget_met(out, c.name);
  // The true creases: points on lines where two of the planes x, y, z in
  // {12, 32, 52} meet, on the surface, with one or three of the four points
  // around them (half a voxel off, across the line) inside.
  const std::array<double, 3> planes{12.0, 32.0, 52.0};
  std::vector<Vec3> crease;
  std::size_t corners = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b) {
      const int along = 3 - a - b;
      for (const double pa : planes)
        for (const double pb : planes)
          for (double t = 0.0; t <= 64.0; t += 0.25) {
            Vec3 p;
            p[a] = pa;
            p[b] = pb;
            p[along] = t;
            if (std::abs(sdf(p)) > 1e-9) continue;
            int inside = 0;
            for (const double sa : {-0.5, 0.5})
              for (const double sb : {-0.5, 0.5}) {
                Vec3 q = p;
                q[a] += sa;
                q[b] += sb;
                inside += sdf(q) < 0.0;
              }
            if (inside == 1 || inside == 3) {
              crease.push_back(p);
              corners += std::abs(t - 12.0) < 1e-9 || std::abs(t - 32.0) < 1e-9 || std::abs(t - 52.0) < 1e-9;
            }
          }
    }
  ASSERT_GT(crease.size(), 1000u);
  ASSERT_GE(corners, 8u);
  const TriangleLocator locator(triangles_of(out.mesh));
  double worst = 0.0, sum = 0.0;
  std::size_t within = 0;
  for (const Vec3& p : crease) {
    const double d = locator.distance(p);
    worst = std::max(worst, d);
    sum += d;
    within += d <= 0.2;
  }
  const double share = static_cast<double>(within) / static_cast<double>(crease.size());
  std::vector<double> near;
  for (auto v : out.mesh.vertices()) {
    const Vec3 p = to_eigen(out.mesh.point(v));
    int planes_near = 0;
    for (int a = 0; a < 3; ++a)
      for (const double plane : planes) planes_near += std::abs(p[a] - plane) < 3.0;
    if (planes_near >= 2) near.push_back(std::abs(sdf(p)));
  }
  const ph::DistanceStats n = ph::distance_stats(near);
  std::printf("creases: %zu points; distance to the mesh mean %.4f max %.4f voxel, %.1f %% within 0.2; %zu vertices "
              "near them: mean %.4f p95 %.4f voxel\n",
              crease.size(), sum / static_cast<double>(crease.size()), worst, 100.0 * share, near.size(), n.mean, n.p95);
  ASSERT_GT(near.size(), 50u);
  EXPECT_LE(sum / static_cast<double>(crease.size()), 0.05);
  EXPECT_GE(share, 0.95);
  EXPECT_LE(worst, 1.0);
  EXPECT_LE(n.p95, 0.2);
}

// Impulse noise: 10 % of the inside voxels at the background value (dark
// specks) and 1 % of the outside ones at the object's, on the ellipsoid on
// 1 x 1 x 2 mm voxels (a speck is two voxels' worth of the surface's normal
// at the poles). The fine fit of the subdivided model sees a speck just
// inside the surface as a dent; the reduction must not spend its faces on
// the dents nor keep vertices in them. Measured (mean / p95, voxels): budget
// 1,500: 0.079 / 0.326 with the fine fit anchored within the coarse faces'
// sagitta (subdivision_fit_bounds), 0.127 / 0.663 without; budget 3,000:
// 0.070 / 0.346 against 0.088 / 0.465. The default run's own model (no
// subdivision) stays better still (the study: 0.040 / 0.117 at 3,032 faces).
TEST(FaceBudgetTargets, impulse_noise_does_not_dent_the_reduced_model) {
  ph::Grid grid;
  grid.dims = {64, 64, 32};
  grid.spacing = Vec3(1.0, 1.0, 2.0);
  const Vec3 c = grid.center(), radii(24, 16, 20);
  const auto sdf = ph::ellipsoid(c, radii);
  const Volume clean = ph::voxelize(grid, sdf, kBackground, kContrast);
  const Volume peppered = ph::with_pepper(clean, sdf, 0.10, kBackground, 1.0, 305);
  std::vector<float> values = peppered.values();
  unsigned state = 306u;
  std::size_t i = 0;
  for (int z = 0; z < grid.dims[2]; ++z)
    for (int y = 0; y < grid.dims[1]; ++y)
      for (int x = 0; x < grid.dims[0]; ++x, ++i) {
        state = state * 1664525u + 1013904223u;  // a fixed sequence: the same volume everywhere
        if (sdf(clean.to_physical(Vec3(x, y, z))) > 1.0 && (state >> 8) % 100u == 0u)
          values[i] = static_cast<float>(kBackground + kContrast);
      }
  const Case k{"ellipsoid 1x1x2, salt and pepper",
               Volume(clean.dims(), std::move(values), clean.spacing(), clean.origin(), clean.direction()),
               [c, radii](const Vec3& p) { return ph::distance_to_ellipsoid(p, c, radii); }, c};
  for (const std::size_t budget : {1500u, 3000u}) {
    DeformOptions o;
    o.threshold = kThreshold;
    o.face_budget = budget;
    Outcome out;
    out.budget = budget;
    out.mesh = make_icosahedron(k.seed, 3.0);
    out.result = deform(out.mesh, k.volume, o);
    out.distance = test::surface_distances(out.mesh, k.distance, k.volume.voxel_size());
    std::printf("%s, budget %zu: faces %zu (%zu subdivisions, %d channel rounds, %zu faces asked); mean %.4f p95 %.4f "
                "max %.4f voxel\n",
                k.name.c_str(), budget, out.mesh.n_faces(), out.result.budget_subdivisions, out.result.channel_rounds,
                out.result.channel_faces, out.distance.mean, out.distance.p95, out.distance.max);
    expect_budget_met(out, k.name);
    EXPECT_GT(out.result.budget_subdivisions, 0u);
    EXPECT_LE(out.distance.mean, 0.085) << k.name << ", budget " << budget;
    EXPECT_LE(out.distance.p95, 0.4) << k.name << ", budget " << budget;
  }
}

// Shrink mode (the model shrinks onto the object from a sphere around it):
// the budget is met and the model fits, on a noisy ellipsoid.
TEST(FaceBudgetTargets, shrink_mode_meets_the_budget) {
  ph::Grid g;
  g.dims = {48, 48, 48};
  const Vec3 c = g.center(), radii(18.0, 12.0, 9.0);
  const Volume v = ph::with_gaussian_noise(ph::voxelize(g, ph::ellipsoid(c, radii), kBackground, kContrast),
                                           0.05 * kContrast, 307);
  for (const std::size_t budget : {600u, 2000u}) {
    PipelineOptions o;
    o.threshold_otsu = false;
    o.threshold = kThreshold;
    o.deform.mode = Mode::shrink;
    o.deform.face_budget = budget;
    const PipelineResult r = extract_surface(v, o);
    ASSERT_TRUE(r.failure.empty()) << r.failure;
    test::expect_valid_closed_surface(r.mesh);
    EXPECT_NEAR(static_cast<double>(r.mesh.n_faces()), static_cast<double>(budget), 0.05 * static_cast<double>(budget));
    const ph::DistanceStats d = test::surface_distances(
        r.mesh, [&](const Vec3& p) { return ph::distance_to_ellipsoid(p, c, radii); }, v.voxel_size());
    std::printf("shrink, ellipsoid, budget %zu: faces %zu; mean %.4f p95 %.4f voxel\n", budget, r.mesh.n_faces(), d.mean, d.p95);
    EXPECT_LE(d.mean, 0.1) << "budget " << budget;
    EXPECT_LE(d.p95, 0.3) << "budget " << budget;
  }
}
