#include "gdm/shrink_wrap.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "gdm/cell_hash.h"
#include "gdm/distance_field.h"
#include "gdm/errors.h"
#include "gdm/float_snap.h"
#include "gdm/intersection_guard.h"
#include "gdm/mesh_checks.h"
#include "gdm/obstacle.h"
#include "gdm/resampler.h"
#include "gdm/seed.h"
#include "gdm/option_catalogue.h"
#include "gdm/text.h"
#include "gdm/triangle_locator.h"
#include "gdm/triangle_quality.h"

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
  // No triangle-quality pass inside the wrap's deformations: the fairing of
  // the vertices over holes runs after them; the wrap runs its own pass last.
  o.min_angle = 0.0;
  // The wrap's field is an offset of the input, its own bridging decides
  // what is spanned: no cavity fill nor handle caps (cavities.h) on it.
  o.fill_cavities = false;
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
  require(std::isfinite(w.bridge) && w.bridge >= 0.0, "bridge must be >= 0 (mm; 0 = off), got " + fmt(w.bridge));
  require(w.coverage_rounds >= 0, "coverage_rounds must be >= 0, got " + std::to_string(w.coverage_rounds));
  require(std::isfinite(w.min_angle) && w.min_angle >= 0.0 && w.min_angle <= 30.0,
          "min_angle must be in [0, 30] (degrees; 0 = off), got " + fmt(w.min_angle));
  // The model's options: the catalogue's ranges (lod_face_area in cell^2 here).
  const DeformOptions model = model_options(w);
  for (const auto& option : deform_option_catalogue()) check_option(option, option.get(model));
  require(std::isfinite(w.time_limit) && w.time_limit >= 0.0,
          "time_limit must be >= 0 (s; 0 = no limit), got " + fmt(w.time_limit));
  require(std::isfinite(w.memory_limit) && w.memory_limit >= 0.0,
          "memory_limit must be >= 0 (GiB; 0 = no limit), got " + fmt(w.memory_limit));
  require(!input.empty(), "the input is empty: nothing to wrap");
  for (const auto& t : input)
    for (const auto& p : t) require(p.allFinite(), "the input has a non-finite coordinate");
}

// The bridge in mm (0 = off).
double bridge_of(const WrapOptions& w) { return w.bridge; }

// Where the wrap works: the input's box, the offset it settles at, the seed
// sphere around the input and the distance field's grid over that sphere.
struct WrapGeometry {
  Vec3 lo, hi;                   // the input's bounding box
  double offset = 0.0;           // the wrap settles this far from the input, mm
  Vec3 centre;                   // of the seed sphere
  double radius = 0.0;           // of the seed sphere, mm
  Vec3 field_lo, field_hi;       // the box the field covers (plus its padding)
  DistanceFieldOptions field;
};

WrapGeometry geometry_of(const std::vector<Triangle>& input, const WrapOptions& w) {
  WrapGeometry g;
  g.lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  g.hi = -g.lo;
  for (const auto& t : input)
    for (const auto& p : t) {
      g.lo = g.lo.cwiseMin(p);
      g.hi = g.hi.cwiseMax(p);
    }
  // The wrap settles where the distance to the input is a third of the
  // tolerance: in a concave crease of angle theta the offset surface's corner
  // lies offset / sin(theta / 2) from the crease, so creases down to about
  // 40 degrees stay within the tolerance.
  g.offset = w.tolerance / 3.0;
  g.centre = 0.5 * (g.lo + g.hi);
  g.radius = 0.5 * (g.hi - g.lo).norm() + g.offset + 2.0 * w.cell_size;
  g.field.cell_size = w.cell_size;
  g.field.offset = g.offset;
  // The grid holds the seed sphere with a cell to spare.
  g.field_lo = g.centre - Vec3::Constant(g.radius);
  g.field_hi = g.centre + Vec3::Constant(g.radius);
  // Bridging rolls balls of diameter `bridge` in from the grid's border: the
  // grid reaches a ball's radius beyond the input's offset.
  g.field.padding = w.cell_size + (bridge_of(w) > 0.0 ? 0.5 * bridge_of(w) + g.offset : 0.0);
  return g;
}

