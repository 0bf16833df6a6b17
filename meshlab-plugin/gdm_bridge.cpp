#include "gdm_bridge.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "gdm/errors.h"
#include "gdm/float_snap.h"
#include "gdm/mesh_checks.h"
#include "gdm/seed.h"
#include "volume_io.h"

namespace gdm_meshlab {
namespace {

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}

// Maps the deformation cycles onto [from, to] percent: each stage (the first
// convergence and every global refinement) gets an equal share, filled
// asymptotically as its cycles go by.
gdm::DeformObserver observer_for(const Progress& progress, int from, int to, int stages, const char* text) {
  if (!progress) return {};
  auto stage_start = std::make_shared<std::pair<int, int>>(0, 0);  // stage, first cycle
  return [=](const gdm::CycleReport& r) {
    if (r.stage != stage_start->first) *stage_start = {r.stage, r.cycle};
    const double in_stage = r.cycle - stage_start->second;
    const double f = 1.0 - 1.0 / (1.0 + in_stage / 30.0);
    const double share = (std::min(r.stage, stages - 1) + f) / stages;
    return progress(from + static_cast<int>((to - from) * share), text);
  };
}

gdm::DeformOptions deform_options(double a0, double a1, double a2, double lod, int refinements, int max_cycles,
                                  bool subvoxel_fit, double lod_tolerance) {
  gdm::DeformOptions o;
  o.subvoxel_fit = subvoxel_fit;
  o.lod_tolerance = lod_tolerance;
  o.a0 = a0;
  o.a1 = a1;
  o.a2 = a2;
  o.lod_face_area = lod;
  o.global_refinements = refinements;
  o.max_cycles = max_cycles;
  return o;
}

// Compacts the model and logs the outcome. gdm::deform ends with the model on
// float-representable points (float_exact_output): MeshLab's float
// coordinates keep the no-intersection guarantee.
void finish_model(const gdm::DeformResult& r, gdm::Mesh& mesh, LogLines* log) {
  mesh.garbage_collection();
  if (r.float_refused > 0)
    log->push_back("warning: " + std::to_string(r.float_refused) +
                   " vertices could not be moved to float precision without a self-intersection");
  log->push_back("deformation " + gdm::to_string(r.reason) + " after " + std::to_string(r.cycles) + " cycles (" +
                 std::to_string(r.global_refinements) + " global refinements, " + std::to_string(r.rejected_moves) +
                 " moves vetoed by the self-intersection guard)");
  if (r.reason == gdm::StopReason::max_cycles || r.reason == gdm::StopReason::face_limit)
    log->push_back("warning: the model did not converge; raise the maximum number of cycles or check the threshold");
  if (r.border_vertices > 0)
    log->push_back("warning: " + std::to_string(r.border_vertices) +
                   " vertices reached the border of the volume: the object leaks (check threshold and polarity)");
  log->push_back("result: " + gdm::to_string(gdm::measure(mesh)));
}

struct LoadedVolume {
  gdm::Volume volume;
  double threshold;
};

LoadedVolume load(const VolumeParams& v, LogLines* log) {
  std::string description;
  gdm::Volume volume = read_volume(v.volume_file, &description);
  log->push_back(description);
  if (v.smoothing_sigma > 0.0) {
    volume = smooth_volume(volume, v.smoothing_sigma);
    log->push_back("smoothed with a Gaussian of sigma " + fmt(v.smoothing_sigma) + " mm");
  }
  double threshold = v.threshold;
  if (v.auto_threshold) {
    threshold = 0.5 * (volume.min_value() + volume.max_value());
    log->push_back("threshold (midpoint of the value range): " + fmt(threshold));
  }
  return {std::move(volume), threshold};
}

gdm::DeformOptions volume_options(const VolumeParams& v, double threshold) {
  gdm::DeformOptions o =
      deform_options(v.a0, v.a1, v.a2, v.lod_face_area, v.global_refinements, v.max_cycles, v.subvoxel_fit,
                     v.lod_tolerance);
  o.threshold = threshold;
  o.polarity = v.object_darker ? gdm::Polarity::object_darker : gdm::Polarity::object_brighter;
  o.mode = v.shrink ? gdm::Mode::shrink : gdm::Mode::grow;
  return o;
}

}  // namespace

