#include "gdm/cost_terms.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gdm {

DeformationPotential::DeformationPotential(double weight, double reach_voxels, double voxel_size)
    : weight_(weight), reach_(reach_voxels * voxel_size), voxel_size_(voxel_size) {}

Vec3 DeformationPotential::target(const VertexNeighbourhood& n) const {
  return n.position + (n.sense * reach_) * n.normal;
}

double DeformationPotential::cost(const VertexNeighbourhood& n, const Vec3& x) const {
  if (weight_ == 0.0) return 0.0;
  return weight_ * (x - target(n)).norm() / voxel_size_;
}

ImageEvent::ImageEvent(double weight, const Volume& volume, double threshold, Polarity polarity,
                       Mode mode, double intensity_scale)
    : weight_(weight), volume_(&volume), threshold_(threshold), inv_scale_(1.0 / intensity_scale) {
  // The blocked region is the one the model must not enter: the background
  // when growing, the object when shrinking.
  const bool object_brighter = polarity == Polarity::object_brighter;
  const bool blocked_is_object = mode == Mode::shrink;
  sign_ = (object_brighter == blocked_is_object) ? 1.0 : -1.0;
  outside_is_free_ = mode == Mode::shrink;
}

double ImageEvent::excess(const Vec3& x) const {
  // Outside the volume: blocked when growing (the model stays in the
  // image); background when shrinking, so a seed around an object that the
  // scan cuts may start outside and close it at the border.
  double value;
  if (!volume_->sample_inside(x, value))
    return outside_is_free_ ? -inv_scale_ : std::numeric_limits<double>::infinity();
  return sign_ * (value - threshold_) * inv_scale_;
}

double ImageEvent::cost(const Vec3& x) const {
  const double e = excess(x);
  if (std::isinf(e)) return std::numeric_limits<double>::infinity();
  return e > 0.0 ? weight_ * e : 0.0;
}

double TopologyTerm::cost(const VertexNeighbourhood& n, const Vec3& x) const {
  const double limit = n.refined ? std::max(max_ratio_, kRefinedMaxRatio) : max_ratio_;
  if (limit < std::numeric_limits<double>::infinity()) {
    const double r = ratio(n, x);
    if (r > limit && r > ratio(n, n.position)) return std::numeric_limits<double>::infinity();
  }
  if (weight_ == 0.0) return 0.0;
  return weight_ * (x - n.ring_centroid).norm() / std::max(n.ring_extent, min_extent_);
}

}  // namespace gdm
