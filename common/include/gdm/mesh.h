// The triangle mesh type shared by every part of gdm.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace gdm {

// Double precision points: vertices move by fractions of a voxel in volumes
// whose physical coordinates can be hundreds of millimetres from the origin
// (paper section 7 blames float precision for several GDM failures).
struct MeshTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};

using Mesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;
using Vec3 = Eigen::Vector3d;

inline Vec3 to_eigen(const Mesh::Point& p) { return {p[0], p[1], p[2]}; }
inline Mesh::Point to_point(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

// (b - a) x (c - a) over face f's corners in the face's order: its normal,
// twice its area long (the area weighting of the normals summed over rings).
inline Vec3 face_area_normal(const Mesh& mesh, Mesh::FaceHandle f) {
  auto it = mesh.cfv_iter(f);
  const Vec3 a = to_eigen(mesh.point(*it)), b = to_eigen(mesh.point(*++it)), c = to_eigen(mesh.point(*++it));
  return (b - a).cross(c - a);
}

inline double face_area(const Mesh& mesh, Mesh::FaceHandle f) { return 0.5 * face_area_normal(mesh, f).norm(); }

// The smallest angle of triangle abc, degrees (atan2 of |u x w| and u . w:
// accurate near 0 and 180 degrees).
inline double smallest_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const auto angle = [](const Vec3& apex, const Vec3& p, const Vec3& q) {
    const Vec3 u = p - apex, w = q - apex;
    return std::atan2(u.cross(w).norm(), u.dot(w));
  };
  return std::min({angle(a, b, c), angle(b, c, a), angle(c, a, b)}) * 180.0 / 3.14159265358979323846;
}

// The area-weighted normal at v: its faces' face_area_normal() summed in the
// mesh's order around v (not normalised; zero for an isolated vertex).
inline Vec3 vertex_area_normal(const Mesh& mesh, Mesh::VertexHandle v) {
  Vec3 normal = Vec3::Zero();
  for (auto f : mesh.vf_range(v)) normal += face_area_normal(mesh, f);
  return normal;
}

}  // namespace gdm

namespace gdm {

// v and every vertex within `rings` edges of it, each once, sorted by index
// (rings <= 0: v alone), into `found` (whose storage is reused: the per-vertex
// kernels call this for every vertex of every cycle).
void vertices_within(const Mesh& mesh, Mesh::VertexHandle v, int rings, std::vector<int>& found);

inline std::vector<int> vertices_within(const Mesh& mesh, Mesh::VertexHandle v, int rings) {
  std::vector<int> found;
  vertices_within(mesh, v, rings, found);
  return found;
}

// `flagged` (per vertex index) grown by `rings` rings: every vertex within
// `rings` edges of a flagged one flagged too. Ring by ring from the last
// ring's new vertices only.
inline std::vector<char> grow_by_rings(const Mesh& mesh, std::vector<char> flagged, int rings) {
  std::vector<int> frontier, next;
  for (std::size_t i = 0; i < flagged.size(); ++i)
    if (flagged[i]) frontier.push_back(static_cast<int>(i));
  for (int ring = 0; ring < rings && !frontier.empty(); ++ring) {
    next.clear();
    for (int v : frontier)
      for (auto w : mesh.vv_range(Mesh::VertexHandle(v)))
        if (!flagged[static_cast<std::size_t>(w.idx())]) {
          flagged[static_cast<std::size_t>(w.idx())] = 1;
          next.push_back(w.idx());
        }
    frontier.swap(next);
  }
  return flagged;
}

// The faces around any of the vertices, each once, sorted by index, into
// `faces` (storage reused).
void faces_around(const Mesh& mesh, const std::vector<int>& vertices, std::vector<int>& faces);

inline std::vector<int> faces_around(const Mesh& mesh, const std::vector<int>& vertices) {
  std::vector<int> faces;
  faces.reserve(8 * vertices.size());
  faces_around(mesh, vertices, faces);
  return faces;
}

// Lists index i in `listed` unless its flag is set, and sets it: each index
// once, whatever the repeats (a flag per index instead of sorting every
// repeat: the guard's and the fit's faces around their moves).
inline void list_once(int i, std::vector<int>& listed, std::vector<char>& flags) {
  char& flag = flags[static_cast<std::size_t>(i)];
  if (flag) return;
  flag = 1;
  listed.push_back(i);
}

// The indices list_once() listed, in ascending order, their flags cleared:
// by a pass over the flags when they are many (over a sixteenth of the
// flags), else by a sort of the list.
void sort_listed(std::vector<int>& listed, std::vector<char>& flags);

// The per-vertex generation (the deformation cycle that created the vertex,
// paper section 6.4, Fig. 11), stored as the OpenMesh property "v:generation".
inline OpenMesh::VPropHandleT<int> generation_property(Mesh& mesh) {
  OpenMesh::VPropHandleT<int> handle;
  if (!mesh.get_property_handle(handle, "v:generation")) {
    mesh.add_property(handle, "v:generation");
    for (auto v : mesh.vertices()) mesh.property(handle, v) = 0;
  }
  return handle;
}

// The generation property of a const mesh; an invalid handle when absent.
inline OpenMesh::VPropHandleT<int> find_generation_property(const Mesh& mesh) {
  OpenMesh::VPropHandleT<int> handle;
  mesh.get_property_handle(handle, "v:generation");
  return handle;
}

}  // namespace gdm