// The calibration of estimate_wrap. Measured with `gdm wrap` (Release, 2 cores,
// the machine shared) on the real open tooth of the MeshLab tests (6,888
// triangles, diagonal 165.5 mm) and on the generated inputs of those tests
// (wrap_input.ply, 5,430 triangles; wrap_slot.ply, 5,046), cell / tolerance
// in mm -> measured faces, cycles, wall time, peak RSS:
//   tooth    1.67 / 3.34   12,806 faces  154 cycles    3.5 s    38 MB   (112^3 cells)
//   tooth    1.2  / 3.0    18,092        156           7.7 s    48 MB   (151^3)
//   tooth    1.0  / 2.0    25,106        295          16.8 s    60 MB   (178^3)
//   tooth    0.8  / 2.4    32,976        217          18.2 s    86 MB   (220^3)
//   input    0.5  / 1.5    11,454         68           3.3 s    49 MB   (166^3)
//   input    0.3  / 0.9    46,868        219          30.4 s   126 MB   (267^3)
//   slot     0.5  / 1.5     4,142         83           1.0 s    30 MB   (88^3)
//   slot     0.3  / 0.9    10,724         99           3.1 s    42 MB   (138^3)
// and, with the final code (the fairing included; load average 3.5, so the
// wall times are about doubled), the tooth at 0.5 / 1.5: estimated 110 s,
// 270 MiB, 99,000 faces; measured 131 s wall (124 s CPU), 245 MB, 85,658
// faces. At 1.67 / 3.34: estimated 3.8 s, 32 MiB, 8,900 faces; measured 5.0 s,
// 36 MB, 12,806 faces.
// The wrap's area is about kAreaPerOccupiedCell x the area of the cells of
// side diagonal / 50 the input passes through (0.77 to 1.53 on these runs:
// the wrap covers a sheet on both sides and a closed surface on one), its
// mean face kFaceAreaPerLod x the level of detail (0.20 to 0.29; the coverage
// rounds split faces below the level of detail), a cycle costs about
// kSecondsPerFaceCycle per face (1.5 to 3.9 us), and the memory is a base,
// the float grid and kBytesPerFace per face (0.8 to 1.6 kB).
constexpr double kOccupancyCellsPerDiagonal = 50.0;
constexpr double kAreaPerOccupiedCell = 1.2;
constexpr double kFaceAreaPerLod = 0.23;
constexpr double kBridgeFaceFactor = 1.15;      // bridged (10 x the tolerance): faces x1.0 to x1.27 measured
                                                // on the inputs above (the tooth at 1.67 / 3.34: 14,770)
constexpr double kCyclesPerRadiusCell = 2.0;    // cycles per seed-sphere radius in cells, plus kBaseCycles
constexpr double kBaseCycles = 20.0;
constexpr double kSecondsPerFaceCycle = 3.0e-6;
constexpr double kSecondsPerDistance = 5.0e-8;  // per point-triangle distance of the field
constexpr double kSecondsPerCell = 3.0e-9;      // per grid cell (allocation and fill)
constexpr double kBaseBytes = 16.0 * 1048576.0;
constexpr double kBytesPerCell = 4.0;           // the field is float
constexpr double kBytesPerCellBridged = 13.0;   // and the bridged field, the flood fill's mark and queue
constexpr double kBytesPerFace = 1000.0;        // the wrap, its guard grid and per-vertex state
constexpr double kBytesPerInputTriangle = 300.0;  // the input as an obstacle and a locator

// The area of the cells (side diagonal / 50) the input passes through: a
// proxy for the wrap's area that needs no wrap and also sees point clouds.
double occupied_area(const std::vector<Triangle>& input, const WrapGeometry& g, double cell_size) {
  const double diagonal = (g.hi - g.lo).norm();
  const double side = diagonal > 0.0 ? diagonal / kOccupancyCellsPerDiagonal : cell_size;
  std::unordered_set<CellKey> cells;
  for (const auto& t : input) {
    const double longest = std::max({(t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm()});
    const int n = std::max(1, static_cast<int>(std::ceil(2.0 * longest / side)));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const Vec3 p = t[0] + (t[1] - t[0]) * (static_cast<double>(i) / n) + (t[2] - t[0]) * (static_cast<double>(j) / n);
        const auto c = cell_of(p - g.lo, side);
        cells.insert(cell_key(c[0], c[1], c[2]));
      }
  }
  return static_cast<double>(cells.size()) * side * side;
}

