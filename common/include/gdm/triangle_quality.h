// Triangle quality (beyond the paper, issue 16): a last pass that removes
// faces with an angle below a bound (slivers: needles and caps) by guarded
// local operations, so simulation and 3D-printing users can take the model as
// it is. Every operation keeps the guarantees: edge flips and vertex moves are
// checked by the IntersectionGuard (and the obstacle, when there is one),
// collapses by the link condition (closed, 2-manifold, genus kept) and by
// CollapseChecker's exact intersection tests. The pass runs in a fixed order
// (faces by smallest angle, then index), single-threaded: the result does not
// depend on the thread count.
#pragma once

#include <cstddef>

#include "gdm/mesh.h"
#include "gdm/obstacle.h"

namespace gdm {

struct QualityOptions {
  double min_angle = 10.0;      // degrees: faces with a smaller angle are improved (0 = nothing to do)
  double max_error = 0.0;       // mm: how far an operation may move the surface (a flip's new edge from
                                // the old faces, a collapsed vertex from the new ones); relaxed vertices
                                // stay on the old surface of their ring. <= 0: unbounded
  int rounds = 8;               // rounds of flips, collapses and relaxation (stops early when nothing changes)
  double spike_radius = 0.0;    // mm: a corner of a face below the bound whose neighbours lie within this
                                // radius of their centroid, and which stands at least four times as far
                                // from it, is a spike and is removed (collapsed into its nearest
                                // neighbour) whatever max_error says; <= 0: none removed
  bool unfold = false;          // after the rounds, edges folded beyond kFoldDegrees (mesh_checks.h)
                                // flipped or collapsed where that leaves fewer folds around (unfold_phase)
  bool prevent_self_intersection = true;  // flips and moves checked by the IntersectionGuard
  const Obstacle* obstacle = nullptr;     // triangles no operation may touch; not owned
  int threads = 0;              // workers for the scans over every edge (the folds), 0 = all
                                // cores; the operations run in order: the same result for any count
};

struct QualityResult {
  std::size_t flips = 0;          // edge flips made
  std::size_t collapses = 0;      // short edges collapsed (spikes included; a pair of collapses counts two)
  std::size_t spikes = 0;         // of the collapses: spikes removed (spike_radius)
  std::size_t unfolds = 0;        // of the collapses: folded edges collapsed (unfold)
  std::size_t unfold_flips = 0;   // of the flips: folded edges flipped (unfold)
  std::size_t splits = 0;         // long edges of caps split at the foot of the cap's apex
  std::size_t moves = 0;          // vertex moves of the relaxation (the slides included)
  std::size_t slides = 0;         // of the moves: slides along an edge (the last resort)
  std::size_t retreats = 0;       // of the moves: steps back from another sheet the faces left below
                                  // the bound lie against (then the operations again)
  std::size_t faces_below = 0;    // faces still with an angle below min_angle after the pass
  double min_angle_before = 0.0;  // smallest angle of the mesh before the pass, degrees (NaN: no faces)
  double min_angle_after = 0.0;   // ... after it
};

// The smallest interior angle of the triangle abc, degrees.
double triangle_min_angle(const Vec3& a, const Vec3& b, const Vec3& c);

// Improves every face whose smallest angle is below options.min_angle. Per
// round, faces worst first: (1) edge flips that raise the smallest angle of
// the two faces; (2) caps (an angle above 120 degrees at the apex) split at
// the foot of the apex on the long edge (the new faces lie inside the old
// ones); (3) collapses of an edge of each face still below the bound: a
// corner that is a thin spike (spike_radius) removed first, its new faces
// free of intersections and facing the way its ring's other faces face;
// else an edge (shortest first; into either end, else into a point between
// them), when
// no face turns by more than 45 degrees and no new face falls below the
// bound unless the smallest angle around rises; (4) tangential relaxation of
// the corners of faces still below the bound: a vertex moves toward the
// centroid of its neighbours (a quarter, half or the whole way), else a short
// step (a tenth to half its shortest edge) in one of twelve tangential
// directions, projected back onto the old faces of its ring, when that raises
// the smallest angle around it. Flips and collapses move the surface by at
// most max_error; faces still below the bound after the rounds get a second
// and a third series of rounds with 2.5 and 5 times max_error, and after the
// third, pairs of collapses judged on the state they leave together (the
// first, out of a corner or a valence-three neighbour of one, may leave a
// sliver the second removes; undone when no second mends), then slides of
// their corners along an edge (a tenth to half of it: on the old surface,
// where the relaxation's tangent plane is none, as on the crest of a thin
// fin), under the relaxation's rules. With
// options.unfold, edges folded beyond kFoldDegrees (mesh_checks.h) are then
// flipped, else collapsed, where that leaves fewer folded edges around and
// none sharper, under the same rules but the orientation and 45-degree
// normal tests, within 5 times max_error (unfold_phase). Last, the corners
// of faces still below the bound move as the relaxation moves them, by steps
// of a hundredth to a twentieth of the shortest edge (nudge_phase: where the
// guard refuses longer steps, as at a crumpled apex). Leaves the
// mesh garbage-collected (no deleted elements; the status attributes stay
// requested). Best effort: faces_below says how many faces remain below.
QualityResult improve_triangle_quality(Mesh& mesh, const QualityOptions& options);

}  // namespace gdm
