// gdm::shrink_wrap (gdm/shrink_wrap.h) on generated inputs: several pieces, a
// holed sphere, a point cloud; its guarantees and its refusals.
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include "gdm/triangle_quality.h"

#include <iostream>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/obstacle.h"
#include "gdm/seed.h"
#include "gdm/shrink_wrap.h"
#include "gdm/triangle_locator.h"
#include "wrap_pyramids.h"

namespace {


std::vector<gdm::Triangle> sphere_soup(const gdm::Vec3& centre, double radius, int level) {
  return gdm::triangles_of(gdm::make_geodesic_sphere(centre, radius, level));
}

// The guarantees of a wrap of `input` with tolerance `tolerance`.
void expect_valid_wrap(const std::vector<gdm::Triangle>& input, const gdm::WrapResult& r, double tolerance) {
  const gdm::MeshReport m = gdm::measure(r.mesh);
  EXPECT_TRUE(m.closed);
  EXPECT_TRUE(m.two_manifold);
  EXPECT_EQ(m.genus, 0);
  EXPECT_EQ(m.components, 1);
  EXPECT_EQ(m.self_intersections, 0u);
  const std::vector<gdm::Triangle> wrap = gdm::triangles_of(r.mesh);
  const gdm::TriangleLocator to_wrap(wrap);
  double farthest = 0.0;
  for (const auto& t : input)
    for (const auto& p : t) farthest = std::max(farthest, to_wrap.distance(p));
  EXPECT_LE(farthest, tolerance);
  EXPECT_NEAR(farthest, r.farthest_input_distance, 1e-9);
  const gdm::Obstacle obstacle(input);
  std::size_t touching = 0;
  for (const auto& t : wrap) touching += obstacle.blocks(t) ? 1 : 0;
  EXPECT_EQ(touching, 0u) << "wrap faces touching the input";
}

gdm::WrapOptions options(double cell, double tolerance) {
  gdm::WrapOptions o;
  o.cell_size = cell;
  o.tolerance = tolerance;
  return o;
}

TEST(ShrinkWrap, two_separate_spheres_get_one_wrap) {
  std::vector<gdm::Triangle> input = sphere_soup(gdm::Vec3(0, 0, 0), 4.0, 2);
  const auto second = sphere_soup(gdm::Vec3(11.0, 1.0, -2.0), 4.0, 2);
  input.insert(input.end(), second.begin(), second.end());
  const gdm::WrapResult r = gdm::shrink_wrap(input, options(0.5, 1.5));
  expect_valid_wrap(input, r, 1.5);
  EXPECT_FALSE(r.notes.empty());
}

TEST(ShrinkWrap, holed_sphere_is_closed) {
  gdm::Mesh sphere = gdm::make_geodesic_sphere(gdm::Vec3(3, -2, 1), 6.0, 3);
  std::vector<gdm::Triangle> input;
  for (const auto& t : gdm::triangles_of(sphere))
    if ((t[0] + t[1] + t[2]).z() / 3.0 < 1.0 + 4.5) input.push_back(t);  // the cap above z = 5.5 removed
  ASSERT_LT(input.size(), sphere.n_faces());
  const gdm::WrapResult r = gdm::shrink_wrap(input, options(0.5, 1.5));
  expect_valid_wrap(input, r, 1.5);
}

TEST(ShrinkWrap, point_cloud_of_degenerate_triangles) {
  // Points about 0.7 mm apart: closer than twice the wrap's offset (tolerance / 3).
  const gdm::Mesh sphere = gdm::make_geodesic_sphere(gdm::Vec3(0, 0, 0), 5.0, 3);
  std::vector<gdm::Triangle> input;
  for (auto v : sphere.vertices()) {
    const gdm::Vec3 p = gdm::to_eigen(sphere.point(v));
    input.push_back({p, p, p});
  }
  const gdm::WrapResult r = gdm::shrink_wrap(input, options(0.5, 1.5));
  expect_valid_wrap(input, r, 1.5);
}

TEST(ShrinkWrap, same_wrap_for_any_thread_count) {
  // A closed sphere, and a holed one with a bridge (the bridged field, the
  // reopening and the fairing are in play).
  std::vector<gdm::Triangle> holed;
  for (const auto& t : sphere_soup(gdm::Vec3(0, 0, 0), 5.0, 3))
    if ((t[0] + t[1] + t[2]).z() / 3.0 < 3.0) holed.push_back(t);
  for (const auto& input : {sphere_soup(gdm::Vec3(0, 0, 0), 4.0, 2), holed}) {
    gdm::WrapOptions one = options(0.5, 1.5), two = one;
    one.bridge = two.bridge = input.size() == holed.size() ? 10.0 : 0.0;
    one.threads = 1;
    two.threads = 2;
    const gdm::WrapResult a = gdm::shrink_wrap(input, one), b = gdm::shrink_wrap(input, two);
    ASSERT_EQ(a.mesh.n_vertices(), b.mesh.n_vertices());
    for (std::size_t i = 0; i < a.mesh.n_vertices(); ++i)
      EXPECT_EQ(a.mesh.point(gdm::Mesh::VertexHandle(static_cast<int>(i))),
                b.mesh.point(gdm::Mesh::VertexHandle(static_cast<int>(i))));
  }
}

void expect_refused(const std::vector<gdm::Triangle>& input, const gdm::WrapOptions& o, const std::string& names) {
  try {
    gdm::shrink_wrap(input, o);
    ADD_FAILURE() << "accepted; expected a refusal naming " << names;
  } catch (const gdm::InvalidOption& e) {
    EXPECT_NE(std::string(e.what()).find(names), std::string::npos) << e.what();
  }
}

TEST(ShrinkWrap, bad_options_are_refused) {
  const auto input = sphere_soup(gdm::Vec3(0, 0, 0), 4.0, 1);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  gdm::WrapOptions o = options(0.5, 1.5);
  o.tolerance = 0.0;
  expect_refused(input, o, "tolerance must be > 0");
  o.tolerance = -1.0;
  expect_refused(input, o, "tolerance must be > 0");
  o.tolerance = nan;
  expect_refused(input, o, "tolerance must be > 0");
  o = options(0.0, 1.5);
  expect_refused(input, o, "cell_size must be > 0");
  o = options(2.0, 1.5);
  expect_refused(input, o, "must be >= cell_size");
  o = options(0.5, 1.5);
  o.coverage_rounds = -1;
  expect_refused(input, o, "coverage_rounds");
  o = options(0.5, 1.5);
  o.max_cycles = 0;
  expect_refused(input, o, "max_cycles");
  o = options(0.5, 1.5);
  o.lod_face_area = -3;
  expect_refused(input, o, "lod_face_area");
  o = options(0.5, 1.5);
  o.threads = -2;
  expect_refused(input, o, "threads");
  expect_refused({}, options(0.5, 1.5), "empty");
  auto broken = input;
  broken[3][1].x() = nan;
  expect_refused(broken, options(0.5, 1.5), "non-finite");
}

// The vertices of `wrap` within 0.8 of `hole_radius` of the z axis and above
// z = 0 (over the hole of open_sphere_soup): the largest distance from the
// least-squares quadric z = f(x, y) through them, mm; -1 when there are fewer
// than 12. A pyramid (a vertex standing an edge's height above its ring)
// shows as a residual of about an edge; a smooth cap as a small fraction of it.
double cap_roughness(const gdm::Mesh& wrap, double hole_radius, std::size_t* count) {
  std::vector<gdm::Vec3> cap;
  for (auto v : wrap.vertices()) {
    const gdm::Vec3 p = gdm::to_eigen(wrap.point(v));
    if (std::hypot(p.x(), p.y()) < 0.8 * hole_radius && p.z() > 0.0) cap.push_back(p);
  }
  *count = cap.size();
  if (cap.size() < 12) return -1.0;
  Eigen::MatrixXd a(cap.size(), 6);
  Eigen::VectorXd z(cap.size());
  for (std::size_t i = 0; i < cap.size(); ++i) {
    const gdm::Vec3& p = cap[i];
    a.row(static_cast<Eigen::Index>(i)) << 1.0, p.x(), p.y(), p.x() * p.x(), p.x() * p.y(), p.y() * p.y();
    z[static_cast<Eigen::Index>(i)] = p.z();
  }
  const Eigen::VectorXd c = a.colPivHouseholderQr().solve(z);
  return (a * c - z).cwiseAbs().maxCoeff();
}

// A sphere of radius 10 mm around the origin with the faces above z = 6
// removed: a round hole of radius 8 mm.
std::vector<gdm::Triangle> open_sphere_soup() {
  std::vector<gdm::Triangle> out;
  for (const auto& t : sphere_soup(gdm::Vec3(0, 0, 0), 10.0, 3))
    if ((t[0] + t[1] + t[2]).z() / 3.0 < 6.0) out.push_back(t);
  return out;
}

// With a bridge wider than the hole the wrap spans it with a smooth cap (the
// envelope of balls of diameter 17 mm): the cap's vertices lie within 0.5 mm
// (a cell) of a quadric, all of the wrap's guarantees kept. Without it the
// wrap sinks through the hole and crumples inside (pyramids: measured 1.3 mm
// off the quadric over the few vertices left there).
TEST(ShrinkWrap, bridge_caps_a_hole_smoothly) {
  const auto input = open_sphere_soup();
  gdm::WrapOptions o = options(0.5, 1.5);
  o.bridge = 17.0;
  const gdm::WrapResult r = gdm::shrink_wrap(input, o);
  expect_valid_wrap(input, r, 1.5);
  std::size_t count = 0;
  const double rough = cap_roughness(r.mesh, 8.0, &count);
  std::cout << "bridge 17 mm: " << count << " cap vertices, largest distance from the quadric " << rough << " mm\n";
  EXPECT_GE(count, 50u);
  EXPECT_GE(rough, 0.0);
  EXPECT_LT(rough, 0.5);
  o.bridge = 0.0;
  const gdm::WrapResult sunk = gdm::shrink_wrap(input, o);
  expect_valid_wrap(input, sunk, 1.5);
  std::cout << "no bridge: largest distance of the wrap from the input " << sunk.farthest_wrap_distance << " mm\n";
  o.bridge = -1.0;
  expect_refused(input, o, "bridge must be >= 0");
}

// A closed scan cut through by a slit 2 mm wide (the faces of a sphere of
// radius 6 mm within 1 mm of its equator removed), cell 0.25 mm, tolerance 0.75 mm: with a gap (bridge) of 3 mm the wrap is the
// solid's, no face inside the sphere; without one it enters the slit and
// lines the inside (issue 14).
TEST(ShrinkWrap, a_gap_above_a_slit_wraps_the_solid) {
  std::vector<gdm::Triangle> input;
  for (const auto& t : sphere_soup(gdm::Vec3(0, 0, 0), 6.0, 4))
    if (std::abs((t[0] + t[1] + t[2]).z() / 3.0) > 1.0) input.push_back(t);
  const auto deepest = [](const gdm::WrapResult& r) {
    double d = 6.0;
    for (auto v : r.mesh.vertices()) d = std::min(d, gdm::to_eigen(r.mesh.point(v)).norm());
    return d;
  };
  gdm::WrapOptions o = options(0.25, 0.75);
  o.bridge = 3.0;
  const gdm::WrapResult solid = gdm::shrink_wrap(input, o);
  expect_valid_wrap(input, solid, 0.75);
  EXPECT_GT(deepest(solid), 5.0) << "a wrap face lies inside the solid";
  o.bridge = 0.0;
  const gdm::WrapResult lined = gdm::shrink_wrap(input, o);
  expect_valid_wrap(input, lined, 0.75);
  EXPECT_LT(deepest(lined), 4.0) << "without a gap the wrap was expected to enter the slit";
}

// An open box: the five faces of a 20 x 14 x 10 mm box without its top, each
// split into triangles of about 1 mm (a planar hole of 20 x 14 mm at z = 10).
std::vector<gdm::Triangle> open_box() {
  std::vector<gdm::Triangle> out;
  const auto quad = [&out](const gdm::Vec3& o, const gdm::Vec3& u, const gdm::Vec3& v) {
    const int nu = static_cast<int>(std::ceil(u.norm())), nv = static_cast<int>(std::ceil(v.norm()));
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        const gdm::Vec3 a = o + u * (double(i) / nu) + v * (double(j) / nv);
        const gdm::Vec3 b = o + u * (double(i + 1) / nu) + v * (double(j) / nv);
        const gdm::Vec3 c = o + u * (double(i + 1) / nu) + v * (double(j + 1) / nv);
        const gdm::Vec3 d = o + u * (double(i) / nu) + v * (double(j + 1) / nv);
        out.push_back({a, b, c});
        out.push_back({a, c, d});
      }
  };
  const gdm::Vec3 X(20, 0, 0), Y(0, 14, 0), Z(0, 0, 10), O(0, 0, 0);
  quad(O, Y, X);          // bottom
  quad(O, X, Z);          // y = 0
  quad(O + Y, Z, X);      // y = 14
  quad(O, Z, Y);          // x = 0
  quad(O + X, Y, Z);      // x = 20
  return out;
}

