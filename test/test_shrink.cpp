// Shrink mode's automatic seed (seeding.h, issue 15): a sphere around the
// object's voxels, which may reach past the volume, where shrinking counts the
// outside as background. The box it replaces folded its edges and corners
// into fins: on a sphere phantom, 236 contact regions covering more than half
// the model's area, vertices 3.4 voxels from the surface on average.
// Phantoms built here, with noise; distances in voxels.
#include <gtest/gtest.h>

#include <cmath>

#include "gdm/phantoms.h"
#include "gdm/pipeline.h"
#include "gdm/seeding.h"
#include "gdm/self_contact.h"
#include "mesh_expectations.h"

namespace {

using namespace gdm;
namespace ph = phantoms;

constexpr double kLow = 50.0, kHigh = 200.0, kThreshold = 125.0;

PipelineOptions shrink_options() {
  PipelineOptions o;
  o.threshold_otsu = false;
  o.threshold = kThreshold;
  o.deform.mode = Mode::shrink;
  return o;
}

struct Case {
  const char* name;
  ph::Grid grid;
  ph::Sdf sdf;
  std::function<double(const Vec3&)> distance;  // to the true surface, mm
};

std::vector<Case> shapes() {
  std::vector<Case> cases;
  ph::Grid g;
  g.dims = {48, 48, 48};
  const Vec3 c = g.center();
  cases.push_back({"sphere", g, ph::sphere(c, 15.0), [c](const Vec3& p) { return (p - c).norm() - 15.0; }});
  const Vec3 radii(18.0, 12.0, 9.0);
  cases.push_back({"ellipsoid", g, ph::ellipsoid(c, radii),
                   [c, radii](const Vec3& p) { return ph::distance_to_ellipsoid(p, c, radii); }});
  ph::Grid a = g;
  a.dims = {64, 64, 24};
  a.spacing = Vec3(0.6, 0.6, 1.6);
  const Vec3 ca = a.center();
  cases.push_back({"sphere on an anisotropic grid", a, ph::sphere(ca, 13.0),
                   [ca](const Vec3& p) { return (p - ca).norm() - 13.0; }});
  return cases;
}

// Noise 3 and 8 % of the contrast: no fin (no contact), within 0.1 voxel on
// average and half a voxel at the 95th percentile, and the model's area
// within 3 % of the true surface's (fins would add area).
TEST(Shrink, the_automatic_seed_shrinks_onto_convex_shapes_without_fins) {
  unsigned seed = 60u;
  for (const Case& shape : shapes())
    for (const double noise : {0.03, 0.08}) {
      const Volume v = ph::with_gaussian_noise(ph::voxelize(shape.grid, shape.sdf, kLow, kHigh - kLow),
                                               noise * (kHigh - kLow), ++seed);
      const PipelineResult r = extract_surface(v, shrink_options());
      ASSERT_TRUE(r.failure.empty()) << shape.name << ": " << r.failure;
      EXPECT_EQ(r.choices.seed_source, "sphere");
      test::expect_valid_closed_surface(r.mesh);
      EXPECT_TRUE(r.contacts.regions.empty())
          << shape.name << " noise " << noise << ": " << describe_contacts(r.contacts).front();
      const ph::DistanceStats d = ph::vertex_distances(r.mesh, shape.distance, v.voxel_size());
      EXPECT_LE(d.mean, 0.1) << shape.name << " noise " << noise << ": p95 " << d.p95 << " max " << d.max;
      EXPECT_LE(d.p95, 0.5) << shape.name << " noise " << noise;
    }
}

// A molar-like shape (a crown and three roots that part below it, concave
// skirts between them, like the tooth's furcation) and the nerve-sized
// branching shape: a shrinking surface loses area in the concave skirts and
// folded over on itself there (pleats) until smooth_pleats (deformer.cpp).
// Noise 3 and 8 %: contacts and flaps (the model thinner than a voxel with
// background inside) on at most 0.1 % of the area, within 0.1 voxel on
// average and no vertex more than 1.5 voxels away. Measured: mean
// 0.042-0.063, max 0.24-0.96, contacts at most 0.2 mm^2. Before the needles
// (below 60 degrees, deformer.cpp) were taken in, the branching shape kept
// a few vertices 3.4 to 5.9 voxels out in the forks between its branches.
TEST(Shrink, concave_shapes_are_shrunk_onto_without_pleats) {
  ph::Grid g;
  g.dims = {64, 64, 72};
  const Vec3 c = g.center();
  const Vec3 crown = c + Vec3(0.0, 0.0, 14.0);
  std::vector<Case> cases;
  std::vector<ph::Sdf> parts{ph::ellipsoid(crown, Vec3(17.0, 14.0, 10.0))};
  for (int k = 0; k < 3; ++k) {
    const double angle = 2.0 * M_PI * k / 3.0;
    const Vec3 out(std::cos(angle), std::sin(angle), 0.0);
    parts.push_back(ph::capsule(crown + 6.0 * out, c + Vec3(0.0, 0.0, -26.0) + 16.0 * out, 5.5));
  }
  const ph::Sdf molar = ph::unite(parts);
  cases.push_back({"molar", g, molar, molar});
  ph::Grid b;
  b.dims = {64, 64, 64};
  const ph::Sdf branching = ph::branching(b.center());
  cases.push_back({"branching", b, branching, branching});
  unsigned seed = 70u;
  for (const Case& shape : cases)
    for (const double noise : {0.03, 0.08}) {
      const Volume v = ph::with_gaussian_noise(ph::voxelize(shape.grid, shape.sdf, kLow, kHigh - kLow),
                                               noise * (kHigh - kLow), ++seed);
      const PipelineResult r = extract_surface(v, shrink_options());
      ASSERT_TRUE(r.failure.empty()) << shape.name << ": " << r.failure;
      test::expect_valid_closed_surface(r.mesh);
      const double voxel = v.voxel_size();
      std::vector<Vec3> middles;
      const std::vector<char> thin = thin_faces(r.mesh, voxel, &middles);
      double flaps = 0.0;
      for (auto f : r.mesh.faces())
        if (thin[static_cast<std::size_t>(f.idx())] && shape.distance(middles[static_cast<std::size_t>(f.idx())]) > 0.0)
          flaps += r.mesh.calc_face_area(f);
      const ph::DistanceStats d = ph::vertex_distances(r.mesh, shape.distance, voxel);
      std::printf("%s noise %.0f %%: %zu faces, contacts %.1f mm^2, flaps %.1f mm^2, pleat vertices smoothed %zu; "
                  "mean %.3f p95 %.3f max %.3f voxels\n",
                  shape.name, 100.0 * noise, r.mesh.n_faces(), r.contacts.area, flaps, r.deform.pleat_vertices, d.mean,
                  d.p95, d.max);
      const double area = measure(r.mesh).area;
      EXPECT_LE(r.contacts.area, 0.001 * area) << shape.name << " noise " << noise;
      EXPECT_LE(flaps, 0.001 * area) << shape.name << " noise " << noise;
      EXPECT_LE(d.mean, 0.1) << shape.name << " noise " << noise;
      EXPECT_LE(d.max, 1.5) << shape.name << " noise " << noise;
    }
}

// The sphere through the corners of the box around the object's voxels (two
// voxels of margin): it reaches past the volume when the object fills it.
TEST(Shrink, the_seed_encloses_the_object_and_may_leave_the_volume) {
  ph::Grid g;
  g.dims = {40, 30, 20};
  const Vec3 c = g.center();
  const Volume v = ph::voxelize(g, ph::box(c - Vec3(12, 9, 6), c + Vec3(12, 9, 6)), kLow, kHigh - kLow);
  const Mesh seed = make_enclosing_sphere(v, kThreshold, Polarity::object_brighter);
  test::expect_valid_closed_surface(seed);
  double nearest = 1e9, farthest = 0.0;
  for (auto vh : seed.vertices()) {
    const double r = (to_eigen(seed.point(vh)) - c).norm();
    nearest = std::min(nearest, r);
    farthest = std::max(farthest, r);
  }
  // The object's voxels span 24 x 18 x 12 voxel centres (half extents 11.5,
  // 8.5, 5.5); two voxels of margin; the geodesic sphere's vertices lie on
  // the sphere through that box's corners.
  const double corner = Vec3(13.5, 10.5, 7.5).norm();
  EXPECT_NEAR(nearest, corner, 1e-9);
  EXPECT_NEAR(farthest, corner, 1e-9);
  EXPECT_GT(farthest, c.z() + 1.0) << "the sphere should reach past the volume along z";
  // A dark object: the same, by the object's side of T.
  std::vector<float> inverted = v.values();
  for (float& x : inverted) x = static_cast<float>(kLow + kHigh - x);
  const Volume dark(v.dims(), std::move(inverted), v.spacing(), v.origin(), v.direction());
  const Mesh dark_seed = make_enclosing_sphere(dark, kThreshold, Polarity::object_darker);
  EXPECT_EQ(dark_seed.n_vertices(), seed.n_vertices());
  EXPECT_NEAR((to_eigen(dark_seed.point(Mesh::VertexHandle(0))) - to_eigen(seed.point(Mesh::VertexHandle(0)))).norm(),
              0.0, 1e-9);
  EXPECT_THROW(make_enclosing_sphere(v, std::nan(""), Polarity::object_brighter), InvalidOption);
}

// An object the scan cuts (a cylinder through the volume's top and bottom):
// the outside counts as background, so the model closes it at the border; the
// border is then reached (a failure unless allowed, as in grow mode).
TEST(Shrink, an_object_cut_by_the_scan_is_closed_at_the_border) {
  ph::Grid g;
  g.dims = {40, 40, 30};
  const Vec3 c = g.center();
  const Volume v = ph::voxelize(g, ph::capsule(c - Vec3(0, 0, 40), c + Vec3(0, 0, 40), 10.0), kLow, kHigh - kLow);
  PipelineOptions o = shrink_options();
  const PipelineResult refused = extract_surface(v, o);
  EXPECT_NE(refused.failure.find("border"), std::string::npos) << refused.failure;
  o.allow_border = true;
  const PipelineResult r = extract_surface(v, o);
  ASSERT_TRUE(r.failure.empty()) << r.failure;
  test::expect_valid_closed_surface(r.mesh);
  EXPECT_TRUE(r.contacts.regions.empty()) << describe_contacts(r.contacts).front();
  // The side within a voxel of the cylinder; the caps at the volume's first and last slices.
  const double z_lo = v.origin().z(), z_hi = v.origin().z() + (g.dims[2] - 1) * g.spacing.z();
  for (auto vh : r.mesh.vertices()) {
    const Vec3 p = to_eigen(r.mesh.point(vh));
    const bool cap = p.z() < z_lo + 1.0 || p.z() > z_hi - 1.0;
    if (!cap) EXPECT_NEAR(std::hypot(p.x() - c.x(), p.y() - c.y()), 10.0, 1.0) << p.transpose();
    EXPECT_GT(p.z(), z_lo - 1.0);
    EXPECT_LT(p.z(), z_hi + 1.0);
  }
  EXPECT_NEAR(r.report.volume, M_PI * 100.0 * (z_hi - z_lo), 0.1 * M_PI * 100.0 * (z_hi - z_lo));
}

}  // namespace
