// gdm::shrink_wrap (gdm/shrink_wrap.h) on generated inputs: several pieces, a
// holed sphere, a point cloud; its guarantees and its refusals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/obstacle.h"
#include "gdm/seed.h"
#include "gdm/shrink_wrap.h"
#include "gdm/triangle_locator.h"

namespace {


std::vector<gdm::Triangle> sphere_soup(const gdm::Vec3& centre, double radius, int level) {
  return gdm::triangles_of(gdm::make_geodesic_sphere(centre, radius, level));
}

// The guarantees of a wrap of `input` with tolerance `tolerance`.
void expect_valid_wrap(const std::vector<gdm::Triangle>& input, const gdm::WrapResult& r, double tolerance) {
  const gdm::MeshReport m = gdm::measure(r.mesh);
  EXPECT_TRUE(m.closed);
  EXPECT_TRUE(m.two_manifold);
  EXPECT_EQ(m.genus, 0);
  EXPECT_EQ(m.components, 1);
  EXPECT_EQ(m.self_intersections, 0u);
  const std::vector<gdm::Triangle> wrap = gdm::triangles_of(r.mesh);
  const gdm::TriangleLocator to_wrap(wrap);
  double farthest = 0.0;
  for (const auto& t : input)
    for (const auto& p : t) farthest = std::max(farthest, to_wrap.distance(p));
  EXPECT_LE(farthest, tolerance);
  EXPECT_NEAR(farthest, r.farthest_input_distance, 1e-9);
  const gdm::Obstacle obstacle(input);
  std::size_t touching = 0;
  for (const auto& t : wrap) touching += obstacle.blocks(t) ? 1 : 0;
  EXPECT_EQ(touching, 0u) << "wrap faces touching the input";
}

gdm::WrapOptions options(double cell, double tolerance) {
  gdm::WrapOptions o;
  o.cell_size = cell;
  o.tolerance = tolerance;
  return o;
}

TEST(ShrinkWrap, two_separate_spheres_get_one_wrap) {
  std::vector<gdm::Triangle> input = sphere_soup(gdm::Vec3(0, 0, 0), 4.0, 2);
  const auto second = sphere_soup(gdm::Vec3(11.0, 1.0, -2.0), 4.0, 2);
  input.insert(input.end(), second.begin(), second.end());
  const gdm::WrapResult r = gdm::shrink_wrap(input, options(0.5, 1.5));
  expect_valid_wrap(input, r, 1.5);
  EXPECT_FALSE(r.notes.empty());
}

TEST(ShrinkWrap, holed_sphere_is_closed) {
  gdm::Mesh sphere = gdm::make_geodesic_sphere(gdm::Vec3(3, -2, 1), 6.0, 3);
  std::vector<gdm::Triangle> input;
  for (const auto& t : gdm::triangles_of(sphere))
    if ((t[0] + t[1] + t[2]).z() / 3.0 < 1.0 + 4.5) input.push_back(t);  // the cap above z = 5.5 removed
  ASSERT_LT(input.size(), sphere.n_faces());
  const gdm::WrapResult r = gdm::shrink_wrap(input, options(0.5, 1.5));
  expect_valid_wrap(input, r, 1.5);
}

TEST(ShrinkWrap, point_cloud_of_degenerate_triangles) {
  // Points about 0.7 mm apart: closer than twice the wrap's offset (tolerance / 3).
  const gdm::Mesh sphere = gdm::make_geodesic_sphere(gdm::Vec3(0, 0, 0), 5.0, 3);
  std::vector<gdm::Triangle> input;
  for (auto v : sphere.vertices()) {
    const gdm::Vec3 p = gdm::to_eigen(sphere.point(v));
    input.push_back({p, p, p});
  }
  const gdm::WrapResult r = gdm::shrink_wrap(input, options(0.5, 1.5));
  expect_valid_wrap(input, r, 1.5);
}

TEST(ShrinkWrap, same_wrap_for_any_thread_count) {
  const auto input = sphere_soup(gdm::Vec3(0, 0, 0), 4.0, 2);
  gdm::WrapOptions one = options(0.5, 1.5), two = one;
  one.threads = 1;
  two.threads = 2;
  const gdm::WrapResult a = gdm::shrink_wrap(input, one), b = gdm::shrink_wrap(input, two);
  ASSERT_EQ(a.mesh.n_vertices(), b.mesh.n_vertices());
  for (std::size_t i = 0; i < a.mesh.n_vertices(); ++i)
    EXPECT_EQ(a.mesh.point(gdm::Mesh::VertexHandle(static_cast<int>(i))),
              b.mesh.point(gdm::Mesh::VertexHandle(static_cast<int>(i))));
}

void expect_refused(const std::vector<gdm::Triangle>& input, const gdm::WrapOptions& o, const std::string& names) {
  try {
    gdm::shrink_wrap(input, o);
    ADD_FAILURE() << "accepted; expected a refusal naming " << names;
  } catch (const gdm::InvalidOption& e) {
    EXPECT_NE(std::string(e.what()).find(names), std::string::npos) << e.what();
  }
}

TEST(ShrinkWrap, bad_options_are_refused) {
  const auto input = sphere_soup(gdm::Vec3(0, 0, 0), 4.0, 1);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  gdm::WrapOptions o = options(0.5, 1.5);
  o.tolerance = 0.0;
  expect_refused(input, o, "tolerance must be > 0");
  o.tolerance = -1.0;
  expect_refused(input, o, "tolerance must be > 0");
  o.tolerance = nan;
  expect_refused(input, o, "tolerance must be > 0");
  o = options(0.0, 1.5);
  expect_refused(input, o, "cell_size must be > 0");
  o = options(2.0, 1.5);
  expect_refused(input, o, "must be >= cell_size");
  o = options(0.5, 1.5);
  o.coverage_rounds = -1;
  expect_refused(input, o, "coverage_rounds");
  o = options(0.5, 1.5);
  o.max_cycles = 0;
  expect_refused(input, o, "max_cycles");
  o = options(0.5, 1.5);
  o.lod_face_area = -3;
  expect_refused(input, o, "lod_face_area");
  o = options(0.5, 1.5);
  o.threads = -2;
  expect_refused(input, o, "threads");
  expect_refused({}, options(0.5, 1.5), "empty");
  auto broken = input;
  broken[3][1].x() = nan;
  expect_refused(broken, options(0.5, 1.5), "non-finite");
}

}  // namespace