// With a bridge of 10 x the tolerance the holes are capped: at most 1 in 20
// of the vertices over them stands out of its ring (measured 1 of 162 on the
// open sphere, 6 of 360 on the open box). Without a bridge (the default) the
// wrap sinks through a hole much wider than its faces and the vertices the
// field does not hold stand out like pyramids (11 of 56, 28 of 169); the
// fairing (on by default) halves their share of the free vertices (6 of 64,
// 11 of 168: the rest sit in folds where the guard refuses the move). Shares,
// not counts: the runs have different numbers of free vertices.
TEST(ShrinkWrap, no_pyramids_over_holes) {
  struct Case {
    const char* name;
    std::vector<gdm::Triangle> input;
    double cell, tolerance;
  };
  const std::vector<Case> cases = {{"open sphere", open_sphere_soup(), 0.5, 1.5}, {"open box", open_box(), 0.4, 1.2}};
  for (const auto& c : cases) {
    gdm::WrapOptions o = options(c.cell, c.tolerance);
    const double beyond = c.tolerance / 3.0 + 1.5 * c.cell;
    o.bridge = 10.0 * c.tolerance;
    const gdm::WrapResult bridged = gdm::shrink_wrap(c.input, o);
    expect_valid_wrap(c.input, bridged, c.tolerance);
    o.bridge = 0.0;
    o.fairing = false;
    const gdm::WrapResult raw = gdm::shrink_wrap(c.input, o);
    o.fairing = true;
    const gdm::WrapResult faired = gdm::shrink_wrap(c.input, o);
    expect_valid_wrap(c.input, faired, c.tolerance);
    std::size_t raw_free = 0, faired_free = 0, bridged_free = 0;
    const std::size_t before = gdm::test::pyramids(raw.mesh, c.input, beyond, &raw_free);
    const std::size_t after = gdm::test::pyramids(faired.mesh, c.input, beyond, &faired_free);
    const std::size_t capped = gdm::test::pyramids(bridged.mesh, c.input, beyond, &bridged_free);
    std::cout << c.name << ": pyramids " << before << " of " << raw_free << " free vertices without bridge or fairing, "
              << after << " of " << faired_free << " faired, " << capped << " of " << bridged_free
              << " with a bridge of 10 x the tolerance\n";
    EXPECT_GT(before, 0u) << c.name << ": no pyramids to fair (the case no longer tests anything)";
    EXPECT_LE(2.0 * static_cast<double>(after) / static_cast<double>(faired_free),
              static_cast<double>(before) / static_cast<double>(raw_free))
        << c.name;
    EXPECT_LE(after, faired_free / 6) << c.name;
    EXPECT_LE(20 * capped, bridged_free) << c.name;
  }
}

