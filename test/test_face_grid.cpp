// gdm::FaceGrid on generated triangles: for_each_near visits exactly the
// faces whose (margin-inflated) boxes meet the query box, each once, and
// any_near sees the same faces; both compared with a brute-force scan.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

#include "gdm/face_grid.h"
#include "gdm/seed.h"

using namespace gdm;

namespace {

struct Box {
  Vec3 lo, hi;
};

bool boxes_meet(const Box& a, const Box& b) {  // closed boxes: touching counts
  for (int i = 0; i < 3; ++i)
    if (a.lo[i] > b.hi[i] || a.hi[i] < b.lo[i]) return false;
  return true;
}

// Triangles with corners on a 0.25 lattice (so that boxes often touch cell
// boundaries and each other exactly), sizes from a point to several cells,
// around the origin (negative cell indices too).
std::vector<std::array<Vec3, 3>> random_triangles(std::mt19937& rng, int count) {
  std::uniform_int_distribution<int> where(-40, 40), step(-12, 12);
  const auto lattice = [](int i) { return 0.25 * i; };
  std::vector<std::array<Vec3, 3>> tris;
  for (int i = 0; i < count; ++i) {
    const Vec3 a(lattice(where(rng)), lattice(where(rng)), lattice(where(rng)));
    const auto corner = [&]() -> Vec3 { return a + Vec3(lattice(step(rng)), lattice(step(rng)), lattice(step(rng))); };
    tris.push_back({a, corner(), corner()});
  }
  return tris;
}

Box bounds(const std::array<Vec3, 3>& t, double margin) {
  Box b{t[0].cwiseMin(t[1]).cwiseMin(t[2]), t[0].cwiseMax(t[1]).cwiseMax(t[2])};
  b.lo.array() -= margin;
  b.hi.array() += margin;
  return b;
}

// The mesh's faces whose boxes (with the margin) meet q, ascending: what a
// grid over the mesh as it is now must offer for q (a brute-force scan).
std::vector<int> faces_meeting(const Mesh& mesh, double margin, const Box& q) {
  std::vector<int> out;
  for (auto f : mesh.faces()) {
    std::array<Vec3, 3> t;
    int k = 0;
    for (auto v : mesh.fv_range(f)) t[k++] = to_eigen(mesh.point(v));
    if (boxes_meet(bounds(t, margin), q)) out.push_back(f.idx());
  }
  return out;
}

// What for_each_near visits for q: each face once, and among them every face
// of the mesh as it is now whose box (with the margin) meets q (a grid kept
// up by refresh() may offer more).
::testing::AssertionResult visits_each_once_and_all_meeting(FaceGrid& grid, const Mesh& mesh, double margin,
                                                            const Box& q) {
  const std::vector<int> expected = faces_meeting(mesh, margin, q);
  std::vector<int> visited;
  grid.for_each_near(q.lo, q.hi, [&](int f) { visited.push_back(f); });
  std::sort(visited.begin(), visited.end());
  if (std::unique(visited.begin(), visited.end()) != visited.end())
    return ::testing::AssertionFailure() << "a face visited twice";
  if (!std::includes(visited.begin(), visited.end(), expected.begin(), expected.end()))
    return ::testing::AssertionFailure() << "a face meeting the query not visited";
  return ::testing::AssertionSuccess();
}

Box random_query(std::mt19937& rng) {
  std::uniform_int_distribution<int> where(-48, 48), size(0, 20);
  Box q;
  for (int i = 0; i < 3; ++i) {
    q.lo[i] = 0.25 * where(rng);
    q.hi[i] = q.lo[i] + 0.25 * size(rng);  // size 0: a flat box or a point
  }
  return q;
}

}  // namespace

