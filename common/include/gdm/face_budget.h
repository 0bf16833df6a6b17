// The face budget (beyond the paper, issue 16): the final model gets about N
// faces, placed where the surface needs them. The deformation converges and
// the fit puts the model on the threshold surface at a level of detail with
// several times N faces (the Deformer subdivides 1-to-4, as section 6's
// global resampling, and fits again when the paper's level of detail,
// section 4, gives fewer); then edges are collapsed, least error first, until
// N faces remain. The error of a collapse is the quadric error (sum of
// squared distances to the planes of the fitted faces the merged vertex
// stands for, area-weighted) at the merged vertex's position, the point where
// those planes meet best: faces stay small where the fitted surface bends
// (edges, corners, thin parts) and grow where it is flat. Every collapse is
// guarded like the error-driven level of detail's (error_lod.h): link
// condition (closed, 2-manifold, genus kept), exact intersection tests of
// every moved face, no flipped face, a triangle-quality floor. The order is
// fixed (error, edge length, halfedge index), single-threaded: the result
// does not depend on the thread count.
#pragma once

#include <cstddef>
#include <vector>

#include "gdm/mesh.h"

namespace gdm {

struct ReduceOptions {
  std::size_t faces = 0;            // target: collapse until at most this many faces remain
  double min_angle = 10.0;          // no new angle below this, degrees (or below the face's own
                                    // smallest angle, when lower): the floor of the first rounds,
                                    // halved then dropped when the target is not reached
  double noise = 0.0;               // mm: quadric error below area x noise^2 (what image noise of this
                                    // standard deviation explains) counts as none; such collapses go
                                    // shortest edge first
  bool move_vertices = true;        // the kept vertex moves to the point of least quadric error (else it
                                    // stays where it was: a halfedge collapse)
  bool keep_floor = false;          // never lower the floor (the target may then be missed)
  double max_normal_change = 45.0;  // a new face turns at most this much from the old one, degrees
  int threads = 0;                  // workers for the collapses' checks (0 = all cores); the result does
                                    // not depend on it
};

struct ReduceResult {
  std::size_t collapses = 0;  // edges collapsed
  std::size_t faces = 0;      // faces left (deleted ones not counted)
};

// How far the fit may move each vertex of a model just subdivided for the
// budget (1-to-4) from where it stands, mm by vertex index: what the coarse
// faces could miss of a smooth surface, the sagitta e x theta / 8 of a coarse
// edge (twice a fine one, length e) across which the faces turn by theta,
// the largest within `rings` rings, plus `floor_mm`. The coarse model,
// converged and fitted over large faces, averaged the image noise away; a
// fine vertex alone does not, and impulse noise (a dark speck just inside the
// surface) has a crossing of its own that pulls it in, a dent the reduction
// would then keep as a feature. Where the coarse faces turn (edges, corners,
// bends) the bound grows and the fine fit reaches the surface they cut
// across.
std::vector<double> subdivision_fit_bounds(const Mesh& mesh, int rings, double floor_mm);

// Collapses halfedges of `mesh` (a closed 2-manifold), least quadric error
// first, until at most options.faces faces remain or no guarded collapse is
// left. The quadrics are those of the mesh as given (the fitted surface): a
// vertex carries the planes of its faces, a merged vertex the sum of both.
// Garbage-collects the mesh; releases the status attributes it requested.
ReduceResult reduce_to_faces(Mesh& mesh, const ReduceOptions& options);

}  // namespace gdm
