// Where a model meets itself, and what a local zip could take back (issue 16,
// stop 52): a measurement tool, not part of the pipeline.
//
//   gdm_contacts_probe MODEL --distance MM [--rings K] [--zip OUT]
//
// The faces in contact (contact_faces(), as the report counts them) are
// closed on the mesh (grown by K rings of faces, then shrunk by K: a fold's
// narrow tip between its two walls is taken in) and each closed group is
// classed:
//   fold         a disk that holds both sheets: a pocket pressed flat (a
//                zip cuts the disk out and closes its rim: genus kept);
//   one sheet    the other sheet is farther along the surface than K rings:
//                two fronts that met head on (joining them would add a
//                handle);
//   not a disk   anything else.
// With --zip, every fold is cut out and its rim closed by the least-area
// triangulation, kept when the new faces cut no other face exactly
// (faces_meet_mesh) and written to OUT; the closed, 2-manifold, genus and
// self-intersection checks and the contacts after it are printed.
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "gdm/mesh_checks.h"
#include "gdm/mesh_io.h"
#include "gdm/self_contact.h"

namespace {

using gdm::Mesh;
using gdm::Vec3;

Vec3 point(const Mesh& m, Mesh::VertexHandle v) { return gdm::to_eigen(m.point(v)); }

Vec3 unit_normal(const Mesh& m, Mesh::FaceHandle f) {
  auto it = m.cfv_iter(f);
  const Vec3 a = point(m, *it), b = point(m, *++it), c = point(m, *++it);
  return (b - a).cross(c - a).normalized();
}

// Rings of faces (across edges) from the flagged faces, up to `limit`.
std::vector<int> rings_from(const Mesh& m, const std::vector<char>& from, int limit) {
  std::vector<int> ring(m.n_faces(), std::numeric_limits<int>::max());
  std::deque<int> queue;
  for (std::size_t f = 0; f < from.size(); ++f)
    if (from[f]) {
      ring[f] = 0;
      queue.push_back(static_cast<int>(f));
    }
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop_front();
    if (ring[static_cast<std::size_t>(f)] >= limit) continue;
    for (auto g : m.ff_range(Mesh::FaceHandle(f)))
      if (ring[static_cast<std::size_t>(g.idx())] > ring[static_cast<std::size_t>(f)] + 1) {
        ring[static_cast<std::size_t>(g.idx())] = ring[static_cast<std::size_t>(f)] + 1;
        queue.push_back(g.idx());
      }
  }
  return ring;
}

// The rim of a group of faces: its halfedges whose opposite face is not in
// the group.
std::set<int> rim_halfedges(const Mesh& m, const std::vector<int>& group, const std::vector<int>& group_of, int id) {
  std::set<int> rim;
  for (int f : group)
    for (auto h : m.fh_range(Mesh::FaceHandle(f)))
      if (group_of[static_cast<std::size_t>(m.face_handle(m.opposite_halfedge_handle(h)).idx())] != id) rim.insert(h.idx());
  return rim;
}

// The rim halfedge after h along the rim (turning round h's end vertex).
Mesh::HalfedgeHandle next_on_rim(const Mesh& m, const std::set<int>& rim, Mesh::HalfedgeHandle h) {
  Mesh::HalfedgeHandle next = m.next_halfedge_handle(h);
  while (!rim.count(next.idx())) next = m.next_halfedge_handle(m.opposite_halfedge_handle(next));
  return next;
}

// The rim as one loop of vertices, in the direction of the group's own
// halfedges (empty when it is not one simple loop).
std::vector<int> rim_loop(const Mesh& m, const std::set<int>& rim) {
  if (rim.empty()) return {};
  std::vector<int> loop;
  std::set<int> seen;
  Mesh::HalfedgeHandle h(*rim.begin());
  for (std::size_t step = 0; step < rim.size(); ++step) {
    const int v = m.from_vertex_handle(h).idx();
    if (!seen.insert(v).second) return {};
    loop.push_back(v);
    h = next_on_rim(m, rim, h);
  }
  return h.idx() == *rim.begin() ? loop : std::vector<int>{};
}

// How many loops the rim makes.
int rim_loops(const Mesh& m, const std::set<int>& rim) {
  std::set<int> walked;
  int loops = 0;
  for (int start : rim) {
    if (walked.count(start)) continue;
    ++loops;
    for (Mesh::HalfedgeHandle h(start); walked.insert(h.idx()).second;) h = next_on_rim(m, rim, h);
  }
  return loops;
}