WrapEstimate estimate_with(const std::vector<Triangle>& input, const WrapOptions& w, double occupied) {
  const WrapGeometry g = geometry_of(input, w);
  const DistanceFieldSize field = distance_field_size(input, g.field_lo, g.field_hi, g.field);
  WrapEstimate e;
  e.grid = field.dims;
  e.cells = field.cells;
  e.area = kAreaPerOccupiedCell * occupied;
  const double refinements = std::pow(4.0, w.global_refinements);
  e.faces = refinements * e.area / (kFaceAreaPerLod * w.lod_face_area * w.cell_size * w.cell_size) *
            (bridge_of(w) > 0.0 ? kBridgeFaceFactor : 1.0);
  e.cycles = std::min<double>(w.max_cycles, kBaseCycles * (1 + w.global_refinements) +
                                                kCyclesPerRadiusCell * g.radius / w.cell_size);
  e.seconds = kSecondsPerFaceCycle * e.faces * e.cycles + kSecondsPerDistance * field.evaluations +
              kSecondsPerCell * field.cells;
  // Bridging keeps a second float grid, a byte and a 4-byte queue entry per cell while it builds it.
  e.bytes = kBaseBytes + (bridge_of(w) > 0.0 ? kBytesPerCellBridged : kBytesPerCell) * field.cells + kBytesPerFace * e.faces +
            kBytesPerInputTriangle * static_cast<double>(input.size());
  return e;
}

// The smallest cell size (with the tolerance raised to it when below) whose
// estimate is within the limits; 0 when none up to the input's diagonal is.
double fitting_cell_size(const std::vector<Triangle>& input, const WrapOptions& w, double occupied) {
  const auto fits = [&](double cell) {
    WrapOptions o = w;
    o.cell_size = cell;
    o.tolerance = std::max(w.tolerance, cell);
    const WrapEstimate e = estimate_with(input, o, occupied);
    return (w.time_limit <= 0.0 || e.seconds <= w.time_limit) &&
           (w.memory_limit <= 0.0 || e.bytes <= w.memory_limit * 1073741824.0);
  };
  const WrapGeometry g = geometry_of(input, w);
  double bad = w.cell_size, good = std::max((g.hi - g.lo).norm(), 2.0 * w.cell_size);
  if (!fits(good)) return 0.0;
  for (int i = 0; i < 40 && good > 1.01 * bad; ++i) {
    const double mid = std::sqrt(bad * good);
    (fits(mid) ? good : bad) = mid;
  }
  return good;
}

// An estimate to two significant digits, without an exponent ("220", "3.1", "86000").
std::string rough(double v) {
  if (!(v >= 100.0) || !std::isfinite(v)) return format_number(v, 2);
  const double unit = std::pow(10.0, std::floor(std::log10(v)) - 1.0);
  return std::to_string(static_cast<long long>(std::round(v / unit) * unit));
}

std::string megabytes(double bytes) {
  return bytes >= 1073741824.0 ? rough(bytes / 1073741824.0) + " GiB" : rough(bytes / 1048576.0) + " MiB";
}

