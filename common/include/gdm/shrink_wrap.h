// Shrink-wrap: a closed, genus-0, intersection-free mesh around a triangle
// soup (holes, several pieces, noise, point clouds as degenerate triangles),
// shrunk from a sphere onto the soup's distance field (gdm/distance_field.h)
// by gdm::deform, the soup being an obstacle (gdm/obstacle.h): no face of the
// wrap ever touches the input, so all of the input stays inside the wrap,
// however thin its parts. Used by the MeshLab plugin and by `gdm wrap`.
//
//   gdm::WrapOptions o;
//   o.tolerance = 1.5;  // mm
//   o.cell_size = 0.5;  // mm
//   gdm::WrapResult r = gdm::shrink_wrap(triangles, o);
//   // r.mesh: closed, 2-manifold, genus 0, no self-intersection
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "gdm/deformer.h"
#include "gdm/errors.h"
#include "gdm/mesh.h"
#include "gdm/mesh_checks.h"
#include "gdm/triangle_locator.h"

namespace gdm {

struct WrapOptions {
  double cell_size = 1.0;        // distance-field grid spacing, mm (> 0)
  double tolerance = 2.0;        // wanted largest distance of the input from the wrap, mm (>= cell_size);
                                 // the wrap settles tolerance / 3 from the input
  double bridge = 0.0;           // openings of the input up to about this wide with no input under them
                                 // (holes) are spanned by a smooth cap, the envelope of balls of diameter
                                 // `bridge` rolled in from outside, instead of the wrap sinking into them
                                 // (input a cap would hide is reopened: a cavity whose walls are input is
                                 // still entered); mm, >= 0; 0 = off (e.g. 10 x the tolerance)
  bool fairing = true;           // after the deformation, smooth the vertices the field does not hold (over
                                 // holes, where the model's pressure leaves them standing an edge's height
                                 // off their neighbours: "pyramids"); they move toward their neighbours'
                                 // centroid, each move checked by the guard and against the input
  double min_angle = 10.0;       // triangle quality (triangle_quality.h), degrees in [0, 30], 0 = off: the
                                 // last geometric step, after the fairing, every operation also checked
                                 // against the input; best effort (the log says what is left)
  int coverage_rounds = 4;       // local refinement rounds while input lies beyond 90% of the tolerance
                                 // after the convergence (0 = off, >= 0)
  // The model (gdm::DeformOptions, Table 2 and section 6):
  double a0 = 1.0;               // deformation gain
  double a1 = 1.0;               // image event gain
  double a2 = 5.0;               // topology gain
  double lod_face_area = 10.0;   // level of detail: faces larger than this are split, cell^2
  int global_refinements = 0;    // 1-to-4 resamplings, each after a convergence; 0: faces stay near the
                                 // level of detail (one resampling quadruples faces and time)
  int max_cycles = 2000;         // deformation cycles, all stages and coverage rounds together
  int threads = 0;               // worker threads; 0 = all cores; the result does not depend on it
  // Cost limits, checked against estimate_wrap before anything is built: a wrap
  // estimated above either is refused at once (WrapTooCostly, naming the
  // estimate and a cell size that fits). 0 = no limit.
  double time_limit = 180.0;     // estimated wall time, s (3 minutes)
  double memory_limit = 2.0;     // estimated peak memory, GiB (2^30 bytes)
  std::function<bool(double)> field_progress = {};  // the distance field's progress (fraction in [0, 1]);
                                                     // returning false cancels (gdm::Error "cancelled")
};

struct WrapResult {
  Mesh mesh;                              // the wrap, vertices on float-representable points ("v:generation" set)
  DeformResult deform;                    // the first deformation (the stages before the coverage rounds)
  int coverage_rounds_done = 0;           // coverage rounds performed
  int total_cycles = 0;                   // deformation cycles, coverage rounds included
  double farthest_input_distance = 0.0;   // largest distance of an input corner from the wrap, mm (exact)
  double farthest_wrap_distance = 0.0;    // largest distance of a wrap vertex from the input, mm (exact)
  MeshReport report;                      // gdm::measure of the wrap
  std::vector<std::string> notes;         // what happened, for a log (warnings start with "warning: ")
};

// What a wrap would cost, estimated before anything is built (milliseconds
// for any input and options; the grid is exact, the rest a model calibrated by
// measuring gdm wrap on real and generated inputs, 2 cores: the figures are in
// common/src/shrink_wrap.cpp). The faces and the memory come within a factor
// of about 1.5 of the measured ones on those inputs; the time is rougher (it
// also depends on the machine and its load).
struct WrapEstimate {
  Index3 grid = {0, 0, 0};   // distance-field cells per axis (exactly what the wrap builds)
  double cells = 0.0;        // grid[0] * grid[1] * grid[2]
  double area = 0.0;         // expected area of the wrap, mm^2
  double faces = 0.0;        // expected faces of the wrap
  double cycles = 0.0;       // expected deformation cycles
  double seconds = 0.0;      // expected wall time, s
  double bytes = 0.0;        // expected peak memory (resident), bytes
  std::string text() const;  // "about 220 s and 250 MB (a 344 x 344 x 344 grid, about 86,000 faces)"
};
// Throws InvalidOption as shrink_wrap does for bad options or input.
WrapEstimate estimate_wrap(const std::vector<Triangle>& input, const WrapOptions& options);

// A wrap refused before it starts: its estimate exceeds options.time_limit or
// options.memory_limit. The message names the estimate, the limit and what to
// change; option() is "cell_size".
class WrapTooCostly : public InvalidOption {
 public:
  WrapTooCostly(const std::string& message, WrapEstimate estimate, double fitting_cell_size)
      : InvalidOption("cell_size", message), estimate_(estimate), fitting_cell_size_(fitting_cell_size) {}
  const WrapEstimate& estimate() const { return estimate_; }
  double fitting_cell_size() const { return fitting_cell_size_; }  // the smallest cell (mm) within the limits

 private:
  WrapEstimate estimate_;
  double fitting_cell_size_;
};

// The wrap of `input`. Where input still lies beyond 90% of the tolerance
// after the convergence, the wrap's faces near it are split and the wrap
// deformed again (at most options.coverage_rounds times). `observer` sees
// every deformation cycle; coverage round k reports stage
// global_refinements + k; returning false cancels. Throws WrapTooCostly
// (above, before any work), InvalidOption (an
// option out of range, named in the message; empty or non-finite input),
// gdm::Error ("cancelled", or a wrap that fails its closed / manifold / genus 0
// / no self-intersection checks).
WrapResult shrink_wrap(const std::vector<Triangle>& input, const WrapOptions& options,
                       const DeformObserver& observer = {});

}  // namespace gdm
