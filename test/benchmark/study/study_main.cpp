// gdm_benchmark_study: our GDM side by side with its peers (VTK flying edges,
// the 3D Slicer chain, ITK's BinaryMask3DMeshSource and deformable simplex
// mesh, CGAL Mesh_3) on the same volumes, in one run. Writes a markdown report
// with tables, PNG plots and PNG pictures (issue 6). Usage:
//
//   gdm_benchmark_study --out DIR [--quick] [--runs N] [--threads N]
//                       [--data DIR] [--commit TEXT] [--budget SECONDS]
//                       [--noise-sigma S] [--noise-seed N]
//
// Run it under xvfb-run on a machine without a display (VTK renders offscreen
// through an X server). scripts/benchmark-study.sh runs the whole study.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "cases.h"
#include "gdm/cavities.h"
#include "gdm/deformer.h"
#include "gdm/errors.h"
#include "gdm/phantoms.h"
#include "gdm/self_contact.h"
#include "metrics.h"
#include "peer_cgal.h"
#include "peer_itk.h"
#include "peer_vtk.h"

namespace study {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Settings {
  std::string out;
  bool quick = false;
  int runs = 5;            // timed runs per method and case (median reported)
  int threads = 0;         // 0 = all cores
  double method_budget = 8.0;   // seconds of repeated runs per method and case before fewer runs are taken
  std::string data = "../shared/data";
  std::string commit = "unknown";
  std::vector<std::string> only;  // run only the cases whose id contains one of these (debugging)
  bool dump = false;               // write every surface as OFF into out/surfaces/
  bool faces_sweep = false;        // only the face budget against the Slicer chain at equal faces (a table on stdout)
  std::vector<double> fractions = {0.05, 0.10, 0.20};  // --faces-sweep: budgets as fractions of flying edges' faces
  bool sweep_cgal = false;         // --faces-sweep: CGAL Mesh_3 matched to gdm's counts too (slow)
  bool sweep_scans = false;        // --faces-sweep: the real scans (--data) instead of the phantoms
  bool sweep_exact = false;        // --faces-sweep: gdm with topology exact (handles opened, cavities inward)
  bool sweep_voxel_seed = false;   // --faces-sweep: gdm started from the voxel seed (voxel_seed)
  bool sweep_cut = false;          // --faces-sweep: gdm with handle_repair cut (handles cut across their bodies)
  std::vector<double> budgets;     // --faces-sweep: face budgets as counts (instead of --fractions)
  PhantomNoise noise;              // the Gaussian-noise phantoms' sigma and first seed
};

void write_off(const fs::path& file, const Surface& s) {
  fs::create_directories(file.parent_path());
  std::ofstream o(file.string() + ".tmp");
  o << "OFF\n" << s.points.size() << ' ' << s.faces.size() << " 0\n";
  for (const auto& p : s.points) o << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& f : s.faces) o << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  o.close();
  fs::rename(file.string() + ".tmp", file);
}

// ---- the methods ---------------------------------------------------------
// One row per method configuration. A new configuration of our GDM (e.g. with
// a final sub-voxel fit or an error-driven level of detail) is one more row
// with Kind::gdm and its `configure`.
enum class Kind { gdm, flying_edges, slicer_chain, itk_binary_mask, itk_simplex, cgal_mesh3 };

struct Method {
  std::string id;
  std::string label;
  std::string short_label;  // for pictures and plots
  Kind kind;
  std::function<void(gdm::DeformOptions&)> configure = {};  // gdm only: changes to the default options
  bool without_gap = false;  // gdm only: G = 0 even where the case sets a gap; run only on such cases
  int seed_level = 0;        // gdm only: geodesic level of the seed sphere (0: icosahedron)
  bool openings_only = false;  // run only on the "openings and channels" cases
  bool topology_only = false;  // run only on the "topology" cases
  bool skip_topology = false;  // not run on the "topology" cases
  bool scans_too = false;      // with topology_only: run on the "scan" cases as well
};

std::vector<Method> methods() {
  return {
      {"gdm", "our GDM (defaults)", "our GDM", Kind::gdm},
      {"gdm-lod", "our GDM, error-driven level of detail 0.1 voxel", "our GDM (error LOD)", Kind::gdm,
       [](gdm::DeformOptions& o) { o.lod_tolerance = 0.1; }, false, 0, false, false, true},
      {"gdm-nogap", "our GDM without the gap (G = 0), stops at the border", "our GDM, no gap", Kind::gdm, {}, true},
      {"gdm-seed80", "our GDM (defaults), the command's seed (80-face sphere)", "our GDM, 80-face seed", Kind::gdm, {},
       false, 1, true},
      // Issue 15: the data's topology (cavities as inward components, handles as tubes); the default is solid.
      {"gdm-exact", "our GDM, topology exact", "our GDM (exact)", Kind::gdm,
       [](gdm::DeformOptions& o) { o.topology = gdm::Topology::exact; }, false, 0, false, true},
      {"gdm-exact-seed80", "our GDM, topology exact, the command's seed (80-face sphere)", "our GDM (exact, 80-face seed)",
       Kind::gdm, [](gdm::DeformOptions& o) { o.topology = gdm::Topology::exact; }, false, 1, false, true},
      // Stop 52: each handle cut across its body instead of capped across its hole (growing).
      {"gdm-cut", "our GDM, handles cut (handle_repair cut)", "our GDM (cut)", Kind::gdm,
       [](gdm::DeformOptions& o) {
         if (o.mode == gdm::Mode::grow && o.topology == gdm::Topology::solid) o.handle_repair = gdm::HandleRepair::cut;
       },
       false, 0, false, true},
      // Stop 54: the model started from the object's voxels (voxel_seed.h) instead of grown from the seed.
      // On the scans too (stop 67): their grown models' seams are what it removes (the hint of the
      // command's summary), and issue 16's real-surface targets are measured there.
      {"gdm-voxel-seed", "our GDM, started from the voxel seed (voxel_seed)", "our GDM (voxel seed)", Kind::gdm,
       [](gdm::DeformOptions& o) { o.voxel_seed = true; }, false, 0, false, true, false, true},
      {"fe", "VTK flying edges", "flying edges", Kind::flying_edges},
      {"slicer", "Slicer chain (FE + sinc + quadric, to our faces)", "Slicer chain", Kind::slicer_chain},
      {"itk-mc", "ITK BinaryMask3DMeshSource", "ITK mask MC", Kind::itk_binary_mask},
      {"itk-simplex", "ITK simplex mesh, balloon", "ITK simplex", Kind::itk_simplex},
      {"cgal", "CGAL Mesh_3 (facet_distance to our faces)", "CGAL Mesh_3", Kind::cgal_mesh3},
  };
}

struct Row {
  std::string method_id, label, short_label;
  bool ran = false;
  std::string skip_reason;
  std::size_t faces = 0;
  double median_s = 0.0;
  int runs = 0;
  ErrorStats error;     // model -> truth
  double coverage = NAN;  // max truth -> model, voxels
  // Our defaults on scans: the same over the truth's points on the seed's
  // object more than two voxels from what the model fills on purpose and
  // reports (cavities.h); NAN for other rows. `filled_regions`: how many it reports (0: none).
  double coverage_outside_filled = NAN;
  std::size_t filled_regions = 0;
  double missed = NAN;    // share of the truth's sample points farther than a voxel from the model
  double leak_share = NAN;  // phantoms: share of the model's points more than a voxel outside the true object
  double leak_max = NAN;    // phantoms: how far outside the object the model goes, voxels (0: nowhere)
  Checks checks;
  std::string note;
  Surface surface;      // kept for pictures
  std::vector<double> truth_to_model;  // per point of the truth, in its order (physical units); empty without a truth
  // Topology cases (issue 15):
  std::string truth;                     // "outer" (our solid topology) or "all" surfaces: what mean/p95 measure
  std::vector<ComponentTopology> parts;  // per component, largest extent first
  int contact_regions = -1;              // regions where the surface meets itself (gdm::find_self_contacts);
                                         // -1: not measurable (not a consistently oriented 2-manifold)
  int contacts_across_object = 0;        // of them, those whose gap lies on the object's side (a double sheet)
  double contact_area = 0.0;             // mm^2, all regions
};

