#include "plugin_support.h"

#include <algorithm>
#include <memory>
#include <sstream>

#include "gdm/mesh_checks.h"

namespace gdm_meshlab {

gdm::DeformOptions model_options(const ModelParams& m) {
  gdm::DeformOptions o;
  o.a0 = m.a0;
  o.a1 = m.a1;
  o.a2 = m.a2;
  o.lod_face_area = m.lod_face_area;
  o.global_refinements = m.global_refinements;
  o.max_cycles = m.max_cycles;
  return o;
}

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}

// Each stage (the first convergence and every global refinement) gets an
// equal share, filled asymptotically as its cycles go by.
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

// gdm::deform ends with the model on float-representable points
// (float_exact_output): MeshLab's float coordinates keep the no-intersection
// guarantee.
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

}  // namespace gdm_meshlab
