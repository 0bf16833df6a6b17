#include "gdm/mesh_order.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>

#include "gdm/errors.h"

namespace gdm {

namespace {

// The 21 low bits of x spread to every third bit.
std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

std::uint64_t morton_key(const std::array<std::uint64_t, 3>& cell) {
  return spread_bits(cell[0]) | spread_bits(cell[1]) << 1 | spread_bits(cell[2]) << 2;
}

}  // namespace

std::vector<int> sort_spatially(Mesh& mesh, double cell) {
  if (!(cell > 0.0) || !std::isfinite(cell)) throw InvalidOption("sort_spatially: the cell must be a positive length, got " + std::to_string(cell));
  const bool statuses = mesh.has_vertex_status() && mesh.has_face_status();
  const auto deleted_vertex = [&](Mesh::VertexHandle v) { return statuses && mesh.status(v).deleted(); };
  const auto deleted_face = [&](Mesh::FaceHandle f) { return statuses && mesh.status(f).deleted(); };

  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  for (auto v : mesh.vertices())
    if (!deleted_vertex(v)) lo = lo.cwiseMin(to_eigen(mesh.point(v)));
  // Z-order over cubes of `cell`: 21 bits per axis (two million cells; a
  // model wider than that wraps, which only costs locality).
  std::vector<std::pair<std::uint64_t, int>> keyed;
  keyed.reserve(mesh.n_vertices());
  for (auto v : mesh.vertices()) {
    if (deleted_vertex(v)) continue;
    const Vec3 q = (to_eigen(mesh.point(v)) - lo) / cell;
    std::array<std::uint64_t, 3> c{};
    for (int a = 0; a < 3; ++a) c[static_cast<std::size_t>(a)] = static_cast<std::uint64_t>(std::max(0.0, std::floor(q[a])));
    keyed.emplace_back(morton_key(c), v.idx());
  }
  std::sort(keyed.begin(), keyed.end());

  std::vector<int> new_index(mesh.n_vertices(), -1);
  for (std::size_t i = 0; i < keyed.size(); ++i) new_index[static_cast<std::size_t>(keyed[i].second)] = static_cast<int>(i);

  struct FaceEntry {
    std::array<int, 3> corners;  // new vertex indices, in the face's order
    int first;                   // the smallest of them
    int old;                     // the old face index
  };
  std::vector<FaceEntry> faces;
  faces.reserve(mesh.n_faces());
  for (auto f : mesh.faces()) {
    if (deleted_face(f)) continue;
    FaceEntry e{};
    int k = 0;
    for (auto v : mesh.fv_range(f)) {
      if (k == 3) throw InvalidInput("sort_spatially: a face with more than three vertices");
      e.corners[static_cast<std::size_t>(k++)] = new_index[static_cast<std::size_t>(v.idx())];
    }
    e.first = *std::min_element(e.corners.begin(), e.corners.end());
    e.old = f.idx();
    faces.push_back(e);
  }
  std::sort(faces.begin(), faces.end(),
            [](const FaceEntry& a, const FaceEntry& b) { return a.first != b.first ? a.first < b.first : a.old < b.old; });

  Mesh out;
  const auto generation = find_generation_property(mesh);
  OpenMesh::VPropHandleT<int> out_generation;
  if (generation.is_valid()) out.add_property(out_generation, "v:generation");
  out.reserve(keyed.size(), 3 * faces.size() / 2, faces.size());
  for (const auto& [key, old] : keyed) {
    const Mesh::VertexHandle v(old);
    const Mesh::VertexHandle w = out.add_vertex(mesh.point(v));
    if (generation.is_valid()) out.property(out_generation, w) = mesh.property(generation, v);
  }
  for (const FaceEntry& e : faces) {
    const Mesh::FaceHandle f = out.add_face(Mesh::VertexHandle(e.corners[0]), Mesh::VertexHandle(e.corners[1]),
                                            Mesh::VertexHandle(e.corners[2]));
    if (!f.is_valid()) {  // not a manifold mesh (OpenMesh refused the face): left as it was
      std::vector<int> same(mesh.n_vertices());
      std::iota(same.begin(), same.end(), 0);
      return same;
    }
  }
  mesh = std::move(out);
  return new_index;
}

}  // namespace gdm
