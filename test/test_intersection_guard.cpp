// gdm::IntersectionGuard on generated meshes: a move that would pierce (or
// touch) a neighbouring face is vetoed, a harmless one is allowed, a move that
// flips or flattens a face of the moved fan is vetoed, and every decision
// equals a brute-force check against all faces (no grid neighbourhood) as
// long as vertices stay within the margin between rebuilds.
#include <gtest/gtest.h>

#include <array>
#include <random>
#include <vector>

#include "gdm/intersection_guard.h"
#include "gdm/mesh_checks.h"
#include "gdm/predicates.h"
#include "gdm/seed.h"

using namespace gdm;

namespace {

constexpr double kMinArea = 1e-6;

// An n x n grid of unit squares at height z (two triangles each, normal +z),
// shifted by `shift` in x and y; returns the vertex handles row by row.
std::vector<Mesh::VertexHandle> add_sheet(Mesh& mesh, int n, double z, double shift) {
  std::vector<Mesh::VertexHandle> v;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) v.push_back(mesh.add_vertex(Mesh::Point(x + shift, y + shift, z)));
  const auto at = [&](int x, int y) { return v[static_cast<std::size_t>(y * (n + 1) + x)]; };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      mesh.add_face(at(x, y), at(x + 1, y), at(x + 1, y + 1));
      mesh.add_face(at(x, y), at(x + 1, y + 1), at(x, y + 1));
    }
  return v;
}

std::array<Vec3, 3> corners(const Mesh& mesh, Mesh::FaceHandle f, Mesh::VertexHandle moved, const Vec3& to,
                            std::array<int, 3>& ids) {
  std::array<Vec3, 3> t;
  int k = 0;
  for (auto v : mesh.fv_range(f)) {
    ids[k] = v.idx();
    t[k++] = v == moved ? to : to_eigen(mesh.point(v));
  }
  return t;
}

// The guard's rule without its grid: every face of the moved fan keeps its
// orientation and an area of at least kMinArea, and meets no other face of
// the mesh improperly.
bool brute_force_move_is_safe(const Mesh& mesh, Mesh::VertexHandle v, const Vec3& p) {
  std::array<int, 3> ids{}, other_ids{};
  for (auto f : mesh.vf_range(v)) {
    const auto before = corners(mesh, f, Mesh::VertexHandle(), Vec3::Zero(), ids);
    const auto after = corners(mesh, f, v, p, ids);
    const Vec3 nb = (before[1] - before[0]).cross(before[2] - before[0]);
    const Vec3 na = (after[1] - after[0]).cross(after[2] - after[0]);
    if (0.5 * na.norm() < kMinArea || na.dot(nb) <= 0.0) return false;
  }
  for (auto f : mesh.vf_range(v)) {
    const auto t = corners(mesh, f, v, p, ids);
    for (auto g : mesh.faces()) {
      if (g == f) continue;
      const auto o = corners(mesh, g, v, p, other_ids);
      if (triangles_intersect_improperly(t, ids, o, other_ids)) return false;
    }
  }
  return true;
}

Mesh::VertexHandle center_of(const std::vector<Mesh::VertexHandle>& sheet, int n) {
  return sheet[static_cast<std::size_t>((n / 2) * (n + 1) + n / 2)];
}

// Two parallel sheets of kSheetCells^2 squares, one unit apart, the upper
// shifted by 0.3 in x and y (its vertices numbered after the lower's);
// returns the lower sheet's centre vertex.
constexpr int kSheetCells = 6;
constexpr int kSheetVertices = (kSheetCells + 1) * (kSheetCells + 1);
Mesh::VertexHandle add_two_sheets(Mesh& mesh) {
  const auto lower = add_sheet(mesh, kSheetCells, 0.0, 0.0);
  add_sheet(mesh, kSheetCells, 1.0, 0.3);
  return center_of(lower, kSheetCells);
}

}  // namespace

TEST(IntersectionGuard, vetoes_a_move_that_pierces_a_neighbouring_face) {
  Mesh mesh;
  const auto v = add_two_sheets(mesh);
  IntersectionGuard guard(mesh, 0.5, kMinArea);
  const Vec3 p = to_eigen(mesh.point(v));
  // Through the upper sheet: vetoed.
  EXPECT_FALSE(guard.move_is_safe(v, p + Vec3(0, 0, 1.5)));
  // Exactly onto the upper sheet (touching a face that shares no vertex): vetoed.
  EXPECT_FALSE(guard.move_is_safe(v, p + Vec3(0.05, 0.05, 1.0)));
  EXPECT_EQ(guard.statistics().rejected_moves, 2u);
  // Up, but below the upper sheet, and down: allowed.
  EXPECT_TRUE(guard.move_is_safe(v, p + Vec3(0, 0, 0.9)));
  EXPECT_TRUE(guard.move_is_safe(v, p + Vec3(0.1, -0.2, -3.0)));
  EXPECT_EQ(guard.statistics().rejected_moves, 2u);
  EXPECT_TRUE(brute_force_move_is_safe(mesh, v, p + Vec3(0, 0, 0.9)));
  EXPECT_FALSE(brute_force_move_is_safe(mesh, v, p + Vec3(0, 0, 1.5)));
}