// Triangle quality (issue 16): the wrap's last step lifts every angle to
// min_angle (10 degrees by default), each operation checked against the input
// too; 0 turns it off.
TEST(ShrinkWrap, smallest_angle_reaches_min_angle) {
  for (const auto& [name, input, cell, tolerance] :
       {std::tuple{"open sphere", open_sphere_soup(), 0.5, 1.5}, std::tuple{"open box", open_box(), 0.4, 1.2}}) {
    gdm::WrapOptions o = options(cell, tolerance);
    o.min_angle = 0.0;
    const gdm::WrapResult off = gdm::shrink_wrap(input, o);
    o.min_angle = gdm::WrapOptions{}.min_angle;
    const gdm::WrapResult on = gdm::shrink_wrap(input, o);
    expect_valid_wrap(input, on, tolerance);
    std::cout << name << ": smallest angle " << off.report.min_angle_deg << " deg at min_angle 0, "
              << on.report.min_angle_deg << " at " << o.min_angle << " (" << off.report.faces << " and "
              << on.report.faces << " faces)\n";
    EXPECT_EQ(o.min_angle, 10.0);
    EXPECT_GE(on.report.min_angle_deg, off.report.min_angle_deg) << name;
    // The count reported is the truth (checked on the float-snapped output).
    std::size_t below = 0;
    for (auto f : on.mesh.faces()) {
      auto it = on.mesh.cfv_iter(f);
      const gdm::Vec3 a = gdm::to_eigen(on.mesh.point(*it)), b = gdm::to_eigen(on.mesh.point(*++it)),
                      c = gdm::to_eigen(on.mesh.point(*++it));
      below += gdm::triangle_min_angle(a, b, c) < o.min_angle ? 1 : 0;
    }
    EXPECT_EQ(on.deform.faces_below_min_angle, below) << name;
    std::cout << name << ": " << below << " faces below " << o.min_angle << " degrees\n";
    // Measured: the open box reaches the bound; on the open sphere 16 faces
    // stay below it (0.90 degrees, from 0.26; 3136 faces from 3058), caps folded over the rim of
    // the input where every operation would touch the input or fold the ring.
    if (std::string(name) == "open box") EXPECT_GE(on.report.min_angle_deg, 10.0);
    else EXPECT_LE(below, 25u) << name;
  }
}