struct CaseResult {
  const Case* c = nullptr;
  std::vector<Row> rows;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int thread_count(const Settings& s) {
  return s.threads > 0 ? s.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

gdm::Volume to_volume(const Image& image) {
  return gdm::Volume(image.dims, image.values, gdm::Vec3(image.spacing[0], image.spacing[1], image.spacing[2]),
                     gdm::Vec3(image.origin[0], image.origin[1], image.origin[2]));
}

// Runs `once` `runs` times, or fewer (at least once) when they would take more than the budget.
template <typename F>
PeerResult repeat(const Settings& s, int runs, F once, std::vector<double>& times) {
  PeerResult last = once();
  times.push_back(last.seconds);
  int n = runs;
  if (last.seconds * runs > s.method_budget) n = std::max(1, static_cast<int>(s.method_budget / std::max(last.seconds, 1e-9)));
  for (int i = 1; i < n; ++i) {
    last = once();
    times.push_back(last.seconds);
  }
  return last;
}

// The options our GDM row `m` runs with on case c.
gdm::DeformOptions gdm_options(const Case& c, const Method& m, int threads) {
  gdm::DeformOptions o;
  o.threshold = c.threshold;
  o.polarity = c.object_brighter ? gdm::Polarity::object_brighter : gdm::Polarity::object_darker;
  o.mode = c.mode;
  o.threads = threads;
  o.gap = m.without_gap ? 0.0 : c.gap;
  // Without the gap the model leaks; like the command line (without --allow-border)
  // it stops when it reaches the volume's border instead of filling the outside.
  if (m.without_gap) o.stop_at_border = true;
  if (m.configure) m.configure(o);
  return o;
}

PeerResult run_gdm(const Case& c, const gdm::Volume& volume, const Method& m, int threads, double lod = 0.0,
                   std::size_t face_budget = 0) {
  gdm::DeformOptions o = gdm_options(c, m, threads);
  if (lod > 0.0) o.lod_face_area = lod;
  o.face_budget = face_budget;
  gdm::Mesh mesh = seed_mesh(c, m.seed_level);
  const auto t0 = Clock::now();
  const gdm::DeformResult r = gdm::deform(mesh, volume, o);
  PeerResult out;
  out.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  out.surface = from_gdm(mesh);
  out.note = gdm::to_string(r.reason) + " after " + std::to_string(r.cycles) + " cycles";
  if (face_budget > 0)
    out.note += ", budget: " + std::to_string(r.budget_subdivisions) + " subdivisions, " +
                std::to_string(r.budget_collapses) + " collapses, " + std::to_string(r.budget_splits) + " splits";
  if (r.border_vertices > 0) out.note += ", " + std::to_string(r.border_vertices) + " vertices at the border (leak)";
  if (c.group == "topology") {
    out.note += std::string(", topology ") + (o.topology == gdm::Topology::exact ? "exact" : "solid") + ": " +
                std::to_string(r.cavities) + " cavities filled, " + std::to_string(r.handles) + " handles capped";
    if (o.topology == gdm::Topology::exact)
      out.note += ", " + std::to_string(r.handles_opened) + " opened into tubes, " + std::to_string(r.cavity_components) +
                  " cavities as inward components (" + std::to_string(r.cavities_not_modelled) + " not modelled)";
  }
  if (c.group == "topology" && std::getenv("GDM_STUDY_VERBOSE"))
    std::fprintf(stderr, "    %s\n    %s\n    %s\n", gdm::cavity_summary(r).c_str(), gdm::handle_summary(r).c_str(),
                 gdm::topology_summary(r).c_str());
  if (o.gap > 0.0) {
    char g[32];
    std::snprintf(g, sizeof g, "%g", o.gap);
    out.note += std::string(", gap ") + g + " mm: " + std::to_string(r.gap_closed_voxels) + " voxels closed";
  }
  return out;
}

// CGAL with facet_distance searched so that its face count is within 15% of
// `target`: faces grow roughly as 1 / facet_distance^2 (measured here); once two distances
// bracket the target, geometric bisection. The closest run is returned.
PeerResult run_cgal_matched(const Case& c, std::size_t target, double& distance_mm) {
  double d = distance_mm > 0 ? distance_mm : 0.2 * c.voxel_size();
  double lo = 0.0, hi = 0.0;  // distances known to give too many / too few faces
  PeerResult best;
  double best_d = d, best_gap = 1e300;
  const auto start = Clock::now();
  for (int i = 0; i < 6; ++i) {
    // Calibration stops after 30 s (large surfaces), keeping the closest run.
    if (i > 0 && std::chrono::duration<double>(Clock::now() - start).count() > 30.0) break;
    PeerResult r = run_cgal_mesh3(c.image, c.threshold, c.object_brighter, d);
    const double f = static_cast<double>(r.surface.faces.size());
    if (std::getenv("GDM_STUDY_VERBOSE")) std::fprintf(stderr, "    cgal calibration: facet_distance %.4g -> %.0f faces (target %zu)\n", d, f, target);
    const double gap = target ? std::abs(std::log(std::max(f, 1.0) / target)) : 0.0;
    if (gap < best_gap) {
      best_gap = gap;
      best = std::move(r);
      best_d = d;
    }
    if (target == 0 || f == 0 || gap <= std::log(1.15)) break;
    if (f > target) lo = d; else hi = d;
    if (lo > 0 && hi > 0) d = std::sqrt(lo * hi);
    else d = std::clamp(d * std::clamp(std::sqrt(f / static_cast<double>(target)), 0.5, 2.0), 0.005 * c.voxel_size(), 10.0 * c.voxel_size());
  }
  distance_mm = best_d;
  return best;
}

int simplex_resolution(std::size_t target) {
  // RegularSphereMeshSource: 8 * 4^r triangles; the simplex dual keeps that count.
  int r = 1;
  while (r < 5 && 8.0 * std::pow(4.0, r + 1) <= 1.4 * static_cast<double>(target)) ++r;
  return r;
}

PeerResult run_simplex(const Case& c, std::size_t target) {
  SimplexOptions o;
  o.resolution = simplex_resolution(target);
  Point seed = c.seed;
  if (c.mode == gdm::Mode::shrink) {
    // Deflate from the ellipsoid GDM shrinks from (in index units).
    o.kappa = -o.kappa;
    for (int a = 0; a < 3; ++a) {
      seed[a] = c.image.origin[a] + 0.5 * (c.image.dims[a] - 1) * c.image.spacing[a];
      o.radii[a] = 0.5 * (c.image.dims[a] - 1) - 1.5;
    }
  } else {
    for (int a = 0; a < 3; ++a) o.radii[a] = c.seed_radius / c.image.spacing[a];
  }
  // Long enough to travel the object's extent at the balloon's pace.
  double extent = 0;
  for (int a = 0; a < 3; ++a) extent = std::max(extent, static_cast<double>(c.image.dims[a]));
  o.iterations = std::clamp(static_cast<int>(4 * extent), 200, 800);
  return run_itk_simplex(c.image, seed, o);
}


// The ground truth of a case: the distance to the true surface, and points on
// it for the coverage (the largest distance from the truth to a model).
struct Truth {
  std::function<double(const Point&)> distance;
  std::unique_ptr<SurfaceDistance> reference;  // scans: the reference surface
  std::vector<Point> points;
  std::size_t reference_faces = 0;
  // Topology cases: the distance to the outer surface only (the truth of the solid topology).
  std::function<double(const Point&)> outer;
  std::unique_ptr<SurfaceDistance> outer_reference;
};

Truth make_truth(const Case& c) {
  Truth t;
  Surface ref;
  if (!c.truth_field.values.empty()) ref = iso_surface(c.truth_field, c.truth_level, 2);
  t.reference_faces = ref.faces.size();
  if (c.exact_distance) {
    t.distance = c.exact_distance;
  } else {
    t.reference = std::make_unique<SurfaceDistance>(ref);
    SurfaceDistance* d = t.reference.get();
    t.distance = [d](const Point& p) { return (*d)(p); };
  }
  if (c.group == "topology") {
    if (c.outer_distance) {
      t.outer = c.outer_distance;
    } else {
      t.outer_reference = std::make_unique<SurfaceDistance>(largest_component(ref));
      SurfaceDistance* d = t.outer_reference.get();
      t.outer = [d](const Point& p) { return (*d)(p); };
    }
  }
  // At most 100k points of the reference for the coverage.
  const std::size_t step = std::max<std::size_t>(1, ref.points.size() / 100000);
  for (std::size_t i = 0; i < ref.points.size(); i += step) t.points.push_back(ref.points[i]);
  return t;
}

void evaluate(Row& row, const Case& c, PeerResult r, const Truth& truth, const gdm::Volume& volume) {
  row.ran = true;
  row.faces = r.surface.faces.size();
  row.note = r.note;
  row.checks = check_surface(r.surface);
  const double voxel = c.voxel_size();
  const std::vector<Point> samples = sample_points(r.surface);
  // Topology cases: our solid model is the outer surface by design and is
  // measured against it; the exact model and the peers against all surfaces.
  const bool outer_truth = truth.outer && row.method_id == "gdm";
  row.error = error_stats(samples, outer_truth ? truth.outer : truth.distance, voxel);
  if (c.group == "topology") {
    row.truth = outer_truth ? "outer" : "all";
    row.parts = component_topology(r.surface);
    gdm::Mesh mesh;
    if (to_gdm_mesh(r.surface, mesh)) {
      const double threshold = c.threshold;
      const bool brighter = c.object_brighter;
      const gdm::ContactReport contacts = gdm::find_self_contacts(mesh, voxel, [&](const gdm::Vec3& p) {
        const double v = volume.sample(p);
        return brighter ? v > threshold : v < threshold;
      });
      row.contact_regions = static_cast<int>(contacts.regions.size());
      row.contact_area = contacts.area;
      for (const gdm::ContactRegion& region : contacts.regions) row.contacts_across_object += region.across_object;
    }
  }
  if (c.signed_distance && !samples.empty()) {
    std::size_t outside = 0;
    double farthest = 0.0;
    for (const Point& p : samples) {
      const double d = c.signed_distance(p) / voxel;
      if (d > 1.0) ++outside;
      farthest = std::max(farthest, d);
    }
    row.leak_share = static_cast<double>(outside) / static_cast<double>(samples.size());
    row.leak_max = farthest;
  }
  if (!truth.points.empty() && !r.surface.faces.empty()) {
    SurfaceDistance model(r.surface);
    double worst = 0.0;
    std::size_t far = 0;
    if (!model.empty()) {
      row.truth_to_model.reserve(truth.points.size());
      for (const Point& p : truth.points) {
        const double d = model(p);
        row.truth_to_model.push_back(d);
        worst = std::max(worst, d);
        if (d > voxel) ++far;
      }
    }
    row.coverage = worst / voxel;
    row.missed = static_cast<double>(far) / static_cast<double>(truth.points.size());
  }
  row.surface = std::move(r.surface);
}

std::string fmt(const char* f, double v);

// Scans: the largest distance from the truth to our model over the truth's
// points on the seed's object and away from what the model fills on purpose
// and reports (cavities.h: enclosed cavities, pockets behind narrow
// openings, membranes across handles; the report gives each one's kind and
// place). The fill is the one deform() makes from the same seed
// (cavity_fill_for); a truth point within two voxels of a filled voxel, or
// farther than that from the seed's object, is left out. Tells a surface the model bridges by design (its topology
// kept to genus 0, as the command line says) from one it misses.
void measure_coverage_outside_filled(Row& row, const Case& c, const gdm::Volume& volume, const Method& m,
                                     const Truth& truth) {
  if (row.truth_to_model.size() != truth.points.size()) return;  // evaluate() measured nothing
  const gdm::Mesh seed = seed_mesh(c, m.seed_level);
  const gdm::CavityFill fill = gdm::cavity_fill_for(seed, volume, gdm_options(c, m, 0));
  row.filled_regions = 0;  // as the report lists them: specks of noise apart (they are filled all the same)
  if (fill.applied)
    for (const gdm::Cavity& r : fill.cavities) row.filled_regions += r.voxels >= gdm::kCavitySpeckVoxels;
  const gdm::Index3& n = volume.dims();
  const std::vector<float>& before = volume.values();
  const std::vector<float>& after = fill.applied ? fill.volume.values() : before;
  const auto index = [&](int i, int j, int k) {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(n[0]) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(k));
  };
  const auto inside = [&](int i, int j, int k) { return i >= 0 && j >= 0 && k >= 0 && i < n[0] && j < n[1] && k < n[2]; };
  // The seed's object: the 6-connected region on the object's side of the
  // threshold (with what is filled) holding the seed's centre; the truth of
  // a scan also holds other objects (a CT table), which no single model is
  // meant to reach. region_below on the values turned over when the object
  // is the brighter side.
  std::vector<float> side(after);
  double level = c.threshold;
  if (c.object_brighter) {
    for (float& v : side) v = -v;
    level = -level;
  }
  const gdm::Vec3 centre = volume.to_continuous_index(gdm::Vec3(c.seed[0], c.seed[1], c.seed[2]));
  gdm::Index3 start;
  for (int a = 0; a < 3; ++a) start[a] = std::clamp(static_cast<int>(std::lround(centre[a])), 0, n[a] - 1);
  const std::vector<char> object = gdm::phantoms::region_below(
      gdm::Volume(n, std::move(side), volume.spacing(), volume.origin(), volume.direction()), start, level);
  const double voxel = c.voxel_size();
  constexpr double kReach = 2.0;  // voxels
  const gdm::Vec3 span = (kReach * voxel) * volume.spacing().cwiseInverse();  // index units per axis
  double worst = 0.0;
  gdm::Vec3 where = gdm::Vec3::Zero();
  for (std::size_t t = 0; t < truth.points.size(); ++t) {
    const Point& p = truth.points[t];
    const gdm::Vec3 x(p[0], p[1], p[2]);
    const gdm::Vec3 ci = volume.to_continuous_index(x);
    bool near_fill = false, near_object = false;
    for (int k = static_cast<int>(std::floor(ci[2] - span[2])); k <= static_cast<int>(std::ceil(ci[2] + span[2])) && !near_fill; ++k)
      for (int j = static_cast<int>(std::floor(ci[1] - span[1])); j <= static_cast<int>(std::ceil(ci[1] + span[1])) && !near_fill; ++j)
        for (int i = static_cast<int>(std::floor(ci[0] - span[0])); i <= static_cast<int>(std::ceil(ci[0] + span[0])) && !near_fill; ++i) {
          if (!inside(i, j, k) || (volume.to_physical(gdm::Vec3(i, j, k)) - x).norm() > kReach * voxel) continue;
          const std::size_t at = index(i, j, k);
          near_fill = before[at] != after[at];
          near_object = near_object || object[at];
        }
    if (near_fill || !near_object) continue;
    const double d = row.truth_to_model[t];
    if (d > worst) {
      worst = d;
      where = x;
    }
  }
  row.coverage_outside_filled = worst / voxel;
  row.note += ", truth→model max on the seed's object " + fmt("%.2f", row.coverage_outside_filled) + " (at (" + fmt("%.0f", where[0]) +
              ", " + fmt("%.0f", where[1]) + ", " + fmt("%.0f", where[2]) + ") mm)" +
              (row.filled_regions == 0 ? std::string(" (it fills nothing)")
                                       : " away from the " + std::to_string(row.filled_regions) +
                                             (row.filled_regions == 1 ? " region" : " regions") + " it fills and reports");
}

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

CaseResult run_case(const Settings& s, const Case& c, const std::vector<Method>& ms) {
  CaseResult out;
  out.c = &c;
  const int threads = thread_count(s);
  const gdm::Volume volume = to_volume(c.image);
  const Truth truth = make_truth(c);
  std::size_t ours = 0;
  for (const Method& m : ms) {
    if (m.without_gap && c.gap <= 0.0) continue;  // the same run as the defaults
    if (m.openings_only && c.group != "openings and channels") continue;
    if (m.topology_only && c.group != "topology" && !(m.scans_too && c.group == "scan")) continue;
    if (m.skip_topology && c.group == "topology") continue;
    Row row;
    row.method_id = m.id;
    row.label = m.label;
    row.short_label = m.short_label;
    const auto t0 = Clock::now();
    try {
      std::vector<double> times;
      PeerResult r;
      const int runs = s.quick ? 1 : s.runs;
      switch (m.kind) {
        case Kind::gdm:
          r = repeat(s, runs, [&] { return run_gdm(c, volume, m, threads); }, times);
          if (m.id == "gdm") ours = r.surface.faces.size();
          break;
        case Kind::flying_edges:
          r = repeat(s, runs, [&] { return run_flying_edges(c.image, c.threshold); }, times);
          break;
        case Kind::slicer_chain:
          r = repeat(s, runs, [&] { return run_slicer_chain(c.image, c.threshold, ours); }, times);
          break;
        case Kind::itk_binary_mask:
          r = repeat(s, runs, [&] { return run_itk_binary_mask(c.image, c.threshold, c.object_brighter); }, times);
          break;
        case Kind::itk_simplex:
          if (c.image.values.size() > 40000000) {
            row.skip_reason = "skipped: its gradient image would need " +
                              fmt("%.1f", 24.0 * c.image.values.size() / 1e9) + " GB";
            break;
          }
          r = repeat(s, runs, [&] { return run_simplex(c, ours); }, times);
          break;
        case Kind::cgal_mesh3: {
          double d = 0.0;
          run_cgal_matched(c, ours, d);  // calibration runs are not timed
          r = repeat(s, runs, [&] { return run_cgal_mesh3(c.image, c.threshold, c.object_brighter, d); }, times);
          break;
        }
      }
      if (row.skip_reason.empty()) {
        row.median_s = median(times);
        row.runs = static_cast<int>(times.size());
        if (s.dump) write_off(fs::path(s.out) / "surfaces" / (c.id + "-" + m.id + ".off"), r.surface);
        evaluate(row, c, std::move(r), truth, volume);
        if (m.id == "gdm" && c.group == "scan") measure_coverage_outside_filled(row, c, volume, m, truth);
        std::vector<double>().swap(row.truth_to_model);  // a scan's truth has millions of points; rows outlive the case
      }
    } catch (const std::exception& e) {
      row.ran = false;
      row.skip_reason = std::string("failed: ") + e.what();
    }
    std::fprintf(stderr, "  %-12s %-44s faces %8zu  median %8.3f s x%d  mean %.3f  (%.1f s)%s\n", m.id.c_str(),
                 c.name.c_str(), row.faces, row.median_s, row.runs, row.error.mean,
                 std::chrono::duration<double>(Clock::now() - t0).count(),
                 row.skip_reason.empty() ? "" : (" " + row.skip_reason).c_str());
    out.rows.push_back(std::move(row));
  }
  return out;
}

// ---- report ----------------------------------------------------------------

std::string yes_no(bool b) { return b ? "yes" : "**no**"; }

std::string cell_time(const Row& r) { return fmt("%.1f", 1000.0 * r.median_s) + " (" + std::to_string(r.runs) + ")"; }

void write_table(std::ostream& o, const CaseResult& cr) {
  const Case& c = *cr.c;
  o << "\n#### " << c.name << "\n\n";
  o << "Volume " << c.image.dims[0] << "x" << c.image.dims[1] << "x" << c.image.dims[2] << ", spacing "
    << fmt("%g", c.image.spacing[0]) << "x" << fmt("%g", c.image.spacing[1]) << "x" << fmt("%g", c.image.spacing[2])
    << " mm, threshold " << fmt("%g", c.threshold) << ", object " << (c.object_brighter ? "brighter" : "darker")
    << (c.gap > 0.0 ? ", gap " + fmt("%g", c.gap) + " mm for our GDM" : std::string())
    << ", GDM " << (c.mode == gdm::Mode::grow ? "grows from a seed inside" : "shrinks from outside")
    << (c.exact_distance ? "; distances to the exact surface" : "; distances to the iso-surface of the 2x-upsampled volume")
    << ". " << c.note << "\n\n";
  o << "| method | faces | time ms (runs) | mean | p95 | max | truth→model max | closed | 2-manifold | self-int. pairs | components | genus | note |\n";
  o << "|---|---:|---:|---:|---:|---:|---:|:-:|:-:|---:|---:|---:|---|\n";
  for (const Row& r : cr.rows) {
    if (!r.ran) {
      o << "| " << r.label << " | | | | | | | | | | | | " << r.skip_reason << " |\n";
      continue;
    }
    o << "| " << r.label << " | " << r.faces << " | " << cell_time(r) << " | " << fmt("%.3f", r.error.mean) << " | "
      << fmt("%.3f", r.error.p95) << " | " << fmt("%.2f", r.error.max) << " | "
      << (std::isnan(r.coverage) ? std::string("–") : fmt("%.2f", r.coverage)) << " | " << yes_no(r.checks.closed)
      << " | " << yes_no(r.checks.two_manifold) << " | "
      << (r.checks.self_intersections < 0 ? std::string("not computed") : std::to_string(r.checks.self_intersections))
      << " | " << r.checks.components << " | " << (r.checks.genus < 0 ? std::string("–") : std::to_string(r.checks.genus))
      << " | " << r.note << " |\n";
  }
}

const Row* find_row(const CaseResult& cr, const std::string& id) {
  for (const Row& r : cr.rows)
    if (r.method_id == id && r.ran) return &r;
  return nullptr;
}

std::string machine_cpu() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

Series named(const std::string& name) {
  Series s;
  s.name = name;
  return s;
}

std::string percent(double share) {
  if (std::isnan(share)) return "–";
  if (share == 0.0) return "0";
  return share < 0.001 ? "<0.1" : fmt("%.1f", 100.0 * share);
}

// Where each method leaks through an opening (its surface outside the true
// object) or misses a part of the object (the truth far from its surface):
// the cases with openings the model must bridge and channels it must follow.
void write_leak_section(std::ostream& o, const std::vector<CaseResult>& results) {
  std::vector<const CaseResult*> cases;
  for (const CaseResult& cr : results)
    if (cr.c->gap > 0.0 || cr.c->group == "openings and channels") cases.push_back(&cr);
  if (cases.empty()) return;
  o << "\n## Leaks and misses: openings and channels\n\n";
  o << "The cases whose object has an opening in its wall that the model must not pass (the hole-in-the-wall phantoms, "
       "the opened bottles) or channels it must follow (the chamber with channels). The truth is the object without "
       "the opening: the cavity's analytic surface, the opening capped on it (bottles: the cavity's sphere). "
       "**leak %**: share of the method's surface (vertices and face centroids) more than a voxel outside the true "
       "object; **leak max**: how far outside it goes (voxels; the bottles' wall is 2 voxels thick, the holed "
       "phantoms' 4, so a surface that takes the wall's outside shows that much, a model that escapes through the "
       "opening much more). **missed %**: share of the true surface (sampled) farther than a voxel from the method's "
       "surface; **truth→model max**: the largest such distance (a channel not followed to its end shows its missing "
       "length). Our GDM runs with the case's gap G (the opening plus two voxels) and once without it; the peers have "
       "no notion of a gap. Flying edges, the Slicer chain, ITK's BinaryMask3DMeshSource and CGAL Mesh_3 mesh the "
       "whole volume at the threshold, with no seed and no connected-component step, so they return the wall's "
       "outside as well as the cavity: flying edges and the Slicer chain one surface joined at the opening's rim; "
       "ITK's mask of the dark side is also cut open at the volume's border; CGAL Mesh_3 bounds the dark region by "
       "the image's box, and on the opened bottles, at these face counts, returned only that box. A seeded "
       "connected-component step would not help them: the cavity and the outside are one connected region of the "
       "thresholded image through the opening. ITK's simplex mesh is the only seeded peer; it has no gap either, "
       "and where it stops depends on its balloon force and iterations.\n\n";
  o << "| case | method | faces | time ms | leak % | leak max | missed % | truth→model max | mean | closed | components |\n";
  o << "|---|---|---:|---:|---:|---:|---:|---:|---:|:-:|---:|\n";
  for (const CaseResult* cr : cases) {
    for (const Row& r : cr->rows) {
      if (!r.ran) {
        o << "| " << cr->c->name << " | " << r.label << " | | | | | | | | | " << r.skip_reason << " |\n";
        continue;
      }
      std::string label = r.label;
      if (cr->c->gap > 0.0 && r.method_id.rfind("gdm", 0) == 0 && r.method_id != "gdm-nogap")
        label += ", G = " + fmt("%g", cr->c->gap) + " mm";
      o << "| " << cr->c->name << " | " << label << " | " << r.faces << " | " << fmt("%.1f", 1000.0 * r.median_s) << " | "
        << percent(r.leak_share) << " | " << (std::isnan(r.leak_max) ? std::string("–") : fmt("%.2f", std::max(0.0, r.leak_max)))
        << " | " << percent(r.missed) << " | " << (std::isnan(r.coverage) ? std::string("–") : fmt("%.2f", r.coverage))
        << " | " << fmt("%.3f", r.error.mean) << " | " << yes_no(r.checks.closed) << " | " << r.checks.components << " |\n";
    }
  }
}

// Genus per edge-connected component: those with at least 1 % of the faces
// (largest extent first), the others summed up as islands.
std::string genera(const Row& r) {
  std::size_t total = 0;
  for (const ComponentTopology& p : r.parts) total += p.faces;
  std::string main;
  std::size_t islands = 0, island_faces = 0, islands_open = 0;
  for (const ComponentTopology& p : r.parts) {
    if (static_cast<double>(p.faces) >= 0.01 * static_cast<double>(total)) {
      main += (main.empty() ? "" : ", ") + (p.genus < 0 ? std::string("open") : std::to_string(p.genus));
    } else {
      ++islands;
      island_faces += p.faces;
      if (p.genus < 0) ++islands_open;
    }
  }
  if (main.empty()) main = "–";
  if (islands > 0)
    main += " + " + std::to_string(islands) + " island" + (islands > 1 ? "s" : "") + " (" + std::to_string(island_faces) +
            " faces" + (islands_open > 0 ? ", " + std::to_string(islands_open) + " open or non-manifold" : "") + ")";
  return main;
}

// The main components (at least 1 % of the faces) of a row and their genera.
struct MainParts {
  int components = 0;
  int genus_sum = 0;
  bool all_closed = true;
  std::size_t islands = 0;
};
MainParts main_parts(const Row& r) {
  MainParts m;
  std::size_t total = 0;
  for (const ComponentTopology& p : r.parts) total += p.faces;
  for (const ComponentTopology& p : r.parts) {
    if (static_cast<double>(p.faces) < 0.01 * static_cast<double>(total)) {
      ++m.islands;
      continue;
    }
    ++m.components;
    if (p.genus < 0) m.all_closed = false;
    else m.genus_sum += p.genus;
  }
  return m;
}

// Objects that are not a ball (issue 15): an enclosed cavity (the hollow
// sphere), handles (the tori) and the whole tooth from the dentin. Per method
// the validity, the components and the genus of each (its own Euler
// characteristic), where the surface meets itself, and the distance to the
// truth: the outer surface for our solid topology, all surfaces otherwise.
void write_topology_section(std::ostream& o, const std::vector<CaseResult>& results) {
  std::vector<const CaseResult*> cases;
  for (const CaseResult& cr : results)
    if (cr.c->group == "topology") cases.push_back(&cr);
  if (cases.empty()) return;
  o << "\n## Topology: cavities and handles\n\n";
  o << "Objects that are not a ball (issue 15): a hollow sphere (a bright shell 3 voxels thick around an enclosed "
       "cavity: two surfaces, each genus 0), a torus (genus 1), a double torus (genus 2), each with Gaussian noise of "
       "5% of the contrast and grown from a seed inside the object, and the whole tooth grown from a seed in the "
       "dentin (no cavity filled beforehand, so the pulp chamber is in every method's input). Our GDM runs with "
       "the default topology **solid** (cavities filled, each handle capped by a membrane across its hole: one closed "
       "genus-0 surface, the object's outside) and with topology **exact** (each enclosed cavity its own closed "
       "component with normals into it, each handle's cap opened into a tube: the data's genus), the latter from the study's 20-face "
       "icosahedron and from the command line's 80-face seed sphere. The peers get the "
       "volume and threshold; the Slicer chain and CGAL Mesh_3 are matched to the face count of our solid run. "
       "**truth**: what mean and p95 (voxels, vertices and face centroids) are measured against: *outer* = the object's "
       "outer surface only (our solid run: by design it models nothing inside), *all* = every surface of the object "
       "(the phantoms' analytic surfaces; the tooth: the iso-surface of the 2x-upsampled volume, every component, "
       "outer = its largest). On the tori outer and all are the same surface, so the caps of the solid run count as "
       "error there. **components**: edge-connected components; **genus per component**: (2 − χ)/2 with χ = V − E + F "
       "of each closed component, listed for the components with at least 1% of the faces (largest first), the "
       "smaller ones counted as islands; *open*: a component with an edge not shared by exactly two faces. **contact "
       "regions**: where the surface meets itself (gdm's `find_self_contacts`: two faces that are not neighbours, "
       "facing each other, closer than a voxel), in brackets those whose gap lies on the object's side (a double "
       "sheet: a model grown round something from both sides); – where the output is not a consistently oriented "
       "2-manifold and cannot be measured so. Self-intersecting pairs as in the tables below.\n\n";
  o << "| case | method | truth | faces | time ms | closed | 2-manifold | self-int. pairs | components | genus per "
       "component | contact regions (across object) | contact area mm² | mean | p95 |\n";
  o << "|---|---|:-:|---:|---:|:-:|:-:|---:|---:|---|---:|---:|---:|---:|\n";
  for (const CaseResult* cr : cases) {
    for (const Row& r : cr->rows) {
      std::string label = r.label;
      if (r.method_id == "gdm") label = "our GDM, topology solid (default)";
      if (!r.ran) {
        o << "| " << cr->c->name << " | " << label << " | | | | | | | | " << r.skip_reason << " | | | | |\n";
        continue;
      }
      o << "| " << cr->c->name << " | " << label << " | " << r.truth << " | " << r.faces << " | "
        << fmt("%.1f", 1000.0 * r.median_s) << " | " << yes_no(r.checks.closed) << " | " << yes_no(r.checks.two_manifold)
        << " | "
        << (r.checks.self_intersections < 0 ? std::string("not computed") : std::to_string(r.checks.self_intersections))
        << " | " << r.checks.components << " | " << genera(r) << " | "
        << (r.contact_regions < 0 ? std::string("–")
                                  : std::to_string(r.contact_regions) + " (" + std::to_string(r.contacts_across_object) + ")")
        << " | " << (r.contact_regions < 0 ? std::string("–") : fmt("%.1f", r.contact_area)) << " | "
        << fmt("%.3f", r.error.mean) << " | " << fmt("%.3f", r.error.p95) << " |\n";
    }
  }
  // What the table shows, from its own figures.
  const auto valid = [](const Row& r) {
    return r.checks.closed && r.checks.two_manifold && r.checks.self_intersections == 0;
  };
  const auto describe = [&](const char* id) {
    std::string out;
    for (const CaseResult* cr : cases) {
      const Row* r = find_row(*cr, id);
      if (!r) continue;
      const MainParts m = main_parts(*r);
      out += (out.empty() ? "" : "; ") + cr->c->name + ": " + std::to_string(r->checks.components) + " component" +
             (r->checks.components == 1 ? "" : "s") + " (genus " + genera(*r) + ")" +
             (valid(*r) ? "" : ", **not valid**") +
             (r->contact_regions > 0 ? ", " + std::to_string(r->contact_regions) + " contact regions" : "");
      (void)m;
    }
    return out;
  };
  const auto islands_of = [&](const char* id) {
    std::size_t n = 0, with = 0;
    for (const CaseResult* cr : cases)
      if (const Row* r = find_row(*cr, id)) {
        const std::size_t k = main_parts(*r).islands;
        n += k;
        with += k > 0;
      }
    return std::to_string(n) + " on " + std::to_string(with) + " of " + std::to_string(cases.size()) + " cases";
  };
  int solid_ok = 0, solid_n = 0;
  for (const CaseResult* cr : cases)
    if (const Row* r = find_row(*cr, "gdm")) {
      ++solid_n;
      const MainParts m = main_parts(*r);
      if (valid(*r) && r->checks.components == 1 && m.all_closed && m.genus_sum == 0) ++solid_ok;
    }
  // Which methods give the phantoms' own components and genus (valid and without islands).
  const auto matches = [&](const char* id) {
    int n = 0, k = 0;
    std::string misses;
    for (const CaseResult* cr : cases) {
      if (cr->c->truth_genus < 0) continue;
      const Row* r = find_row(*cr, id);
      if (!r) continue;
      ++n;
      const MainParts m = main_parts(*r);
      if (valid(*r) && m.all_closed && m.islands == 0 && m.components == cr->c->truth_components &&
          m.genus_sum == cr->c->truth_genus)
        ++k;
      else
        misses += (misses.empty() ? "" : ", ") + cr->c->name;
    }
    return std::to_string(k) + " of " + std::to_string(n) + (misses.empty() ? "" : " (not: " + misses + ")");
  };
  o << "\n**What the table shows** (generated from the rows above). Our GDM with the solid topology: " << solid_ok
    << " of " << solid_n
    << " cases give one closed, 2-manifold, self-intersection-free surface of genus 0, as chosen: the hollow sphere's "
       "cavity is not modelled (measured against the outer sphere), the tori's holes are capped (their caps show in "
       "p95 against the tori's surface). Valid, without islands, and with the phantom's own components and genus "
       "(hollow sphere 2 components of genus 0, torus genus 1, double torus genus 2), phantoms matched: our GDM exact "
    << matches("gdm-exact") << "; exact from the command's 80-face seed " << matches("gdm-exact-seed80")
    << "; flying edges " << matches("fe") << "; the Slicer chain " << matches("slicer") << "; ITK's "
    << "BinaryMask3DMeshSource " << matches("itk-mc") << "; ITK's simplex mesh " << matches("itk-simplex")
    << "; CGAL Mesh_3 " << matches("cgal") << ". Our GDM with the exact topology, per case: "
    << describe("gdm-exact") << "; from the 80-face seed: " << describe("gdm-exact-seed80") << ". Flying edges, as marching cubes, has the data's topology by construction: "
    << describe("fe") << " (islands, components under 1% of the faces: " << islands_of("fe")
    << "); ITK's BinaryMask3DMeshSource, marching cubes on the binary mask: "
    << describe("itk-mc") << ". The Slicer chain, decimated to our solid face count: " << describe("slicer")
    << ". CGAL Mesh_3 at our face count: " << describe("cgal") << ". ITK's simplex mesh is one sphere-like "
                                                                   "surface from the seed whatever the object: "
    << describe("itk-simplex") << ". Faces: ";
  {
    std::string faces;
    for (const CaseResult* cr : cases) {
      const Row* e = find_row(*cr, "gdm-exact");
      const Row* fe = find_row(*cr, "fe");
      if (!e || !fe) continue;
      faces += (faces.empty() ? "" : "; ") + cr->c->name + " " + std::to_string(e->faces) + " (exact, mean " +
               fmt("%.3f", e->error.mean) + ") against flying edges' " + std::to_string(fe->faces) + " (mean " +
               fmt("%.3f", fe->error.mean) + ")";
    }
    o << (faces.empty() ? std::string("–") : faces) << ".\n";
  }
}

struct Sweep {
  std::string case_name;
  std::vector<Series> series;
};

}  // namespace

