// Topological and geometric checks and measurements on triangle meshes.
//
// All functions ignore elements marked deleted (they iterate with OpenMesh's
// skipping ranges) and never modify the mesh.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "gdm/mesh.h"

namespace gdm {

// True when the mesh has at least one face and no boundary halfedge.
bool is_closed(const Mesh& mesh);

// True when every edge has exactly two faces and the faces around every
// vertex form a single closed fan (its link is one cycle). A vertex without
// faces (isolated vertex) or with several fans (e.g. two cones touching at
// their tips) makes the mesh non-manifold. A mesh without faces is not one.
bool is_two_manifold(const Mesh& mesh);

// V - E + F over the non-deleted elements.
int euler_characteristic(const Mesh& mesh);

// Number of connected components of the faces, where two faces are connected
// when they share an edge (faces meeting only at a vertex are separate).
int connected_components(const Mesh& mesh);

// Genus summed over the components: (2 * components - chi) / 2, with chi
// computed without isolated vertices. For one closed connected orientable
// surface this is (2 - chi) / 2; for several closed orientable components it
// is the sum of their genera (two spheres: 0, sphere + torus: 1). Only
// meaningful for closed orientable meshes (the division truncates).
int genus(const Mesh& mesh);

// Number of unordered face pairs that intersect improperly, as decided by
// triangles_intersect_improperly (exact; shared vertices and edges are
// allowed contacts, fold-overs and any other contact are not). A uniform grid
// over face bounding boxes limits the exact tests to nearby faces; the result
// does not depend on the grid. The grid's cells are tested on up to `threads`
// threads (0 = all cores); the count does not depend on it.
std::size_t self_intersecting_pairs(const Mesh& mesh, int threads = 0);

// Whether any of `faces` (faces of `mesh`) intersects another face of the
// mesh improperly, as self_intersecting_pairs decides: one of the others or
// one of the list. Each is tested against the faces whose box meets the
// list's common box (one pass over the mesh; deleted faces skipped when the
// mesh has face status). For faces a change added to a mesh free of
// intersections before: whether the change made one, without counting the
// pairs of the whole mesh (the exact topology's tubes and cavity
// components: 0.5 s per question on the CT series' model, issue 17).
bool faces_meet_mesh(const Mesh& mesh, const std::vector<Mesh::FaceHandle>& faces);

// Signed enclosed volume by the divergence theorem: positive when the faces
// of a closed mesh are oriented with outward normals (counterclockwise seen
// from outside). Meaningless for open meshes.
double enclosed_volume(const Mesh& mesh);

// The mean length of the mesh's edges (deleted ones skipped when it has
// edge status, yet counted in the divisor as n_edges() counts them), mm; 0
// without edges. The length scale of the grids and tolerances built on it.
double mean_edge_length(const Mesh& mesh);

// Sum of triangle areas.
double surface_area(const Mesh& mesh);

// Smallest interior angle of any face, in degrees (0 for a face with a
// zero-length edge). NaN for a mesh without faces.
double smallest_angle_degrees(const Mesh& mesh);

// Folds: an edge folds by the angle between the normals of its two faces
// (0 flat, 90 a cube's edge, 180 two faces folded flat onto each other).
// An edge folding by more than kFoldDegrees is a wedge thinner than 20
// degrees: a fin, a crumple where a model's fronts met, a pleat.
constexpr double kFoldDegrees = 160.0;

// The fold between two triangles sharing an edge (their corners in their
// faces' order), degrees: the angle between their normals; 0 when either is
// degenerate.
double fold_degrees(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b);

// The fold of an edge with two faces, degrees (fold_degrees of its faces).
double edge_fold_degrees(const Mesh& mesh, Mesh::EdgeHandle e);

// The largest fold of any edge with two faces, degrees (0 for a mesh
// without such an edge; a degenerate face folds by nothing).
double sharpest_fold_degrees(const Mesh& mesh);

// Number of edges folding by more than `degrees`.
std::size_t folded_edges(const Mesh& mesh, double degrees = kFoldDegrees);

// Everything above in one record.
struct MeshReport {
  std::size_t vertices = 0;
  std::size_t faces = 0;
  std::size_t edges = 0;
  bool closed = false;
  bool two_manifold = false;
  int euler = 0;
  int genus = 0;
  int components = 0;
  bool euler_consistent = false;  // closed, and chi = 2 * components - 2 * genus (topology.h)
  std::size_t self_intersections = 0;
  double volume = 0.0;
  double area = 0.0;
  double min_angle_deg = 0.0;
  double max_fold_deg = 0.0;  // sharpest_fold_degrees
  std::size_t folds = 0;      // folded_edges beyond kFoldDegrees
};

// Measures all fields of MeshReport (self-intersections included, on up to
// `threads` threads: 0 = all cores).
MeshReport measure(const Mesh& mesh, int threads = 0);

// One readable line, e.g. "V=8 F=12 E=18 closed=yes manifold=yes chi=2 ...".
std::string to_string(const MeshReport& report);

}  // namespace gdm
