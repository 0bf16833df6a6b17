// The pipeline every front end runs (gdm/pipeline.h) on generated phantoms:
// it chooses the threshold and the seed, runs the model, checks the result,
// and refuses what cannot work with a typed error that names the problem.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/phantoms.h"
#include "gdm/pipeline.h"
#include "gdm/seed.h"
#include "gdm/seeding.h"

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

// A shell four voxels thick (a hollow ball, a vessel wall, a skull) at
// Otsu's T and the automatic seed, noise 3 and 8 %: the deepest voxel is a
// voxel from the contour, and half of that (half a voxel) was a seed smaller
// than the optimiser's steps: it ended "converged" at its own size, exit 0.
// The seed is now at least three quarters of a voxel and the model reaches
// the shell's outer sphere; a smaller seed radius is refused by name.
TEST(Pipeline, the_automatic_seed_grows_in_a_thin_shell) {
  for (const double noise : {0.03, 0.08}) {
    phantoms::Grid grid;
    grid.dims = {48, 48, 48};
    grid.spacing = Vec3(0.8, 0.8, 0.8);
    const Vec3 c = grid.center();
    const Volume shell = phantoms::with_gaussian_noise(
        phantoms::voxelize(grid, phantoms::difference(phantoms::sphere(c, 12.8), phantoms::sphere(c, 9.6)), 50.0, 150.0),
        noise * 150.0, 17u);
    PipelineOptions o;
    o.threshold_otsu = false;
    o.threshold = 125.0;
    const PipelineResult r = extract_surface(shell, o);
    ASSERT_TRUE(r.failure.empty()) << r.failure;
    EXPECT_EQ(r.choices.seed_source, "auto");
    EXPECT_GE(r.choices.seed_radius, kMinGrowingSeedRadius * shell.voxel_size() - 1e-12);
    const auto d = phantoms::vertex_distances(r.mesh, [&](const Vec3& p) { return (p - c).norm() - 12.8; }, 0.8);
    EXPECT_LT(d.mean, 0.15) << "noise " << noise << ": the model is not the shell's outer sphere";
    EXPECT_LT(d.max, 1.0) << "noise " << noise;

    o.seed.kind = SeedKind::point;
    o.seed.point = r.choices.seed_center;
    o.seed.radius = 0.5 * shell.voxel_size();
    try {
      extract_surface(shell, o);
      ADD_FAILURE() << "a seed of half a voxel was accepted";
    } catch (const InvalidOption& e) {
      EXPECT_NE(std::string(e.what()).find("seed_radius 0.4 mm is below 0.75 voxel"), std::string::npos) << e.what();
    }
  }
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
  EXPECT_EQ(r.choices.seed_source, "sphere");
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
  // The seed's region is the background, which covers the border: no object the scan cuts.
  EXPECT_FALSE(r.choices.cut_by_scan);
  EXPECT_GT(r.choices.border.fraction(), kCutByScanBorderFraction);
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

// The fuzz target's volume (test/fuzz/fuzz_pipeline.cpp): a ball of 100s in
// 0s, radius r voxels around voxel c.
Volume fuzz_blob(Index3 dims, Vec3 spacing, Vec3 c, double r) {
  std::vector<float> values;
  for (int z = 0; z < dims[2]; ++z)
    for (int y = 0; y < dims[1]; ++y)
      for (int x = 0; x < dims[0]; ++x)
        values.push_back((Vec3(x, y, z) - c).squaredNorm() <= r * r ? 100.0f : 0.0f);
  return Volume(dims, values, spacing);
}

const OptionEntry<PipelineOptions>& pipeline_option(const std::string& name) {
  for (const auto& e : pipeline_option_catalogue())
    if (e.name == name) return e;
  throw std::runtime_error("no option " + name);
}

// Found by fuzz_pipeline (test/fuzz/corpus/fuzz_pipeline/crash_polarity_nan):
// the catalogue's setter cast NaN to the Polarity enum (undefined behaviour,
// UndefinedBehaviorSanitizer stopped there); the same for every integer or
// choice option and NaN, infinities or 1e300, and value_text() cast a choice's
// value to int before its range check. Now the setter refuses with
// InvalidOption naming the option, and real options keep the value for
// validate() to name.
TEST(Pipeline, fuzz_option_setters_refuse_values_their_field_cannot_hold) {
  const Volume volume = fuzz_blob({12, 12, 12}, Vec3(0.7, 0.7, 2.0), Vec3(6, 6, 6), 5.0);
  PipelineOptions o = quick_options();
  o.threshold_otsu = false;
  o.threshold = 0.5;
  o.deform.global_refinements = 1;
  pipeline_option("smooth").set(o, std::nan(""));
  try {
    pipeline_option("polarity").set(o, std::nan(""));
    ADD_FAILURE() << "polarity = nan was stored";
  } catch (const InvalidOption& e) {
    EXPECT_EQ(e.option(), "polarity");
    EXPECT_NE(std::string(e.what()).find("polarity must be bright or dark, got nan"), std::string::npos) << e.what();
  }
  EXPECT_EQ(value_text(pipeline_option("mode"), 1e300), "1e+300");  // the message's value: no cast of 1e300 to int
  try {
    extract_surface(volume, o);
    ADD_FAILURE() << "smooth = nan was accepted";
  } catch (const InvalidOption& e) {
    EXPECT_EQ(e.option(), "smooth");
  }
  const double hostile[] = {std::nan(""), INFINITY, -INFINITY, 1e300, -1e300, 1e19, 4294967296.0};
  for (const auto& e : pipeline_option_catalogue()) {
    for (const double v : hostile) {
      PipelineOptions p;
      try {
        e.set(p, v);
      } catch (const InvalidOption& error) {
        EXPECT_EQ(error.option(), e.name);
        EXPECT_TRUE(e.type == OptionType::integer || e.type == OptionType::choice) << e.name;
        continue;
      }
      // Stored: an integer field holds it exactly (1e19 fits max_faces'
      // size_t), and validate() names what the range refuses.
      if (e.type == OptionType::integer || e.type == OptionType::choice) EXPECT_EQ(e.get(p), v) << e.name;
      if (e.type != OptionType::boolean && !accepts(e, v)) {
        try {
          validate(p);
          ADD_FAILURE() << e.name << " = " << v << " was accepted";
        } catch (const InvalidOption& error) {
          EXPECT_EQ(error.option(), e.name);
        }
      }
    }
  }
}

// Found by fuzz_pipeline (test/fuzz/corpus/fuzz_pipeline/timeout_smooth_tiny_spacing):
// smooth 1000 mm on a volume with a spacing of 1e-6 mm made a Gaussian kernel
// of 4e9 voxels each side (the cast to int overflowed first): a hang. A sigma
// wider than the volume along an axis is now refused up front.
TEST(Pipeline, fuzz_smoothing_wider_than_the_volume_is_refused_at_once) {
  const Volume volume = fuzz_blob({10, 7, 8}, Vec3(1e-6, 1.0, 1.0), Vec3(5, 3, 4), 3.0);
  PipelineOptions o = quick_options();
  o.time_limit = 1.0;
  for (const double smooth : {1000.0, 1.0, 2e-5}) {
    o.smooth = smooth;
    const auto start = std::chrono::steady_clock::now();
    try {
      extract_surface(volume, o);
      ADD_FAILURE() << "smooth " << smooth << " on a 1e-6 mm spacing was accepted";
    } catch (const InvalidOption& e) {
      EXPECT_EQ(e.option(), "smooth");
      EXPECT_NE(std::string(e.what()).find("wider than the volume's 10 voxels"), std::string::npos) << e.what();
    }
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
  }
  // Narrower than the volume on every axis: smoothed as before.
  o.smooth = 5e-6;
  EXPECT_NO_THROW(gaussian_smooth(volume, o.smooth));
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