// Refuses (WrapTooCostly) a wrap whose estimate exceeds the limits.
void check_cost(const std::vector<Triangle>& input, const WrapOptions& w) {
  if (w.time_limit <= 0.0 && w.memory_limit <= 0.0) return;
  const WrapGeometry g = geometry_of(input, w);
  const double occupied = occupied_area(input, g, w.cell_size);
  const WrapEstimate e = estimate_with(input, w, occupied);
  const bool slow = w.time_limit > 0.0 && e.seconds > w.time_limit;
  const bool big = w.memory_limit > 0.0 && e.bytes > w.memory_limit * 1073741824.0;
  if (!slow && !big) return;
  const double cell = fitting_cell_size(input, w, occupied);
  std::string message = "the wrap would take " + e.text() + ", above ";
  if (slow) message += "the time limit of " + fmt(w.time_limit) + " s";
  if (slow && big) message += " and ";
  if (big) message += "the memory limit of " + fmt(w.memory_limit) + " GiB";
  message += "; refused before starting. Raise the cell size";
  if (cell > 0.0) {
    const double rounded = std::ceil(cell * 100.0) / 100.0;  // up to 0.01 mm: still within the limits
    message += " (" + fmt(rounded) + " mm is within the limits" +
               (rounded > w.tolerance ? ", with a tolerance of at least " + fmt(rounded) + " mm" : "") + ")";
  }
  message += ", or the limits (time_limit, memory_limit; 0 = no limit). The cost grows as (size / cell size)^3.";
  throw WrapTooCostly(message, e, cell);
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

// Fairing of the vertices the field does not hold. The model's pressure (D)
// is stronger per cell than eq. 3's pull (a2 / extent, the extent floored at
// the level of detail), so a vertex over free space, where nothing in the
// field stops it, advances until eq. 3's ratio reaches its hard limit (0.5):
// over a hole, and where the wrap sinks through one, such vertices stand an
// edge's height above or below their neighbours (the "pyramids"). Here every
// vertex more than a cell beyond the level the wrap settles at is moved
// toward the centroid of its neighbours, in vertex order (the same result for
// any thread count), a cell at most per pass, while it stays out of the
// object region, the guard and the obstacle accept it; the vertices the field
// holds stay. Returns the moves made; `free_count` gets the vertices faired.
// (shrink_wrap undoes the fairing when it takes input farther from the wrap
// than 90% of the tolerance and than before.)
std::size_t fair_unsupported(Mesh& mesh, const Volume& field, double level, double cell, const Obstacle& obstacle,
                             int passes, std::size_t* free_count) {
  std::vector<Mesh::VertexHandle> free;
  for (auto v : mesh.vertices())
    if (field.sample(to_eigen(mesh.point(v))) > level + cell) free.push_back(v);
  *free_count = free.size();
  if (free.empty()) return 0;
  IntersectionGuard guard(mesh, cell, 1e-6 * cell * cell);
  return relax_toward_neighbours(mesh, free, 0.5, cell, passes, [&] { guard.rebuild(); },
                                 [&](Mesh::VertexHandle v, const Vec3& q) {
                                   return field.sample(q) >= level && guard.move_is_safe(v, q) &&
                                          !obstacle.blocks_move(mesh, v, q);
                                 });
}

}  // namespace

std::string WrapEstimate::text() const {
  std::ostringstream s;
  s << "about " << rough(seconds) << " s and " << megabytes(bytes) << " (a " << grid[0] << " x " << grid[1] << " x "
    << grid[2] << " distance grid, about " << rough(faces) << " faces)";
  return s.str();
}

WrapEstimate estimate_wrap(const std::vector<Triangle>& input, const WrapOptions& w) {
  validate(input, w);
  const WrapGeometry g = geometry_of(input, w);
  return estimate_with(input, w, occupied_area(input, g, w.cell_size));
}

