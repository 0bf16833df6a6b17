// Seeds from the image (issue 12): the automatic seed, the shrink-mode box
// and the checks of a user's seed mesh, on generated inputs.
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/phantoms.h"
#include "gdm/seed.h"
#include "gdm/seeding.h"

using gdm::Index3;
using gdm::Mesh;
using gdm::Polarity;
using gdm::Vec3;
using gdm::Volume;
namespace ph = gdm::phantoms;

namespace {

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const gdm::Error& e) {
    return e.what();
  }
  return "";
}

// The same vertices with every face's order swapped (optionally dropping faces
// from `drop` on, or transforming the points).
Mesh rebuilt(const Mesh& in, bool swap, std::size_t keep_faces = ~std::size_t{0},
             const std::function<Vec3(const Vec3&)>& move = nullptr) {
  Mesh out;
  std::vector<Mesh::VertexHandle> h;
  for (auto v : in.vertices()) {
    const Vec3 p = gdm::to_eigen(in.point(v));
    h.push_back(out.add_vertex(gdm::to_point(move ? move(p) : p)));
  }
  std::size_t n = 0;
  for (auto f : in.faces()) {
    if (n++ >= keep_faces) break;
    std::vector<Mesh::VertexHandle> fv;
    for (auto v : in.fv_range(f)) fv.push_back(h[static_cast<std::size_t>(v.idx())]);
    if (swap) std::swap(fv[1], fv[2]);
    out.add_face(fv);
  }
  return out;
}

// Both meshes' faces in one mesh (separate vertices).
Mesh merged(const Mesh& a, const Mesh& b) {
  Mesh out = rebuilt(a, false);
  std::vector<Mesh::VertexHandle> h;
  for (auto v : b.vertices()) h.push_back(out.add_vertex(b.point(v)));
  for (auto f : b.faces()) {
    std::vector<Mesh::VertexHandle> fv;
    for (auto v : b.fv_range(f)) fv.push_back(h[static_cast<std::size_t>(v.idx())]);
    out.add_face(fv);
  }
  return out;
}

}  // namespace

TEST(AutoSeed, sphere_phantom_seed_is_at_the_centre_with_depth_near_the_radius) {
  for (const Vec3& spacing : {Vec3(1, 1, 1), Vec3(0.8, 1.0, 1.25)}) {
    ph::Grid grid;
    grid.dims = {41, 41, 41};
    grid.spacing = spacing;
    grid.origin = Vec3(-3, 5, 2);
    const Vec3 c = grid.center();  // a voxel centre (odd dimensions)
    const double r = 12.3;  // no voxel centre on the sphere
    const Volume v = ph::voxelize(grid, ph::sphere(c, r));
    const gdm::AutoSeed s = gdm::find_auto_seed(v, 125.0, Polarity::object_brighter);
    EXPECT_EQ(s.index, (Index3{20, 20, 20})) << spacing.transpose();
    EXPECT_LT((s.center - c).norm(), 1e-9);
    // The distance is measured to the region's contour voxels (those with an
    // outside voxel among their 26 neighbours, as ITK's Maurer map): within a
    // voxel diagonal inside the sphere.
    EXPECT_LT(s.depth, r);
    EXPECT_GT(s.depth, r - std::sqrt(3.0) * spacing.maxCoeff());
    EXPECT_DOUBLE_EQ(s.radius, 0.5 * s.depth);
    EXPECT_EQ(s.regions, 1u);
    EXPECT_NEAR(static_cast<double>(s.region_voxels) * spacing.prod(), 4.0 / 3.0 * M_PI * r * r * r,
                0.05 * 4.0 / 3.0 * M_PI * r * r * r);
  }
}

TEST(AutoSeed, object_darker_takes_the_dark_side) {
  ph::Grid grid;
  grid.dims = {31, 31, 31};
  const Vec3 c = grid.center();
  // A dark ball (50) in a bright background (200).
  const Volume v = ph::voxelize(grid, ph::sphere(c, 9.2), 200.0, -150.0);
  const gdm::AutoSeed s = gdm::find_auto_seed(v, 125.0, Polarity::object_darker);
  EXPECT_EQ(s.index, (Index3{15, 15, 15}));
  EXPECT_LT(s.depth, 9.2);
  EXPECT_GT(s.depth, 9.2 - std::sqrt(3.0));
  EXPECT_EQ(s.regions, 1u);
}

TEST(AutoSeed, of_two_blobs_picks_the_larger) {
  ph::Grid grid;
  grid.dims = {60, 40, 40};
  const Vec3 small(12, 20, 20), large(40, 20, 20);
  const Volume v = ph::voxelize(grid, ph::unite({ph::sphere(small, 6.0), ph::sphere(large, 10.2)}));
  const gdm::AutoSeed s = gdm::find_auto_seed(v, 125.0, Polarity::object_brighter);
  EXPECT_EQ(s.regions, 2u);
  EXPECT_LT((s.center - large).norm(), 1.0);
  EXPECT_LT(s.depth, 10.2);
  EXPECT_GT(s.depth, 10.2 - std::sqrt(3.0));
  const double large_volume = 4.0 / 3.0 * M_PI * std::pow(10.2, 3);
  EXPECT_NEAR(static_cast<double>(s.region_voxels), large_volume, 0.05 * large_volume);
}

