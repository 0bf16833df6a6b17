#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "gdm/errors.h"
#include "gdm/volume.h"

using gdm::Index3;
using gdm::Vec3;
using gdm::Volume;

namespace {

// f(i, j, k) = 2 i + 3 j - k + 7: trilinear interpolation reproduces it exactly.
Volume linear_volume(const Vec3& spacing, const Vec3& origin, const Eigen::Matrix3d& direction) {
  const Index3 dims{6, 5, 4};
  std::vector<float> values;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) values.push_back(static_cast<float>(2 * i + 3 * j - k + 7));
  return Volume(dims, values, spacing, origin, direction);
}

}  // namespace

TEST(Volume, trilinear_sampling_reproduces_a_linear_field) {
  const Volume v = linear_volume(Vec3::Ones(), Vec3::Zero(), Eigen::Matrix3d::Identity());
  EXPECT_DOUBLE_EQ(v.sample(Vec3(0, 0, 0)), 7.0);
  EXPECT_NEAR(v.sample(Vec3(1.25, 2.5, 0.75)), 2 * 1.25 + 3 * 2.5 - 0.75 + 7, 1e-9);
  EXPECT_NEAR(v.sample(Vec3(5, 4, 3)), 2 * 5 + 3 * 4 - 3 + 7, 1e-9);  // the far corner
  EXPECT_EQ(v.min_value(), 4.0);
  EXPECT_EQ(v.max_value(), 29.0);
}

TEST(Volume, physical_space_honours_spacing_origin_and_direction) {
  Eigen::Matrix3d rot;  // 90 degrees about z: index x goes to physical y
  rot << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  const Vec3 spacing(0.5, 2.0, 3.0), origin(10, -4, 1);
  const Volume v = linear_volume(spacing, origin, rot);
  const Vec3 index(1.5, 2.25, 1.0);
  const Vec3 p = v.to_physical(index);
  EXPECT_NEAR(p.x(), 10 - 2.0 * 2.25, 1e-12);
  EXPECT_NEAR(p.y(), -4 + 0.5 * 1.5, 1e-12);
  EXPECT_NEAR(p.z(), 1 + 3.0 * 1.0, 1e-12);
  EXPECT_TRUE(v.to_continuous_index(p).isApprox(index, 1e-12));
  EXPECT_NEAR(v.sample(p), 2 * 1.5 + 3 * 2.25 - 1.0 + 7, 1e-9);
  EXPECT_DOUBLE_EQ(v.voxel_size(), 0.5);
}

TEST(Volume, outside_the_grid_returns_the_outside_value) {
  Volume v = linear_volume(Vec3::Ones(), Vec3::Zero(), Eigen::Matrix3d::Identity());
  EXPECT_EQ(v.sample(Vec3(-0.01, 1, 1)), 0.0);
  v.set_outside_value(-100.0);
  EXPECT_EQ(v.sample(Vec3(1, 1, 3.5)), -100.0);
  EXPECT_EQ(v.sample(Vec3(NAN, 1, 1)), -100.0);
  EXPECT_FALSE(v.contains(Vec3(6, 1, 1)));
  EXPECT_TRUE(v.contains(Vec3(5, 1, 1)));
  EXPECT_FALSE(v.contains(Vec3(5, 1, 1), 0.5));
}

TEST(Volume, rejects_unusable_grids_with_a_clear_message) {
  const auto make = [](Index3 dims, std::size_t count, Vec3 spacing, float fill = 1.0f) {
    return Volume(dims, std::vector<float>(count, fill), spacing);
  };
  EXPECT_THROW(make({4, 4, 4}, 64, Vec3(1, 0, 1)), gdm::InvalidVolume);
  EXPECT_THROW(make({4, 4, 4}, 64, Vec3(1, NAN, 1)), gdm::InvalidVolume);
  EXPECT_THROW(make({4, 4, 4}, 64, Vec3(1, -1, 1)), gdm::InvalidVolume);
  EXPECT_THROW(make({4, 4, 1}, 16, Vec3::Ones()), gdm::InvalidVolume);
  EXPECT_THROW(make({4, 4, 4}, 63, Vec3::Ones()), gdm::InvalidVolume);
  EXPECT_THROW(make({4, 4, 4}, 64, Vec3::Ones(), NAN), gdm::InvalidVolume);
  try {
    make({4, 4, 4}, 64, Vec3(1, 0, 1));
  } catch (const gdm::InvalidVolume& e) {
    EXPECT_NE(std::string(e.what()).find("spacing"), std::string::npos) << e.what();
  }
  EXPECT_THROW(Volume({4, 4, 4}, std::vector<float>(64, 1.f), Vec3::Ones(), Vec3::Zero(), Eigen::Matrix3d::Zero()),
               gdm::InvalidVolume);
}

