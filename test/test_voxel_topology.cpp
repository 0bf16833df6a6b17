// The topology of voxel sets (voxel_topology.h): the Euler characteristic
// from 2 x 2 x 2 windows against a direct count of the cubical complex's
// cells, and the handles of shapes whose genus is known (issue 17: the cavity
// fill skips the handle growth on a region without a handle). The flood by
// runs (voxel_flood.h) against a voxel-by-voxel one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <tuple>
#include <utility>

#include "gdm/phantoms.h"
#include "gdm/voxel_flood.h"
#include "gdm/voxel_topology.h"

namespace gdm {
namespace {

namespace ph = phantoms;

std::size_t at(const Index3& n, int i, int j, int k) {
  return static_cast<std::size_t>(i) + static_cast<std::size_t>(n[0]) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(k));
}

// The cells of the union of closed unit cubes, listed one by one: a cell is
// named by its lowest lattice corner and the axes it spans (a bit mask), and
// every set voxel adds its 8 vertices, 12 edges, 6 faces and itself.
std::int64_t euler_by_listing_cells(const std::vector<char>& set, const Index3& n) {
  std::set<std::tuple<int, int, int, int>> cells;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        if (!set[at(n, i, j, k)]) continue;
        for (int axes = 0; axes < 8; ++axes)  // the cell spans the axes in `axes`; its corner may sit at +1 along the others
          for (int shift = 0; shift < 8; ++shift) {
            if (shift & axes) continue;
            cells.insert({i + (shift & 1), j + ((shift >> 1) & 1), k + ((shift >> 2) & 1), axes});
          }
      }
  std::int64_t chi = 0;
  for (const auto& c : cells) chi += (__builtin_popcount(static_cast<unsigned>(std::get<3>(c))) % 2 == 0) ? 1 : -1;
  return chi;
}

// Random voxel sets of several densities: every window configuration occurs.
TEST(VoxelTopology, euler_characteristic_matches_the_cells_counted_one_by_one) {
  std::mt19937 random(17);
  for (const double density : {0.1, 0.3, 0.5, 0.7, 0.9}) {
    const Index3 n{9, 7, 8};
    std::vector<char> set(static_cast<std::size_t>(n[0] * n[1] * n[2]));
    std::bernoulli_distribution draw(density);
    for (char& c : set) c = draw(random) ? 1 : 0;
    EXPECT_EQ(euler_characteristic(set, n), euler_by_listing_cells(set, n)) << "density " << density;
  }
}

// The voxels inside an analytic shape (sdf < 0 at the voxel's centre).
std::vector<char> inside(const ph::Grid& grid, const ph::Sdf& sdf) {
  const Index3& n = grid.dims;
  std::vector<char> set(static_cast<std::size_t>(n[0]) * n[1] * n[2], 0);
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        set[at(n, i, j, k)] = sdf(grid.origin + Vec3(i, j, k).cwiseProduct(grid.spacing)) < 0.0;
  return set;
}

ph::Sdf torus(const Vec3& c, double R, double r) {
  return [=](const Vec3& p) { return std::hypot(std::hypot(p.x() - c.x(), p.y() - c.y()) - R, p.z() - c.z()) - r; };
}

TEST(VoxelTopology, shapes_of_known_genus) {
  ph::Grid grid;  // 64^3
  const Vec3 c = grid.center();
  struct Shape {
    const char* name;
    ph::Sdf sdf;
    std::int64_t pieces, handles, cavities;
  };
  const std::vector<Shape> shapes{
      {"ball", ph::sphere(c, 9.0), 1, 0, 0},
      {"cube with a corner missing", ph::difference(ph::box(c - Vec3(10, 10, 10), c + Vec3(10, 10, 10)), ph::box(c, c + Vec3(12, 12, 12))), 1, 0, 0},
      {"branching", ph::branching(c + Vec3(0, 0, 2)), 1, 0, 0},
      {"torus", torus(c, 10.0, 4.0), 1, 1, 0},
      {"double torus", ph::unite({torus(c - Vec3(8, 0, 0), 7.5, 3.0), torus(c + Vec3(8, 0, 0), 7.5, 3.0)}), 1, 2, 0},
      {"hollow ball", ph::difference(ph::sphere(c, 11.0), ph::sphere(c, 7.0)), 1, 0, 1},
      {"two balls", ph::unite({ph::sphere(c - Vec3(12, 0, 0), 6.0), ph::sphere(c + Vec3(12, 0, 0), 6.0)}), 2, 0, 0},
  };
  for (const Shape& s : shapes) {
    const std::vector<char> set = inside(grid, s.sdf);
    const VoxelTopology t = voxel_topology(set, grid.dims);
    EXPECT_EQ(t.pieces, s.pieces) << s.name;
    EXPECT_EQ(t.cavities, s.cavities) << s.name;
    EXPECT_EQ(t.handles(), s.handles) << s.name << ": Euler characteristic " << t.euler;
  }
}

