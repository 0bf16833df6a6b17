// Error-driven level of detail (beyond the paper's face-area threshold,
// section 4): faces are split where the threshold surface deviates from them
// by more than a tolerance, and edges are collapsed where the surface is flat
// enough that the coarser faces stay within it. Every collapse keeps the mesh
// closed, 2-manifold and genus 0 (link condition), free of self-intersections
// (exact predicates), without flipped faces and above a triangle-quality floor.
#pragma once

#include <limits>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "gdm/intersection_guard.h"
#include "gdm/mesh.h"
#include "gdm/volume.h"

namespace gdm {

// How far (mm) the threshold surface leaves the face: from seven points spread
// over the face, each measured along the face normal to the crossing (searched
// within search_mm), the larger of |mean signed distance| and a third of the
// largest distance (robust to image noise, yet catching faces that straddle a
// crease; see the source), each less what image noise of noise_mm (the
// standard deviation of one crossing distance, estimate_crossing_noise)
// explains; infinity when a point finds no crossing.
double face_deviation(const Mesh& mesh, Mesh::FaceHandle f, const Volume& volume, double threshold,
                      double search_mm, double noise_mm = 0.0);

// The standard deviation (mm) of one crossing distance that the image noise
// causes, estimated over the whole mesh from the residuals of the faces'
// seven distances about their mean (median absolute residual: robust to the
// few faces that straddle an edge; about 0 on a noise-free volume). The
// faces on `threads` workers (0 = all cores); the same for any count.
double estimate_crossing_noise(const Mesh& mesh, const Volume& volume, double threshold, double search_mm,
                               int threads = 0);

// The standard deviation (mm) of one crossing distance that a voxel's noise
// of voxel_noise (estimate_voxel_noise) causes where the edge has the slope
// it has at this mesh: the noise of a trilinear sample (sqrt(8/27) of
// voxel_noise, the mean over a cell) over the median, over the faces, of the
// change in value across one voxel along the face normal at the centroid,
// per mm. Unlike estimate_crossing_noise it does not read the noise off
// crossings a voxel apart (which interpolate the same voxels and so
// understate it, the more the noisier the image; measured in the README,
// stop 45); 0 on a clean volume. The faces on `threads` workers; the same
// for any count.
double estimate_edge_noise(const Mesh& mesh, const Volume& volume, double voxel_noise, int threads = 0);

// Splits the longest edge of every face that deviates by more than
// `tolerance_mm` (faces with no crossing within reach are left alone) and
// whose longest edge is longer than `min_edge_mm` (the new
// vertex at the midpoint, with `generation`). The new triangles lie inside the
// old ones, so no split creates an intersection. Returns the number of splits.
std::size_t split_deviating_faces(Mesh& mesh, const Volume& volume, double threshold, double tolerance_mm,
                                  double min_edge_mm, int generation, double noise_mm = 0.0);

// True when collapsing h (its from-vertex removed, merged into its to-vertex)
// keeps a closed 2-manifold of the same genus: OpenMesh's is_collapse_ok and
// the link condition (the two vertices share exactly the two neighbours
// opposite the edge, and those keep a valence of at least 3). Non-const only
// because OpenMesh tags vertices in is_collapse_ok; the mesh is not changed.
bool collapse_keeps_topology(Mesh& mesh, Mesh::HalfedgeHandle h);

// Calls keep_going(face) for each face that a collapse of h moves: every face
// around either end of h but h's own two, each once (a face around both ends
// is seen from h's start). Stops, and returns false, at the first call that
// returns false.
template <class Fn>
bool for_each_face_moved_by_collapse(const Mesh& mesh, Mesh::HalfedgeHandle h, Fn&& keep_going) {
  const auto v0 = mesh.from_vertex_handle(h), v1 = mesh.to_vertex_handle(h);
  const auto gone0 = mesh.face_handle(h), gone1 = mesh.face_handle(mesh.opposite_halfedge_handle(h));
  for (const auto end : {v0, v1})
    for (auto f : mesh.vf_range(end)) {
      if (f == gone0 || f == gone1) continue;
      bool of_both = false;
      for (auto w : mesh.fv_range(f)) of_both = of_both || (end == v1 && w == v0);
      if (of_both) continue;
      if (!keep_going(f)) return false;
    }
  return true;
}

struct CollapseOptions {
  double tolerance = 0.0;         // deviation allowed for the new faces, mm; <= 0: not checked
  double search = 1.5;            // crossing search range for the deviation, mm
  double noise = 0.0;             // crossing-distance noise discounted from the deviation, mm (face_deviation)
  double min_angle = 15.0;        // quality floor: smallest angle of a new face, degrees (or the
                                  // smallest angle already there, when lower)
  double max_normal_change = 45.0;  // a new face turns at most this much from the old one, degrees
  double max_length = std::numeric_limits<double>::infinity();  // only edges shorter than this, mm
  const std::vector<char>* only_edges = nullptr;  // when given: only the edges flagged here (by index)
  const std::vector<char>* removable = nullptr;   // when given: only the vertices flagged here (by index) go
};

// Checks collapses geometrically against the whole mesh: a uniform grid over
// face boxes limits the exact intersection tests to nearby faces.
class CollapseChecker {
 public:
  CollapseChecker(const Mesh& mesh, double cell_size);
  // Registers every face again (after changes it did not hear of), reusing
  // the grid's storage.
  void rebuild(double cell_size);
  // Would collapsing h leave the faces around its from-vertex non-degenerate,
  // unflipped, above the quality floor and free of improper intersections?
  bool geometry_ok(Mesh::HalfedgeHandle h, const CollapseOptions& options);
  // The same for a collapse that also moves the kept (to-)vertex to
  // `target`: every face around either vertex is checked.
  bool geometry_ok(Mesh::HalfedgeHandle h, const CollapseOptions& options, const Vec3& target);
  // What one check with a target works in: the faces it moves, where they
  // go, their boxes, and marks of the faces the grid offered.
  struct Scratch {
    std::vector<int> moved;
    std::vector<FilteredTriangle> created;
    std::vector<Vec3> lo, hi;
    std::vector<std::uint32_t> stamps;
    std::uint32_t stamp = 0;
  };
  // The same answer, reading the mesh and the grid only: threads may run it
  // at once, each with its own scratch, while nothing changes the mesh.
  bool geometry_ok(Mesh::HalfedgeHandle h, const CollapseOptions& options, const Vec3& target, Scratch& s) const;
  // Registers the faces around v after a collapse into v (or a move of v).
  void note_vertex(Mesh::VertexHandle v);
  // The faces renumbered by the mesh's garbage collection (FaceGrid::renumber).
  void renumber_faces(const std::vector<int>& to) { grid_.renumber(to, mesh_->n_faces()); }

 private:
  // Are the moved faces (s.moved, by index; s.created, where the collapse
  // puts them) free of improper intersections among themselves and with
  // every other face but the two the collapse deletes?
  bool moved_faces_clear(Mesh::FaceHandle gone0, Mesh::FaceHandle gone1, Scratch& s) const;

  const Mesh* mesh_;
  FaceGrid grid_;    // the intersection guard's grid, without a margin
  Scratch scratch_;  // geometry_ok's with a target, called without one
};

// One pass of collapses, shortest edges first, each one checked by
// collapse_keeps_topology, CollapseChecker::geometry_ok and, when
// options.tolerance > 0, the deviation of the new faces from the threshold
// surface. Needs the mesh's status attributes; deleted elements are left for
// the caller's garbage_collection(). Returns the number of collapses.
std::size_t collapse_flat_edges(Mesh& mesh, const Volume* volume, double threshold,
                                const CollapseOptions& options);

}  // namespace gdm
