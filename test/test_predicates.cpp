// Tests of the exact predicates in gdm/predicates.h.
#include "gdm/predicates.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

namespace {

using gdm::Vec2;
using gdm::Vec3;
using Tri = std::array<Vec3, 3>;
using Ids = std::array<int, 3>;

int sign_of(double x) { return (x > 0) - (x < 0); }
int sign_of(__int128 x) { return (x > 0) - (x < 0); }

// The plain double evaluation without any error control.
double naive_orient3d(const Vec3& a, const Vec3& b, const Vec3& c,
                      const Vec3& d) {
  return (b - a).cross(c - a).dot(d - a);
}

// Exact determinant of integer points (differences and products in 128 bits;
// coordinates must stay below 2^30 so the products fit).
__int128 integer_orient3d(const std::array<int64_t, 3>& a,
                          const std::array<int64_t, 3>& b,
                          const std::array<int64_t, 3>& c,
                          const std::array<int64_t, 3>& d) {
  __int128 B[3], C[3], D[3];
  for (int k = 0; k < 3; ++k) {
    B[k] = b[k] - a[k];
    C[k] = c[k] - a[k];
    D[k] = d[k] - a[k];
  }
  return B[0] * (C[1] * D[2] - C[2] * D[1]) +
         B[1] * (C[2] * D[0] - C[0] * D[2]) +
         B[2] * (C[0] * D[1] - C[1] * D[0]);
}

TEST(Orient3d, sign_convention_matches_documentation) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_GT(gdm::orient3d(a, b, c, Vec3(0, 0, 1)), 0.0);
  EXPECT_LT(gdm::orient3d(a, b, c, Vec3(0, 0, -1)), 0.0);
  EXPECT_EQ(gdm::orient3d(a, b, c, Vec3(5, -7, 0)), 0.0);
  EXPECT_DOUBLE_EQ(gdm::orient3d(a, b, c, Vec3(0.3, 0.2, 2.0)), 2.0);
}

// Integer grids scaled by a power of two and shifted by a power of two are
// represented exactly; the sign of the determinant is that of the integer
// determinant. Points are exactly coplanar, then pushed off by one grid step.
TEST(Orient3d, exact_on_scaled_integer_grids_near_coplanar) {
  std::mt19937_64 rng(12345);
  std::uniform_int_distribution<int64_t> coord(-(1LL << 25), 1LL << 25);
  std::uniform_int_distribution<int64_t> small(-3, 3);
  const double scale = std::ldexp(1.0, -20), shift = 1024.0;
  int naive_wrong = 0, zeros = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    std::array<int64_t, 3> a, b, c, d;
    for (int k = 0; k < 3; ++k) {
      a[k] = coord(rng);
      b[k] = coord(rng);
      c[k] = coord(rng);
    }
    const int64_t i = small(rng), j = small(rng);
    for (int k = 0; k < 3; ++k) d[k] = a[k] + i * (b[k] - a[k]) + j * (c[k] - a[k]);
    d[trial % 3] += (trial / 3) % 3 - 1;  // -1, 0 or +1 grid step off plane
    auto to_vec = [&](const std::array<int64_t, 3>& p) {
      return Vec3(shift + static_cast<double>(p[0]) * scale,
                  shift + static_cast<double>(p[1]) * scale,
                  shift + static_cast<double>(p[2]) * scale);
    };
    const int expected = sign_of(integer_orient3d(a, b, c, d));
    const Vec3 va = to_vec(a), vb = to_vec(b), vc = to_vec(c), vd = to_vec(d);
    ASSERT_EQ(sign_of(gdm::orient3d(va, vb, vc, vd)), expected)
        << "trial " << trial;
    if (sign_of(naive_orient3d(va, vb, vc, vd)) != expected) ++naive_wrong;
    if (expected == 0) ++zeros;
  }
  // The inputs are hard: plain double evaluation gets many signs wrong.
  EXPECT_GT(naive_wrong, 100);
  EXPECT_GT(zeros, 1000);
}

// Points on the plane z = x + y with arbitrary decimal coordinates
// (0.1 + k*1e-17, large offsets): y is rounded so that x + y is exact, so the
// points are exactly coplanar although the differences are not exact.
// Raising z by one ulp puts the point strictly on the side the normal's z
// component points to; lowering it, on the other side.
Vec3 on_plane_z_equals_x_plus_y(double x, double fraction) {
  const double z = x + fraction * x;  // fraction in [0, 1]: z in [x, 2x]
  const double y = z - x;             // exact (Sterbenz), so x + y == z
  return Vec3(x, y, z);
}

