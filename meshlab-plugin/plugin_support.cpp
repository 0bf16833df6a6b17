#include "plugin_support.h"

#include <sstream>

#include "gdm/mesh_checks.h"
#include "gdm/text.h"

namespace gdm_meshlab {

std::string fmt(double v) { return gdm::format_number(v, 4); }

// The pipeline ends with the model on float-representable points
// (float_exact_output): MeshLab's float coordinates keep the no-intersection
// guarantee.
void log_result(const gdm::PipelineResult& r, bool voxel_seed_possible, LogLines* log) {
  const gdm::DeformResult& d = r.deform;
  if (d.float_refused > 0)
    log->push_back("warning: " + std::to_string(d.float_refused) +
                   " vertices could not be moved to float precision without a self-intersection");
  log->push_back("deformation " + gdm::to_string(d.reason) + " after " + std::to_string(d.cycles) + " cycles (" +
                 std::to_string(d.global_refinements) + " global refinements, " + std::to_string(d.rejected_moves) +
                 " moves vetoed by the self-intersection guard)");
  if (d.gap_closed_voxels > 0) log->push_back(gdm::gap_summary(d));
  if (d.face_budget > 0) log->push_back(gdm::budget_summary(d));
  if (d.voxel_seed) log->push_back(gdm::voxel_seed_summary(d));
  if (d.cavities > 0) log->push_back(gdm::cavity_summary(d));
  if (d.handles > 0) log->push_back(gdm::handle_summary(d));
  if (d.topology == gdm::Topology::exact) log->push_back(gdm::topology_summary(d));
  if (d.quality_flips + d.quality_splits + d.quality_collapses + d.quality_moves > 0)
    log->push_back("triangle quality: " + std::to_string(d.quality_flips) + " flips, " +
                   std::to_string(d.quality_splits) + " splits, " + std::to_string(d.quality_collapses) +
                   " collapses (" + std::to_string(d.quality_spikes) + " spikes removed, " +
                   std::to_string(d.quality_unfolds) + " folded edges), " +
                   std::to_string(d.quality_moves) + " moves; smallest angle " +
                   fmt(r.report.min_angle_deg) + " degrees");
  if (d.faces_below_min_angle > 0)
    log->push_back("warning: " + std::to_string(d.faces_below_min_angle) +
                   " faces keep an angle below min_angle (the guarantees came first)");
  if (d.reason == gdm::StopReason::max_cycles)
    log->push_back("warning: the model did not converge; raise max_cycles or check the threshold");
  if (r.failure.empty()) log->push_back("result: " + gdm::to_string(r.report));
  for (const std::string& line : gdm::describe_contacts(r.contacts, 5, r.report.area)) log->push_back("warning: " + line);
  if (voxel_seed_possible && !d.voxel_seed && gdm::seams_worth_a_voxel_seed(r.contacts, r.report.area))
    log->push_back("hint: \"Start from the object's voxels\" (voxel_seed) starts the model from the object's voxels, so "
                   "no fronts meet and no seam is left where the object has no handle (it takes longer)");
}

}  // namespace gdm_meshlab