// --faces-sweep (issue 16): on every phantom (clean and noisy; --only
// filters), gdm with a face budget of 5, 10 and 20 % of flying edges' faces
// (--fractions) and the Slicer chain decimated to the faces gdm gave, side by
// side: faces, mean and p95 distance (voxels, vertices, centroids and edge
// midpoints) to the exact surface. A table on stdout; with --out DIR also
// DIR/faces-sweep.csv (gdm, the chain and, with --sweep-cgal, CGAL Mesh_3
// matched to gdm's counts), which scripts/faces_sweep_plot.py draws as one
// distance-vs-faces SVG per phantom. (VTK's line_plot crashed here, outside
// the whole study's run.) With --dump the gdm surfaces go to DIR/surfaces as
// OFF. A fraction of 0 is gdm without a budget (its own count). --budgets
// gives the budgets as face counts; --sweep-scans runs the real scans of
// --data (distances to their reference surfaces) instead of the phantoms;
// --sweep-exact runs gdm with topology exact (its handles opened, its
// enclosed cavities as inward components), as a user keeping the data's
// topology would; --sweep-cut with its handles cut across their bodies
// (handle_repair cut) where it grows; --sweep-voxel-seed started from the
// voxel seed (voxel_seed), also with either of the two.
int faces_sweep(const Settings& s) {
  const int threads = thread_count(s);
  set_vtk_threads(threads);
  const auto all = methods();
  const auto exact = std::find_if(all.begin(), all.end(), [](const Method& m) { return m.id == "gdm-exact"; });
  const auto cut = std::find_if(all.begin(), all.end(), [](const Method& m) { return m.id == "gdm-cut"; });
  const auto voxel = std::find_if(all.begin(), all.end(), [](const Method& m) { return m.id == "gdm-voxel-seed"; });
  Method gdm_method = s.sweep_exact && exact != all.end()        ? *exact
                      : s.sweep_cut && cut != all.end()          ? *cut
                      : s.sweep_voxel_seed && voxel != all.end() ? *voxel
                                                                 : all.front();
  if (s.sweep_voxel_seed && gdm_method.id != "gdm-voxel-seed") {  // with --sweep-cut or --sweep-exact
    gdm_method.id += "-voxel-seed";
    gdm_method.configure = [then = gdm_method.configure](gdm::DeformOptions& o) {
      if (then) then(o);
      o.voxel_seed = true;
    };
  }
  std::ofstream csv;
  if (!s.out.empty()) {
    fs::create_directories(s.out);
    csv.open((fs::path(s.out) / "faces-sweep.csv").string());
    csv << "case,fraction,fe_faces,method,faces,mean_vox,p95_vox,seconds,share_beyond_1vox,mean_within_1vox,"
           "share_on_seams,mean_off_seams_vox\n";
  }
  std::printf("| phantom | budget | gdm faces | gdm mean / p95 | chain faces | chain mean / p95 | gdm s "
              "| beyond 1 voxel: gdm / chain | mean within 1 voxel: gdm / chain | faces on seams: gdm / chain "
              "| mean off the seams: gdm / chain |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|\n");
  const CaseSet set = s.sweep_scans ? scan_cases(s.data) : phantom_cases(false, s.noise);
  for (const std::string& why : set.skipped) std::fprintf(stderr, "skipped: %s\n", why.c_str());
  for (const Case& c : set.cases) {
    if (!s.only.empty() && std::none_of(s.only.begin(), s.only.end(),
                                        [&](const std::string& o) { return c.id.find(o) != std::string::npos; }))
      continue;
    const gdm::Volume volume = to_volume(c.image);
    const Truth truth = make_truth(c);
    const std::size_t fe_faces = run_flying_edges(c.image, c.threshold).surface.faces.size();
    double cgal_distance = 0.0;
    const auto row = [&](double fraction, const char* method, std::size_t faces, const ErrorStats& e, double seconds,
                         const SeamSplit& seams) {
      if (csv.is_open()) {
        csv << '"' << c.name << "\"," << fraction << ',' << fe_faces << ',' << method << ',' << faces << ',' << e.mean
            << ',' << e.p95 << ',' << seconds << ',' << e.share_beyond_one << ',' << e.mean_within_one << ',';
        if (seams.valid)
          csv << seams.share << ',' << seams.mean_elsewhere << '\n';
        else
          csv << ",\n";
      }
    };
    // Seams: faces facing another part of the surface across the object (its side of the threshold).
    const auto object_side = [&](const gdm::Vec3& p) {
      double value = 0.0;
      if (!volume.sample_inside(p, value)) return false;
      return c.object_brighter ? value > c.threshold : value < c.threshold;
    };
    const auto seams_of = [&](const Surface& surface) {
      return seam_split(surface, truth.distance, c.voxel_size(), object_side, threads);
    };
    std::vector<double> fractions = s.fractions;
    if (!s.budgets.empty()) {
      fractions.clear();
      for (const double b : s.budgets) fractions.push_back(b / static_cast<double>(fe_faces));
    }
    for (const double fraction : fractions) {
      const auto budget = static_cast<std::size_t>(std::lround(fraction * static_cast<double>(fe_faces)));
      if (fraction > 0.0 && budget < 20) continue;
      try {
        const PeerResult g = run_gdm(c, volume, gdm_method, threads, 0.0, budget);
        if (std::getenv("GDM_STUDY_VERBOSE")) std::fprintf(stderr, "  %s: %s\n", c.name.c_str(), g.note.c_str());
        if (s.dump)
          write_off(fs::path(s.out) / "surfaces" / (c.id + "-faces-" + std::to_string(budget) + ".off"), g.surface);
        const ErrorStats ge = error_stats(sample_points(g.surface), truth.distance, c.voxel_size());
        const PeerResult sl = run_slicer_chain(c.image, c.threshold, g.surface.faces.size());
        const ErrorStats se = error_stats(sample_points(sl.surface), truth.distance, c.voxel_size());
        const SeamSplit gs = seams_of(g.surface), ss = seams_of(sl.surface);
        const auto share = [](const SeamSplit& x) { return x.valid ? fmt("%.1f %%", 100.0 * x.share) : std::string("-"); };
        const auto elsewhere = [](const SeamSplit& x) { return x.valid ? fmt("%.3f", x.mean_elsewhere) : std::string("-"); };
        std::printf("| %s | %.0f %% of %zu | %zu | %.3f / %.3f | %zu | %.3f / %.3f | %.2f | %.1f / %.1f %% | %.3f / %.3f "
                    "| %s / %s | %s / %s |\n",
                    c.name.c_str(), 100.0 * fraction, fe_faces, g.surface.faces.size(), ge.mean, ge.p95,
                    sl.surface.faces.size(), se.mean, se.p95, g.seconds, 100.0 * ge.share_beyond_one,
                    100.0 * se.share_beyond_one, ge.mean_within_one, se.mean_within_one, share(gs).c_str(),
                    share(ss).c_str(), elsewhere(gs).c_str(), elsewhere(ss).c_str());
        row(fraction, "gdm", g.surface.faces.size(), ge, g.seconds, gs);
        row(fraction, "slicer", sl.surface.faces.size(), se, sl.seconds, ss);
        if (s.sweep_cgal) {
          const PeerResult cg = run_cgal_matched(c, g.surface.faces.size(), cgal_distance);
          const ErrorStats ce = error_stats(sample_points(cg.surface), truth.distance, c.voxel_size());
          row(fraction, "cgal", cg.surface.faces.size(), ce, cg.seconds, seams_of(cg.surface));
        }
      } catch (const std::exception& e) {
        std::printf("| %s | %.0f %% | failed: %s |\n", c.name.c_str(), 100.0 * fraction, e.what());
      }
      std::fflush(stdout);
      csv.flush();
    }
  }
  return 0;
}