TEST(IntersectionGuard, vetoes_a_move_that_flips_or_flattens_a_face_of_its_fan) {
  Mesh mesh;
  const int n = 4;
  const auto sheet = add_sheet(mesh, n, 0.0, 0.0);
  IntersectionGuard guard(mesh, 0.5, kMinArea);
  const auto v = center_of(sheet, n);
  const Vec3 p = to_eigen(mesh.point(v));
  // Across its ring in the plane: faces of the fan turn over.
  EXPECT_FALSE(guard.move_is_safe(v, p + Vec3(1.5, 0.2, 0.0)));
  // Onto the far edge of a fan face: that face has zero area.
  EXPECT_FALSE(guard.move_is_safe(v, p + Vec3(1.0, 0.5, 0.0)));
  // Within the ring: allowed.
  EXPECT_TRUE(guard.move_is_safe(v, p + Vec3(0.3, -0.2, 0.4)));
  EXPECT_EQ(guard.statistics().rejected_moves, 2u);
}

// The deformer refuses a move again without a check while the faces the guard
// decided on stay put (deformer.cpp, guard_allows): it needs the face a
// refused move would cut, and -1 for a refusal by the move's own fan.
TEST(IntersectionGuard, names_the_face_a_refused_move_would_cut) {
  Mesh mesh;
  const auto v = add_two_sheets(mesh);
  IntersectionGuard guard(mesh, 0.5, kMinArea);
  const Vec3 p = to_eigen(mesh.point(v));
  const Vec3 to = p + Vec3(0, 0, 1.5);
  ASSERT_FALSE(guard.move_is_safe(v, to));
  const int blocker = guard.last_blocking_face();
  ASSERT_GE(blocker, 0);
  // It is a face of the upper sheet (no vertex of the lower one) that the
  // moved fan really cuts.
  std::array<int, 3> ids{}, fan_ids{};
  const auto other = corners(mesh, Mesh::FaceHandle(blocker), v, to, ids);
  for (int id : ids) EXPECT_GE(id, kSheetVertices);
  bool cut = false;
  for (auto f : mesh.vf_range(v))
    cut = cut || triangles_intersect_improperly(corners(mesh, f, v, to, fan_ids), fan_ids, other, ids);
  EXPECT_TRUE(cut);
  // A move that folds its own fan names no face.
  ASSERT_FALSE(guard.move_is_safe(v, p + Vec3(1.5, 0.2, 0.0)));
  EXPECT_EQ(guard.last_blocking_face(), -1);
  // A refusal counted without a check shows in the statistics.
  guard.count_rejected_move();
  EXPECT_EQ(guard.statistics().rejected_moves, 3u);
}

TEST(IntersectionGuard, vetoes_a_flip_whose_new_edge_pierces_a_face) {
  // Two faces folded into a valley along v0-v1; the flip makes a ridge along
  // a-b. A separate thin vertical triangle stands between valley and ridge:
  // the flip is vetoed with it and allowed without it.
  for (bool with_obstacle : {true, false}) {
    Mesh mesh;
    const auto v0 = mesh.add_vertex(Mesh::Point(0, 0, 0));
    const auto v1 = mesh.add_vertex(Mesh::Point(2, 0, 0));
    const auto a = mesh.add_vertex(Mesh::Point(1, 1, 1));
    const auto b = mesh.add_vertex(Mesh::Point(1, -1, 1));
    mesh.add_face(v0, v1, a);
    mesh.add_face(v1, v0, b);
    if (with_obstacle)
      mesh.add_face(mesh.add_vertex(Mesh::Point(0.95, 0, 0.2)), mesh.add_vertex(Mesh::Point(1.05, 0, 0.2)),
                    mesh.add_vertex(Mesh::Point(1, 0, 1.5)));
    IntersectionGuard guard(mesh, 0.1, kMinArea);
    Mesh::EdgeHandle e;
    for (auto h : mesh.halfedges())
      if (!mesh.is_boundary(mesh.edge_handle(h)) && mesh.from_vertex_handle(h) != a &&
          mesh.from_vertex_handle(h) != b && mesh.to_vertex_handle(h) != a && mesh.to_vertex_handle(h) != b)
        e = mesh.edge_handle(h);
    ASSERT_TRUE(e.is_valid());
    // The resampler's quad: {from, opposite apex, to, apex} of halfedge 0.
    const auto h0 = mesh.halfedge_handle(e, 0), h1 = mesh.halfedge_handle(e, 1);
    const Mesh::VertexHandle quad[4] = {mesh.from_vertex_handle(h0),
                                        mesh.to_vertex_handle(mesh.next_halfedge_handle(h1)),
                                        mesh.to_vertex_handle(h0),
                                        mesh.to_vertex_handle(mesh.next_halfedge_handle(h0))};
    EXPECT_EQ(guard.flip_is_safe(e, quad), !with_obstacle) << "obstacle " << with_obstacle;
    EXPECT_EQ(guard.statistics().rejected_flips, with_obstacle ? 1u : 0u);
  }
}

