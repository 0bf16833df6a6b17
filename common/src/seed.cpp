#include "gdm/seed.h"

#include <cmath>
#include <string>

#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/resampler.h"

namespace gdm {

Mesh make_icosahedron(const Vec3& center, double radius) {
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw InvalidSeed("seed radius must be positive and finite, got " + std::to_string(radius));
  if (!center.allFinite()) throw InvalidSeed("seed centre is not finite");
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  const Vec3 corners[12] = {{-1, t, 0}, {1, t, 0},  {-1, -t, 0}, {1, -t, 0},
                            {0, -1, t}, {0, 1, t},  {0, -1, -t}, {0, 1, -t},
                            {t, 0, -1}, {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  // Counter-clockwise seen from outside, so face normals point outward.
  const int faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                            {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                            {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                            {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  Mesh mesh;
  Mesh::VertexHandle v[12];
  for (int i = 0; i < 12; ++i) v[i] = mesh.add_vertex(to_point(center + radius * corners[i].normalized()));
  for (const auto& f : faces) mesh.add_face(v[f[0]], v[f[1]], v[f[2]]);
  generation_property(mesh);
  return mesh;
}

Mesh make_geodesic_sphere(const Vec3& center, double radius, int level) {
  if (level < 0 || level > 8)
    throw InvalidSeed("geodesic sphere level must be in [0, 8], got " + std::to_string(level));
  Mesh mesh = make_icosahedron(center, radius);
  for (int i = 0; i < level; ++i) {
    subdivide_all(mesh, 0);
    for (auto vh : mesh.vertices()) {
      const Vec3 d = to_eigen(mesh.point(vh)) - center;
      mesh.set_point(vh, to_point(center + radius * d.normalized()));
    }
  }
  return mesh;
}

void check_seed_mesh(const Mesh& mesh) {
  if (mesh.n_faces() == 0) throw InvalidSeed("seed mesh has no faces");
  for (auto vh : mesh.vertices()) {
    const auto& p = mesh.point(vh);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw InvalidSeed("seed mesh vertex " + std::to_string(vh.idx()) + " is not finite");
  }
  for (auto fh : mesh.faces()) {
    if (mesh.valence(fh) != 3)
      throw InvalidSeed("seed mesh face " + std::to_string(fh.idx()) + " is not a triangle");
  }
  if (!is_closed(mesh))
    throw InvalidSeed("seed mesh is not closed: it has boundary edges (holes)");
  if (!is_two_manifold(mesh)) throw InvalidSeed("seed mesh is not a 2-manifold");
}

}  // namespace gdm
