// VTK peers (flying edges, the 3D Slicer chain), the ground-truth iso-surface
// of scans, and every picture and plot of the report (offscreen rendering; run
// under xvfb-run on a machine without a display).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "study_types.h"

namespace study {

// vtkFlyingEdges3D at the threshold (VTK's multithreaded marching cubes).
PeerResult run_flying_edges(const Image& image, double threshold);

// What 3D Slicer runs to make a model: flying edges, then
// vtkWindowedSincPolyDataFilter (20 iterations, pass band 10^(-4 * 0.5), as
// Slicer's default smoothing factor 0.5), then vtkQuadricDecimation down to
// `target_faces` (0: no decimation).
PeerResult run_slicer_chain(const Image& image, double threshold, std::size_t target_faces);

// The iso-surface of the image resampled `upsample` times finer (trilinear):
// the reference surface of scans.
Surface iso_surface(const Image& image, double level, int upsample);

// Number of threads VTK's SMP backend uses, and the backend's name.
void set_vtk_threads(int threads);
std::string vtk_smp_backend();

// Several surfaces side by side, each with a title, rendered offscreen to a PNG.
struct Panel {
  std::string title;
  const Surface* surface = nullptr;
  bool by_generation = false;  // colour by Surface::generation (Fig. 11)
};
// The camera frames panel `frame` (or all panels when it is negative).
void render_panels(const std::string& png, const std::vector<Panel>& panels, int panel_size = 360, int frame = -1);

// A line plot (vtkChartXY) written to a PNG.
struct Series {
  std::string name;
  std::vector<double> x, y;
  bool points_only = false;
};
void line_plot(const std::string& png, const std::string& title, const std::string& x_label,
               const std::string& y_label, const std::vector<Series>& series, bool log_x, bool log_y);

}  // namespace study