TEST(FaceGrid, for_each_near_visits_exactly_the_faces_whose_boxes_meet_the_query) {
  std::mt19937 rng(2024);
  for (double cell : {0.5, 1.0, 2.75, 20.0}) {
    for (double margin : {0.0, 0.25}) {
      const auto tris = random_triangles(rng, 500);
      FaceGrid grid;
      grid.reset(cell, margin);
      std::vector<Box> boxes;
      for (std::size_t f = 0; f < tris.size(); ++f) {
        boxes.push_back(bounds(tris[f], margin));
        const Box raw = bounds(tris[f], 0.0);
        grid.insert_box(static_cast<int>(f), raw.lo, raw.hi);
      }
      std::size_t found_total = 0;
      for (int i = 0; i < 400; ++i) {
        const Box q = random_query(rng);
        std::vector<int> expected;
        for (std::size_t f = 0; f < boxes.size(); ++f)
          if (boxes_meet(boxes[f], q)) expected.push_back(static_cast<int>(f));
        std::vector<int> visited;
        grid.for_each_near(q.lo, q.hi, [&](int f) { visited.push_back(f); });
        std::vector<int> sorted = visited;
        std::sort(sorted.begin(), sorted.end());
        EXPECT_TRUE(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end())
            << "a face visited twice; cell " << cell << " margin " << margin << " query " << i;
        EXPECT_EQ(sorted, expected) << "cell " << cell << " margin " << margin << " query " << i;
        found_total += expected.size();
        for (std::size_t f = 0; f < boxes.size(); ++f)
          EXPECT_EQ(grid.box_meets(static_cast<int>(f), q.lo, q.hi), boxes_meet(boxes[f], q));
      }
      EXPECT_GT(found_total, 200u);  // the queries do hit faces
    }
  }
}

TEST(FaceGrid, any_near_sees_the_same_faces_as_for_each_near) {
  std::mt19937 rng(77);
  const auto tris = random_triangles(rng, 250);
  FaceGrid grid;
  grid.reset(1.5, 0.25);
  std::vector<Box> boxes;
  for (std::size_t f = 0; f < tris.size(); ++f) {
    boxes.push_back(bounds(tris[f], 0.25));
    const Box raw = bounds(tris[f], 0.0);
    grid.insert_box(static_cast<int>(f), raw.lo, raw.hi);
  }
  std::uniform_int_distribution<int> pick(0, static_cast<int>(tris.size()) - 1);
  int hits = 0, misses = 0;
  for (int i = 0; i < 500; ++i) {
    const Box q = random_query(rng);
    std::set<int> expected;
    for (std::size_t f = 0; f < boxes.size(); ++f)
      if (boxes_meet(boxes[f], q)) expected.insert(static_cast<int>(f));
    // Every face, repeats allowed, with a test that never stops the walk.
    std::set<int> seen;
    EXPECT_FALSE(grid.any_near(q.lo, q.hi, [&](int f) {
      seen.insert(f);
      return false;
    }));
    EXPECT_EQ(seen, expected) << "query " << i;
    // A test that is true for a few chosen faces: true exactly when one of them meets the box.
    const std::set<int> chosen{pick(rng), pick(rng), pick(rng), pick(rng), pick(rng), pick(rng)};
    bool want = false;
    for (int f : chosen) want = want || expected.count(f) > 0;
    const bool got = grid.any_near(q.lo, q.hi, [&](int f) { return chosen.count(f) > 0; });
    EXPECT_EQ(got, want) << "query " << i;
    (want ? hits : misses) += 1;
  }
  EXPECT_GT(hits, 0);
  EXPECT_GT(misses, 0);
}

TEST(FaceGrid, rebuild_registers_every_mesh_face_with_the_margin) {
  const Mesh mesh = make_geodesic_sphere(Vec3(3, -2, 1), 5.0, 2);
  const double margin = 0.3;
  FaceGrid grid;
  grid.rebuild(mesh, 1.2, margin);
  std::vector<Box> boxes;
  for (auto f : mesh.faces()) {
    std::array<Vec3, 3> t;
    int k = 0;
    for (auto v : mesh.fv_range(f)) t[k++] = to_eigen(mesh.point(v));
    boxes.push_back(bounds(t, margin));
  }
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> where(-4.0, 10.0), size(0.0, 2.0);
  for (int i = 0; i < 300; ++i) {
    Box q;
    q.lo = Vec3(where(rng), where(rng) - 5.0, where(rng) - 3.0);
    q.hi = q.lo + Vec3(size(rng), size(rng), size(rng));
    std::vector<int> expected, visited;
    for (std::size_t f = 0; f < boxes.size(); ++f)
      if (boxes_meet(boxes[f], q)) expected.push_back(static_cast<int>(f));
    grid.for_each_near(q.lo, q.hi, [&](int f) { visited.push_back(f); });
    std::sort(visited.begin(), visited.end());
    EXPECT_EQ(visited, expected) << "query " << i;
  }
  // A face re-registered after a move is found at its new place (and, an
  // extra entry being harmless, possibly still at its old one).
  const Vec3 far(100, 100, 100);
  grid.insert_box(0, far, far + Vec3::Ones());
  bool found = false;
  grid.for_each_near(far, far, [&](int f) { found = found || f == 0; });
  EXPECT_TRUE(found);
}

