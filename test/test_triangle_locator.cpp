// gdm::TriangleLocator and gdm::point_triangle_distance on generated triangle
// soups: the located distance equals the brute-force minimum over every
// triangle, and the point-triangle distance equals an independent reference
// (projection onto the plane, else the nearest of the three edges).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "gdm/seed.h"
#include "gdm/triangle_locator.h"

using namespace gdm;

namespace {

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// Independent of point_triangle_distance: the foot of the perpendicular when
// it falls inside the triangle (barycentric coordinates from the normal
// equations, in long double: slivers make them ill-conditioned), else the
// nearest point of the three closed edges.
double reference_distance(const Vec3& p, const Triangle& t) {
  const double edges = std::min({segment_distance(p, t[0], t[1]), segment_distance(p, t[1], t[2]),
                                 segment_distance(p, t[2], t[0])});
  using V = Eigen::Matrix<long double, 3, 1>;
  const V a = t[0].cast<long double>();
  const V u = t[1].cast<long double>() - a, v = t[2].cast<long double>() - a, w = p.cast<long double>() - a;
  const long double uu = u.dot(u), uv = u.dot(v), vv = v.dot(v), wu = w.dot(u), wv = w.dot(v);
  const long double det = uu * vv - uv * uv;
  if (!(det > 1e-12L * uu * vv)) return edges;  // degenerate: a segment or a point
  const long double s = (vv * wu - uv * wv) / det, r = (uu * wv - uv * wu) / det;
  if (s < 0.0L || r < 0.0L || s + r > 1.0L) return edges;
  return std::min(edges, static_cast<double>((w - s * u - r * v).norm()));
}

// Longest edge over the smallest height, the factor by which rounding in the
// corners grows in a distance computed from them.
double condition(const Triangle& t) {
  const double longest = std::max({(t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm()});
  const double twice_area = (t[1] - t[0]).cross(t[2] - t[0]).norm();
  return twice_area > 0.0 ? longest * longest / twice_area : std::numeric_limits<double>::infinity();
}

double brute_force(const std::vector<Triangle>& soup, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : soup) best = std::min(best, point_triangle_distance(p, t));
  return best;
}

// Triangles of mixed sizes and shapes in [-5, 15]^3: ordinary ones, long
// slivers, tiny ones, and degenerate ones (collinear corners, a single point).
std::vector<Triangle> random_soup(std::mt19937& rng, int count) {
  std::uniform_real_distribution<double> where(-5.0, 15.0), unit(-1.0, 1.0), size(0.05, 3.0);
  std::uniform_int_distribution<int> kind(0, 9);
  const auto dir = [&] { return Vec3(unit(rng), unit(rng), unit(rng)); };
  std::vector<Triangle> soup;
  for (int i = 0; i < count; ++i) {
    const Vec3 a(where(rng), where(rng), where(rng));
    const double s = size(rng);
    switch (kind(rng)) {
      case 0: {  // a long sliver
        const Vec3 d = dir();
        soup.push_back({a, a + 8.0 * d, a + 8.0 * d + 0.01 * dir()});
        break;
      }
      case 1:  // tiny
        soup.push_back({a, a + 1e-3 * dir(), a + 1e-3 * dir()});
        break;
      case 2: {  // collinear corners
        const Vec3 d = dir();
        soup.push_back({a, a + s * d, a + 0.5 * s * d});
        break;
      }
      case 3:  // a single point
        soup.push_back({a, a, a});
        break;
      default:
        soup.push_back({a, a + s * dir(), a + s * dir()});
    }
  }
  return soup;
}

// Compares the locator with the brute force (same primitive, so exactly
// equal) and the primitive with the reference (up to rounding).
void expect_exact(const TriangleLocator& locator, const std::vector<Triangle>& soup, const Vec3& p,
                  const char* what) {
  const double located = locator.distance(p);
  const double brute = brute_force(soup, p);
  EXPECT_EQ(located, brute) << what << " at " << p.transpose();
  double reference = std::numeric_limits<double>::infinity();
  for (const auto& t : soup) reference = std::min(reference, reference_distance(p, t));
  // Rounding on the soup's coordinates (up to ~25 mm), amplified on slivers:
  // far below the size of any wrong Voronoi region.
  EXPECT_NEAR(brute, reference, 1e-8 * (1.0 + reference)) << what << " at " << p.transpose();
}

}  // namespace

