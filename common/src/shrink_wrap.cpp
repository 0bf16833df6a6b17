#include "gdm/shrink_wrap.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <unordered_map>

#include "gdm/cell_hash.h"
#include "gdm/distance_field.h"
#include "gdm/errors.h"
#include "gdm/float_snap.h"
#include "gdm/mesh_checks.h"
#include "gdm/obstacle.h"
#include "gdm/resampler.h"
#include "gdm/seed.h"
#include "gdm/option_catalogue.h"
#include "gdm/text.h"
#include "gdm/triangle_locator.h"

namespace gdm {

namespace {

// A number with four significant digits, for the notes.
std::string fmt(double v) { return format_number(v, 4); }

// Compacts the wrap after gdm::deform and notes the outcome.
void finish_deformation(const DeformResult& r, Mesh& mesh, std::vector<std::string>* log) {
  mesh.garbage_collection();
  if (r.float_refused > 0)
    log->push_back("warning: " + std::to_string(r.float_refused) +
                   " vertices could not be moved to float precision without a self-intersection");
  log->push_back("deformation " + to_string(r.reason) + " after " + std::to_string(r.cycles) + " cycles (" +
                 std::to_string(r.global_refinements) + " global refinements, " + std::to_string(r.rejected_moves) +
                 " moves vetoed by the self-intersection guard)");
  if (r.reason == StopReason::max_cycles || r.reason == StopReason::face_limit)
    log->push_back("warning: the model did not converge; raise the maximum number of cycles or check the threshold");
  if (r.border_vertices > 0)
    log->push_back("warning: " + std::to_string(r.border_vertices) +
                   " vertices reached the border of the volume: the object leaks (check threshold and polarity)");
  log->push_back("result: " + to_string(measure(mesh)));
}

// The model's options of the wrap (its level of detail in cell^2, the rest at the core's defaults).
DeformOptions model_options(const WrapOptions& w) {
  DeformOptions o;
  o.a0 = w.a0;
  o.a1 = w.a1;
  o.a2 = w.a2;
  o.lod_face_area = w.lod_face_area;
  o.global_refinements = w.global_refinements;
  o.max_cycles = w.max_cycles;
  o.threads = w.threads;
  // The wrap bridges the input's holes: no refinement to enter what lies behind them.
  o.refine_channels = false;
  return o;
}

void validate(const std::vector<Triangle>& input, const WrapOptions& w) {
  const auto require = [](bool ok, const std::string& message) {
    if (!ok) throw InvalidOption(message);
  };
  require(std::isfinite(w.cell_size) && w.cell_size > 0.0, "cell_size must be > 0 (mm), got " + fmt(w.cell_size));
  require(std::isfinite(w.tolerance) && w.tolerance > 0.0, "tolerance must be > 0 (mm), got " + fmt(w.tolerance));
  require(w.tolerance >= w.cell_size, "tolerance (" + fmt(w.tolerance) + ") must be >= cell_size (" +
                                          fmt(w.cell_size) + "): the grid cannot resolve a closer wrap");
  require(w.coverage_rounds >= 0, "coverage_rounds must be >= 0, got " + std::to_string(w.coverage_rounds));
  // The model's options: the catalogue's ranges (lod_face_area in cell^2 here).
  const DeformOptions model = model_options(w);
  for (const auto& option : deform_option_catalogue()) check_option(option, option.get(model));
  require(!input.empty(), "the input is empty: nothing to wrap");
  for (const auto& t : input)
    for (const auto& p : t) require(p.allFinite(), "the input has a non-finite coordinate");
}

// An input point far from the wrap.
struct FarPoint {
  gdm::Vec3 point;
  double distance;  // from the wrap, mm
};

// Every distinct corner of the input farther than `beyond` from the wrap;
// `largest` gets the largest distance of any corner.
std::vector<FarPoint> far_input(const std::vector<Triangle>& input, const gdm::Mesh& wrap, double beyond,
                                double* largest) {
  const gdm::TriangleLocator to_wrap(triangles_of(wrap));
  std::vector<FarPoint> out;
  *largest = 0.0;
  for (const auto& t : input)
    for (int i = 0; i < 3; ++i) {
      if ((i == 1 && t[1] == t[0]) || (i == 2 && (t[2] == t[0] || t[2] == t[1]))) continue;
      const double d = to_wrap.distance(t[i]);
      *largest = std::max(*largest, d);
      if (d > beyond) out.push_back({t[i], d});
    }
  // A corner shared by several triangles is listed once.
  std::sort(out.begin(), out.end(), [](const FarPoint& a, const FarPoint& b) {
    return std::lexicographical_compare(a.point.data(), a.point.data() + 3, b.point.data(), b.point.data() + 3);
  });
  const auto same = [](const FarPoint& a, const FarPoint& b) { return a.point == b.point; };
  out.erase(std::unique(out.begin(), out.end(), same), out.end());
  return out;
}

// Local refinement: the faces of the wrap that span a far input point
// (a face whose centroid lies within the point's distance plus the face's
// longest edge) get their longest edge split, `passes` times, down to edges of
// `min_edge`. The wrap has converged there with faces too coarse to follow
// the offset surface into a crevice narrower than an edge; more vertices let
// the next deformation follow it: the paper's local resampling (section 4),
// driven by the distance to the input instead of the face area. A midpoint
// split keeps the new triangles in the old ones: no intersection and no
// obstacle contact can appear.
std::size_t refine_near(gdm::Mesh& mesh, const std::vector<FarPoint>& points, double min_edge, int passes,
                        int generation) {
  double largest_distance = 0.0;
  for (const auto& u : points) largest_distance = std::max(largest_distance, u.distance);
  std::size_t splits = 0;
  for (int pass = 0; pass < passes; ++pass) {
    double edge = 0.0;
    for (auto e : mesh.edges()) edge = std::max(edge, static_cast<double>(mesh.calc_edge_length(e)));
    const double cell = largest_distance + edge;
    std::unordered_map<gdm::CellKey, std::vector<int>> buckets;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const auto c = gdm::cell_of(points[i].point, cell);
      buckets[gdm::cell_key(c[0], c[1], c[2])].push_back(static_cast<int>(i));
    }
    const std::size_t s = gdm::split_longest_edges(
        mesh, generation, [&](gdm::Mesh::FaceHandle f, gdm::Mesh::HalfedgeHandle longest) {
          const double l = mesh.calc_edge_length(longest);
          if (l <= min_edge) return false;
          gdm::Vec3 centroid = gdm::Vec3::Zero();
          for (auto v : mesh.fv_range(f)) centroid += gdm::to_eigen(mesh.point(v)) / 3.0;
          const auto c = gdm::cell_of(centroid, cell);
          for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dz = -1; dz <= 1; ++dz) {
                const auto it = buckets.find(gdm::cell_key(c[0] + dx, c[1] + dy, c[2] + dz));
                if (it == buckets.end()) continue;
                for (int i : it->second)
                  if ((points[i].point - centroid).norm() < points[i].distance + l) return true;
              }
          return false;
        });
    splits += s;
    if (s == 0) break;
  }
  return splits;
}

}  // namespace