TEST(AutoSeed, on_a_concave_c_shape_lands_inside) {
  ph::Grid grid;
  grid.dims = {48, 48, 24};
  const Vec3 c = grid.center();
  const ph::Sdf shape = ph::bent_tube(c, 14.0, 5.0, 1.5 * M_PI);
  const Volume v = ph::voxelize(grid, shape);
  const gdm::AutoSeed s = gdm::find_auto_seed(v, 125.0, Polarity::object_brighter);
  EXPECT_GT((s.center - c).norm(), 8.0);  // not at the C's empty centre
  EXPECT_LT(shape(s.center), -3.0);       // well inside the tube
  EXPECT_GT(v.sample(s.center), 125.0);
  EXPECT_LT(s.depth, 5.0);
  EXPECT_GT(s.depth, 5.0 - 2.0);
}

TEST(AutoSeed, counts_the_volume_border_as_boundary) {
  // Everything is object: the deepest voxel is the middle of the grid.
  const Volume v({9, 7, 5}, std::vector<float>(9 * 7 * 5, 300.0f), Vec3(1, 1, 2));
  const gdm::AutoSeed s = gdm::find_auto_seed(v, 100.0, Polarity::object_brighter);
  EXPECT_EQ(s.region_voxels, 9u * 7 * 5);
  // Border distances (idx + 0.5) * spacing: x 4.5, y 3.5, z 2.5 * 2 = 5; the first
  // voxel in raster order with depth 3.5 (z index 2: min(2, 2) + 0.5 = 2.5 voxels).
  EXPECT_DOUBLE_EQ(s.depth, 3.5);
  EXPECT_EQ(s.index, (Index3{3, 3, 2}));
}

TEST(AutoSeed, throws_when_nothing_is_on_the_object_side) {
  ph::Grid grid;
  grid.dims = {16, 16, 16};
  const Volume v = ph::voxelize(grid, ph::sphere(grid.center(), 4.0));
  EXPECT_THROW(gdm::find_auto_seed(v, 500.0, Polarity::object_brighter), gdm::InvalidSeed);
  EXPECT_THROW(gdm::find_auto_seed(v, 10.0, Polarity::object_darker), gdm::InvalidSeed);
  EXPECT_NE(message_of([&] { gdm::find_auto_seed(v, 500.0, Polarity::object_brighter); }).find("above"),
            std::string::npos);
  EXPECT_THROW(gdm::find_auto_seed(v, std::nan(""), Polarity::object_brighter), gdm::InvalidOption);
  // Strictly beyond T: the maximum itself is not above it.
  EXPECT_THROW(gdm::find_auto_seed(v, v.max_value(), Polarity::object_brighter), gdm::InvalidSeed);
}

TEST(AutoSeed, a_region_without_interior_voxels_is_refused) {
  // A one-voxel-thick plane: every region voxel is on its contour.
  const Index3 dims{10, 10, 10};
  std::vector<float> values(1000, 0.0f);
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < 10; ++i) values[static_cast<std::size_t>(i + 10 * j + 100 * 5)] = 100.0f;
  const Volume v(dims, values);
  EXPECT_THROW(gdm::find_auto_seed(v, 50.0, Polarity::object_brighter), gdm::InvalidSeed);
}

TEST(VolumeBox, is_closed_outward_and_inset) {
  const Volume v({11, 9, 7}, std::vector<float>(11 * 9 * 7, 1.0f), Vec3(0.5, 1.0, 2.0), Vec3(1, 2, 3));
  const Mesh box = gdm::make_volume_box(v);
  EXPECT_EQ(box.n_faces(), 12u);
  EXPECT_TRUE(gdm::is_closed(box));
  EXPECT_TRUE(gdm::is_two_manifold(box));
  EXPECT_NEAR(gdm::enclosed_volume(box), (8 * 0.5) * (6 * 1.0) * (4 * 2.0), 1e-9);
  const Mesh half = gdm::make_volume_box(v, 0.5);
  EXPECT_NEAR(gdm::enclosed_volume(half), (9 * 0.5) * (7 * 1.0) * (5 * 2.0), 1e-9);
  EXPECT_THROW(gdm::make_volume_box(v, 3.0), gdm::InvalidOption);  // z: 2 * 3 >= 6
  EXPECT_THROW(gdm::make_volume_box(v, -1.0), gdm::InvalidOption);
}