TEST(TriangleLocator, point_triangle_distance_matches_the_reference_in_every_region) {
  const Triangle t{Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 3, 0)};
  // Above the face, beside each edge, beyond each corner, on the plane.
  EXPECT_NEAR(point_triangle_distance(Vec3(1, 1, 2), t), 2.0, 1e-12);
  EXPECT_NEAR(point_triangle_distance(Vec3(2, -1, 0), t), 1.0, 1e-12);      // below edge 01
  EXPECT_NEAR(point_triangle_distance(Vec3(-2, 1, 0), t), 2.0, 1e-12);      // left of edge 02
  EXPECT_NEAR(point_triangle_distance(Vec3(4, 3, 0), t), 2.4, 1e-12);       // beyond the hypotenuse
  EXPECT_NEAR(point_triangle_distance(Vec3(-3, -4, 0), t), 5.0, 1e-12);     // beyond corner 0
  EXPECT_NEAR(point_triangle_distance(Vec3(7, -4, 0), t), 5.0, 1e-12);      // beyond corner 1
  EXPECT_NEAR(point_triangle_distance(Vec3(0, 3, 5), t), 5.0, 1e-12);       // above corner 2
  EXPECT_NEAR(point_triangle_distance(Vec3(2, 0, 0), t), 0.0, 1e-12);       // on an edge
  // Degenerate triangles: a segment and a point.
  const Triangle segment{Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(1, 0, 0)};
  EXPECT_NEAR(point_triangle_distance(Vec3(1, 3, 4), segment), 5.0, 1e-12);
  EXPECT_NEAR(point_triangle_distance(Vec3(5, 4, 0), segment), 5.0, 1e-12);
  // Collinear up to rounding (the third corner computed as a midpoint): the
  // points of its edges are at distance 0, not at the distance of a corner.
  const Vec3 s0(-1.6, 5.7, 1.7), s1 = s0 + 3.1 * Vec3(0.3, -0.7, 0.64).normalized();
  const Triangle nearly{s0, s1, s0 + 0.5 * (s1 - s0)};
  for (double f : {0.1, 0.25, 0.4, 0.75, 0.9})
    EXPECT_NEAR(point_triangle_distance(s0 + f * (s1 - s0), nearly), 0.0, 1e-12) << f;
  const Triangle point{Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)};
  EXPECT_NEAR(point_triangle_distance(Vec3(1, 4, 5), point), 5.0, 1e-12);

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int i = 0; i < 2000; ++i) {
    const Triangle r{Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng))};
    const Vec3 p(2 * u(rng), 2 * u(rng), 2 * u(rng));
    EXPECT_NEAR(point_triangle_distance(p, r), reference_distance(p, r), 1e-9) << i;
  }
}

TEST(TriangleLocator, nearest_distance_equals_brute_force_on_random_soups) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> around(-12.0, 22.0), bary(0.0, 1.0), t01(0.0, 1.0);
  std::uniform_int_distribution<int> pick_corner(0, 2);
  for (int soup_size : {1, 7, 60, 400}) {
    const auto soup = random_soup(rng, soup_size);
    const TriangleLocator locator(soup);
    std::uniform_int_distribution<int> pick(0, soup_size - 1);
    for (int i = 0; i < 150; ++i) {
      // Anywhere, including well outside the soup's box.
      expect_exact(locator, soup, Vec3(around(rng), around(rng), around(rng)), "free point");
      const Triangle& t = soup[pick(rng)];
      // On a corner: distance 0.
      const Vec3 corner = t[pick_corner(rng)];
      // On a corner, an edge, inside the face: distance 0 up to rounding,
      // which grows with the triangle's condition (capped: a degenerate one is
      // a segment, measured along its edges).
      const double rounding = 1e-12 * std::min(condition(t), 1e4);
      EXPECT_NEAR(locator.distance(corner), 0.0, rounding) << corner.transpose();
      expect_exact(locator, soup, corner, "corner");
      const int k = pick_corner(rng);
      const Vec3 on_edge = t[k] + t01(rng) * (t[(k + 1) % 3] - t[k]);
      EXPECT_NEAR(locator.distance(on_edge), 0.0, rounding) << on_edge.transpose();
      expect_exact(locator, soup, on_edge, "edge point");
      double a = bary(rng), b = bary(rng);
      if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
      const Vec3 on_face = t[0] + a * (t[1] - t[0]) + b * (t[2] - t[0]);
      EXPECT_NEAR(locator.distance(on_face), 0.0, rounding) << on_face.transpose();
      expect_exact(locator, soup, on_face, "face point");
      // Just off the face along its normal: at most that far.
      const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
      if (n.norm() > 1e-9) {
        const Vec3 off = on_face + 0.01 * n.normalized();
        EXPECT_LE(locator.distance(off), 0.01 + 1e-12);
        expect_exact(locator, soup, off, "point off a face");
      }
    }
  }
}

