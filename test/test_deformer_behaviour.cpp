// The driver's contract: determinism across threads, the observer and
// cancellation, the generation property, and clear errors on bad input.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "gdm/deformer.h"
#include "gdm/errors.h"
#include "gdm/float_snap.h"
#include "gdm/mesh_checks.h"
#include "gdm/phantoms.h"
#include "gdm/resampler.h"
#include "gdm/seed.h"

using namespace gdm;
namespace ph = gdm::phantoms;

namespace {

struct Case {
  Volume volume;
  Vec3 seed;
};

Case branching_case() {
  ph::Grid grid;
  grid.dims = {48, 48, 48};
  const Vec3 c = grid.center();
  const auto sdf = ph::unite({ph::capsule(c + Vec3(0, 0, 12), c, 5.0), ph::capsule(c, c + Vec3(10, 0, -12), 4.0),
                              ph::capsule(c, c + Vec3(-9, 6, -12), 4.0)});
  return {ph::voxelize(grid, sdf), c + Vec3(0, 0, 8)};
}

DeformOptions options() {
  DeformOptions o;
  o.threshold = 125.0;
  return o;
}

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Deformer, results_are_identical_for_any_thread_count) {
  const Case k = branching_case();
  std::vector<Mesh> results;
  for (int threads : {1, 2, 3, 8}) {
    Mesh m = make_icosahedron(k.seed, 3.0);
    DeformOptions o = options();
    o.threads = threads;
    deform(m, k.volume, o);
    results.push_back(m);
  }
  for (std::size_t i = 1; i < results.size(); ++i) {
    ASSERT_EQ(results[i].n_vertices(), results[0].n_vertices());
    ASSERT_EQ(results[i].n_faces(), results[0].n_faces());
    for (auto v : results[0].vertices()) ASSERT_EQ(results[i].point(v), results[0].point(v)) << "vertex " << v.idx();
    auto f0 = results[0].faces_begin();
    for (auto f : results[i].faces()) {
      auto a = results[i].cfv_iter(f);
      auto b = results[0].cfv_iter(*f0++);
      for (int j = 0; j < 3; ++j, ++a, ++b) ASSERT_EQ(a->idx(), b->idx());
    }
  }
}

TEST(Deformer, observer_sees_every_cycle_and_can_cancel) {
  const Case k = branching_case();
  Mesh m = make_icosahedron(k.seed, 3.0);
  std::vector<CycleReport> seen;
  const DeformResult full = deform(m, k.volume, options(), [&](const CycleReport& r) {
    seen.push_back(r);
    return true;
  });
  ASSERT_EQ(static_cast<int>(seen.size()), full.cycles);
  for (std::size_t i = 0; i < seen.size(); ++i) {
    EXPECT_EQ(seen[i].cycle, static_cast<int>(i) + 1);
    EXPECT_LE(seen[i].moved, seen[i].evaluated);
    EXPECT_EQ(seen[i].faces, 2 * seen[i].vertices - 4);  // a closed genus-0 triangle mesh
  }
  EXPECT_GT(seen.front().moved, 0u);
  EXPECT_EQ(seen.back().moved, 0u);
  // Work proportional to the moving surface: late cycles evaluate few vertices.
  EXPECT_LT(seen.back().evaluated, seen.back().vertices / 4);

  Mesh cancelled = make_icosahedron(k.seed, 3.0);
  int calls = 0;
  const DeformResult r = deform(cancelled, k.volume, options(), [&](const CycleReport&) { return ++calls < 5; });
  EXPECT_EQ(r.reason, StopReason::cancelled);
  EXPECT_EQ(r.cycles, 5);
  EXPECT_TRUE(is_closed(cancelled));
}

TEST(Deformer, vertices_record_their_generation) {
  const Case k = branching_case();
  Mesh m = make_icosahedron(k.seed, 3.0);
  const DeformResult r = deform(m, k.volume, options());
  const auto gen = find_generation_property(m);
  ASSERT_TRUE(gen.is_valid());
  int oldest = 1 << 30, youngest = -1, seed_vertices = 0;
  for (auto v : m.vertices()) {
    const int g = m.property(gen, v);
    oldest = std::min(oldest, g);
    youngest = std::max(youngest, g);
    seed_vertices += g == 0;
  }
  EXPECT_EQ(oldest, 0);
  EXPECT_EQ(seed_vertices, 12);  // the icosahedron's vertices survive
  EXPECT_GT(youngest, 1);
  EXPECT_LE(youngest, r.cycles);
}

TEST(Deformer, max_cycles_stops_the_run) {
  const Case k = branching_case();
  Mesh m = make_icosahedron(k.seed, 3.0);
  DeformOptions o = options();
  o.max_cycles = 7;
  const DeformResult r = deform(m, k.volume, o);
  EXPECT_EQ(r.reason, StopReason::max_cycles);
  EXPECT_EQ(r.cycles, 7);
}