WrapResult shrink_wrap(const std::vector<Triangle>& input, const WrapOptions& w, const DeformObserver& observer) {
  validate(input, w);
  WrapResult out;
  std::vector<std::string>* log = &out.notes;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& t : input)
    for (const auto& p : t) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  // The wrap settles where the distance to the input is a third of the
  // tolerance: in a concave crease of angle theta the offset surface's corner
  // lies offset / sin(theta / 2) from the crease, so creases down to about
  // 40 degrees stay within the tolerance.
  const double offset = w.tolerance / 3.0;
  const Vec3 centre = 0.5 * (lo + hi);
  const double radius = 0.5 * (hi - lo).norm() + offset + 2.0 * w.cell_size;
  DistanceFieldOptions fo;
  fo.cell_size = w.cell_size;
  fo.offset = offset;
  // The grid holds the seed sphere with a cell to spare.
  const Vec3 sphere_lo = centre - Vec3::Constant(radius), sphere_hi = centre + Vec3::Constant(radius);
  fo.padding = w.cell_size;
  const Volume field = distance_field(input, sphere_lo, sphere_hi, fo, w.field_progress);
  if (field.voxel_count() == 0) throw Error("cancelled");
  log->push_back("distance field: " + std::to_string(field.dims()[0]) + " x " + std::to_string(field.dims()[1]) +
                 " x " + std::to_string(field.dims()[2]) + " cells of " + fmt(w.cell_size) + " mm; the wrap settles " +
                 fmt(offset) + " mm from the input");

  // A geodesic sphere whose faces are about the level of detail.
  const double sphere_area = 4.0 * M_PI * radius * radius;
  const double lod_mm2 = w.lod_face_area * w.cell_size * w.cell_size;
  int level = 0;
  while (level < 5 && sphere_area / (20.0 * std::pow(4.0, level)) > 4.0 * lod_mm2) ++level;
  Mesh& mesh = out.mesh;
  mesh = make_geodesic_sphere(centre, radius, level);
  log->push_back("seed: geodesic sphere of radius " + fmt(radius) + " mm, " + std::to_string(mesh.n_faces()) +
                 " faces");

  DeformOptions o = model_options(w);
  o.subvoxel_fit = false;
  o.lod_tolerance = 0.0;
  o.mode = Mode::shrink;
  o.polarity = Polarity::object_darker;
  o.threshold = offset;
  // The fit and the error-driven level of detail do not check obstacles (off above).
  const Obstacle obstacle(input);
  o.obstacle = &obstacle;
  const auto result = deform(mesh, field, o, observer);
  if (result.reason == StopReason::cancelled) throw Error("cancelled");
  out.deform = result;
  out.total_cycles = result.cycles;
  finish_deformation(result, mesh, log);

  // Coverage: where input still lies farther than the tolerance, the wrap
  // converged with faces spanning a crevice of the offset surface narrower
  // than its edges (its vertices sit on the offset surface on either side).
  // Split the faces over it and deform again from the wrap as it is, a
  // bounded number of rounds. Rounds run while input lies beyond 90% of the
  // tolerance (a point just inside the tolerance for one input is just
  // outside it for a slightly different one), and stop when a round gains
  // nothing. A round refines near every input point beyond three quarters of
  // the tolerance. Edges are not split below half a cell: the field does not
  // resolve finer detail.
  const double aim = 0.9 * w.tolerance, refine_beyond = 0.75 * w.tolerance;
  int cycles_left = w.max_cycles - result.cycles;
  double input_to_wrap = 0.0;
  std::vector<FarPoint> far = far_input(input, mesh, refine_beyond, &input_to_wrap);
  for (int round = 1; round <= w.coverage_rounds && input_to_wrap > aim && cycles_left > 0; ++round) {
    const double before = input_to_wrap;
    const int cycle = w.max_cycles - cycles_left;  // new vertices' generation: the cycle they appear after
    const std::size_t splits = refine_near(mesh, far, 0.5 * w.cell_size, 2, cycle);
    if (splits == 0) break;
    out.coverage_rounds_done = round;
    DeformOptions again = o;
    again.global_refinements = 0;
    again.max_cycles = cycles_left;
    DeformObserver round_observer;
    if (observer) {
      const int stage = w.global_refinements + round;
      round_observer = [&observer, stage](const CycleReport& c) {
        CycleReport shifted = c;
        shifted.stage = stage;
        return observer(shifted);
      };
    }
    const auto r = deform(mesh, field, again, round_observer);
    if (r.reason == StopReason::cancelled) throw Error("cancelled");
    mesh.garbage_collection();
    if (r.float_refused > 0)
      log->push_back("warning: " + std::to_string(r.float_refused) +
                     " vertices could not be moved to float precision without a self-intersection");
    cycles_left -= r.cycles;
    out.total_cycles += r.cycles;
    const std::size_t refined_near = far.size();
    far = far_input(input, mesh, refine_beyond, &input_to_wrap);
    log->push_back("coverage round " + std::to_string(round) + ": the farthest input was " + fmt(before) +
                   " mm from the wrap; " + std::to_string(splits) + " edges split near " +
                   std::to_string(refined_near) + " input points beyond " + fmt(refine_beyond) + " mm, " +
                   std::to_string(r.cycles) + " cycles (" + to_string(r.reason) + ", " +
                   std::to_string(r.rejected_moves) + " moves vetoed); now the farthest is " + fmt(input_to_wrap) +
                   " mm");
    if (input_to_wrap > before - 0.05 * w.cell_size) break;  // no gain: a crevice the field does not resolve
  }

  const MeshReport report = measure(mesh);
  if (!report.closed || !report.two_manifold || report.genus != 0 || report.self_intersections != 0)
    throw Error("the wrap failed its checks (" + to_string(report) + ")");
  out.report = report;
  // The wrap is on float points: float consumers (MeshLab, STL, PLY) change
  // nothing. Check it.
  {
    Mesh rounded = mesh;
    for (auto v : rounded.vertices()) rounded.set_point(v, to_point(round_to_float(to_eigen(rounded.point(v)))));
    const std::size_t crossings = self_intersecting_pairs(rounded);
    if (crossings > 0)
      log->push_back("warning: " + std::to_string(crossings) +
                     " face pairs intersect once the coordinates are rounded to float precision");
  }
  // input_to_wrap is exact (far_input); the other way, exact too.
  const TriangleLocator to_input(input);
  double wrap_to_input = 0.0;
  for (auto v : mesh.vertices()) wrap_to_input = std::max(wrap_to_input, to_input.distance(to_eigen(mesh.point(v))));
  out.farthest_input_distance = input_to_wrap;
  out.farthest_wrap_distance = wrap_to_input;
  log->push_back("wrap: " + std::to_string(report.faces) + " faces, " + std::to_string(report.vertices) +
                 " vertices, volume " + fmt(report.volume) + " mm^3, genus " + std::to_string(report.genus) +
                 ", self-intersections " + std::to_string(report.self_intersections));
  log->push_back("largest distance of the input from the wrap: " + fmt(input_to_wrap) + " mm (tolerance " +
                 fmt(w.tolerance) + " mm); largest distance of the wrap from the input: " + fmt(wrap_to_input) + " mm");
  if (input_to_wrap > w.tolerance)
    log->push_back("warning: some input lies farther than the tolerance from the wrap (a crevice narrower than "
                   "the cell size, or a hole wider than the level of detail); lower the cell size, the level of "
                   "detail or a2");
  return out;
}

}  // namespace gdm
