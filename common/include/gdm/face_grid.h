// A uniform grid over triangle bounding boxes: the broad phase of the exact
// intersection tests (the self-intersection guard, the error-driven level of
// detail's collapse checks, obstacles).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "gdm/cell_lists.h"
#include "gdm/mesh.h"

namespace gdm {

// Boxes are inflated by a margin so that a face stays inside its registered
// cells while its vertices move by up to that margin; rebuilding once per
// cycle then suffices. Faces are identified by an index (a mesh face's idx(),
// or any numbering of a triangle list).
class FaceGrid {
 public:
  // An empty grid with this cell size and margin.
  void reset(double cell_size, double margin);
  // reset(), then every face of the mesh registered.
  void rebuild(const Mesh& mesh, double cell_size, double margin);
  // Registers a face's current box (extra entries are harmless).
  void insert(const Mesh& mesh, Mesh::FaceHandle f);
  // Registers a box for a face (inflated by the margin).
  void insert_box(int face, Vec3 lo, Vec3 hi);
  // Keeps the grid valid for moves of up to `reach` per vertex (reach at
  // most the margin) without a rebuild: registers again each face whose box,
  // grown by `reach`, leaves the box it was last registered with, and
  // registers faces new since then. Returns false, changing nothing, when
  // more than half the faces would be registered again: rebuild then.
  bool refresh(const Mesh& mesh, double reach);
  // The same, looking only at `faces` (ascending, no repeats) and the faces
  // new since the last registration: the caller knows every other face kept
  // its box since it was last registered or looked at (their test would
  // pass), so the outcome is refresh()'s at a cost proportional to the faces
  // that moved.
  bool refresh(const Mesh& mesh, double reach, const std::vector<int>& faces);
  // Registers the faces added since the last rebuild or refresh (a split
  // leaves the faces it shrinks inside their registered boxes).
  void register_new_faces(const Mesh& mesh);
  // The faces renumbered (a mesh's garbage collection): face i becomes
  // to[i], or leaves the grid when to[i] < 0; `faces` is the new count.
  // Faces only move down (to[i] <= i, to[i] < faces), as a garbage
  // collection compacts; else std::invalid_argument, the grid unchanged.
  // Every face keeps the boxes it was registered with: a grid that held
  // every face's present box before still does, for the cost of the cells
  // of the faces that leave or move instead of a rebuild.
  void renumber(const std::vector<int>& to, std::size_t faces);

  // Has the face a registered box?
  bool registered(int face) const {
    return static_cast<std::size_t>(face) < box_lo_.size() && box_lo_[face].x() <= box_hi_[face].x();
  }
  // Does the union of the face's registered boxes meet the box [lo, hi]?
  bool box_meets(int face, const Vec3& lo, const Vec3& hi) const {
    return !((box_lo_[face].array() > hi.array()).any() || (box_hi_[face].array() < lo.array()).any());
  }
  // Calls visit(face index) once for every face registered in a cell the box
  // touches whose registered box meets it.
  template <class Visit>
  void for_each_near(const Vec3& lo, const Vec3& hi, Visit&& visit);
  // The same faces, possibly more than once, without touching the grid's
  // state; stops and returns true at the first face for which test(face) is.
  template <class Test>
  bool any_near(const Vec3& lo, const Vec3& hi, Test&& test) const;

  // any_near() visiting each face once, marked in the caller's `stamps`
  // (one array per thread: the grid is not touched) with a value new to them.
  template <class Test>
  bool any_near_once(const Vec3& lo, const Vec3& hi, std::vector<std::uint32_t>& stamps, std::uint32_t stamp,
                     Test&& test) const {
    if (stamps.size() < box_lo_.size()) stamps.resize(box_lo_.size(), 0);
    return scan_cells(lo, hi, [&](int f) {
      if (stamps[static_cast<std::size_t>(f)] == stamp) return false;
      stamps[static_cast<std::size_t>(f)] = stamp;
      return box_meets(f, lo, hi) && test(f);
    });
  }

  double cell_size() const { return cell_size_; }
  // The largest extent, along any axis, of a face's union box registered
  // since the last reset (it only grows until then): a face the grid offers
  // for a box lies within this distance of it.
  double widest_box() const { return widest_box_; }
  std::size_t cell_count() const { return cells_.size(); }

 private:
  using Key = std::uint64_t;
  Key key(int x, int y, int z) const;
  std::array<int, 3> cell_of(const Vec3& p) const;
  void grow_to(std::size_t faces);
  void add_to_cells(int face, const Vec3& lo, const Vec3& hi);
  void remove_from_cells(int face);
  // Every entry of the face in one cell gone (the last entry takes each place).
  void remove_from_cell(Key cell_key, int face);
  // A face listed once in each cell from `from_lo` to `from_hi` (cell
  // coordinates) listed so in those from `to_lo` to `to_hi` instead.
  void move_cells(int face, const std::array<int, 3>& from_lo, const std::array<int, 3>& from_hi,
                  const std::array<int, 3>& to_lo, const std::array<int, 3>& to_hi);
  // Registers the face's box afresh (inflated by the margin) in place of all
  // its earlier ones.
  void reregister(int face, const Vec3& lo, const Vec3& hi);
  // refresh()'s end: registers redo_'s faces again, or returns false for a rebuild.
  bool reregister_redo(const Mesh& mesh);
  // Calls scan(face) for every entry of the cells the box touches, until it returns true.
  template <class Scan>
  bool scan_cells(const Vec3& lo, const Vec3& hi, Scan&& scan) const;

  double cell_size_ = 1.0;
  double margin_ = 0.0;
  CellLists cells_;
  std::vector<Vec3> box_lo_, box_hi_;  // per face: union of its registered (inflated) boxes
  // Per face: a box listed in every cell it touches, whose content refresh()
  // may leave in place (empty after a second insert_box: refresh re-registers).
  std::vector<Vec3> reg_lo_, reg_hi_;
  std::vector<int> redo_;  // scratch of refresh() (faces to register again) and renumber() (faces that leave or move)
  std::vector<std::uint32_t> stamp_;
  std::uint32_t current_stamp_ = 0;
  double widest_box_ = 0.0;
};

template <class Scan>
inline bool FaceGrid::scan_cells(const Vec3& lo, const Vec3& hi, Scan&& scan) const {
  const auto a = cell_of(lo), b = cell_of(hi);
  for (int x = a[0]; x <= b[0]; ++x)
    for (int y = a[1]; y <= b[1]; ++y)
      for (int z = a[2]; z <= b[2]; ++z) {
        const std::vector<int>* list = cells_.find(key(x, y, z));
        if (!list) continue;
        for (int f : *list)
          if (scan(f)) return true;
      }
  return false;
}

template <class Visit>
inline void FaceGrid::for_each_near(const Vec3& lo, const Vec3& hi, Visit&& visit) {
  if (++current_stamp_ == 0) {
    std::fill(stamp_.begin(), stamp_.end(), 0);
    current_stamp_ = 1;
  }
  scan_cells(lo, hi, [&](int f) {
    if (stamp_[f] == current_stamp_) return false;
    stamp_[f] = current_stamp_;
    if (box_meets(f, lo, hi)) visit(f);
    return false;
  });
}

template <class Test>
inline bool FaceGrid::any_near(const Vec3& lo, const Vec3& hi, Test&& test) const {
  return scan_cells(lo, hi, [&](int f) { return box_meets(f, lo, hi) && test(f); });
}

}  // namespace gdm