TEST(Deformer, bad_options_are_refused_with_the_option_named) {
  const Case k = branching_case();
  const auto run = [&](DeformOptions o) {
    return error_of([&] {
      Mesh m = make_icosahedron(k.seed, 3.0);
      deform(m, k.volume, o);
    });
  };
  DeformOptions o = options();
  o.a2 = -1.0;
  EXPECT_NE(run(o).find("a2"), std::string::npos);
  o = options();
  o.a0 = NAN;
  EXPECT_NE(run(o).find("a0"), std::string::npos);
  o = options();
  o.threshold = NAN;
  EXPECT_NE(run(o).find("threshold"), std::string::npos);
  o = options();
  o.threshold = 1e6;
  EXPECT_NE(run(o).find("outside the volume's value range"), std::string::npos);
  o = options();
  o.optimizer.min_step = 2.0;
  EXPECT_NE(run(o).find("min_step"), std::string::npos);
  o = options();
  o.lod_face_area = 0.0;
  EXPECT_NE(run(o).find("lod_face_area"), std::string::npos);
  o = options();
  o.threads = -3;
  EXPECT_NE(run(o).find("threads"), std::string::npos);
}

TEST(Deformer, bad_volumes_and_seeds_are_refused) {
  DeformOptions o = options();
  const Volume constant({8, 8, 8}, std::vector<float>(512, 3.0f));
  Mesh m = make_icosahedron(Vec3(4, 4, 4), 1.0);
  EXPECT_NE(error_of([&] { deform(m, constant, o); }).find("constant"), std::string::npos);

  const Case k = branching_case();
  Mesh outside = make_icosahedron(Vec3(200, 4, 4), 3.0);
  EXPECT_NE(error_of([&] { deform(outside, k.volume, o); }).find("outside the volume"), std::string::npos);

  Mesh in_background = make_icosahedron(Vec3(5, 5, 5), 2.0);  // a corner of the grid, no object there
  const std::string msg = error_of([&] { deform(in_background, k.volume, o); });
  EXPECT_NE(msg.find("outside the object"), std::string::npos) << msg;
  // Nothing was changed.
  EXPECT_EQ(in_background.n_vertices(), 12u);

  Mesh open = make_icosahedron(k.seed, 3.0);
  open.request_face_status();
  open.request_edge_status();
  open.request_vertex_status();
  open.delete_face(*open.faces_begin(), false);
  open.garbage_collection();
  EXPECT_THROW(deform(open, k.volume, o), InvalidSeed);
}

TEST(Deformer, stays_inside_the_volume_and_reports_the_leak) {
  // An object cut by the grid's faces: the model reaches the border and stops.
  ph::Grid grid;
  grid.dims = {24, 24, 24};
  const Volume volume = ph::voxelize(grid, ph::sphere(grid.center(), 14.0));
  Mesh m = make_icosahedron(grid.center(), 3.0);
  const DeformResult r = deform(m, volume, options());
  EXPECT_GT(r.border_vertices, 0u);
  for (auto v : m.vertices()) EXPECT_TRUE(volume.contains(to_eigen(m.point(v))));
  EXPECT_TRUE(is_closed(m));
  EXPECT_EQ(self_intersecting_pairs(m), 0u);
}

TEST(Deformer, models_end_on_float_points_unless_asked_not_to) {
  // Far from the origin, as scanner coordinates are: float spacing there is
  // about 1e-5 mm, coarse enough to matter between close sheets.
  ph::Grid grid;
  grid.dims = {40, 40, 40};
  grid.origin = Vec3(-312.4, 187.9, 1021.3);
  const Vec3 c = grid.center();
  const Volume volume = ph::voxelize(grid, ph::sphere(c, 12.0));
  for (bool snap : {true, false}) {
    Mesh m = make_icosahedron(c, 3.0);
    DeformOptions o = options();
    o.float_exact_output = snap;
    const DeformResult r = deform(m, volume, o);
    EXPECT_EQ(is_float_exact(m), snap);
    EXPECT_EQ(r.float_refused, 0u);
    EXPECT_EQ(self_intersecting_pairs(m), 0u);
  }
}