int run(const Settings& s) {
  const auto study_start = Clock::now();
  fs::create_directories(s.out);
  const int threads = thread_count(s);
  set_vtk_threads(threads);
  set_itk_threads(threads);
  const auto ms = methods();

  std::vector<CaseSet> sets;
  sets.push_back(phantom_cases(s.quick, s.noise));
  sets.push_back(opening_cases(s.quick));
  if (!s.quick) sets.push_back(scan_cases(s.data));
  if (!s.quick) sets.push_back(topology_cases(s.data));
  sets.push_back(volume_scaling_cases(s.quick));
  sets.push_back(area_scaling_cases(s.quick));
  std::vector<std::string> skipped;
  std::vector<CaseResult> results;
  for (const CaseSet& set : sets) {
    skipped.insert(skipped.end(), set.skipped.begin(), set.skipped.end());
    for (const Case& c : set.cases) {
      if (!s.only.empty() && std::none_of(s.only.begin(), s.only.end(),
                                          [&](const std::string& o) { return c.id.find(o) != std::string::npos; }))
        continue;
      std::fprintf(stderr, "case %s\n", c.name.c_str());
      results.push_back(run_case(s, c, ms));
    }
  }

  // Distance versus faces: our levels of detail, the Slicer chain decimated to
  // the same counts, CGAL matched to them, flying edges as one point.
  std::vector<Sweep> sweeps;
  const std::vector<std::string> sweep_ids =
      s.quick ? std::vector<std::string>{"sphere-clean"} : std::vector<std::string>{"cube-clean", "branching-clean", "tooth-pulp"};
  const std::vector<double> lods = s.quick ? std::vector<double>{20.0, 5.0} : std::vector<double>{40.0, 20.0, 10.0, 5.0, 2.5};
  for (const CaseResult& cr : results) {
    const Case& c = *cr.c;
    if (std::find(sweep_ids.begin(), sweep_ids.end(), c.id) == sweep_ids.end()) continue;
    std::fprintf(stderr, "sweep %s\n", c.name.c_str());
    const gdm::Volume volume = to_volume(c.image);
    const Truth truth = make_truth(c);
    Sweep sw;
    sw.case_name = c.name;
    Series ours = named("our GDM, lod_face_area " + fmt("%g", lods.front()) + " to " + fmt("%g", lods.back()));
    Series slicer = named("Slicer chain at our counts"), cgal = named("CGAL Mesh_3 at our counts"), fe = named("flying edges");
    double d = 0.0;
    for (double lod : lods) {
      try {
        PeerResult g = run_gdm(c, volume, ms.front(), threads, lod);
        const std::size_t n = g.surface.faces.size();
        ours.x.push_back(n);
        ours.y.push_back(error_stats(sample_points(g.surface), truth.distance, c.voxel_size()).mean);
        PeerResult sl = run_slicer_chain(c.image, c.threshold, n);
        slicer.x.push_back(sl.surface.faces.size());
        slicer.y.push_back(error_stats(sample_points(sl.surface), truth.distance, c.voxel_size()).mean);
        PeerResult cg = run_cgal_matched(c, n, d);
        cgal.x.push_back(cg.surface.faces.size());
        cgal.y.push_back(error_stats(sample_points(cg.surface), truth.distance, c.voxel_size()).mean);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "  sweep lod %g failed: %s\n", lod, e.what());
      }
    }
    if (const Row* r = find_row(cr, "fe")) {
      fe.x.push_back(r->faces);
      fe.y.push_back(r->error.mean);
      fe.points_only = true;
    }
    sw.series = {ours, slicer, cgal, fe};
    sweeps.push_back(std::move(sw));
  }

  // ---- pictures and plots
  std::vector<std::pair<std::string, std::string>> pictures;  // file, caption
  for (const CaseResult& cr : results) {
    const Case& c = *cr.c;
    const bool side_by_side = c.id == "tooth-pulp" || c.id == "cube-clean" || c.id == "bottle-d8" ||
                              c.id == "topo-double-torus" ||
                              c.id == "channels-2-3-4" || (s.quick && c.id == "sphere-clean");
    if (side_by_side) {
      std::vector<Panel> panels;
      int frame = 0;
      for (const Row& r : cr.rows)
        if (r.ran) {
          if (r.method_id == "fe") frame = static_cast<int>(panels.size());
          panels.push_back({r.short_label + ": " + std::to_string(r.faces) + " faces", &r.surface, false});
        }
      const std::string file = "surfaces-" + c.id + ".png";
      // Framed on flying edges' surface (the whole iso-surface), the same camera for every panel.
      render_panels((fs::path(s.out) / file).string(), panels, 360, frame);
      pictures.emplace_back(file, "Every method's surface, " + c.name + " (same camera)");
    }
    const bool generations = c.id == "tooth-pulp" || c.id == "cube-clean" || c.id == "branching-clean" ||
                             (s.quick && c.id == "sphere-clean");
    if (generations)
      if (const Row* r = find_row(cr, "gdm")) {
        const std::string file = "generations-" + c.id + ".png";
        render_panels((fs::path(s.out) / file).string(), {{"our GDM, " + c.name + ", by vertex generation", &r->surface, true}}, 560);
        pictures.emplace_back(file, "Our model of " + c.name +
                                        " coloured by vertex generation (blue: early, red: late), as the paper's Fig. 11");
      }
  }
  std::vector<std::pair<std::string, std::string>> plots;
  for (std::size_t i = 0; i < sweeps.size(); ++i) {
    const std::string file = "distance-vs-faces-" + std::to_string(i + 1) + ".png";
    line_plot((fs::path(s.out) / file).string(), "Mean distance vs faces: " + sweeps[i].case_name, "faces",
              "mean distance to the truth (voxels)", sweeps[i].series, true, true);
    plots.emplace_back(file, "Mean distance to the true surface against face count, " + sweeps[i].case_name);
  }
  for (const std::string group : {"scaling: volume size", "scaling: surface area"}) {
    std::vector<Series> series;
    for (const Method& m : ms) {
      if (m.without_gap || m.openings_only || m.topology_only) continue;  // not run on these cases
      Series se = named(m.short_label);
      for (const CaseResult& cr : results) {
        if (cr.c->group != group) continue;
        if (const Row* r = find_row(cr, m.id)) {
          const bool volume_axis = group == std::string("scaling: volume size");
          se.x.push_back(volume_axis ? static_cast<double>(cr.c->image.values.size())
                                     : static_cast<double>(find_row(cr, "fe") ? find_row(cr, "fe")->faces : r->faces));
          se.y.push_back(r->median_s);
        }
      }
      series.push_back(se);
    }
    if (series.empty() || series.front().x.empty()) continue;
    const bool volume_axis = group == std::string("scaling: volume size");
    const std::string file = volume_axis ? "time-vs-volume.png" : "time-vs-area.png";
    line_plot((fs::path(s.out) / file).string(), volume_axis ? "Wall time vs volume size (sphere of radius 20)" : "Wall time vs surface size (160^3 volume)",
              volume_axis ? "voxels" : "surface size: flying-edges faces", "median wall time (s)", series, true, true);
    plots.emplace_back(file, volume_axis ? "Time against volume size, one fixed sphere of radius 20 voxels"
                                         : "Time against surface size (spheres of radius 10 to 70 in 160^3; x = faces of flying edges, a measure of area)");
  }

  // ---- CSV of every row
  {
    const fs::path csv = fs::path(s.out) / "results.csv";
    std::ofstream o(csv.string() + ".tmp");
    o << "group,case,method,faces,median_s,runs,mean_vox,p95_vox,max_vox,coverage_vox,closed,two_manifold,self_intersections,"
         "components,genus,note,missed_share,leak_share,leak_max_vox,gap_mm,truth,genus_per_component,contact_regions,"
         "contacts_across_object,contact_area_mm2\n";
    for (const CaseResult& cr : results)
      for (const Row& r : cr.rows)
        o << '"' << cr.c->group << "\",\"" << cr.c->name << "\"," << r.method_id << ',' << r.faces << ',' << r.median_s << ','
          << r.runs << ',' << r.error.mean << ',' << r.error.p95 << ',' << r.error.max << ',' << r.coverage << ','
          << r.checks.closed << ',' << r.checks.two_manifold << ',' << r.checks.self_intersections << ','
          << r.checks.components << ',' << r.checks.genus << ",\"" << (r.ran ? r.note : r.skip_reason) << "\","
          << r.missed << ',' << r.leak_share << ',' << r.leak_max << ','
          << (r.method_id.rfind("gdm", 0) == 0 && r.method_id != "gdm-nogap" ? cr.c->gap : 0.0) << ',' << r.truth
          << ",\"" << (cr.c->group == "topology" && r.ran ? genera(r) : std::string()) << "\"," << r.contact_regions << ','
          << r.contacts_across_object << ',' << r.contact_area << "\n";
    o.close();
    fs::rename(csv.string() + ".tmp", csv);
  }

  // ---- the report
  const double total = std::chrono::duration<double>(Clock::now() - study_start).count();
  const fs::path md = fs::path(s.out) / "README.md";
  std::ofstream o(md.string() + ".tmp");
  const std::time_t now = std::time(nullptr);
  char date[64];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  o << "# gdm against its peers: side-by-side benchmark study\n\n";
  o << "Generated by `scripts/benchmark-study.sh`" << (s.quick ? " (**--quick** configuration)" : "")
    << " on " << date << "; nothing in this file is typed by hand.\n\n";
  o << "| | |\n|---|---|\n";
  o << "| commit | `" << s.commit << "` |\n";
  o << "| CPU | " << machine_cpu() << " |\n";
  o << "| cores (nproc) | " << std::thread::hardware_concurrency() << " |\n";
  o << "| threads | " << threads << " for our GDM (`DeformOptions::threads`), VTK (SMP backend " << vtk_smp_backend()
    << ") and ITK (global default); CGAL Mesh_3 sequential |\n";
  o << "| timed runs | median of " << (s.quick ? 1 : s.runs) << " runs per method and case; fewer where " << s.runs
    << " runs would exceed " << fmt("%g", s.method_budget) << " s (the runs column says how many) |\n";
  o << "| study wall time | " << fmt("%.0f", total) << " s |\n\n";
  o << "Distances are in voxels (the smallest spacing): **mean / p95 / max** from the model's vertices and face centroids to "
       "the true surface (the exact analytic surface for phantoms; for scans the iso-surface of the volume upsampled 2x, "
       "trilinear); **truth→model max** is the largest distance from the true surface (sampled) to the model, "
       "which shows parts a method missed. Times are wall-clock of the method alone (input already in memory, "
       "output in the method's own mesh type), peers' conversions excluded. Validity checks use gdm's `mesh_checks` "
       "on a `gdm::Mesh` when the output is a consistently oriented 2-manifold, otherwise the same checks on the triangle "
       "soup with gdm's exact predicate. **Self-intersecting pairs** follow gdm's definition "
       "(`triangles_intersect_improperly`): a zero-area triangle counts against every face it touches, so marching-cubes "
       "outputs with degenerate triangles (the iso-surface through grid points) show such pairs without any crossing.\n\n";

  // Summary ratios.
  o << "## Headline ratios\n\n";
  struct Acc { double log_sum = 0; int n = 0; int faster = 0; };
  std::map<std::string, Acc> time_acc;
  for (const CaseResult& cr : results) {
    const Row* g = find_row(cr, "gdm");
    if (!g) continue;
    for (const Row& r : cr.rows) {
      if (!r.ran || r.method_id == "gdm" || r.method_id == "gdm-nogap" || r.method_id == "gdm-seed80" || r.method_id.rfind("gdm-exact", 0) == 0 || r.median_s <= 0 ||
          g->median_s <= 0)
        continue;
      auto& a = time_acc[r.method_id];
      a.log_sum += std::log(g->median_s / r.median_s);
      ++a.n;
      if (g->median_s < r.median_s) ++a.faster;
    }
  }
  o << "Time ratio = our median time / the peer's (below 1: we are faster), geometric mean over the cases both ran:\n\n";
  o << "| peer | our time / peer's time | cases where we are faster |\n|---|---:|---:|\n";
  for (const Method& m : ms) {
    if (m.id == "gdm" || !time_acc.count(m.id)) continue;
    const Acc& a = time_acc[m.id];
    o << "| " << m.label << " | " << fmt("%.2f", std::exp(a.log_sum / a.n)) << " | " << a.faster << " of " << a.n << " |\n";
  }
  o << "\nPer case: time ratio (ours / peer), and faces: ours / flying edges' when our mean error is equal or lower; "
       "against the Slicer chain and CGAL (matched to our face count) the ratio of mean errors (ours / theirs).\n\n";
  o << "| case | t/FE | t/Slicer | t/ITK MC | t/ITK simplex | t/CGAL | faces ours/FE at ≤ error | error ours/Slicer | error ours/CGAL |\n";
  o << "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  std::vector<std::string> losses;
  for (const CaseResult& cr : results) {
    const Row* g = find_row(cr, "gdm");
    if (!g) {
      losses.push_back(cr.c->name + ": our GDM did not run (" +
                       (cr.rows.empty() ? std::string("?") : cr.rows.front().skip_reason) + ")");
      continue;
    }
    o << "| " << cr.c->name;
    for (const char* id : {"fe", "slicer", "itk-mc", "itk-simplex", "cgal"}) {
      const Row* r = find_row(cr, id);
      o << " | " << (r && r->median_s > 0 ? fmt("%.2f", g->median_s / r->median_s) : std::string("–"));
    }
    const Row* fe = find_row(cr, "fe");
    if (fe && fe->faces > 0)
      o << " | " << (g->error.mean <= fe->error.mean ? fmt("%.3f", double(g->faces) / fe->faces)
                                                      : "error higher (" + fmt("%.3f", g->error.mean) + " vs " + fmt("%.3f", fe->error.mean) + ")");
    else
      o << " | –";
    for (const char* id : {"slicer", "cgal"}) {
      const Row* r = find_row(cr, id);
      o << " | " << (r && r->error.mean > 0 ? fmt("%.2f", g->error.mean / r->error.mean) : std::string("–"));
    }
    o << " |\n";
    // Where we lose.
    for (const Row& r : cr.rows) {
      if (!r.ran || r.method_id == "gdm") continue;
      if ((r.method_id == "slicer" || r.method_id == "cgal" || r.method_id == "itk-simplex") && r.faces <= g->faces * 1.15 &&
          r.error.mean < g->error.mean)
        losses.push_back(cr.c->name + ": " + r.label + " is closer to the truth with " + std::to_string(r.faces) +
                         " faces (mean " + fmt("%.3f", r.error.mean) + " vs our " + fmt("%.3f", g->error.mean) + " with " +
                         std::to_string(g->faces) + ")");
    }
    if (!g->checks.closed || !g->checks.two_manifold || g->checks.self_intersections > 0)
      losses.push_back(cr.c->name + ": our model is not a valid closed surface");
    if (!std::isnan(g->leak_share) && g->leak_share > 0.01)
      losses.push_back(cr.c->name + ": our model leaks (" + fmt("%.1f", 100.0 * g->leak_share) +
                       "% of it more than a voxel outside the object, up to " + fmt("%.1f", g->leak_max) + " voxels)");
    if (!std::isnan(g->coverage) && g->coverage > 2.0) {
      std::string line = cr.c->name + ": our model misses part of the object (truth→model max " + fmt("%.1f", g->coverage) + " voxels";
      if (!std::isnan(g->coverage_outside_filled)) {
        line += "; on the seed's object " + fmt("%.1f", g->coverage_outside_filled);
        if (g->filled_regions > 0)
          line += " away from the " + std::to_string(g->filled_regions) +
                  (g->filled_regions == 1 ? " cavity, pocket or handle" : " cavities, pockets and handles") +
                  " it fills by design and reports";
      }
      losses.push_back(line + ")");
    }
    if (fe && g->error.mean > fe->error.mean)
      losses.push_back(cr.c->name + ": our mean error " + fmt("%.3f", g->error.mean) + " is above flying edges' " +
                       fmt("%.3f", fe->error.mean));
  }
  o << "\n## Where we lose\n\n";
  // Speed: one line per peer that is faster somewhere.
  for (const Method& m : ms) {
    if (m.id == "gdm" || !time_acc.count(m.id)) continue;
    const Acc& a = time_acc[m.id];
    if (a.faster == a.n) continue;
    double worst = 0.0;
    std::string worst_case;
    for (const CaseResult& cr : results) {
      const Row* g = find_row(cr, "gdm");
      const Row* r = find_row(cr, m.id);
      if (g && r && r->median_s > 0 && g->median_s / r->median_s > worst) {
        worst = g->median_s / r->median_s;
        worst_case = cr.c->name;
      }
    }
    o << "- Speed: " << m.label << " is faster than us in " << (a.n - a.faster) << " of " << a.n
      << " cases (at worst " << fmt("%.0f", worst) << "x, " << worst_case << ").\n";
  }
  if (losses.empty()) o << "- Nowhere else in this run.\n";
  for (const std::string& l : losses) o << "- " << l << "\n";

  write_leak_section(o, results);
  write_topology_section(o, results);

  std::string group;
  for (const CaseResult& cr : results) {
    if (cr.c->group != group) {
      group = cr.c->group;
      o << "\n## Cases: " << group << "\n";
    }
    write_table(o, cr);
  }
  if (!skipped.empty()) {
    o << "\n### Skipped cases\n\n";
    for (const std::string& k : skipped) o << "- " << k << "\n";
  }
  o << "\n## Plots\n\n";
  for (const auto& [file, caption] : plots) o << "![" << caption << "](" << file << ")\n\n*" << caption << "*\n\n";
  o << "\n## Pictures\n\n";
  for (const auto& [file, caption] : pictures) o << "![" << caption << "](" << file << ")\n\n*" << caption << "*\n\n";
  o << "\n## Methods\n\n";
  o << "- **our GDM**: `gdm::deform` with the default `DeformOptions` (the paper's Table 2), threshold and polarity of the case; "
       "grown from an icosahedron of radius 3 mm at the seed, or shrunk from a geodesic sphere (level 3) scaled to the "
       "ellipsoid inscribed in the volume. The level-of-detail sweep varies `lod_face_area`. Where a case has openings the "
       "model must not pass (the hole-in-the-wall phantoms, the opened bottles), our GDM rows run with the case's gap size "
       "`DeformOptions::gap` (the opening's width plus two voxels) and one more row runs without it (G = 0) with "
       "`stop_at_border` on, as the command line does: the run ends when the leaking model reaches the volume's "
       "border; on the "
       "openings-and-channels cases one more row starts from the command line's default seed, a geodesic sphere of "
       "80 faces (level 1) of the same radius, instead of the 20-face icosahedron. On the topology cases our GDM runs "
       "with the default `topology = solid` and once more with `topology = exact` (seeds of radius 1.2 mm in the "
       "hollow sphere's shell, 1.5 mm in the tori's tubes, 3 mm in the tooth's dentin); the error-driven "
       "level-of-detail row is not run there.\n";
  o << "- **VTK flying edges**: `vtkFlyingEdges3D` at the threshold.\n";
  o << "- **Slicer chain**: flying edges, `vtkWindowedSincPolyDataFilter` (20 iterations, pass band 0.01, as Slicer's "
       "smoothing factor 0.5), `vtkQuadricDecimation` to our face count.\n";
  o << "- **ITK BinaryMask3DMeshSource**: marching cubes on the thresholded mask.\n";
  o << "- **ITK simplex mesh**: `DeformableSimplexMesh3DBalloonForceFilter` from a `RegularSphereMeshSource` at the "
       "seed (radius 3 mm, or the inscribed ellipsoid deflating with a negative balloon force), resolution chosen so "
       "its face count is the nearest 8·4^r to ours; external force: the gradient of the Gaussian gradient magnitude "
       "(sigma 1 voxel) scaled to [0, 1]; alpha 0.2, beta 0.5, gamma 0.05, |kappa| 0.05, rigidity 1; iterations 4x the "
       "largest dimension (200 to 800), resolution at most 5 (8192 faces). The filter works in index units: it runs on the index grid and its points are "
       "mapped back. Its time includes the edge map.\n";
  o << "- **CGAL Mesh_3**: `Labeled_mesh_domain_3::create_gray_image_mesh_domain`, initialised with "
       "`initialize_triangulation_from_gray_image`, criteria facet_angle 25, facet_distance searched (untimed) so the "
       "face count is within 15% of ours, no cell criteria (only the surface is refined), no perturbation or "
       "exudation; the complex's boundary facets.\n";
  o.close();
  fs::rename(md.string() + ".tmp", md);
  std::fprintf(stderr, "study finished in %.0f s; report %s\n", total, md.c_str());
  return 0;
}

}  // namespace study

