// The exact topology (issue 15, topology.h): an enclosed cavity becomes its
// own closed component with normals into the cavity. Phantoms built here with
// noise 3 to 10 % of the contrast, distances in voxels; and the real tooth,
// whose dentin encloses the pulp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <tuple>
#include <vector>

#include "gdm/deformer.h"
#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/phantoms.h"
#include "gdm/pipeline.h"
#include "gdm/seed.h"
#include "gdm/topology.h"
#include "gdm/voxel_topology.h"
#include "mesh_expectations.h"
#include "shared_data.h"
#include "tori.h"

namespace gdm {
namespace {

namespace ph = phantoms;

constexpr double kLow = 50.0, kHigh = 200.0, kThreshold = 125.0;

// A bright spherical shell, radii `inner` to `outer` voxels, around a dark cavity.
Volume hollow_sphere(const ph::Grid& grid, double inner, double outer, double noise, unsigned seed) {
  const Vec3 c = grid.center();
  const ph::Sdf solid = ph::difference(ph::sphere(c, outer), ph::sphere(c, inner));
  return ph::with_gaussian_noise(ph::voxelize(grid, solid, kLow, kHigh - kLow), noise * (kHigh - kLow), seed);
}

// One closed component of a mesh: its vertices and its signed volume
// (positive: normals outward, negative: normals into what it encloses).
struct Component {
  std::vector<Vec3> points;
  double volume = 0.0;
};

// The edge-connected components of the faces, largest |volume| first.
std::vector<Component> split_components(const Mesh& mesh) {
  std::vector<int> label(mesh.n_faces(), -1);
  std::vector<Component> out;
  for (auto start : mesh.faces()) {
    if (label[start.idx()] >= 0) continue;
    const int id = static_cast<int>(out.size());
    out.emplace_back();
    std::vector<char> vertex_seen(mesh.n_vertices(), 0);
    std::vector<Mesh::FaceHandle> stack{start};
    label[start.idx()] = id;
    while (!stack.empty()) {
      const auto f = stack.back();
      stack.pop_back();
      std::vector<Vec3> p;
      for (auto v : mesh.fv_range(f)) {
        p.push_back(to_eigen(mesh.point(v)));
        if (!vertex_seen[v.idx()]) {
          vertex_seen[v.idx()] = 1;
          out[id].points.push_back(p.back());
        }
      }
      out[id].volume += p[0].dot(p[1].cross(p[2])) / 6.0;
      for (auto g : mesh.ff_range(f))
        if (label[g.idx()] < 0) {
          label[g.idx()] = id;
          stack.push_back(g);
        }
    }
  }
  std::sort(out.begin(), out.end(),
            [](const Component& a, const Component& b) { return std::abs(a.volume) > std::abs(b.volume); });
  return out;
}

// Distances (voxels) of a component's vertices to a sphere's surface.
ph::DistanceStats to_sphere(const Component& c, const Vec3& centre, double radius, double voxel) {
  std::vector<double> d;
  for (const Vec3& p : c.points) d.push_back(std::abs((p - centre).norm() - radius) / voxel);
  return ph::distance_stats(d);
}

DeformOptions grow(Topology topology) {
  DeformOptions o;
  o.threshold = kThreshold;
  o.topology = topology;
  return o;
}

// Closed, 2-manifold, no self-intersection (also between components), the
// genus and components agreeing with the Euler characteristic.
void expect_valid_closed_surfaces(const Mesh& mesh, int components) {
  const MeshReport r = measure(mesh);
  EXPECT_TRUE(r.closed) << to_string(r);
  EXPECT_TRUE(r.two_manifold) << to_string(r);
  EXPECT_EQ(r.self_intersections, 0u) << to_string(r);
  EXPECT_EQ(r.components, components) << to_string(r);
  EXPECT_EQ(r.genus, 0) << to_string(r);
  EXPECT_TRUE(r.euler_consistent) << to_string(r);
  EXPECT_GT(r.volume, 0.0) << to_string(r);
}

TEST(Topology, euler_consistency_of_genus_and_components) {
  EXPECT_TRUE(euler_consistent(2, 1, 0, true));    // a sphere
  EXPECT_TRUE(euler_consistent(0, 1, 1, true));    // a torus
  EXPECT_TRUE(euler_consistent(4, 2, 0, true));    // two spheres
  EXPECT_TRUE(euler_consistent(2, 2, 1, true));    // a sphere and a torus
  EXPECT_FALSE(euler_consistent(3, 1, 0, true));   // odd
  EXPECT_FALSE(euler_consistent(2, 1, 1, true));   // the genus disagrees
  EXPECT_FALSE(euler_consistent(2, 1, 0, false));  // open
  Mesh two = make_geodesic_sphere(Vec3(0, 0, 0), 2.0, 1);
  const Mesh other = make_geodesic_sphere(Vec3(10, 0, 0), 3.0, 2);
  std::vector<Mesh::VertexHandle> map;
  for (auto v : other.vertices()) map.push_back(two.add_vertex(other.point(v)));
  for (auto f : other.faces()) {
    std::vector<Mesh::VertexHandle> t;
    for (auto v : other.fv_range(f)) t.push_back(map[v.idx()]);
    two.add_face(t);
  }
  const MeshReport r = measure(two);
  EXPECT_EQ(r.components, 2);
  EXPECT_EQ(r.genus, 0);
  EXPECT_EQ(r.euler, 4);
  EXPECT_TRUE(r.euler_consistent);
}

TEST(Topology, exact_needs_the_cavity_fill) {
  ph::Grid grid;
  grid.dims = {24, 24, 24};
  const Volume v = hollow_sphere(grid, 5.0, 9.0, 0.03, 7u);
  DeformOptions o = grow(Topology::exact);
  o.fill_cavities = false;
  Mesh mesh = make_geodesic_sphere(grid.center() + Vec3(7.0, 0, 0), 1.0, 1);
  EXPECT_THROW(deform(mesh, v, o), InvalidOption);
}

// A hollow sphere (shell 3 voxels thick, radii 11 and 14) grown from a seed
// in the shell. solid: the outer sphere only, within 0.1 voxel on average and
// 1 voxel everywhere. exact: two components, the outer sphere (outward) and
// the inner sphere (inward: negative signed volume), each within 0.1 voxel on
// average; no self-intersection, also between them.
class HollowSphereTopology : public ::testing::TestWithParam<int> {};

TEST_P(HollowSphereTopology, exact_adds_the_cavity_as_an_inward_component) {
  const int noise_percent = GetParam();
  ph::Grid grid;
  grid.dims = {40, 40, 40};
  const Vec3 c = grid.center();
  const Volume v = hollow_sphere(grid, 11.0, 14.0, 0.01 * noise_percent, 140u + static_cast<unsigned>(noise_percent));
  const Vec3 seed = c + Vec3(12.5, 0.0, 0.0);

  Mesh solid = make_geodesic_sphere(seed, 1.2, 1);
  const DeformResult s = deform(solid, v, grow(Topology::solid));
  EXPECT_EQ(s.reason, StopReason::converged) << to_string(s.reason);
  EXPECT_EQ(s.cavity_components, 0u);
  test::expect_valid_closed_surface(solid);
  const ph::DistanceStats outer_only = to_sphere(split_components(solid).front(), c, 14.0, v.voxel_size());
  EXPECT_LE(outer_only.mean, 0.1);
  EXPECT_LE(outer_only.max, 1.0);

  Mesh exact = make_geodesic_sphere(seed, 1.2, 1);
  const DeformResult e = deform(exact, v, grow(Topology::exact));
  EXPECT_EQ(e.reason, StopReason::converged) << to_string(e.reason);
  EXPECT_EQ(e.topology, Topology::exact);
  EXPECT_EQ(e.cavity_components, 1u) << topology_summary(e);
  EXPECT_EQ(e.cavities_not_modelled, 0u) << topology_summary(e);
  EXPECT_EQ(e.faces, exact.n_faces());
  expect_valid_closed_surfaces(exact, 2);
  const std::vector<Component> parts = split_components(exact);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_GT(parts[0].volume, 0.0) << "the outer sphere faces outward";
  EXPECT_LT(parts[1].volume, 0.0) << "the cavity's sphere faces into the cavity";
  const ph::DistanceStats outer = to_sphere(parts[0], c, 14.0, v.voxel_size());
  const ph::DistanceStats inner = to_sphere(parts[1], c, 11.0, v.voxel_size());
  std::printf("noise %d %%: solid %zu faces, mean %.3f max %.3f; exact %zu faces (%zu in the cavity), outer mean %.3f "
              "max %.3f, inner mean %.3f max %.3f voxels; %s\n",
              noise_percent, solid.n_faces(), outer_only.mean, outer_only.max, exact.n_faces(), e.cavity_component_faces,
              outer.mean, outer.max, inner.mean, inner.max, topology_summary(e).c_str());
  EXPECT_LE(outer.mean, 0.1);
  EXPECT_LE(inner.mean, 0.1);
  EXPECT_LE(inner.max, 1.0);
  // The enclosed volume is the shell's: 4/3 pi (14^3 - 11^3) = 5,918 voxels.
  EXPECT_NEAR(measure(exact).volume, 4.0 / 3.0 * M_PI * (14.0 * 14.0 * 14.0 - 11.0 * 11.0 * 11.0), 250.0);
}

INSTANTIATE_TEST_SUITE_P(Noise, HollowSphereTopology, ::testing::Values(3, 10),
                         [](const auto& info) { return "noise" + std::to_string(info.param); });

// Two cavities of different sizes in one block, and a model the same bit for
// bit with one thread and with two.
TEST(Topology, two_cavities_two_inward_components_for_any_thread_count) {
  ph::Grid grid;
  grid.dims = {44, 30, 30};
  const Vec3 c = grid.center();
  const ph::Sdf block = ph::difference(ph::box(c - Vec3(18, 11, 11), c + Vec3(18, 11, 11)),
                                       ph::unite({ph::sphere(c - Vec3(8, 0, 0), 6.0), ph::sphere(c + Vec3(9, 0, 0), 4.0)}));
  const Volume v = ph::with_gaussian_noise(ph::voxelize(grid, block, kLow, kHigh - kLow), 0.05 * (kHigh - kLow), 77u);
  Mesh one = make_geodesic_sphere(c + Vec3(0, 0, 6), 2.0, 1);
  Mesh two = one;
  DeformOptions o = grow(Topology::exact);
  o.threads = 1;
  const DeformResult r1 = deform(one, v, o);
  o.threads = 2;
  const DeformResult r2 = deform(two, v, o);
  EXPECT_EQ(r1.cavity_components, 2u) << topology_summary(r1);
  expect_valid_closed_surfaces(one, 3);
  test::expect_same_mesh(one, two);
  EXPECT_EQ(r2.cavity_components, r1.cavity_components);
  const std::vector<Component> parts = split_components(one);
  ASSERT_EQ(parts.size(), 3u);
  EXPECT_GT(parts[0].volume, 0.0);
  EXPECT_LT(parts[1].volume, 0.0);
  EXPECT_LT(parts[2].volume, 0.0);
  const ph::DistanceStats big = to_sphere(parts[1], c - Vec3(8, 0, 0), 6.0, v.voxel_size());
  const ph::DistanceStats small = to_sphere(parts[2], c + Vec3(9, 0, 0), 4.0, v.voxel_size());
  std::printf("two cavities: %zu faces, cavity r 6 mean %.3f max %.3f, r 4 mean %.3f max %.3f voxels\n", one.n_faces(),
              big.mean, big.max, small.mean, small.max);
  EXPECT_LE(big.mean, 0.15);
  EXPECT_LE(small.mean, 0.15);
}

// The extra runs of the exact topology (each cavity's model, each opened
// handle's fit) report their cycles to the observer and stop when it says so:
// cancelled at the first cycle after the outer model, deform() says
// cancelled and leaves the outer model as it was, whole and valid.
TEST(Topology, the_extra_runs_can_be_cancelled) {
  ph::Grid grid;
  grid.dims = {40, 40, 40};
  const Volume v = hollow_sphere(grid, 11.0, 14.0, 0.05, 21u);
  const Vec3 seed = grid.center() + Vec3(12.5, 0.0, 0.0);
  int solid_calls = 0, exact_calls = 0;
  Mesh solid = make_geodesic_sphere(seed, 1.2, 1);
  const DeformResult s = deform(solid, v, grow(Topology::solid), [&](const CycleReport&) { return ++solid_calls > 0; });
  Mesh exact = make_geodesic_sphere(seed, 1.2, 1);
  const DeformResult e = deform(exact, v, grow(Topology::exact), [&](const CycleReport&) { return ++exact_calls > 0; });
  ASSERT_EQ(e.cavity_components, 1u) << topology_summary(e);
  ASSERT_GT(exact_calls, solid_calls) << "the cavity's own model reports its cycles";

  int calls = 0;
  Mesh cancelled = make_geodesic_sphere(seed, 1.2, 1);
  const DeformResult c =
      deform(cancelled, v, grow(Topology::exact), [&](const CycleReport&) { return ++calls <= solid_calls; });
  EXPECT_EQ(c.reason, StopReason::cancelled) << to_string(c.reason);
  EXPECT_EQ(calls, solid_calls + 1) << "no cycle runs after the cancel";
  EXPECT_EQ(c.cavity_components, 0u);
  test::expect_same_mesh(cancelled, solid);
  test::expect_valid_closed_surface(cancelled);
  EXPECT_EQ(s.reason, StopReason::converged);
}

// A cavity's model that the outer model does not enclose is no cavity of
// it: with a seed of half a voxel the outer model stays at its seed's size
// (the pipeline refuses such seeds; deform() is called directly here), and
// the model grown in the shell's cavity, larger than it, is not added. Before,
// it was: two components, a negative total volume.
TEST(Topology, a_cavity_model_the_outer_model_does_not_enclose_is_not_added) {
  ph::Grid grid;
  grid.dims = {40, 40, 40};
  const Volume v = hollow_sphere(grid, 11.0, 14.0, 0.05, 23u);
  Mesh mesh = make_geodesic_sphere(grid.center() + Vec3(12.5, 0.0, 0.0), 0.4, 1);
  const DeformResult r = deform(mesh, v, grow(Topology::exact));
  EXPECT_EQ(r.cavity_components, 0u) << topology_summary(r);
  EXPECT_EQ(r.cavities_not_modelled, 1u) << topology_summary(r);
  const MeshReport m = measure(mesh);
  EXPECT_EQ(m.components, 1) << to_string(m);
  EXPECT_GT(m.volume, 0.0) << to_string(m);
}

// The pipeline checks the components against the topology and reports them.
TEST(Topology, the_pipeline_reports_the_components) {
  ph::Grid grid;
  grid.dims = {40, 40, 40};
  const Volume v = hollow_sphere(grid, 11.0, 14.0, 0.05, 9u);
  PipelineOptions o;
  o.threshold_otsu = false;
  o.threshold = kThreshold;
  o.seed.kind = SeedKind::point;
  o.seed.point = grid.center() + Vec3(12.5, 0, 0);
  o.seed.radius = 1.2;
  o.deform.topology = Topology::exact;
  const PipelineResult r = extract_surface(v, o);
  ASSERT_TRUE(r.failure.empty()) << r.failure;
  EXPECT_EQ(r.report.components, 2);
  EXPECT_EQ(r.report.genus, 0);
  EXPECT_TRUE(r.report.euler_consistent);
  EXPECT_EQ(r.deform.cavity_components, 1u);
  EXPECT_TRUE(r.contacts.regions.empty()) << "the shell is 3 voxels thick: no contact";
  o.deform.topology = Topology::solid;
  const PipelineResult s = extract_surface(v, o);
  ASSERT_TRUE(s.failure.empty()) << s.failure;
  EXPECT_EQ(s.report.components, 1);
  EXPECT_TRUE(topology_summary(s.deform).empty());
}

// The whole tooth from a seed in the dentin (T 115), exact: the pulp chamber
// (if enclosed at this threshold) is its own inward component; what the data
// say is printed. Every guarantee holds and the components agree with the
// report.
TEST(Topology, the_tooth_from_the_dentin_exact) {
  Volume tooth;
  std::string why;
  if (!test::load_tooth(GDM_TEST_SHARED_DIR, tooth, why)) GTEST_SKIP() << why;
  DeformOptions o;
  o.threshold = 115.0;
  o.topology = Topology::exact;
  Mesh mesh = make_geodesic_sphere(Vec3(56.0, 56.0, 70.0), 3.0, 1);
  const DeformResult r = deform(mesh, tooth, o);
  const MeshReport m = measure(mesh);
  std::printf("tooth exact, T 115: %s; %s; %s; %s\n", to_string(m).c_str(), cavity_summary(r).c_str(),
              handle_summary(r).c_str(), topology_summary(r).c_str());
  for (const Component& c : split_components(mesh))
    std::printf("  component: %zu vertices, signed volume %.1f mm^3\n", c.points.size(), c.volume);
  EXPECT_EQ(r.reason, StopReason::converged);
  expect_valid_closed_surfaces(mesh, 1 + static_cast<int>(r.cavity_components));
}

// A torus (genus 1) or two side by side whose tubes merge (a double torus,
// genus 2): the shared phantoms (tori.h), voxelized with noise.
using Torus = test::Tori;
Torus make_torus(int holes, double noise, unsigned seed) { return test::make_tori(holes, kLow, kHigh - kLow, noise, seed); }

// The shared handle phantoms (phantoms::tori, also the benchmark study's
// topology cases) have the genus they are named for: thresholded with 5 %
// noise, one 26-connected piece, no enclosed pocket, 1 and 2 handles.
TEST(Topology, shared_tori_phantoms_have_their_genus) {
  for (const int holes : {1, 2}) {
    const Torus t = make_torus(holes, 0.05, 90u + static_cast<unsigned>(holes));
    std::vector<char> object(t.volume.values().size());
    for (std::size_t i = 0; i < object.size(); ++i) object[i] = t.volume.values()[i] > kThreshold;
    const VoxelTopology vt = voxel_topology(object, t.grid.dims);
    EXPECT_EQ(vt.pieces, 1) << holes << " hole(s)";
    EXPECT_EQ(vt.cavities, 0) << holes << " hole(s)";
    EXPECT_EQ(vt.handles(), holes) << holes << " hole(s)";
  }
}

// A torus and a double torus grown from a seed in the tube. solid: genus 0,
// one cap per hole. exact: each cap opened into a tube through its hole, the
// model's genus that of the data (1 and 2), within 0.1 voxel of the surface
// on average, no self-intersection.
class HandleTopology : public ::testing::TestWithParam<std::tuple<int, int>> {};

TEST_P(HandleTopology, exact_follows_the_genus_of_the_data) {
  const auto [holes, noise_percent] = GetParam();
  const Torus t = make_torus(holes, 0.01 * noise_percent, 160u + static_cast<unsigned>(holes * 10 + noise_percent));
  const Vec3 seed = t.holes.front() + Vec3(0.0, -t.R, 0.0);
  Mesh solid = make_geodesic_sphere(seed, 1.5, 1);
  const DeformResult s = deform(solid, t.volume, grow(Topology::solid));
  EXPECT_EQ(s.handles, static_cast<std::size_t>(holes));
  EXPECT_EQ(s.handles_opened, 0u);
  EXPECT_EQ(measure(solid).genus, 0);

  Mesh exact = make_geodesic_sphere(seed, 1.5, 1);
  const DeformResult e = deform(exact, t.volume, grow(Topology::exact));
  const MeshReport m = measure(exact);
  const ph::DistanceStats d = ph::vertex_distances(exact, [&](const Vec3& p) { return t.distance(p); }, t.volume.voxel_size());
  std::printf("%d hole(s), noise %d %%: solid %zu faces; exact %s; %s; surface mean %.3f p95 %.3f max %.3f voxels\n",
              holes, noise_percent, solid.n_faces(), to_string(m).c_str(), topology_summary(e).c_str(), d.mean, d.p95,
              d.max);
  {
    std::vector<double> in_hole, away;
    for (auto v : exact.vertices()) {
      const Vec3 p = to_eigen(exact.point(v));
      bool hole = false;
      for (const Vec3& h : t.holes) hole = hole || std::hypot(p.x() - h.x(), p.y() - h.y()) < t.R - t.r + 1.5;
      (hole ? in_hole : away).push_back(std::abs(t.distance(p)));
    }
    const ph::DistanceStats a = ph::distance_stats(in_hole), b = ph::distance_stats(away);
    std::printf("  in the holes: %zu vertices, mean %.3f p95 %.3f max %.3f; away: mean %.3f p95 %.3f max %.3f\n",
                in_hole.size(), a.mean, a.p95, a.max, b.mean, b.p95, b.max);
  }
  test::expect_genus_followed(e, exact, m, holes, d.mean, 0.1);
  // The same, bit for bit, on one thread and on two.
  DeformOptions one = grow(Topology::exact), two = one;
  one.threads = 1;
  two.threads = 2;
  Mesh a = make_geodesic_sphere(seed, 1.5, 1), b = a;
  deform(a, t.volume, one);
  deform(b, t.volume, two);
  test::expect_same_mesh(a, b);
  test::expect_same_mesh(a, exact);
}

// From the 20-face icosahedron (the benchmark study's seed) as from the
// 80-face sphere (the command's): the torus's tube met the model at its rims
// from the icosahedron (3 crossing pairs at every pull), so the handle stayed
// capped, genus 0, with no word of why; the patches are now widened by a ring
// of faces when no tube fits between their rims.
TEST(Topology, exact_opens_the_handles_from_either_seed) {
  for (const int holes : {1, 2})
    for (const int level : {0, 1}) {
      const Torus t = make_torus(holes, 0.05, 170u + static_cast<unsigned>(holes));
      Mesh mesh = make_geodesic_sphere(t.holes.front() + Vec3(0.0, -t.R, 0.0), 1.5, level);
      const DeformResult e = deform(mesh, t.volume, grow(Topology::exact));
      const MeshReport m = measure(mesh);
      const ph::DistanceStats d = ph::vertex_distances(mesh, [&](const Vec3& p) { return t.distance(p); }, t.volume.voxel_size());
      EXPECT_EQ(e.handles_opened, static_cast<std::size_t>(holes)) << holes << " hole(s), seed level " << level << ": " << topology_summary(e);
      EXPECT_EQ(m.genus, holes) << to_string(m);
      EXPECT_EQ(m.self_intersections, 0u) << to_string(m);
      EXPECT_TRUE(m.closed && m.two_manifold) << to_string(m);
      EXPECT_LE(d.mean, 0.1) << holes << " hole(s), seed level " << level;
    }
}

// A torus the scan cuts: its outer rim shaved off by the volume's +x border
// (3 voxels of the tube's 10), so the model is closed there with vertices on
// the border. exact opens the hole all the same: the model deformed again
// after the opening touches the border where the first one did, with other
// vertices and not as many (a count compared with the first's refused the
// opening: genus 0, and the summary said "0 of 1 handle(s) opened").
TEST(Topology, exact_opens_the_handle_of_a_torus_the_scan_cuts) {
  for (const int noise_percent : {3, 10}) {
    const Torus t = make_torus(1, 0.01 * noise_percent, 180u + static_cast<unsigned>(noise_percent));
    const Index3 n = t.volume.dims();
    const int keep = static_cast<int>(std::floor(t.holes.front().x() + t.R + t.r)) - 2;  // x = 0 .. keep - 1
    ASSERT_LT(keep, n[0]);
    std::vector<float> values;
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < keep; ++i) values.push_back(static_cast<float>(t.volume.at(i, j, k)));
    const Volume cut({keep, n[1], n[2]}, std::move(values), t.volume.spacing(), t.volume.origin());
    Mesh mesh = make_geodesic_sphere(t.holes.front() + Vec3(0.0, -t.R, 0.0), 1.5, 1);
    const DeformResult e = deform(mesh, cut, grow(Topology::exact));
    const MeshReport m = measure(mesh);
    std::printf("noise %d %%: %s; %zu border vertices; %s\n", noise_percent, to_string(m).c_str(), e.border_vertices,
                topology_summary(e).c_str());
    EXPECT_EQ(e.reason, StopReason::converged) << to_string(e.reason);
    EXPECT_GT(e.border_vertices, 0u);
    EXPECT_EQ(e.handles, 1u);
    EXPECT_EQ(e.handles_opened, 1u) << topology_summary(e);
    EXPECT_EQ(m.genus, 1);
    EXPECT_TRUE(m.closed);
    EXPECT_TRUE(m.two_manifold);
    EXPECT_EQ(m.self_intersections, 0u);
    EXPECT_EQ(m.components, 1);
  }
}

INSTANTIATE_TEST_SUITE_P(TorusAndDoubleTorus, HandleTopology,
                         ::testing::Combine(::testing::Values(1, 2), ::testing::Values(3, 10)), [](const auto& info) {
                           return std::string(std::get<0>(info.param) == 1 ? "torus" : "double_torus") + "_noise" +
                                  std::to_string(std::get<1>(info.param));
                         });

}  // namespace
}  // namespace gdm