TEST(IntersectionGuard, decisions_equal_a_brute_force_check_of_all_faces) {
  // Random moves on two close sheets and on a sphere, each vertex kept within
  // the margin of where it was at the last rebuild; accepted moves are applied.
  struct Case {
    const char* name;
    Mesh mesh;
    double margin;
  };
  std::vector<Case> cases;
  {
    Mesh sheets;
    add_sheet(sheets, 5, 0.0, 0.0);
    add_sheet(sheets, 5, 0.35, 0.4);
    cases.push_back({"two sheets", std::move(sheets), 0.4});
  }
  cases.push_back({"sphere", make_geodesic_sphere(Vec3(1, 2, 3), 2.0, 2), 0.6});

  std::mt19937 rng(31337);
  for (auto& c : cases) {
    Mesh& mesh = c.mesh;
    IntersectionGuard guard(mesh, c.margin, kMinArea);
    std::vector<Vec3> anchor;
    for (auto v : mesh.vertices()) anchor.push_back(to_eigen(mesh.point(v)));
    std::uniform_int_distribution<int> pick(0, static_cast<int>(mesh.n_vertices()) - 1);
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::uniform_real_distribution<double> length(0.0, c.margin);
    int accepted = 0, rejected = 0;
    for (int i = 0; i < 3000; ++i) {
      if (i % 150 == 0) {
        guard.rebuild();
        for (auto v : mesh.vertices()) anchor[static_cast<std::size_t>(v.idx())] = to_eigen(mesh.point(v));
      }
      const Mesh::VertexHandle v(pick(rng));
      const Vec3 dir = Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized();
      const Vec3 p = anchor[static_cast<std::size_t>(v.idx())] + length(rng) * dir;
      const bool safe = guard.move_is_safe(v, p);
      ASSERT_EQ(safe, brute_force_move_is_safe(mesh, v, p)) << c.name << ", move " << i;
      if (safe) {
        mesh.set_point(v, to_point(p));
        ++accepted;
      } else {
        ++rejected;
      }
    }
    EXPECT_GT(accepted, 300) << c.name;
    EXPECT_GT(rejected, 100) << c.name;
    EXPECT_EQ(guard.statistics().rejected_moves, static_cast<std::size_t>(rejected)) << c.name;
  }
}

TEST(IntersectionGuard, decisions_stay_exact_across_prepare_moves_with_moves_and_flips_between) {
  // Rounds of random moves (each vertex within the margin of where the round
  // began) and flips; prepare_moves() between rounds looks only at the faces
  // of the moves and flips it allowed: every decision must still equal the
  // brute-force check, far more rounds than a rebuild would be needed.
  Mesh mesh = make_geodesic_sphere(Vec3(-1, 0.5, 2), 2.0, 2);
  const double margin = 0.3;
  IntersectionGuard guard(mesh, margin, kMinArea);
  std::vector<Vec3> anchor;
  for (auto v : mesh.vertices()) anchor.push_back(to_eigen(mesh.point(v)));
  std::mt19937 rng(4242);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(mesh.n_vertices()) - 1);
  std::uniform_int_distribution<int> pick_edge(0, static_cast<int>(mesh.n_edges()) - 1);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> length(0.0, margin);
  int accepted = 0, rejected = 0, flips = 0;
  for (int round = 0; round < 60; ++round) {
    guard.prepare_moves();
    for (auto v : mesh.vertices()) anchor[static_cast<std::size_t>(v.idx())] = to_eigen(mesh.point(v));
    for (int i = 0; i < 40; ++i) {
      const Mesh::VertexHandle v(pick(rng));
      const Vec3 dir = Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized();
      const Vec3 p = anchor[static_cast<std::size_t>(v.idx())] + length(rng) * dir;
      const bool safe = guard.move_is_safe(v, p);
      ASSERT_EQ(safe, brute_force_move_is_safe(mesh, v, p)) << "round " << round << ", move " << i;
      if (safe) {
        mesh.set_point(v, to_point(p));
        ++accepted;
      } else {
        ++rejected;
      }
    }
    for (int i = 0; i < 5; ++i) {
      const Mesh::EdgeHandle e(pick_edge(rng));
      if (!mesh.is_flip_ok(e)) continue;
      const auto h0 = mesh.halfedge_handle(e, 0), h1 = mesh.halfedge_handle(e, 1);
      const Mesh::VertexHandle quad[4] = {mesh.from_vertex_handle(h0), mesh.to_vertex_handle(mesh.next_halfedge_handle(h1)),
                                          mesh.to_vertex_handle(h0), mesh.to_vertex_handle(mesh.next_halfedge_handle(h0))};
      if (mesh.valence(quad[0]) <= 3 || mesh.valence(quad[2]) <= 3) continue;
      if (!guard.flip_is_safe(e, quad)) continue;
      mesh.flip(e);
      ++flips;
    }
  }
  EXPECT_GT(accepted, 300);
  EXPECT_GT(rejected, 50);
  EXPECT_GT(flips, 10);
}

