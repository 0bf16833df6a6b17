// CGAL peer (Mesh_3 from a gray-level image) and a point-to-surface distance
// (CGAL's AABB tree). No gdm, VTK or ITK header here.
#pragma once

#include <memory>
#include <vector>

#include "study_types.h"

namespace study {

// CGAL Mesh_3 on the gray-level image (Labeled_mesh_domain_3::create_gray_image_mesh_domain),
// criteria facet_angle 25 degrees and facet_distance (mm), no size bound, no
// cell criteria (the inside is not refined), no perturbation or exudation; the boundary facets of the complex are returned.
// The triangulation is initialised from the image's surface voxels (CGAL's
// initialize_triangulation_from_gray_image), so small objects in large volumes are found.
PeerResult run_cgal_mesh3(const Image& image, double threshold, bool object_brighter, double facet_distance);

// Unsigned distance from points to a triangle surface (AABB tree).
class SurfaceDistance {
 public:
  explicit SurfaceDistance(const Surface& surface);
  ~SurfaceDistance();
  SurfaceDistance(const SurfaceDistance&) = delete;
  SurfaceDistance& operator=(const SurfaceDistance&) = delete;
  bool empty() const;
  double operator()(const Point& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace study
