// The exact topology's handles (topology.h): each membrane the cavity fill
// left across a handle's hole (cavities.h) is replaced, on the converged
// solid model, by a tube through the hole. The two patches of the model that
// lie on the membrane's two sides are removed and their boundary loops
// stitched by a band of triangles; the band runs through the object around
// the hole's waist (the membrane meets the wall there), so a further
// deformation on the volume without the membrane moves it onto the hole's
// wall under the intersection guard. A membrane whose patches are not two
// discs, or whose band would intersect the model, stays a cap.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include "gdm/mesh_checks.h"
#include "gdm/topology.h"

namespace gdm {
namespace {

std::size_t linear(const Index3& n, int i, int j, int k) {
  return static_cast<std::size_t>(i) + static_cast<std::size_t>(n[0]) * (static_cast<std::size_t>(j) +
                                                                        static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(k));
}

// Labels (1-based) of the 26-connected groups of filled voxels that are the
// membranes of `fill` (a group whose voxel count is a handle's and whose
// centroid is that handle's centre); 0 elsewhere. `handles` gets, per label,
// the index of the handle in fill.cavities.
std::vector<int> membrane_labels(const Volume& volume, const CavityFill& fill, std::vector<std::size_t>& handles) {
  const Index3 n = volume.dims();
  const std::vector<float>& v = volume.values();
  const std::vector<float>& f = fill.volume.values();
  std::vector<int> label(v.size(), 0);
  std::vector<int> group(v.size(), 0);
  int groups = 0;
  std::vector<std::size_t> queue;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const std::size_t start = linear(n, i, j, k);
        if (group[start] || v[start] == f[start]) continue;
        ++groups;
        queue.assign(1, start);
        group[start] = groups;
        Vec3 sum = Vec3::Zero();
        for (std::size_t q = 0; q < queue.size(); ++q) {
          const std::size_t at = queue[q];
          const int x = static_cast<int>(at % n[0]);
          const int y = static_cast<int>((at / n[0]) % n[1]);
          const int z = static_cast<int>(at / (static_cast<std::size_t>(n[0]) * n[1]));
          sum += volume.to_physical(Vec3(x, y, z));
          for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                const int xi = x + dx, yi = y + dy, zi = z + dz;
                if (xi < 0 || yi < 0 || zi < 0 || xi >= n[0] || yi >= n[1] || zi >= n[2]) continue;
                const std::size_t next = linear(n, xi, yi, zi);
                if (group[next] || v[next] == f[next]) continue;
                group[next] = groups;
                queue.push_back(next);
              }
        }
        const Vec3 centre = sum / static_cast<double>(queue.size());
        // The membrane with specks of the fill next to it: about the handle's
        // voxels, its centroid near the handle's centre.
        for (std::size_t c = 0; c < fill.cavities.size(); ++c) {
          const Cavity& h = fill.cavities[c];
          if (h.kind != CavityKind::handle || queue.size() < h.voxels ||
              static_cast<double>(queue.size()) > 1.1 * static_cast<double>(h.voxels) + 16.0 ||
              (h.centre - centre).norm() > 1.5 * volume.voxel_size())
            continue;
          handles.push_back(c);
          const int id = static_cast<int>(handles.size());
          for (std::size_t at : queue) label[at] = id;
          break;
        }
      }
  return label;
}

// The membrane a face lies on (its label), or 0: the point 0.75 voxel
// behind the face (inside the model, against its outward normal) lies in a
// membrane voxel. Faces on the object's wall have the object behind them.
int face_membrane(const Mesh& mesh, Mesh::FaceHandle f, const Volume& volume, const std::vector<int>& label) {
  std::array<Vec3, 3> p;
  int c = 0;
  for (auto v : mesh.fv_range(f)) p[c++] = to_eigen(mesh.point(v));
  const Vec3 normal = (p[1] - p[0]).cross(p[2] - p[0]);
  if (!(normal.norm() > 0.0)) return 0;
  const Vec3 behind = (p[0] + p[1] + p[2]) / 3.0 - 0.75 * volume.voxel_size() * normal.normalized();
  const Vec3 x = volume.to_continuous_index(behind);
  const Index3 n = volume.dims();
  const int i = static_cast<int>(std::lround(x.x())), j = static_cast<int>(std::lround(x.y())),
            k = static_cast<int>(std::lround(x.z()));
  if (i < 0 || j < 0 || k < 0 || i >= n[0] || j >= n[1] || k >= n[2]) return 0;
  return label[linear(n, i, j, k)];
}