TEST(TriangleLocator, searches_past_empty_buckets_to_a_far_cluster) {
  // Two clusters of small triangles 100 mm apart: a query next to one
  // cluster whose nearest triangle is in it, and queries in the empty space
  // between, where the nearest triangle lies many empty buckets away.
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Triangle> soup;
  for (const Vec3& c : {Vec3(0, 0, 0), Vec3(100, 0, 0)})
    for (int i = 0; i < 200; ++i) {
      const Vec3 a = c + 5.0 * Vec3(u(rng), u(rng), u(rng));
      soup.push_back({a, a + 0.5 * Vec3(u(rng), u(rng), 0), a + 0.5 * Vec3(0, u(rng), u(rng))});
    }
  const TriangleLocator locator(soup);
  for (int i = 0; i <= 40; ++i) {
    const Vec3 p(-20.0 + 3.5 * i, 40.0 * u(rng) - 20.0, 40.0 * u(rng) - 20.0);
    expect_exact(locator, soup, p, "between the clusters");
  }
  EXPECT_EQ(TriangleLocator({}).distance(Vec3::Zero()), std::numeric_limits<double>::infinity());
}

// mean_distance: the vertices and face centroids of a geodesic sphere of
// radius 10 against the triangles of one of radius 12 (the same level, so
// each point lies under a face of the larger one, at 2 voxels along the
// radius, less toward the larger sphere's flat faces); against itself 0;
// the same sum for 1 and 4 threads.
TEST(TriangleLocator, mean_distance_of_a_mesh_over_its_vertices_and_centroids) {
  const gdm::Vec3 c(1, 2, 3);
  const gdm::Mesh inner = gdm::make_geodesic_sphere(c, 10.0, 4);
  const gdm::Mesh outer = gdm::make_geodesic_sphere(c, 12.0, 4);
  const gdm::TriangleLocator to_outer(gdm::triangles_of(outer));
  const gdm::TriangleLocator to_inner(gdm::triangles_of(inner));
  // Brute force: each sample's distance to the nearest triangle.
  const auto soup = gdm::triangles_of(outer);
  double sum = 0.0;
  std::size_t n = 0;
  const auto add = [&](const gdm::Vec3& p) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& t : soup) best = std::min(best, gdm::point_triangle_distance(p, t));
    sum += best;
    ++n;
  };
  for (auto v : inner.vertices()) add(gdm::to_eigen(inner.point(v)));
  for (auto f : inner.faces()) {
    auto it = inner.cfv_iter(f);
    const gdm::Vec3 a = gdm::to_eigen(inner.point(*it)), b = gdm::to_eigen(inner.point(*++it)),
                    d = gdm::to_eigen(inner.point(*++it));
    add((a + b + d) / 3.0);
  }
  const double one = gdm::mean_distance(inner, to_outer, 1);
  EXPECT_NEAR(one, sum / static_cast<double>(n), 1e-12);
  EXPECT_GT(one, 1.9);
  EXPECT_LT(one, 2.0);
  EXPECT_EQ(gdm::mean_distance(inner, to_outer, 4), one);
  EXPECT_NEAR(gdm::mean_distance(inner, to_inner, 2), 0.0, 1e-12);
}