// ------------------------------------------------------------- the cost --

// The process's peak resident memory (VmHWM), bytes; resets the peak first
// when `reset` (Linux: "5" to /proc/self/clear_refs). -1 when unreadable.
double peak_resident_bytes(bool reset) {
  if (reset) {
    std::ofstream clear("/proc/self/clear_refs");
    clear << "5";
    clear.flush();
    if (!clear) return -1.0;
  }
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return 1024.0 * std::stod(line.substr(6));
  return -1.0;
}

// The grid the wrap built, from its note "distance field: A x B x C cells ...".
gdm::Index3 built_grid(const gdm::WrapResult& r) {
  for (const auto& note : r.notes)
    if (note.rfind("distance field: ", 0) == 0) {
      std::istringstream in(note.substr(16));
      gdm::Index3 g{};
      char x;
      in >> g[0] >> x >> g[1] >> x >> g[2];
      return g;
    }
  return {0, 0, 0};
}

// The estimate against the wrap it predicts, on generated inputs: the grid is
// exact, the faces and the peak memory within a factor of 2.5 (no timing is
// asserted: the estimated time is only printed).
TEST(ShrinkWrapCost, estimate_is_near_the_measured_faces_and_memory) {
  gdm::Mesh holed = gdm::make_geodesic_sphere(gdm::Vec3(3, -2, 1), 12.0, 4);
  std::vector<gdm::Triangle> holed_sphere;
  for (const auto& t : gdm::triangles_of(holed))
    if ((t[0] + t[1] + t[2]).z() / 3.0 < 1.0 + 9.0) holed_sphere.push_back(t);
  struct Case {
    const char* name;
    std::vector<gdm::Triangle> input;
    double cell, tolerance;
  };
  const std::vector<Case> cases = {{"open box, 0.4 mm cells", open_box(), 0.4, 1.2},
                                   {"holed sphere, 0.3 mm cells", holed_sphere, 0.3, 0.9}};
  for (const auto& c : cases) {
    const gdm::WrapOptions o = options(c.cell, c.tolerance);
    const gdm::WrapEstimate e = gdm::estimate_wrap(c.input, o);
    const double before = peak_resident_bytes(true);
    const gdm::WrapResult r = gdm::shrink_wrap(c.input, o);
    const double peak = peak_resident_bytes(false);
    const double faces = static_cast<double>(r.mesh.n_faces());
    std::cout << c.name << ": estimated " << e.text() << "; built " << faces << " faces, peak " << peak / 1048576.0
              << " MiB (" << before / 1048576.0 << " MiB before)\n";
    EXPECT_EQ(built_grid(r), e.grid) << c.name;
    EXPECT_DOUBLE_EQ(e.cells, double(e.grid[0]) * e.grid[1] * e.grid[2]);
    EXPECT_GT(e.faces, faces / 2.5) << c.name;
    EXPECT_LT(e.faces, faces * 2.5) << c.name;
    EXPECT_GT(e.seconds, 0.0);
#if defined(__SANITIZE_ADDRESS__)
    std::cout << "AddressSanitizer build (shadow memory): memory not checked\n";
    continue;
#endif
    if (before < 0.0 || peak < 0.0) {
      std::cout << "peak memory not measurable here (/proc/self/clear_refs): memory not checked\n";
      continue;
    }
    EXPECT_GT(e.bytes, peak / 2.5) << c.name;
    EXPECT_LT(e.bytes, peak * 2.5) << c.name;
  }
}

