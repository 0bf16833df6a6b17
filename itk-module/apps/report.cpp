#include "report.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "gdm/mesh_checks.h"
#include "json_writer.h"

namespace gdm_cli {
namespace {

std::string fixed(double x, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, x);
  return buffer;
}

std::string vec(const std::array<double, 3>& v, int digits) {
  return "(" + fixed(v[0], digits) + ", " + fixed(v[1], digits) + ", " + fixed(v[2], digits) + ")";
}

}  // namespace

const char* const kVoxelSeedHint =
    "hint: --voxel-seed starts the model from the object's voxels, so no fronts meet and no seam is left where the "
    "object has no handle (it takes longer: the voxels are taken one by one and reduced)";

bool seams_worth_a_voxel_seed(const RunRecord& r) {
  return r.voxel_seed_possible && !r.model.voxel_seed && gdm::seams_worth_a_voxel_seed(r.contacts, r.mesh.area);
}

void record_extent(const gdm::Mesh& mesh, RunRecord& record) {
  bool first = true;
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    for (int d = 0; d < 3; ++d) {
      record.low[d] = first ? p[d] : std::min(record.low[d], p[d]);
      record.high[d] = first ? p[d] : std::max(record.high[d], p[d]);
    }
    first = false;
  }
  const auto generation = gdm::find_generation_property(mesh);
  if (generation.is_valid())
    for (auto v : mesh.vertices()) record.max_generation = std::max(record.max_generation, mesh.property(generation, v));
}

std::string input_text(const InputInfo& in) {
  std::ostringstream s;
  s << "input: " << in.path << " (" << in.format;
  if (!in.series_uid.empty()) s << ", series " << in.series_uid << ", " << in.files << " slices";
  s << ", " << in.pixel_type << ")\n"
    << "  dimensions " << in.size[0] << " x " << in.size[1] << " x " << in.size[2] << " voxels, spacing "
    << fixed(in.spacing[0], 4) << " x " << fixed(in.spacing[1], 4) << " x " << fixed(in.spacing[2], 4) << " mm\n"
    << "  origin " << vec(in.origin, 3) << " mm, value range [" << in.minimum << ", " << in.maximum << "]\n";
  return s.str();
}

