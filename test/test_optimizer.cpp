#include <random>

#include <gtest/gtest.h>

#include "gdm/optimizer.h"

using namespace gdm;

namespace {

Volume sphere_volume() {
  // A bright ball of radius 6 in a 24^3 grid, with a linear edge.
  std::vector<float> values;
  for (int k = 0; k < 24; ++k)
    for (int j = 0; j < 24; ++j)
      for (int i = 0; i < 24; ++i) {
        const double r = (Vec3(i, j, k) - Vec3(12, 12, 12)).norm();
        values.push_back(static_cast<float>(std::clamp(6.5 - r, 0.0, 1.0) * 100.0));
      }
  return Volume({24, 24, 24}, values);
}

CostFunction make_cost(const Volume& v) {
  return CostFunction{DeformationPotential(1.0, 1.0, 1.0),
                      ImageEvent(1.0, v, 50.0, Polarity::object_brighter, Mode::grow, 1.0), TopologyTerm(5.0)};
}

}  // namespace

TEST(Optimizer, never_moves_uphill) {
  const Volume v = sphere_volume();
  const CostFunction cost = make_cost(v);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const OptimizerOptions options;
  int moved = 0, stayed = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    VertexNeighbourhood n;
    n.position = Vec3(12, 12, 12) + 8.0 * Vec3(u(rng), u(rng), u(rng));
    n.normal = Vec3(u(rng), u(rng), u(rng)).normalized();
    n.sense = u(rng) < 0 ? -1.0 : 1.0;
    n.ring_centroid = n.position + 2.0 * Vec3(u(rng), u(rng), u(rng));
    n.ring_extent = 3.0 + u(rng);
    const double before = cost(n, n.position);
    const StepResult r = steepest_descent_step(cost, n, 1.0, 1.0, options);
    EXPECT_LE(r.cost, before);
    EXPECT_DOUBLE_EQ(r.cost, cost(n, r.position));
    if (r.moved) {
      ++moved;
      EXPECT_LT(r.cost, before);
      const double step = (r.position - n.position).norm();
      EXPECT_GE(step, options.min_step - 1e-12);
      EXPECT_LE(step, options.max_step + 1e-12);
    } else {
      ++stayed;
      EXPECT_EQ(r.position, n.position);
    }
    EXPECT_GE(r.next_step, options.min_step);
    EXPECT_LE(r.next_step, options.max_step);
  }
  EXPECT_GT(moved, 100);  // the test exercises both branches
  EXPECT_GT(stayed, 10);
}

TEST(Optimizer, stays_put_at_a_minimum) {
  const Volume v = sphere_volume();
  const CostFunction cost{DeformationPotential(1.0, 1.0, 1.0),
                          ImageEvent(1.0, v, 50.0, Polarity::object_brighter, Mode::grow, 1.0), TopologyTerm(5.0)};
  VertexNeighbourhood n;
  n.position = Vec3(12, 12, 12);
  n.normal = Vec3(1, 0, 0);
  n.ring_centroid = n.position;
  n.ring_extent = 1.0;  // T pulls with 5 per mm: more than D's 1 per mm
  const StepResult r = steepest_descent_step(cost, n, 1.0, 1.0, OptimizerOptions{});
  EXPECT_FALSE(r.moved);
  EXPECT_EQ(r.position, n.position);
}

TEST(Optimizer, stops_at_the_boundary_of_the_object) {
  const Volume v = sphere_volume();
  const CostFunction cost = make_cost(v);
  VertexNeighbourhood n;
  n.position = Vec3(12, 12, 12);
  n.normal = Vec3(1, 0, 0);
  n.ring_extent = 100.0;
  double step = 1.0;
  for (int i = 0; i < 40; ++i) {
    n.ring_centroid = n.position;  // the neighbours follow
    const StepResult r = steepest_descent_step(cost, n, step, 1.0, OptimizerOptions{});
    n.position = r.position;
    step = r.next_step;
  }
  // The 50 crossing lies at radius 6: the vertex ends within a quarter voxel before it.
  const double r = (n.position - Vec3(12, 12, 12)).norm();
  EXPECT_GT(r, 6.0 - 0.25 - 1e-9);
  EXPECT_LE(r, 6.0 + 1e-9);
}

TEST(Optimizer, gradient_by_central_differences_is_accurate_on_smooth_costs) {
  const Volume v = sphere_volume();
  const CostFunction cost = make_cost(v);
  VertexNeighbourhood n;
  n.position = Vec3(12.3, 11.1, 12.7);
  n.normal = Vec3(0, 0, 1);
  n.ring_centroid = n.position + Vec3(3, 0, 0);
  n.ring_extent = 4.0;
  // D's gradient: unit vector away from the target; T's: unit vector away from the centroid times 5/4.
  const Vec3 expected = (n.position - Vec3(12.3, 11.1, 13.7)).normalized() +
                        1.25 * (n.position - n.ring_centroid).normalized();
  EXPECT_TRUE(cost_gradient(cost, n, 1e-4).isApprox(expected, 1e-6));
}