// refresh() (the deformer's per-cycle update) keeps the grid complete: after
// rounds of moves of up to the margin, a second box registered for a face (as
// a flip does) and faces added by a split, every query visits, once each, every
// face whose current box inflated by the margin meets it (and possibly faces
// whose registered box is larger than their current one: a face shrunk in
// place keeps its box).
TEST(FaceGrid, refresh_after_moves_and_splits_finds_every_face_a_rebuild_would) {
  Mesh mesh = make_geodesic_sphere(Vec3(1, 2, -3), 5.0, 2);
  const double margin = 0.2;
  FaceGrid grid;
  grid.rebuild(mesh, 1.2, margin);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), where(-5.0, 7.0), size(0.0, 2.0);
  std::uniform_int_distribution<int> coin(0, 9);
  for (int round = 0; round < 6; ++round) {
    for (auto v : mesh.vertices())
      if (coin(rng) < 1) {  // a tenth of the vertices: refresh declines past half the faces
        const Vec3 d(unit(rng), unit(rng), unit(rng));
        mesh.set_point(v, mesh.point(v) + to_point(margin * d / std::max(1.0, d.norm())));
      }
    if (round == 2) {  // a split adds faces; register_new_faces must find them
      const auto e = *mesh.edges_begin();
      const auto h = mesh.halfedge_handle(e, 0);
      const auto mid = mesh.add_vertex(0.5 * (mesh.point(mesh.from_vertex_handle(h)) + mesh.point(mesh.to_vertex_handle(h))));
      mesh.split(e, mid);
      grid.register_new_faces(mesh);
    }
    if (round == 4) grid.insert_box(3, Vec3(40, 40, 40), Vec3(41, 41, 41));  // a second box: registered again
    ASSERT_TRUE(grid.refresh(mesh, margin)) << "round " << round;
    for (int i = 0; i < 200; ++i) {
      Box q;
      q.lo = Vec3(where(rng) - 1.0, where(rng), where(rng) - 6.0);
      q.hi = q.lo + Vec3(size(rng), size(rng), size(rng));
      EXPECT_TRUE(visits_each_once_and_all_meeting(grid, mesh, margin, q)) << "round " << round << " query " << i;
    }
  }
}

TEST(FaceGrid, faces_moved_across_cells_are_found_where_they_went_and_only_once) {
  // A face registered again keeps its entries in the cells its new box still
  // touches and moves the rest (FaceGrid::reregister): moves of up to three
  // cells, some back to where they were, in every direction.
  Mesh mesh = make_geodesic_sphere(Vec3(-2, 0.5, 4), 6.0, 2);
  const double margin = 0.1, cell = 1.0;
  FaceGrid grid;
  grid.rebuild(mesh, cell, margin);
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), where(-9.0, 9.0), size(0.0, 3.0);
  std::uniform_int_distribution<int> coin(0, 19);
  std::vector<std::pair<Mesh::VertexHandle, Mesh::Point>> moved_back;
  for (int round = 0; round < 8; ++round) {
    for (const auto& [v, p] : moved_back) mesh.set_point(v, p);  // back to the cells they left
    moved_back.clear();
    for (auto v : mesh.vertices())
      if (coin(rng) == 0) {  // a twentieth: under half the faces change
        moved_back.emplace_back(v, mesh.point(v));
        const Vec3 d(unit(rng), unit(rng), unit(rng));
        mesh.set_point(v, mesh.point(v) + to_point(3.0 * cell * d));
      }
    ASSERT_TRUE(grid.refresh(mesh, margin)) << "round " << round;
    for (int i = 0; i < 300; ++i) {
      Box q;
      q.lo = Vec3(where(rng) - 2.0, where(rng) + 0.5, where(rng) + 4.0);
      q.hi = q.lo + Vec3(size(rng), size(rng), size(rng));
      ASSERT_TRUE(visits_each_once_and_all_meeting(grid, mesh, margin, q)) << "round " << round << " query " << i;
      // A query inside one cell: any_near offers that cell's entries as they
      // are listed, so a face listed twice there (or left behind and added
      // again) would be offered twice.
      Box inner;
      inner.lo = (q.lo / cell).array().floor() * cell + 0.05 * cell;
      inner.hi = inner.lo + Vec3::Constant(0.5 * cell).cwiseMin(q.hi - q.lo);
      const std::vector<int> in_cell = faces_meeting(mesh, margin, inner);
      std::vector<int> offered;
      grid.any_near(inner.lo, inner.hi, [&](int f) {
        offered.push_back(f);
        return false;
      });
      std::sort(offered.begin(), offered.end());
      ASSERT_EQ(std::unique(offered.begin(), offered.end()), offered.end()) << "round " << round << " query " << i;
      ASSERT_TRUE(std::includes(offered.begin(), offered.end(), in_cell.begin(), in_cell.end()))
          << "round " << round << " query " << i;
    }
  }
}