// The least-area triangulation of a loop (dynamic programming over its
// sub-polygons), without a diagonal the mesh already has as an edge; the
// triangles follow the loop's direction. Empty when there is none.
std::vector<std::array<int, 3>> close_loop(const Mesh& m, const std::vector<int>& loop) {
  const int n = static_cast<int>(loop.size());
  const double none = std::numeric_limits<double>::infinity();
  const auto at = [&](int i) { return point(m, Mesh::VertexHandle(loop[static_cast<std::size_t>(i)])); };
  const auto joined = [&](int i, int j) {
    for (auto w : m.vv_range(Mesh::VertexHandle(loop[static_cast<std::size_t>(i)])))
      if (w.idx() == loop[static_cast<std::size_t>(j)]) return true;
    return false;
  };
  std::vector<std::vector<double>> cost(static_cast<std::size_t>(n), std::vector<double>(static_cast<std::size_t>(n), 0.0));
  std::vector<std::vector<int>> apex(static_cast<std::size_t>(n), std::vector<int>(static_cast<std::size_t>(n), -1));
  for (int len = 2; len < n; ++len)
    for (int i = 0; i + len < n; ++i) {
      const int j = i + len;
      double& best = cost[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
      best = none;
      if (!(i == 0 && j == n - 1) && joined(i, j)) continue;  // the edge exists elsewhere
      for (int k = i + 1; k < j; ++k) {
        const double sub = cost[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] +
                           cost[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)];
        const double c = sub + 0.5 * (at(k) - at(i)).cross(at(j) - at(i)).norm();
        if (c < best) {
          best = c;
          apex[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = k;
        }
      }
    }
  if (n < 3 || !(cost[0][static_cast<std::size_t>(n - 1)] < none)) return {};
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::pair<int, int>> todo{{0, n - 1}};
  while (!todo.empty()) {
    const auto [i, j] = todo.back();
    todo.pop_back();
    if (j - i < 2) continue;
    const int k = apex[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
    triangles.push_back({loop[static_cast<std::size_t>(i)], loop[static_cast<std::size_t>(k)], loop[static_cast<std::size_t>(j)]});
    todo.push_back({i, k});
    todo.push_back({k, j});
  }
  return triangles;
}

}  // namespace

int main(int argc, char** argv) {
  std::string model, zip_out;
  double distance = 0.0;
  int rings = 2;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    const auto value = [&]() -> std::string {
      if (a + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", arg.c_str());
        std::exit(2);
      }
      return argv[++a];
    };
    if (arg == "--distance")
      distance = std::atof(value().c_str());
    else if (arg == "--rings")
      rings = std::atoi(value().c_str());
    else if (arg == "--zip")
      zip_out = value();
    else
      model = arg;
  }
  if (model.empty() || !(distance > 0.0) || rings < 0) {
    std::fprintf(stderr, "usage: gdm_contacts_probe MODEL --distance MM [--rings K] [--zip OUT]\n");
    return 2;
  }
  Mesh m = gdm::read_mesh(model);
  m.request_face_status();
  m.request_edge_status();
  m.request_vertex_status();
  m.request_halfedge_status();
  const std::vector<char> contact = gdm::contact_faces(m, distance, nullptr, 0);
  const std::vector<int> out = rings_from(m, contact, rings);
  std::vector<char> outside(m.n_faces());
  for (std::size_t f = 0; f < outside.size(); ++f) outside[f] = out[f] > rings;
  const std::vector<int> in = rings_from(m, outside, rings + 1);
  std::vector<char> closed(m.n_faces());
  for (std::size_t f = 0; f < closed.size(); ++f) closed[f] = contact[f] || in[f] > rings;

  const auto area_of = [&](const std::vector<int>& faces) {
    double s = 0.0;
    for (int f : faces) s += m.calc_face_area(Mesh::FaceHandle(f));
    return s;
  };
  struct Group {
    double area;
    std::size_t faces;
    long euler;
    int loops;
  };
  std::vector<Group> largest;
  std::vector<int> group_of(m.n_faces(), -1);
  int groups = 0, folds = 0, one_sheet = 0, not_disk = 0, zipped = 0, refused = 0;
  double fold_area = 0.0, one_sheet_area = 0.0, not_disk_area = 0.0, zipped_area = 0.0;
  const std::size_t original_faces = m.n_faces();
  for (std::size_t s = 0; s < original_faces; ++s) {
    if (!closed[s] || group_of[s] >= 0 || m.status(Mesh::FaceHandle(static_cast<int>(s))).deleted()) continue;
    const int id = groups++;
    std::vector<int> group, stack{static_cast<int>(s)};
    group_of[s] = id;
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      group.push_back(f);
      for (auto g : m.ff_range(Mesh::FaceHandle(f))) {
        const auto gi = static_cast<std::size_t>(g.idx());
        if (gi < closed.size() && closed[gi] && group_of[gi] < 0 && !m.status(g).deleted()) {
          group_of[gi] = id;
          stack.push_back(g.idx());
        }
      }
    }
    std::set<int> vertices, edges;
    for (int f : group) {
      for (auto v : m.fv_range(Mesh::FaceHandle(f))) vertices.insert(v.idx());
      for (auto e : m.fe_range(Mesh::FaceHandle(f))) edges.insert(e.idx());
    }
    const long euler = static_cast<long>(vertices.size()) - static_cast<long>(edges.size()) + static_cast<long>(group.size());
    const Vec3 first = unit_normal(m, Mesh::FaceHandle(group.front()));
    bool both = false;
    for (int f : group) both = both || unit_normal(m, Mesh::FaceHandle(f)).dot(first) < -0.5;
    const double area = area_of(group);
    const std::set<int> rim = rim_halfedges(m, group, group_of, id);
    largest.push_back({area, group.size(), euler, rim_loops(m, rim)});
    const std::vector<int> loop = euler == 1 ? rim_loop(m, rim) : std::vector<int>{};
    if (loop.empty()) {
      ++not_disk;
      not_disk_area += area;
      continue;
    }
    if (!both) {
      ++one_sheet;
      one_sheet_area += area;
      continue;
    }
    ++folds;
    fold_area += area;
    if (zip_out.empty()) continue;
    const std::vector<std::array<int, 3>> cap = close_loop(m, loop);
    if (cap.empty()) {
      ++refused;
      continue;
    }
    const Mesh before = m;
    for (int f : group) m.delete_face(Mesh::FaceHandle(f), true);
    std::vector<Mesh::FaceHandle> added;
    for (const auto& t : cap) {
      const Mesh::FaceHandle f = m.add_face(Mesh::VertexHandle(t[0]), Mesh::VertexHandle(t[1]), Mesh::VertexHandle(t[2]));
      if (!f.is_valid()) break;
      added.push_back(f);
    }
    if (added.size() != cap.size() || gdm::faces_meet_mesh(m, added)) {
      m = before;
      ++refused;
    } else {
      ++zipped;
      zipped_area += area;
    }
    group_of.resize(m.n_faces(), -2);
    closed.resize(m.n_faces(), 0);
  }
  std::printf("faces in contact %zu; closed over %d rings: %d groups\n", static_cast<std::size_t>(std::count(contact.begin(), contact.end(), 1)), rings, groups);
  std::printf("  folds (a disk with both sheets) %d, %.0f mm^2\n", folds, fold_area);
  std::printf("  one sheet (fronts met head on)  %d, %.0f mm^2\n", one_sheet, one_sheet_area);
  std::printf("  not a disk                      %d, %.0f mm^2\n", not_disk, not_disk_area);
  std::sort(largest.begin(), largest.end(), [](const Group& a, const Group& b) { return a.area > b.area; });
  for (std::size_t k = 0; k < std::min<std::size_t>(5, largest.size()); ++k) {
    const Group& g = largest[k];
    // A piece of surface with b rim loops and Euler characteristic e carries (2 - e - b) / 2 handles.
    std::printf("  group of %zu faces, %.0f mm^2: Euler characteristic %ld, %d rim loop(s), %ld handle(s)\n", g.faces,
                g.area, g.euler, g.loops, (2 - g.euler - g.loops) / 2);
  }
  if (zip_out.empty()) return 0;
  m.garbage_collection();
  std::printf("zipped %d folds (%.0f mm^2), %d refused (no cap, or the cap cuts the model)\n", zipped, zipped_area, refused);
  std::printf("after: closed %d, 2-manifold %d, genus %d, components %d, self-intersecting pairs %zu, faces %zu, smallest angle %.2f\n",
              gdm::is_closed(m), gdm::is_two_manifold(m), gdm::genus(m), gdm::connected_components(m),
              gdm::self_intersecting_pairs(m), m.n_faces(), gdm::smallest_angle_degrees(m));
  const gdm::ContactReport after = gdm::find_self_contacts(m, distance);
  std::printf("contacts after: %zu regions, %.0f mm^2\n", after.regions.size(), after.area);
  gdm::write_mesh(m, zip_out);
  return 0;
}
