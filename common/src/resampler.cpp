#include "gdm/resampler.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace gdm {

namespace {

Vec3 pos(const Mesh& mesh, Mesh::VertexHandle v) { return to_eigen(mesh.point(v)); }


double angle_at(const Vec3& apex, const Vec3& p, const Vec3& q) {
  const Vec3 u = p - apex, w = q - apex;
  return std::atan2(u.cross(w).norm(), u.dot(w));
}

// Is the edge p0-p1 locally Delaunay (the angles at a and b opposite it add
// up to at most pi)? Two acute apexes settle it without atan2, which took 4 %
// of a deformation: with the same dot product as angle_at's x, atan2(y >= 0,
// x > 0) is at most pi/2. Only x > 0: atan2(+0, -0) is pi. Otherwise the
// same sum as before decides.
bool opposite_angles_within_pi(const Vec3& pa, const Vec3& pb, const Vec3& p0, const Vec3& p1) {
  if ((p0 - pa).dot(p1 - pa) > 0.0 && (p0 - pb).dot(p1 - pb) > 0.0) return true;
  return angle_at(pa, p0, p1) + angle_at(pb, p0, p1) <= M_PI + 1e-9;
}

}  // namespace

std::size_t split_longest_edges(Mesh& mesh, int generation, const SplitSelect& select,
                                const std::vector<char>* only_faces) {
  const auto gen = generation_property(mesh);
  std::vector<char> marked(mesh.n_edges(), 0);
  std::vector<std::pair<Mesh::VertexHandle, Mesh::VertexHandle>> to_split;
  for (auto f : mesh.faces()) {
    if (only_faces && (static_cast<std::size_t>(f.idx()) >= only_faces->size() || !(*only_faces)[f.idx()])) continue;
    Mesh::HalfedgeHandle longest;
    double best = -1.0;
    for (auto h : mesh.fh_range(f)) {
      const double len = (pos(mesh, mesh.to_vertex_handle(h)) - pos(mesh, mesh.from_vertex_handle(h))).squaredNorm();
      if (len > best) {
        best = len;
        longest = h;
      }
    }
    const auto e = mesh.edge_handle(longest);
    if (marked[e.idx()] || !select(f, longest)) continue;
    marked[e.idx()] = 1;
    to_split.emplace_back(mesh.from_vertex_handle(longest), mesh.to_vertex_handle(longest));
  }
  // Split by endpoints: an earlier split may have renamed the edge handle.
  for (const auto& [a, b] : to_split) {
    const auto h = mesh.find_halfedge(a, b);
    if (!h.is_valid()) continue;
    const auto mid = mesh.add_vertex(to_point(0.5 * (pos(mesh, a) + pos(mesh, b))));
    mesh.property(gen, mid) = generation;
    mesh.split(mesh.edge_handle(h), mid);
  }
  return to_split.size();
}

std::size_t split_large_faces(Mesh& mesh, double max_face_area, int generation) {
  return split_longest_edges(mesh, generation, [&](Mesh::FaceHandle f, Mesh::HalfedgeHandle) {
    return face_area(mesh, f) > max_face_area;
  });
}

void subdivide_all(Mesh& mesh, int generation) {
  const auto gen = generation_property(mesh);
  Mesh refined;
  // Each edge gains a vertex and becomes two edges, each face four with
  // three inner edges: the arrays sized once (growing them was a third of
  // the subdivision's time on a 841,136-face model).
  refined.reserve(mesh.n_vertices() + mesh.n_edges(), 2 * mesh.n_edges() + 3 * mesh.n_faces(), 4 * mesh.n_faces());
  const auto refined_gen = generation_property(refined);
  for (auto v : mesh.vertices()) {
    const auto nv = refined.add_vertex(mesh.point(v));
    refined.property(refined_gen, nv) = mesh.property(gen, v);
  }
  std::vector<Mesh::VertexHandle> midpoint(mesh.n_edges());
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    const Vec3 m = 0.5 * (pos(mesh, mesh.from_vertex_handle(h)) + pos(mesh, mesh.to_vertex_handle(h)));
    midpoint[e.idx()] = refined.add_vertex(to_point(m));
    refined.property(refined_gen, midpoint[e.idx()]) = generation;
  }
  for (auto f : mesh.faces()) {
    Mesh::VertexHandle corner[3], mid[3];
    int i = 0;
    for (auto h : mesh.fh_range(f)) {
      // corner[i] starts halfedge h; mid[i] is the midpoint of h.
      corner[i] = Mesh::VertexHandle(mesh.from_vertex_handle(h).idx());
      mid[i] = midpoint[mesh.edge_handle(h).idx()];
      ++i;
    }
    refined.add_face(corner[0], mid[0], mid[2]);
    refined.add_face(corner[1], mid[1], mid[0]);
    refined.add_face(corner[2], mid[2], mid[1]);
    refined.add_face(mid[0], mid[1], mid[2]);
  }
  mesh = std::move(refined);
}