TEST(Orient3d, exact_on_tilted_plane_with_decimal_coordinates) {
  const double offsets[] = {0.0, 1.0, 1e3, 1e6};
  int naive_wrong = 0;
  for (const double off : offsets) {
    const Vec3 a = on_plane_z_equals_x_plus_y(off + 0.1, 0.3);
    const Vec3 b = on_plane_z_equals_x_plus_y(off + 5.7, 0.2);
    const Vec3 c = on_plane_z_equals_x_plus_y(off + 0.3, 0.9);
    const int nz = sign_of(gdm::orient2d(Vec2(a.x(), a.y()), Vec2(b.x(), b.y()),
                                         Vec2(c.x(), c.y())));
    ASSERT_NE(nz, 0);
    for (int k = -50; k <= 50; ++k) {
      const Vec3 d = on_plane_z_equals_x_plus_y(off + 0.7 + k * 1e-17, 0.5 + k * 1e-3);
      EXPECT_EQ(gdm::orient3d(a, b, c, d), 0.0) << off << " " << k;
      Vec3 up = d, down = d;
      up.z() = std::nextafter(d.z(), 1e300);
      down.z() = std::nextafter(d.z(), -1e300);
      EXPECT_EQ(sign_of(gdm::orient3d(a, b, c, up)), nz) << off << " " << k;
      EXPECT_EQ(sign_of(gdm::orient3d(a, b, c, down)), -nz) << off << " " << k;
      // Reordering the corners flips the sign exactly.
      EXPECT_EQ(sign_of(gdm::orient3d(b, a, c, up)), -nz);
      EXPECT_EQ(sign_of(gdm::orient3d(up, c, b, a)), nz);
      if (sign_of(naive_orient3d(a, b, c, d)) != 0) ++naive_wrong;
      if (sign_of(naive_orient3d(a, b, c, up)) != nz) ++naive_wrong;
      if (sign_of(naive_orient3d(a, b, c, down)) != -nz) ++naive_wrong;
    }
  }
  // The inputs are hard: plain double evaluation gets many signs wrong.
  EXPECT_GT(naive_wrong, 10);
}

// Sign must be invariant under even permutations and flip under odd ones.
TEST(Orient3d, consistent_under_all_permutations) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 300; ++trial) {
    // Nearly coplanar: d is an affine combination of a, b, c in floating
    // point, which rounds it a few ulps off the plane (or onto it).
    std::array<Vec3, 4> p;
    for (int i = 0; i < 3; ++i) p[i] = Vec3(u(rng), u(rng), u(rng)) + Vec3(100, 200, 300);
    const double s = u(rng), t = u(rng);
    p[3] = p[0] + s * (p[1] - p[0]) + t * (p[2] - p[0]);
    const int reference = sign_of(gdm::orient3d(p[0], p[1], p[2], p[3]));
    std::array<int, 4> perm = {0, 1, 2, 3};
    do {
      int inversions = 0;
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) inversions += perm[i] > perm[j];
      const int parity = inversions % 2 == 0 ? 1 : -1;
      ASSERT_EQ(sign_of(gdm::orient3d(p[perm[0]], p[perm[1]], p[perm[2]], p[perm[3]])),
                parity * reference)
          << "trial " << trial;
    } while (std::next_permutation(perm.begin(), perm.end()));
  }
}

TEST(Orient2d, sign_convention_matches_documentation) {
  EXPECT_GT(gdm::orient2d(Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)), 0.0);
  EXPECT_LT(gdm::orient2d(Vec2(0, 0), Vec2(0, 1), Vec2(1, 0)), 0.0);
  EXPECT_EQ(gdm::orient2d(Vec2(0, 0), Vec2(1, 1), Vec2(3, 3)), 0.0);
}

