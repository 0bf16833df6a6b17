#include <cmath>

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