std::size_t flip_to_improve(Mesh& mesh, double max_dihedral_deg, const FlipVeto& allow, std::vector<char>* dirty) {
  const double min_normal_dot = std::cos(max_dihedral_deg * M_PI / 180.0);
  std::size_t flips = 0;
  if (dirty) dirty->resize(mesh.n_edges(), 1);
  for (auto e : mesh.edges()) {
    if (dirty) {
      if (!(*dirty)[e.idx()]) continue;
      (*dirty)[e.idx()] = 0;
    }
    if (mesh.is_boundary(e)) continue;
    const auto h0 = mesh.halfedge_handle(e, 0), h1 = mesh.halfedge_handle(e, 1);
    const auto v0 = mesh.from_vertex_handle(h0), v1 = mesh.to_vertex_handle(h0);
    const auto a = mesh.to_vertex_handle(mesh.next_halfedge_handle(h0));
    const auto b = mesh.to_vertex_handle(mesh.next_halfedge_handle(h1));
    if (a == b) continue;
    const Vec3 p0 = pos(mesh, v0), p1 = pos(mesh, v1), pa = pos(mesh, a), pb = pos(mesh, b);
    // Delaunay criterion: flip when the angles opposite the edge add up past pi.
    // (Tested before the valences, which walk the vertex rings: most edges
    // fail it. Every test here is a pure condition, so their order does not
    // change which edges flip.)
    if (opposite_angles_within_pi(pa, pb, p0, p1)) continue;
    if (mesh.valence(v0) <= 3 || mesh.valence(v1) <= 3) continue;
    const Vec3 n0 = (p1 - p0).cross(pa - p0), n1 = (p0 - p1).cross(pb - p1);
    if (n0.normalized().dot(n1.normalized()) < min_normal_dot) continue;
    // The new faces (v0, b, a) and (v1, a, b) must keep the orientation.
    const Vec3 m0 = (pb - p0).cross(pa - p0), m1 = (pa - p1).cross(pb - p1);
    const Vec3 old_n = n0 + n1;
    if (m0.dot(old_n) <= 0.0 || m1.dot(old_n) <= 0.0) continue;
    if (!mesh.is_flip_ok(e)) continue;
    const Mesh::VertexHandle quad[4] = {v0, b, v1, a};
    if (allow && !allow(e, quad)) {
      if (dirty) (*dirty)[e.idx()] = 1;  // asked again next pass
      continue;
    }
    mesh.flip(e);
    ++flips;
    if (dirty)
      for (const auto q : quad)
        for (auto f : mesh.vf_range(q))
          for (auto fe : mesh.fe_range(f)) (*dirty)[fe.idx()] = 1;
  }
  return flips;
}

namespace {

// The passes of both relaxations: each vertex of `vertices`, in order,
// `fraction` of the way toward its neighbours' centroid (within the plane of
// its area-weighted normal when `tangential`), at most `max_move` a pass.
std::size_t relax(Mesh& mesh, const std::vector<Mesh::VertexHandle>& vertices, bool tangential, double fraction,
                  double max_move, int passes, const std::function<void()>& before_pass, const MoveCheck& accept) {
  std::size_t moves = 0;
  for (int pass = 0; pass < passes; ++pass) {
    if (before_pass) before_pass();
    double largest = 0.0;
    for (auto v : vertices) {
      const Vec3 p = pos(mesh, v);
      Vec3 centroid = Vec3::Zero();
      int n = 0;
      for (auto w : mesh.vv_range(v)) {
        centroid += pos(mesh, w);
        ++n;
      }
      if (n == 0) continue;
      Vec3 step = fraction * (centroid / n - p);
      if (tangential) {
        Vec3 normal = vertex_area_normal(mesh, v);
        if (!(normal.norm() > 0.0)) continue;
        normal.normalize();
        step -= step.dot(normal) * normal;
      }
      const double length = step.norm();
      if (length < 1e-3 * max_move) continue;
      if (length > max_move) step *= max_move / length;
      const Vec3 q = p + step;
      if (!accept(v, q)) continue;
      mesh.set_point(v, to_point(q));
      largest = std::max(largest, step.norm());
      ++moves;
    }
    if (largest < 0.01 * max_move) break;
  }
  return moves;
}

}  // namespace

std::size_t relax_toward_neighbours(Mesh& mesh, const std::vector<Mesh::VertexHandle>& vertices, double fraction,
                                    double max_move, int passes, const std::function<void()>& before_pass,
                                    const MoveCheck& accept) {
  return relax(mesh, vertices, false, fraction, max_move, passes, before_pass, accept);
}

std::vector<char> crease_vertices(const Mesh& mesh, double max_dihedral_deg) {
  const double min_cos = std::cos(max_dihedral_deg * M_PI / 180.0);
  std::vector<char> on_crease(mesh.n_vertices(), 0);
  for (auto e : mesh.edges()) {
    if (mesh.is_boundary(e)) continue;
    const Vec3 n0 = face_area_normal(mesh, mesh.face_handle(mesh.halfedge_handle(e, 0)));
    const Vec3 n1 = face_area_normal(mesh, mesh.face_handle(mesh.halfedge_handle(e, 1)));
    const double l = n0.norm() * n1.norm();
    if (l > 0.0 && n0.dot(n1) >= min_cos * l) continue;
    on_crease[static_cast<std::size_t>(mesh.to_vertex_handle(mesh.halfedge_handle(e, 0)).idx())] = 1;
    on_crease[static_cast<std::size_t>(mesh.from_vertex_handle(mesh.halfedge_handle(e, 0)).idx())] = 1;
  }
  return on_crease;
}

std::size_t relax_tangentially(Mesh& mesh, const std::vector<char>& held, double fraction, double max_move, int passes,
                               const std::function<void()>& before_pass, const MoveCheck& accept) {
  std::vector<Mesh::VertexHandle> free;
  for (auto v : mesh.vertices()) {
    const auto i = static_cast<std::size_t>(v.idx());
    if (!(i < held.size() && held[i]) && !mesh.is_boundary(v)) free.push_back(v);
  }
  return relax(mesh, free, true, fraction, max_move, passes, before_pass, accept);
}

}  // namespace gdm
