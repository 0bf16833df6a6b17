// Telling an object the scan cuts from a leak (gdm/border_contact.h): where the
// seed's region meets the volume's border, and the pipeline closing such an
// object at the border without being told to.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "gdm/border_contact.h"
#include "gdm/mesh_checks.h"
#include "gdm/phantoms.h"
#include "gdm/pipeline.h"

namespace {

using namespace gdm;

// A noisy ball whose centre lies `centre_z` voxels above the -z side: the
// scan cuts it there when centre_z < radius.
struct CutBall {
  phantoms::Grid grid;
  Vec3 centre;
  double radius = 0.0;
  Volume volume;
};

CutBall cut_ball(double centre_z, double noise_fraction, unsigned seed) {
  CutBall b;
  b.grid.dims = {40, 40, 36};
  b.grid.spacing = Vec3(0.9, 0.9, 1.2);
  b.radius = 11.0;
  b.centre = Vec3(20 * 0.9, 19 * 0.9, centre_z * 1.2);
  const Volume clean = phantoms::voxelize(b.grid, phantoms::sphere(b.centre, b.radius), 50.0, 150.0);
  b.volume = phantoms::with_gaussian_noise(clean, noise_fraction * 100.0, seed);
  return b;
}

TEST(BorderContact, a_ball_the_scan_cuts_meets_one_side_on_a_small_part) {
  const CutBall b = cut_ball(3.0, 0.05, 11);
  const BorderContact c = measure_border_contact(b.volume, {20, 19, 3}, 100.0, Polarity::object_brighter);
  ASSERT_TRUE(c.measured);
  EXPECT_TRUE(c.complete);
  EXPECT_TRUE(c.cut_by_scan()) << c.fraction();
  EXPECT_GT(c.per_side[4], 100u);  // -z: the ball's cut, a disc of radius ~9 voxels
  for (int side : {0, 1, 2, 3, 5}) EXPECT_EQ(c.per_side[side], 0u) << "side " << side;
  EXPECT_LT(c.fraction(), 0.1);
  EXPECT_NE(c.sides_text().find("-z ("), std::string::npos) << c.sides_text();
}

TEST(BorderContact, the_background_covers_the_border_and_is_no_cut_object) {
  const CutBall b = cut_ball(18.0, 0.05, 12);
  // Wrong polarity: the seed's region is the background around the ball.
  const BorderContact c = measure_border_contact(b.volume, {20, 19, 18}, 100.0, Polarity::object_darker);
  EXPECT_FALSE(c.measured);  // the ball's centre is bright
  const BorderContact bg = measure_border_contact(b.volume, {2, 2, 2}, 100.0, Polarity::object_darker);
  ASSERT_TRUE(bg.measured);
  EXPECT_FALSE(bg.complete);  // stopped once past a quarter of the border
  EXPECT_FALSE(bg.cut_by_scan());
  EXPECT_GT(bg.fraction(), kCutByScanBorderFraction);
  // A ball inside the scan meets the border nowhere: nothing to allow.
  const BorderContact inside = measure_border_contact(b.volume, {20, 19, 18}, 100.0, Polarity::object_brighter);
  ASSERT_TRUE(inside.measured);
  EXPECT_EQ(inside.border_voxels, 0u);
  EXPECT_FALSE(inside.cut_by_scan());
}

// At the defaults, a ball the scan cuts is closed across the cut and fits
// the sphere elsewhere; the choices say why the border was allowed.
TEST(BorderContact, the_pipeline_closes_an_object_the_scan_cuts_at_the_border) {
  for (const double noise : {0.03, 0.08}) {
    const CutBall b = cut_ball(4.0, noise, 13);
    PipelineOptions o;
    o.deform.threads = 1;
    const PipelineResult r = extract_surface(b.volume, o);
    ASSERT_TRUE(r.failure.empty()) << r.failure;
    EXPECT_TRUE(r.choices.cut_by_scan);
    EXPECT_GT(r.deform.border_vertices, 0u);
    EXPECT_TRUE(r.report.closed);
    EXPECT_TRUE(r.report.two_manifold);
    EXPECT_EQ(r.report.genus, 0);
    EXPECT_EQ(r.report.components, 1);
    EXPECT_EQ(r.report.self_intersections, 0u);
    // Off the cut (more than 1.5 voxels above the -z side), the sphere.
    std::vector<double> sphere_d;
    double lowest = 1e9;
    for (const auto v : r.mesh.vertices()) {
      const Vec3 p = to_eigen(r.mesh.point(v));
      lowest = std::min(lowest, p.z());
      if (p.z() > 1.5 * 1.2) sphere_d.push_back(std::abs((p - b.centre).norm() - b.radius) / 0.9);
    }
    const phantoms::DistanceStats d = phantoms::distance_stats(sphere_d);
    EXPECT_LT(d.mean, 0.15) << "noise " << noise;
    // The cap lies at the border: the model reaches within a voxel of z = 0.
    EXPECT_LT(lowest, 1.2) << "noise " << noise;
    bool mentioned = false;
    PreparedModel p = prepare_model(b.volume, o);
    for (const auto& line : describe_choices(p)) mentioned |= line.find("cut by the scan") != std::string::npos;
    EXPECT_TRUE(mentioned);
  }
}

}  // namespace
