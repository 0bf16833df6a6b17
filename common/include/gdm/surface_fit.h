// The sub-voxel final fit (beyond the paper): after the deformation has
// converged, every vertex is moved along its smoothed normal onto the
// threshold crossing of the trilinear field. The paper's optimiser stops up to
// its smallest step (1/4 voxel, section 3.2) short of the boundary and its
// curvature term (eq. 3) pulls convex parts inward; the fit removes both.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "gdm/mesh.h"
#include "gdm/volume.h"

namespace gdm {

// The signed distance t (mm) along the unit direction `dir` from p to the
// nearest point where the trilinear value crosses `threshold`, searched within
// |t| <= max_mm in steps of step_mm on both sides and refined by regula falsi
// (Illinois) inside the bracket: exact for a field that is linear along the
// line. Empty when no crossing lies within reach inside the grid.
std::optional<double> find_crossing(const Volume& volume, double threshold, const Vec3& p, const Vec3& dir,
                                    double max_mm, double step_mm);

struct FitOptions {
  int passes = 8;               // sweeps over the vertices (normals re-estimated each sweep); stops
                                // early when a sweep moves no vertex by `still`
  double still = 0.01;          // voxels, >= 0: a move shorter than this is not made (the guard's checks
                                // of the last passes' many tiny moves were most of the fit's time); a
                                // smaller one fits a clean image closer, with more moves (README, stop 51)
  double max_distance = 1.0;    // a vertex ends at most this far from where the fit found it, voxels
  double search = 1.5;          // crossings are searched this far along the normal, voxels
  int normal_rings = 2;         // rings of faces averaged into the fit direction (section 7)
  double noise = -1.0;          // crossing-distance noise (estimate_crossing_noise), mm: the part h of a
                                // vertex's offset beyond its ring's mean is kept as h^2 / (h^2 + noise^2);
                                // < 0: not kept (the ring's mean only)
  double regularization = 0.5;  // noise-adaptive smoothness (needs noise > 0): a vertex's offset is
                                // drawn toward the quadric fitted over its 2-ring with weight
                                // s^2 / (s^2 + h^2), s = regularization x noise, h the vertex's height
                                // above that quadric; 0: off
  double quadric_step = 1.0;    // share of that pull a vertex goes per pass, in (0, 1]: every vertex
                                // moves at once, so a strong pull (most vertices within s) needs a
                                // damped step or the ring's finest mode is swapped, not smoothed
  double over_relaxation = 1.0;  // each pass moves a vertex this many times its offset, in [1, 2): the
                                // offsets of neighbours averaged in a ring shrink a lone vertex's step,
                                // so at 1 the passes creep toward the fixed point and moves under
                                // `still` stop them short of it (README, stop 57)
  bool curvature_correction = false;  // each crossing corrected for the trilinear field's bias on a curved
                                // surface (a convex part's crossing lies up to x(1-x)/2 times the
                                // curvature inside), with the curvature of the model where its 3-ring
                                // is a quadric within kQuadricResidual voxels; for quiet images only
                                // (README, stop 58)
  std::vector<double> vertex_max_distance;  // mm, by vertex index: where given (and > 0) it replaces
                                            // max_distance for that vertex; empty: max_distance for all
  bool prevent_self_intersection = true;  // every move checked by the IntersectionGuard
  int threads = 0;              // workers for the offsets (0 = all cores); the result does not depend on it
};

struct FitResult {
  std::size_t moves = 0;      // accepted vertex moves, all passes together
  std::size_t rejected = 0;   // moves vetoed by the self-intersection guard
  double last_pass_rms = 0.0; // RMS of the (averaged) per-vertex offsets of the last pass, mm
};

// Moves each vertex along its smoothed normal so that the surface around it
// lies on the threshold crossings on average: per pass, each vertex's offset
// is the mean signed distance to the crossing from its samples (itself, its
// faces' centroids, its edges' midpoints), weighted by how much each moves
// with the vertex; offsets are averaged once with the 1-ring's (noise), the
// vertex's own part given back in proportion to how far it stands above
// options.noise (Wiener-like) and drawn toward the quadric over its 2-ring
// where its height above it is within what the noise explains, then applied
// one at a time (moves under options.still skipped), each checked
// by the IntersectionGuard (a refused move is retried at half and a quarter
// length) and kept inside the grid: in vertex order, or, in a pass of at
// least kFitMovesByCubes moves, by cubes of space (space_blocks.h), the same
// for any thread count either way. At the fixed point flat faces sit across
// a curved surface instead of inside it (no chord bias) and the curvature
// term's inward pull is gone.
// `origin` (indexed by vertex handle; extended with the current positions of
// vertices it does not cover) anchors the max_distance bound: pass an empty
// vector to anchor at the current positions.
FitResult fit_to_threshold(Mesh& mesh, const Volume& volume, double threshold, const FitOptions& options,
                           std::vector<Vec3>& origin);

}  // namespace gdm
