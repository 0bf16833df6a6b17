// The gap size G (passage.h): openings narrower than G are bridged, channels
// wider than G are followed (issue 14). Phantoms built here, with CT-like
// edges and noise; distances in voxels.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "gdm/deformer.h"
#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/passage.h"
#include "gdm/phantoms.h"
#include "gdm/seed.h"
#include "gdm/triangle_locator.h"
#include "marching_cubes_surface.h"
#include "shared_data.h"
#include "mesh_expectations.h"

namespace gdm {
namespace {

namespace ph = phantoms;

constexpr double kLow = 50.0, kHigh = 200.0, kThreshold = 125.0;

// An opened bottle: a spherical cavity of radius 15 voxels inside a wall 2
// voxels thick, pierced along +x by a round opening of diameter `opening`;
// the cavity and the outside are one side of T, the wall the other.
struct Bottle {
  ph::Grid grid;
  Vec3 center;
  double radius = 15.0;
  double opening = 0.0;
  Volume volume;

  // Distance of p to the opening's axis (the ray from the centre along +x).
  double from_axis(const Vec3& p) const { return std::hypot(p.y() - center.y(), p.z() - center.z()); }
  bool in_cap(const Vec3& p) const { return p.x() > center.x() && from_axis(p) < opening; }
};

Bottle make_bottle(double opening, bool cavity_dark, double noise_fraction, unsigned seed) {
  Bottle b;
  b.grid.dims = {48, 48, 48};
  b.center = b.grid.center();
  b.opening = opening;
  const Vec3 c = b.center;
  const double inner = b.radius, outer = b.radius + 2.0, half = 0.5 * opening;
  const ph::Sdf shell = [=](const Vec3& p) {
    const double r = (p - c).norm();
    return std::max(r - outer, inner - r);
  };
  const ph::Sdf hole = [=](const Vec3& p) {
    return std::max(std::hypot(p.y() - c.y(), p.z() - c.z()) - half, c.x() - p.x());
  };
  const ph::Sdf wall = ph::difference(shell, hole);
  // The wall is the bright side when the cavity is dark, and the other way round.
  const Volume clean = cavity_dark ? ph::voxelize(b.grid, wall, kLow, kHigh - kLow)
                                   : ph::voxelize(b.grid, wall, kHigh, kLow - kHigh);
  b.volume = ph::with_gaussian_noise(clean, noise_fraction * (kHigh - kLow), seed);
  return b;
}

DeformOptions bottle_options(bool cavity_dark, double gap) {
  DeformOptions o;
  o.threshold = kThreshold;
  o.polarity = cavity_dark ? Polarity::object_darker : Polarity::object_brighter;
  o.gap = gap;
  o.stop_at_border = true;
  return o;
}

void expect_bottle_filled(const Bottle& b, const Mesh& mesh, const DeformResult& r) {
  ASSERT_EQ(r.border_vertices, 0u) << "the model leaked out of the opening";
  EXPECT_EQ(r.reason, StopReason::converged) << to_string(r.reason);
  EXPECT_GT(r.gap_closed_voxels, 0u);
  test::expect_valid_closed_surface(mesh);
  std::vector<double> wall, cap;
  for (auto v : mesh.vertices()) {
    const Vec3 p = to_eigen(mesh.point(v));
    const double d = std::abs((p - b.center).norm() - b.radius);
    (b.in_cap(p) ? cap : wall).push_back(d);
  }
  ASSERT_FALSE(cap.empty());
  const ph::DistanceStats w = ph::distance_stats(wall), c = ph::distance_stats(cap);
  EXPECT_LE(w.mean, 0.15) << "opening " << b.opening << ": wall mean " << w.mean << " p95 " << w.p95;
  EXPECT_LE(c.max, 1.0) << "opening " << b.opening << ": the cap strays " << c.max << " voxels from the sphere (mean "
                        << c.mean << ")";
}

// Noise 3 and 10 % of the contrast, each with its own noise seed.
class OpenedBottle : public ::testing::TestWithParam<std::tuple<int, bool, int>> {};

TEST_P(OpenedBottle, gap_above_the_opening_bridges_it) {
  const auto [opening, dark, noise_percent] = GetParam();
  const Bottle b = make_bottle(opening, dark, 0.01 * noise_percent, 17u + static_cast<unsigned>(opening + noise_percent));
  Mesh mesh = make_geodesic_sphere(b.center, 3.0, 1);
  const DeformResult r = deform(mesh, b.volume, bottle_options(dark, opening + 2.0));
  expect_bottle_filled(b, mesh, r);
}

INSTANTIATE_TEST_SUITE_P(Openings, OpenedBottle,
                         ::testing::Combine(::testing::Values(2, 4, 6, 8), ::testing::Bool(), ::testing::Values(3, 10)),
                         [](const auto& info) {
                           return "d" + std::to_string(std::get<0>(info.param)) +
                                  (std::get<1>(info.param) ? "_dark" : "_bright") + "_noise" +
                                  std::to_string(std::get<2>(info.param));
                         });

TEST(Gap, without_a_gap_the_model_leaks_out_of_the_bottle) {
  const Bottle b = make_bottle(6, true, 0.05, 3u);
  Mesh mesh = make_geodesic_sphere(b.center, 3.0, 1);
  const DeformResult r = deform(mesh, b.volume, bottle_options(true, 0.0));
  EXPECT_EQ(r.reason, StopReason::border);
  EXPECT_GT(r.border_vertices, 0u);
  EXPECT_EQ(r.gap_closed_voxels, 0u);
}

// The gate, the caps and the channel refinement give the same mesh for any
// thread count.
TEST(Gap, same_mesh_for_any_thread_count) {
  const Bottle b = make_bottle(6, true, 0.05, 5u);
  std::vector<Vec3> first;
  for (const int threads : {1, 2}) {
    Mesh mesh = make_geodesic_sphere(b.center, 3.0, 1);
    DeformOptions o = bottle_options(true, 8.0);
    o.threads = threads;
    deform(mesh, b.volume, o);
    std::vector<Vec3> points;
    for (auto v : mesh.vertices()) points.push_back(to_eigen(mesh.point(v)));
    if (first.empty()) first = points;
    else EXPECT_EQ(points, first) << "threads " << threads;
  }
  ASSERT_FALSE(first.empty());
}

TEST(Gap, two_voxels_or_less_is_no_gate) {
  const Bottle b = make_bottle(6, true, 0.0, 3u);
  EXPECT_FALSE(gap_gate_active(0.0, b.volume));
  EXPECT_FALSE(gap_gate_active(2.0, b.volume));
  EXPECT_TRUE(gap_gate_active(2.01, b.volume));
}

TEST(Gap, seed_in_an_opening_narrower_than_the_gap_is_refused) {
  const Bottle b = make_bottle(6, true, 0.0, 3u);
  // A seed in the middle of the opening, which no ball of diameter 10 fits.
  const Vec3 in_hole = b.center + Vec3(b.radius + 1.0, 0.0, 0.0);
  Mesh mesh = make_geodesic_sphere(in_hole, 0.5, 0);
  try {
    deform(mesh, b.volume, bottle_options(true, 10.0));
    FAIL() << "a seed where no ball of the gap fits was accepted";
  } catch (const InvalidSeed& e) {
    EXPECT_NE(std::string(e.what()).find("gap"), std::string::npos) << e.what();
  }
}

// A chamber (sphere of radius 9 voxels) with three channels 20 voxels long
// beyond its wall, of widths 2, 3 and 4 voxels (round, with round ends).
struct Channels {
  ph::Grid grid;
  ph::Sdf sdf;
  Volume volume;
};

Channels make_channels(double noise_fraction, unsigned seed) {
  Channels c;
  c.grid.dims = {72, 72, 72};
  const Vec3 o = c.grid.center();
  const double chamber = 9.0, length = 20.0;
  c.sdf = ph::unite({ph::sphere(o, chamber), ph::capsule(o, o + Vec3(chamber + length - 1.0, 0, 0), 1.0),
                     ph::capsule(o, o + Vec3(0, chamber + length - 1.5, 0), 1.5),
                     ph::capsule(o, o - Vec3(0, 0, chamber + length - 2.0), 2.0)});
  c.volume = ph::with_gaussian_noise(ph::voxelize(c.grid, c.sdf, kLow, kHigh - kLow), noise_fraction * (kHigh - kLow), seed);
  return c;
}

// Distances (voxels) from the true surface (marching cubes of the noise-free
// phantom) to the model's faces.
ph::DistanceStats truth_to_model(const Channels& c, const Mesh& mesh) {
  const TriangleLocator model(triangles_of(mesh));
  std::vector<double> d;
  for (const Triangle& t : test::marching_cubes(ph::voxelize(c.grid, c.sdf, kLow, kHigh - kLow), kThreshold))
    d.push_back(model.distance(t[0]) / c.volume.voxel_size());
  return ph::distance_stats(std::move(d));
}

TEST(Gap, channels_two_to_four_voxels_wide_are_followed_to_their_ends_at_the_defaults) {
  for (const double noise : {0.03, 0.08}) {
    const Channels c = make_channels(noise, 29u);
    Mesh mesh = make_geodesic_sphere(c.grid.center(), 3.0, 1);
    DeformOptions o;
    o.threshold = kThreshold;
    o.stop_at_border = true;
    const DeformResult r = deform(mesh, c.volume, o);
    test::expect_valid_closed_surface(mesh);
    EXPECT_EQ(r.reason, StopReason::converged);
    EXPECT_GT(r.channel_rounds, 0) << "noise " << noise;
    EXPECT_GE(r.channel_faces, static_cast<std::size_t>(r.channel_rounds)) << "noise " << noise;
    const ph::DistanceStats truth = truth_to_model(c, mesh);
    const ph::DistanceStats model = ph::vertex_distances(mesh, c.sdf, c.volume.voxel_size());
    EXPECT_LE(truth.max, 1.0) << "noise " << noise << ": a channel is not followed to its end (truth to model mean "
                              << truth.mean << ", p95 " << truth.p95 << ")";
    EXPECT_LE(model.mean, 0.15) << "noise " << noise;
  }
}

// Truth-to-model max (voxels) over each channel's own surface: beyond the
// chamber along +x (two voxels wide), +y (three) and -z (four).
std::array<double, 3> channel_truth_max(const Channels& c, const Mesh& mesh) {
  const TriangleLocator model(triangles_of(mesh));
  const Vec3 o = c.grid.center();
  std::array<double, 3> worst{0.0, 0.0, 0.0};
  for (const Triangle& t : test::marching_cubes(ph::voxelize(c.grid, c.sdf, kLow, kHigh - kLow), kThreshold)) {
    const Vec3 d = t[0] - o;
    const int channel = d.x() > 10.0 ? 0 : d.y() > 10.0 ? 1 : d.z() < -10.0 ? 2 : -1;
    if (channel >= 0) worst[channel] = std::max(worst[channel], model.distance(t[0]) / c.volume.voxel_size());
  }
  return worst;
}

// The same chamber from seeds of other sizes and places, at other noise
// levels and noise draws: channel following must not hang on where the
// seed's vertices happen to fall. Seeds: icosahedra of 12, 42 and 162
// vertices, at the chamber's centre and 2.7 voxels off it; 36 runs.
// Before the held-vertex and face-centre requests (refine_where_blocked), a
// sweep like this followed every channel in 6 of 18 runs, and the three- and
// four-voxel channels were missed too. Now the channels three and four
// voxels wide are followed in every run; the two-voxel channel, at the
// resolution's limit, in 35 of these 36 (README, "Channels from any seed").
// Asserted: at most two misses.
TEST(Gap, channels_are_followed_from_seeds_of_any_size_and_place) {
  int runs = 0, followed = 0;
  for (const unsigned draw : {61u, 401u})
    for (const double noise : {0.03, 0.06, 0.10})
      for (const int level : {0, 1, 2})
        for (const int off : {0, 1}) {
          const Channels c = make_channels(noise, draw);
          Mesh mesh = make_geodesic_sphere(c.grid.center() + off * Vec3(2.0, -1.5, 1.0), 2.5 + 0.5 * level, level);
          DeformOptions o;
          o.threshold = kThreshold;
          o.stop_at_border = true;
          const DeformResult r = deform(mesh, c.volume, o);
          test::expect_valid_closed_surface(mesh);
          const std::array<double, 3> worst = channel_truth_max(c, mesh);
          const std::string run = "noise " + std::to_string(noise) + " draw " + std::to_string(draw) + " seed level " +
                                  std::to_string(level) + (off ? " off centre" : " at the centre");
          EXPECT_EQ(r.reason, StopReason::converged) << run;
          for (int k = 1; k < 3; ++k)
            EXPECT_LE(worst[k], 1.0) << run << ": the channel " << k + 2 << " voxels wide is not followed to its end";
          ++runs;
          if (worst[0] <= 1.0) ++followed;
          else std::printf("the two-voxel channel missed (%s): truth to model max %.2f voxels\n", run.c_str(), worst[0]);
        }
  std::printf("the two-voxel channel followed from %d of %d seeds\n", followed, runs);
  EXPECT_GE(followed, runs - 2);
}

// refine_channels off: the paper's behaviour, the face size decides. The
// faces of the default level of detail (about 4.8 voxels across) span the
// mouths of the two- and three-voxel channels: the model stops there.
TEST(Gap, without_refine_channels_the_face_size_decides_and_narrow_channels_are_bridged) {
  const Channels c = make_channels(0.03, 29u);
  Mesh mesh = make_geodesic_sphere(c.grid.center(), 3.0, 1);
  DeformOptions o;
  o.threshold = kThreshold;
  o.stop_at_border = true;
  o.refine_channels = false;
  const DeformResult r = deform(mesh, c.volume, o);
  test::expect_valid_closed_surface(mesh);
  EXPECT_EQ(r.reason, StopReason::converged);
  EXPECT_EQ(r.channel_rounds, 0);
  const ph::DistanceStats truth = truth_to_model(c, mesh);
  std::printf("channels without refine_channels: %zu faces, truth to model mean %.3f max %.3f voxel\n", mesh.n_faces(),
              truth.mean, truth.max);
  EXPECT_GT(truth.max, 5.0) << "a channel narrower than the faces was followed without local refinement";
}

// A chamber (sphere of radius 9 voxels) with a sheet 5 voxels thick beyond
// its wall, reached through a slit 2.5 voxels thick (the mouth, too narrow
// for faces of the level of detail); slit and sheet have rounded edges.
// With refine_channels the model follows the sheet to its end, and the faces
// it makes inside follow the sheet's thickness (channel_width.h), not the
// fine size the slit asked for.
ph::Sdf rounded_slab(const Vec3& lo, const Vec3& hi, double thickness) {
  const double r = 0.5 * thickness;
  const Vec3 mid_z(0, 0, 0.5 * (lo.z() + hi.z()));
  const ph::Sdf core = ph::box(Vec3(lo.x() + r, lo.y() + r, mid_z.z()), Vec3(hi.x() - r, hi.y() - r, mid_z.z()));
  return [core, r](const Vec3& p) { return core(p) - r; };
}

TEST(Gap, a_sheet_behind_a_narrow_mouth_is_followed_with_faces_of_its_thickness) {
  for (const double noise : {0.03, 0.08}) {
    Channels c;
    c.grid.dims = {72, 72, 48};
    const Vec3 o = c.grid.center();
    const double chamber = 9.0, length = 22.0, slit = 2.5, thickness = 5.0;
    c.sdf = ph::unite({ph::sphere(o, chamber),
                       rounded_slab(o + Vec3(0, -8, -0.5 * slit), o + Vec3(chamber + 6.0, 8, 0.5 * slit), slit),
                       rounded_slab(o + Vec3(chamber + 4.0, -12, -0.5 * thickness), o + Vec3(chamber + length, 12, 0.5 * thickness),
                                    thickness)});
    c.volume = ph::with_gaussian_noise(ph::voxelize(c.grid, c.sdf, kLow, kHigh - kLow), noise * (kHigh - kLow), 31u);
    Mesh mesh = make_geodesic_sphere(o, 3.0, 1);
    DeformOptions opt;
    opt.threshold = kThreshold;
    opt.stop_at_border = true;
    const DeformResult r = deform(mesh, c.volume, opt);
    test::expect_valid_closed_surface(mesh);
    EXPECT_EQ(r.reason, StopReason::converged) << "noise " << noise;
    EXPECT_GT(r.channel_rounds, 0) << "noise " << noise;
    const ph::DistanceStats truth = truth_to_model(c, mesh);
    EXPECT_LE(truth.max, 1.0) << "noise " << noise << ": the sheet is not followed to its end (mean " << truth.mean << ")";
    // Faces well inside the sheet (beyond the chamber and its mouth).
    std::vector<double> areas;
    for (auto f : mesh.faces()) {
      Vec3 middle = Vec3::Zero();
      for (auto v : mesh.fv_range(f)) middle += to_eigen(mesh.point(v)) / 3.0;
      if (middle.x() - o.x() < chamber + 8.0) continue;
      auto it = mesh.cfv_iter(f);
      const Vec3 a = to_eigen(mesh.point(*it)), b = to_eigen(mesh.point(*++it)), d = to_eigen(mesh.point(*++it));
      areas.push_back(0.5 * (b - a).cross(d - a).norm());
    }
    ASSERT_FALSE(areas.empty()) << "noise " << noise << ": no face in the sheet";
    std::sort(areas.begin(), areas.end());
    const double median = areas[areas.size() / 2];
    std::printf("sheet, noise %.2f: %zu faces (%zu in the sheet, median area %.2f voxel^2), truth to model mean %.3f max %.3f, %d rounds\n",
                noise, mesh.n_faces(), areas.size(), median, truth.mean, truth.max, r.channel_rounds);
    // The finest local size is 0.5 voxel^2; a sheet 5 voxels thick takes
    // faces of about 2.7 (edge half its thickness). Measured: 1.9 and 2.1;
    // with the slit's size inherited inside (before), 1.3 and 1.05.
    EXPECT_GE(median, 1.6) << "noise " << noise << ": the sheet is lined with the mouth's fine faces";
  }
}

// The benchmark study's "hole in the wall" cases: a dark cavity (a bent
// tube, a branching shape) in a bright wall 4 voxels thick with a hole of
// radius 2 voxels. At the defaults (refine_channels) the hole is a channel the model
// follows out (a leak); a gap above the hole (6 voxels) keeps it in the
// cavity, which it fits.
TEST(Gap, tube_and_branching_with_a_hole_in_the_wall_do_not_leak_with_a_gap_above_it) {
  ph::Grid grid;
  const Vec3 c = grid.center();
  struct Shape {
    const char* name;
    ph::Sdf cavity;
    Vec3 seed;
  };
  const Shape shapes[] = {
      {"bent tube", ph::bent_tube(c, 18.0, 6.0, 1.5 * M_PI), c + Vec3(18.0, 0.5, 0.0)},
      {"branching shape",
       ph::branching(c),
       c + Vec3(0, 0, 10)},
  };
  for (const Shape& shape : shapes) {
    Vec3 exit = shape.seed;
    while (shape.cavity(exit) < 0.0) exit.x() += 0.25;
    const ph::Sdf cavity = shape.cavity;
    const ph::Sdf wall = ph::difference(ph::difference([cavity](const Vec3& p) { return cavity(p) - 4.0; }, cavity),
                                        ph::capsule(exit - Vec3(2, 0, 0), exit + Vec3(8, 0, 0), 2.0));
    const Volume volume = ph::with_gaussian_noise(ph::voxelize(grid, wall, kLow, kHigh - kLow), 0.05 * (kHigh - kLow), 41u);
    DeformOptions o;
    o.threshold = kThreshold;
    o.polarity = Polarity::object_darker;
    o.stop_at_border = true;
    // The hole is a channel the model follows (refine_channels, on by default), unless the gap says otherwise.
    Mesh leaking = make_geodesic_sphere(shape.seed, 2.0, 1);
    EXPECT_EQ(deform(leaking, volume, o).reason, StopReason::border) << shape.name << ": no leak without a gap";
    o.gap = 6.0;
    Mesh mesh = make_geodesic_sphere(shape.seed, 2.0, 1);
    const DeformResult r = deform(mesh, volume, o);
    EXPECT_EQ(r.reason, StopReason::converged) << shape.name;
    EXPECT_GT(r.gap_closed_voxels, 0u) << shape.name;
    test::expect_valid_closed_surface(mesh);
    // Away from the hole, the model lies on the cavity; over it, within the wall.
    const ph::DistanceStats d = ph::vertex_distances(mesh, cavity, 1.0, [&](const Vec3& p) { return (p - exit).norm() > 4.0; });
    const ph::DistanceStats cap = ph::vertex_distances(mesh, cavity, 1.0, [&](const Vec3& p) { return (p - exit).norm() <= 4.0; });
    EXPECT_LE(d.mean, 0.15) << shape.name << " (p95 " << d.p95 << ")";
    EXPECT_LE(cap.max, 1.5) << shape.name << ": the cap over the hole strays into it";
  }
}

// The real tooth's pulp at the default settings: its canals are followed
// (issue 14).
TEST(Gap, tooth_pulp_at_the_defaults_follows_the_canals) {
  Volume tooth;
  std::string why;
  if (!test::load_tooth(GDM_TEST_SHARED_DIR, tooth, why)) GTEST_SKIP() << why;
  const Index3 s = test::kToothPulpSeed;
  // The seed the pipeline makes for a seed voxel: a sphere of two voxels.
  Mesh mesh = make_geodesic_sphere(tooth.to_physical(Vec3(s[0], s[1], s[2])), 2.0 * tooth.voxel_size(), 1);
  DeformOptions o = test::tooth_pulp_options();
  o.stop_at_border = true;
  const DeformResult r = deform(mesh, tooth, o);
  test::expect_valid_closed_surface(mesh);
  EXPECT_EQ(r.reason, StopReason::converged);
  const std::vector<char> pulp = test::tooth_pulp_voxels(tooth);
  const double voxel_volume = tooth.spacing().prod();
  const double flood = voxel_volume * static_cast<double>(std::count(pulp.begin(), pulp.end(), 1));
  const double volume = measure(mesh).volume;
  // Where the pulp is at least two voxels wide: pulp voxels whose six
  // neighbours are pulp too, and the voxels next to them. The canals' last
  // voxels, one voxel wide, are narrower than the default gap.
  const Index3& n = tooth.dims();
  const auto at = [&](int i, int j, int k) {
    return static_cast<std::size_t>(i) + static_cast<std::size_t>(n[0]) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(n[1]) * k);
  };
  const int offsets[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  std::vector<char> core(pulp.size(), 0), wide(pulp.size(), 0);
  for (int k = 1; k + 1 < n[2]; ++k)
    for (int j = 1; j + 1 < n[1]; ++j)
      for (int i = 1; i + 1 < n[0]; ++i) {
        bool inside = pulp[at(i, j, k)];
        for (const auto& o6 : offsets) inside = inside && pulp[at(i + o6[0], j + o6[1], k + o6[2])];
        core[at(i, j, k)] = inside;
      }
  for (int k = 1; k + 1 < n[2]; ++k)
    for (int j = 1; j + 1 < n[1]; ++j)
      for (int i = 1; i + 1 < n[0]; ++i)
        for (int dk = -1; dk <= 1; ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) wide[at(i, j, k)] |= core[at(i + di, j + dj, k + dk)];
  const TriangleLocator model(triangles_of(mesh));
  std::vector<double> all, in_wide;
  for (const Triangle& t : test::tooth_pulp_surface(tooth)) {
    const double e = model.distance(t[0]) / tooth.voxel_size();
    all.push_back(e);
    const Vec3 c = tooth.to_continuous_index(t[0]);
    const int i = static_cast<int>(std::lround(c.x())), j = static_cast<int>(std::lround(c.y())), k = static_cast<int>(std::lround(c.z()));
    if (i >= 0 && j >= 0 && k >= 0 && i < n[0] && j < n[1] && k < n[2] && wide[at(i, j, k)]) in_wide.push_back(e);
  }
  const ph::DistanceStats truth = ph::distance_stats(std::move(all)), wide_truth = ph::distance_stats(std::move(in_wide));
  std::printf("tooth pulp at the defaults: %zu faces, volume %.1f vs %.1f flood-filled (%+.1f %%); truth to model mean %.3f "
              "p95 %.3f max %.3f voxel, where the pulp is two voxels wide or more: max %.3f\n",
              mesh.n_faces(), volume, flood, 100.0 * (volume / flood - 1.0), truth.mean, truth.p95, truth.max, wide_truth.max);
  EXPECT_LE(std::abs(volume / flood - 1.0), 0.04);
  EXPECT_LE(truth.p95, 0.5);
  EXPECT_LE(wide_truth.max, 2.0);
}

}  // namespace
}  // namespace gdm