namespace {

// Every face keeps its orientation and at least kMinArea against `before`.
bool faces_keep_shape(const Mesh& before, const Mesh& after) {
  std::array<int, 3> ids{};
  for (auto f : after.faces()) {
    const auto a = corners(before, f, Mesh::VertexHandle(), Vec3::Zero(), ids);
    const auto b = corners(after, f, Mesh::VertexHandle(), Vec3::Zero(), ids);
    const Vec3 na = (a[1] - a[0]).cross(a[2] - a[0]), nb = (b[1] - b[0]).cross(b[2] - b[0]);
    if (0.5 * nb.norm() < kMinArea || nb.dot(na) <= 0.0) return false;
  }
  return true;
}

}  // namespace

// apply_moves(): all moves of a round at once, checked in parallel. Random
// moves of every vertex within the margin, on two close sheets (which the
// moves push into each other) and on a sphere: the mesh after the round has no
// improper intersection and no face turned over or flattened, many moves stay
// and some go back, and the outcome is the same for one thread and for two.
TEST(IntersectionGuard, moves_applied_at_once_leave_a_valid_mesh_the_same_for_any_thread_count) {
  std::vector<std::pair<const char*, Mesh>> cases;
  {
    Mesh sheets;
    add_sheet(sheets, 16, 0.0, 0.0);
    add_sheet(sheets, 16, 0.3, 0.4);
    cases.emplace_back("two sheets", std::move(sheets));
  }
  cases.emplace_back("sphere", make_geodesic_sphere(Vec3(1, 2, 3), 2.0, 3));
  for (auto& [name, start] : cases) {
    ASSERT_EQ(self_intersecting_pairs(start, 1), 0u) << name;
    const double margin = 0.4;
    std::mt19937 rng(4242);
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::uniform_real_distribution<double> length(0.0, margin);
    std::vector<IntersectionGuard::Move> moves;
    for (auto v : start.vertices())
      moves.push_back({v.idx(), to_eigen(start.point(v)) +
                                    length(rng) * Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized()});
    std::vector<std::vector<char>> kept;
    std::vector<Mesh> results;
    for (int threads : {1, 2}) {
      Mesh mesh = start;
      IntersectionGuard guard(mesh, margin, kMinArea);
      std::vector<int> blocking;
      kept.push_back(guard.apply_moves(mesh, moves, threads, &blocking));
      const auto& k = kept.back();
      std::size_t stayed = 0;
      for (std::size_t i = 0; i < moves.size(); ++i) {
        const Vec3 p = to_eigen(mesh.point(Mesh::VertexHandle(moves[i].vertex)));
        EXPECT_EQ(p, k[i] ? moves[i].to : to_eigen(start.point(Mesh::VertexHandle(moves[i].vertex))))
            << name << ", move " << i;
        if (!k[i] && blocking[i] >= 0) EXPECT_LT(blocking[i], static_cast<int>(mesh.n_faces()));
        stayed += k[i] ? 1 : 0;
      }
      EXPECT_EQ(self_intersecting_pairs(mesh, 1), 0u) << name << ", " << threads << " thread(s)";
      EXPECT_TRUE(faces_keep_shape(start, mesh)) << name;
      EXPECT_GT(stayed, moves.size() / 4) << name;
      EXPECT_LT(stayed, moves.size()) << name;
      EXPECT_EQ(guard.statistics().rejected_moves, moves.size() - stayed) << name;
      results.push_back(std::move(mesh));
    }
    EXPECT_EQ(kept[0], kept[1]) << name;
  }
}