TEST(Orient2d, exact_on_integer_grids_near_collinear) {
  std::mt19937_64 rng(99);
  // |coordinates| < 2^52 (exact doubles), products < 2^104 (fit 128 bits).
  std::uniform_int_distribution<int64_t> coord(-(1LL << 48), 1LL << 48);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  int naive_wrong = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const int64_t ax = coord(rng), ay = coord(rng), bx = coord(rng), by = coord(rng);
    // c near line ab: a + t (b - a) rounded to the integer grid.
    const double t = u(rng);
    const int64_t cx = ax + std::llround(t * static_cast<double>(bx - ax)) + (trial % 3 == 0);
    const int64_t cy = ay + std::llround(t * static_cast<double>(by - ay));
    const __int128 exact = static_cast<__int128>(bx - ax) * (cy - ay) -
                           static_cast<__int128>(by - ay) * (cx - ax);
    const double s = std::ldexp(1.0, -7);
    const Vec2 a(ax * s, ay * s), b(bx * s, by * s), c(cx * s, cy * s);
    ASSERT_EQ(sign_of(gdm::orient2d(a, b, c)), sign_of(exact)) << trial;
    const double naive = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    if (sign_of(naive) != sign_of(exact)) ++naive_wrong;
  }
  EXPECT_GT(naive_wrong, 100);
}

TEST(Orient2d, exact_on_line_y_equals_x_with_decimal_coordinates) {
  const Vec2 a(0.1, 0.1), b(1e6 + 0.3, 1e6 + 0.3);
  for (int k = -50; k <= 50; ++k) {
    const double x = 0.7 + k * 1e-17;
    EXPECT_EQ(gdm::orient2d(a, b, Vec2(x, x)), 0.0);
    EXPECT_GT(gdm::orient2d(a, b, Vec2(x, std::nextafter(x, 2.0))), 0.0);
    EXPECT_LT(gdm::orient2d(a, b, Vec2(x, std::nextafter(x, 0.0))), 0.0);
  }
}

// ---------------------------------------------------------------------------

class SegmentTriangle : public ::testing::Test {
 protected:
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  bool hits(const Vec3& p, const Vec3& q) const {
    const bool result = gdm::segment_intersects_triangle(p, q, a, b, c);
    // The answer must not depend on the order of endpoints or corners.
    EXPECT_EQ(result, gdm::segment_intersects_triangle(q, p, c, a, b));
    EXPECT_EQ(result, gdm::segment_intersects_triangle(p, q, b, a, c));
    return result;
  }
};

TEST_F(SegmentTriangle, crossing_through_interior) {
  EXPECT_TRUE(hits(Vec3(0.2, 0.2, -1), Vec3(0.2, 0.2, 1)));
  EXPECT_TRUE(hits(Vec3(-1, -1, -1), Vec3(1, 1.2, 1)));  // oblique
}

TEST_F(SegmentTriangle, crossing_the_plane_outside_the_triangle) {
  EXPECT_FALSE(hits(Vec3(0.6, 0.6, -1), Vec3(0.6, 0.6, 1)));
  EXPECT_FALSE(hits(Vec3(2, 2, -1), Vec3(2, 2, 1)));
}

TEST_F(SegmentTriangle, touching_an_edge_or_vertex_counts) {
  EXPECT_TRUE(hits(Vec3(0.5, 0, -1), Vec3(0.5, 0, 1)));      // through edge ab
  EXPECT_TRUE(hits(Vec3(0.5, 0.5, -1), Vec3(0.5, 0.5, 1)));  // through hypotenuse
  EXPECT_TRUE(hits(Vec3(0, 0, -1), Vec3(0, 0, 1)));          // through vertex a
  const double off = -std::ldexp(1.0, -40);                  // just outside ab
  EXPECT_FALSE(hits(Vec3(0.5, off, -1), Vec3(0.5, off, 1)));
}

TEST_F(SegmentTriangle, endpoint_on_the_face) {
  EXPECT_TRUE(hits(Vec3(0.2, 0.2, 0), Vec3(0.2, 0.2, 1)));
  const double above = std::ldexp(1.0, -50);
  EXPECT_FALSE(hits(Vec3(0.2, 0.2, above), Vec3(0.2, 0.2, 1)));
}

TEST_F(SegmentTriangle, parallel_to_the_plane) {
  EXPECT_FALSE(hits(Vec3(-1, 0.25, 1), Vec3(2, 0.25, 1)));
  EXPECT_FALSE(hits(Vec3(-1, 0.25, -1e-9), Vec3(2, 0.25, -1e-9)));
}

TEST_F(SegmentTriangle, coplanar_overlap) {
  EXPECT_TRUE(hits(Vec3(-1, 0.25, 0), Vec3(2, 0.25, 0)));     // crosses it
  EXPECT_TRUE(hits(Vec3(0.1, 0.1, 0), Vec3(0.2, 0.2, 0)));    // inside
  EXPECT_TRUE(hits(Vec3(0.5, 0.5, 0), Vec3(1, 1, 0)));        // touches hypotenuse
  EXPECT_TRUE(hits(Vec3(-1, 0, 0), Vec3(3, 0, 0)));           // along edge ab
  EXPECT_TRUE(hits(Vec3(0.3, 0.3, 0), Vec3(0.3, 0.3, 0)));    // single point
}