// value_range against a plain loop over the values: random buffers of
// every length from 0 to 40 (the lanes' tail), with NaN and infinities
// mixed in at random places, and the extremes at the first and last place.
TEST(Volume, value_range_is_the_plain_loops_range) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> value(-1000.0f, 1000.0f);
  std::uniform_int_distribution<int> kind(0, 9);
  const float inf = std::numeric_limits<float>::infinity();
  for (int round = 0; round < 20; ++round)
    for (std::size_t n = 0; n <= 40; ++n) {
      std::vector<float> v(n);
      for (float& x : v) {
        const int k = kind(rng);
        x = k == 0 && round % 2 ? NAN : k == 1 && round % 3 == 0 ? inf : k == 2 && round % 5 == 0 ? -inf : value(rng);
      }
      if (n > 0 && round == 7) v.front() = 5000.0f;
      if (n > 0 && round == 8) v.back() = -5000.0f;
      float lo = inf, hi = -inf;
      std::size_t bad = 0, nan = 0;
      for (float x : v) {
        if (!std::isfinite(x)) {
          ++bad;
          nan += std::isnan(x) ? 1 : 0;
          continue;
        }
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
      const gdm::ValueRange r = gdm::value_range(v.data(), v.size());
      EXPECT_EQ(r.min, lo) << n;
      EXPECT_EQ(r.max, hi) << n;
      EXPECT_EQ(r.non_finite, bad) << n;
      EXPECT_EQ(r.nan, nan) << n;
    }
  const Volume v({3, 3, 3}, std::vector<float>{-2.5f, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 9.0f});
  EXPECT_EQ(v.min_value(), -2.5);
  EXPECT_EQ(v.max_value(), 9.0);
}

namespace {

// A 40^3 volume: a linear ramp (no residual about the 6-neighbour mean) plus
// Gaussian noise of the given sigma, from a fixed seed.
Volume ramp_with_noise(double sigma, unsigned seed) {
  const Index3 dims{40, 40, 40};
  std::vector<float> values(40 * 40 * 40);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma > 0.0 ? sigma : 1.0);
  std::size_t n = 0;
  for (int k = 0; k < 40; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 40; ++i)
        values[n++] = static_cast<float>(100.0 + 2.0 * i - 1.5 * j + 0.5 * k + (sigma > 0.0 ? noise(rng) : 0.0));
  return Volume(dims, std::move(values), Vec3(0.5, 0.5, 2.0));
}

}  // namespace

TEST(VoxelNoise, reads_the_sigma_of_gaussian_noise_over_a_trend) {
  for (const double sigma : {3.0, 7.5, 15.0}) {
    const double estimate = gdm::estimate_voxel_noise(ramp_with_noise(sigma, 11u));
    EXPECT_NEAR(estimate / sigma, 1.0, 0.06) << "sigma " << sigma;
  }
}

TEST(VoxelNoise, is_zero_without_noise) {
  EXPECT_NEAR(gdm::estimate_voxel_noise(ramp_with_noise(0.0, 1u)), 0.0, 1e-4);
  EXPECT_EQ(gdm::estimate_voxel_noise(Volume({2, 5, 5}, std::vector<float>(50, 1.0f))), 0.0);
}

TEST(VoxelNoise, a_box_reads_the_same_voxels_in_any_crop_that_holds_it) {
  // The noise over a physical box is a property of the voxels in it: a crop
  // of the volume around the box (origin moved with it) gives the same value.
  const Volume whole = ramp_with_noise(6.0, 3u);
  const Index3 crop_dims{30, 28, 26};
  const int di = 4, dj = 7, dk = 9;
  std::vector<float> values;
  for (int k = 0; k < crop_dims[2]; ++k)
    for (int j = 0; j < crop_dims[1]; ++j)
      for (int i = 0; i < crop_dims[0]; ++i) values.push_back(whole.at(i + di, j + dj, k + dk));
  const Volume crop(crop_dims, std::move(values), whole.spacing(), whole.to_physical(Vec3(di, dj, dk)));
  const Vec3 lo = whole.to_physical(Vec3(8.3, 10.6, 12.2)), hi = whole.to_physical(Vec3(25.4, 29.1, 30.7));
  const double a = gdm::estimate_voxel_noise(whole, lo, hi);
  EXPECT_NEAR(a / 6.0, 1.0, 0.1);
  EXPECT_EQ(gdm::estimate_voxel_noise(crop, lo, hi), a);
  // A box outside the grid holds no voxel.
  EXPECT_EQ(gdm::estimate_voxel_noise(whole, Vec3::Constant(-50.0), Vec3::Constant(-40.0)), 0.0);
}