std::string summary_text(const RunRecord& r) {
  const gdm::MeshReport& m = r.mesh;
  std::ostringstream s;
  s << "model: " << m.vertices << " vertices, " << m.faces << " faces, " << r.model.cycles << " cycles ("
    << gdm::to_string(r.model.reason) << "), " << r.model.global_refinements << " global refinement(s)";
  if (r.model.coarse_levels > 0)
    s << "; grown first at " << r.model.coarse_levels << " coarser level(s), " << r.model.coarse_cycles << " of the cycles";
  s << "\n";
  if (r.model.voxel_seed) s << "  " << gdm::voxel_seed_summary(r.model) << "\n";
  // The final stages, when they did anything.
  std::string finish;
  const auto part = [&](std::size_t n, const char* what) {
    if (n > 0) finish += (finish.empty() ? "" : ", ") + std::to_string(n) + " " + what;
  };
  part(r.model.fit_moves, "fit moves");
  part(r.model.sharp_corners, "vertices onto corners");
  part(r.model.sharp_edge_moves, "vertices onto sharp edges");
  part(r.model.sharp_edge_splits, "edges split on sharp edges");
  part(r.model.lod_splits, "lod splits");
  part(r.model.lod_collapses, "lod collapses");
  part(r.model.pleat_vertices, "pleat collapses and smoothed vertices (shrinking)");
  part(r.model.quality_flips, "quality flips");
  part(r.model.quality_splits, "quality splits");
  part(r.model.quality_collapses, "quality collapses");
  part(r.model.quality_spikes, "of them spikes removed");
  part(r.model.quality_unfolds, "of them folded edges");
  part(r.model.quality_moves, "quality moves");
  part(r.model.float_refused, "vertices not float-exact");
  if (!finish.empty()) s << "  after convergence: " << finish << "\n";
  if (r.model.face_budget > 0) s << "  " << gdm::budget_summary(r.model) << "\n";
  if (r.model.gap_closed_voxels > 0) s << "  " << gdm::gap_summary(r.model) << "\n";
  if (r.model.cavities > 0) s << "  " << gdm::cavity_summary(r.model) << "\n";
  if (r.model.handles > 0) s << "  " << gdm::handle_summary(r.model) << "\n";
  if (r.model.topology == gdm::Topology::exact) s << "  " << gdm::topology_summary(r.model) << "\n";
  for (const std::string& line : gdm::describe_contacts(r.contacts, 5, m.area)) s << "  " << line << "\n";
  if (seams_worth_a_voxel_seed(r)) s << "  " << kVoxelSeedHint << "\n";
  s << "  closed " << (m.closed ? "yes" : "NO") << ", manifold " << (m.two_manifold ? "yes" : "NO") << ", genus "
    << m.genus << ", components " << m.components << ", self-intersections " << m.self_intersections << "\n"
    << "  smallest angle " << fixed(m.min_angle_deg, 2) << " deg";
  if (r.model.faces_below_min_angle > 0)
    s << " (" << r.model.faces_below_min_angle << " faces left below --min-angle)";
  s << "; sharpest fold " << fixed(m.max_fold_deg, 1) << " deg";
  if (m.folds > 0) s << " (" << m.folds << " edges folded beyond " << fixed(gdm::kFoldDegrees, 0) << " deg)";
  s << "\n"
    << "  volume " << fixed(m.volume, 1) << " mm^3 = " << fixed(m.volume / 1000.0, 3) << " ml, area "
    << fixed(m.area, 1) << " mm^2\n"
    << "  extent " << vec(r.low, 2) << " to " << vec(r.high, 2) << " mm\n"
    << "  time " << fixed(r.model_seconds, 2) << " s model, " << fixed(r.total_seconds, 2) << " s total; peak memory "
    << fixed(r.peak_memory_mb, 0) << " MB\n";
  const gdm::StageSeconds& t = r.model.seconds;
  s << "  stages: ";
  if (r.model.voxel_seed) s << "voxel seed " << fixed(t.voxel_seed, 2) << " s, ";
  s << "growth " << fixed(t.growth, 2) << " s, global refinement " << fixed(t.refinement, 2)
    << " s, refined stages " << fixed(t.refined_stages, 2) << " s, fit " << fixed(t.fit, 2) << " s, error lod "
    << fixed(t.error_lod, 2) << " s, triangle quality " << fixed(t.quality, 2) << " s, float snap "
    << fixed(t.float_snap, 2) << " s, cavity fill " << fixed(t.cavity_fill, 2) << " s, gap gate "
    << fixed(t.gap_gate, 2) << " s, topology " << fixed(t.topology, 2) << " s, checks " << fixed(r.check_seconds, 2)
    << " s\n";
  if (!r.output.empty()) s << "wrote " << r.output << "\n";
  return s.str();
}

namespace {

// Where the model's time went (gdm::StageSeconds, and the checks), wall seconds.
std::string stage_seconds_json(const RunRecord& r) {
  const gdm::StageSeconds& t = r.model.seconds;
  JsonObject o;
  o.add("voxel_seed", json_number(t.voxel_seed))
      .add("gap_gate", json_number(t.gap_gate))
      .add("cavity_fill", json_number(t.cavity_fill))
      .add("growth", json_number(t.growth))
      .add("global_refinement", json_number(t.refinement))
      .add("refined_stages", json_number(t.refined_stages))
      .add("fit", json_number(t.fit))
      .add("error_lod", json_number(t.error_lod))
      .add("triangle_quality", json_number(t.quality))
      .add("float_snap", json_number(t.float_snap))
      .add("topology", json_number(t.topology))
      .add("checks", json_number(r.check_seconds));
  return o.str();
}

// What the cavity fill filled (gdm/cavities.h), largest first: each
// cavity, pocket behind narrow openings and handle cap, with where it is.
std::string filled_regions_json(const gdm::DeformResult& d) {
  const auto point = [](const gdm::Vec3& p) { return json_array(std::array<double, 3>{p.x(), p.y(), p.z()}); };
  std::string list = "[";
  for (std::size_t i = 0; i < d.filled_regions.size(); ++i) {
    const gdm::Cavity& c = d.filled_regions[i];
    JsonObject region;
    region.add("kind", json_string(gdm::to_string(c.kind)))
        .add("voxels", json_number(c.voxels))
        .add("centre_mm", point(c.centre));
    if (c.kind == gdm::CavityKind::narrow_openings)
      region.add("openings", json_number(c.openings)).add("largest_opening_mm", point(c.opening_centre));
    if (c.kind == gdm::CavityKind::handle) region.add("hole_width_mm", json_number(c.width));
    if (c.kind == gdm::CavityKind::cut) region.add("body_width_mm", json_number(c.width));
    list += (i ? ", " : "") + region.str(0);
  }
  return list + "]";
}

}  // namespace