TEST_F(SegmentTriangle, coplanar_disjoint) {
  EXPECT_FALSE(hits(Vec3(0.6, 0.6, 0), Vec3(2, 2, 0)));
  EXPECT_FALSE(hits(Vec3(-1, -0.5, 0), Vec3(1, -0.5, 0)));
  EXPECT_FALSE(hits(Vec3(2, 0, 0), Vec3(3, 0, 0)));  // collinear with ab, beyond b
}

TEST(SegmentTriangleExact, endpoint_on_tilted_plane_with_decimal_coordinates) {
  const Vec3 a(0.1, 0.3, 0.1), b(5.7, 0.2, 5.7), c(0.3, 4.1, 0.3);  // plane z = x
  const Vec3 p(1.1, 1.3, 1.1), q(1.1, 1.3, 5.0);                    // q has z > x
  EXPECT_TRUE(gdm::segment_intersects_triangle(p, q, a, b, c));
  const Vec3 p_up(1.1, 1.3, std::nextafter(1.1, 2.0));
  EXPECT_FALSE(gdm::segment_intersects_triangle(p_up, q, a, b, c));
  const Vec3 p_down(1.1, 1.3, std::nextafter(1.1, 0.0));
  EXPECT_TRUE(gdm::segment_intersects_triangle(p_down, q, a, b, c));
}

TEST(SegmentTriangleExact, degenerate_triangle_is_its_edges) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(2, 0, 0);  // collinear
  EXPECT_TRUE(gdm::is_degenerate_triangle(a, b, c));
  EXPECT_TRUE(gdm::segment_intersects_triangle(Vec3(1.5, -1, 0), Vec3(1.5, 1, 0), a, b, c));
  EXPECT_TRUE(gdm::segment_intersects_triangle(Vec3(1.5, -1, -1), Vec3(1.5, 1, 1), a, b, c));
  EXPECT_FALSE(gdm::segment_intersects_triangle(Vec3(1.5, -1, 1), Vec3(1.5, 1, 1), a, b, c));
  EXPECT_FALSE(gdm::segment_intersects_triangle(Vec3(3, -1, 0), Vec3(3, 1, 0), a, b, c));
}

// ---------------------------------------------------------------------------

bool improper(const Tri& t1, const Ids& i1, const Tri& t2, const Ids& i2) {
  const bool result = gdm::triangles_intersect_improperly(t1, i1, t2, i2);
  // Symmetric, and independent of the corner rotation.
  EXPECT_EQ(result, gdm::triangles_intersect_improperly(t2, i2, t1, i1));
  const Tri r1 = {t1[1], t1[2], t1[0]};
  const Ids ri1 = {i1[1], i1[2], i1[0]};
  EXPECT_EQ(result, gdm::triangles_intersect_improperly(r1, ri1, t2, i2));
  return result;
}

const Tri kBase = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
const Ids kBaseIds = {0, 1, 2};

TEST(TrianglesImproper, no_shared_vertex_disjoint_is_proper) {
  EXPECT_FALSE(improper(kBase, kBaseIds, {Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(0, 1, 1)}, {3, 4, 5}));
  EXPECT_FALSE(improper(kBase, kBaseIds, {Vec3(1, 1, 0), Vec3(2, 1, 0), Vec3(1, 2, 0)}, {3, 4, 5}));
}

TEST(TrianglesImproper, no_shared_vertex_any_contact_is_improper) {
  // Crossing.
  EXPECT_TRUE(improper(kBase, kBaseIds, {Vec3(0.2, 0.2, -1), Vec3(0.2, 0.2, 1), Vec3(5, 5, 0.5)}, {3, 4, 5}));
  // A corner touching the interior.
  EXPECT_TRUE(improper(kBase, kBaseIds, {Vec3(0.2, 0.2, 0), Vec3(0.2, 0.2, 1), Vec3(1, 1, 1)}, {3, 4, 5}));
  // Coplanar, one inside the other.
  EXPECT_TRUE(improper(kBase, kBaseIds, {Vec3(0.1, 0.1, 0), Vec3(0.3, 0.1, 0), Vec3(0.1, 0.3, 0)}, {3, 4, 5}));
  // Same position as a corner of the other but a different vertex id.
  EXPECT_TRUE(improper(kBase, kBaseIds, {Vec3(0, 0, 0), Vec3(-1, 0, 1), Vec3(0, -1, 1)}, {3, 4, 5}));
}