WrapResult shrink_wrap(const std::vector<Triangle>& input, const WrapOptions& w, const DeformObserver& observer) {
  validate(input, w);
  check_cost(input, w);
  WrapResult out;
  std::vector<std::string>* log = &out.notes;
  const WrapGeometry g = geometry_of(input, w);
  const double offset = g.offset;
  const Vec3 centre = g.centre;
  const double radius = g.radius;
  const Volume distance = distance_field(input, g.field_lo, g.field_hi, g.field, w.field_progress);
  if (distance.voxel_count() == 0) throw Error("cancelled");
  log->push_back("distance field: " + std::to_string(distance.dims()[0]) + " x " + std::to_string(distance.dims()[1]) +
                 " x " + std::to_string(distance.dims()[2]) + " cells of " + fmt(w.cell_size) + " mm; the wrap settles " +
                 fmt(offset) + " mm from the input");
  // Bridging: the wrap settles on the field of balls of diameter `bridge`
  // rolled in from outside, which spans the openings they cannot pass.
  const double bridge = bridge_of(w);
  const bool bridging = bridge > 0.0;
  // Input a cap would hide more than 3/4 of the tolerance deep is reopened up
  // front: only openings with no input under them (holes) stay capped.
  std::vector<Vec3> corners;
  if (bridging)
    for (const auto& t : input)
      for (const auto& p : t) corners.push_back(p);
  std::size_t reopened = 0;
  Volume bridged =
      bridging ? bridged_distance_field(distance, offset, 0.5 * bridge, corners, 0.75 * w.tolerance, &reopened)
               : Volume();
  std::vector<Vec3>().swap(corners);
  if (bridging)
    log->push_back("bridging: openings balls of " + fmt(bridge) + " mm cannot pass are capped, but " +
                   std::to_string(reopened) + " regions over input the caps would hide");
  const Volume& field = bridging ? bridged : distance;

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
    if (bridging) {
      // A cap that hides input opens around it, down to the input.
      std::vector<Vec3> points;
      std::vector<double> radii;
      for (const auto& p : far) {
        points.push_back(p.point);
        radii.push_back(p.distance + 2.0 * w.cell_size);
      }
      reopen_field(bridged, distance, points, radii);
    }
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

  // No pyramids: the vertices the field does not hold are faired.
  if (w.fairing) {
    std::vector<Mesh::Point> before;  // undone when it takes input away from the wrap
    for (auto v : mesh.vertices()) before.push_back(mesh.point(v));
    std::size_t free = 0;
    const std::size_t moves = fair_unsupported(mesh, field, offset, w.cell_size, obstacle, 30, &free);
    if (moves > 0) {
      const FloatSnapResult snap = snap_to_float(mesh, w.threads);
      double faired = 0.0;
      far_input(input, mesh, refine_beyond, &faired);
      if (faired > input_to_wrap && faired > aim) {
        for (auto v : mesh.vertices()) mesh.set_point(v, before[static_cast<std::size_t>(v.idx())]);
        log->push_back("fairing undone: it took input to " + fmt(faired) + " mm from the wrap");
      } else {
        input_to_wrap = faired;
        log->push_back("fairing: " + std::to_string(free) + " vertices over free space (holes) smoothed, " +
                       std::to_string(moves) + " moves");
        if (snap.refused > 0)
          log->push_back("warning: " + std::to_string(snap.refused) +
                         " vertices could not be moved to float precision without a self-intersection");
      }
    }
  }

  // Triangle quality, the last geometric step: after the fairing, every flip,
  // collapse and move also checked against the input (the obstacle); the
  // surface moves by at most a tenth of a cell (a quarter, half a cell for
  // the faces still below the bound after that).
  if (w.min_angle > 0.0) {
    QualityOptions q;
    q.min_angle = w.min_angle;
    q.max_error = 0.1 * w.cell_size;
    q.obstacle = &obstacle;
    q.threads = w.threads;
    const QualityResult r = improve_triangle_quality(mesh, q);
    mesh.release_vertex_status();
    mesh.release_edge_status();
    mesh.release_halfedge_status();
    mesh.release_face_status();
    out.deform.quality_flips = r.flips;
    out.deform.quality_splits = r.splits;
    out.deform.quality_collapses = r.collapses;
    out.deform.quality_moves = r.moves;
    out.deform.faces_below_min_angle = r.faces_below;
    if (r.flips + r.splits + r.collapses + r.moves > 0) {
      const FloatSnapResult snap = snap_to_float(mesh, w.threads);
      far_input(input, mesh, refine_beyond, &input_to_wrap);
      log->push_back("triangle quality: " + std::to_string(r.flips) + " flips, " + std::to_string(r.splits) +
                     " splits, " + std::to_string(r.collapses) + " collapses, " + std::to_string(r.moves) +
                     " moves; smallest angle " + fmt(r.min_angle_before) + " -> " + fmt(r.min_angle_after) +
                     " degrees");
      if (snap.refused > 0)
        log->push_back("warning: " + std::to_string(snap.refused) +
                       " vertices could not be moved to float precision without a self-intersection");
    }
    if (r.faces_below > 0)
      log->push_back("warning: " + std::to_string(r.faces_below) + " faces keep an angle below " +
                     fmt(w.min_angle) + " degrees (the guarantees came first)");
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