gdm::Mesh to_gdm_seed(const CMeshO& m, LogLines* log) {
  gdm::Mesh mesh;
  std::vector<gdm::Mesh::VertexHandle> handle(m.vert.size());
  std::vector<std::array<gdm::Mesh::VertexHandle, 3>> faces;
  for (const CFaceO& f : m.face) {
    if (f.IsD()) continue;
    std::array<gdm::Mesh::VertexHandle, 3> tri;
    for (int i = 0; i < 3; ++i) {
      const std::size_t idx = vcg::tri::Index(m, f.cV(i));
      if (!handle[idx].is_valid()) {
        const auto& p = f.cV(i)->cP();
        handle[idx] = mesh.add_vertex(gdm::Mesh::Point(p[0], p[1], p[2]));
      }
      tri[i] = handle[idx];
    }
    faces.push_back(tri);
  }
  if (faces.empty()) throw gdm::InvalidSeed("the current layer has no faces: a closed triangle mesh is needed");
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const auto& t = faces[i];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      throw gdm::InvalidSeed("the current layer is not a 2-manifold: face " + std::to_string(i) +
                             " uses the same vertex twice (try Filters > Cleaning and Repairing)");
    if (!mesh.add_face(t[0], t[1], t[2]).is_valid())
      throw gdm::InvalidSeed("the current layer is not a 2-manifold: face " + std::to_string(i) +
                             " meets an edge already shared by two faces, or is oriented against its "
                             "neighbours (try Filters > Cleaning and Repairing)");
  }
  gdm::check_seed_mesh(mesh);  // closed, 2-manifold, finite
  if (gdm::enclosed_volume(mesh) < 0.0) {
    gdm::Mesh flipped;
    for (auto v : mesh.vertices()) flipped.add_vertex(mesh.point(v));
    for (const auto& t : faces) flipped.add_face(t[0], t[2], t[1]);
    mesh = std::move(flipped);
    if (log) log->push_back("the layer's faces pointed inwards; they were reversed");
  }
  return mesh;
}

void to_meshlab(const gdm::Mesh& mesh, CMeshO& out) {
  out.Clear();
  const auto generation = gdm::find_generation_property(mesh);
  std::vector<int> index(mesh.n_vertices(), -1);
  std::size_t nv = 0, nf = 0;
  for (auto v : mesh.vertices()) index[v.idx()] = static_cast<int>(nv++);
  for (auto f : mesh.faces()) { (void)f; ++nf; }
  auto vi = vcg::tri::Allocator<CMeshO>::AddVertices(out, nv);
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    CVertexO& cv = out.vert[index[v.idx()]];
    cv.P() = Point3m(static_cast<Scalarm>(p[0]), static_cast<Scalarm>(p[1]), static_cast<Scalarm>(p[2]));
    cv.Q() = generation.is_valid() ? static_cast<float>(mesh.property(generation, v)) : 0.0f;
  }
  (void)vi;
  auto fi = vcg::tri::Allocator<CMeshO>::AddFaces(out, nf);
  for (auto f : mesh.faces()) {
    int k = 0;
    for (auto v : mesh.fv_range(f)) fi->V(k++) = &out.vert[index[v.idx()]];
    ++fi;
  }
}

std::vector<Triangle> triangle_soup(const CMeshO& m) {
  std::vector<Triangle> soup;
  const auto point = [](const CVertexO* v) {
    return gdm::Vec3(v->cP()[0], v->cP()[1], v->cP()[2]);
  };
  for (const CFaceO& f : m.face)
    if (!f.IsD()) soup.push_back({point(f.cV(0)), point(f.cV(1)), point(f.cV(2))});
  if (soup.empty())
    for (const CVertexO& v : m.vert)
      if (!v.IsD()) soup.push_back({point(&v), point(&v), point(&v)});
  for (const auto& t : soup)
    for (const auto& p : t)
      if (!p.allFinite()) throw gdm::InvalidOption("the current layer has vertices with non-finite coordinates");
  return soup;
}

