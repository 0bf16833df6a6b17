// The separating-axis filter of the triangle test (triangle_separation.h):
// wherever it says "no improper contact", the exact predicates agree, on
// random pairs built to be hard (coplanar on a coarse grid, nearly coplanar,
// sharing a vertex, touching); and it decides most of the coplanar pairs
// that do not meet (what it is for: the guard on a cube's flat faces).
#include <gtest/gtest.h>

#include <random>

#include "gdm/predicates.h"
#include "gdm/triangle_separation.h"

namespace gdm {
namespace {

using Tri = std::array<Vec3, 3>;
using Ids = std::array<int, 3>;

// The exact answer from the exact segment tests alone: with no shared
// vertex any contact is improper; with one, contact besides it is, which
// shows as an opposite edge of one touching the other (predicates.cpp).
bool improper_exactly(const Tri& t1, const Ids& i1, const Tri& t2, const Ids& i2) {
  int s1 = -1, s2 = -1;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (i1[i] == i2[j]) s1 = i, s2 = j;
  if (s1 < 0) return triangles_touch(t1, t2);
  return segment_intersects_triangle(t1[(s1 + 1) % 3], t1[(s1 + 2) % 3], t2[0], t2[1], t2[2]) ||
         segment_intersects_triangle(t2[(s2 + 1) % 3], t2[(s2 + 2) % 3], t1[0], t1[1], t1[2]);
}

TEST(TriangleSeparation, never_clears_a_pair_the_exact_test_finds_improper) {
  std::mt19937 random(1717);
  std::uniform_int_distribution<int> grid(-4, 4);
  std::uniform_real_distribution<double> tiny(-1e-12, 1e-12), unit(-1.0, 1.0);
  int cleared = 0, proper_coplanar = 0, cleared_coplanar = 0;
  for (int trial = 0; trial < 40000; ++trial) {
    const int kind = trial % 4;  // 0 coplanar, 1 nearly coplanar, 2 general, 3 general on the grid
    const auto point = [&]() {
      Vec3 p(grid(random), grid(random), kind <= 1 ? 0.0 : grid(random));
      if (kind == 1) p.z() += tiny(random);
      if (kind == 2) p = Vec3(unit(random), unit(random), unit(random));
      return Vec3(0.25 * p.x() + 10.0, 0.25 * p.y() - 3.0, 0.25 * p.z() + 7.0);  // away from the origin
    };
    Tri t1{point(), point(), point()}, t2{point(), point(), point()};
    Ids i1{0, 1, 2}, i2{3, 4, 5};
    if (trial % 3 == 0) {  // one shared vertex
      t2[1] = t1[2];
      i2[1] = 2;
    }
    if (is_degenerate_triangle(t1[0], t1[1], t1[2]) || is_degenerate_triangle(t2[0], t2[1], t2[2])) continue;
    const bool improper = improper_exactly(t1, i1, t2, i2);
    const int filter = separated_by_an_axis(t1, i1, t2, i2);
    if (filter == 0) {
      ++cleared;
      ASSERT_FALSE(improper) << "trial " << trial << ": the filter cleared a pair that meets improperly";
    }
    ASSERT_EQ(triangles_intersect_improperly(t1, i1, t2, i2), improper) << "trial " << trial;
    if (kind == 0 && !improper) {
      ++proper_coplanar;
      if (filter == 0) ++cleared_coplanar;
    }
  }
  EXPECT_GT(cleared, 0);
  std::printf("cleared %d pairs; %d of %d coplanar pairs that do not meet\n", cleared, cleared_coplanar, proper_coplanar);
  EXPECT_GT(cleared_coplanar, proper_coplanar / 2) << "the filter should decide most coplanar pairs that do not meet";
}

// Tiny triangles far from the origin: their corners' differences round by
// an ulp of the coordinates, which can exceed the filter's margin; the
// filter must leave them to the exact code rather than clear a contact.
TEST(TriangleSeparation, tiny_triangles_far_from_the_origin_are_left_to_the_exact_code) {
  std::mt19937 random(1718);
  std::uniform_int_distribution<int> grid(-4, 4);
  for (const double size : {1e-3, 1e-6, 1e-9}) {
    int cleared = 0;
    for (int trial = 0; trial < 4000; ++trial) {
      const auto point = [&]() {
        return Vec3(812.5 + size * grid(random), -433.0 + size * grid(random), 650.25 + size * (trial % 2) * grid(random));
      };
      Tri t1{point(), point(), point()}, t2{point(), point(), point()};
      const Ids i1{0, 1, 2}, i2{3, 4, 5};
      if (is_degenerate_triangle(t1[0], t1[1], t1[2]) || is_degenerate_triangle(t2[0], t2[1], t2[2])) continue;
      const int filter = separated_by_an_axis(t1, i1, t2, i2);
      if (filter == 0) {
        ++cleared;
        ASSERT_FALSE(improper_exactly(t1, i1, t2, i2)) << "size " << size << ", trial " << trial;
      }
    }
    // Below 1e-4 of the coordinates' size nothing is cleared at all.
    if (size < 1e-4 * 812.5) EXPECT_EQ(cleared, 0) << "size " << size;
  }
}

}  // namespace
}  // namespace gdm