TEST(TrianglesImproper, one_shared_vertex_fan_neighbours_are_proper) {
  EXPECT_FALSE(improper(kBase, kBaseIds, {Vec3(0, 0, 0), Vec3(-1, 0, 1), Vec3(0, -1, 1)}, {0, 4, 5}));
  // Coplanar, opposite sectors.
  EXPECT_FALSE(improper(kBase, kBaseIds, {Vec3(0, 0, 0), Vec3(-1, 0, 0), Vec3(0, -1, 0)}, {0, 4, 5}));
  // An edge from v in the plane but outside the angle.
  EXPECT_FALSE(improper(kBase, kBaseIds, {Vec3(0, 0, 0), Vec3(-0.3, -0.3, 0), Vec3(0, 0, 1)}, {0, 4, 5}));
}

TEST(TrianglesImproper, one_shared_vertex_overlaps_are_improper) {
  // Opposite edge piercing the other triangle.
  EXPECT_TRUE(improper(kBase, kBaseIds, {Vec3(0, 0, 0), Vec3(0.2, 0.2, -1), Vec3(0.2, 0.2, 1)}, {0, 4, 5}));
  // Edge from v in the other's plane, direction inside its angle.
  EXPECT_TRUE(improper(kBase, kBaseIds, {Vec3(0, 0, 0), Vec3(0.3, 0.3, 0), Vec3(0, 0, 1)}, {0, 4, 5}));
  // ... and on the boundary of the angle (along edge v-b, shorter or longer).
  EXPECT_TRUE(improper(kBase, kBaseIds, {Vec3(0, 0, 0), Vec3(0.5, 0, 0), Vec3(0, 0, 1)}, {0, 4, 5}));
  EXPECT_TRUE(improper(kBase, kBaseIds, {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, -1, 1)}, {0, 4, 5}));
  // Coplanar, sharing the ray along v-b only.
  EXPECT_TRUE(improper(kBase, kBaseIds, {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, -1, 0)}, {0, 4, 5}));
  // Coplanar overlapping sectors.
  EXPECT_TRUE(improper(kBase, kBaseIds, {Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(1, -1, 0)}, {0, 4, 5}));
}

TEST(TrianglesImproper, shared_edge_proper_cases) {
  // Shared edge (0,0,0)-(1,0,0); apexes in different planes.
  EXPECT_FALSE(improper(kBase, kBaseIds, {Vec3(1, 0, 0), Vec3(0, 0, 0), Vec3(0.5, 0.3, 1)}, {1, 0, 7}));
  // Coplanar, apexes on opposite sides: a flat pair.
  EXPECT_FALSE(improper(kBase, kBaseIds, {Vec3(1, 0, 0), Vec3(0, 0, 0), Vec3(0.5, -1, 0)}, {1, 0, 7}));
  // Almost folded, apex a tiny bit off the plane: not coplanar, proper.
  EXPECT_FALSE(improper(kBase, kBaseIds, {Vec3(1, 0, 0), Vec3(0, 0, 0), Vec3(0.3, 0.8, 1e-30)}, {1, 0, 7}));
}

TEST(TrianglesImproper, shared_edge_fold_over_is_improper) {
  EXPECT_TRUE(improper(kBase, kBaseIds, {Vec3(1, 0, 0), Vec3(0, 0, 0), Vec3(0.3, 0.8, 0)}, {1, 0, 7}));
  EXPECT_TRUE(improper(kBase, kBaseIds, {Vec3(1, 0, 0), Vec3(0, 0, 0), Vec3(3, 5, 0)}, {1, 0, 7}));
}

TEST(TrianglesImproper, duplicate_face_is_improper) {
  EXPECT_TRUE(improper(kBase, kBaseIds, {Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0)}, {0, 2, 1}));
}

TEST(TrianglesImproper, degenerate_triangle_intersects_what_it_touches) {
  const Tri flat = {Vec3(0, 0, 0), Vec3(-1, 0, 1), Vec3(-2, 0, 2)};  // collinear
  EXPECT_TRUE(improper(kBase, kBaseIds, flat, {0, 4, 5}));            // touches at v
  const Tri far = {Vec3(5, 5, 5), Vec3(6, 5, 5), Vec3(7, 5, 5)};
  EXPECT_FALSE(improper(kBase, kBaseIds, far, {3, 4, 5}));
}

}  // namespace