// The edge-connected groups of the faces marked with membrane `id`.
std::vector<std::vector<int>> patches_of(const Mesh& mesh, const std::vector<int>& face_label, int id) {
  std::vector<std::vector<int>> out;
  std::vector<char> seen(mesh.n_faces(), 0);
  for (auto f : mesh.faces()) {
    if (face_label[f.idx()] != id || seen[f.idx()]) continue;
    out.emplace_back();
    std::vector<Mesh::FaceHandle> stack{f};
    seen[f.idx()] = 1;
    while (!stack.empty()) {
      const auto g = stack.back();
      stack.pop_back();
      out.back().push_back(g.idx());
      for (auto h : mesh.ff_range(g))
        if (face_label[h.idx()] == id && !seen[h.idx()]) {
          seen[h.idx()] = 1;
          stack.push_back(h);
        }
    }
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  return out;
}

// Grows a patch over the faces it encloses (a face of the mesh not in the
// patch but cut off from the rest by it), so that what remains is a disc when
// the patch is one: the complement's largest edge-connected part is kept.
void close_patch(const Mesh& mesh, std::vector<int>& patch) {
  std::vector<char> in(mesh.n_faces(), 0);
  for (int f : patch) in[f] = 1;
  std::vector<int> part(mesh.n_faces(), -1);
  std::vector<std::size_t> sizes;
  for (auto f : mesh.faces()) {
    if (in[f.idx()] || part[f.idx()] >= 0) continue;
    const int id = static_cast<int>(sizes.size());
    sizes.push_back(0);
    std::vector<Mesh::FaceHandle> stack{f};
    part[f.idx()] = id;
    while (!stack.empty()) {
      const auto g = stack.back();
      stack.pop_back();
      ++sizes[id];
      for (auto h : mesh.ff_range(g))
        if (!in[h.idx()] && part[h.idx()] < 0) {
          part[h.idx()] = id;
          stack.push_back(h);
        }
    }
  }
  if (sizes.size() <= 1) return;
  const int keep = static_cast<int>(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
  for (auto f : mesh.faces())
    if (!in[f.idx()] && part[f.idx()] != keep) patch.push_back(f.idx());
  std::sort(patch.begin(), patch.end());
}

// The patch's boundary as one loop of vertex indices, in the direction of
// the patch's own halfedges there (those of the boundary once the patch is
// removed); empty unless the patch is a disc (one loop,
// V - E + F = 1, no vertex twice on the loop).
std::vector<int> disc_boundary(const Mesh& mesh, const std::vector<int>& patch) {
  std::vector<char> in(mesh.n_faces(), 0);
  for (int f : patch) in[f] = 1;
  std::map<int, int> next;  // loop vertex -> following loop vertex
  std::vector<char> vertex_in(mesh.n_vertices(), 0);
  std::size_t vertices = 0, edges = 0;
  for (int fi : patch) {
    const auto f = mesh.face_handle(fi);
    for (auto h : mesh.fh_range(f)) {
      const auto v = mesh.to_vertex_handle(h);
      if (!vertex_in[v.idx()]) {
        vertex_in[v.idx()] = 1;
        ++vertices;
      }
      const auto opposite = mesh.opposite_halfedge_handle(h);
      const auto g = mesh.face_handle(opposite);
      if (!g.is_valid() || !in[g.idx()]) {
        ++edges;
        // Removing the patch, h is left without a face: a boundary halfedge, tail to head.
        const int from = mesh.from_vertex_handle(h).idx(), to = mesh.to_vertex_handle(h).idx();
        if (next.count(from)) return {};  // a vertex twice on the boundary
        next[from] = to;
      } else if (f.idx() < g.idx()) {
        ++edges;
      }
    }
  }
  if (static_cast<long>(vertices) - static_cast<long>(edges) + static_cast<long>(patch.size()) != 1) return {};
  if (next.empty()) return {};
  std::vector<int> loop{next.begin()->first};
  while (true) {
    const int following = next.at(loop.back());
    if (following == loop.front()) break;
    loop.push_back(following);
    if (loop.size() > next.size()) return {};
  }
  if (loop.size() != next.size()) return {};
  return loop;
}

// Cumulative arclength of a closed polyline: at[0] = 0, at[n] = its length.
std::vector<double> arclength(const std::vector<Vec3>& loop) {
  std::vector<double> at(loop.size() + 1, 0.0);
  for (std::size_t i = 0; i < loop.size(); ++i) at[i + 1] = at[i] + (loop[(i + 1) % loop.size()] - loop[i]).norm();
  return at;
}

// Stitches two boundary loops (each in its boundary halfedges' direction) by
// a band: each step adds the triangle with the shorter new diagonal (or,
// by_arclength, the one that keeps the two loops' arclength fractions
// closest), the second loop walked backwards, starting from the pair of
// closest vertices.
// The new faces are returned (invalid handles when OpenMesh refused one).
std::vector<Mesh::FaceHandle> stitch(Mesh& mesh, const std::vector<int>& a, std::vector<int> b, bool by_arclength) {
  const auto p = [&](int v) { return to_eigen(mesh.point(mesh.vertex_handle(v))); };
  std::reverse(b.begin(), b.end());
  std::size_t shift = 0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < b.size(); ++j) {
    const double d = (p(a[0]) - p(b[j])).squaredNorm();
    if (d < best) best = d, shift = j;
  }
  std::rotate(b.begin(), b.begin() + static_cast<long>(shift), b.end());
  const std::size_t n = a.size(), m = b.size();
  // By arclength: each loop's vertices at their fraction of its length from
  // the start pair, merged in that order (never a fan round one vertex, when
  // the loops differ much in size).
  const auto fractions = [&](const std::vector<int>& loop) {
    std::vector<Vec3> points;
    for (int v : loop) points.push_back(p(v));
    std::vector<double> at = arclength(points);
    for (double& x : at) x = at.back() > 0.0 ? x / at.back() : 0.0;
    return at;
  };
  const std::vector<double> fa = by_arclength ? fractions(a) : std::vector<double>{};
  const std::vector<double> fb = by_arclength ? fractions(b) : std::vector<double>{};
  std::vector<Mesh::FaceHandle> faces;
  std::size_t i = 0, j = 0;
  const auto vh = [&](int v) { return mesh.vertex_handle(v); };
  // OpenMesh's add_face, refused here when it would refuse (and print to
  // stderr): a corner that is not on the boundary, an edge with both faces.
  const auto add = [&](int x, int y, int z) {
    const int c[3] = {x, y, z};
    for (int k = 0; k < 3; ++k) {
      const auto v = vh(c[k]);
      if (!mesh.is_isolated(v) && !mesh.is_boundary(v)) return Mesh::FaceHandle();
      const auto h = mesh.find_halfedge(v, vh(c[(k + 1) % 3]));
      if (h.is_valid() && !mesh.is_boundary(h)) return Mesh::FaceHandle();
    }
    return Mesh::FaceHandle(mesh.add_face(vh(x), vh(y), vh(z)));
  };
  while (i < n || j < m) {
    const int ui = a[i % n], un = a[(i + 1) % n], wj = b[j % m], wn = b[(j + 1) % m];
    const bool advance_a =
        j >= m || (i < n && (by_arclength ? fa[i + 1] <= fb[j + 1]
                                          : (p(un) - p(wj)).squaredNorm() <= (p(ui) - p(wn)).squaredNorm()));
    if (advance_a) {
      faces.push_back(add(ui, un, wj));
      ++i;
    } else {
      faces.push_back(add(wn, wj, ui));
      ++j;
    }
    if (!faces.back().is_valid()) return faces;
  }
  return faces;
}

// A point at arclength fraction s in [0, 1) along a closed polyline.
Vec3 along(const std::vector<Vec3>& loop, const std::vector<double>& at, double s) {
  const double total = at.back();
  const double target = s * total;
  std::size_t i = static_cast<std::size_t>(std::upper_bound(at.begin(), at.end(), target) - at.begin());
  i = std::min(std::max<std::size_t>(i, 1), loop.size());
  const double length = at[i] - at[i - 1];
  const double f = length > 0.0 ? (target - at[i - 1]) / length : 0.0;
  return loop[i - 1] + f * (loop[i % loop.size()] - loop[i - 1]);
}

// The tube between two boundary loops: rings of new vertices, each at the
// same fraction of the straight way from `a` to `b` (matched by arclength,
// `b` walked backwards from its vertex nearest a[0]), as many as make the
// tube's edges about as long as the loops' own; then the loops and rings
// stitched in turn. The rings lie in the solid model's inside (between the
// membrane's two rims), where the next deformation moves them onto the
// hole's wall; `pull` draws each ring that fraction of the way toward the
// line between the loops' centroids. The new faces go to `added`. False
// when a face could not be added (its corner or edge already taken).
bool tube(Mesh& mesh, const std::vector<int>& a, const std::vector<int>& b, double pull,
          std::vector<Mesh::FaceHandle>& added) {
  const auto p = [&](int v) { return to_eigen(mesh.point(mesh.vertex_handle(v))); };
  std::vector<Vec3> pa, pb;
  for (int v : a) pa.push_back(p(v));
  std::vector<int> rb(b.rbegin(), b.rend());
  std::size_t start = 0;
  for (std::size_t j = 1; j < rb.size(); ++j)
    if ((p(rb[j]) - pa[0]).squaredNorm() < (p(rb[start]) - pa[0]).squaredNorm()) start = j;
  std::rotate(rb.begin(), rb.begin() + static_cast<long>(start), rb.end());
  for (int v : rb) pb.push_back(p(v));
  const std::vector<double> la = arclength(pa), lb = arclength(pb);
  const double edge = 0.5 * (la.back() / static_cast<double>(pa.size()) + lb.back() / static_cast<double>(pb.size()));
  const std::size_t n = std::max(pa.size(), pb.size());
  double widest = 0.0;
  std::vector<Vec3> from(n), to(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double s = static_cast<double>(i) / static_cast<double>(n);
    from[i] = along(pa, la, s);
    to[i] = along(pb, lb, s);
    widest = std::max(widest, (to[i] - from[i]).norm());
  }
  const int rings = edge > 0.0 ? std::max(0, static_cast<int>(std::ceil(widest / edge)) - 1) : 0;
  Vec3 ca = Vec3::Zero(), cb = Vec3::Zero();
  for (const Vec3& q : pa) ca += q / static_cast<double>(pa.size());
  for (const Vec3& q : pb) cb += q / static_cast<double>(pb.size());
  std::vector<int> previous = a;
  for (int k = 1; k <= rings; ++k) {
    const double f = static_cast<double>(k) / static_cast<double>(rings + 1);
    const Vec3 axis = ca + f * (cb - ca);
    std::vector<int> ring;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 q = from[i] + f * (to[i] - from[i]);
      ring.push_back(mesh.add_vertex(to_point(q + pull * (axis - q))).idx());
    }
    // stitch() walks its second loop backwards: hand it the ring reversed.
    const std::vector<int> reversed(ring.rbegin(), ring.rend());
    const std::vector<Mesh::FaceHandle> faces = stitch(mesh, previous, reversed, pull > 0.0);
    added.insert(added.end(), faces.begin(), faces.end());
    if (faces.empty() || !std::all_of(faces.begin(), faces.end(), [](auto h) { return h.is_valid(); })) return false;
    previous = ring;
  }
  const std::vector<Mesh::FaceHandle> faces = stitch(mesh, previous, b, pull > 0.0);
  added.insert(added.end(), faces.begin(), faces.end());
  return !faces.empty() && std::all_of(faces.begin(), faces.end(), [](auto h) { return h.is_valid(); });
}

