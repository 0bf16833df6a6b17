// The pipeline's volume operations (issue 12): region of interest, Gaussian
// smoothing and Otsu's threshold, on generated volumes.
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gdm/errors.h"
#include "gdm/volume_ops.h"

using gdm::Index3;
using gdm::Vec3;
using gdm::Volume;
using gdm::VoxelBox;

namespace {

Volume filled(Index3 dims, const std::function<float(int, int, int)>& f, Vec3 spacing = Vec3::Ones(),
              Vec3 origin = Vec3::Zero(), Eigen::Matrix3d direction = Eigen::Matrix3d::Identity()) {
  std::vector<float> values;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) values.push_back(f(i, j, k));
  return Volume(dims, std::move(values), spacing, origin, direction);
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const gdm::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(PipelineCrop, keeps_physical_positions_and_values) {
  Eigen::Matrix3d rot;  // 90 degrees about z
  rot << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  const Volume v = filled({7, 6, 5}, [](int i, int j, int k) { return float(i + 10 * j + 100 * k); },
                          Vec3(0.5, 2.0, 1.5), Vec3(3, -1, 7), rot);
  const VoxelBox box{{2, 1, 1}, {5, 4, 2}};
  const Volume c = gdm::crop(v, box);
  ASSERT_EQ(c.dims(), (Index3{4, 4, 2}));
  EXPECT_EQ(c.spacing(), v.spacing());
  EXPECT_EQ(c.direction(), v.direction());
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(c.at(i, j, k), v.at(i + 2, j + 1, k + 1));
        const Vec3 p = c.to_physical(Vec3(i, j, k));
        EXPECT_TRUE(p.isApprox(v.to_physical(Vec3(i + 2, j + 1, k + 1)), 1e-12));
        EXPECT_DOUBLE_EQ(c.sample(p), v.sample(p));
      }
}

TEST(PipelineCrop, the_whole_volume_is_a_copy) {
  const Volume v = filled({4, 3, 2}, [](int i, int j, int k) { return float(i * j - k); });
  const Volume c = gdm::crop(v, {{0, 0, 0}, {3, 2, 1}});
  EXPECT_EQ(c.values(), v.values());
  EXPECT_EQ(c.origin(), v.origin());
}

TEST(PipelineCrop, refuses_boxes_outside_the_volume_or_too_thin) {
  const Volume v = filled({6, 6, 6}, [](int i, int, int) { return float(i); });
  for (const VoxelBox& bad : {VoxelBox{{-1, 0, 0}, {3, 3, 3}}, VoxelBox{{0, 0, 0}, {6, 3, 3}},
                              VoxelBox{{3, 0, 0}, {2, 3, 3}}, VoxelBox{{0, 2, 0}, {3, 2, 3}}}) {
    EXPECT_THROW(gdm::crop(v, bad), gdm::InvalidOption);
    EXPECT_NE(message_of([&] { gdm::crop(v, bad); }).find("roi"), std::string::npos);
  }
}

TEST(PipelineGaussian, preserves_a_constant) {
  const Volume v = filled({9, 8, 7}, [](int, int, int) { return 42.5f; }, Vec3(0.5, 1.0, 2.0));
  const Volume s = gdm::gaussian_smooth(v, 1.5);
  for (float x : s.values()) EXPECT_NEAR(x, 42.5f, 1e-4);
  EXPECT_EQ(s.spacing(), v.spacing());
  EXPECT_EQ(s.origin(), v.origin());
}

TEST(PipelineGaussian, zero_sigma_is_a_copy) {
  const Volume v = filled({5, 5, 5}, [](int i, int j, int k) { return float(i * i + j - 3 * k); });
  EXPECT_EQ(gdm::gaussian_smooth(v, 0.0).values(), v.values());
}

