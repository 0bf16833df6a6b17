// A scalar volume in physical space: dimensions, spacing, origin and
// direction cosines, sampled by trilinear interpolation (paper section 3.1.2).
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "gdm/mesh.h"

namespace gdm {

using Index3 = std::array<int, 3>;

// The finite values' range of a buffer, and how many are not finite.
struct ValueRange {
  float min = 0.0f, max = 0.0f;  // over the finite values (+inf / -inf when there is none)
  std::size_t non_finite = 0;    // NaN or infinite values
  std::size_t nan = 0;           // of them, NaN
};
// One pass in blocks of independent lanes, without a branch per value (a
// 512^3 volume's check was a third of a second before a model began, issue
// 17); the same range as a plain loop over the values.
ValueRange value_range(const float* values, std::size_t count);

// Voxel values are stored x fastest, then y, then z (ITK and MetaImage order).
// Physical point p of continuous index i: p = origin + direction * (spacing .* i).
class Volume {
 public:
  Volume() = default;
  // Throws InvalidVolume when the grid cannot be used (dimension below 2,
  // zero/negative/NaN spacing, singular or NaN direction, wrong value count,
  // NaN or infinite values).
  Volume(Index3 dims, std::vector<float> values, Vec3 spacing = Vec3::Ones(),
         Vec3 origin = Vec3::Zero(), Eigen::Matrix3d direction = Eigen::Matrix3d::Identity());

  const Index3& dims() const { return dims_; }
  const Vec3& spacing() const { return spacing_; }
  const Vec3& origin() const { return origin_; }
  const Eigen::Matrix3d& direction() const { return direction_; }
  const std::vector<float>& values() const { return values_; }
  // Moves the values out (the volume is left empty), e.g. to change a few and
  // build a new volume without a copy.
  std::vector<float> take_values() {
    dims_ = {0, 0, 0};
    return std::move(values_);
  }
  std::size_t voxel_count() const { return values_.size(); }

  // "One voxel" as a length: the smallest spacing.
  double voxel_size() const { return voxel_size_; }

  // The value returned for points outside the grid (default 0).
  double outside_value() const { return outside_value_; }
  void set_outside_value(double v) { outside_value_ = v; }

  float at(int i, int j, int k) const {
    return values_[static_cast<std::size_t>(i) +
                   static_cast<std::size_t>(dims_[0]) *
                       (static_cast<std::size_t>(j) + static_cast<std::size_t>(dims_[1]) * k)];
  }

  Vec3 to_continuous_index(const Vec3& physical) const { return to_index_ * (physical - origin_); }
  Vec3 to_physical(const Vec3& index) const { return origin_ + to_physical_ * index; }

  // True when the point lies in the grid's box [0, n-1] per axis, shrunk by
  // `margin_voxels` (in index units) on every side.
  bool contains(const Vec3& physical, double margin_voxels = 0.0) const;

  // Trilinear interpolation; outside_value() outside the grid.
  double sample(const Vec3& physical) const;
  // contains(physical) and, when it does, the sample there in `value`: one
  // index transform for both (the fit's crossing search asks both at every
  // step).
  bool sample_inside(const Vec3& physical, double& value) const;

  // Smallest and largest voxel value.
  double min_value() const { return min_value_; }
  double max_value() const { return max_value_; }

  // Physical bounding box corners of the grid (axis-aligned box of the 8 corners).
  void physical_bounds(Vec3& lo, Vec3& hi) const;

 private:
  Index3 dims_{0, 0, 0};
  std::vector<float> values_;
  Vec3 spacing_ = Vec3::Ones();
  Vec3 origin_ = Vec3::Zero();
  Eigen::Matrix3d direction_ = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d to_physical_ = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d to_index_ = Eigen::Matrix3d::Identity();
  double voxel_size_ = 1.0;
  double outside_value_ = 0.0;
  double min_value_ = 0.0;
  double max_value_ = 0.0;
};

// The volume at half the resolution, for growing a model coarse first
// (multi-resolution growth, issue 17): along each axis whose spacing is below
// 1.5 times the smallest (so 1 x 1 x 2 mm becomes 2 x 2 x 2), pairs of voxels
// become one at their centre (a trailing odd voxel is dropped, so the coarse
// grid lies inside the fine one); the new voxel holds the block's minimum
// (keep_minimum) or maximum. The extreme, not the mean: a coarse voxel is on
// the object's side of a threshold only when the whole block is, so a model
// grown in the coarse volume stays in the object (no opening one voxel
// wide is closed by averaging, none is opened). Axes with fewer than 4 voxels
// are kept. Outside value, direction kept.
Volume reduce_by_two(const Volume& volume, bool keep_minimum);

// The standard deviation of one voxel's noise, in the volume's values: the
// median of |v - mean of its 6 neighbours| over the voxels of the physical
// box [lo, hi] (every one, or a regular stride from the box's first voxel
// when there are more than about two million: the same voxels in any crop
// that holds the box), scaled to a normal law's sigma (median absolute value
// 0.6745 sigma; the residual about the mean of six carries 7/6 of one
// voxel's variance). A linear trend cancels; edges and texture are the
// minority a median ignores; exactly constant regions (a clean phantom,
// padding) pull it toward 0. 0 when the box holds no voxel with all six
// neighbours.
double estimate_voxel_noise(const Volume& volume, const Vec3& lo, const Vec3& hi);
// ... over the whole volume.
double estimate_voxel_noise(const Volume& volume);

}  // namespace gdm