gdm::Mesh model_from_volume(const VolumeParams& v, const SeedParams& s, const Progress& progress, LogLines* log) {
  if (progress) progress(0, "Reading the volume");
  LoadedVolume lv = load(v, log);
  gdm::Vec3 centre = s.point;
  if (s.at_volume_centre) {
    gdm::Vec3 lo, hi;
    lv.volume.physical_bounds(lo, hi);
    centre = 0.5 * (lo + hi);
  }
  if (!(s.radius > 0.0)) throw gdm::InvalidSeed("the seed radius must be positive");
  log->push_back("seed: icosahedron of radius " + fmt(s.radius) + " mm at (" + fmt(centre.x()) + ", " +
                 fmt(centre.y()) + ", " + fmt(centre.z()) + ") mm");
  gdm::Mesh mesh = gdm::make_icosahedron(centre, s.radius);
  const gdm::DeformOptions o = volume_options(v, lv.threshold);
  const auto result =
      gdm::deform(mesh, lv.volume, o, observer_for(progress, 5, 99, v.global_refinements + 1, "Deforming the model"));
  if (result.reason == gdm::StopReason::cancelled) throw gdm::Error("cancelled");
  finish_model(result, mesh, log);
  return mesh;
}

gdm::Mesh deform_seed_in_volume(gdm::Mesh seed, const VolumeParams& v, const Progress& progress, LogLines* log) {
  if (progress) progress(0, "Reading the volume");
  LoadedVolume lv = load(v, log);
  const gdm::DeformOptions o = volume_options(v, lv.threshold);
  log->push_back(std::string("seed: the current layer, ") + std::to_string(seed.n_faces()) + " faces, " +
                 (v.shrink ? "shrinking onto" : "growing into") + " the object");
  const auto result =
      gdm::deform(seed, lv.volume, o, observer_for(progress, 5, 99, v.global_refinements + 1, "Deforming the seed"));
  if (result.reason == gdm::StopReason::cancelled) throw gdm::Error("cancelled");
  finish_model(result, seed, log);
  return seed;
}

