#include "gdm/optimizer.h"

#include <algorithm>
#include <cmath>

namespace gdm {

Vec3 cost_gradient(const CostFunction& cost, const VertexNeighbourhood& n, double h_mm) {
  return cost_gradient(cost, n, h_mm, cost(n, n.position));
}

Vec3 cost_gradient(const CostFunction& cost, const VertexNeighbourhood& n, double h_mm, double c0) {
  Vec3 g = Vec3::Zero();
  for (int axis = 0; axis < 3; ++axis) {
    Vec3 d = Vec3::Zero();
    d[axis] = h_mm;
    const double plus = cost(n, n.position + d), minus = cost(n, n.position - d);
    const bool fp = std::isfinite(plus), fm = std::isfinite(minus);
    if (fp && fm) {
      g[axis] = (plus - minus) / (2.0 * h_mm);
    } else if (fp && std::isfinite(c0)) {
      g[axis] = (plus - c0) / h_mm;
    } else if (fm && std::isfinite(c0)) {
      g[axis] = (c0 - minus) / h_mm;
    } else if (fp) {
      g[axis] = -1.0;  // only the + side is usable: head there
    } else if (fm) {
      g[axis] = 1.0;
    }
  }
  return g;
}

StepResult steepest_descent_step(const CostFunction& cost, const VertexNeighbourhood& n,
                                 double step, double voxel_size, const OptimizerOptions& options) {
  StepResult result;
  result.position = n.position;
  result.cost = cost(n, n.position);
  step = std::clamp(step, options.min_step, options.max_step);
  result.next_step = options.min_step;

  // The cost here is known: it was evaluated twice per step (issue 17).
  const Vec3 g = cost_gradient(cost, n, options.gradient_step * voxel_size, result.cost);
  const double norm = g.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) return result;
  const Vec3 direction = -g / norm;

  // A move must lower the cost by more than rounding noise.
  const double tolerance = 1e-12 * std::max(1.0, std::abs(result.cost));
  double tried = -1.0;
  for (int attempt = 0; attempt <= options.max_step_reductions; ++attempt) {
    const double s = std::max(options.min_step, step / std::pow(2.0, attempt));
    if (s == tried) break;  // clamped at the smallest step: nothing new to try
    tried = s;
    const Vec3 candidate = n.position + (s * voxel_size) * direction;
    const double c = cost(n, candidate);
    if (c < result.cost - tolerance) {
      result.position = candidate;
      result.cost = c;
      result.moved = true;
      result.next_step = attempt == 0 ? std::min(options.max_step, 2.0 * s) : s;
      return result;
    }
  }
  return result;
}

}  // namespace gdm
