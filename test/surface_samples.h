// Test helper: points spread over a mesh's surface (its vertices, face
// centroids and edge midpoints), so that distances measure the faces and not
// only the vertices, which the fit puts on the surface.
#pragma once

#include <algorithm>
#include <functional>
#include <vector>

#include "gdm/mesh.h"
#include "gdm/phantoms.h"

namespace gdm::test {

inline std::vector<Vec3> surface_samples(const Mesh& mesh) {
  std::vector<Vec3> s;
  for (auto v : mesh.vertices()) s.push_back(to_eigen(mesh.point(v)));
  for (auto f : mesh.faces()) {
    Vec3 c = Vec3::Zero();
    for (auto v : mesh.fv_range(f)) c += to_eigen(mesh.point(v));
    s.push_back(c / 3.0);
  }
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    s.push_back(0.5 * (to_eigen(mesh.point(mesh.from_vertex_handle(h))) +
                       to_eigen(mesh.point(mesh.to_vertex_handle(h)))));
  }
  return s;
}

// |distance| statistics over the surface samples, in voxels.
inline phantoms::DistanceStats surface_distances(const Mesh& mesh,
                                                 const std::function<double(const Vec3&)>& distance,
                                                 double voxel_size) {
  std::vector<double> d;
  for (const Vec3& p : surface_samples(mesh)) d.push_back(std::abs(distance(p)) / voxel_size);
  return phantoms::distance_stats(std::move(d));
}

}  // namespace gdm::test
