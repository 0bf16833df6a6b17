// Keeps the model free of self-intersections (beyond the paper, section 7):
// every vertex move, and every edge flip, is checked against the nearby faces
// with exact predicates before it is applied.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "gdm/mesh.h"

namespace gdm {

// A uniform grid over face bounding boxes. Boxes are inflated by a margin so
// that a face stays inside its registered cells while its vertices move by up
// to that margin; rebuilding once per cycle then suffices.
class FaceGrid {
 public:
  void rebuild(const Mesh& mesh, double cell_size, double margin);
  // Registers a face's current box (extra entries are harmless).
  void insert(const Mesh& mesh, Mesh::FaceHandle f);
  // Registers a box for a face (inflated by the margin).
  void insert_box(int face, Vec3 lo, Vec3 hi);
  // Calls visit(face index) once for every face registered in a cell the box touches.
  template <class Visit>
  void for_each_near(const Vec3& lo, const Vec3& hi, Visit&& visit);

 private:
  using Key = std::uint64_t;
  Key key(int x, int y, int z) const;
  std::array<int, 3> cell_of(const Vec3& p) const;

  double cell_size_ = 1.0;
  double margin_ = 0.0;
  std::unordered_map<Key, std::vector<int>> cells_;
  std::vector<Vec3> box_lo_, box_hi_;  // per face: union of its registered (inflated) boxes
  std::vector<std::uint32_t> stamp_;
  std::uint32_t current_stamp_ = 0;
};

template <class Visit>
inline void FaceGrid::for_each_near(const Vec3& lo, const Vec3& hi, Visit&& visit) {
  if (++current_stamp_ == 0) {
    std::fill(stamp_.begin(), stamp_.end(), 0);
    current_stamp_ = 1;
  }
  const auto a = cell_of(lo), b = cell_of(hi);
  for (int x = a[0]; x <= b[0]; ++x)
    for (int y = a[1]; y <= b[1]; ++y)
      for (int z = a[2]; z <= b[2]; ++z) {
        const auto it = cells_.find(key(x, y, z));
        if (it == cells_.end()) continue;
        for (int f : it->second) {
          if (stamp_[f] == current_stamp_) continue;
          stamp_[f] = current_stamp_;
          if ((box_lo_[f].array() > hi.array()).any() || (box_hi_[f].array() < lo.array()).any()) continue;
          visit(f);
        }
      }
}

struct GuardStatistics {
  std::size_t rejected_moves = 0;  // moves vetoed for an intersection or a degenerate face
  std::size_t rejected_flips = 0;
};

class IntersectionGuard {
 public:
  // `margin` must bound how far any vertex moves between two rebuilds.
  IntersectionGuard(const Mesh& mesh, double margin, double min_face_area);

  // Re-registers every face (after topology changes or once per cycle).
  void rebuild();
  void note_face(Mesh::FaceHandle f) { grid_.insert(*mesh_, f); }

  // Would moving v to p leave every face non-degenerate, with its orientation
  // kept, and free of improper intersections with all other faces?
  bool move_is_safe(Mesh::VertexHandle v, const Vec3& p);

  // Would the flip creating (q0, q1, q3) and (q2, q3, q1) from the faces
  // around edge e keep the mesh free of intersections?
  bool flip_is_safe(Mesh::EdgeHandle e, const Mesh::VertexHandle (&quad)[4]);

  const GuardStatistics& statistics() const { return stats_; }

 private:
  struct Triangle {
    std::array<Vec3, 3> p;
    std::array<int, 3> id;
  };
  bool triangle_is_clear(const Triangle& t, const std::vector<int>& ignore_faces, int moved_vertex,
                         const Vec3& moved_to);
  Triangle face_triangle(int face, int moved_vertex, const Vec3& moved_to) const;

  const Mesh* mesh_;
  double margin_;
  double min_face_area_;
  FaceGrid grid_;
  GuardStatistics stats_;
};

}  // namespace gdm
