// Sharp edges and corners (issue 16; the cube with a corner missing of the
// paper's section 6.1). The fit puts every vertex on the threshold surface,
// and that surface is rounded where the object has an edge or a corner: the
// partial volume of the voxels across the edge blurs it (a box's edge cut
// by about 0.3 voxel at the threshold halfway between the levels), and the
// model's faces cut across it wherever no vertex lies on it. Here the
// surface near each vertex is looked at as planes: the faces within two rings,
// each with the point where the data crosses the threshold along its normal
// from its centroid, fall into two or three groups of nearly equal normals
// (a crease or a corner) whose crossings all lie on a plane; faces whose
// normals lie between the groups' (the faces cutting across the edge) join
// none. Then, as dual contouring places its vertices on the data's tangent
// planes (Ju et al. 2002; Kobbelt et al. 2001's extended marching cubes),
// the model gets vertices on the edge: a vertex near a corner moves to the
// planes' common point, an edge whose ends lie on different planes is split
// where it crosses their line of intersection (or its nearer end moves onto
// that line) and the new vertex moves onto the line. Every move is checked by
// the intersection guard; a split adds faces inside the old ones. Where the
// surface bends smoothly (a sphere, a tube) or the image is noisy, the faces'
// crossings lie off any one plane by more than `flatness` and nothing changes.
#pragma once

#include <cstddef>
#include <vector>

#include "gdm/mesh.h"
#include "gdm/volume.h"

namespace gdm {

struct CreaseOptions {
  double min_angle = 35.0;     // degrees: planes closer than this make no edge
  double plane_spread = 12.0;  // degrees: a face belongs to a plane whose normal is this close to its own
  double flatness = 0.15;      // voxels: every crossing of a plane's faces lies this close to the plane
  double max_move = 1.0;       // voxels: farthest a vertex moves onto an edge or corner
  double search = 1.5;         // voxels: crossings are searched this far along each face's normal
  int rings = 2;               // the faces within this many rings of a vertex make its planes
  double noise = 0.0;          // mm: the crossings' noise (estimate_crossing_noise); an edge flatter than
                               // this can tell from a smooth bend is not taken
  int generation = 0;          // stored on the vertices that splits add ("v:generation")
  bool prevent_self_intersection = true;  // moves checked by the intersection guard
  int threads = 0;             // workers for the faces' samples and the vertices' planes (0 = all cores);
                               // the moves and splits are sequential: the result does not depend on it
};

struct CreaseResult {
  std::size_t edge_vertices = 0;    // vertices with two planes around them
  std::size_t corner_vertices = 0;  // vertices with three
  std::size_t corners = 0;          // vertices moved onto a corner
  std::size_t edge_moves = 0;       // vertices moved onto an edge (old ones, and those splits added)
  std::size_t splits = 0;           // edges split where they cross an edge of the object
  std::size_t refused = 0;          // moves the guard refused (a split's vertex then stays on its edge)
};

// Gives `mesh` (closed, 2-manifold, on the threshold surface) vertices on the
// object's sharp edges and corners. The moves and splits in vertex and edge
// order, one at a time: the same for any thread count. Keeps the mesh closed, 2-manifold, its genus and,
// with prevent_self_intersection, free of self-intersections.
CreaseResult sharpen_creases(Mesh& mesh, const Volume& volume, double threshold, const CreaseOptions& options = {});

}  // namespace gdm
