#include <cmath>

#include <gtest/gtest.h>

#include "gdm/cost_terms.h"

using namespace gdm;

namespace {

// A 1D ramp along x: value = 10 x on a 11 x 2 x 2 grid with unit spacing.
Volume ramp() {
  std::vector<float> values;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i <= 10; ++i) values.push_back(10.0f * i);
  return Volume({11, 2, 2}, values);
}

}  // namespace

TEST(ImageEvent, shifted_threshold_matches_equation_2) {
  const Volume v = ramp();
  // Growing in a darker object: the brighter side is blocked, I = (X - T)^+.
  const ImageEvent grow_dark(1.0, v, 42.0, Polarity::object_darker, Mode::grow, 1.0);
  EXPECT_DOUBLE_EQ(grow_dark.cost(Vec3(3.0, 0.5, 0.5)), 0.0);    // X = 30 < T
  EXPECT_DOUBLE_EQ(grow_dark.cost(Vec3(5.5, 0.5, 0.5)), 13.0);   // X = 55: 55 - 42
  EXPECT_DOUBLE_EQ(grow_dark.cost(Vec3(4.2, 0.0, 1.0)), 0.0);    // exactly at T
  // Weight and intensity scale multiply and divide.
  const ImageEvent weighted(2.0, v, 42.0, Polarity::object_darker, Mode::grow, 4.0);
  EXPECT_DOUBLE_EQ(weighted.cost(Vec3(5.5, 0.5, 0.5)), 2.0 * 13.0 / 4.0);
}

TEST(ImageEvent, polarity_and_mode_follow_the_duality_of_table_1) {
  const Volume v = ramp();
  const Vec3 dark(2.0, 1, 1), bright(8.0, 1, 1);  // 20 and 80 around T = 50
  const ImageEvent grow_bright(1, v, 50, Polarity::object_brighter, Mode::grow, 1);
  const ImageEvent shrink_bright(1, v, 50, Polarity::object_brighter, Mode::shrink, 1);
  const ImageEvent grow_dark(1, v, 50, Polarity::object_darker, Mode::grow, 1);
  const ImageEvent shrink_dark(1, v, 50, Polarity::object_darker, Mode::shrink, 1);
  EXPECT_DOUBLE_EQ(grow_bright.cost(dark), 30.0);
  EXPECT_DOUBLE_EQ(grow_bright.cost(bright), 0.0);
  EXPECT_DOUBLE_EQ(shrink_bright.cost(bright), 30.0);
  EXPECT_DOUBLE_EQ(shrink_bright.cost(dark), 0.0);
  // Duals: shrinking with one object definition is growing with the other.
  for (double x = 0.0; x <= 10.0; x += 0.37) {
    const Vec3 p(x, 0.3, 0.6);
    EXPECT_DOUBLE_EQ(shrink_bright.cost(p), grow_dark.cost(p));
    EXPECT_DOUBLE_EQ(shrink_dark.cost(p), grow_bright.cost(p));
  }
  EXPECT_TRUE(grow_bright.is_blocked(dark));
  EXPECT_FALSE(grow_bright.is_blocked(bright));
}

TEST(ImageEvent, leaving_the_volume_costs_infinity) {
  const Volume v = ramp();
  const ImageEvent term(1, v, 50, Polarity::object_brighter, Mode::grow, 1);
  EXPECT_TRUE(std::isinf(term.cost(Vec3(10.5, 0.5, 0.5))));
  EXPECT_TRUE(std::isinf(term.cost(Vec3(5, -0.1, 0.5))));
}

TEST(TopologyTerm, matches_equation_3_by_hand) {
  // Neighbours: a unit square around the origin in the z = 0 plane; the
  // centroid is the origin and the largest separation is the diagonal sqrt(2).
  VertexNeighbourhood n;
  n.ring_centroid = Vec3(0, 0, 0);
  n.ring_extent = std::sqrt(2.0);
  const TopologyTerm t(1.0);
  EXPECT_DOUBLE_EQ(t.cost(n, Vec3(0, 0, 0)), 0.0);
  EXPECT_NEAR(t.cost(n, Vec3(0, 0, 1)), 1.0 / std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(t.cost(n, Vec3(0.3, 0.4, 0)), 0.5 / std::sqrt(2.0), 1e-15);
  const TopologyTerm weighted(5.0);
  EXPECT_NEAR(weighted.cost(n, Vec3(0, 0, 1)), 5.0 / std::sqrt(2.0), 1e-14);
}

TEST(TopologyTerm, extent_floor_applies_only_below_it) {
  VertexNeighbourhood n;
  n.ring_centroid = Vec3::Zero();
  n.ring_extent = 2.0;
  EXPECT_DOUBLE_EQ(TopologyTerm(1.0, 1.0).cost(n, Vec3(0, 0, 1)), 0.5);   // floor below the extent
  EXPECT_DOUBLE_EQ(TopologyTerm(1.0, 4.0).cost(n, Vec3(0, 0, 1)), 0.25);  // floor above it
}

TEST(DeformationPotential, attracts_to_the_point_along_the_sensed_normal) {
  VertexNeighbourhood n;
  n.position = Vec3(1, 2, 3);
  n.normal = Vec3(0, 0, 1);
  n.sense = 1.0;
  const DeformationPotential d(1.0, 1.0, 0.5);  // reach 1 voxel = 0.5 mm
  EXPECT_TRUE(d.target(n).isApprox(Vec3(1, 2, 3.5)));
  EXPECT_DOUBLE_EQ(d.cost(n, n.position), 1.0);             // one voxel away
  EXPECT_DOUBLE_EQ(d.cost(n, Vec3(1, 2, 3.5)), 0.0);
  EXPECT_LT(d.cost(n, Vec3(1, 2, 3.25)), d.cost(n, n.position));  // decreases along the normal
  n.sense = -1.0;  // flipped: now attracted the other way
  EXPECT_TRUE(d.target(n).isApprox(Vec3(1, 2, 2.5)));
  EXPECT_GT(d.cost(n, Vec3(1, 2, 3.25)), d.cost(n, n.position));
}
