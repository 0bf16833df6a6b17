#include <gtest/gtest.h>

#include <cmath>

#include "gdm/deformer.h"
#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/obstacle.h"
#include "gdm/phantoms.h"
#include "gdm/seed.h"

using namespace gdm;
namespace ph = gdm::phantoms;

namespace {

// The winding number of a closed mesh around p (1 inside, 0 outside), from the
// solid angles of its faces (Van Oosterom and Strackee).
double winding_number(const Mesh& mesh, const Vec3& p) {
  double sum = 0.0;
  for (auto f : mesh.faces()) {
    Vec3 q[3];
    int k = 0;
    for (auto v : mesh.fv_range(f)) q[k++] = to_eigen(mesh.point(v)) - p;
    const double a = q[0].norm(), b = q[1].norm(), c = q[2].norm();
    const double num = q[0].dot(q[1].cross(q[2]));
    const double den = a * b * c + q[0].dot(q[1]) * c + q[0].dot(q[2]) * b + q[1].dot(q[2]) * a;
    sum += 2.0 * std::atan2(num, den);
  }
  return sum / (4.0 * M_PI);
}

std::size_t faces_touching(const Mesh& mesh, const Obstacle& obstacle) {
  std::size_t n = 0;
  for (auto f : mesh.faces()) {
    Obstacle::Triangle t;
    int k = 0;
    for (auto v : mesh.fv_range(f)) t[k++] = to_eigen(mesh.point(v));
    n += obstacle.blocks(t) ? 1 : 0;
  }
  return n;
}

}  // namespace

TEST(Obstacle, blocks_exactly_the_triangles_that_touch_it) {
  const Obstacle obstacle({{Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0)}});
  EXPECT_TRUE(obstacle.blocks({Vec3(1, 1, -1), Vec3(1, 1, 1), Vec3(2, 1, 1)}));      // pierces it
  EXPECT_TRUE(obstacle.blocks({Vec3(1, 1, 0), Vec3(1, 1, 1), Vec3(2, 1, 1)}));       // touches it at a corner
  EXPECT_FALSE(obstacle.blocks({Vec3(1, 1, 1e-9), Vec3(1, 1, 1), Vec3(2, 1, 1)}));   // just above
  EXPECT_FALSE(obstacle.blocks({Vec3(3, 3, -1), Vec3(3, 3, 1), Vec3(4, 3, 1)}));     // beside the hypotenuse
  // A point (a degenerate triangle) is an obstacle too.
  const Obstacle point({{Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)}});
  EXPECT_TRUE(point.blocks({Vec3(0, 0, 1), Vec3(3, 0, 1), Vec3(0, 3, 1)}));
  EXPECT_FALSE(point.blocks({Vec3(0, 0, 2), Vec3(3, 0, 2), Vec3(0, 3, 2)}));
}

TEST(Obstacle, a_shrinking_model_does_not_pass_through_a_thin_fin) {
  // A ball with a fin: a triangle far thinner than any face of the model,
  // reaching 6 voxels out of the ball. The image sees only the ball; the
  // obstacle keeps the fin inside the shrinking model.
  ph::Grid grid;
  grid.dims = {48, 48, 48};
  const Vec3 c = grid.center();
  const Volume volume = ph::voxelize(grid, ph::sphere(c, 10.0));
  const Vec3 tip = c + Vec3(16.0, 0.5, 0.3);
  const Obstacle fin({{c + Vec3(5, -3, 0.2), c + Vec3(5, 3, -0.1), tip}});
  DeformOptions o;
  o.threshold = 125.0;
  o.mode = Mode::shrink;
  o.subvoxel_fit = false;

  Mesh free = make_geodesic_sphere(c, 21.0, 2);
  deform(free, volume, o);
  ASSERT_LT(winding_number(free, tip), 0.5) << "without the obstacle the model should leave the tip out";
  EXPECT_GT(faces_touching(free, fin), 0u);

  o.obstacle = &fin;
  Mesh wrapped = make_geodesic_sphere(c, 21.0, 2);
  const DeformResult r = deform(wrapped, volume, o);
  EXPECT_EQ(faces_touching(wrapped, fin), 0u);
  EXPECT_NEAR(winding_number(wrapped, tip), 1.0, 1e-6);
  EXPECT_GT(r.rejected_moves, 0u);
  const MeshReport report = measure(wrapped);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.two_manifold);
  EXPECT_EQ(report.genus, 0);
  EXPECT_EQ(report.self_intersections, 0u);
  // Away from the fin the model still reaches the ball.
  const Vec3 away = c - Vec3(10.0, 0, 0);
  double nearest = 1e9;
  for (auto v : wrapped.vertices()) nearest = std::min(nearest, (to_eigen(wrapped.point(v)) - away).norm());
  EXPECT_LT(nearest, 1.5);
}

TEST(Obstacle, needs_the_fit_and_error_lod_off) {
  ph::Grid grid;
  grid.dims = {24, 24, 24};
  const Volume volume = ph::voxelize(grid, ph::sphere(grid.center(), 6.0));
  const Obstacle fin({{grid.center(), grid.center() + Vec3(1, 0, 0), grid.center() + Vec3(0, 1, 0)}});
  DeformOptions o;
  o.threshold = 125.0;
  o.obstacle = &fin;
  Mesh m = make_icosahedron(grid.center() + Vec3(0, 0, 3), 1.0);
  try {
    deform(m, volume, o);
    FAIL() << "expected InvalidOption";
  } catch (const InvalidOption& e) {
    EXPECT_NE(std::string(e.what()).find("obstacle"), std::string::npos) << e.what();
  }
}
