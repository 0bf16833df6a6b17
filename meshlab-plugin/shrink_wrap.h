// The shrink-wrap filter's work without MeshLab: a closed, genus-0,
// intersection-free wrap of a triangle soup (holes, several pieces, noise,
// point clouds), shrunk from a sphere onto the soup's distance field
// (shrink_wrap_field.h) by gdm::deform, the soup being an obstacle
// (gdm/obstacle.h). Used by the plugin (gdm_bridge.h) and by the test tool.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "gdm/deformer.h"
#include "gdm/mesh.h"
#include "shrink_wrap_field.h"

namespace gdm_meshlab {

// percent in [0, 100] and a short text; returns false to cancel.
using Progress = std::function<bool(int, const char*)>;
using LogLines = std::vector<std::string>;

// The deformation parameters every filter takes (Table 2 and section 6).
struct ModelParams {
  double a0 = 1.0, a1 = 1.0, a2 = 5.0;  // weights of eq. 1
  double lod_face_area = 10.0;          // voxel^2 (cell^2 for the wrap)
  int global_refinements = 1;
  int max_cycles = 2000;
};

// DeformOptions carrying m, the rest at their defaults.
gdm::DeformOptions model_options(const ModelParams& m);

struct WrapParams : ModelParams {
  double cell_size = 1.0;     // mm
  double tolerance = 2.0;     // mm: largest distance of the input from the wrap
  int coverage_rounds = 4;    // local refinement rounds while input lies beyond 90% of the tolerance; 0 = off
};

// A number with four significant digits, for the log lines.
std::string fmt(double v);

// Maps the deformation cycles of `stages` stages onto [from, to] percent.
gdm::DeformObserver observer_for(const Progress& progress, int from, int to, int stages, const char* text);

// Compacts a deformed model and logs the outcome of gdm::deform.
void finish_model(const gdm::DeformResult& r, gdm::Mesh& mesh, LogLines* log);

// Filter 3: a closed, genus-0, intersection-free wrap shrunk from a sphere
// around the triangles onto their distance field. The input is an obstacle:
// no face of the wrap ever touches it, so all of the input stays inside the
// wrap, however thin its parts. Where input still lies beyond 90% of the
// tolerance after the convergence, the wrap's faces near it are split and the
// wrap deformed again (at most w.coverage_rounds times).
gdm::Mesh shrink_wrap(const std::vector<Triangle>& input, const WrapParams& w, const Progress& progress,
                      LogLines* log);

}  // namespace gdm_meshlab