// An absurd request (1 um cells around a 12 mm sphere: 1e13 cells) is refused
// before anything is built, naming the estimate, the limits and a cell size
// that fits; that cell size does fit; 0 lifts a limit.
TEST(ShrinkWrapCost, absurd_request_is_refused_before_any_work) {
  const auto input = sphere_soup(gdm::Vec3(0, 0, 0), 6.0, 2);
  gdm::WrapOptions o = options(0.001, 0.003);
  try {
    gdm::shrink_wrap(input, o);
    FAIL() << "an absurd wrap was accepted";
  } catch (const gdm::WrapTooCostly& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("the wrap would take about "), std::string::npos) << m;
    EXPECT_NE(m.find(" distance grid, about "), std::string::npos) << m;
    EXPECT_NE(m.find("above the time limit of 180 s and the memory limit of 2 GiB; refused before starting"),
              std::string::npos) << m;
    EXPECT_NE(m.find("mm is within the limits"), std::string::npos) << m;
    EXPECT_EQ(e.option(), "cell_size");
    EXPECT_GT(e.estimate().cells, 1e12);
    EXPECT_GT(e.estimate().bytes, 2.0 * 1073741824.0);
    ASSERT_GT(e.fitting_cell_size(), 0.001);
    gdm::WrapOptions fits = o;
    fits.cell_size = e.fitting_cell_size();
    fits.tolerance = std::max(o.tolerance, fits.cell_size);
    const gdm::WrapEstimate f = gdm::estimate_wrap(input, fits);
    EXPECT_LE(f.seconds, o.time_limit);
    EXPECT_LE(f.bytes, o.memory_limit * 1073741824.0);
  }
  // Without limits the same request passes the cost check (and meets the
  // distance field's own ceiling of 400 million cells, also before any work).
  o.time_limit = 0.0;
  o.memory_limit = 0.0;
  try {
    gdm::shrink_wrap(input, o);
    FAIL() << "a grid of 1e13 cells was accepted";
  } catch (const gdm::WrapTooCostly&) {
    FAIL() << "refused as too costly without limits";
  } catch (const gdm::InvalidOption& e) {
    EXPECT_NE(std::string(e.what()).find("cells; increase the cell size"), std::string::npos) << e.what();
  }
}

TEST(ShrinkWrapCost, bad_limits_are_refused) {
  const auto input = sphere_soup(gdm::Vec3(0, 0, 0), 4.0, 1);
  gdm::WrapOptions o = options(0.5, 1.5);
  o.time_limit = -1.0;
  expect_refused(input, o, "time_limit must be >= 0");
  o = options(0.5, 1.5);
  o.memory_limit = std::numeric_limits<double>::quiet_NaN();
  expect_refused(input, o, "memory_limit must be >= 0");
}

}  // namespace
