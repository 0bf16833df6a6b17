// The pipeline every front end runs (gdm/pipeline.h) on generated phantoms:
// it chooses the threshold and the seed, runs the model, checks the result,
// and refuses what cannot work with a typed error that names the problem.
#include <gtest/gtest.h>

#include <cmath>

#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/phantoms.h"
#include "gdm/pipeline.h"
#include "gdm/seed.h"

namespace {

using namespace gdm;

Volume noisy_sphere(double radius, unsigned seed = 3) {
  phantoms::Grid grid;
  grid.dims = {40, 40, 40};
  grid.spacing = Vec3(0.8, 0.8, 1.1);
  const Volume clean = phantoms::voxelize(grid, phantoms::sphere(grid.center(), radius), 50.0, 150.0);
  return phantoms::with_gaussian_noise(clean, 0.05 * 150.0, seed);
}

PipelineOptions quick_options() {
  PipelineOptions o;
  o.deform.global_refinements = 0;
  o.deform.threads = 1;
  return o;
}

TEST(Pipeline, otsu_and_automatic_seed_find_a_noisy_sphere) {
  phantoms::Grid grid;
  grid.dims = {40, 40, 40};
  grid.spacing = Vec3(0.8, 0.8, 1.1);
  const double radius = 10.0;
  const Volume volume = noisy_sphere(radius);
  const PipelineResult r = extract_surface(volume, quick_options());
  ASSERT_TRUE(r.failure.empty()) << r.failure;
  EXPECT_EQ(r.choices.threshold_source, "otsu");
  EXPECT_GT(r.choices.threshold, 90.0);  // between the classes 50 and 200
  EXPECT_LT(r.choices.threshold, 160.0);
  EXPECT_EQ(r.choices.seed_source, "auto");
  EXPECT_LT((r.choices.seed_center - grid.center()).norm(), 1.5);
  EXPECT_TRUE(r.report.closed);
  EXPECT_TRUE(r.report.two_manifold);
  EXPECT_EQ(r.report.genus, 0);
  EXPECT_EQ(r.report.self_intersections, 0u);
  // Otsu's T sits off the mid-value, so the surface moves a little: within a voxel.
  const auto d = phantoms::vertex_distances(
      r.mesh, [&](const Vec3& p) { return (p - grid.center()).norm() - radius; }, 0.8);
  EXPECT_LT(d.mean, 1.0);
}

TEST(Pipeline, same_mesh_as_deform_with_the_same_seed) {
  const Volume volume = noisy_sphere(9.0);
  PipelineOptions o = quick_options();
  o.threshold_otsu = false;
  o.threshold = 125.0;
  o.seed.kind = SeedKind::point;
  o.seed.point = volume.to_physical(Vec3(20, 20, 20));
  o.seed.radius = 3.0;
  const PipelineResult r = extract_surface(volume, o);
  ASSERT_TRUE(r.failure.empty()) << r.failure;

  Mesh direct = make_geodesic_sphere(o.seed.point, 3.0, o.seed.level);
  DeformOptions d = o.deform;
  d.threshold = 125.0;
  deform(direct, volume, d);
  direct.garbage_collection();
  ASSERT_EQ(direct.n_vertices(), r.mesh.n_vertices());
  ASSERT_EQ(direct.n_faces(), r.mesh.n_faces());
  for (auto v : direct.vertices()) EXPECT_EQ(direct.point(v), r.mesh.point(v));
}

TEST(Pipeline, region_of_interest_and_smoothing_keep_physical_positions) {
  phantoms::Grid grid;
  grid.dims = {40, 40, 40};
  const Volume volume = phantoms::voxelize(grid, phantoms::sphere(grid.center(), 8.0));
  PipelineOptions o = quick_options();
  o.threshold_otsu = false;
  o.threshold = 125.0;
  o.use_roi = true;
  o.roi.lo = {5, 6, 7};
  o.roi.hi = {34, 33, 32};
  o.smooth = 0.7;
  const PipelineResult r = extract_surface(volume, o);
  ASSERT_TRUE(r.failure.empty()) << r.failure;
  const auto d = phantoms::vertex_distances(
      r.mesh, [&](const Vec3& p) { return (p - grid.center()).norm() - 8.0; }, 1.0);
  EXPECT_LT(d.mean, 0.3);
}

TEST(Pipeline, shrink_from_the_volume_box) {
  phantoms::Grid grid;
  grid.dims = {32, 32, 32};
  const Volume volume = phantoms::voxelize(grid, phantoms::sphere(grid.center(), 9.0));
  PipelineOptions o = quick_options();
  o.threshold_otsu = false;
  o.threshold = 125.0;
  o.deform.mode = Mode::shrink;
  const PipelineResult r = extract_surface(volume, o);
  ASSERT_TRUE(r.failure.empty()) << r.failure;
  EXPECT_EQ(r.choices.seed_source, "box");
  EXPECT_NEAR(r.report.volume, 4.0 / 3.0 * M_PI * 729.0, 0.05 * 4.0 / 3.0 * M_PI * 729.0);
}

TEST(Pipeline, refuses_a_seed_outside_the_volume_or_the_object) {
  const Volume volume = noisy_sphere(9.0);
  PipelineOptions o = quick_options();
  o.seed.kind = SeedKind::point;
  o.seed.point = Vec3(1000, 0, 0);
  EXPECT_THROW(extract_surface(volume, o), InvalidSeed);
  o.seed.point = volume.to_physical(Vec3(3, 3, 3));  // background
  try {
    extract_surface(volume, o);
    ADD_FAILURE() << "a seed in the background was accepted";
  } catch (const InvalidSeed& e) {
    EXPECT_NE(std::string(e.what()).find("not inside the object"), std::string::npos) << e.what();
  }
  o.seed.kind = SeedKind::index;
  o.seed.index = {20, 20, 99};
  EXPECT_THROW(extract_surface(volume, o), InvalidSeed);
}

TEST(Pipeline, refuses_bad_thresholds_and_volumes) {
  const Volume volume = noisy_sphere(9.0);
  PipelineOptions o = quick_options();
  o.threshold_otsu = false;
  o.threshold = 1e6;
  try {
    extract_surface(volume, o);
    ADD_FAILURE();
  } catch (const InvalidOption& e) {
    EXPECT_EQ(e.option(), "threshold");
  }
  o.threshold = std::nan("");
  EXPECT_THROW(extract_surface(volume, o), InvalidOption);
  const Volume constant({4, 4, 4}, std::vector<float>(64, 7.0f));
  EXPECT_THROW(extract_surface(constant, quick_options()), InvalidVolume);
}

TEST(Pipeline, a_leak_to_the_border_is_a_failure_unless_allowed) {
  // Wrong polarity: the "object" is the background around the sphere.
  const Volume volume = noisy_sphere(9.0);
  PipelineOptions o = quick_options();
  o.threshold_otsu = false;
  o.threshold = 125.0;
  o.deform.polarity = Polarity::object_darker;
  o.deform.subvoxel_fit = false;
  const PipelineResult r = extract_surface(volume, o);
  EXPECT_NE(r.failure.find("reached the volume border"), std::string::npos) << r.failure;
  EXPECT_THROW(require_success(r), ModelFailed);
  EXPECT_EQ(r.deform.reason, StopReason::border);
  // It stopped at the first contact, long before the leaked model would have converged.
  o.allow_border = true;
  const PipelineResult allowed = extract_surface(volume, o);
  EXPECT_TRUE(allowed.failure.empty()) << allowed.failure;
  EXPECT_LT(r.deform.cycles * 3, allowed.deform.cycles) << r.deform.cycles << " vs " << allowed.deform.cycles;
}

TEST(Pipeline, a_seed_mesh_pointing_inwards_is_reversed) {
  const Volume volume = noisy_sphere(9.0);
  Mesh seed = make_icosahedron(volume.to_physical(Vec3(20, 20, 20)), 3.0);
  Mesh inward;
  std::vector<Mesh::VertexHandle> h;
  for (auto v : seed.vertices()) h.push_back(inward.add_vertex(seed.point(v)));
  for (auto f : seed.faces()) {
    std::vector<Mesh::VertexHandle> fv;
    for (auto v : seed.fv_range(f)) fv.push_back(h[v.idx()]);
    inward.add_face(fv[0], fv[2], fv[1]);
  }
  ASSERT_LT(enclosed_volume(inward), 0.0);
  PipelineOptions o = quick_options();
  o.threshold_otsu = false;
  o.threshold = 125.0;
  o.seed.kind = SeedKind::mesh;
  o.seed.mesh = inward;
  const PipelineResult r = extract_surface(volume, o);
  ASSERT_TRUE(r.failure.empty()) << r.failure;
  EXPECT_TRUE(r.choices.seed_reversed);
  EXPECT_GT(r.report.volume, 0.0);
}

TEST(Pipeline, progress_is_monotone_below_one_and_can_cancel) {
  const Volume volume = noisy_sphere(9.0);
  PipelineOptions o = quick_options();
  double last = 0.0;
  int calls = 0;
  const PipelineResult r = extract_surface(volume, o, [&](const PipelineProgress& p) {
    EXPECT_GE(p.fraction, last);
    EXPECT_LT(p.fraction, 1.0);
    last = p.fraction;
    return ++calls < 5;
  });
  EXPECT_EQ(calls, 5);
  EXPECT_EQ(r.deform.reason, StopReason::cancelled);
  EXPECT_EQ(r.failure, "cancelled");
}

}  // namespace
