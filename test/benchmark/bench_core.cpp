// Timings of the core on the phantoms of the paper's section 6 (reported, never
// asserted). Counters: cycles, final faces, evaluated vertex-cycles, and the
// time per evaluated vertex-cycle.
#include <benchmark/benchmark.h>

#include "gdm/deformer.h"
#include "gdm/phantoms.h"
#include "gdm/seed.h"

namespace {

using namespace gdm;
namespace ph = gdm::phantoms;

struct Case {
  Volume volume;
  Vec3 seed;
  double lod;
};

Case cube_case() {
  // Section 6.1: 64^3, a cube with one corner missing.
  ph::Grid grid;
  const auto sdf = ph::difference(ph::box(Vec3(12, 12, 12), Vec3(52, 52, 52)), ph::box(Vec3(32, 32, 32), Vec3(60, 60, 60)));
  return {ph::voxelize(grid, sdf), Vec3(24, 24, 24), 10.0};
}

Case nerve_case() {
  // A branching object of the size of the tooth's nerve (section 6.3), whose
  // model ends near 7,000 faces.
  ph::Grid grid;
  grid.dims = {96, 96, 150};
  const Vec3 c = grid.center() + Vec3(0, 0, 20);
  const auto sdf = ph::unite({ph::capsule(c + Vec3(0, 0, 40), c, 9.0), ph::capsule(c, c + Vec3(22, 0, -60), 6.0),
                              ph::capsule(c, c + Vec3(-20, 12, -62), 6.0), ph::capsule(c, c + Vec3(-6, -24, -58), 5.5)});
  return {ph::voxelize(grid, sdf), c + Vec3(0, 0, 30), 10.0};
}

Case head_case() {
  // Issue 17's whole-head MRI size (181 x 217 x 180 voxels of 1 mm): a scalp
  // 6 mm thick over a dark layer 7 mm thick (skull and fluid) around the
  // brain, two enclosed dark ventricles in the brain, and four bridges of
  // tissue across the dark layer. The volume cuts the head below, as a scan
  // cuts the neck, so the dark layer is open to the outside there and the
  // model grows the brain, then the scalp through the bridges, whose fronts
  // meet in the scalp: seams, as on the T1 head of ../shared/data (measured:
  // 146,400 faces, 289 cycles, one handle capped, 33,821 of 221,802 mm^2 on
  // seams). Gaussian noise, sigma 5 % of the contrast; grown from the
  // brain's centre at the defaults but the level of detail, the other cases'.
  ph::Grid grid;
  grid.dims = {181, 217, 180};
  const Vec3 c = grid.center() - Vec3(0, 0, 20);
  const Vec3 skin(72.0, 90.0, 80.0);
  const Vec3 skull = skin - Vec3::Constant(6.0), brain = skin - Vec3::Constant(13.0);
  const auto sdf = ph::unite(
      {ph::difference(ph::ellipsoid(c, skin), ph::ellipsoid(c, skull)),
       ph::difference(ph::ellipsoid(c, brain), ph::unite({ph::ellipsoid(c + Vec3(-9, 4, 6), Vec3(5, 16, 7)),
                                                        ph::ellipsoid(c + Vec3(9, 4, 6), Vec3(5, 16, 7))})),
       ph::capsule(c + Vec3(0, 0, -55), c + Vec3(0, 0, -75), 5.0), ph::capsule(c + Vec3(0, 65, -10), c + Vec3(0, 84, -12), 4.0),
       ph::capsule(c + Vec3(52, 0, 10), c + Vec3(70, 0, 12), 4.0), ph::capsule(c + Vec3(-52, -10, 10), c + Vec3(-70, -12, 12), 4.0)});
  return {ph::with_gaussian_noise(ph::voxelize(grid, sdf), 0.05 * 150.0, 17u), c + Vec3(0, -25, -10), 10.0};
}

void run(benchmark::State& state, const Case& k, bool voxel_seed = false) {
  DeformOptions options;
  options.voxel_seed = voxel_seed;  // start from the object's voxels (voxel_seed.h)
  options.threshold = 125.0;
  options.lod_face_area = k.lod;
  options.threads = static_cast<int>(state.range(0));
  options.coarse_levels = static_cast<int>(state.range(1));  // multi-resolution growth (0 = off, the default)
  std::size_t faces = 0, evaluated = 0, handles = 0;
  int cycles = 0;
  StageSeconds seconds;  // the last run's, per step
  for (auto _ : state) {
    Mesh mesh = make_icosahedron(k.seed, 3.0);
    evaluated = 0;
    const DeformResult r = deform(mesh, k.volume, options, [&](const CycleReport& c) {
      evaluated += c.evaluated;
      return true;
    });
    faces = mesh.n_faces();
    cycles = r.cycles;
    handles = r.handles;
    seconds = r.seconds;
  }
  state.counters["cycles"] = cycles;
  state.counters["faces"] = static_cast<double>(faces);
  state.counters["vertex_cycles"] = static_cast<double>(evaluated);
  state.counters["handles"] = static_cast<double>(handles);
  // Where the time went (the last iteration's steps, ms): what to optimise.
  const std::pair<const char*, double> steps[] = {
      {"ms_voxel_seed", seconds.voxel_seed}, {"ms_gap_gate", seconds.gap_gate},
      {"ms_cavity_fill", seconds.cavity_fill},
      {"ms_growth", seconds.growth},       {"ms_refinement", seconds.refinement},
      {"ms_refined", seconds.refined_stages}, {"ms_fit", seconds.fit},
      {"ms_error_lod", seconds.error_lod}, {"ms_quality", seconds.quality},
      {"ms_float_snap", seconds.float_snap}, {"ms_topology", seconds.topology}};
  for (const auto& [name, s] : steps)
    if (s > 0.0) state.counters[name] = 1000.0 * s;
  state.counters["time_per_vertex_cycle"] =
      benchmark::Counter(static_cast<double>(evaluated) * static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_cube_with_corner_missing(benchmark::State& state) {
  static const Case k = cube_case();
  run(state, k);
}

void BM_branching_nerve(benchmark::State& state) {
  static const Case k = nerve_case();
  run(state, k);
}

void BM_head_mri_size(benchmark::State& state) {
  static const Case k = head_case();
  run(state, k);
}

// The same head started from its voxels (stop 54): no seams in the scalp.
void BM_head_mri_size_voxel_seed(benchmark::State& state) {
  static const Case k = head_case();
  run(state, k, true);
}

}  // namespace

// Arguments: threads, coarse levels.
BENCHMARK(BM_cube_with_corner_missing)
    ->ArgNames({"threads", "coarse_levels"})
    ->ArgsProduct({{1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_branching_nerve)
    ->ArgNames({"threads", "coarse_levels"})
    ->ArgsProduct({{1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
// Seconds a run: one iteration each, the default level only.
BENCHMARK(BM_head_mri_size)
    ->ArgNames({"threads", "coarse_levels"})
    ->ArgsProduct({{1, 2}, {0}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_head_mri_size_voxel_seed)
    ->ArgNames({"threads", "coarse_levels"})
    ->ArgsProduct({{2}, {0}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_MAIN();
