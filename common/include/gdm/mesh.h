// The triangle mesh type shared by every part of gdm.
#pragma once

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <Eigen/Core>

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

}  // namespace gdm