std::string report_json(const RunRecord& r, const Options& options) {
  JsonObject input;
  input.add("path", json_string(r.input.path))
      .add("format", json_string(r.input.format))
      .add("series_uid", r.input.series_uid.empty() ? "null" : json_string(r.input.series_uid))
      .add("files", json_number(r.input.files))
      .add("pixel_type", json_string(r.input.pixel_type))
      .add("size", "[" + std::to_string(r.input.size[0]) + ", " + std::to_string(r.input.size[1]) + ", " +
                       std::to_string(r.input.size[2]) + "]")
      .add("spacing_mm", json_array(r.input.spacing))
      .add("origin_mm", json_array(r.input.origin))
      .add("direction", json_array(r.input.direction))
      .add("value_min", json_number(r.input.minimum))
      .add("value_max", json_number(r.input.maximum));

  JsonObject threshold;
  threshold.add("value", json_number(r.threshold)).add("source", json_string(r.threshold_source));

  JsonObject seed;
  seed.add("source", json_string(r.seed_source))
      .add("center_mm", json_array(r.seed_center))
      .add("radius_mm", json_number(r.seed_radius));
  if (r.seed_source == "auto") {
    seed.add("depth_mm", json_number(r.seed_depth))
        .add("region_voxels", json_number(r.seed_region_voxels))
        .add("regions", json_number(r.seed_regions));
  }
  seed.add("cut_by_scan", json_bool(r.cut_by_scan))
      .add("border_fraction", json_number(r.border_fraction))
      .add("border_sides", json_string(r.border_sides));

  JsonObject model;
  model.add("stop_reason", r.model.cycles == 0 ? "null" : json_string(gdm::to_string(r.model.reason)))
      .add("cycles", json_number(r.model.cycles))
      .add("coarse_levels", json_number(r.model.coarse_levels))
      .add("coarse_cycles", json_number(r.model.coarse_cycles))
      .add("voxel_seed", json_bool(r.model.voxel_seed))
      .add("voxel_seed_voxels", json_number(r.model.voxel_seed_voxels))
      .add("voxel_seed_background_voxels", json_number(r.model.voxel_seed_background))
      .add("voxel_seed_left_out", json_number(r.model.voxel_seed_left_out))
      .add("voxel_seed_surface_faces", json_number(r.model.voxel_seed_surface_faces))
      .add("global_refinements", json_number(r.model.global_refinements))
      .add("rejected_moves", json_number(r.model.rejected_moves))
      .add("flips", json_number(r.model.flips))
      .add("border_vertices", json_number(r.model.border_vertices))
      .add("fit_moves", json_number(r.model.fit_moves))
      .add("sharp_corners", json_number(r.model.sharp_corners))
      .add("sharp_edge_moves", json_number(r.model.sharp_edge_moves))
      .add("sharp_edge_splits", json_number(r.model.sharp_edge_splits))
      .add("lod_splits", json_number(r.model.lod_splits))
      .add("lod_collapses", json_number(r.model.lod_collapses))
      .add("pleat_vertices", json_number(r.model.pleat_vertices))
      .add("quality_flips", json_number(r.model.quality_flips))
      .add("quality_splits", json_number(r.model.quality_splits))
      .add("quality_collapses", json_number(r.model.quality_collapses))
      .add("quality_moves", json_number(r.model.quality_moves))
      .add("quality_spikes", json_number(r.model.quality_spikes))
      .add("quality_unfolds", json_number(r.model.quality_unfolds))
      .add("faces_below_min_angle", json_number(r.model.faces_below_min_angle))
      .add("face_budget", json_number(r.model.face_budget))
      .add("budget_faces", json_number(r.model.faces))
      .add("budget_subdivisions", json_number(r.model.budget_subdivisions))
      .add("budget_collapses", json_number(r.model.budget_collapses))
      .add("budget_splits", json_number(r.model.budget_splits))
      .add("budget_relax_moves", json_number(r.model.budget_relax_moves))
      .add("float_refused", json_number(r.model.float_refused))
      .add("gap_closed_voxels", json_number(r.model.gap_closed_voxels))
      .add("gap_reachable_voxels", json_number(r.model.gap_reachable_voxels))
      .add("bridge_vertices", json_number(r.model.bridge_vertices))
      .add("channel_rounds", json_number(r.model.channel_rounds))
      .add("channel_faces", json_number(r.model.channel_faces))
      .add("cavities", json_number(r.model.cavities))
      .add("cavity_voxels", json_number(r.model.cavity_voxels))
      .add("cavity_volume_mm3", json_number(r.model.cavity_volume))
      .add("cavity_specks", json_number(r.model.cavity_specks))
      .add("cavities_behind_openings", json_number(r.model.cavities_behind_openings))
      .add("cavity_opening_mm", json_number(r.model.cavity_opening_width))
      .add("handles", json_number(r.model.handles))
      .add("handle_voxels", json_number(r.model.handle_voxels))
      .add("handle_repair", json_string(gdm::to_string(r.model.handle_repair)))
      .add("topology", json_string(gdm::to_string(r.model.topology)))
      .add("handles_opened", json_number(r.model.handles_opened))
      .add("cavity_components", json_number(r.model.cavity_components))
      .add("cavity_component_faces", json_number(r.model.cavity_component_faces))
      .add("cavities_not_modelled", json_number(r.model.cavities_not_modelled))
      .add("filled_regions", filled_regions_json(r.model))
      .add("seconds", json_number(r.model_seconds))
      .add("stage_seconds", stage_seconds_json(r));

  const gdm::MeshReport& m = r.mesh;
  JsonObject mesh;
  mesh.add("vertices", json_number(m.vertices))
      .add("faces", json_number(m.faces))
      .add("edges", json_number(m.edges))
      .add("closed", json_bool(m.closed))
      .add("manifold", json_bool(m.two_manifold))
      .add("euler_characteristic", json_number(m.euler))
      .add("genus", json_number(m.genus))
      .add("components", json_number(m.components))
      .add("euler_consistent", json_bool(m.euler_consistent))
      .add("self_intersections", json_number(m.self_intersections))
      .add("volume_mm3", json_number(m.volume))
      .add("volume_ml", json_number(m.volume / 1000.0))
      .add("area_mm2", json_number(m.area))
      .add("min_angle_deg", json_number(m.min_angle_deg))
      .add("max_fold_deg", json_number(m.max_fold_deg))
      .add("folds", json_number(m.folds))
      .add("bounds_min_mm", json_array(r.low))
      .add("bounds_max_mm", json_array(r.high))
      .add("max_generation", json_number(r.max_generation));

  // Where the model meets itself (gdm/self_contact.h), largest first.
  std::string regions = "[";
  for (std::size_t i = 0; i < r.contacts.regions.size(); ++i) {
    const gdm::ContactRegion& c = r.contacts.regions[i];
    JsonObject region;
    region.add("centre_mm", json_array(std::array<double, 3>{c.centre.x(), c.centre.y(), c.centre.z()}))
        .add("area_mm2", json_number(c.area))
        .add("faces", json_number(c.faces))
        .add("across", json_string(c.across_object ? "object" : "background"));
    regions += (i ? ", " : "") + region.str(0);
  }
  regions += "]";
  JsonObject contacts;
  contacts.add("regions", json_number(r.contacts.regions.size()))
      .add("faces", json_number(r.contacts.faces))
      .add("area_mm2", json_number(r.contacts.area))
      .add("seam_faces", json_number(r.contacts.seam_faces))
      .add("seam_area_mm2", json_number(r.contacts.seam_area))
      .add("seams_worth_a_voxel_seed", json_bool(seams_worth_a_voxel_seed(r)))
      .add("list", regions);

  JsonObject root;
  root.add("program", json_string("gdm"))
      .add("version", json_string(GDM_VERSION))
      .add("status", json_string(r.status))
      .add("exit_code", json_number(r.exit_code))
      .add("output", r.output.empty() ? "null" : json_string(r.output))
      .add("input", input.str())
      .add("threshold", threshold.str())
      .add("seed", seed.str())
      .add("model", model.str())
      .add("mesh", mesh.str())
      .add("contacts", contacts.str())
      .add("total_seconds", json_number(r.total_seconds))
      .add("peak_memory_mb", json_number(r.peak_memory_mb))
      .add("parameters", parameters_json(options, 2));
  return root.str() + "\n";
}

}  // namespace gdm_cli
