// The width of the room a refined vertex is in (channel_width.h): measured on
// noisy phantoms built here (5 % of the contrast), distances in voxels.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "gdm/channel_width.h"
#include "gdm/cost_terms.h"
#include "gdm/phantoms.h"

namespace gdm {
namespace {

namespace ph = phantoms;

constexpr double kLow = 50.0, kHigh = 200.0, kThreshold = 125.0;

ImageEvent grow_bright(const Volume& v) {
  return ImageEvent(1.0, v, kThreshold, Polarity::object_brighter, Mode::grow, 0.01 * (kHigh - kLow));
}

ChannelWidthOptions options() {
  ChannelWidthOptions o;
  o.cap = 8.0;
  return o;
}

TEST(ChannelWidth, a_slab_is_as_wide_as_it_is_thick_from_its_wall_and_from_inside) {
  for (const double thickness : {3.0, 4.0, 6.0}) {
    ph::Grid grid;
    grid.dims = {40, 40, 40};
    const Vec3 c = grid.center();
    const Volume v = ph::with_gaussian_noise(
        ph::voxelize(grid, ph::box(c - Vec3(30, 30, 0.5 * thickness), c + Vec3(30, 30, 0.5 * thickness)), kLow, kHigh - kLow),
        0.05 * (kHigh - kLow), 7u);
    const ImageEvent image = grow_bright(v);
    // A vertex on the upper wall, facing out of the slab (blocked ahead):
    // the room behind it.
    const Vec3 wall = c + Vec3(0.3, -0.2, 0.5 * thickness - 0.2);
    EXPECT_NEAR(room_width(image, wall, Vec3::UnitZ(), options()), thickness, 1.0) << "thickness " << thickness;
    // A vertex entering the slab from below its middle, facing along it: the
    // room ahead.
    EXPECT_NEAR(room_width(image, c + Vec3(0.2, 0.1, 0.3), Vec3::UnitX(), options()), thickness, 1.0)
        << "thickness " << thickness;
    EXPECT_NEAR(narrowest_chord(image, c + Vec3(0.2, 0.1, 0.3), options()), thickness, 1.0);
  }
}

TEST(ChannelWidth, a_round_channel_is_as_wide_as_its_diameter_and_an_open_room_reaches_the_cap) {
  ph::Grid grid;
  grid.dims = {48, 48, 48};
  const Vec3 c = grid.center();
  for (const double radius : {1.0, 1.5, 2.0}) {
    const ph::Sdf shape = ph::unite({ph::sphere(c, 10.0), ph::capsule(c, c + Vec3(20, 0, 0), radius)});
    const Volume v = ph::with_gaussian_noise(ph::voxelize(grid, shape, kLow, kHigh - kLow), 0.05 * (kHigh - kLow), 11u);
    const ImageEvent image = grow_bright(v);
    // A vertex in the channel's mouth looking in, one on its wall.
    EXPECT_NEAR(room_width(image, c + Vec3(10.5, 0.2, 0.0), Vec3::UnitX(), options()), 2.0 * radius, 1.0) << "radius " << radius;
    EXPECT_NEAR(room_width(image, c + Vec3(15.0, 0.0, radius - 0.2), Vec3::UnitZ(), options()), 2.0 * radius, 1.0)
        << "radius " << radius;
    // In the chamber, the level of detail's faces fit.
    EXPECT_DOUBLE_EQ(narrowest_chord(image, c, options()), options().cap);
    // Inside the wall, no room.
    EXPECT_EQ(narrowest_chord(image, c + Vec3(0, 0, 14), options()), 0.0);
  }
}

// free_room_reaches tells a channel from a speck: from the wall of a ball
// (the model's front half a voxel out of it, facing out), a channel two
// voxels wide leaving the ball (two 2 mm slices across on the 1x1x2 mm grid)
// reaches three voxels ahead, tilted by 30 degrees too; a bright speck of one and of two voxels just outside the
// wall, and the plain background, do not. On a 1x1x2 mm grid too.
TEST(ChannelWidth, free_room_reaches_through_a_channel_not_through_a_speck) {
  for (const double z_spacing : {1.0, 2.0}) {
    ph::Grid grid;
    grid.dims = {40, 40, z_spacing > 1.0 ? 20 : 40};
    grid.spacing = Vec3(1.0, 1.0, z_spacing);
    const Vec3 c = grid.center();
    const Vec3 out = Vec3::UnitX();
    const ph::Sdf shape = ph::unite({ph::sphere(c, 8.0), ph::capsule(c, c + 18.0 * out, z_spacing),
                                     ph::sphere(c + Vec3(0, 9.0, 0), 0.7), ph::sphere(c + Vec3(0, -9.3, 0), 1.2)});
    const Volume v = ph::with_gaussian_noise(ph::voxelize(grid, shape, kLow, kHigh - kLow), 0.05 * (kHigh - kLow), 13u);
    const ImageEvent image = grow_bright(v);
    const std::string grid_name = "z spacing " + std::to_string(z_spacing);
    // Into the channel, straight and tilted (the front of a model whose faces
    // lean on the channel's sides).
    const Vec3 mouth = c + 8.5 * out;
    EXPECT_TRUE(free_room_reaches(image, mouth, out, 3.0, grid.spacing)) << grid_name;
    const Vec3 tilted = (out + std::tan(M_PI / 6.0) * Vec3::UnitY()).normalized();
    EXPECT_TRUE(free_room_reaches(image, mouth, tilted, 3.0, grid.spacing)) << grid_name;
    // Specks of one and two voxels beyond the wall, and the background.
    EXPECT_FALSE(free_room_reaches(image, c + Vec3(0, 8.8, 0), Vec3::UnitY(), 3.0, grid.spacing)) << grid_name;
    EXPECT_FALSE(free_room_reaches(image, c + Vec3(0, -8.8, 0), -Vec3::UnitY(), 3.0, grid.spacing)) << grid_name;
    EXPECT_FALSE(free_room_reaches(image, c + Vec3(0, 0, 12.0), Vec3::UnitZ(), 3.0, grid.spacing)) << grid_name;
  }
}

TEST(ChannelWidth, face_area_grows_with_the_width_between_the_finest_and_the_level_of_detail) {
  const ChannelWidthOptions o = options();
  double last = 0.0;
  for (double w = 0.0; w <= 10.0; w += 0.5) {
    const double a = area_for_width(w, o, 0.5, 10.0);
    EXPECT_GE(a, last);
    EXPECT_GE(a, 0.5);
    EXPECT_LE(a, 10.0);
    last = a;
  }
  EXPECT_EQ(area_for_width(0.0, o, 0.5, 10.0), 0.5);
  EXPECT_EQ(area_for_width(o.cap * 2.0, o, 0.5, 10.0), 10.0);
  // A channel two voxels wide: faces small enough to enter it (edge below its width).
  EXPECT_LT(std::sqrt(4.0 * area_for_width(2.0, o, 0.5, 10.0) / std::sqrt(3.0)), 2.0);
}

}  // namespace
}  // namespace gdm
