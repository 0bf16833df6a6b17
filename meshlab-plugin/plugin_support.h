// What the plugin's filters share besides the gdm core: progress and log
// plumbing towards MeshLab, and the deformation parameters every filter takes.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "gdm/deformer.h"
#include "gdm/mesh.h"

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

// A number with four significant digits, for the log lines.
std::string fmt(double v);

// Maps the deformation cycles of `stages` stages onto [from, to] percent.
gdm::DeformObserver observer_for(const Progress& progress, int from, int to, int stages, const char* text);

// Compacts a deformed model and logs the outcome of gdm::deform.
void finish_model(const gdm::DeformResult& r, gdm::Mesh& mesh, LogLines* log);

}  // namespace gdm_meshlab