gdm::Mesh shrink_wrap(const std::vector<Triangle>& input, const WrapParams& w, const Progress& progress,
                      LogLines* log) {
  if (!(w.cell_size > 0.0)) throw gdm::InvalidOption("the cell size must be positive");
  if (!(w.tolerance >= w.cell_size))
    throw gdm::InvalidOption("the tolerance (" + fmt(w.tolerance) + ") must be at least the cell size (" +
                             fmt(w.cell_size) + "): the grid cannot resolve a closer wrap");
  gdm::Vec3 lo = gdm::Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& t : input)
    for (const auto& p : t) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  if (input.empty()) throw gdm::InvalidOption("the current layer is empty: nothing to wrap");
  // The wrap settles where the distance to the input is a third of the
  // tolerance: in a concave crease of angle theta the offset surface's corner
  // lies offset / sin(theta / 2) from the crease, so creases down to about
  // 40 degrees stay within the tolerance.
  const double offset = w.tolerance / 3.0;
  const gdm::Vec3 centre = 0.5 * (lo + hi);
  const double radius = 0.5 * (hi - lo).norm() + offset + 2.0 * w.cell_size;
  WrapFieldOptions fo;
  fo.cell_size = w.cell_size;
  fo.offset = offset;
  // The grid holds the seed sphere with a cell to spare.
  const gdm::Vec3 sphere_lo = centre - gdm::Vec3::Constant(radius), sphere_hi = centre + gdm::Vec3::Constant(radius);
  fo.padding = w.cell_size;
  const gdm::Volume field = make_wrap_field(input, sphere_lo, sphere_hi, fo, [&](double f) {
    return !progress || progress(static_cast<int>(20 * f), "Distance field of the input");
  });
  if (field.voxel_count() == 0) throw gdm::Error("cancelled");
  log->push_back("distance field: " + std::to_string(field.dims()[0]) + " x " + std::to_string(field.dims()[1]) +
                 " x " + std::to_string(field.dims()[2]) + " cells of " + fmt(w.cell_size) + " mm; the wrap settles " +
                 fmt(offset) + " mm from the input");

  // A geodesic sphere whose faces are about the level of detail.
  const double sphere_area = 4.0 * M_PI * radius * radius;
  const double lod_mm2 = w.lod_face_area * w.cell_size * w.cell_size;
  int level = 0;
  while (level < 5 && sphere_area / (20.0 * std::pow(4.0, level)) > 4.0 * lod_mm2) ++level;
  gdm::Mesh mesh = gdm::make_geodesic_sphere(centre, radius, level);
  log->push_back("seed: geodesic sphere of radius " + fmt(radius) + " mm, " + std::to_string(mesh.n_faces()) +
                 " faces");

  gdm::DeformOptions o = deform_options(w.a0, w.a1, w.a2, w.lod_face_area, w.global_refinements, w.max_cycles,
                                        false, 0.0);
  o.mode = gdm::Mode::shrink;
  o.polarity = gdm::Polarity::object_darker;
  o.threshold = offset;
  // The fit and the error-driven level of detail do not check obstacles (off above).
  const gdm::Obstacle obstacle(input);
  o.obstacle = &obstacle;
  const auto result =
      gdm::deform(mesh, field, o, observer_for(progress, 20, 95, w.global_refinements + 1, "Shrinking the wrap"));
  if (result.reason == gdm::StopReason::cancelled) throw gdm::Error("cancelled");
  finish_model(result, mesh, log);

  if (progress) progress(96, "Measuring the wrap");
  const gdm::MeshReport report = gdm::measure(mesh);
  if (!report.closed || !report.two_manifold || report.genus != 0 || report.self_intersections != 0)
    throw gdm::Error("the wrap failed its checks (" + gdm::to_string(report) + ")");
  // The wrap is on float points: MeshLab's rounding changes nothing. Check it.
  {
    gdm::Mesh rounded = mesh;
    for (auto v : rounded.vertices())
      rounded.set_point(v, gdm::to_point(gdm::round_to_float(gdm::to_eigen(rounded.point(v)))));
    const std::size_t crossings = gdm::self_intersecting_pairs(rounded);
    if (crossings > 0)
      log->push_back("warning: " + std::to_string(crossings) +
                     " face pairs intersect once the coordinates are rounded to MeshLab's float precision");
  }
  // Largest distances both ways, exact.
  std::vector<Triangle> wrap_triangles;
  for (auto f : mesh.faces()) {
    Triangle t;
    int k = 0;
    for (auto v : mesh.fv_range(f)) t[k++] = gdm::to_eigen(mesh.point(v));
    wrap_triangles.push_back(t);
  }
  const gdm::TriangleLocator to_wrap(std::move(wrap_triangles));
  double input_to_wrap = 0.0;
  for (const auto& t : input)
    for (const auto& p : t) input_to_wrap = std::max(input_to_wrap, to_wrap.distance(p));
  const gdm::TriangleLocator to_input(input);
  double wrap_to_input = 0.0;
  for (auto v : mesh.vertices()) wrap_to_input = std::max(wrap_to_input, to_input.distance(gdm::to_eigen(mesh.point(v))));
  log->push_back("wrap: " + std::to_string(report.faces) + " faces, " + std::to_string(report.vertices) +
                 " vertices, volume " + fmt(report.volume) + " mm^3, genus " + std::to_string(report.genus) +
                 ", self-intersections " + std::to_string(report.self_intersections));
  log->push_back("largest distance of the input from the wrap: " + fmt(input_to_wrap) + " mm (tolerance " +
                 fmt(w.tolerance) + " mm); largest distance of the wrap from the input: " + fmt(wrap_to_input) + " mm");
  if (input_to_wrap > w.tolerance)
    log->push_back("warning: some input lies farther than the tolerance from the wrap (a concavity or hole "
                   "wider than the level of detail); lower the level of detail or a2");
  return mesh;
}

}  // namespace gdm_meshlab