TEST(PipelineGaussian, preserves_the_mean_away_from_the_borders) {
  // Noise in the middle, zero within 4 sigma of every border: no mass is lost.
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(10.0f, 5.0f);
  const Index3 dims{40, 36, 30};
  const Vec3 spacing(0.5, 0.75, 1.0);
  const double sigma = 1.0;
  const Volume v = filled(dims, [&](int i, int j, int k) {
    const bool inside = i >= 9 && i < 31 && j >= 7 && j < 29 && k >= 5 && k < 25;
    return inside ? noise(rng) : 0.0f;
  }, spacing);
  const Volume s = gdm::gaussian_smooth(v, sigma);
  const double before = std::accumulate(v.values().begin(), v.values().end(), 0.0);
  const double after = std::accumulate(s.values().begin(), s.values().end(), 0.0);
  EXPECT_NEAR(after, before, 1e-5 * std::abs(before));
  // ... and it smooths: the noise's variance in the middle drops.
  double var_v = 0.0, var_s = 0.0;
  for (int k = 12; k < 18; ++k)
    for (int j = 14; j < 22; ++j)
      for (int i = 16; i < 24; ++i) {
        var_v += (v.at(i, j, k) - 10.0) * (v.at(i, j, k) - 10.0);
        var_s += (s.at(i, j, k) - 10.0) * (s.at(i, j, k) - 10.0);
      }
  EXPECT_LT(var_s, 0.2 * var_v);
}

TEST(PipelineGaussian, matches_the_analytic_blur_of_a_step_edge_at_anisotropic_spacings) {
  const double sigma = 2.0;  // mm
  for (const Vec3& spacing : {Vec3(0.5, 1.0, 2.0), Vec3(1.5, 0.7, 1.0)}) {
    for (int axis = 0; axis < 3; ++axis) {
      Index3 dims{6, 6, 6};
      dims[axis] = 48;
      const Volume v = filled(dims, [&](int i, int j, int k) {
        const int idx[3] = {i, j, k};
        return idx[axis] >= 24 ? 1.0f : 0.0f;
      }, spacing);
      const Volume s = gdm::gaussian_smooth(v, sigma);
      const double edge = 23.5 * spacing[axis];
      const double h = spacing[axis], sigma_voxels = sigma / h;
      // A sampled step blurred by a sampled Gaussian is the continuous step's
      // blur with the variance sigma^2 - h^2 / 12 (Euler-Maclaurin): compare
      // with that closely, and with the plain erf within the second-order
      // term max|g'| / 24 = 0.0101 / sigma_voxels^2.
      const double sigma_sampled = std::sqrt(sigma * sigma - h * h / 12.0);
      double worst = 0.0, worst_sampled = 0.0;
      for (int n = 0; n < dims[axis]; ++n) {
        Index3 at{3, 3, 3};
        at[axis] = n;
        const double x = n * h - edge;
        const double value = s.at(at[0], at[1], at[2]);
        worst = std::max(worst, std::abs(value - 0.5 * (1.0 + std::erf(x / (std::sqrt(2.0) * sigma)))));
        worst_sampled =
            std::max(worst_sampled, std::abs(value - 0.5 * (1.0 + std::erf(x / (std::sqrt(2.0) * sigma_sampled)))));
      }
      EXPECT_LT(worst, 0.0105 / (sigma_voxels * sigma_voxels) + 2e-4) << "axis " << axis << " spacing " << spacing.transpose();
      EXPECT_LT(worst_sampled, 1e-3) << "axis " << axis << " spacing " << spacing.transpose();
    }
  }
}

TEST(PipelineGaussian, refuses_a_negative_or_nan_sigma) {
  const Volume v = filled({4, 4, 4}, [](int i, int, int) { return float(i); });
  for (double bad : {-1.0, std::nan(""), double(INFINITY)}) {
    EXPECT_THROW(gdm::gaussian_smooth(v, bad), gdm::InvalidOption);
    EXPECT_NE(message_of([&] { gdm::gaussian_smooth(v, bad); }).find("smooth"), std::string::npos);
  }
}

