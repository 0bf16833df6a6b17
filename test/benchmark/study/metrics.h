// Validity checks and error figures of any method's surface, computed with
// gdm's mesh checks (study surfaces are converted to a gdm::Mesh when they are
// 2-manifold; triangle soups that are not get the same checks done on the soup,
// with gdm's exact predicate for self-intersections).
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "gdm/mesh.h"
#include "study_types.h"

namespace study {

Surface from_gdm(const gdm::Mesh& mesh);  // keeps the vertex generation

struct Checks {
  bool closed = false;
  bool two_manifold = false;
  long self_intersections = -1;  // improperly intersecting face pairs; -1 = not computed
  int components = 0;            // faces connected through edges
  int genus = -1;                // only for closed 2-manifold surfaces; -1 otherwise
  bool via_gdm_mesh = false;     // measured on a gdm::Mesh with gdm::measure
};
// Self-intersections are skipped (-1) above `max_faces_for_intersections` faces.
Checks check_surface(const Surface& surface, std::size_t max_faces_for_intersections = 3000000);

// The surface as a gdm::Mesh (unreferenced points dropped) when it is a
// consistently oriented 2-manifold; false otherwise.
bool to_gdm_mesh(const Surface& surface, gdm::Mesh& mesh);

// Topology per edge-connected component (issue 15): its faces, its extent
// (bounding-box diagonal, mm) and its genus from its own Euler
// characteristic, g = (2 - (V - E + F)) / 2, when every edge of it has two
// faces (-1 otherwise: open or non-manifold). Largest extent first.
struct ComponentTopology {
  std::size_t faces = 0;
  double extent = 0.0;
  int genus = -1;
};
std::vector<ComponentTopology> component_topology(const Surface& surface);

// The component of largest extent (the outer surface of an iso-surface).
Surface largest_component(const Surface& surface);

// Points where a surface's error is measured: its vertices and face centroids.
std::vector<Point> sample_points(const Surface& surface);

struct ErrorStats {
  double mean = 0.0, p95 = 0.0, max = 0.0;  // voxels
  // Split at one voxel: where a model bridges what the reference follows
  // (a solid model's membranes over handles and pocket mouths) its points
  // lie farther than that, elsewhere it follows the data.
  double share_beyond_one = 0.0;  // share of the points farther than one voxel
  double mean_within_one = 0.0;   // mean over the others, voxels
  bool valid = false;
};
// |distance| of the points, divided by voxel_size.
ErrorStats error_stats(const std::vector<Point>& points, const std::function<double(const Point&)>& distance,
                       double voxel_size);

// Seams (issue 16): the faces of a surface that face another part of it
// closer than a voxel across the object (gdm::contact_faces, the gap's
// midpoint on the object's side), where a growing model's fronts met head on
// and stopped; an iso-surface has none (its sheets face each other across
// background only). `share` of the faces, and the error of the sample points
// away from them (the centroids of the other faces and the vertices with
// another face around them), in voxels; a face that is not part of a
// 2-manifold with the ones before it (a decimated surface has a few) counts
// as off the seams.
struct SeamSplit {
  double share = 0.0;           // share of the faces on seams
  double mean_elsewhere = 0.0;  // mean error of the points away from the seams, voxels
  bool valid = false;
};
SeamSplit seam_split(const Surface& surface, const std::function<double(const Point&)>& distance, double voxel_size,
                     const std::function<bool(const gdm::Vec3&)>& object_side, int threads);

}  // namespace study
