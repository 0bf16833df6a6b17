// The adaptive steepest descent of one vertex (paper section 3.2).
#pragma once

#include "gdm/cost_terms.h"

namespace gdm {

struct OptimizerOptions {
  double min_step = 0.25;        // smallest step, voxels (section 3.2: [1/4, 1])
  double max_step = 1.0;         // largest step, voxels
  int max_step_reductions = 3;   // step halvings tried before the vertex stays put
  double gradient_step = 0.1;    // central-difference half width, voxels
};

struct StepResult {
  Vec3 position = Vec3::Zero();  // where the vertex goes (its old place when it stays)
  double cost = 0.0;             // the cost there
  double next_step = 1.0;        // the step (voxels) to try next cycle
  bool moved = false;
};

// The cost gradient by central differences along the physical axes. Where one
// side is infinite (outside the volume) a one-sided difference is used.
Vec3 cost_gradient(const CostFunction& cost, const VertexNeighbourhood& n, double h_mm);
// The same with the cost at n.position already known (`cost_here`).
Vec3 cost_gradient(const CostFunction& cost, const VertexNeighbourhood& n, double h_mm, double cost_here);

// One steepest-descent step from n.position: try `step` voxels against the
// gradient, halve up to max_step_reductions times (never below min_step), and
// move only where the cost is strictly lower. A step taken at the first try
// doubles the next one (up to max_step); otherwise the next starts where this
// one succeeded or, after a failure, at the smallest step.
StepResult steepest_descent_step(const CostFunction& cost, const VertexNeighbourhood& n,
                                 double step, double voxel_size, const OptimizerOptions& options);

}  // namespace gdm