TEST(Deformer, global_refinement_never_rounds_faces_into_each_other) {
  // A tetrahedron folded flat to within one double spacing: D lies an ulp
  // above C, so faces ABC and ADB fold onto each other across AB, and ACD,
  // BDC are slivers (exactly, no two faces meet improperly). With no force
  // on the vertices (a0 far too small to lower the cost beyond rounding, a1
  // and a2 zero) and no face above the level of detail, the first stage
  // converges at once and the model is refined globally. The rounded midpoints of AC and AD are the
  // same point: the children of ABC and ADB at A fold onto each other. An MRI
  // head at the defaults refined such a spot (vertices its first stage had
  // gathered) into 104 intersecting face pairs that no later step removed.
  ph::Grid grid;
  grid.dims = {32, 32, 32};
  const Vec3 c = grid.center();
  const Volume volume = ph::voxelize(grid, ph::sphere(c, 10.0));
  const Vec3 a(c.x(), c.y(), c.z()), b(c.x() + 1.5, c.y() + 2.5, c.z()), p(c.x() + 3.0, c.y(), c.z());
  const Vec3 d(p.x(), p.y(), std::nextafter(p.z(), 1e300));
  ASSERT_NE(p.z(), d.z());
  Mesh seed;
  const auto va = seed.add_vertex(to_point(a)), vb = seed.add_vertex(to_point(b)), vc = seed.add_vertex(to_point(p)),
             vd = seed.add_vertex(to_point(d));
  seed.add_face(va, vb, vc);
  seed.add_face(va, vd, vb);
  seed.add_face(va, vc, vd);
  seed.add_face(vb, vd, vc);
  ASSERT_TRUE(is_closed(seed));
  ASSERT_EQ(self_intersecting_pairs(seed), 0u);
  Mesh refined = seed;  // what the refinement alone makes of it
  subdivide_all(refined, 1);
  ASSERT_GT(self_intersecting_pairs(refined), 0u);
  for (bool flips : {true, false}) {
    Mesh m = seed;
    DeformOptions o = options();
    o.improve_triangles = flips;
    o.a0 = 1e-20;
    o.a1 = 0.0;
    o.a2 = 0.0;
    o.float_exact_output = false;
    const DeformResult r = deform(m, volume, o);
    EXPECT_TRUE(is_closed(m));
    EXPECT_TRUE(is_two_manifold(m));
    EXPECT_EQ(self_intersecting_pairs(m), 0u);
    EXPECT_EQ(r.reason, StopReason::converged);
    EXPECT_EQ(r.global_refinements, 0);  // the refinement was undone
  }
}

// Cycles with many moves make them by blocks of space, the blocks of a
// colour on the threads at once (deformer.cpp, apply_moves): still the same
// model for any thread count. A U whose arms stand two voxels apart, so
// that the guard refuses moves where the two fronts meet; a seed of many
// small faces, so that thousands of vertices move in a cycle.
TEST(Deformer, many_moves_in_blocks_give_the_same_model_for_any_thread_count) {
  ph::Grid grid;
  grid.dims = {96, 72, 72};
  const Vec3 c = grid.center();
  const auto sdf = ph::unite({ph::capsule(c + Vec3(-11, 0, -8), c + Vec3(-11, 0, 22), 10.0),
                              ph::capsule(c + Vec3(11, 0, -8), c + Vec3(11, 0, 22), 10.0),
                              ph::capsule(c + Vec3(-11, 0, -8), c + Vec3(11, 0, -8), 10.0)});
  const Volume volume = ph::voxelize(grid, sdf);
  std::vector<Mesh> results;
  for (int threads : {1, 2, 3}) {
    Mesh m = make_geodesic_sphere(c + Vec3(0, 0, -8), 7.0, 5);  // 10,242 vertices
    DeformOptions o = options();
    o.lod_face_area = 2.0;
    o.max_cycles = 15;  // the fronts meet across the gap by then
    o.refine_channels = false;  // the cycles are under test, not what follows them
    o.subvoxel_fit = false;
    o.sharp_edges = false;
    o.min_angle = 0.0;
    o.threads = threads;
    std::size_t most_moves = 0;
    const DeformResult r = deform(m, volume, o, [&](const CycleReport& cycle) {
      most_moves = std::max(most_moves, cycle.moved);
      return true;
    });
    EXPECT_GT(most_moves, 4096u) << "no cycle moved enough vertices to go by blocks";
    EXPECT_GT(r.rejected_moves, 0u) << "the guard refused nothing: the fronts never met";
    std::printf("%d threads: %zu moves in the busiest cycle, %zu refused, %d cycles\n", threads, most_moves, r.rejected_moves, r.cycles);
    EXPECT_TRUE(is_closed(m));
    EXPECT_EQ(self_intersecting_pairs(m), 0u);
    results.push_back(m);
  }
  for (std::size_t i = 1; i < results.size(); ++i) {
    ASSERT_EQ(results[i].n_vertices(), results[0].n_vertices());
    ASSERT_EQ(results[i].n_faces(), results[0].n_faces());
    for (auto v : results[0].vertices()) ASSERT_EQ(results[i].point(v), results[0].point(v)) << "vertex " << v.idx();
  }
}
