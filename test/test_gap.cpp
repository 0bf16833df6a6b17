// The gap size G (passage.h): openings narrower than G are bridged, channels
// wider than G are followed (issue 14). Phantoms built here, with CT-like
// edges and noise; distances in voxels.
#include <gtest/gtest.h>

#include <cmath>

#include "gdm/deformer.h"
#include "gdm/errors.h"
#include "gdm/passage.h"
#include "gdm/phantoms.h"
#include "gdm/seed.h"
#include "mesh_expectations.h"

namespace gdm {
namespace {

namespace ph = phantoms;

constexpr double kLow = 50.0, kHigh = 200.0, kThreshold = 125.0;

// An opened bottle: a spherical cavity of radius 15 voxels inside a wall 2
// voxels thick, pierced along +x by a round opening of diameter `opening`;
// the cavity and the outside are one side of T, the wall the other.
struct Bottle {
  ph::Grid grid;
  Vec3 center;
  double radius = 15.0;
  double opening = 0.0;
  Volume volume;

  // Distance of p to the opening's axis (the ray from the centre along +x).
  double from_axis(const Vec3& p) const { return std::hypot(p.y() - center.y(), p.z() - center.z()); }
  bool in_cap(const Vec3& p) const { return p.x() > center.x() && from_axis(p) < opening; }
};

Bottle make_bottle(double opening, bool cavity_dark, double noise_fraction, unsigned seed) {
  Bottle b;
  b.grid.dims = {48, 48, 48};
  b.center = b.grid.center();
  b.opening = opening;
  const Vec3 c = b.center;
  const double inner = b.radius, outer = b.radius + 2.0, half = 0.5 * opening;
  const ph::Sdf shell = [=](const Vec3& p) {
    const double r = (p - c).norm();
    return std::max(r - outer, inner - r);
  };
  const ph::Sdf hole = [=](const Vec3& p) {
    return std::max(std::hypot(p.y() - c.y(), p.z() - c.z()) - half, c.x() - p.x());
  };
  const ph::Sdf wall = ph::difference(shell, hole);
  // The wall is the bright side when the cavity is dark, and the other way round.
  const Volume clean = cavity_dark ? ph::voxelize(b.grid, wall, kLow, kHigh - kLow)
                                   : ph::voxelize(b.grid, wall, kHigh, kLow - kHigh);
  b.volume = ph::with_gaussian_noise(clean, noise_fraction * (kHigh - kLow), seed);
  return b;
}

DeformOptions bottle_options(bool cavity_dark, double gap) {
  DeformOptions o;
  o.threshold = kThreshold;
  o.polarity = cavity_dark ? Polarity::object_darker : Polarity::object_brighter;
  o.gap = gap;
  o.stop_at_border = true;
  return o;
}

void expect_bottle_filled(const Bottle& b, const Mesh& mesh, const DeformResult& r) {
  ASSERT_EQ(r.border_vertices, 0u) << "the model leaked out of the opening";
  EXPECT_EQ(r.reason, StopReason::converged) << to_string(r.reason);
  EXPECT_GT(r.gap_closed_voxels, 0u);
  test::expect_valid_closed_surface(mesh);
  std::vector<double> wall, cap;
  for (auto v : mesh.vertices()) {
    const Vec3 p = to_eigen(mesh.point(v));
    const double d = std::abs((p - b.center).norm() - b.radius);
    (b.in_cap(p) ? cap : wall).push_back(d);
  }
  ASSERT_FALSE(cap.empty());
  const ph::DistanceStats w = ph::distance_stats(wall), c = ph::distance_stats(cap);
  EXPECT_LE(w.mean, 0.15) << "opening " << b.opening << ": wall mean " << w.mean << " p95 " << w.p95;
  EXPECT_LE(c.max, 1.0) << "opening " << b.opening << ": the cap strays " << c.max << " voxels from the sphere (mean "
                        << c.mean << ")";
}

// Noise 3 and 10 % of the contrast, each with its own noise seed.
class OpenedBottle : public ::testing::TestWithParam<std::tuple<int, bool, int>> {};

TEST_P(OpenedBottle, gap_above_the_opening_bridges_it) {
  const auto [opening, dark, noise_percent] = GetParam();
  const Bottle b = make_bottle(opening, dark, 0.01 * noise_percent, 17u + static_cast<unsigned>(opening + noise_percent));
  Mesh mesh = make_geodesic_sphere(b.center, 3.0, 1);
  const DeformResult r = deform(mesh, b.volume, bottle_options(dark, opening + 2.0));
  expect_bottle_filled(b, mesh, r);
}

INSTANTIATE_TEST_SUITE_P(Openings, OpenedBottle,
                         ::testing::Combine(::testing::Values(2, 4, 6, 8), ::testing::Bool(), ::testing::Values(3, 10)),
                         [](const auto& info) {
                           return "d" + std::to_string(std::get<0>(info.param)) +
                                  (std::get<1>(info.param) ? "_dark" : "_bright") + "_noise" +
                                  std::to_string(std::get<2>(info.param));
                         });

TEST(Gap, without_a_gap_the_model_leaks_out_of_the_bottle) {
  const Bottle b = make_bottle(6, true, 0.05, 3u);
  Mesh mesh = make_geodesic_sphere(b.center, 3.0, 1);
  const DeformResult r = deform(mesh, b.volume, bottle_options(true, 0.0));
  EXPECT_EQ(r.reason, StopReason::border);
  EXPECT_GT(r.border_vertices, 0u);
  EXPECT_EQ(r.gap_closed_voxels, 0u);
}

TEST(Gap, two_voxels_or_less_is_no_gate) {
  const Bottle b = make_bottle(6, true, 0.0, 3u);
  EXPECT_FALSE(gap_gate_active(0.0, b.volume));
  EXPECT_FALSE(gap_gate_active(2.0, b.volume));
  EXPECT_TRUE(gap_gate_active(2.01, b.volume));
}

TEST(Gap, seed_in_an_opening_narrower_than_the_gap_is_refused) {
  const Bottle b = make_bottle(6, true, 0.0, 3u);
  // A seed in the middle of the opening, which no ball of diameter 10 fits.
  const Vec3 in_hole = b.center + Vec3(b.radius + 1.0, 0.0, 0.0);
  Mesh mesh = make_geodesic_sphere(in_hole, 0.5, 0);
  try {
    deform(mesh, b.volume, bottle_options(true, 10.0));
    FAIL() << "a seed where no ball of the gap fits was accepted";
  } catch (const InvalidSeed& e) {
    EXPECT_NE(std::string(e.what()).find("gap"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace gdm