TEST(VolumeBox, stays_outward_with_a_mirroring_direction) {
  Eigen::Matrix3d mirror = Eigen::Matrix3d::Identity();
  mirror(0, 0) = -1.0;
  Eigen::Matrix3d rotated_mirror;  // a rotation about z times a mirror of y
  rotated_mirror << 0, 1, 0, 1, 0, 0, 0, 0, 1;
  for (const Eigen::Matrix3d& dir : {mirror, rotated_mirror}) {
    ASSERT_LT(dir.determinant(), 0.0);
    const Volume v({6, 6, 6}, std::vector<float>(216, 1.0f), Vec3(1, 2, 3), Vec3(-4, 0, 9), dir);
    const Mesh box = gdm::make_volume_box(v);
    EXPECT_TRUE(gdm::is_closed(box));
    EXPECT_NEAR(gdm::enclosed_volume(box), 3.0 * 6.0 * 9.0, 1e-9);
    // Corners one voxel inside the border.
    Vec3 lo, hi;
    v.physical_bounds(lo, hi);
    for (auto vh : box.vertices()) {
      const Vec3 p = gdm::to_eigen(box.point(vh));
      EXPECT_TRUE(v.contains(p, 0.999));
    }
  }
}

TEST(PrepareSeedMesh, keeps_an_outward_mesh) {
  const Mesh ico = gdm::make_icosahedron(Vec3(1, 2, 3), 2.0);
  bool reversed = true;
  const Mesh out = gdm::prepare_seed_mesh(ico, &reversed);
  EXPECT_FALSE(reversed);
  EXPECT_DOUBLE_EQ(gdm::enclosed_volume(out), gdm::enclosed_volume(ico));
}

TEST(PrepareSeedMesh, reverses_an_inward_icosahedron) {
  const Mesh ico = gdm::make_icosahedron(Vec3(1, 2, 3), 2.0);
  const Mesh inward = rebuilt(ico, true);
  ASSERT_LT(gdm::enclosed_volume(inward), 0.0);
  bool reversed = false;
  const Mesh out = gdm::prepare_seed_mesh(inward, &reversed);
  EXPECT_TRUE(reversed);
  EXPECT_NEAR(gdm::enclosed_volume(out), gdm::enclosed_volume(ico), 1e-12);
  EXPECT_EQ(out.n_vertices(), ico.n_vertices());
  EXPECT_EQ(out.n_faces(), ico.n_faces());
  EXPECT_TRUE(gdm::is_closed(out));
  EXPECT_NO_THROW(gdm::prepare_seed_mesh(inward));  // `reversed` is optional
}

TEST(PrepareSeedMesh, refuses_an_open_mesh) {
  const Mesh open = rebuilt(gdm::make_icosahedron(Vec3::Zero(), 1.0), false, 19);
  EXPECT_THROW(gdm::prepare_seed_mesh(open), gdm::InvalidSeed);
  EXPECT_NE(message_of([&] { gdm::prepare_seed_mesh(open); }).find("closed"), std::string::npos);
  EXPECT_THROW(gdm::prepare_seed_mesh(Mesh()), gdm::InvalidSeed);
}

TEST(PrepareSeedMesh, refuses_a_self_intersecting_mesh) {
  const Mesh two = merged(gdm::make_icosahedron(Vec3::Zero(), 1.0), gdm::make_icosahedron(Vec3(0.6, 0.1, 0.05), 1.0));
  const std::string m = message_of([&] { gdm::prepare_seed_mesh(two); });
  EXPECT_NE(m.find("the seed mesh intersects itself: "), std::string::npos) << m;
  EXPECT_NE(m.find("face pairs"), std::string::npos) << m;
  EXPECT_THROW(gdm::prepare_seed_mesh(two), gdm::InvalidSeed);
}

TEST(PrepareSeedMesh, refuses_a_flat_mesh) {
  const Mesh ico = gdm::make_icosahedron(Vec3::Zero(), 1.0);
  for (double z : {0.0, 3.0}) {
    const Mesh flat = rebuilt(ico, false, ~std::size_t{0}, [z](const Vec3& p) { return Vec3(p.x(), p.y(), z); });
    const std::string m = message_of([&] { gdm::prepare_seed_mesh(flat); });
    EXPECT_NE(m.find("encloses no volume"), std::string::npos) << m;
    EXPECT_THROW(gdm::prepare_seed_mesh(flat), gdm::InvalidSeed);
  }
}

TEST(PrepareSeedMesh, refuses_a_nan_vertex) {
  Mesh ico = gdm::make_icosahedron(Vec3::Zero(), 1.0);
  ico.set_point(Mesh::VertexHandle(3), Mesh::Point(NAN, 0, 0));
  EXPECT_THROW(gdm::prepare_seed_mesh(ico), gdm::InvalidSeed);
  EXPECT_NE(message_of([&] { gdm::prepare_seed_mesh(ico); }).find("finite"), std::string::npos);
}