// Voxels meeting only at an edge or a corner are one piece (closed cubes),
// and a ring closed only through such a contact is a handle.
TEST(VoxelTopology, cubes_touching_at_an_edge_or_corner_are_joined) {
  const Index3 n{6, 6, 6};
  std::vector<char> set(216, 0);
  set[at(n, 2, 2, 2)] = set[at(n, 3, 3, 3)] = 1;  // corner contact
  VoxelTopology t = voxel_topology(set, n);
  EXPECT_EQ(t.pieces, 1);
  EXPECT_EQ(t.handles(), 0);
  // A square ring of 8 voxels in a plane: one handle; with its corners
  // removed the four sides still meet at edges: still one handle.
  std::fill(set.begin(), set.end(), 0);
  for (int i = 1; i <= 3; ++i)
    for (int j = 1; j <= 3; ++j)
      if (i != 2 || j != 2) set[at(n, i, j, 2)] = 1;
  EXPECT_EQ(voxel_topology(set, n).handles(), 1);
  for (const auto& corner : {std::pair{1, 1}, std::pair{1, 3}, std::pair{3, 1}, std::pair{3, 3}}) set[at(n, corner.first, corner.second, 2)] = 0;
  t = voxel_topology(set, n);
  EXPECT_EQ(t.pieces, 1);
  EXPECT_EQ(t.handles(), 1);
}

// The flood by runs marks exactly what a voxel-by-voxel breadth-first flood
// marks, 6- and 26-connected, on random grids (thin ones included, each axis
// one voxel wide), with seeds that are not passable themselves and walls
// marked before the call.
TEST(VoxelFlood, marks_what_a_voxel_by_voxel_flood_marks) {
  std::mt19937 random(20261205);
  const Index3 sizes[] = {{1, 1, 1}, {7, 1, 1}, {1, 9, 1}, {1, 1, 8}, {5, 6, 7}, {23, 17, 11}, {40, 3, 29}};
  int floods = 0;
  for (const Index3& n : sizes)
    for (const double density : {0.3, 0.5, 0.7, 0.9})
      for (const bool connect26 : {false, true}) {
        const std::size_t count = static_cast<std::size_t>(n[0]) * n[1] * n[2];
        std::bernoulli_distribution open(density), wall(0.05), seed(0.01);
        std::vector<char> passable(count), marked(count, 0);
        std::vector<std::size_t> seeds;
        for (std::size_t c = 0; c < count; ++c) {
          passable[c] = open(random);
          if (wall(random)) marked[c] = 1;
        }
        for (std::size_t c = 0; c < count; ++c)
          if (!marked[c] && (seeds.empty() || seed(random))) {
            marked[c] = 1;
            seeds.push_back(c);
          }
        std::vector<char> expected = marked;
        std::vector<std::size_t> queue = seeds;
        for (std::size_t q = 0; q < queue.size(); ++q) {
          const std::size_t c = queue[q];
          const int i = static_cast<int>(c % n[0]), j = static_cast<int>(c / n[0] % n[1]), k = static_cast<int>(c / n[0] / n[1]);
          for (int dk = -1; dk <= 1; ++dk)
            for (int dj = -1; dj <= 1; ++dj)
              for (int di = -1; di <= 1; ++di) {
                const int l1 = std::abs(di) + std::abs(dj) + std::abs(dk);
                if (l1 == 0 || (!connect26 && l1 > 1)) continue;
                const int u = i + di, v = j + dj, w = k + dk;
                if (u < 0 || v < 0 || w < 0 || u >= n[0] || v >= n[1] || w >= n[2]) continue;
                const std::size_t m = at(n, u, v, w);
                if (expected[m] || !passable[m]) continue;
                expected[m] = 1;
                queue.push_back(m);
              }
        }
        flood_by_runs(n, connect26, marked, seeds, [&](std::size_t c) { return passable[c] != 0; });
        EXPECT_EQ(marked, expected) << n[0] << " x " << n[1] << " x " << n[2] << ", density " << density
                                    << (connect26 ? ", 26-connected" : ", 6-connected");
        floods += std::count(expected.begin(), expected.end(), 1) > static_cast<std::ptrdiff_t>(seeds.size());
      }
  EXPECT_GT(floods, 20);  // most floods went beyond their seeds
}

}  // namespace
}  // namespace gdm