// Adds to `patch` the faces that share an edge with it.
void widen_patch(const Mesh& mesh, std::vector<int>& patch) {
  std::vector<char> in(mesh.n_faces(), 0);
  for (int f : patch) in[f] = 1;
  const std::size_t n = patch.size();
  for (std::size_t i = 0; i < n; ++i)
    for (auto g : mesh.ff_range(mesh.face_handle(patch[i])))
      if (!in[g.idx()]) {
        in[g.idx()] = 1;
        patch.push_back(g.idx());
      }
}

// Whether two patches share a face or a vertex.
bool overlap(const Mesh& mesh, const std::vector<int>& first, const std::vector<int>& second) {
  std::vector<char> vertex(mesh.n_vertices(), 0);
  for (int f : first)
    for (auto v : mesh.fv_range(mesh.face_handle(f))) vertex[v.idx()] = 1;
  for (int f : second)
    for (auto v : mesh.fv_range(mesh.face_handle(f)))
      if (vertex[v.idx()]) return true;
  return false;
}

// Replaces the two patches of `trial` by a tube between their boundary
// loops `a` and `b` (rings drawn `pull` of the way toward the axis); true
// when the result is closed, 2-manifold and no face of the tube meets
// another face (so it has no intersecting pair the model had not).
bool opened_by_tube(Mesh& trial, const std::vector<int>& first, const std::vector<int>& second,
                    const std::vector<int>& a, const std::vector<int>& b, double pull) {
  trial.request_vertex_status();
  trial.request_edge_status();
  trial.request_halfedge_status();
  trial.request_face_status();
  for (const auto& patch : {first, second})
    for (int f : patch) trial.delete_face(trial.face_handle(f), true);
  std::vector<Mesh::FaceHandle> added;
  if (!tube(trial, a, b, pull, added) || faces_meet_mesh(trial, added)) return false;
  trial.garbage_collection();
  trial.release_vertex_status();
  trial.release_edge_status();
  trial.release_halfedge_status();
  trial.release_face_status();
  return is_closed(trial) && is_two_manifold(trial);
}

}  // namespace