TEST(PipelineOtsu, separates_a_two_level_noisy_volume_between_the_levels) {
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.0f, 12.0f);
  // A brighter block in a darker background, unequal class sizes.
  const Volume v = filled({30, 30, 30}, [&](int i, int j, int k) {
    const bool object = i >= 8 && i < 20 && j >= 5 && j < 25 && k >= 10 && k < 28;
    return (object ? 300.0f : 100.0f) + noise(rng);
  });
  const double t = gdm::otsu_threshold(v);
  // Two clusters with an empty gap: Otsu's first maximum lies just above the
  // lower cluster's last bin (ITK's choice too).
  EXPECT_GT(t, 100.0 + 2 * 12.0);
  EXPECT_LT(t, 300.0 - 2 * 12.0);
  // Every voxel is classified right.
  std::size_t wrong = 0;
  for (int k = 0; k < 30; ++k)
    for (int j = 0; j < 30; ++j)
      for (int i = 0; i < 30; ++i) {
        const bool object = i >= 8 && i < 20 && j >= 5 && j < 25 && k >= 10 && k < 28;
        wrong += (v.at(i, j, k) > t) != object;
      }
  EXPECT_EQ(wrong, 0u);
}

TEST(PipelineOtsu, returns_the_upper_edge_of_a_bin) {
  // Values 0 and 10 only: 256 bins over [0, 10 + 10/25600]; the lower class is
  // the first bin alone, so the threshold is that bin's upper edge.
  const Volume v = filled({4, 4, 4}, [](int i, int, int) { return i < 2 ? 0.0f : 10.0f; });
  const double t = gdm::otsu_threshold(v);
  const float interval = (static_cast<float>(10.0 + 10.0 / 256 / 100) - 0.0f) / 256.0f;
  EXPECT_EQ(t, static_cast<double>(static_cast<float>(interval)));
  EXPECT_GT(t, 0.0);
  EXPECT_LT(t, 10.0);
}

TEST(PipelineOtsu, refuses_a_constant_volume) {
  const Volume v = filled({4, 4, 4}, [](int, int, int) { return 5.0f; });
  EXPECT_THROW(gdm::otsu_threshold(v), gdm::InvalidVolume);
  EXPECT_NE(message_of([&] { gdm::otsu_threshold(v); }).find("constant"), std::string::npos);
}

// Issue 13, item 9: values near FLT_MAX overflowed ITK's float bin width (inf
// threshold); the threshold is finite and separates the two classes.
TEST(PipelineOtsu, values_near_float_max_give_a_finite_threshold_between_the_classes) {
  const float big = 3e38f;
  const auto inside = [](int i, int j, int k) { return i >= 2 && i < 6 && j >= 2 && j < 6 && k >= 2 && k < 6; };
  struct Case {
    const char* name;
    std::function<float(int, int, int)> value;
    float low, high;  // the two classes
  };
  const Case cases[] = {
      {"-3e38 and 3e38", [&](int i, int j, int k) { return inside(i, j, k) ? big : -big; }, -big, big},
      {"1e38 but one voxel", [](int i, int j, int k) { return i + j + k == 0 ? 0.0f : 1e38f; }, 0.0f, 1e38f},
      {"FLT_MAX but one voxel",
       [](int i, int j, int k) { return i + j + k == 0 ? 0.0f : std::numeric_limits<float>::max(); }, 0.0f,
       std::numeric_limits<float>::max()},
      {"-FLT_MAX and FLT_MAX",
       [&](int i, int j, int k) {
         return inside(i, j, k) ? std::numeric_limits<float>::max() : std::numeric_limits<float>::lowest();
       },
       std::numeric_limits<float>::lowest(), std::numeric_limits<float>::max()},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const Volume v = filled({8, 8, 8}, c.value);
    const double t = gdm::otsu_threshold(v);
    EXPECT_TRUE(std::isfinite(t)) << t;
    EXPECT_GE(t, static_cast<double>(c.low));
    EXPECT_LT(t, static_cast<double>(c.high));
    EXPECT_EQ(t, static_cast<double>(static_cast<float>(t))) << "a float, as ITK's";
  }
}

// Below the overflow the float bins (ITK's) are kept: the same threshold as a
// scaled copy of returns_the_upper_edge_of_a_bin.
TEST(PipelineOtsu, large_values_that_fit_keep_the_float_bins) {
  const Volume v = filled({4, 4, 4}, [](int i, int, int) { return i < 2 ? 0.0f : 1e37f; });
  const double t = gdm::otsu_threshold(v);
  const double hi = 1e37f;
  const double upper = hi + (hi / 256) / 100;
  const float interval = (static_cast<float>(upper) - 0.0f) / 256.0f;
  EXPECT_EQ(t, static_cast<double>(static_cast<float>(interval)));
}
