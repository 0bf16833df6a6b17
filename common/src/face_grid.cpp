#include "gdm/face_grid.h"

#include <limits>

#include "gdm/cell_hash.h"

namespace gdm {

FaceGrid::Key FaceGrid::key(int x, int y, int z) const { return cell_key(x, y, z); }

std::array<int, 3> FaceGrid::cell_of(const Vec3& p) const { return gdm::cell_of(p, cell_size_); }

void FaceGrid::insert_box(int face, Vec3 lo, Vec3 hi) {
  lo.array() -= margin_;
  hi.array() += margin_;
  if (static_cast<std::size_t>(face) >= stamp_.size()) {
    stamp_.resize(face + 1, 0);
    box_lo_.resize(face + 1, Vec3::Constant(std::numeric_limits<double>::infinity()));
    box_hi_.resize(face + 1, Vec3::Constant(-std::numeric_limits<double>::infinity()));
  }
  box_lo_[face] = box_lo_[face].cwiseMin(lo);
  box_hi_[face] = box_hi_[face].cwiseMax(hi);
  const auto a = cell_of(lo), b = cell_of(hi);
  for (int x = a[0]; x <= b[0]; ++x)
    for (int y = a[1]; y <= b[1]; ++y)
      for (int z = a[2]; z <= b[2]; ++z) cells_[key(x, y, z)].push_back(face);
}

void FaceGrid::reset(double cell_size, double margin) {
  cell_size_ = cell_size;
  margin_ = margin;
  for (auto& [k, list] : cells_) list.clear();  // keeps the cells' storage for the next rebuild
  stamp_.clear();
  box_lo_.clear();
  box_hi_.clear();
  current_stamp_ = 0;
}

void FaceGrid::rebuild(const Mesh& mesh, double cell_size, double margin) {
  reset(cell_size, margin);
  stamp_.assign(mesh.n_faces(), 0);
  box_lo_.assign(mesh.n_faces(), Vec3::Constant(std::numeric_limits<double>::infinity()));
  box_hi_.assign(mesh.n_faces(), Vec3::Constant(-std::numeric_limits<double>::infinity()));
  for (auto f : mesh.faces()) insert(mesh, f);
}

void FaceGrid::insert(const Mesh& mesh, Mesh::FaceHandle f) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (auto v : mesh.fv_range(f)) {
    const Vec3 p = to_eigen(mesh.point(v));
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  insert_box(f.idx(), lo, hi);
}

}  // namespace gdm