TEST(FaceGrid, renumber_after_collapses_and_garbage_collection_finds_every_face_a_rebuild_would) {
  Mesh mesh = make_geodesic_sphere(Vec3(-2, 1, 4), 5.0, 3);
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_halfedge_status();
  mesh.request_face_status();
  const double margin = 0.05;
  FaceGrid grid;
  grid.rebuild(mesh, 1.0, margin);
  std::mt19937 rng(23);
  std::uniform_int_distribution<int> coin(0, 19);
  // Every twentieth edge collapsed where OpenMesh allows it; the faces around
  // each kept vertex registered with their new boxes, as a caller keeping
  // the grid current does.
  std::size_t collapses = 0;
  for (auto e : mesh.edges()) {
    if (mesh.status(e).deleted() || coin(rng) != 0) continue;
    const auto h = mesh.halfedge_handle(e, 0);
    if (!mesh.is_collapse_ok(h)) continue;
    const auto kept = mesh.to_vertex_handle(h);
    mesh.collapse(h);
    for (auto f : mesh.vf_range(kept)) grid.insert(mesh, f);
    ++collapses;
  }
  ASSERT_GT(collapses, 20u);
  const std::size_t before = mesh.n_faces();
  std::vector<Mesh::FaceHandle> all;
  for (std::size_t i = 0; i < before; ++i) all.emplace_back(static_cast<int>(i));
  std::vector<Mesh::VertexHandle*> vertices;
  std::vector<Mesh::HalfedgeHandle*> halfedges;
  std::vector<Mesh::FaceHandle*> faces;
  for (auto& f : all) faces.push_back(&f);
  mesh.garbage_collection(vertices, halfedges, faces);
  ASSERT_EQ(mesh.n_faces(), before - 2 * collapses);
  std::vector<int> to;
  for (const auto& f : all) to.push_back(f.is_valid() ? f.idx() : -1);
  grid.renumber(to, mesh.n_faces());
  std::uniform_real_distribution<double> where(-8.0, 10.0), size(0.0, 2.0);
  for (int i = 0; i < 400; ++i) {
    Box q;
    q.lo = Vec3(where(rng) - 2.0, where(rng) - 1.0, where(rng) + 2.0);
    q.hi = q.lo + Vec3(size(rng), size(rng), size(rng));
    const std::vector<int> expected = faces_meeting(mesh, margin, q);
    std::vector<int> visited;
    grid.for_each_near(q.lo, q.hi, [&](int f) { visited.push_back(f); });
    std::sort(visited.begin(), visited.end());
    EXPECT_EQ(std::unique(visited.begin(), visited.end()), visited.end()) << "query " << i;
    ASSERT_TRUE(visited.empty() || (visited.front() >= 0 && static_cast<std::size_t>(visited.back()) < mesh.n_faces()))
        << "query " << i << " was offered a face that is gone";
    EXPECT_TRUE(std::includes(visited.begin(), visited.end(), expected.begin(), expected.end())) << "query " << i;
  }
  // A numbering that moves a face up is not a garbage collection's.
  std::vector<int> up(mesh.n_faces());
  for (std::size_t i = 0; i < up.size(); ++i) up[i] = static_cast<int>(i);
  std::swap(up[0], up[1]);
  EXPECT_THROW(grid.renumber(up, mesh.n_faces()), std::invalid_argument);
}

// The walk's cell set (cell_lists.h): against std::set over passes of
// random keys, with growth inside a pass and passes of every size after it.
TEST(CellSet, each_pass_holds_exactly_the_cells_added_in_it) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> coordinate(-40, 40);
  gdm::CellSet cells;
  for (int pass = 0; pass < 60; ++pass) {
    cells.start_pass();
    std::set<gdm::CellKey> truth;
    const int adds = pass % 3 == 0 ? 5000 : 30;  // every third pass grows the table
    for (int k = 0; k < adds; ++k) {
      const gdm::CellKey key = gdm::cell_key(coordinate(rng), coordinate(rng), coordinate(rng) / 8);
      ASSERT_EQ(cells.insert(key), truth.insert(key).second) << "pass " << pass << " add " << k;
    }
    for (gdm::CellKey key : truth) ASSERT_FALSE(cells.insert(key)) << "pass " << pass;
  }
}
