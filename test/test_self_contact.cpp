// Where a model meets itself (gdm/self_contact.h, issue 15): a model grown
// inside a shell around a cavity meets itself across the object on the far
// side; a ball does not. Phantoms built here, with noise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "gdm/phantoms.h"
#include "gdm/pipeline.h"
#include "gdm/self_contact.h"
#include "gdm/text.h"

namespace {

using namespace gdm;
namespace ph = phantoms;

constexpr double kLow = 50.0, kHigh = 200.0, kThreshold = 125.0;

PipelineOptions grown_from(const Vec3& seed) {
  PipelineOptions o;
  o.threshold_otsu = false;
  o.threshold = kThreshold;
  o.seed.kind = SeedKind::point;
  o.seed.point = seed;
  o.seed.radius = 1.5;
  // The lined model these tests look at: filled (the default), the shell's
  // cavity leaves no contact (test_cavities.cpp).
  o.deform.fill_cavities = false;
  return o;
}

// A bright spherical shell (radii 8 to 14 voxels) around a dark cavity, on
// a 40^3 grid, noise 5 % of the contrast.
ph::Grid shell_grid() {
  ph::Grid grid;
  grid.dims = {40, 40, 40};
  return grid;
}

Volume noisy_shell() {
  const ph::Grid grid = shell_grid();
  const Vec3 c = grid.center();
  return ph::with_gaussian_noise(
      ph::voxelize(grid, ph::difference(ph::sphere(c, 14.0), ph::sphere(c, 8.0)), kLow, kHigh - kLow), 0.05 * (kHigh - kLow), 5u);
}

// A bright spherical shell (radii 8 to 14 voxels) around a dark cavity, the
// model grown from a seed in the shell: the fronts go round the cavity and
// meet on the far side, two sheets a hair apart across the object.
TEST(SelfContact, a_shell_grown_from_one_side_meets_itself_across_the_object) {
  const Vec3 c = shell_grid().center();
  const Volume shell = noisy_shell();
  const PipelineResult r = extract_surface(shell, grown_from(c + Vec3(11.0, 0.0, 0.0)));
  ASSERT_TRUE(r.failure.empty()) << r.failure;
  ASSERT_FALSE(r.contacts.regions.empty()) << "the model's two fronts meeting behind the cavity were not seen";
  const ContactRegion& largest = r.contacts.regions.front();
  EXPECT_TRUE(largest.across_object);
  EXPECT_GT(largest.area, 1.0);
  // The fronts meet on the far side of the cavity from the seed.
  EXPECT_LT(largest.centre.x(), c.x()) << "contact at x = " << largest.centre.x();
  const std::vector<std::string> lines = describe_contacts(r.contacts);
  ASSERT_GE(lines.size(), 2u);
  EXPECT_NE(lines[1].find("cavity or a handle"), std::string::npos) << lines[1];
  // The seams: the regions across the object, summed; the summary gives
  // their share of the model's area.
  double seam_area = 0.0;
  std::size_t seam_faces = 0;
  for (const ContactRegion& region : r.contacts.regions)
    if (region.across_object) {
      seam_area += region.area;
      seam_faces += region.faces;
    }
  EXPECT_GT(r.contacts.seam_area, 1.0);
  EXPECT_DOUBLE_EQ(r.contacts.seam_area, seam_area);
  EXPECT_EQ(r.contacts.seam_faces, seam_faces);
  EXPECT_LE(r.contacts.seam_area, r.contacts.area);
  const double percent = 100.0 * r.contacts.seam_area / r.report.area;
  const std::string first = describe_contacts(r.contacts, 5, r.report.area).front();
  EXPECT_NE(first.find(format_number(std::round(percent), 3) + " % of the model's area"), std::string::npos)
      << first << " (" << percent << " %)";
}

TEST(SelfContact, a_shell_filled_by_default_does_not_meet_itself) {
  const Vec3 c = shell_grid().center();
  const Volume shell = noisy_shell();
  PipelineOptions o = grown_from(c + Vec3(11.0, 0.0, 0.0));
  o.deform.fill_cavities = true;
  const PipelineResult r = extract_surface(shell, o);
  ASSERT_TRUE(r.failure.empty()) << r.failure;
  EXPECT_EQ(r.deform.cavities, 1u);
  EXPECT_TRUE(r.contacts.regions.empty()) << describe_contacts(r.contacts).front();
}

TEST(SelfContact, a_ball_does_not_meet_itself) {
  ph::Grid grid;
  grid.dims = {40, 40, 40};
  const Vec3 c = grid.center();
  const Volume ball = ph::with_gaussian_noise(ph::voxelize(grid, ph::sphere(c, 12.0), kLow, kHigh - kLow), 0.05 * (kHigh - kLow), 6u);
  const PipelineResult r = extract_surface(ball, grown_from(c));
  ASSERT_TRUE(r.failure.empty()) << r.failure;
  EXPECT_TRUE(r.contacts.regions.empty()) << describe_contacts(r.contacts).front();
  EXPECT_TRUE(describe_contacts(r.contacts).empty());
}

// No false alarms: the genus-0 phantoms of the other tests (an ellipsoid on
// an anisotropic grid, a cube with a corner missing, a Y-shaped branching,
// a C-shaped tube), noise 3 and 8 % of the contrast, grown at the defaults
// from the automatic seed, meet themselves nowhere, fill no cavity and cap
// no handle.
TEST(SelfContact, genus_zero_phantoms_raise_no_false_alarm) {
  struct Shape {
    const char* name;
    ph::Grid grid;
    ph::Sdf sdf;
  };
  std::vector<Shape> shapes;
  {
    ph::Grid g;
    g.dims = {48, 48, 24};
    g.spacing = Vec3(0.5, 0.5, 2.0);
    shapes.push_back({"ellipsoid", g, ph::ellipsoid(g.center(), Vec3(9.0, 7.0, 16.0))});
  }
  {
    ph::Grid g;
    g.dims = {40, 40, 40};
    const Vec3 c = g.center();
    shapes.push_back({"cube without a corner", g,
                      ph::difference(ph::box(c - Vec3(12, 12, 12), c + Vec3(12, 12, 12)), ph::box(c, c + Vec3(20, 20, 20)))});
  }
  {
    ph::Grid g;
    g.dims = {48, 48, 40};
    const Vec3 c = g.center();
    shapes.push_back({"branching", g,
                      ph::unite({ph::capsule(c + Vec3(0, -14, 0), c, 4.0), ph::capsule(c, c + Vec3(-11, 12, 0), 3.0),
                                 ph::capsule(c, c + Vec3(11, 12, 0), 3.0)})});
  }
  {
    ph::Grid g;
    g.dims = {48, 48, 24};
    shapes.push_back({"C tube", g, ph::bent_tube(g.center(), 14.0, 4.0, 4.5)});
  }
  unsigned seed = 20u;
  for (const Shape& shape : shapes)
    for (const double noise : {0.03, 0.08}) {
      const Volume v = ph::with_gaussian_noise(ph::voxelize(shape.grid, shape.sdf, kLow, kHigh - kLow),
                                               noise * (kHigh - kLow), ++seed);
      PipelineOptions o;
      o.threshold_otsu = false;
      o.threshold = kThreshold;
      const PipelineResult r = extract_surface(v, o);
      ASSERT_TRUE(r.failure.empty()) << shape.name << ": " << r.failure;
      EXPECT_TRUE(r.contacts.regions.empty()) << shape.name << " noise " << noise << ": " << describe_contacts(r.contacts).front();
      EXPECT_EQ(r.deform.cavities, 0u) << shape.name << " noise " << noise << ": " << cavity_summary(r.deform);
      EXPECT_EQ(r.deform.handles, 0u) << shape.name << " noise " << noise << ": " << handle_summary(r.deform);
    }
}

// The gap's side decides what a region means: the same contacts, told that
// the gap lies on the background's side, are slits of background.
TEST(SelfContact, the_side_of_the_gap_names_the_region) {
  ph::Grid grid;
  grid.dims = {40, 40, 40};
  const Vec3 c = grid.center();
  const Volume shell = ph::voxelize(grid, ph::difference(ph::sphere(c, 14.0), ph::sphere(c, 8.0)), kLow, kHigh - kLow);
  const PipelineResult r = extract_surface(shell, grown_from(c + Vec3(11.0, 0.0, 0.0)));
  ASSERT_TRUE(r.failure.empty()) << r.failure;
  const ContactReport background = find_self_contacts(r.mesh, shell.voxel_size(), [](const Vec3&) { return false; });
  ASSERT_EQ(background.regions.size(), r.contacts.regions.size());
  EXPECT_EQ(background.faces, r.contacts.faces);
  for (const ContactRegion& region : background.regions) EXPECT_FALSE(region.across_object);
  EXPECT_NE(describe_contacts(background)[1].find("slit of background"), std::string::npos);
  // No seam among them: slits of background are the object's surface.
  EXPECT_EQ(background.seam_area, 0.0);
  EXPECT_EQ(background.seam_faces, 0u);
  EXPECT_NE(describe_contacts(background).front().find("0 mm^2 of them (0 faces) are seams"), std::string::npos)
      << describe_contacts(background).front();
}

// The contact search flags the faces on several threads: the flags, the
// gaps' midpoints and the regions are the same for any thread count.
TEST(SelfContact, contact_flags_are_the_same_for_any_thread_count) {
  const Vec3 c = shell_grid().center();
  const Volume shell = noisy_shell();
  const PipelineResult r = extract_surface(shell, grown_from(c + Vec3(11.0, 0.0, 0.0)));
  ASSERT_TRUE(r.failure.empty()) << r.failure;
  ASSERT_GT(r.mesh.n_faces(), 2000u);  // several chunks per thread
  const double distance = shell.voxel_size();
  std::vector<Vec3> gaps_one;
  const std::vector<char> one = contact_faces(r.mesh, distance, &gaps_one, 1);
  ASSERT_GT(std::count(one.begin(), one.end(), 1), 0) << "no contact to compare";
  const ContactReport report_one = find_self_contacts(r.mesh, distance, {}, 1);
  for (int threads : {2, 3, 8}) {
    std::vector<Vec3> gaps;
    EXPECT_EQ(contact_faces(r.mesh, distance, &gaps, threads), one) << threads << " threads";
    ASSERT_EQ(gaps.size(), gaps_one.size());
    for (std::size_t i = 0; i < gaps.size(); ++i)
      ASSERT_EQ(gaps[i], gaps_one[i]) << "face " << i << ", " << threads << " threads";
    const ContactReport report = find_self_contacts(r.mesh, distance, {}, threads);
    EXPECT_EQ(report.faces, report_one.faces) << threads << " threads";
    EXPECT_EQ(report.area, report_one.area) << threads << " threads";
    ASSERT_EQ(report.regions.size(), report_one.regions.size()) << threads << " threads";
    for (std::size_t k = 0; k < report.regions.size(); ++k) {
      EXPECT_EQ(report.regions[k].faces, report_one.regions[k].faces);
      EXPECT_EQ(report.regions[k].centre, report_one.regions[k].centre);
    }
  }
}

// Asked about a few faces (local refinement asks about a few hundred of a
// large model's faces), the search looks only near them: each flagged face
// gets the answer the search over every face gives, the others none, for
// any thread count; with no face flagged, none is in contact.
TEST(SelfContact, a_few_flagged_faces_get_the_answers_of_the_whole_search) {
  const Vec3 c = shell_grid().center();
  const Volume shell = noisy_shell();
  const PipelineResult r = extract_surface(shell, grown_from(c + Vec3(11.0, 0.0, 0.0)));
  ASSERT_TRUE(r.failure.empty()) << r.failure;
  const std::size_t n = r.mesh.n_faces();
  for (const double distance : {shell.voxel_size(), 2.5 * shell.voxel_size()}) {
    const std::vector<char> all = contact_faces(r.mesh, distance, nullptr, 1);
    // Every 37th face and every 5th face in contact: a few of both kinds,
    // far fewer than a sixteenth of the faces.
    std::vector<char> only(n, 0);
    std::size_t in_contact = 0, flagged = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (i % 37 == 0 || (all[i] && in_contact++ % 5 == 0)) only[i] = 1;
    for (char f : only) flagged += f;
    ASSERT_LT(16 * flagged, n) << "not few enough for the search near them";
    std::size_t flagged_in_contact = 0;
    for (std::size_t i = 0; i < n; ++i) flagged_in_contact += only[i] && all[i];
    ASSERT_GT(flagged_in_contact, 3u) << "no flagged face in contact to compare";
    ASSERT_LT(flagged_in_contact, flagged) << "no flagged face without contact to compare";
    for (int threads : {1, 2, 3}) {
      const std::vector<char> few = contact_faces(r.mesh, distance, nullptr, threads, &only);
      ASSERT_EQ(few.size(), n);
      for (std::size_t i = 0; i < n; ++i)
        ASSERT_EQ(few[i], only[i] ? all[i] : 0) << "face " << i << ", " << threads << " threads, distance " << distance;
    }
    const std::vector<char> none(n, 0);
    const std::vector<char> nothing = contact_faces(r.mesh, distance, nullptr, 2, &none);
    EXPECT_EQ(std::count(nothing.begin(), nothing.end(), 1), 0);
  }
}

}  // namespace