OpenedHandles open_handles(Mesh& mesh, const Volume& volume, const CavityFill& fill) {
  OpenedHandles out;
  if (!fill.applied) return out;
  std::vector<std::size_t> handles;
  const std::vector<int> label = membrane_labels(volume, fill, handles);
  if (handles.empty()) return out;
  std::vector<int> face_label(mesh.n_faces(), 0);
  for (auto f : mesh.faces()) face_label[f.idx()] = face_membrane(mesh, f, volume, label);
  std::vector<float> values = fill.volume.values();
  for (std::size_t h = 0; h < handles.size(); ++h) {
    const int id = static_cast<int>(h) + 1;
    std::vector<std::vector<int>> patches = patches_of(mesh, face_label, id);
    if (patches.size() < 2 || patches[1].size() < 3) {
      ++out.kept_caps;
      continue;
    }
    // The straight tube first (rings on the way from rim to rim); when it
    // meets the model (a shrunk model's rims are not always matched well
    // enough), rings drawn toward the hole's axis, inside the membrane,
    // where no face of the model lies: the next deformation carries them
    // onto the wall either way. When no tube fits between the patches' rims
    // (the model folds at a rim: a torus grown from a 20-face seed met its
    // tube 3 times at every pull), the patches widened by a ring of faces,
    // then two: rims farther from the fold.
    Mesh trial;
    bool done = false;
    for (int widen = 0; widen <= 2 && !done; ++widen) {
      std::vector<int> first = patches[0], second = patches[1];
      for (int k = 0; k < widen; ++k) {
        widen_patch(mesh, first);
        widen_patch(mesh, second);
      }
      if (widen > 0 && overlap(mesh, first, second)) break;
      close_patch(mesh, first);
      close_patch(mesh, second);
      const std::vector<int> a = disc_boundary(mesh, first), b = disc_boundary(mesh, second);
      if (a.size() < 3 || b.size() < 3) continue;
      for (const double pull : {0.0, 0.4, 0.7}) {
        Mesh attempt(mesh);  // a fresh copy: status flags of an earlier attempt do not carry over
        if (opened_by_tube(attempt, first, second, a, b, pull)) {
          trial = std::move(attempt);
          done = true;
          break;
        }
      }
    }
    if (!done) {
      ++out.kept_caps;
      continue;
    }
    mesh = std::move(trial);
    ++out.opened;
    // Face indices changed: label the new mesh's faces again for the next membranes.
    face_label.assign(mesh.n_faces(), 0);
    for (auto f : mesh.faces()) face_label[f.idx()] = face_membrane(mesh, f, volume, label);
    for (std::size_t at = 0; at < values.size(); ++at)
      if (label[at] == id) values[at] = volume.values()[at];
  }
  if (out.opened > 0) {
    out.volume = Volume(fill.volume.dims(), std::move(values), fill.volume.spacing(), fill.volume.origin(),
                        fill.volume.direction());
    out.volume.set_outside_value(fill.volume.outside_value());
  }
  return out;
}

}  // namespace gdm