int main(int argc, char** argv) {
  study::Settings s;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "gdm_benchmark_study: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    try {
      if (a == "--out") s.out = value();
      else if (a == "--quick") s.quick = true;
      else if (a == "--runs") s.runs = std::stoi(value());
      else if (a == "--threads") s.threads = std::stoi(value());
      else if (a == "--data") s.data = value();
      else if (a == "--commit") s.commit = value();
      else if (a == "--budget") s.method_budget = std::stod(value());
      else if (a == "--only") s.only.push_back(value());
      else if (a == "--dump") s.dump = true;
      else if (a == "--noise-sigma") {
        s.noise.sigma = std::stod(value());
        if (!(s.noise.sigma >= 0.0)) throw std::invalid_argument("sigma");
      }
      else if (a == "--noise-seed") s.noise.seed = static_cast<unsigned>(std::stoul(value()));
      else if (a == "--faces-sweep") s.faces_sweep = true;
      else if (a == "--sweep-cgal") s.sweep_cgal = true;
      else if (a == "--sweep-scans") s.sweep_scans = true;
      else if (a == "--sweep-exact") s.sweep_exact = true;
      else if (a == "--sweep-cut") s.sweep_cut = true;
      else if (a == "--sweep-voxel-seed") s.sweep_voxel_seed = true;
      else if (a == "--budgets") {
        std::stringstream list(value());
        for (std::string item; std::getline(list, item, ',');) s.budgets.push_back(std::stod(item));
      }
      else if (a == "--fractions") {
        s.fractions.clear();
        std::stringstream list(value());
        for (std::string item; std::getline(list, item, ',');) s.fractions.push_back(std::stod(item));
      }
      else {
        std::fprintf(stderr, "gdm_benchmark_study: unknown argument '%s'\nusage: gdm_benchmark_study --out DIR [--quick] "
                             "[--runs N] [--threads N] [--data DIR] [--commit TEXT] [--budget SECONDS] [--only CASE-ID-PART]... [--dump] [--noise-sigma S] [--noise-seed N] [--faces-sweep [--fractions F,F,...|--budgets N,N,...] [--sweep-cgal] [--sweep-scans] [--sweep-exact] [--sweep-cut] [--sweep-voxel-seed]]\n", a.c_str());
        return 2;
      }
    } catch (const std::exception&) {
      std::fprintf(stderr, "gdm_benchmark_study: bad value for %s\n", a.c_str());
      return 2;
    }
  }
  if (s.faces_sweep) return study::faces_sweep(s);
  if (s.out.empty()) {
    std::fprintf(stderr, "gdm_benchmark_study: --out DIR is required\n");
    return 2;
  }
  if (s.runs < 1) {
    std::fprintf(stderr, "gdm_benchmark_study: --runs must be at least 1\n");
    return 2;
  }
  try {
    return study::run(s);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gdm_benchmark_study: %s\n", e.what());
    return 1;
  }
}
