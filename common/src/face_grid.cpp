#include "gdm/face_grid.h"

#include <limits>
#include <stdexcept>
#include <string>

#include "gdm/cell_hash.h"

namespace gdm {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

void face_box(const Mesh& mesh, Mesh::FaceHandle f, Vec3& lo, Vec3& hi) {
  lo = Vec3::Constant(kInf);
  hi = -lo;
  for (auto v : mesh.fv_range(f)) {
    const Vec3 p = to_eigen(mesh.point(v));
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
}

}  // namespace

FaceGrid::Key FaceGrid::key(int x, int y, int z) const { return cell_key(x, y, z); }

std::array<int, 3> FaceGrid::cell_of(const Vec3& p) const { return gdm::cell_of(p, cell_size_); }

void FaceGrid::grow_to(std::size_t faces) {
  if (faces <= stamp_.size()) return;
  stamp_.resize(faces, 0);
  box_lo_.resize(faces, Vec3::Constant(kInf));
  box_hi_.resize(faces, Vec3::Constant(-kInf));
  reg_lo_.resize(faces, Vec3::Constant(kInf));
  reg_hi_.resize(faces, Vec3::Constant(-kInf));
}

void FaceGrid::add_to_cells(int face, const Vec3& lo, const Vec3& hi) {
  const auto a = cell_of(lo), b = cell_of(hi);
  for (int x = a[0]; x <= b[0]; ++x)
    for (int y = a[1]; y <= b[1]; ++y)
      for (int z = a[2]; z <= b[2]; ++z) cells_[key(x, y, z)].push_back(face);
}

void FaceGrid::insert_box(int face, Vec3 lo, Vec3 hi) {
  lo.array() -= margin_;
  hi.array() += margin_;
  grow_to(static_cast<std::size_t>(face) + 1);
  // Within the box the face is listed under in every cell it touches: the
  // cells and the union box hold it already (the sub-voxel fit registers
  // the faces around each of its moves, most of them a fraction of the
  // margin; each was listed again in its cells, and the lists grew).
  if (reg_lo_[face].x() <= reg_hi_[face].x() && (lo.array() >= reg_lo_[face].array()).all() &&
      (hi.array() <= reg_hi_[face].array()).all())
    return;
  const bool first = !(box_lo_[face].x() <= box_hi_[face].x());
  box_lo_[face] = box_lo_[face].cwiseMin(lo);
  box_hi_[face] = box_hi_[face].cwiseMax(hi);
  widest_box_ = std::max(widest_box_, (box_hi_[face] - box_lo_[face]).maxCoeff());
  // A face with one box is listed in all its cells; with several (a flip
  // registers both candidate triangles), refresh() must register it again.
  reg_lo_[face] = first ? lo : Vec3::Constant(kInf);
  reg_hi_[face] = first ? hi : Vec3::Constant(-kInf);
  add_to_cells(face, lo, hi);
}

// The face's entries lie in the cells its union box touches; the order of a
// cell's entries does not matter (for_each_near's callers decide on all).
void FaceGrid::remove_from_cells(int face) {
  if (!(box_lo_[face].x() <= box_hi_[face].x())) return;  // never registered
  const auto a = cell_of(box_lo_[face]), b = cell_of(box_hi_[face]);
  for (int x = a[0]; x <= b[0]; ++x)
    for (int y = a[1]; y <= b[1]; ++y)
      for (int z = a[2]; z <= b[2]; ++z) remove_from_cell(key(x, y, z), face);
}

void FaceGrid::remove_from_cell(Key cell_key, int face) {
  std::vector<int>* cell = cells_.find(cell_key);
  if (!cell) return;
  auto& list = *cell;
  for (std::size_t i = 0; i < list.size();)
    if (list[i] == face) {
      list[i] = list.back();
      list.pop_back();
    } else {
      ++i;
    }
}

void FaceGrid::reregister(int face, const Vec3& lo, const Vec3& hi) {
  const Vec3 a = lo.array() - margin_, b = hi.array() + margin_;
  grow_to(static_cast<std::size_t>(face) + 1);
  // A face registered with one box is listed once in each cell of it (its
  // union box is that box): it stays listed in the cells the new box also
  // touches, leaves the others and joins the new ones. A move of a fraction
  // of a cell mostly keeps the same cells: removing the face from every
  // cell and adding it again was most of prepare_moves() on the T1 head
  // (issue 17). With several boxes, or none, every cell of the union goes.
  const bool single = reg_lo_[face].x() <= reg_hi_[face].x();
  if (single) {
    move_cells(face, cell_of(reg_lo_[face]), cell_of(reg_hi_[face]), cell_of(a), cell_of(b));
  } else {
    remove_from_cells(face);
    add_to_cells(face, a, b);
  }
  box_lo_[face] = reg_lo_[face] = a;
  box_hi_[face] = reg_hi_[face] = b;
  widest_box_ = std::max(widest_box_, (b - a).maxCoeff());
}

void FaceGrid::move_cells(int face, const std::array<int, 3>& from_lo, const std::array<int, 3>& from_hi,
                          const std::array<int, 3>& to_lo, const std::array<int, 3>& to_hi) {
  const auto inside = [](int x, int y, int z, const std::array<int, 3>& l, const std::array<int, 3>& h) {
    return x >= l[0] && x <= h[0] && y >= l[1] && y <= h[1] && z >= l[2] && z <= h[2];
  };
  for (int x = from_lo[0]; x <= from_hi[0]; ++x)
    for (int y = from_lo[1]; y <= from_hi[1]; ++y)
      for (int z = from_lo[2]; z <= from_hi[2]; ++z)
        if (!inside(x, y, z, to_lo, to_hi)) remove_from_cell(key(x, y, z), face);
  for (int x = to_lo[0]; x <= to_hi[0]; ++x)
    for (int y = to_lo[1]; y <= to_hi[1]; ++y)
      for (int z = to_lo[2]; z <= to_hi[2]; ++z)
        if (!inside(x, y, z, from_lo, from_hi)) cells_[key(x, y, z)].push_back(face);
}

void FaceGrid::reset(double cell_size, double margin) {
  cell_size_ = cell_size;
  margin_ = margin;
  cells_.clear_lists();  // keeps the cells' storage for the next rebuild
  stamp_.clear();
  box_lo_.clear();
  box_hi_.clear();
  reg_lo_.clear();
  reg_hi_.clear();
  current_stamp_ = 0;
  widest_box_ = 0.0;
}

void FaceGrid::rebuild(const Mesh& mesh, double cell_size, double margin) {
  reset(cell_size, margin);
  grow_to(mesh.n_faces());
  for (auto f : mesh.faces()) insert(mesh, f);
}

void FaceGrid::insert(const Mesh& mesh, Mesh::FaceHandle f) {
  Vec3 lo, hi;
  face_box(mesh, f, lo, hi);
  insert_box(f.idx(), lo, hi);
}

bool FaceGrid::refresh(const Mesh& mesh, double reach) {
  redo_.clear();
  const std::size_t registered = reg_lo_.size();
  Vec3 lo, hi;
  for (auto f : mesh.faces()) {
    const auto i = static_cast<std::size_t>(f.idx());
    if (i < registered) {
      face_box(mesh, f, lo, hi);
      if (((lo.array() - reach) >= reg_lo_[i].array()).all() && ((hi.array() + reach) <= reg_hi_[i].array()).all())
        continue;
    }
    redo_.push_back(f.idx());
  }
  return reregister_redo(mesh);
}

bool FaceGrid::refresh(const Mesh& mesh, double reach, const std::vector<int>& faces) {
  redo_.clear();
  const std::size_t registered = reg_lo_.size();
  Vec3 lo, hi;
  for (int i : faces) {
    if (static_cast<std::size_t>(i) >= registered) break;  // ascending: the new faces follow
    face_box(mesh, Mesh::FaceHandle(i), lo, hi);
    if (((lo.array() - reach) >= reg_lo_[i].array()).all() && ((hi.array() + reach) <= reg_hi_[i].array()).all())
      continue;
    redo_.push_back(i);
  }
  for (std::size_t i = registered; i < mesh.n_faces(); ++i) redo_.push_back(static_cast<int>(i));
  return reregister_redo(mesh);
}

bool FaceGrid::reregister_redo(const Mesh& mesh) {
  Vec3 lo, hi;
  // Moving a face costs about twice inserting it: past half the faces a
  // rebuild is cheaper.
  if (2 * redo_.size() > mesh.n_faces()) return false;
  for (int i : redo_) {
    face_box(mesh, Mesh::FaceHandle(i), lo, hi);
    reregister(i, lo, hi);
  }
  return true;
}

void FaceGrid::renumber(const std::vector<int>& to, std::size_t faces) {
  for (std::size_t i = 0; i < to.size(); ++i)
    if (to[i] > static_cast<int>(i) || (to[i] >= 0 && static_cast<std::size_t>(to[i]) >= faces))
      throw std::invalid_argument("FaceGrid::renumber: face " + std::to_string(i) + " would move up to " +
                                  std::to_string(to[i]) + " (a garbage collection only moves faces down)");
  // Only the faces that leave or move change their cells' entries: their
  // entries go (a collection moves a few hundred faces of hundreds of
  // thousands; rewriting every cell's list was most of its cost), and each
  // moved face is listed again under its new index in the cells of its
  // union box (which holds every box it was registered with).
  std::vector<int>& changed = redo_;
  changed.clear();
  for (std::size_t i = 0; i < to.size(); ++i)
    if (to[i] != static_cast<int>(i)) changed.push_back(static_cast<int>(i));
  for (const int i : changed)
    if (static_cast<std::size_t>(i) < box_lo_.size()) remove_from_cells(i);
  // A garbage collection moves faces only down, into places of faces that
  // left (to[i] <= i): the per-face boxes then move in place, in ascending
  // order, each place written only by a face from above it after its own
  // face moved out or left (no allocation: a fresh copy of the four arrays
  // per collection cost more than the rebuilds it replaced, in page faults).
  const auto move = [&](std::vector<Vec3>& per_face, double fill) {
    const std::size_t n = per_face.size();
    for (const int changed_face : changed) {  // ascending, as the order above needs
      const auto i = static_cast<std::size_t>(changed_face);
      const int g = to[i];
      if (i < n) {
        if (g >= 0) per_face[static_cast<std::size_t>(g)] = per_face[i];
        per_face[i] = Vec3::Constant(fill);  // its face left (a face from above may take the place)
      } else if (g >= 0 && static_cast<std::size_t>(g) < n) {
        per_face[static_cast<std::size_t>(g)] = Vec3::Constant(fill);  // a face never registered
      }
    }
    per_face.resize(faces, Vec3::Constant(fill));  // as long as stamp_, as grow_to() keeps them
  };
  move(box_lo_, kInf);
  move(box_hi_, -kInf);
  move(reg_lo_, kInf);
  move(reg_hi_, -kInf);
  for (const int i : changed)
    if (const int g = to[static_cast<std::size_t>(i)]; g >= 0 && registered(g)) add_to_cells(g, box_lo_[g], box_hi_[g]);
  stamp_.assign(faces, 0);
  current_stamp_ = 0;
}

void FaceGrid::register_new_faces(const Mesh& mesh) {
  Vec3 lo, hi;
  for (std::size_t i = reg_lo_.size(); i < mesh.n_faces(); ++i) {
    face_box(mesh, Mesh::FaceHandle(static_cast<int>(i)), lo, hi);
    reregister(static_cast<int>(i), lo, hi);
  }
}

}  // namespace gdm
